#!/usr/bin/python3
"""Figures and a comparison report of the paper's design studies (section 5: Fig. 12, 14, 15 and
Table 1) from sets of lap.h5 files (docs/lap_h5.md), one per design point, each written by
`lap road.h5 data/bx15.yaml --set key=value ... -o lap.h5`.

usage: study_report.py [--gear LAP...] [--battery LAP...] [--grid LAP...] [--motors LAP...]
           -o OUTDIR [--reference-gear 2.8] [--reference-pack-mj 51] [--partial]

Each study option takes lap.h5 files or folders (a folder stands for its *.h5 files and its
*/lap.h5 files, sorted by name); give any subset of the four, at least one. A point's design is
read from its `bike_yaml` attribute (the bike after the --set overrides):
  --gear     varies drive.gear_ratio                                  (Fig. 12)
  --battery  varies the pack energy                                   (Fig. 14)
  --grid     varies drive.gear_ratio and the pack energy              (Fig. 15)
  --motors   varies motor.count and/or the pack arrangement           (Table 1)
pack energy [J] = battery.cells_series x battery.cells_parallel x battery.cell_energy_j; the pack
varies through any of those three keys. Every other bike key must be the same at all points of a
study, no two points may share the study's coordinates, and the points' road_sha256 (when given)
must agree. A study needs at least 2 points that vary its key (a grid: points off one line of gear
x pack); with --partial (a report of the points solved so far) a study that has not got them yet
is left out with a line saying so, instead of refused, and with no study left nothing is written.

Writes into OUTDIR (created if missing), each file atomically:
  fig12_gear.png     (--gear) vs gear ratio: lap time [s], top speed on course [km/h] (attribute
                     top_speed), 0-120 km/h time [s], energy used [MJ] with the pack energy as a
                     black line, overall power-train efficiency [%]
  gear_gain.png      (--gear, when the optimum and the reference gear both converged and differ)
                     where the optimum gains on the reference gear: both speeds [km/h] and the
                     running time difference [s] along the road (scripts/lap_compare.py)
  fig14_battery.png  (--battery) lap time [s] and battery usage [% of the pack] vs pack energy [MJ]
  fig15_grid.png     (--grid) filled contours of lap time over gear ratio x pack energy,
                     triangulated from the points themselves (an incomplete grid is drawn where
                     it has points), the points on top
  table1.md          (--motors) motors, pack arrangement (cells_parallel P cells_series S), pack
                     energy [MJ], lap time m:ss, battery usage [%], in the paper's order (its three
                     configurations first, then any other by motors and pack)
  report.md          per study, the paper's figures beside ours with the difference in percent,
                     (ours - paper) / paper (for locations such as the optimum gear the absolute
                     difference too; for percentages the difference in percentage points too),
                     the gear study's 1 km segments where the optimum gains most on the
                     reference gear (as gear_gain.png), a table of every point, the points that
                     did not converge, those solved
                     otherwise than the most of them (solver, mesh_ds, mesh_dt_max), and what the
                     studies cost to solve (each lap's `iterations` and `solve_seconds`; a lap
                     that several studies share, e.g. a copy of the reference lap, counts once;
                     beside a lap.h5, the attempts the pipeline set aside before it,
                     lap-first-attempt.h5 and lap-second-attempt.h5, count with it)
It prints one summary line per study and one of the solve cost.

Definitions:
  0-120 km/h time: t where state/V first reaches 120 km/h (linear between nodes) minus the lap's
    first t. The lap starts rolling (initial.speed_m_per_s, 5 m/s for the BX-15), not from rest,
    and nothing is added for the missing 0-5 m/s: it is the time from the lap's start to 120 km/h
    ("not reached" if V never gets there).
  At its limit (gear study): the share of the lap time where a constraint's `constraint/<kind>`
    (g <= 0 scaled by its limit, docs/lap_h5.md) is above -1e-3, each node standing for half of
    each interval beside it: the motor current (`motor_current`, eq. 39e) and the motor voltage
    (either of `motor_voltage_max` and `motor_voltage_pack`, section 5). Largest motor voltage:
    the maximum of `motor/voltage` [V]. Together they say which limit shapes each point's lap.
  Power-train efficiency: integral of max(wheel/power, 0) dt over integral of max(battery/power,
    0) dt along t (trapezoids): energy delivered to the wheel over energy drawn from the pack,
    regenerated and braking power left out.
  Optimum: the converged point of least lap_time. Points whose lap.h5 says converged = 0 are drawn
    hollow, listed in report.md, and never chosen as an optimum (unless no point converged; the
    report then says so).
  Reference design (red circle): gear ratio --reference-gear (2.8, data/bx15.yaml), pack energy
    --reference-pack-mj (51 MJ, 4P24S), 2 motors. The optimum is a green diamond, as in the paper.

Bad input (a missing file, a lap.h5 of another schema, a missing attribute or bike key, two points
of the same design, a study with fewer than 2 points or whose points do not vary its key, the last
two left out instead with --partial) is reported as one line on stderr naming the file or key, exit
status 1, and nothing is written: all input is read and checked first.
"""
import glob
import math
import os

import numpy as np

import lap_compare
import ttz_h5

KMH = 3.6                      # (km/h) per (m/s)
V_120_KMH = 120.0
GEAR_KEY = "drive.gear_ratio"
MOTOR_KEY = "motor.count"
PACK_KEYS = ("battery.cells_series", "battery.cells_parallel", "battery.cell_energy_j")
REFERENCE_MOTORS = 2           # the BX-15 of the 2015 TT Zero (paper sec 2.3)
REFERENCE_PACK_TOLERANCE = 0.005   # relative: a pack this close to the reference one is it
LAP_CHANNELS = ("state/V", "battery/power", "wheel/power", "motor/voltage",
                "constraint/motor_current", "constraint/motor_voltage_max",
                "constraint/motor_voltage_pack")
BINDING_MARGIN = 1e-3          # a scaled constraint g <= 0 is at its limit where g > -1e-3

