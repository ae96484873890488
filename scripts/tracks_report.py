#!/usr/bin/python3
"""One bike's laps of several circuits side by side (the pipelines' `tracks` target,
docs/pipelines.md "Other circuits"): a markdown table with a row per lap.h5 (docs/lap_h5.md),
the circuit named after the lap's folder, its road read from road.h5 in the same folder
(docs/road_h5.md).

usage: tracks_report.py LAP.h5 [LAP.h5 ...] -o report.md

Columns:
  circuit           the name of the lap's folder
  length            road length_m [km]
  elevation range   max - min of the road's z [m]
  tightest radius   1 / max |kappa| of the centre line [m]
  largest banking   max |banking| [deg] (0 for a road level across, or a road.h5 of version 1)
  lap time          m:ss.s (lap_time)
  average speed     road length / lap time [km/h]
  top speed         top_speed [km/h]
  energy used       energy_used [MJ] and energy_fraction of the pack [%]
  start             standing or flying (the lap's `start`, lap --start; standing in laps written
                    before it) with the speed at the line, state/V at the first node [km/h]
  converged         yes, or no with the solver's message
  re-simulation     the lap time's difference (resim_lap_time_relative) [%], then "passed" or the
                    state that differs most with its difference (resim_worst_state,
                    resim_max_state_difference) [% of the state's scale]
  largest design sensitivity  the design value of bike.yaml (sensitivity/kind "design": not the
                    rider's limits, conditions such as gravity, or the motor's reference
                    temperature) whose 1 % more changes the lap time most (sensitivity/*, the
                    indirect solver's laps) with that change [s] (negative: faster), or "-" for a
                    lap without sensitivities or without a finite one

Writes report.md atomically (its folder created if missing) and prints it on stdout. Bad input
(a missing file, a file that is not a lap.h5, no road.h5 beside a lap or one of another length, a
missing dataset or attribute, a figure that is not finite or a lap time, length, top speed or
pack share that is not positive, a re-simulation verdict without its figures) is one line on
stderr, exit status 1, and nothing is written.
"""
import math
import os

import numpy as np

import lap_plots
import ttz_h5

KMH = 3.6  # (km/h) per (m/s)
HEADER = ("circuit", "length [km]", "elevation range [m]", "tightest radius [m]", "largest banking [deg]", "lap time",
          "average speed [km/h]", "top speed [km/h]", "energy used [MJ]", "start", "converged",
          "re-simulation", "largest design sensitivity (1 % more)")


def checked(path, name, value, positive=False):
    """`value` when it is finite (and > 0 with `positive`), else InputError naming `name`."""
    if not math.isfinite(value) or (positive and value <= 0.0):
        raise ttz_h5.InputError(path, f"'{name}' is {value}, expected a finite"
                                f"{' positive' if positive else ''} number")
    return value


def read_lap_figures(lap_path):
    """{figure: value} of one lap.h5, each checked."""
    lap = ttz_h5.open_lap(lap_path)
    try:
        row = {name: checked(lap_path, name, lap.attr(name), positive=name != "energy_used")
               for name in ("lap_time", "energy_used", "energy_fraction", "top_speed", "road_length")}
        speed = lap.data("state/V")
        row.update(converged=lap.attr("converged", int), message=lap.attr("message", str),
                   start=lap.optional_attr("start", str, "standing"),
                   start_speed=checked(lap_path, "state/V", float(speed[0]) if speed.size else math.nan),
                   resim_passed=lap.optional_attr("resim_passed", int),
                   largest=ttz_h5.largest_sensitivities(ttz_h5.sensitivities(lap), 1)[0])
        if row["resim_passed"] is not None:  # the check's figures come with its verdict
            row.update(resim_time=checked(lap_path, "resim_lap_time_relative", lap.attr("resim_lap_time_relative")),
                       resim_state=checked(lap_path, "resim_max_state_difference",
                                           lap.attr("resim_max_state_difference")),
                       resim_worst=lap.optional_attr("resim_worst_state", str, "a state"))
        return row
    finally:
        lap.h5.close()


def read_circuit(lap_path):
    """{figure: value} of one lap and the road.h5 beside it."""
    row = read_lap_figures(lap_path)
    folder = os.path.dirname(os.path.abspath(lap_path))
    road_path = os.path.join(folder, "road.h5")
    road = lap_plots.read_road(road_path, row["road_length"], ("s", "z", "kappa", "banking"))
    for name in ("z", "kappa", "banking"):
        ttz_h5.require_finite(road_path, name, road[name])
    row.update(name=os.path.basename(folder), z_range=float(np.ptp(road["z"])),
               kappa_max=float(np.max(np.abs(road["kappa"]))),
               banking_max=math.degrees(float(np.max(np.abs(road["banking"])))))
    return row


def resim_text(row):
    """The re-simulation column: lap time difference, then passed or the worst state."""
    if row["resim_passed"] is None:
        return "not run"
    text = f"lap time {100 * row['resim_time']:.4f} %, "
    if row["resim_passed"]:
        return text + "passed"
    return text + f"{row['resim_worst']} {100 * row['resim_state']:.1f} % (failed)"


def sensitivity_text(row):
    """The design value the lap time is most sensitive to, with its seconds per 1 % more, or "-"."""
    if not row["largest"]:
        return "-"
    key, _, per_percent, _ = row["largest"][0]
    return f"`{key}` {per_percent:+.2f} s"


def table_row(row):
    """The markdown cells of one circuit."""
    radius = 1.0 / row["kappa_max"] if row["kappa_max"] > 0 else float("inf")
    return [row["name"], f"{row['road_length'] / 1e3:.2f}", f"{row['z_range']:.0f}",
            f"{radius:.1f}", f"{row['banking_max']:.1f}", lap_plots.format_lap_time(row["lap_time"]),
            f"{KMH * row['road_length'] / row['lap_time']:.1f}", f"{KMH * row['top_speed']:.1f}",
            f"{row['energy_used'] / 1e6:.2f} ({100 * row['energy_fraction']:.1f} %)",
            f"{row['start']} at {KMH * row['start_speed']:.1f} km/h", "yes" if row["converged"] else "no: " + row["message"],
            resim_text(row), sensitivity_text(row)]


def report_text(rows):
    """report.md: a title, the table, and how to read it."""
    lines = ["# One bike round several circuits", "",
             "| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    lines += ["| " + " | ".join(table_row(row)) + " |" for row in rows]
    lines += ["", "A standing start is bike.yaml's initial speed, as on the TT; a flying one the speed "
              "with which the QSS lap on the centre line arrives back at the line (lap --start "
              "flying). Roads as fitted by road_fit: banked where the input gives the banking "
              "(3-D border points, a banking column), else level across. "
              "docs/pipelines.md \"Other circuits\".", ""]
    return "\n".join(lines)


def main():
    """Reads every lap and road, then writes the report."""
    parser = ttz_h5.argument_parser(__doc__)
    parser.add_argument("laps", nargs="+", help="lap.h5 files, each with its road.h5 beside it")
    parser.add_argument("-o", "--output", required=True, help="report.md to write")
    args = parser.parse_args()
    text = report_text([read_circuit(path) for path in args.laps])
    ttz_h5.write_text(args.output, text)
    print(text)


if __name__ == "__main__":
    ttz_h5.run_cli(main)
