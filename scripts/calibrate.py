#!/usr/bin/python3
"""Calibration stage of the TT Zero study (issue 4): fits ONE uncertain bike constant so that the
optimal lap of `lap` matches a target lap time, and writes the fitted value to a file of `--set`
overrides that the pipeline passes to every later lap.

    calibrate.py ROAD.h5 BIKE.yaml --lap BIN/lap -o calibration.txt
                 [--key motor.current_max_a] [--target 1771] [--start 300 400]
                 [--rel-tol 0.002] [--max-evals 8] [--workdir DIR] [--parallel-start]
                 [--warm-start] [--keep-lap DIR] [-- LAP_ARGS...]

What and why (docs/pipelines.md, "Calibration"): the paper gives neither the motors' current limit
nor any other power-train constant; data/bx15.yaml reasons each one. Its lap time is the one figure
of the paper's section 4 this stage fits (29:31 = 1771 s by default); everything else the pipeline
reports (energy used, battery and motor levels, the design studies) is then judged against the
paper without having been fitted.

Method: the secant method on f(x) = lap_time(x) - target from the two --start values, with
--parallel-start the two start laps solved at once (they are independent; on two cores this saves
one lap's wall time), and with --warm-start each lap started (--init) from the closest value solved
so far (it does not pay with Ipopt, docs/pipelines.md); a step is kept inside [x/4, 4x] of the last
value. Stops when |f| <= rel_tol x target. Every value is rounded to the 6 significant digits the
output file gives it, so a lap with `--set KEY=VALUE` from that file is the calibration's own lap.
Every lap is `lap ROAD BIKE --set KEY=x LAP_ARGS` into WORKDIR (its summary beside it as .txt, its
figures read from its attributes); a lap that exits 0 or 4 (converged; exit 4 = the re-simulation
check failed, docs/lap_h5.md) counts, any other exit ends the calibration with an error.

Output (written atomically): comment lines with the history (value, lap time, energy used, exit),
then one line `KEY=VALUE`. With --keep-lap DIR the fitted value's lap is also copied to
DIR/lap.h5 and its summary to DIR/lap.txt (the pipeline's reference lap: the same road, bike, value
and LAP_ARGS, so it is not solved again). Exit 0 when the target was met, 3 when --max-evals ran
out (nothing written), 1 on bad input or a failed lap.
"""
import os
import shutil
import subprocess
import sys

import ttz_h5


class CalibrationError(Exception):
    pass


def _parse():
    p = ttz_h5.argument_parser(__doc__)
    p.add_argument("road")
    p.add_argument("bike")
    p.add_argument("--lap", required=True, help="the lap executable")
    p.add_argument("-o", "--output", required=True, help="the overrides file to write")
    p.add_argument("--key", default="motor.current_max_a", help="the bike.yaml key to fit")
    p.add_argument("--target", type=float, default=1771.0, help="target lap time [s]")
    p.add_argument("--start", type=float, nargs=2, default=[300.0, 400.0],
                   help="the two first values of the key")
    p.add_argument("--rel-tol", type=float, default=0.002, help="|lap - target| / target to reach")
    p.add_argument("--max-evals", type=int, default=8, help="laps to solve at most")
    p.add_argument("--workdir", default=None, help="folder of the laps (default: beside --output)")
    p.add_argument("--parallel-start", action="store_true",
                   help="solve the two --start values at once (two processes)")
    p.add_argument("--warm-start", action="store_true",
                   help="start each lap from the closest one solved (--init)")
    p.add_argument("--keep-lap", metavar="DIR",
                   help="copy the fitted value's lap to DIR/lap.h5 and its summary to DIR/lap.txt")
    argv = sys.argv[1:]
    split = argv.index("--") if "--" in argv else len(argv)
    a = p.parse_args(argv[:split])
    a.lap_args = argv[split + 1:]
    if a.start[0] <= 0 or a.start[1] <= 0 or a.start[0] == a.start[1]:
        p.error("--start needs two different positive values")
    return a


