#!/usr/bin/python3
"""elevation_compare.py on a constructed square loop with known elevation differences."""
import json
import math
import os
import unittest

import ttz_fixtures as fx

LAT0, LON0 = 54.2, -4.5
SIDE_M = 1000.0
STEP_M = 50.0
R = 6371000.0


def square_point(s):
    """(east, north) [m] at distance s along a square loop of side SIDE_M centred on the origin,
    starting at its south-west corner, anticlockwise."""
    side, along = divmod(s % (4 * SIDE_M), SIDE_M)
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1), (-1, -1)]
    (x0, y0), (x1, y1) = corners[int(side)], corners[int(side) + 1]
    t = along / SIDE_M
    return 0.5 * SIDE_M * (x0 + t * (x1 - x0)), 0.5 * SIDE_M * (y0 + t * (y1 - y0))


def lat_lon(x, y):
    """Inverse of the scripts' equirectangular projection about (LAT0, LON0)."""
    return LAT0 + math.degrees(y / R), LON0 + math.degrees(x / (R * math.cos(math.radians(LAT0))))


def write_points(path, distances, elevations=None, header="lat_deg,lon_deg,elev_m"):
    with open(path, "w") as handle:
        handle.write(f"# constructed\n{header}\n")
        for k, s in enumerate(distances):
            lat, lon = lat_lon(*square_point(s))
            extra = f",{elevations[k]!r}" if elevations is not None else ""
            handle.write(f"{lat!r},{lon!r}{extra}\n")
    return path


def profile(s):
    return 100.0 + 20.0 * math.sin(2 * math.pi * s / (4 * SIDE_M))


class ElevationCompareTest(fx.TempFolder, fx.ScriptAssertions, unittest.TestCase):
    def setUp(self):
        super().setUp()
        self.png = self.path("out.png")
        distances = [STEP_M * k for k in range(int(4 * SIDE_M / STEP_M))]
        self.centre = write_points(self.path("centre.csv"), distances, header="lat_deg,lon_deg")
        # A at every 50 m, plus one point 300 m off the course that must be left out.
        a_elev = [profile(s) for s in distances]
        self.a = write_points(self.path("a.csv"), distances, a_elev)
        with open(self.a, "a") as handle:
            lat, lon = lat_lon(0.0, 0.0)
            handle.write(f"{lat!r},{lon!r},9999\n")
        # B = A - 3, and A - 13 at s = 500 m.
        b_elev = [e - (13.0 if s == 500.0 else 3.0) for s, e in zip(distances, a_elev)]
        self.b = write_points(self.path("b.csv"), distances, b_elev)

    def compare(self, a, b, *options):
        return fx.run("elevation_compare.py", a, b, "--centreline", self.centre, "-o", self.png,
                      *options)

    def test_known_difference(self):
        result = self.compare(self.a, self.b, "--json")
        self.assert_ok(result)
        stats = json.loads(result.stdout)
        # On the 10 m grid the difference is 3 m plus a triangle 10 m high, 100 m wide at 500 m
        # (grid values 2, 4, 6, 8, 10, 8, 6, 4, 2 over 400 points): mean 3 + 50/400,
        # mean square 9 + 6 * 50/400 + 340/400.
        self.assertAlmostEqual(stats["mean_m"], 3.125, places=6)
        self.assertAlmostEqual(stats["rms_m"], math.sqrt(10.6), places=6)
        self.assertAlmostEqual(stats["max_abs_m"], 13.0, places=6)
        self.assertAlmostEqual(stats["at_km"], 0.5, places=6)
        self.assertAlmostEqual(stats["length_km"], 4.0, places=6)
        self.assertEqual((stats["left_out_a"], stats["left_out_b"]), (1, 0))
        self.assertGreater(os.path.getsize(self.png), 1000)
        self.assert_no_temporaries(self.dir)

    def test_plain_output_line(self):
        result = self.compare(self.b, self.b)
        self.assert_ok(result)
        self.assertEqual(result.stdout.strip(), "mean_m=0.00 rms_m=0.00 max_abs_m=0.00 at_km=0.00")

    def test_malformed_csv(self):
        with open(self.path("bad.csv"), "w") as handle:
            handle.write("lat_deg,lon_deg,elev_m\n54.2,-4.5,100\n54.2,-4.5,high\n")
        self.assert_refused(self.compare(self.a, self.path("bad.csv")), "bad.csv", "line 3",
                            absent=(self.png,))

    def test_missing_elevation_column(self):
        self.assert_refused(self.compare(self.a, self.centre), "centre.csv", "elev_m",
                            absent=(self.png,))

    def test_missing_file(self):
        self.assert_refused(self.compare(self.a, self.path("none.csv")), "none.csv",
                            "no such file", absent=(self.png,))

    def test_missing_option(self):
        result = fx.run("elevation_compare.py", self.a, self.b, "-o", self.png)
        self.assert_refused(result, "--centreline", absent=(self.png,))


if __name__ == "__main__":
    fx.main()
