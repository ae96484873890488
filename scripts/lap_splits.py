#!/usr/bin/python3
"""The laps of a race solved on a repeated road (scripts/repeat_road.py): each lap's time, the
speed at its start and end, and the energy it used.

usage: lap_splits.py LAP.h5 --laps N [--json]

LAP.h5 is a lap.h5 (docs/lap_h5.md) solved on a road driven N times: lap i runs from
s = (i - 1) L to i L, L = road_length / N. The mesh need not have nodes on those lines, so time
t [s], speed state/V [m/s] and charge state/e [J] are interpolated linearly in s there. Prints
a line per lap: its time [s], the speed at its start and end [km/h] and the energy it used [MJ];
--json prints the same as a JSON list.

Bad input (a missing file, a file that is not a lap.h5, a missing dataset, a time that does not
increase along s) is one line on stderr, exit status 1 (2 for a usage error such as N < 1); the
script writes no file.
"""
import json

import numpy as np

import ttz_h5

KMH = 3.6  # (km/h) per (m/s)


def read_lap(path):
    """s [m], t [s], V [m/s], e [J] and the road's length [m] of a lap.h5, checked."""
    lap = ttz_h5.open_lap(path)
    try:
        s = lap.data("s")
        channels = {name: lap.data(name, s.size) for name in ("t", "state/V", "state/e")}
        length = lap.attr("road_length")
    finally:
        lap.h5.close()
    if s.size < 2 or not np.all(np.diff(s) > 0) or not np.all(np.diff(channels["t"]) > 0):
        raise ttz_h5.InputError(path, "'s' and 't' do not both increase along the lap")
    return s, channels, length


def splits(s, channels, length, laps):
    """[{lap, time_s, start_kmh, end_kmh, energy_mj}] of each of the `laps` laps."""
    at = {name: (lambda x, v=values: float(np.interp(x, s, v))) for name, values in channels.items()}
    out = []
    for i in range(laps):
        start, end = s[0] + i * length / laps, s[0] + (i + 1) * length / laps
        out.append({"lap": i + 1, "time_s": at["t"](end) - at["t"](start),
                    "start_kmh": KMH * at["state/V"](start), "end_kmh": KMH * at["state/V"](end),
                    "energy_mj": (at["state/e"](start) - at["state/e"](end)) / 1e6})
    return out


def main():
    """Reads the lap, prints its splits."""
    parser = ttz_h5.argument_parser(__doc__)
    parser.add_argument("lap", help="lap.h5 of a road driven N times")
    parser.add_argument("-n", "--laps", type=ttz_h5.positive(int), required=True, help="laps of its road")
    parser.add_argument("--json", action="store_true", help="print the splits as JSON")
    args = parser.parse_args()
    rows = splits(*read_lap(args.lap), args.laps)
    if args.json:
        print(json.dumps(rows))
        return
    for r in rows:
        print(f"lap {r['lap']}: {r['time_s']:.3f} s, {r['start_kmh']:.2f} -> {r['end_kmh']:.2f} km/h, "
              f"{r['energy_mj']:.3f} MJ")


if __name__ == "__main__":
    ttz_h5.run_cli(main)
