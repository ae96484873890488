#!/usr/bin/python3
"""The reference lap (lap.h5, docs/lap_h5.md) of the BX-15 on the Snaefell Mountain Course beside
the figures the paper (Dal Bianco et al., TT Zero lap-time paper) gives for its reference lap: a
markdown report with, per figure, the paper's value, ours, the difference in percent
(ours - paper) / paper (for percentages also in percentage points) and where the paper gives it.

usage: reference_report.py LAP.h5 [--calibration calibration.txt] -o report.md

Rows:
  lap time          paper 29:31 = 1771 s (sec 4, simulated), and as context the real 2015 practice
                    lap 29:47 = 1787 s. With --calibration (the file scripts/calibrate.py writes:
                    '#' comment lines, then key=value lines) the row is marked "fitted
                    (calibration: key=value)": the pipeline fits one bike constant to this lap
                    time, so it is no validation. When the lap's bike_yaml holds that key at
                    another value the lap is not the calibrated one, and the report says so
                    instead. A calibration file without key=value lines (a piece of the course)
                    fits nothing.
  energy used       paper 72 % of the 51 MJ pack = 36.7 MJ (Table 1, 2 motors 4P24S); ours the
                    attributes energy_used [J] and energy_fraction (pack = their ratio)
  average speed     paper 122 km/h (sec 5, dual motor, reference gear); ours the attribute
                    average_speed (road length / lap time), or road_length / lap_time without it
  power-train       paper "close to or slightly below 70 %" (Fig. 11: power delivered to the
  efficiency        ground vs power drained from the battery); ours the integral of wheel/power
                    dt over the integral of battery/power P_b dt, both over the nodes where the
                    bike drives (P_b > 0), trapezoids in t. Power to the ground = wheel/power, the
                    drive's torque at the wheel times the wheel speed, tau_t omega_w = eta_c
                    omega_m tau_e (eq. 31; without the brake torque, which state/tau_w includes):
                    the power train's output, as study_report.py takes it. The note also gives
                    the ratio with tyre/force_x x state/V (the traction power on the bike, after
                    the tyre's rolling resistance and slip, and counting the brakes where they act
                    while the pack still delivers power): not a power-train figure.
  Fig. 10           battery current linear in speed and in motor voltage: Pearson r and the
                    least-squares slope of battery/current vs state/V [A per m/s] and vs
                    motor/voltage [A per V], over the nodes with battery/current > 0; the paper
                    gives no number ("linear trend"), so no difference
  Fig. 8 / Fig. 9   levels, ours only (the paper's text gives no numbers: "graph only"): battery
                    voltage start/end/min/max [V], battery current mean/max [A], battery power
                    mean/max [kW], motor voltage max [V], motor current max [A] (all motors).
                    Means are time-weighted (trapezoids in t over the lap time), not node means:
                    the mesh is not uniform in time.
What buys time: when the lap has design sensitivities (sensitivity/key and sensitivity/per_percent,
lap/sensitivity.h: the indirect solver's laps), a second table lists the SENSITIVITY_ROWS largest
by size of the design values (sensitivity/kind "design"), the lap time 1 % more of each bike value
costs (negative: buys), with the value itself; a third lists the values of the other kinds (the
rider's limits, conditions such as gravity, the motor's reference temperature); values without a
finite figure are named below them.
The header names the lap file and its converged / resim_passed attributes; a lap that did not
converge is flagged at the top. Constraints whose max_violation_<kind> exceeds the solver's
1e-4 tolerance are listed there too.

Writes report.md atomically (its folder created if missing) and prints the table on stdout.
Bad input (a missing file, a file that is not a lap.h5, a missing dataset or attribute,
non-finite values, an unreadable calibration file) is one line on stderr, exit status 1, and
nothing is written.
"""
import math

import numpy as np

import study_report
import ttz_h5