# The paper's figures (paper-tt-zero-lap-time-optimisation.md, sections 4 and 5).
PAPER = {
    "reference_lap_s": 1771.0,          # sec 4: 29 min 31 s
    "reference_energy_mj": 37.0,        # sec 5: "37MJ or 10.3kWh with gear ratio 2.8"
    "reference_usage_pct": 72.0,        # Table 1: 72 % of the 51 MJ pack
    "reference_pack_mj": 51.0,          # Table 1: 4P24S, 51 MJ
    "gear_optimum": 3.4,                # sec 5, Fig. 12
    "gear_gain_s": 105.0,               # "approximately 1 minute and 45 seconds"
    "gear_top_speed_peak": 3.1,         # "maximum top speed is achieved with a gear ratio 3.1"
    "gear_energy_peak": 3.3,            # "maximum energy usage (41MJ) ... gear ratio 3.3"
    "gear_energy_peak_mj": 41.0,
    "gear_fastest_accel": 4.3,          # "maximum acceleration ... shortest gear ratio (4.3)"
    "battery_optimum_mj": 37.0,         # Fig. 14: "minimum lap time ... (approximately) 37MJ"
    "battery_smallest_mj": 25.0,        # Fig. 14: the 25 MJ pack is drained: 100 %
    "battery_smallest_usage_pct": 100.0,
    "grid_min_lap_s": 1654.0,           # Fig. 15: 27 min 34 s
    "grid_min_gear": 3.4,
    "grid_min_pack_mj": 42.0,
}
# Table 1 (lap times as the text gives them: 1566 s; the table prints 26m 7s), in its order.
PAPER_TABLE1 = (  # (motors, cells_parallel, cells_series, pack MJ, lap [s], usage [%])
    (2, 4, 24, 51.0, 1771.0, 72.0),
    (3, 4, 24, 51.0, 1566.0, 100.0),
    (3, 5, 24, 64.0, 1571.0, 85.0),
)

STUDIES = {  # name: (option, figure/table, keys the study may vary)
    "gear": ("--gear", "Fig. 12", {GEAR_KEY}),
    "battery": ("--battery", "Fig. 14", set(PACK_KEYS)),
    "grid": ("--grid", "Fig. 15", {GEAR_KEY, *PACK_KEYS}),
    "motors": ("--motors", "Table 1", {MOTOR_KEY, *PACK_KEYS}),
}


# --- reading ---------------------------------------------------------------------------------

class Point:
    """One design point: its lap.h5's summary attributes, its bike, and (gear study) the 0-120
    km/h time, the power-train efficiency, the shares of the lap time at the motor-current and
    motor-voltage limits and the largest motor voltage."""

    def __init__(self, path, lap, bike):
        self.path = path
        self.name = path
        self.bike = bike
        self.lap_time = lap.attr("lap_time")
        self.top_speed = lap.attr("top_speed")
        self.energy_used = lap.attr("energy_used")
        self.energy_fraction = lap.attr("energy_fraction")
        self.converged = bool(lap.attr("converged", int))
        self.message = lap.attr("message", str) if "message" in lap.h5.attrs else ""
        self.road = lap.attr("road_sha256", str) if "road_sha256" in lap.h5.attrs else None
        self.gear = bike[GEAR_KEY]
        self.motors = int(bike[MOTOR_KEY])
        self.series = int(bike["battery.cells_series"])
        self.parallel = int(bike["battery.cells_parallel"])
        self.pack_j = self.series * self.parallel * bike["battery.cell_energy_j"]
        self.accel_120 = math.nan
        self.efficiency = math.nan
        self.current_limited = math.nan   # share of the lap time at the motor-current limit
        self.voltage_limited = math.nan   # ... at a motor-voltage limit
        self.max_motor_voltage = math.nan  # [V]
        timed = "iterations" in lap.h5.attrs and "solve_seconds" in lap.h5.attrs
        self.iterations = lap.attr("iterations", int) if timed else None
        self.solve_seconds = lap.attr("solve_seconds") if timed else None
        self.attempts = set_aside_attempts(path)
        meshed = "mesh_ds" in lap.h5.attrs and "mesh_dt_max" in lap.h5.attrs
        solver = lap.attr("solver", str) if "solver" in lap.h5.attrs else ""
        self.method = (solver, lap.attr("mesh_ds"), lap.attr("mesh_dt_max")) if meshed else None

    @property
    def solve_key(self):
        """What identifies one solve: a copied lap has the same lap time, iterations and time."""
        return (self.lap_time, self.iterations, self.solve_seconds)

    @property
    def pack_mj(self):
        return self.pack_j / 1e6

    @property
    def arrangement(self):
        return f"{self.parallel}P{self.series}S"


def parse_bike(path, text):
    """{'section.key': value} of a bike_yaml attribute (two levels, docs/bike.md); the keys the
    studies read must be numbers."""
    import yaml

    try:
        tree = yaml.safe_load(text)
    except yaml.YAMLError as err:
        first_line = str(err).splitlines()[0]
        raise ttz_h5.InputError(path, f"attribute 'bike_yaml' is not YAML ({first_line})") from None
    if not isinstance(tree, dict):
        raise ttz_h5.InputError(path, "attribute 'bike_yaml' is not a YAML mapping of sections")
    bike = {}
    for section, keys in tree.items():
        if isinstance(keys, dict):
            bike.update({f"{section}.{key}": value for key, value in keys.items()})
        else:
            bike[str(section)] = keys
    for key in (GEAR_KEY, MOTOR_KEY, *PACK_KEYS):
        value = bike.get(key)
        number = isinstance(value, (int, float)) and not isinstance(value, bool)
        if not number or not math.isfinite(value):
            what = "missing" if key not in bike else f"'{value}' is not a finite number"
            raise ttz_h5.InputError(path, f"bike_yaml key '{key}' {what}")
    return bike


def accel_time(t, v):
    """Time from the lap's start until v first reaches 120 km/h (linear between nodes) [s]; NaN
    if it never does."""
    target = V_120_KMH / KMH
    above = np.nonzero(v >= target)[0]
    if above.size == 0:
        return math.nan
    k = above[0]
    if k == 0:
        return 0.0
    crossing = t[k - 1] + (target - v[k - 1]) / (v[k] - v[k - 1]) * (t[k] - t[k - 1])
    return float(crossing - t[0])


def binding_share(t, g):
    """Share of the lap time where the scaled constraint g is within BINDING_MARGIN of its limit
    (trapezoidal in time) [1]; NaN for a lap of no duration."""
    duration = t[-1] - t[0]
    if duration <= 0:
        return math.nan
    return float(np.trapz((g > -BINDING_MARGIN).astype(float), t) / duration)


def powertrain_efficiency(t, wheel, battery):
    """Energy to the wheel over energy drawn from the pack, positive parts only [1]."""
    drawn = np.trapz(np.maximum(battery, 0.0), t)
    return float(np.trapz(np.maximum(wheel, 0.0), t) / drawn) if drawn > 0 else math.nan


# The attempts pipelines/Makefile sets aside beside a point's lap.h5 before it solves it again.
ATTEMPT_FILES = ("lap-first-attempt.h5", "lap-second-attempt.h5")


