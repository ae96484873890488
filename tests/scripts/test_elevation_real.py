#!/usr/bin/python3
"""elevation_compare.py on the real FlightGear and bike-sim profiles of the Snaefell course.
usage: test_elevation_real.py SHARED_DATA_DIR"""
import json
import os
import sys
import tempfile
import unittest

import ttz_fixtures as fx

DATA = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("TTZ_SHARED_DATA", "")


@unittest.skipUnless(DATA, "no shared data folder given")
class ElevationRealTest(fx.ScriptAssertions, unittest.TestCase):
    def test_flightgear_vs_bikesim(self):
        folder = os.path.join(DATA, "snaefell")
        self.assertTrue(os.path.isdir(folder), f"{folder} not found")
        with tempfile.TemporaryDirectory() as tmp:
            png = os.path.join(tmp, "elevation.png")
            result = fx.run("elevation_compare.py", os.path.join(folder, "elevation-flightgear.csv"),
                            os.path.join(folder, "elevation-bikesim.csv"), "--centreline",
                            os.path.join(folder, "centreline-osm.csv"), "-o", png, "--json")
            self.assert_ok(result)
            self.assertGreater(os.path.getsize(png), 1000)
        stats = json.loads(result.stdout)
        # The README: the two agree to about 11 m standard deviation; the loop is 60.6 km.
        self.assertLess(stats["rms_m"], 15.0)
        self.assertLess(abs(stats["mean_m"]), 5.0)
        self.assertAlmostEqual(stats["length_km"], 60.64, delta=0.1)
        self.assertEqual((stats["left_out_a"], stats["left_out_b"]), (0, 0))


if __name__ == "__main__":
    fx.main()
