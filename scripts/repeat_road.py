#!/usr/bin/python3
"""A closed road driven N times: one road.h5 (docs/road_h5.md) whose centre line goes round a
circuit N times, for `lap` to solve a race of N laps (how the pack's energy is spread over a
race) or, with three laps, a near-periodic lap in the middle one (docs/lap.md "Flying laps").

usage: repeat_road.py ROAD.h5 -n N -o ROAD_N.h5

The input must be a closed road (attribute closed = 1: road_fit --closed) with s uniformly
spaced, as road_fit writes it. Every dataset along s is repeated N times without the duplicate
joins (the last sample of a lap is the first of the next): s goes on from the lap's last s,
theta from the turn of a lap (its last minus first value), every other channel (x, y, z, sigma,
banking, width, kappa, nu, tau, borders, lat/lon) repeats as it is. The datasets per input point
(points/*) are the first lap's, as road_fit wrote them. Attributes are copied; length_m and the
attribute `laps` (1 when absent) are multiplied by N, and `repeated_from` names the input file
(docs/road_h5.md); the schema version stays the input's. scripts/lap_splits.py gives the laps'
times of a lap.h5 solved on it.

Writes ROAD_N.h5 atomically (gzip-compressed datasets). Bad input (a missing file, a file that
is not a road.h5, an open road, a missing or non-numeric s, theta or length_m, an s that is not
uniformly increasing, an along-s dataset whose length is not that of s) is one line on stderr,
exit status 1 (2 for a usage error such as N < 2), and nothing is written.
"""
import numpy as np

import ttz_h5


def at_least_two(text):
    """argparse type: an integer of 2 or more."""
    value = int(text)
    if value < 2:
        raise ValueError(text)
    return value


UNIFORM = 1e-6  # largest relative deviation of an s step from the first (lap/road_track.cc's rule)


def read_road(path):
    """{name: (values, attributes)} of every dataset, the file's attributes, checked: closed, with
    s uniformly increasing, theta beside it and a numeric length_m."""
    road = ttz_h5.open_road(path)
    try:
        if not road.attr("closed", int):
            raise ttz_h5.InputError(path, "an open road (closed = 0): only a circuit can be driven again "
                                    "(road_fit --closed)")
        s = road.data("s")
        road.data("theta", s.size)
        road.attr("length_m")
        steps = np.diff(s)
        if s.size < 2 or not np.all(np.abs(steps - steps[0]) <= UNIFORM * steps[0]) or steps[0] <= 0:
            raise ttz_h5.InputError(path, "dataset 's' is not uniformly increasing (as road_fit writes it)")
        datasets = {}
        road.h5.visititems(lambda name, obj: datasets.update({name: (obj[()], dict(obj.attrs))})
                           if hasattr(obj, "shape") else None)
        return datasets, dict(road.h5.attrs)
    finally:
        road.h5.close()


def repeated(name, values, laps, length, turn):
    """One along-s dataset driven `laps` times (joins not duplicated)."""
    offset = {"s": length, "theta": turn}.get(name, 0.0)
    return np.concatenate([values] + [values[1:] + lap * offset for lap in range(1, laps)])


def repeat(path, datasets, attrs, laps):
    """{name: (values, attributes)} and the attributes of the road driven `laps` times."""
    s = datasets["s"][0]
    length = float(s[-1] - s[0])  # the lap's, from s: the joins keep its spacing
    turn = float(datasets["theta"][0][-1] - datasets["theta"][0][0])
    out = {}
    for name, (values, dataset_attrs) in datasets.items():
        along_s = not name.startswith("points/")
        if along_s and values.shape != s.shape:
            raise ttz_h5.InputError(path, f"dataset '{name}' has {values.size} values, {s.size} expected (as 's')")
        out[name] = (repeated(name, values, laps, length, turn) if along_s else values, dataset_attrs)
    return out, dict(attrs, length_m=laps * float(attrs["length_m"]), laps=laps * int(attrs.get("laps", 1)),
                     repeated_from=path)


def write(path, datasets, attrs):
    """The road.h5 at `path`, atomically."""
    import h5py

    def write_file(temp):
        with h5py.File(temp, "w") as h5:
            h5.attrs.update(attrs)
            for name, (values, dataset_attrs) in datasets.items():
                compress = {"compression": "gzip", "shuffle": True} if np.ndim(values) else {}
                h5.create_dataset(name, data=values, **compress).attrs.update(dataset_attrs)

    ttz_h5.write_atomically(path, write_file)


def main():
    """Reads the road, repeats it, writes it."""
    parser = ttz_h5.argument_parser(__doc__)
    parser.add_argument("road", help="road.h5 of a closed circuit")
    parser.add_argument("-n", "--laps", type=at_least_two, required=True, help="laps, 2 or more")
    parser.add_argument("-o", "--output", required=True, help="road.h5 to write")
    args = parser.parse_args()
    datasets, attrs = read_road(args.road)
    datasets, attrs = repeat(args.road, datasets, attrs, args.laps)
    write(args.output, datasets, attrs)
    print(f"{args.output}: {attrs['laps']} laps, {attrs['length_m']:.1f} m")


if __name__ == "__main__":
    ttz_h5.run_cli(main)
