#!/usr/bin/python3
"""lap_compare.py on tiny lap.h5 fixtures: B faster on the second half of the road, on another
mesh; the totals and the segments where it gains; bad input refused."""
import json
import os
import unittest

import h5py
import numpy as np

import ttz_fixtures as fx


def write_lap_at(path, nodes, faster=1.0):
    """A lap of the fixture road on `nodes` nodes at fx.lap_speed, `faster` times that beyond
    500 m; its time by the trapezoidal rule of 1/V."""
    fx.write_lap(path)
    s = np.linspace(0.0, fx.LAP_LENGTH_M, nodes)
    v = fx.lap_speed(s) * np.where(s > 500.0, faster, 1.0)
    t = np.concatenate([[0.0], np.cumsum(np.diff(s) * 0.5 * (1 / v[1:] + 1 / v[:-1]))])
    with h5py.File(path, "a") as h5:
        for name, values in (("s", s), ("t", t), ("state/V", v)):
            del h5[name]
            h5.create_dataset(name, data=values)
    return path


class LapCompareTest(fx.TempFolder, fx.ScriptAssertions, unittest.TestCase):
    def test_where_b_gains(self):
        a = write_lap_at(self.path("a.h5"), 101)
        b = write_lap_at(self.path("b.h5"), 61, faster=1.1)
        png = self.path("delta.png")
        result = fx.run("lap_compare.py", a, b, "-o", png, "--segment-m", "250", "--rows", "2", "--json")
        self.assert_ok(result)
        out = json.loads(result.stdout)
        with h5py.File(a) as ha, h5py.File(b) as hb:
            t_a, t_b = ha["t"][-1], hb["t"][-1]
        self.assertAlmostEqual(out["difference_s"], t_b - t_a, places=9)
        self.assertLess(out["difference_s"], -1.0)  # ~10 % of the second half's ~20 s
        # B gains on the two last segments (500-1000 m); on the first half only the meshes differ
        self.assertEqual([(p["from_m"], p["to_m"]) for p in sorted(out["b_gains"], key=lambda p: p["from_m"])],
                         [(500.0, 750.0), (750.0, 1000.0)])
        for p in out["b_loses"]:
            self.assertLess(p["to_m"], 500.1)
            self.assertLess(p["delta_s"], 1e-3)
        for p in out["b_gains"]:
            self.assertAlmostEqual(p["speed_b"] / p["speed_a"], 1.1, delta=0.01)
        self.assertGreater(os.path.getsize(png), 1000)
        text = fx.run("lap_compare.py", b, a, "-o", png).stdout
        self.assertIn("where B gains most (1000 m segments):\n  nowhere\nwhere B loses most:\n     0.00-1.00 km", text)
        self.assertIn("B - A  +", text)

    def test_bad_input_is_one_line_and_nothing_written(self):
        a = fx.write_lap(self.path("a.h5"))
        png = self.path("delta.png")
        other = fx.write_lap(self.path("other.h5"))
        with h5py.File(other, "a") as h5:
            h5.attrs["road_length"] = 2 * fx.LAP_LENGTH_M
        self.assert_refused(fx.run("lap_compare.py", a, other, "-o", png), "other.h5", "a lap of another road",
                            absent=[png])
        backwards = fx.write_lap(self.path("backwards.h5"))
        with h5py.File(backwards, "a") as h5:
            h5["t"][5] = 0.0
        self.assert_refused(fx.run("lap_compare.py", a, backwards, "-o", png), "backwards.h5", "increase",
                            absent=[png])
        self.assert_refused(fx.run("lap_compare.py", a, self.path("none.h5"), "-o", png), "none.h5",
                            absent=[png])
        self.assert_refused(fx.run("lap_compare.py", a, a, "-o", png, "--segment-m", "0"), "--segment-m",
                            absent=[png])


if __name__ == "__main__":
    fx.main()