KMH = 3.6  # (km/h) per (m/s)
SENSITIVITY_ROWS = 10
CHANNELS = ("t", "state/V", "tyre/force_x", "wheel/power", "battery/power", "battery/current",
            "battery/voltage", "motor/voltage", "motor/current")
VIOLATION_TOLERANCE = 1e-4   # docs/lap_h5.md: the check allows 1e-4

# The paper's figures for its reference lap (2 motors, 4P24S 51 MJ pack, gear ratio 2.8).
PAPER = {
    "lap_s": 1771.0,            # sec 4: simulated 29 min 31 s
    "practice_lap_s": 1787.0,   # sec 4: the real 2015 practice lap, 29 min 47 s
    "usage_pct": 72.0,          # Table 1: 72 % of the pack
    "pack_mj": 51.0,            # Table 1: 4P24S, 51 MJ
    "average_speed_kmh": 122.0,  # sec 5: dual motor, reference gear
    "efficiency_pct": 70.0,     # Fig. 11: "close to or slightly below 70 %"
}
PAPER["energy_mj"] = PAPER["usage_pct"] / 100.0 * PAPER["pack_mj"]   # 36.72 MJ


# --- reading ---------------------------------------------------------------------------------

def read_lap(path):
    """({dataset: values}, {attribute: value}) of the lap, every channel checked finite."""
    lap = ttz_h5.open_lap(path)
    try:
        s = lap.data("s")
        channels = {name: lap.data(name, s.size) for name in CHANNELS}
        for name, values in channels.items():
            ttz_h5.require_finite(path, name, values)
        attrs = {name: lap.attr(name) for name in
                 ("lap_time", "energy_used", "energy_fraction", "road_length")}
        attrs["converged"] = lap.attr("converged", int)
        attrs["message"] = lap.optional_attr("message", str, "")
        attrs["resim_passed"] = lap.optional_attr("resim_passed", int)
        attrs["resim_message"] = lap.optional_attr("resim_message", str, "")
        attrs["average_speed"] = lap.optional_attr("average_speed")
        attrs["bike_yaml"] = lap.optional_attr("bike_yaml", str)
        attrs["violations"] = {name[len("max_violation_"):]: lap.attr(name)
                               for name in sorted(lap.h5.attrs)
                               if name.startswith("max_violation_")}
        attrs["sensitivities"] = ttz_h5.sensitivities(lap)
        return channels, attrs
    finally:
        lap.h5.close()


def sensitivity_lines(sensitivities):
    """The SENSITIVITY_ROWS largest finite sensitivities of design values by size as a markdown
    section, then those of the other kinds (the rider's limits, conditions, references), and the
    values without a finite one named ([] without any)."""
    if not sensitivities:
        return []
    largest, missing = ttz_h5.largest_sensitivities(sensitivities, SENSITIVITY_ROWS)
    designs = sum(1 for row in sensitivities if row[3] == "design")
    rows = [[f"`{key}`", f"{value:.6g}", f"{per_percent:+.3f} s"] for key, value, per_percent, _ in largest]
    lines = ["", "## What buys lap time (design sensitivities of this lap, lap.h5 sensitivity/*)", "",
             "The lap time 1 % more of each bike value costs (negative: buys), by the adjoint of "
             f"the solve (lap/sensitivity.h); the {len(largest)} largest of the {designs} design values.", ""
             ] + study_report.table(["bike value", "value", "lap time per 1 % more"], rows)
    others = []
    for kind in ttz_h5.SENSITIVITY_KINDS[1:]:  # after design
        found, lost = ttz_h5.largest_sensitivities(sensitivities, len(sensitivities), kind)
        others += [[f"`{key}`", kind, f"{value:.6g}", f"{per_percent:+.3f} s"] for key, value, per_percent, _ in found]
        missing += lost
    if others:
        lines += ["", "Not changes to the bike (sensitivity/kind): the rider's limits, the day's and the start's "
                  "conditions, and the motor's reference temperature (the temperature its constants are given at):", ""
                  ] + study_report.table(["bike value", "kind", "value", "lap time per 1 % more"], others)
    if missing:
        lines += ["", "Without a finite figure (left out): " + ", ".join(f"`{key}`" for key in missing)]
    return lines


