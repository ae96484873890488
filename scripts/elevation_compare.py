#!/usr/bin/python3
"""Compares two elevation polylines of a closed course (CSV with lat_deg, lon_deg, elev_m) along
a centre line (CSV with lat_deg, lon_deg), prints the mean, RMS and largest difference A - B [m]
and writes a PNG of both profiles and of the difference vs distance [km].

usage: elevation_compare.py A.csv B.csv --centreline centreline.csv -o out.png [--max-offset M] [--json]
e.g.   elevation_compare.py elevation-flightgear.csv elevation-bikesim.csv \\
           --centreline centreline-osm.csv -o elevation.png

Method: every elevation point is placed at the distance along the centre line of its nearest
point on the centre line (orthogonal projection onto the nearest segment, in a local
equirectangular frame [m]). Not the polylines' own cumulative distance rescaled: the FlightGear
line has segments up to 1.8 km that cut the corners, so its length is short by an amount that
varies along the course and a linear rescaling would misplace hills by hundreds of metres; a
projection puts each point where it is on the road, whatever the spacing of its polyline.
The centre line is a closed loop (its last point joins its first), so distance is periodic:
each profile is interpolated linearly in distance, with wrap-around, onto a common 10 m grid over
the whole loop, and the statistics are over that grid (distance-weighted). Points farther than
--max-offset (default 100 m) from the centre line are left out and counted.

Output: one line `mean_m=... rms_m=... max_abs_m=... at_km=...` (A - B), or JSON with --json.
"""
import json
import os

import numpy as np

import ttz_h5

GRID_STEP_M = 10.0


class Centreline:
    """A closed centre line in a local frame [m], with cumulative distance of its vertices."""

    def __init__(self, path):
        columns = ttz_h5.read_csv_columns(path, ("lat_deg", "lon_deg"), min_rows=3)
        self.origin = (float(np.mean(columns["lat_deg"])), float(np.mean(columns["lon_deg"])))
        x, y = ttz_h5.local_xy(columns["lat_deg"], columns["lon_deg"], *self.origin)
        if np.hypot(x[-1] - x[0], y[-1] - y[0]) > 1e-3:
            x, y = np.append(x, x[0]), np.append(y, y[0])  # close the loop
        self.start = np.column_stack([x[:-1], y[:-1]])
        self.step = np.column_stack([np.diff(x), np.diff(y)])
        lengths = np.hypot(self.step[:, 0], self.step[:, 1])
        self.cumulative = np.concatenate([[0.0], np.cumsum(lengths)])
        self.length = float(self.cumulative[-1])
        self.step_sq = np.maximum(lengths ** 2, 1e-12)

    def project(self, lat_deg, lon_deg):
        """(distance along the loop [m], distance off the line [m]) of each point."""
        px, py = ttz_h5.local_xy(lat_deg, lon_deg, *self.origin)
        along, offset = np.empty(px.size), np.empty(px.size)
        for k, point in enumerate(np.column_stack([px, py])):
            along[k], offset[k] = self._project_one(point)
        return along, offset

    def _project_one(self, point):
        """Projection of one point [m] on its nearest segment."""
        u = np.clip(np.einsum("ij,ij->i", point - self.start, self.step) / self.step_sq, 0, 1)
        foot = self.start + u[:, None] * self.step
        gaps = np.hypot(*(foot - point).T)
        i = int(np.argmin(gaps))
        along = self.cumulative[i] + u[i] * (self.cumulative[i + 1] - self.cumulative[i])
        return along % self.length, gaps[i]


def read_profile(path, centreline, max_offset):
    """(distance [m], elevation [m], points left out) of an elevation polyline on the loop,
    sorted by distance."""
    columns = ttz_h5.read_csv_columns(path, ("lat_deg", "lon_deg", "elev_m"))
    along, offset = centreline.project(columns["lat_deg"], columns["lon_deg"])
    near = offset <= max_offset
    if near.sum() < 2:
        raise ttz_h5.InputError(path, f"fewer than 2 points within {max_offset} m of the centre line")
    order = np.argsort(along[near], kind="stable")
    return along[near][order], columns["elev_m"][near][order], int((~near).sum())


def compare(grid, profile_a, profile_b, period):
    """(A, B, A - B) on the grid [m], each interpolated periodically in distance."""
    a = np.interp(grid, profile_a[0], profile_a[1], period=period)
    b = np.interp(grid, profile_b[0], profile_b[1], period=period)
    return a, b, a - b


def statistics(grid, difference):
    """Mean, RMS and largest absolute difference [m] and where that is [km]."""
    worst = int(np.argmax(np.abs(difference)))
    return {"mean_m": float(np.mean(difference)),
            "rms_m": float(np.sqrt(np.mean(difference ** 2))),
            "std_m": float(np.std(difference)),
            "max_abs_m": float(abs(difference[worst])),
            "at_km": float(grid[worst] / 1e3)}


def profile_figure(grid, curves, names, stats):
    """Both profiles and their difference [m] vs distance [km]."""
    plt = ttz_h5.pyplot()
    figure, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(11, 6),
                                         gridspec_kw={"height_ratios": [2, 1]})
    for curve, name in zip(curves[:2], names):
        top.plot(grid / 1e3, curve, lw=0.9, label=name)
    top.set_ylabel("elevation [m]")
    top.legend()
    bottom.plot(grid / 1e3, curves[2], lw=0.8, color="C3")
    bottom.set_ylabel(f"{names[0]} - {names[1]} [m]", fontsize=8)
    bottom.set_xlabel("distance along the centre line [km]")
    bottom.set_title(f"mean {stats['mean_m']:.1f} m, RMS {stats['rms_m']:.1f} m, "
                     f"max |diff| {stats['max_abs_m']:.1f} m", fontsize=9)
    for axis in (top, bottom):
        axis.grid(True, alpha=0.3)
    figure.tight_layout()
    return figure


def parse_args():
    """Command line."""
    parser = ttz_h5.argument_parser(__doc__)
    parser.add_argument("a", help="first elevation CSV (lat_deg, lon_deg, elev_m)")
    parser.add_argument("b", help="second elevation CSV")
    parser.add_argument("--centreline", required=True, help="closed centre line CSV (lat_deg, lon_deg)")
    parser.add_argument("-o", "--output", required=True, help="PNG to write")
    parser.add_argument("--max-offset", type=float, default=100.0,
                        help="leave out points farther from the centre line [m] (default 100)")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    return parser.parse_args()


def main():
    """Projects both profiles, compares them on a common grid, writes the PNG, prints figures."""
    args = parse_args()
    centreline = Centreline(args.centreline)
    profile_a = read_profile(args.a, centreline, args.max_offset)
    profile_b = read_profile(args.b, centreline, args.max_offset)
    grid = np.arange(0.0, centreline.length, GRID_STEP_M)
    curves = compare(grid, profile_a, profile_b, centreline.length)
    stats = statistics(grid, curves[2])
    stats.update(length_km=centreline.length / 1e3, left_out_a=profile_a[2], left_out_b=profile_b[2])
    names = [os.path.splitext(os.path.basename(p))[0] for p in (args.a, args.b)]
    ttz_h5.save_figure(profile_figure(grid, curves, names, stats), args.output)
    if args.json:
        print(json.dumps(stats))
    else:
        print(" ".join(f"{k}={stats[k]:.2f}" for k in ("mean_m", "rms_m", "max_abs_m", "at_km")))


if __name__ == "__main__":
    ttz_h5.run_cli(main)