def set_aside_attempts(path):
    """[(iterations, solve_seconds)] of the attempts set aside beside `path` when it is a
    lap.h5 (pipelines/Makefile, "Retrying a solve")."""
    if os.path.basename(path) != "lap.h5":
        return []
    attempts = []
    for name in ATTEMPT_FILES:
        attempt_path = os.path.join(os.path.dirname(path), name)
        if os.path.exists(attempt_path):
            attempt = ttz_h5.open_lap(attempt_path)
            try:
                attempts.append((attempt.attr("iterations", int), attempt.attr("solve_seconds")))
            finally:
                attempt.h5.close()
    return attempts


def read_point(path, channels):
    """The Point of one lap.h5; with `channels`, also its 0-120 time, efficiency and limits."""
    lap = ttz_h5.open_lap(path)
    try:
        point = Point(path, lap, parse_bike(path, lap.attr("bike_yaml", str)))
        if channels:
            t = lap.data("t")
            if t.size == 0:
                raise ttz_h5.InputError(path, "dataset 't' is empty")
            data = {name: lap.data(name, t.size) for name in LAP_CHANNELS}
            for name, values in (("t", t), *data.items()):
                ttz_h5.require_finite(path, name, values)
            point.accel_120 = accel_time(t, data["state/V"])
            point.efficiency = powertrain_efficiency(t, data["wheel/power"], data["battery/power"])
            point.current_limited = binding_share(t, data["constraint/motor_current"])
            point.voltage_limited = binding_share(t, np.maximum(
                data["constraint/motor_voltage_max"], data["constraint/motor_voltage_pack"]))
            point.max_motor_voltage = float(np.max(data["motor/voltage"]))
        return point
    finally:
        lap.h5.close()


def expand(paths):
    """The lap.h5 files of a study's arguments: files as given, folders as their *.h5 and
    */lap.h5 files."""
    files = []
    for path in paths:
        if os.path.isdir(path):
            found = sorted(glob.glob(os.path.join(path, "*.h5"))) + \
                sorted(glob.glob(os.path.join(path, "*", "lap.h5")))
            if not found:
                raise ttz_h5.InputError(path, "folder holds no *.h5 or */lap.h5 file")
            files.extend(found)
        else:
            files.append(path)
    return files


# --- checks ----------------------------------------------------------------------------------

def coordinates(study, point):
    """The design coordinates of a point in a study (what must differ between points)."""
    if study == "gear":
        return (round(point.gear, 9),)
    if study == "battery":
        return (round(point.pack_j, 3),)
    if study == "grid":
        return (round(point.gear, 9), round(point.pack_j, 3))
    return (point.motors, point.parallel, point.series, round(point.pack_j, 3))


def describe(study, point):
    """The point's coordinates as text."""
    if study == "gear":
        return f"{GEAR_KEY} = {point.gear:g}"
    if study == "battery":
        return f"pack energy {point.pack_mj:.2f} MJ"
    if study == "grid":
        return f"{GEAR_KEY} = {point.gear:g} and pack energy {point.pack_mj:.2f} MJ"
    return f"{point.motors} motors, {point.arrangement}, {point.pack_mj:.2f} MJ"


class TooFewPoints(ttz_h5.InputError):
    """A study whose points cannot make its figure yet (too few, or not varying its key)."""


def check_study(study, points):
    """Refuses a study of fewer than 2 points, points varying another key, two points of the
    same design, points of different roads, or a study that does not vary its key."""
    option, _, allowed = STUDIES[study]
    if len(points) < 2:
        raise TooFewPoints(option, f"{len(points)} lap.h5 given, a study needs at least 2 "
                           "design points")
    first = points[0]
    for point in points[1:]:
        for key in sorted(set(first.bike) | set(point.bike)):
            if key not in allowed and first.bike.get(key) != point.bike.get(key):
                raise ttz_h5.InputError(point.path, f"bike key '{key}' is {point.bike.get(key)} "
                                        f"but {first.bike.get(key)} in {first.path}: the {study} "
                                        f"study may vary only {', '.join(sorted(allowed))}")
        if first.road and point.road and first.road != point.road:
            raise ttz_h5.InputError(point.path, f"road_sha256 differs from {first.path}'s: "
                                    "a lap of another road")
    seen = {}
    for point in points:
        key = coordinates(study, point)
        if key in seen:
            raise ttz_h5.InputError(point.path, f"same design ({describe(study, point)}) as "
                                    f"{seen[key].path}: each point of the {study} study must "
                                    "differ")
        seen[key] = point
    pack = "pack energy (" + " x ".join(PACK_KEYS) + ")"
    varied = {"gear": [(0, GEAR_KEY)], "battery": [(0, pack)],
              "grid": [(0, GEAR_KEY), (1, pack)], "motors": []}[study]
    for index, label in varied:
        values = {coordinates(study, p)[index] for p in points}
        if len(values) < 2:
            raise TooFewPoints(option, f"all {len(points)} points have the same {label}: "
                               f"the {study} study must vary {label}")
    if study == "grid":
        xy = np.array([[p.gear, p.pack_mj] for p in points])
        spread = (xy - xy.mean(axis=0)) / np.ptp(xy, axis=0)
        if np.linalg.matrix_rank(spread, tol=1e-9) < 2:
            raise TooFewPoints(option, f"the {len(points)} points lie on one line of gear "
                               "ratio x pack energy: a grid needs points off it")


def read_studies(args):
    """{study: [Point]} of the studies given, read and checked; with args.partial a study with
    too few points is left out (printed), not refused."""
    studies = {}
    for study in STUDIES:
        paths = getattr(args, study)
        if paths is None:
            continue
        points = [read_point(path, study == "gear") for path in expand(paths)]
        try:
            check_study(study, points)
        except TooFewPoints as why:
            if not args.partial:
                raise
            print(f"{study}: left out, {why}")
            continue
        studies[study] = points
    return studies


# --- numbers ---------------------------------------------------------------------------------

def lap_text(seconds):
    """m:ss.s of a time in seconds."""
    if not math.isfinite(seconds):
        return "n/a"
    tenths = int(round(seconds * 10))
    return f"{tenths // 600}:{(tenths % 600) / 10:04.1f}"


def lap_text_whole(seconds):
    """m:ss of a time in seconds, rounded to the second."""
    whole = int(round(seconds))
    return f"{whole // 60}:{whole % 60:02d}"


def percent(ours, paper):
    """(ours - paper) / paper in percent, signed."""
    if ours is None or not math.isfinite(ours) or not paper:
        return "n/a"
    return f"{100.0 * (ours - paper) / paper:+.1f} %"


def location_difference(ours, paper, digits=2, unit=""):
    """Absolute and relative difference of a location (a gear ratio, a pack energy)."""
    if ours is None or not math.isfinite(ours):
        return "n/a"
    return f"{ours - paper:+.{digits}f}{unit} ({percent(ours, paper)})"