def read_calibration(path):
    """The key=value lines of a calibration file as [(key, value text)] ('#' lines skipped)."""
    pairs = []
    try:
        with open(path) as handle:
            for number, line in enumerate(handle, start=1):
                line = line.strip()
                if not line or line.startswith("#"):
                    continue
                key, sep, value = line.partition("=")
                if not sep or not key.strip() or not value.strip():
                    raise ttz_h5.InputError(path, f"line {number}: '{line}' is not key=value")
                pairs.append((key.strip(), value.strip()))
    except FileNotFoundError:
        raise ttz_h5.InputError(path, "no such file") from None
    except UnicodeDecodeError:
        raise ttz_h5.InputError(path, "not a text file") from None
    return pairs


def lap_bike(path, bike_yaml):
    """{'section.key': value} of the lap's bike_yaml attribute ({} without one)."""
    return study_report.parse_bike(path, bike_yaml) if bike_yaml else {}


# --- figures ---------------------------------------------------------------------------------

def driving_ratio(t, numerator, battery_power):
    """Integral of numerator over integral of battery power, both over the nodes where the
    battery power is > 0 (zero elsewhere; trapezoids in t) [1]."""
    driving = battery_power > 0
    drawn = np.trapz(np.where(driving, battery_power, 0.0), t)
    if drawn <= 0:
        return math.nan
    return float(np.trapz(np.where(driving, numerator, 0.0), t) / drawn)


def linear_fit(x, y):
    """(Pearson r, least-squares slope dy/dx, points) of y vs x; NaN where undefined."""
    if x.size < 2 or np.ptp(x) == 0:
        return math.nan, math.nan, x.size
    slope = float(np.polyfit(x, y, 1)[0])
    r = float(np.corrcoef(x, y)[0, 1]) if np.ptp(y) > 0 else math.nan
    return r, slope, x.size


def time_mean(t, values):
    """Time-weighted mean over the lap (trapezoids in t)."""
    span = t[-1] - t[0]
    return float(np.trapz(values, t) / span) if span > 0 else float(np.mean(values))


def figures(ch, attrs):
    """Our figures, in the units of the report (s, MJ, %, km/h, V, A, kW)."""
    t, v, pb = ch["t"], ch["state/V"], ch["battery/power"]
    fraction = attrs["energy_fraction"]
    average = attrs["average_speed"]
    if average is None:
        average = attrs["road_length"] / attrs["lap_time"]
    drawing = ch["battery/current"] > 0
    ours = {
        "lap_s": attrs["lap_time"],
        "energy_mj": attrs["energy_used"] / 1e6,
        "usage_pct": 100.0 * fraction,
        "pack_mj": attrs["energy_used"] / fraction / 1e6 if fraction else math.nan,
        "average_speed_kmh": KMH * average,
        "efficiency_pct": 100.0 * driving_ratio(t, ch["wheel/power"], pb),
        "tyre_efficiency_pct": 100.0 * driving_ratio(t, ch["tyre/force_x"] * v, pb),
        "driving_time_pct": 100.0 * float(np.trapz(np.where(pb > 0, 1.0, 0.0), t)
                                          / (t[-1] - t[0])) if t[-1] > t[0] else math.nan,
        "fit_speed": linear_fit(v[drawing], ch["battery/current"][drawing]),
        "fit_voltage": linear_fit(ch["motor/voltage"][drawing],
                                  ch["battery/current"][drawing]),
    }
    bv, bi = ch["battery/voltage"], ch["battery/current"]
    ours["levels"] = [
        ("battery voltage at the start", f"{bv[0]:.1f} V"),
        ("battery voltage at the end", f"{bv[-1]:.1f} V"),
        ("battery voltage min / max", f"{bv.min():.1f} / {bv.max():.1f} V"),
        ("battery current mean (time-weighted) / max",
         f"{time_mean(t, bi):.1f} / {bi.max():.1f} A"),
        ("battery power mean (time-weighted) / max",
         f"{time_mean(t, pb) / 1e3:.1f} / {pb.max() / 1e3:.1f} kW"),
        ("motor voltage max (Fig. 9)", f"{ch['motor/voltage'].max():.1f} V"),
        ("motor current max, all motors (Fig. 9)", f"{ch['motor/current'].max():.1f} A"),
    ]
    return ours


