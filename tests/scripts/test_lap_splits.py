#!/usr/bin/python3
"""lap_splits.py on the tiny lap.h5 fixture taken as two laps: times, speeds and energies at the
lap lines (interpolated between nodes), bad input refused."""
import json
import unittest

import h5py
import numpy as np

import ttz_fixtures as fx


class LapSplitsTest(fx.TempFolder, fx.ScriptAssertions, unittest.TestCase):
    def lap(self, name="lap.h5"):
        """The fixture lap with a charge falling 1 MJ per 100 m."""
        path = fx.write_lap(self.path(name))
        with h5py.File(path, "a") as h5:
            h5.create_dataset("state/e", data=50e6 - 1e4 * h5["s"][()])
        return path

    def test_two_laps(self):
        lap = self.lap()
        result = fx.run("lap_splits.py", lap, "--laps", "2", "--json")
        self.assert_ok(result)
        rows = json.loads(result.stdout)
        with h5py.File(lap) as h5:
            s, t = h5["s"][()], h5["t"][()]
        half = fx.LAP_LENGTH_M / 2
        self.assertEqual([r["lap"] for r in rows], [1, 2])
        self.assertAlmostEqual(rows[0]["time_s"], np.interp(half, s, t), places=9)
        self.assertAlmostEqual(rows[0]["time_s"] + rows[1]["time_s"], t[-1], places=9)
        self.assertAlmostEqual(rows[1]["start_kmh"], 3.6 * fx.lap_speed(half), places=6)  # linear: exact
        self.assertAlmostEqual(rows[1]["end_kmh"], 3.6 * fx.lap_speed(fx.LAP_LENGTH_M), places=6)
        self.assertAlmostEqual(rows[0]["energy_mj"], 5.0, places=9)
        text = fx.run("lap_splits.py", lap, "-n", "2").stdout
        self.assertIn(f"lap 2: {rows[1]['time_s']:.3f} s, 90.00 -> 108.00 km/h, 5.000 MJ", text)

    def test_bad_input_is_one_line(self):
        lap = self.lap()
        zero = fx.run("lap_splits.py", lap, "--laps", "0")
        self.assertEqual(zero.returncode, 2)
        self.assert_refused(zero, "--laps")
        self.assert_refused(fx.run("lap_splits.py", self.path("none.h5"), "-n", "2"), "none.h5", "no such file")
        no_charge = fx.write_lap(self.path("no_e.h5"))
        self.assert_refused(fx.run("lap_splits.py", no_charge, "-n", "2"), "no_e.h5", "state/e")
        with h5py.File(lap, "a") as h5:
            h5["t"][5] = 0.0
        self.assert_refused(fx.run("lap_splits.py", lap, "-n", "2"), "lap.h5", "do not both increase")


if __name__ == "__main__":
    fx.main()