def points_difference(ours, paper):
    """Difference of two percentages in percentage points and relative."""
    if ours is None or not math.isfinite(ours):
        return "n/a"
    return f"{ours - paper:+.1f} pp ({percent(ours, paper)})"


def best(points):
    """The converged point of least lap time (any point if none converged)."""
    pool = [p for p in points if p.converged] or points
    return min(pool, key=lambda p: p.lap_time)


def is_reference_gear(point, gear):
    return abs(point.gear - gear) <= 1e-6


def is_reference_pack(point, pack_mj):
    return abs(point.pack_mj - pack_mj) <= REFERENCE_PACK_TOLERANCE * pack_mj


def find(points, predicate):
    """The first point satisfying predicate (a converged one first), or None."""
    found = [p for p in points if predicate(p)]
    found.sort(key=lambda p: not p.converged)
    return found[0] if found else None


def flag(point):
    """' (not converged)' for a point that did not converge."""
    return "" if point.converged else " (not converged)"


def argmax_gear(points, value):
    """The gear ratio of the converged point of largest value(point) (NaN-safe)."""
    pool = [p for p in points if p.converged and math.isfinite(value(p))]
    return max(pool, key=value) if pool else None


def argmin_gear(points, value):
    pool = [p for p in points if p.converged and math.isfinite(value(p))]
    return min(pool, key=value) if pool else None


# --- report ----------------------------------------------------------------------------------

def table(header, rows):
    """A markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return lines


def status_lines(points):
    """The points that did not converge (or a line saying all did), then those solved with
    another solver or mesh than the most of them."""
    return not_converged_lines(points) + other_method_lines(points)


def method_text(method):
    """(solver, ds [m], dt_max [s]) as `lap`'s flags (no --solver when the lap does not say)."""
    solver = f"--solver {method[0]} " if method[0] else ""
    return f"{solver}--ds {method[1]:g} --dt-max {method[2]:g}"


def other_method_lines(points):
    """The points solved with another solver or mesh than the most of them (pipelines/Makefile
    solves again with Ipopt a point the indirect solver did not converge on), or nothing when all
    share one."""
    methods = [p.method for p in points if p.method is not None]
    if len(set(methods)) <= 1:
        return []
    common = max(methods, key=methods.count)  # on a tie the first point's
    others = [p for p in points if p.method is not None and p.method != common]
    lines = [f"**{len(others)} of {len(points)} points solved otherwise** than the others "
             f"({method_text(common)}); another mesh has its own error, and the indirect "
             "solver's lap (at its last barrier weight) is ~0.01 % above Ipopt's on the same "
             "mesh (docs/lap.md):", ""]
    lines += [f"- `{p.name}`: {method_text(p.method)}" for p in others]
    return lines + [""]


def not_converged_lines(points):
    """The list of points that did not converge, or a line saying all did."""
    bad = [p for p in points if not p.converged]
    if not bad:
        return [f"All {len(points)} points converged.", ""]
    lines = [f"**{len(bad)} of {len(points)} points did not converge** (converged = 0; drawn "
             "hollow, not used for optima):", ""]
    lines += [f"- NOT CONVERGED: `{p.name}`: {p.message or '(no message)'}" for p in bad]
    if len(bad) == len(points):
        lines += ["", "No point converged: the optimum above is taken over non-converged points."]
    return lines + [""]


def percent_or_na(share, digits):
    """A share [1] as a percentage with `digits` decimals, or n/a when it is NaN."""
    return "n/a" if math.isnan(share) else f"{100 * share:.{digits}f}"


# The per-point table's columns that only the gear study reads (read_point's `channels`).
GEAR_ONLY_COLUMNS = ("0-120 km/h s", "power-train eff. %", "current at limit %",
                     "voltage at limit %", "largest motor voltage V")


def point_rows(points, study):
    """Rows of the per-point table, sorted by the study's coordinates."""
    rows = []
    for p in sorted(points, key=lambda p: coordinates(study, p)):
        rows.append([f"{p.gear:g}", p.motors, p.arrangement, f"{p.pack_mj:.2f}",
                     f"{lap_text(p.lap_time)} ({p.lap_time:.1f} s)", f"{KMH * p.top_speed:.1f}",
                     "not reached" if math.isnan(p.accel_120) else f"{p.accel_120:.2f}",
                     f"{p.energy_used / 1e6:.2f}", f"{100 * p.energy_fraction:.1f}",
                     percent_or_na(p.efficiency, 1),
                     percent_or_na(p.current_limited, 0), percent_or_na(p.voltage_limited, 0),
                     f"{p.max_motor_voltage:.1f}",
                     "yes" if p.converged else "**NO**", f"`{p.name}`"])
    header = ["gear", "motors", "pack", "pack MJ", "lap time", "top speed km/h", "0-120 km/h s",
              "energy MJ", "usage %", "power-train eff. %", "current at limit %",
              "voltage at limit %", "largest motor voltage V", "converged", "file"]
    if study != "gear":
        keep = [k for k, name in enumerate(header) if name not in GEAR_ONLY_COLUMNS]
        header = [header[k] for k in keep]
        rows = [[r[k] for k in keep] for r in rows]
    return table(header, rows)


# Where the optimum gear gains on the reference gear: segments of this length, this many listed.
GAIN_SEGMENT_M = 1000.0
GAIN_ROWS = 3


def gear_gain(points, ref_gear):
    """{"gears": (reference, optimum), "a", "b": their laps (lap_compare.read_lap), "result":
    lap_compare.compare's} when the optimum and the reference gear's point both converged and
    differ; else None."""
    opt = best(points)
    ref = find(points, lambda p: is_reference_gear(p, ref_gear))
    if ref is None or opt is ref or not (ref.converged and opt.converged):
        return None
    a, b = lap_compare.read_lap(ref.path), lap_compare.read_lap(opt.path)
    lap_compare.check_same_road(a, b)
    return {"gears": (ref.gear, opt.gear), "a": a, "b": b,
            "result": lap_compare.compare(a, b, GAIN_SEGMENT_M, GAIN_ROWS)}


def gain_lines(compared):
    """The segments where the optimum gains most on the reference gear (`compared`: gear_gain's)."""
    if compared is None:
        return []
    (ref_gear, opt_gear), result = compared["gears"], compared["result"]
    lines = [f"Where gear {opt_gear:g} gains its {-result['difference_s']:.1f} s on gear "
             f"{ref_gear:g} (gear_gain.png; `scripts/lap_compare.py`), the "
             f"{GAIN_SEGMENT_M / 1e3:g} km segments of the largest gains:", ""]
    lines += [f"- km {p['from_m'] / 1e3:g}-{p['to_m'] / 1e3:g}: {p['delta_s']:+.2f} s, "
              f"{KMH * p['speed_a']:.1f} -> {KMH * p['speed_b']:.1f} km/h" for p in result["b_gains"]]
    return lines + [""]


