#!/usr/bin/python3
"""Two laps of the same road side by side: where one gains time on the other (a design change,
a flying against a standing start, another mesh or solver).

usage: lap_compare.py A.h5 B.h5 -o delta.png [--segment-m 1000] [--rows 3] [--json]

Both files are lap.h5 artefacts (docs/lap_h5.md) of one road: refused when their road_sha256
differ and their road_length differ by more than 1 m (the rule of lap --init). B's time t [s]
and speed state/V [m/s] are interpolated linearly in s onto A's nodes, so the two meshes may
differ. The lap times are the time datasets' last values.

Prints the two lap times and B - A [s] (negative: B is faster), then the road cut into segments
of --segment-m metres (the last one shorter) and the --rows segments where B gains the most and
loses the most (changes under 0.5 ms are neither): the change of t_B - t_A over the segment [s],
with A's and B's mean speeds there [km/h] (segment length over the time taken). --json prints the same as one JSON object.

Writes delta.png: both speeds [km/h] and the running difference t_B(s) - t_A(s) [s] against the
distance [km].

Bad input (a missing file, a file that is not a lap.h5, laps of different roads, a time that
does not increase along s, a non-positive --segment-m or --rows) is one line on stderr, exit
status 1 (2 for a usage error), and nothing is written.
"""
import json

import numpy as np

import ttz_h5

KMH = 3.6  # (km/h) per (m/s)
SAME_ROAD_M = 1.0  # largest difference of road_length of two laps of one road [m]
NOTABLE_S = 5e-4   # a segment's change below this [s] is neither a gain nor a loss (its 3 decimals)


def read_lap(path):
    """s [m], t [s], V [m/s] and the road's identity of one lap, checked."""
    lap = ttz_h5.open_lap(path)
    try:
        s = lap.data("s")
        t, V = lap.data("t", s.size), lap.data("state/V", s.size)
        if s.size < 2 or not (np.all(np.diff(s) > 0) and np.all(np.diff(t) > 0)):
            raise ttz_h5.InputError(path, "'s' and 't' must increase from node to node")
        return {"path": path, "s": s, "t": t, "V": ttz_h5.require_finite(path, "state/V", V),
                "road_sha256": lap.optional_attr("road_sha256", str, ""),
                "road_length": lap.attr("road_length")}
    finally:
        lap.h5.close()


def check_same_road(a, b):
    """InputError naming B when it is a lap of another road than A."""
    same_file = a["road_sha256"] and a["road_sha256"] == b["road_sha256"]
    if not same_file and abs(a["road_length"] - b["road_length"]) > SAME_ROAD_M:
        raise ttz_h5.InputError(b["path"], f"is a lap of another road: road_length {b['road_length']:.1f} m "
                                f"against {a['road_length']:.1f} m of {a['path']}")


def segments(a, b_t, segment_m):
    """[(start, end) [m], change of t_B - t_A [s], A's and B's mean speeds [m/s]] of each
    segment of A's road, B's time b_t on A's nodes."""
    s = a["s"]
    edges = np.append(np.arange(s[0], s[-1], segment_m), s[-1])
    t_a = np.interp(edges, s, a["t"])
    t_b = np.interp(edges, s, b_t)
    rows = []
    for k in range(edges.size - 1):
        length = edges[k + 1] - edges[k]
        if length <= 0.0:
            continue
        da, db = t_a[k + 1] - t_a[k], t_b[k + 1] - t_b[k]
        rows.append({"from_m": float(edges[k]), "to_m": float(edges[k + 1]), "delta_s": float(db - da),
                     "speed_a": length / da, "speed_b": length / db})
    return rows


def compare(a, b, segment_m, rows):
    """The comparison as a dict (the --json object)."""
    b_t = np.interp(a["s"], b["s"], b["t"])
    parts = segments(a, b_t, segment_m)
    by_gain = sorted(parts, key=lambda p: p["delta_s"])
    return {"a": a["path"], "b": b["path"], "lap_time_a": float(a["t"][-1]), "lap_time_b": float(b["t"][-1]),
            "difference_s": float(b["t"][-1] - a["t"][-1]), "segment_m": segment_m,
            "b_gains": [p for p in by_gain[:rows] if p["delta_s"] <= -NOTABLE_S],
            "b_loses": [p for p in reversed(by_gain[-rows:]) if p["delta_s"] >= NOTABLE_S]}


def report_text(result):
    """The comparison as lines of text."""
    def segment_line(p):
        return (f"  {p['from_m'] / 1e3:7.2f}-{p['to_m'] / 1e3:.2f} km  {p['delta_s']:+8.3f} s  "
                f"(A {KMH * p['speed_a']:.1f} km/h, B {KMH * p['speed_b']:.1f} km/h)")

    lines = [f"A  {result['a']}: {result['lap_time_a']:.3f} s",
             f"B  {result['b']}: {result['lap_time_b']:.3f} s",
             f"B - A  {result['difference_s']:+.3f} s",
             f"where B gains most ({result['segment_m']:g} m segments):"]
    lines += [segment_line(p) for p in result["b_gains"]] or ["  nowhere"]
    lines += ["where B loses most:"]
    lines += [segment_line(p) for p in result["b_loses"]] or ["  nowhere"]
    return "\n".join(lines)


def delta_figure(plt, a, b, labels=("A", "B")):
    """Speeds [km/h] and t_B - t_A [s] against the distance along A's road [km]; the laps named
    by `labels` in the legend."""
    figure, (speed, delta) = plt.subplots(2, 1, figsize=(11, 7), sharex=True)
    km = a["s"] / 1e3
    speed.plot(km, KMH * a["V"], lw=0.8, label=labels[0])
    speed.plot(b["s"] / 1e3, KMH * b["V"], lw=0.8, label=labels[1])
    speed.set_ylabel("speed [km/h]")
    speed.legend()
    delta.plot(km, np.interp(a["s"], b["s"], b["t"]) - a["t"], color="k", lw=0.9)
    delta.axhline(0.0, color="0.6", lw=0.5)
    delta.set_ylabel(f"t({labels[1]}) - t({labels[0]}) [s]")
    delta.set_xlabel("distance s [km]")
    for axis in (speed, delta):
        axis.grid(True, alpha=0.3)
    figure.tight_layout()
    return figure


def main():
    """Reads both laps, then prints the comparison and writes the figure."""
    parser = ttz_h5.argument_parser(__doc__)
    parser.add_argument("a", help="lap.h5 A")
    parser.add_argument("b", help="lap.h5 B, of the same road")
    parser.add_argument("-o", "--output", required=True, help="delta.png to write")
    parser.add_argument("--segment-m", type=ttz_h5.positive(float), default=1000.0, help="segment length [m]")
    parser.add_argument("--rows", type=ttz_h5.positive(int), default=3, help="segments listed each way")
    parser.add_argument("--json", action="store_true", help="print the comparison as JSON")
    args = parser.parse_args()
    a, b = read_lap(args.a), read_lap(args.b)
    check_same_road(a, b)
    result = compare(a, b, args.segment_m, args.rows)
    ttz_h5.save_figure(delta_figure(ttz_h5.pyplot(), a, b), args.output)
    print(json.dumps(result) if args.json else report_text(result))


if __name__ == "__main__":
    ttz_h5.run_cli(main)