# --- report ----------------------------------------------------------------------------------

def number(value, digits=1, unit=""):
    """A float as text ('n/a' when not finite)."""
    return f"{value:.{digits}f}{unit}" if value is not None and math.isfinite(value) else "n/a"


def calibration_note(calibration, bike, lap_path):
    """(marks the lap time as fitted, note) from the calibration's key=value pairs and the
    lap's bike."""
    path, pairs = calibration
    if not pairs:
        return False, f"validation: `{path}` holds no key=value line (nothing fitted)"
    mismatched = []
    for key, value in pairs:
        ours = bike.get(key)
        try:
            wanted = float(value)
            differs = ours is not None and abs(float(ours) - wanted) > 1e-6 * abs(wanted)
        except (TypeError, ValueError):
            differs = str(ours) != value
        if differs:
            mismatched.append(f"{key}={value} but this lap has {key}={ours}")
    fitted = ", ".join(f"{key}={value}" for key, value in pairs)
    if mismatched:
        return False, (f"validation: this lap is NOT the calibrated one (calibration `{path}`: "
                       + "; ".join(mismatched) + ")")
    return True, (f"**fitted (calibration: {fitted})**: the pipeline fits this constant to "
                  "the paper's lap time, so this row is not a validation")


def rows(ours, calibration, bike, lap_path):
    """The comparison table's rows: figure | paper | ours | difference | source / note."""
    pct = study_report.percent
    lap_note = "sec 4 (simulated reference lap); validation (no --calibration given)"
    if calibration is not None:
        fitted, note = calibration_note(calibration, bike, lap_path)
        lap_note = f"sec 4 (simulated reference lap); {note}"
    r_v, slope_v, n_v = ours["fit_speed"]
    r_u, slope_u, _ = ours["fit_voltage"]
    result = [
        ["lap time", "29:31 (1771 s)",
         f"{study_report.lap_text(ours['lap_s'])} ({ours['lap_s']:.1f} s)",
         pct(ours["lap_s"], PAPER["lap_s"]), lap_note],
        ["lap time vs the real 2015 practice lap (context)", "29:47 (1787 s, measured)",
         f"{study_report.lap_text(ours['lap_s'])} ({ours['lap_s']:.1f} s)",
         pct(ours["lap_s"], PAPER["practice_lap_s"]),
         "sec 4: the BX-15's 2015 practice lap; the simulation is of an ideal rider"],
        ["energy used", f"{PAPER['energy_mj']:.1f} MJ (72 % of 51 MJ)",
         f"{number(ours['energy_mj'], 2)} MJ", pct(ours["energy_mj"], PAPER["energy_mj"]),
         "Table 1 (2 motors, 4P24S); sec 5 text: 37 MJ at gear 2.8"],
        ["battery usage (of the pack)", f"72 % of {PAPER['pack_mj']:g} MJ",
         f"{number(ours['usage_pct'])} % of {number(ours['pack_mj'], 2)} MJ",
         study_report.points_difference(ours["usage_pct"], PAPER["usage_pct"]),
         "Table 1; pack = energy_used / energy_fraction"],
        ["average speed", "122 km/h", f"{number(ours['average_speed_kmh'])} km/h",
         pct(ours["average_speed_kmh"], PAPER["average_speed_kmh"]),
         "sec 5 (dual motor, reference gear); ours road length / lap time"],
        ["overall power-train efficiency (driving)", "close to or slightly below 70 %",
         f"{number(ours['efficiency_pct'])} %",
         study_report.points_difference(ours["efficiency_pct"], PAPER["efficiency_pct"]),
         "Fig. 11; ours: integral of wheel/power (drive torque x wheel speed) over integral "
         "of battery/power, where battery/power > 0 "
         f"({number(ours['driving_time_pct'])} % of the lap time); with tyre/force_x x state/V "
         "instead (after rolling resistance, slip and any braking while driving): "
         f"{number(ours['tyre_efficiency_pct'])} %"],
        ["battery current vs speed (Fig. 10)", "linear trend",
         f"r = {number(r_v, 3)}, slope {number(slope_v, 2)} A per m/s", "-",
         f"Fig. 10; Pearson r and least-squares slope over the {n_v} nodes with "
         "battery/current > 0"],
        ["battery current vs motor voltage (Fig. 10)", "linear trend",
         f"r = {number(r_u, 3)}, slope {number(slope_u, 3)} A per V", "-",
         "Fig. 10; same nodes"],
    ]
    result += [[name, "graph only", value, "-", "Fig. 8" if "battery" in name else "Fig. 9"]
               for name, value in ours["levels"]]
    return result