def gear_section(points, ref_gear, compared=None):
    """report.md section and summary line of the gear study; `compared`: gear_gain's."""
    opt = best(points)
    ref = find(points, lambda p: is_reference_gear(p, ref_gear))
    gain = ref.lap_time - opt.lap_time if ref else None
    top = argmax_gear(points, lambda p: p.top_speed)
    energy = argmax_gear(points, lambda p: p.energy_used)
    accel = argmin_gear(points, lambda p: p.accel_120)
    eff = sorted((p for p in points if p.converged and math.isfinite(p.efficiency)),
                 key=lambda p: p.gear)
    eff_values = [p.efficiency for p in eff]
    if len(eff) < 2:
        trend = "n/a"
    elif all(b > a for a, b in zip(eff_values, eff_values[1:])):
        trend = "increases throughout"
    else:
        trend = f"not monotonic (highest at gear {max(eff, key=lambda p: p.efficiency).gear:g})"
    P = PAPER
    paper_opt_lap = P["reference_lap_s"] - P["gear_gain_s"]
    rows = [
        ["optimum gear ratio (least lap time)", f"{P['gear_optimum']:g}",
         f"{opt.gear:g}{flag(opt)}",
         location_difference(opt.gear, P["gear_optimum"])],
        ["lap time at the optimum",
         f"{lap_text_whole(paper_opt_lap)} ({paper_opt_lap:.0f} s; 1771 - 105)",
         f"{lap_text(opt.lap_time)} ({opt.lap_time:.1f} s)", percent(opt.lap_time, paper_opt_lap)],
        [f"lap time at gear {ref_gear:g} (reference)", f"29:31 ({P['reference_lap_s']:.0f} s)",
         (f"{lap_text(ref.lap_time)} ({ref.lap_time:.1f} s){flag(ref)}" if ref
          else "not in the study"),
         percent(ref.lap_time, P["reference_lap_s"]) if ref else "n/a"],
        [f"gain of the optimum over gear {ref_gear:g}", f"{P['gear_gain_s']:.0f} s (1:45, ~6 %)",
         f"{gain:.1f} s ({100 * gain / ref.lap_time:.1f} %)" if ref else "n/a",
         percent(gain, P["gear_gain_s"])],
        ["gear of the highest top speed on course", f"{P['gear_top_speed_peak']:g}",
         f"{top.gear:g} ({KMH * top.top_speed:.1f} km/h)" if top else "n/a",
         location_difference(top.gear, P["gear_top_speed_peak"]) if top else "n/a"],
        ["gear of the highest energy use", f"{P['gear_energy_peak']:g}",
         f"{energy.gear:g}" if energy else "n/a",
         location_difference(energy.gear, P["gear_energy_peak"]) if energy else "n/a"],
        ["highest energy use", f"{P['gear_energy_peak_mj']:g} MJ",
         f"{energy.energy_used / 1e6:.2f} MJ" if energy else "n/a",
         percent(energy.energy_used / 1e6, P["gear_energy_peak_mj"]) if energy else "n/a"],
        [f"energy used at gear {ref_gear:g}", f"{P['reference_energy_mj']:g} MJ",
         f"{ref.energy_used / 1e6:.2f} MJ{flag(ref)}" if ref else "not in the study",
         percent(ref.energy_used / 1e6, P["reference_energy_mj"]) if ref else "n/a"],
        ["gear of the quickest 0-120 km/h", f"{P['gear_fastest_accel']:g} (the shortest studied)",
         f"{accel.gear:g} ({accel.accel_120:.2f} s)" if accel else "n/a",
         location_difference(accel.gear, P["gear_fastest_accel"]) if accel else "n/a"],
        ["power-train efficiency vs gear ratio", "increases throughout 2.5-4.3", trend, "-"],
    ]
    lines = [f"## Gear ratio (Fig. 12): {len(points)} points, gear {min(p.gear for p in points):g}"
             f" to {max(p.gear for p in points):g}", ""]
    lines += table(["quantity", "paper", "ours", "difference"], rows) + [""]
    lines += gain_lines(compared)
    lines += status_lines(points) + point_rows(points, "gear") + [""]
    summary = f"gear: optimum {opt.gear:g}{flag(opt)} (lap {lap_text(opt.lap_time)})"
    summary += (f", gain over {ref_gear:g} {gain:.1f} s" if ref
                else f", gear {ref_gear:g} not in the study")
    return lines, summary + unconverged_note(points)


def unconverged_note(points):
    bad = sum(not p.converged for p in points)
    return f"; {bad} of {len(points)} points NOT converged" if bad else ""


def battery_section(points, ref_pack_mj):
    """report.md section and summary line of the battery study."""
    P = PAPER
    opt = best(points)
    smallest = min(points, key=lambda p: p.pack_j)
    ref = find(points, lambda p: is_reference_pack(p, ref_pack_mj))
    rows = [
        ["pack energy of the least lap time", f"~{P['battery_optimum_mj']:g} MJ",
         f"{opt.pack_mj:.2f} MJ{flag(opt)}",
         location_difference(opt.pack_mj, P["battery_optimum_mj"], unit=" MJ")],
        ["least lap time", "not given", f"{lap_text(opt.lap_time)} ({opt.lap_time:.1f} s)", "-"],
        [f"battery usage of the smallest pack (paper: {P['battery_smallest_mj']:g} MJ)",
         f"{P['battery_smallest_usage_pct']:g} %",
         f"{100 * smallest.energy_fraction:.1f} % of {smallest.pack_mj:.2f} MJ{flag(smallest)}",
         points_difference(100 * smallest.energy_fraction, P["battery_smallest_usage_pct"])],
        [f"lap time with the {ref_pack_mj:g} MJ pack (reference)",
         f"29:31 ({P['reference_lap_s']:.0f} s)",
         (f"{lap_text(ref.lap_time)} ({ref.lap_time:.1f} s){flag(ref)}" if ref
          else "not in the study"),
         percent(ref.lap_time, P["reference_lap_s"]) if ref else "n/a"],
        [f"battery usage with the {ref_pack_mj:g} MJ pack", f"{P['reference_usage_pct']:g} %",
         f"{100 * ref.energy_fraction:.1f} %" if ref else "not in the study",
         points_difference(100 * ref.energy_fraction, P["reference_usage_pct"]) if ref else "n/a"],
    ]
    lines = [f"## Battery pack (Fig. 14): {len(points)} points, {smallest.pack_mj:.2f} to "
             f"{max(p.pack_mj for p in points):.2f} MJ", ""]
    lines += table(["quantity", "paper", "ours", "difference"], rows) + [""]
    lines += status_lines(points) + point_rows(points, "battery") + [""]
    summary = (f"battery: minimum lap {lap_text(opt.lap_time)}{flag(opt)} with a {opt.pack_mj:.2f} "
               f"MJ pack (uses {100 * opt.energy_fraction:.1f} %)")
    return lines, summary + unconverged_note(points)


