#!/usr/bin/python3
"""Overlays a telemetry CSV's speed vs distance on a lap's V vs s (lap.h5) and prints the RMS
speed difference [m/s].

usage: telemetry_overlay.py lap.h5 telemetry.csv -o overlay.png [--speed-column NAME]
           [--distance-column NAME] [--lap N] [--lap-length M] [--json]

Columns: by default the first of v_wheel_mps, v_gps_mps, speed_mps, v_mps (speed, m/s) and of
distance_m, dist_m, s_m (distance, m) found in the header. The header is the first non-comment
line, or, when the file has none, the column list of a '#' comment line.

Which telemetry is the lap: the lap starts at telemetry distance d0 = 0 if the distances reach
0 or below (a lap distance, 0 at the start line; earlier samples are dropped), else at the first
distance. A telemetry lap is M long: --lap-length, else the whole span d_max - d0 divided into
round(span / road length) equal laps (1 for a single lap: all of it; under half a lap of
telemetry is not rescaled, M = road length). --lap N (default 1, the
first lap) takes [d0 + (N-1) M, d0 + N M]. Its distance is rescaled linearly onto [0, road
length] (s = (d - d_lapstart) L / M), so an odometer that reads long or short still lines up.

RMS: over the lap's mesh nodes (uniform in s, so distance-weighted) inside the telemetry lap's
range, of telemetry speed (linearly interpolated in rescaled distance) minus the lap's state/V.
Prints one line `rms_speed_difference_mps=<value>`, or with --json one JSON object.
The telemetry distance must not decrease.
"""
import json
import os

import numpy as np

import ttz_h5

SPEED_COLUMNS = ("v_wheel_mps", "v_gps_mps", "speed_mps", "v_mps")
DISTANCE_COLUMNS = ("distance_m", "dist_m", "s_m")


def pick_column(path, given, candidates):
    """The column to use: the one given, else the first candidate the CSV has."""
    if given:
        return given
    header = ttz_h5.csv_header(path)
    for name in candidates:
        if name in header:
            return name
    raise ttz_h5.InputError(path, "malformed CSV: none of the columns " + ", ".join(candidates)
                            + " (choose with --speed-column / --distance-column)")


def read_telemetry(path, distance_column, speed_column):
    """(distance [m], speed [m/s]) of the telemetry, the distance checked not to decrease."""
    distance_column = pick_column(path, distance_column, DISTANCE_COLUMNS)
    speed_column = pick_column(path, speed_column, SPEED_COLUMNS)
    columns = ttz_h5.read_csv_columns(path, (distance_column, speed_column))
    distance = columns[distance_column]
    backwards = np.flatnonzero(np.diff(distance) < 0)
    if backwards.size:
        raise ttz_h5.InputError(path, f"column '{distance_column}' decreases after data row "
                                f"{backwards[0] + 1} ({distance[backwards[0]]} -> "
                                f"{distance[backwards[0] + 1]})")
    return distance, columns[speed_column]


def lap_window(path, distance, road_length, lap_number, lap_length):
    """(start, length) of telemetry lap `lap_number` in telemetry distance [m]."""
    start = 0.0 if distance[0] <= 0 else distance[0]
    span = distance[-1] - start
    if lap_length is None:
        laps = round(span / road_length)
        lap_length = span / laps if laps >= 1 else road_length
    if lap_length <= 0 or lap_number < 1:
        raise ttz_h5.InputError(path, f"no lap {lap_number} of length {lap_length:.1f} m")
    first = start + (lap_number - 1) * lap_length
    if first >= distance[-1]:
        raise ttz_h5.InputError(path, f"no lap {lap_number}: distance ends at {distance[-1]:.1f} m,"
                                f" lap {lap_number} would start at {first:.1f} m")
    return first, lap_length


def rescaled_lap(distance, speed, window, road_length):
    """(s [m], speed [m/s]) of the telemetry samples inside window = (start, length), their
    distance mapped linearly onto [0, road_length]."""
    start, length = window
    inside = (distance >= start) & (distance <= start + length)
    return (distance[inside] - start) * road_length / length, speed[inside]


def rms_difference(s_lap, v_lap, s_tel, v_tel):
    """(RMS [m/s] of telemetry minus lap speed over the lap nodes covered by s_tel, nodes)."""
    covered = (s_lap >= s_tel[0]) & (s_lap <= s_tel[-1])
    difference = np.interp(s_lap[covered], s_tel, v_tel) - v_lap[covered]
    return float(np.sqrt(np.mean(difference ** 2))), int(covered.sum())


def overlay_figure(s_lap, v_lap, s_tel, v_tel, labels):
    """Speed [km/h] vs distance [km] of the lap and of the rescaled telemetry."""
    plt = ttz_h5.pyplot()
    figure, axis = plt.subplots(figsize=(11, 4))
    axis.plot(s_lap / 1e3, 3.6 * v_lap, lw=0.9, label=labels[0])
    axis.plot(s_tel / 1e3, 3.6 * v_tel, lw=0.7, alpha=0.8, label=labels[1])
    axis.set_xlabel("distance s [km] (telemetry rescaled to the road length)")
    axis.set_ylabel("speed [km/h]")
    axis.grid(True, alpha=0.3)
    axis.legend()
    figure.tight_layout()
    return figure


def parse_args():
    """Command line."""
    parser = ttz_h5.argument_parser(__doc__)
    parser.add_argument("lap", help="lap.h5")
    parser.add_argument("telemetry", help="telemetry CSV")
    parser.add_argument("-o", "--output", required=True, help="overlay PNG")
    parser.add_argument("--speed-column", help="speed column [m/s]")
    parser.add_argument("--distance-column", help="distance column [m]")
    parser.add_argument("--lap", type=int, default=1, dest="lap_number",
                        help="telemetry lap to compare, 1-based (default 1)")
    parser.add_argument("--lap-length", type=float,
                        help="length of one telemetry lap in its own distance [m]")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    return parser.parse_args()


def main():
    """Reads the lap and the telemetry, writes the overlay, prints the RMS difference."""
    args = parse_args()
    lap = ttz_h5.open_lap(args.lap)
    s_lap = lap.data("s")
    v_lap = lap.data("state/V", s_lap.size)
    road_length = s_lap[-1]
    distance, speed = read_telemetry(args.telemetry, args.distance_column, args.speed_column)
    window = lap_window(args.telemetry, distance, road_length, args.lap_number, args.lap_length)
    s_tel, v_tel = rescaled_lap(distance, speed, window, road_length)
    if s_tel.size < 2:
        raise ttz_h5.InputError(args.telemetry, f"fewer than 2 samples in lap {args.lap_number}")
    rms, nodes = rms_difference(s_lap, v_lap, s_tel, v_tel)
    labels = (f"lap {os.path.basename(args.lap)}",
              f"telemetry {os.path.basename(args.telemetry)} (lap {args.lap_number})")
    ttz_h5.save_figure(overlay_figure(s_lap, v_lap, s_tel, v_tel, labels), args.output)
    result = {"rms_speed_difference_mps": rms, "nodes": nodes, "lap": args.lap_number,
              "telemetry_lap_start_m": window[0], "telemetry_lap_length_m": window[1],
              "distance_scale": road_length / window[1]}
    print(json.dumps(result) if args.json else f"rms_speed_difference_mps={rms:.4f}")


if __name__ == "__main__":
    ttz_h5.run_cli(main)
