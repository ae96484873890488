#!/usr/bin/python3
"""Prints `--init PATH` for the warm start of one point of a design study, or nothing.

    nearest_lap.py POINT_FOLDER [--along K]

A study (pipelines/Makefile) keeps each point in a folder named after its values joined by "_"
(`gear/3.4`, `grid/3.4_42`); the point's lap is POINT_FOLDER/lap.h5. The nearest point is the
sibling folder holding a finished lap.h5 whose values are closest to POINT_FOLDER's in the sum of
relative differences; ties go to the smaller values. With --along K (1-based) only the siblings
whose other values equal POINT_FOLDER's count: its neighbours along its K-th value (`--along 2`
in the grid: the same gear, another pack). Nothing is printed when no such sibling has finished
(a cold start) or a name is not numeric.
"""
import os

import ttz_h5


def values(name):
    try:
        return [float(v) for v in name.split("_")]
    except ValueError:
        return None


def distance(a, b):
    return sum(abs(x - y) / max(abs(x), abs(y), 1e-12) for x, y in zip(a, b))


def on_line(a, b, along):
    """True when a and b differ at most in their along-th value (1-based; None: any)."""
    return along is None or all(x == y for i, (x, y) in enumerate(zip(a, b)) if i != along - 1)


def main():
    parser = ttz_h5.argument_parser(__doc__)
    parser.add_argument("point")
    parser.add_argument("--along", type=int, help="only neighbours along this value (1-based)")
    args = parser.parse_args()
    point = os.path.abspath(args.point)
    study, name = os.path.split(point)
    target = values(name)
    if target is None or not os.path.isdir(study):
        return
    if args.along is not None and not 1 <= args.along <= len(target):
        parser.error(f"--along {args.along}: {name} has {len(target)} value(s)")
    siblings = {n: values(n) for n in os.listdir(study) if n != name}
    done = [(distance(v, target), v, os.path.join(study, n, "lap.h5"))
            for n, v in sorted(siblings.items())
            if v is not None and len(v) == len(target) and on_line(v, target, args.along)
            and os.path.isfile(os.path.join(study, n, "lap.h5"))]
    if done:
        print("--init", min(done)[2])


if __name__ == "__main__":
    main()