def grid_section(points, ref_gear, ref_pack_mj):
    """report.md section and summary line of the gear x pack grid."""
    P = PAPER
    opt = best(points)
    ref = find(points, lambda p: is_reference_gear(p, ref_gear)
               and is_reference_pack(p, ref_pack_mj))
    gain = ref.lap_time - opt.lap_time if ref else None
    paper_gain = P["reference_lap_s"] - P["grid_min_lap_s"]
    rows = [
        ["least lap time", f"27:34 ({P['grid_min_lap_s']:.0f} s)",
         f"{lap_text(opt.lap_time)} ({opt.lap_time:.1f} s){flag(opt)}",
         percent(opt.lap_time, P["grid_min_lap_s"])],
        ["its gear ratio", f"{P['grid_min_gear']:g}", f"{opt.gear:g}",
         location_difference(opt.gear, P["grid_min_gear"])],
        ["its pack energy", f"~{P['grid_min_pack_mj']:g} MJ", f"{opt.pack_mj:.2f} MJ",
         location_difference(opt.pack_mj, P["grid_min_pack_mj"], unit=" MJ")],
        [f"gain over gear {ref_gear:g} with {ref_pack_mj:g} MJ",
         f"{paper_gain:.0f} s (1771 - 1654, ~6.5 %)",
         f"{gain:.1f} s{flag(ref)}" if ref else "reference not in the grid",
         percent(gain, paper_gain) if ref else "n/a"],
    ]
    gears = sorted({p.gear for p in points})
    packs = sorted({round(p.pack_mj, 6) for p in points})
    lines = [f"## Gear ratio x pack energy (Fig. 15): {len(points)} points on "
             f"{len(gears)} gears x {len(packs)} packs"
             + ("" if len(points) == len(gears) * len(packs) else " (incomplete grid)"), ""]
    lines += table(["quantity", "paper", "ours", "difference"], rows) + [""]
    lines += status_lines(points) + point_rows(points, "grid") + [""]
    summary = (f"grid: minimum lap {lap_text(opt.lap_time)}{flag(opt)} at gear {opt.gear:g}, "
               f"{opt.pack_mj:.2f} MJ pack")
    return lines, summary + unconverged_note(points)


def paper_row(point):
    """The Table 1 row of the paper with the point's motors and arrangement, or None."""
    for row in PAPER_TABLE1:
        if row[:3] == (point.motors, point.parallel, point.series):
            return row
    return None


def table1_order(points):
    """The points in the paper's order: its configurations first, then the others."""
    def rank(p):
        row = paper_row(p)
        return (PAPER_TABLE1.index(row) if row else len(PAPER_TABLE1), p.motors, p.parallel,
                p.series, p.pack_j)
    return sorted(points, key=rank)


def table1_text(points):
    """table1.md: our Table 1."""
    rows = [[p.motors, p.arrangement, f"{p.pack_mj:.1f}", lap_text_whole(p.lap_time),
             f"{100 * p.energy_fraction:.0f}", "yes" if p.converged else "**NO**"]
            for p in table1_order(points)]
    lines = ["# Table 1: lap time by motor count and pack arrangement", "",
             "Pack arrangement: cells_parallel P cells_series S; pack energy = cells x "
             "battery.cell_energy_j. Lap time m:ss (rounded to the second).", ""]
    lines += table(["motors", "pack", "pack energy MJ", "lap time", "battery usage %", "converged"],
                   rows)
    return "\n".join(lines + [""])


def motors_section(points):
    """report.md section and summary line of the motor-count study."""
    rows = []
    for p in table1_order(points):
        row = paper_row(p)
        config = f"{p.motors} motors, {p.arrangement} ({p.pack_mj:.1f} MJ){flag(p)}"
        ours_lap = f"{lap_text_whole(p.lap_time)} ({p.lap_time:.1f} s)"
        ours_usage = f"{100 * p.energy_fraction:.1f} %"
        if row:
            rows.append([config, f"{lap_text_whole(row[4])} ({row[4]:.0f} s)", ours_lap,
                         percent(p.lap_time, row[4]), f"{row[5]:g} %", ours_usage,
                         points_difference(100 * p.energy_fraction, row[5])])
        else:
            rows.append([config, "not in the paper", ours_lap, "-", "-", ours_usage, "-"])
    lines = [f"## Motors and pack arrangement (Table 1): {len(points)} points", "",
             "Paper lap times as its text gives them (1566 s; its table prints 26m 7s).", ""]
    lines += table(["configuration", "paper lap", "our lap", "difference", "paper usage",
                    "our usage", "difference"], rows) + [""]
    lines += status_lines(points) + point_rows(points, "motors") + [""]
    summary = "motors: " + "; ".join(
        f"{p.motors} motors {p.arrangement} {lap_text_whole(p.lap_time)} "
        f"{100 * p.energy_fraction:.0f} %{flag(p)}" for p in table1_order(points))
    return lines, summary


def reference_section(studies, ref_gear, ref_pack_mj):
    """The reference lap (paper section 4) from whichever study holds the reference design."""
    P = PAPER
    ref = None
    for study in ("gear", "motors", "battery", "grid"):
        ref = find(studies.get(study, []), lambda p: is_reference_gear(p, ref_gear)
                   and is_reference_pack(p, ref_pack_mj) and p.motors == REFERENCE_MOTORS)
        if ref:
            break
    lines = [f"## Reference lap (section 4): gear {ref_gear:g}, {REFERENCE_MOTORS} motors, "
             f"{ref_pack_mj:g} MJ pack", ""]
    if ref is None:
        return lines + ["No point of the studies has the reference design.", ""]
    rows = [["lap time", f"29:31 ({P['reference_lap_s']:.0f} s)",
             f"{lap_text(ref.lap_time)} ({ref.lap_time:.1f} s)",
             percent(ref.lap_time, P["reference_lap_s"])],
            ["energy used", f"~{P['reference_energy_mj']:g} MJ", f"{ref.energy_used / 1e6:.2f} MJ",
             percent(ref.energy_used / 1e6, P["reference_energy_mj"])],
            ["battery usage", f"{P['reference_usage_pct']:g} % of {P['reference_pack_mj']:g} MJ",
             f"{100 * ref.energy_fraction:.1f} % of {ref.pack_mj:.2f} MJ",
             points_difference(100 * ref.energy_fraction, P["reference_usage_pct"])]]
    lines += table(["quantity", "paper", "ours", "difference"], rows)
    return lines + ["", f"From `{ref.name}`{flag(ref)}.", ""]


