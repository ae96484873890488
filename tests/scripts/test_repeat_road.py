#!/usr/bin/python3
"""repeat_road.py on a tiny road.h5 fixture: the road driven three times, bad input refused."""
import unittest

import h5py
import numpy as np

import ttz_fixtures as fx


class RepeatRoadTest(fx.TempFolder, fx.ScriptAssertions, unittest.TestCase):
    def test_three_laps(self):
        road = fx.write_road(self.path("road.h5"), banking=-0.1, closed=True)
        with h5py.File(road, "a") as h5:
            h5.create_dataset("points/s", data=[1.0, 2.0, 3.0])
        out = self.path("out", "road3.h5")
        result = fx.run("repeat_road.py", road, "-n", "3", "-o", out)
        self.assert_ok(result)
        self.assertIn("3 laps, 3000.0 m", result.stdout)
        with h5py.File(road) as one, h5py.File(out) as three:
            s, s1 = three["s"][()], one["s"][()]
            self.assertEqual(s.size, 3 * s1.size - 2)  # the joins are not duplicated
            np.testing.assert_allclose(np.diff(s), s1[1] - s1[0])  # uniform, as lap needs
            self.assertEqual(s[-1], 3 * fx.LAP_LENGTH_M)
            turn = one["theta"][-1] - one["theta"][0]
            np.testing.assert_allclose(three["theta"][s1.size - 1:2 * s1.size - 1], one["theta"][()] + turn)
            for name in ("x", "z", "kappa", "banking"):  # repeated as they are (after the join)
                np.testing.assert_array_equal(three[name][2 * s1.size - 1:], one[name][1:])
            np.testing.assert_array_equal(three["points/s"][()], [1.0, 2.0, 3.0])  # the first lap's
            self.assertEqual(three["kappa"].attrs["units"], "1/m")
            self.assertEqual(three.attrs["laps"], 3)
            self.assertEqual(three.attrs["length_m"], 3 * fx.LAP_LENGTH_M)
            self.assertEqual(three.attrs["schema_version"], 2)
            self.assertEqual(three.attrs["repeated_from"], road)
        self.assert_no_temporaries(self.path("out"))
        # repeated again: the laps multiply; a version 1 road (no banking) stays version 1
        six = self.path("road6.h5")
        self.assert_ok(fx.run("repeat_road.py", out, "-n", "2", "-o", six))
        level = fx.write_road(self.path("level.h5"), closed=True)
        self.assert_ok(fx.run("repeat_road.py", level, "-n", "2", "-o", self.path("level2.h5")))
        with h5py.File(six) as h6, h5py.File(self.path("level2.h5")) as h2:
            self.assertEqual((h6.attrs["laps"], h6.attrs["length_m"]), (6, 6 * fx.LAP_LENGTH_M))
            self.assertEqual(h6["s"][-1], 6 * fx.LAP_LENGTH_M)
            self.assertEqual(h2.attrs["schema_version"], 1)
            self.assertNotIn("banking", h2)

    def test_bad_input_is_one_line_and_nothing_written(self):
        out = self.path("road2.h5")
        open_road = fx.write_road(self.path("open.h5"))
        self.assert_refused(fx.run("repeat_road.py", open_road, "-n", "2", "-o", out), "open.h5", "an open road",
                            absent=[out])
        closed = fx.write_road(self.path("closed.h5"), closed=True)
        one = fx.run("repeat_road.py", closed, "-n", "1", "-o", out)
        self.assertEqual(one.returncode, 2)
        self.assert_refused(one, "--laps", absent=[out])
        self.assert_refused(fx.run("repeat_road.py", self.path("none.h5"), "-n", "2", "-o", out), "none.h5",
                            "no such file", absent=[out])
        with h5py.File(closed, "a") as h5:
            del h5["z"]
            h5.create_dataset("z", data=[0.0, 1.0])
        self.assert_refused(fx.run("repeat_road.py", closed, "-n", "2", "-o", out), "closed.h5", "'z' has 2 values",
                            absent=[out])
        with h5py.File(closed, "a") as h5:
            del h5["theta"]
        self.assert_refused(fx.run("repeat_road.py", closed, "-n", "2", "-o", out), "closed.h5", "'theta'",
                            absent=[out])
        uneven = fx.write_road(self.path("uneven.h5"), closed=True)
        with h5py.File(uneven, "a") as h5:
            h5["s"][7] += 0.5
        self.assert_refused(fx.run("repeat_road.py", uneven, "-n", "2", "-o", out), "uneven.h5",
                            "not uniformly increasing", absent=[out])


if __name__ == "__main__":
    fx.main()
