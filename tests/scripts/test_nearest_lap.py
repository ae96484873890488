#!/usr/bin/python3
"""nearest_lap.py on a study folder of empty lap.h5 files: the nearest finished sibling, the
neighbours along one value only (--along), a cold start when none has finished, bad --along, a
usage error in one line."""
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.environ.get("TTZ_SCRIPTS_DIR", "scripts"), "nearest_lap.py")


def nearest(*args):
    run = subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)
    return run.returncode, run.stdout.strip(), run.stderr


class NearestLapTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.grid = os.path.join(self.tmp.name, "grid")
        for point in ("3.1_42", "3.4_60", "3.7_42"):   # finished points
            os.makedirs(os.path.join(self.grid, point))
            open(os.path.join(self.grid, point, "lap.h5"), "w").close()
        os.makedirs(os.path.join(self.grid, "3.4_51"))  # started, not finished

    def tearDown(self):
        self.tmp.cleanup()

    def lap(self, point):
        return "--init " + os.path.join(self.grid, point, "lap.h5")

    def test_the_nearest_finished_sibling_in_relative_differences(self):
        # 3.4_42: 3.1_42 is 0.088 away, 3.7_42 0.081, 3.4_60 0.3
        self.assertEqual(nearest(os.path.join(self.grid, "3.4_42")), (0, self.lap("3.7_42"), ""))

    def test_along_keeps_the_other_values(self):
        # the same gear, another pack: 3.4_60, though two points of other gears are nearer
        self.assertEqual(nearest(os.path.join(self.grid, "3.4_42"), "--along", "2"),
                         (0, self.lap("3.4_60"), ""))
        # the same pack, another gear
        self.assertEqual(nearest(os.path.join(self.grid, "3.4_42"), "--along", "1"),
                         (0, self.lap("3.7_42"), ""))

    def test_nothing_when_no_such_sibling_has_finished(self):
        self.assertEqual(nearest(os.path.join(self.grid, "4.0_30"), "--along", "2"), (0, "", ""))
        self.assertEqual(nearest(os.path.join(self.tmp.name, "gear", "3.4")), (0, "", ""))

    def test_along_beyond_the_values_is_an_error(self):
        code, out, err = nearest(os.path.join(self.grid, "3.4_42"), "--along", "3")
        self.assertEqual((code, out), (2, ""))
        self.assertIn("--along 3: 3.4_42 has 2 value(s)", err)

    def test_a_usage_error_is_one_line(self):
        code, out, err = nearest(os.path.join(self.grid, "3.4_42"), "--along", "two")
        self.assertEqual((code, out), (2, ""))
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        self.assertIn("--along", err)


if __name__ == "__main__":
    unittest.main()