def cost_section(studies):
    """report.md section and summary line of the solve cost: per study its laps not already
    counted for a study before it, their iterations and solve time (lap.h5's solve_seconds: the
    wall time of each solve, with whatever shared the machine then)."""
    # a copy has no attempts beside it: a solve's attempts are those of any point that has it
    attempts = {}
    for p in (p for points in studies.values() for p in points):
        if p.attempts:
            attempts[p.solve_key] = p.attempts
    counted, rows, untimed = set(), [], 0
    for study, points in studies.items():
        new = []
        for p in points:
            if p.solve_seconds is None:
                untimed += 1
            elif p.solve_key not in counted:
                counted.add(p.solve_key)
                new.append(p)
        tried = [a for p in new for a in attempts.get(p.solve_key, [])]
        rows.append([study, len(points), len(new), len(tried),
                     sum(p.iterations for p in new) + sum(a[0] for a in tried),
                     (sum(p.solve_seconds for p in new) + sum(a[1] for a in tried)) / 3600])
    totals = [sum(row[k] for row in rows) for k in (2, 3, 4, 5)]
    rows.append(["all", sum(row[1] for row in rows), *totals])
    rows = [row[:5] + [f"{row[5]:.2f}"] for row in rows]
    lines = ["## Solve cost", "",
             "Each lap's `solve_seconds` is the wall time of its solve, with whatever else shared "
             "the machine then; a lap shared by several points (the same lap time, iterations and "
             "solve time: a copy) counts once, for the first study that has it. The attempts the "
             "pipeline set aside before a lap (lap-first-attempt.h5, lap-second-attempt.h5 beside "
             "its lap.h5) count with it. `make -j2` solves two laps at once.", ""]
    lines += table(["study", "points", "laps solved", "attempts set aside", "iterations",
                    "solve time h"], rows)
    if untimed:
        lines += ["", f"Points without `iterations`/`solve_seconds`, not counted: {untimed}."]
    total_laps, total_attempts, total_iterations, total_hours = totals
    summary = (f"solve cost: {total_laps} laps, {total_iterations} iterations, {total_hours:.2f} h"
               + (f" ({total_attempts} attempts set aside included)" if total_attempts else ""))
    return lines + [""], summary


def report_text(studies, ref_gear, ref_pack_mj, compared=None):
    """report.md and the summary lines; `compared`: gear_gain's of the gear study."""
    lines = ["# Design studies against the paper (section 5)", "",
             "Paper: paper-tt-zero-lap-time-optimisation.md, sections 4 and 5. Differences are "
             "(ours - paper) / paper; locations (gear ratio, pack energy) give the absolute "
             "difference first, percentages the difference in percentage points (pp). Optima are "
             "taken over converged points only; points with converged = 0 are listed as NOT "
             "CONVERGED and drawn hollow in the figures.", ""]
    lines += reference_section(studies, ref_gear, ref_pack_mj)
    summaries = []
    builders = {"gear": lambda p: gear_section(p, ref_gear, compared),
                "battery": lambda p: battery_section(p, ref_pack_mj),
                "grid": lambda p: grid_section(p, ref_gear, ref_pack_mj),
                "motors": motors_section}
    for study, points in studies.items():
        section, summary = builders[study](points)
        lines += section
        summaries.append(summary)
    section, summary = cost_section(studies)
    return "\n".join(lines + section), summaries + [summary]


# --- figures ---------------------------------------------------------------------------------

def draw_points(axis, x, y, converged, color="C0"):
    """Converged points joined by a line, the others as hollow markers (not joined)."""
    x, y, converged = np.asarray(x), np.asarray(y), np.asarray(converged, dtype=bool)
    axis.plot(x[converged], y[converged], "o-", color=color, ms=5, lw=1)
    axis.plot(x[~converged], y[~converged], "o", ls="none", mfc="none", mec=color, ms=6, mew=1.5)


def mark(axis, x, y, reference):
    """The paper's markers: red circle (reference design) or green diamond (optimum), drawn
    as outlines around the point so a hollow (non-converged) point stays visible."""
    if x is None or not math.isfinite(y):
        return
    style = (dict(marker="o", mec="red", ms=13) if reference
             else dict(marker="D", mec="green", ms=12))
    axis.plot([x], [y], ls="none", mfc="none", mew=2, zorder=5, **style)


def legend(axis, any_unconverged):
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], marker="o", color="C0", label="converged"),
               Line2D([], [], marker="o", ls="none", mfc="none", mec="red", ms=11, mew=2,
                      label="reference (TT Zero 2015)"),
               Line2D([], [], marker="D", ls="none", mfc="none", mec="green", ms=10, mew=2,
                      label="optimum (least lap time)")]
    if any_unconverged:
        handles.insert(1, Line2D([], [], marker="o", ls="none", mfc="none", mec="C0",
                                 label="NOT converged"))
    axis.legend(handles=handles, fontsize=7, loc="best")


def draw_panels(axes, panels, points, x_of, ref, opt, label_size=None):
    """One (label, value) panel per axis: the points vs x_of(point), the reference (when there is
    one) and the optimum marked, labelled and gridded."""
    x = [x_of(p) for p in points]
    conv = [p.converged for p in points]
    for axis, (label, value) in zip(axes, panels):
        draw_points(axis, x, [value(p) for p in points], conv)
        if ref:
            mark(axis, x_of(ref), value(ref), True)
        mark(axis, x_of(opt), value(opt), False)
        axis.set_ylabel(label, fontsize=label_size)
        axis.grid(True, alpha=0.3)


def gear_figure(plt, points, ref_gear):
    """Fig. 12: five panels vs gear ratio."""
    points = sorted(points, key=lambda p: p.gear)
    x = [p.gear for p in points]
    conv = [p.converged for p in points]
    opt = best(points)
    ref = find(points, lambda p: is_reference_gear(p, ref_gear))
    panels = [("lap time [s]", lambda p: p.lap_time),
              ("top speed on course [km/h]", lambda p: KMH * p.top_speed),
              ("0-120 km/h [s]", lambda p: p.accel_120),
              ("energy used [MJ]", lambda p: p.energy_used / 1e6),
              ("power-train efficiency [%]", lambda p: 100 * p.efficiency)]
    figure, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(7, 12))
    draw_panels(axes, panels, points, lambda p: p.gear, ref, opt, label_size=8)
    axes[3].plot(x, [p.pack_mj for p in points], "k-", lw=1.5, label="pack energy")  # energy panel
    legend(axes[0], not all(conv))
    axes[-1].set_xlabel("wheel-to-motor gear ratio [1]")
    figure.suptitle("gear ratio study (paper Fig. 12)")
    figure.tight_layout()
    return figure