def _solve(a, xs, solved):
    """Runs one lap per value x in xs at once (they are independent); returns for each x
    (x, lap time [s], energy used [J], exit code, lap.h5); each lap's summary is beside it as .txt."""
    workdir = a.workdir or os.path.dirname(os.path.abspath(a.output))
    os.makedirs(workdir, exist_ok=True)
    runs = []
    for x in xs:
        out = os.path.join(workdir, f"calibration_{a.key}_{x:.6g}.h5")
        cmd = [a.lap, a.road, a.bike, "-o", out, "--set", f"{a.key}={x:.6g}", "-q"]
        if solved and a.warm_start:
            closest = min(solved, key=lambda r: abs(r[0] - x))
            cmd += ["--init", closest[4]]
        cmd += a.lap_args
        runs.append((x, out, cmd, subprocess.Popen(cmd, stdout=subprocess.PIPE,
                                                  stderr=subprocess.PIPE, text=True)))
    results = []
    for x, out, cmd, run in runs:
        stdout, stderr = run.communicate()
        if run.returncode not in (0, 4):
            raise CalibrationError(f"{' '.join(cmd)}: exit {run.returncode}: {stderr.strip()}")
        with open(_summary(out), "w") as handle:
            handle.write(stdout)
        lap = ttz_h5.open_lap(out)
        results.append((x, lap.attr("lap_time"), lap.attr("energy_used"), run.returncode, out))
    return results


def _as_written(x):
    """x rounded to the 6 significant digits with which the output file and each lap's --set
    give it."""
    return float(f"{x:.6g}")


def _summary(lap_h5):
    """The file of a calibration lap's printed summary."""
    return os.path.splitext(lap_h5)[0] + ".txt"


def _keep(lap_h5, folder):
    """Copies a lap and its summary to folder/lap.h5 and folder/lap.txt, each atomically."""
    for source, name in ((_summary(lap_h5), "lap.txt"), (lap_h5, "lap.h5")):
        ttz_h5.write_atomically(os.path.join(folder, name),
                                lambda temp, source=source: shutil.copyfile(source, temp))


def _next(history, a):
    """The secant step from the last two laps, kept within [x/4, 4x] of the last value."""
    (x0, t0, *_), (x1, t1, *_) = history[-2], history[-1]
    if t1 == t0:
        raise CalibrationError(f"{a.key}: lap time {t1} s did not change between {x0} and {x1}")
    x2 = x1 - (t1 - a.target) * (x1 - x0) / (t1 - t0)
    return min(max(x2, x1 / 4.0), 4.0 * x1)


def _write(a, history):
    lines = [f"# {a.key} fitted by scripts/calibrate.py to a lap of {a.target:g} s on {a.road}",
             "# value, lap time [s], energy used [MJ], lap exit code"]
    lines += [f"# {x:.6g} {t:.3f} {e / 1e6:.3f} {code}" for x, t, e, code, _ in history]
    lines.append(f"{a.key}={history[-1][0]:.6g}")
    def write(path):
        with open(path, "w") as handle:
            handle.write("\n".join(lines) + "\n")

    ttz_h5.write_atomically(a.output, write)


def main():
    a = _parse()
    history = []
    xs = [_as_written(x) for x in (a.start if a.parallel_start else a.start[:1])]
    while len(history) < a.max_evals:
        for x, t, e, code, out in _solve(a, xs, history):
            history.append((x, t, e, code, out))
            print(f"{a.key} = {x:.6g}: lap {t:.3f} s, energy {e / 1e6:.3f} MJ (exit {code})",
                  flush=True)
        best = min(history, key=lambda r: abs(r[1] - a.target))
        if abs(best[1] - a.target) <= a.rel_tol * a.target:
            history.remove(best)
            history.append(best)
            if a.keep_lap:
                _keep(best[4], a.keep_lap)
            _write(a, history)
            return 0
        xs = [_as_written(a.start[1] if len(history) == 1 else _next(history, a))]
    print(f"error: {a.key}: lap time still {history[-1][1]:.3f} s after {a.max_evals} laps "
          f"(target {a.target:g} s); {a.output} not written", file=sys.stderr)
    return 3


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (CalibrationError, ttz_h5.InputError) as err:
        sys.exit(f"error: {err}")