def header(lap_path, attrs):
    """Title, the lap's file and state, a prominent warning for a lap that did not converge."""
    lines = ["# Reference lap vs the paper (Dal Bianco et al., TT Zero)", ""]
    if not attrs["converged"]:
        lines += [f"**WARNING: this lap did NOT converge (converged = 0): "
                  f"{attrs['message'] or '(no message)'}. Its figures are not a solution.**", ""]
    resim = attrs["resim_passed"]
    resim_text = ("not recorded" if resim is None else "1 (passed)" if resim
                  else f"0 (failed: {attrs['resim_message'] or 'no message'})")
    lines += [f"- lap file: `{lap_path}`",
              f"- converged: {attrs['converged']}" + ("" if attrs["converged"] else " (NO)"),
              f"- resim_passed: {resim_text}"]
    violated = {k: v for k, v in attrs["violations"].items() if v > VIOLATION_TOLERANCE}
    if violated:
        lines.append("- constraints violated by more than 1e-4 (max_violation_<kind>, scaled by "
                     "the limit): " + ", ".join(f"{k} {v:.3g}" for k, v in violated.items()))
    lines += ["- difference: (ours - paper) / paper; for percentages also in percentage points "
              "(pp)", ""]
    return lines


def report_text(lap_path, attrs, ours, calibration, bike):
    """The whole report.md and, separately, its table (printed on stdout)."""
    table = study_report.table(["figure", "paper", "ours", "difference %",
                                "source in paper / note"],
                               rows(ours, calibration, bike, lap_path))
    lines = header(lap_path, attrs) + table + sensitivity_lines(attrs["sensitivities"])
    return "\n".join(lines + [""]), "\n".join(table)


def parse_args():
    """Command line."""
    parser = ttz_h5.argument_parser(__doc__)
    parser.add_argument("lap", help="lap.h5 of the reference lap")
    parser.add_argument("--calibration", help="calibration.txt of scripts/calibrate.py: the lap "
                        "time row is then marked as fitted")
    parser.add_argument("-o", "--output", required=True, help="report.md to write")
    return parser.parse_args()


def main():
    """Reads and checks everything, then writes the report."""
    args = parse_args()
    channels, attrs = read_lap(args.lap)
    calibration = None
    if args.calibration is not None:
        calibration = (args.calibration, read_calibration(args.calibration))
    bike = lap_bike(args.lap, attrs["bike_yaml"]) if calibration else {}
    text, table = report_text(args.lap, attrs, figures(channels, attrs), calibration, bike)
    ttz_h5.write_text(args.output, text)
    print(table)


if __name__ == "__main__":
    ttz_h5.run_cli(main)