def battery_figure(plt, points, ref_pack_mj):
    """Fig. 14: lap time and battery usage vs pack energy."""
    points = sorted(points, key=lambda p: p.pack_j)
    conv = [p.converged for p in points]
    opt = best(points)
    ref = find(points, lambda p: is_reference_pack(p, ref_pack_mj))
    panels = [("lap time [s]", lambda p: p.lap_time),
              ("battery usage [% of pack]", lambda p: 100 * p.energy_fraction)]
    figure, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    draw_panels(axes, panels, points, lambda p: p.pack_mj, ref, opt)
    axes[1].axhline(100.0, color="k", lw=1, ls="--")
    legend(axes[0], not all(conv))
    axes[-1].set_xlabel("pack energy [MJ]")
    figure.suptitle("battery pack study (paper Fig. 14)")
    figure.tight_layout()
    return figure


def grid_figure(plt, points, ref_gear, ref_pack_mj):
    """Fig. 15: lap-time contours over gear ratio x pack energy from the scattered points."""
    import matplotlib.tri as mtri

    conv_points = [p for p in points if p.converged]
    opt = best(points)
    figure, axis = plt.subplots(figsize=(8, 6))
    use, note = conv_points, ""
    if not triangulable(conv_points):
        use, note = points, " (contours include NOT converged points)"
    x = np.array([p.gear for p in use])
    y = np.array([p.pack_mj for p in use])
    z = np.array([p.lap_time for p in use])
    if np.ptp(z) > 0:
        levels = np.linspace(z.min(), z.max(), 15)
        filled = axis.tricontourf(mtri.Triangulation(x, y), z, levels=levels, cmap="viridis_r")
        axis.tricontour(mtri.Triangulation(x, y), z, levels=levels, colors="k", linewidths=0.3)
        figure.colorbar(filled, ax=axis, label="lap time [s]")
    conv = np.array([p.converged for p in points])
    px = np.array([p.gear for p in points])
    py = np.array([p.pack_mj for p in points])
    axis.plot(px[conv], py[conv], "k.", ms=5)
    axis.plot(px[~conv], py[~conv], "o", ls="none", mfc="none", mec="k", ms=7,
              label="NOT converged")
    if px.min() <= ref_gear <= px.max() and py.min() <= ref_pack_mj <= py.max():
        mark(axis, ref_gear, ref_pack_mj, True)  # only inside the grid, not to stretch the axes
    mark(axis, opt.gear, opt.pack_mj, False)
    axis.use_sticky_edges = False  # contours are sticky: margins keep edge markers whole
    axis.margins(0.04)
    axis.annotate(f"{lap_text(opt.lap_time)}", (opt.gear, opt.pack_mj), textcoords="offset points",
                  xytext=(8, 8), color="green")
    if not conv.all():
        axis.legend(fontsize=8)
    axis.set_xlabel("wheel-to-motor gear ratio [1]")
    axis.set_ylabel("pack energy [MJ]")
    axis.set_title("lap time over gear ratio and pack energy (paper Fig. 15)" + note, fontsize=10)
    figure.tight_layout()
    return figure


def triangulable(points):
    """At least 3 points not all on one line."""
    if len(points) < 3:
        return False
    xy = np.array([[p.gear, p.pack_mj] for p in points])
    span = np.ptp(xy, axis=0)
    if np.any(span == 0):
        return False
    return np.linalg.matrix_rank((xy - xy.mean(axis=0)) / span, tol=1e-9) >= 2


# --- command line ----------------------------------------------------------------------------

def parse_args():
    """Command line."""
    parser = ttz_h5.argument_parser(__doc__)
    for study, (option, what, _) in STUDIES.items():
        parser.add_argument(option, nargs="+", metavar="LAP", dest=study,
                            help=f"lap.h5 files or folders of the {study} study ({what})")
    parser.add_argument("-o", "--outdir", required=True, help="output folder")
    parser.add_argument("--reference-gear", type=float, default=2.8,
                        help="gear ratio of the reference design (default 2.8, data/bx15.yaml)")
    parser.add_argument("--reference-pack-mj", type=float, default=PAPER["reference_pack_mj"],
                        help="pack energy of the reference design [MJ] (default 51, 4P24S)")
    parser.add_argument("--partial", action="store_true",
                        help="leave out a study with too few points instead of refusing it")
    args = parser.parse_args()
    if all(getattr(args, study) is None for study in STUDIES) and not args.partial:
        parser.error("give at least one of " + ", ".join(o for o, _, _ in STUDIES.values()))
    return args


def main():
    """Reads and checks every study, then writes the figures, table1.md and report.md."""
    args = parse_args()
    studies = read_studies(args)
    if not studies:
        print("no study has enough points yet: nothing written")
        return
    compared = gear_gain(studies["gear"], args.reference_gear) if "gear" in studies else None
    report, summaries = report_text(studies, args.reference_gear, args.reference_pack_mj, compared)
    plt = ttz_h5.pyplot()
    builders = {}
    if "gear" in studies:
        builders["fig12_gear.png"] = lambda: gear_figure(plt, studies["gear"], args.reference_gear)
    if compared is not None:
        builders["gear_gain.png"] = lambda: lap_compare.delta_figure(
            plt, compared["a"], compared["b"], tuple(f"gear {gear:g}" for gear in compared["gears"]))
    if "battery" in studies:
        builders["fig14_battery.png"] = lambda: battery_figure(plt, studies["battery"],
                                                               args.reference_pack_mj)
    if "grid" in studies:
        builders["fig15_grid.png"] = lambda: grid_figure(plt, studies["grid"], args.reference_gear,
                                                         args.reference_pack_mj)
    figures = {name: build() for name, build in builders.items()}  # all built before any write
    os.makedirs(args.outdir, exist_ok=True)
    for name, figure in figures.items():
        ttz_h5.save_figure(figure, os.path.join(args.outdir, name))
    written = list(figures)
    if "motors" in studies:
        ttz_h5.write_text(os.path.join(args.outdir, "table1.md"), table1_text(studies["motors"]))
        written.append("table1.md")
    ttz_h5.write_text(os.path.join(args.outdir, "report.md"), report)
    written.append("report.md")
    for line in summaries:
        print(line)
    print(f"wrote {', '.join(written)} to {args.outdir}")


if __name__ == "__main__":
    ttz_h5.run_cli(main)
