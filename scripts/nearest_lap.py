#!/usr/bin/python3
"""Prints `--init PATH` for the warm start of one point of a design study, or nothing.

    nearest_lap.py POINT_FOLDER

A study (pipelines/Makefile) keeps each point in a folder named after its values joined by "_"
(`gear/3.4`, `grid/3.4_42`); the point's lap is POINT_FOLDER/lap.h5. The nearest point is the
sibling folder holding a finished lap.h5 whose values are closest to POINT_FOLDER's in the sum of
relative differences; ties go to the smaller values. Nothing is printed when no sibling has finished
(a cold start) or a name is not numeric.
"""
import os
import sys


def values(name):
    try:
        return [float(v) for v in name.split("_")]
    except ValueError:
        return None


def distance(a, b):
    return sum(abs(x - y) / max(abs(x), abs(y), 1e-12) for x, y in zip(a, b))


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: nearest_lap.py POINT_FOLDER")
    point = os.path.abspath(sys.argv[1])
    study, name = os.path.split(point)
    target = values(name)
    if target is None or not os.path.isdir(study):
        return
    done = [(distance(values(n), target), values(n), os.path.join(study, n, "lap.h5"))
            for n in sorted(os.listdir(study))
            if n != name and values(n) is not None and len(values(n)) == len(target)
            and os.path.isfile(os.path.join(study, n, "lap.h5"))]
    if done:
        print("--init", min(done)[2])


if __name__ == "__main__":
    main()
