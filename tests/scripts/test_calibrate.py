#!/usr/bin/python3
"""calibrate.py: the secant fit against a stand-in `lap` whose lap time is a known function of the
fitted key; failed laps and exhausted evaluations refused."""
import os
import stat
import unittest

import h5py

import ttz_fixtures as fx

# A stand-in for the lap executable: lap time 1000 + 3e5 / x [s] at --set KEY=x, so 1771 s at
# x = 3e5 / 771 = 389.1; it records its arguments, writes a lap.h5 with those figures as attributes
# (docs/lap_h5.md), prints a one-line summary and exits with $FAKE_EXIT.
FAKE_LAP = """#!/usr/bin/python3
import os, sys
import h5py
args = sys.argv[1:]
x = float(next(a for a in args if "=" in a).split("=")[1])
with h5py.File(args[args.index("-o") + 1], "w") as h5:
    h5.attrs.update({"schema": "ttz.lap", "schema_version": 2, "lap_time": 1000 + 3e5 / x,
                     "energy_used": 1e5 * x})
with open(os.environ["FAKE_LOG"], "a") as log:
    log.write(" ".join(args) + "\\n")
print(f"lap at x = {x}")
sys.exit(int(os.environ.get("FAKE_EXIT", "0")))
"""


def read_lines(path):
    with open(path) as handle:
        return handle.read().splitlines()


class CalibrateTest(fx.TempFolder, fx.ScriptAssertions, unittest.TestCase):
    def setUp(self):
        super().setUp()
        self.lap = self.path("lap")
        with open(self.lap, "w") as handle:
            handle.write(FAKE_LAP)
        os.chmod(self.lap, os.stat(self.lap).st_mode | stat.S_IEXEC)
        self.log = self.path("laps.log")
        self.out = self.path("calibration.txt")

    def calibrate(self, *extra, exit_code=0):
        os.environ.update(FAKE_LOG=self.log, FAKE_EXIT=str(exit_code))  # read by FAKE_LAP
        return fx.run("calibrate.py", "road.h5", "bike.yaml", "--lap", self.lap, "-o", self.out, *extra)

    def test_the_secant_method_meets_the_target_and_writes_the_override(self):
        self.assert_ok(self.calibrate("--warm-start", "--", "--solver", "ipopt"))
        lines = read_lines(self.out)
        key, value = lines[-1].split("=")
        self.assertEqual(key, "motor.current_max_a")
        self.assertLess(abs(1000 + 3e5 / float(value) - 1771) / 1771, 0.002)
        laps = read_lines(self.log)
        self.assertEqual(len([line for line in lines if line.startswith("# ") and "exit" not in line]) - 1, len(laps))
        self.assertNotIn("--init", laps[0])
        self.assertTrue(all("--init" in lap and lap.endswith("--solver ipopt") for lap in laps[1:]), laps)

    def test_every_value_is_solved_as_written_and_keep_lap_copies_the_fitted_lap(self):
        keep = self.path("reference")
        self.assert_ok(self.calibrate("--start", "300.0001234", "400", "--keep-lap", keep))
        value = read_lines(self.out)[-1].split("=")[1]
        laps = read_lines(self.log)
        self.assertIn(f"motor.current_max_a={value}", laps[-1])
        self.assertTrue(laps[0].startswith("road.h5 bike.yaml -o ") and "=300 " in laps[0], laps[0])
        self.assertEqual(read_lines(os.path.join(keep, "lap.txt")), [f"lap at x = {float(value)}"])
        with h5py.File(os.path.join(keep, "lap.h5"), "r") as h5:
            self.assertAlmostEqual(h5.attrs["lap_time"], 1000 + 3e5 / float(value), places=9)
        self.assert_no_temporaries(keep)

    def test_a_lap_file_of_another_kind_ends_the_calibration(self):
        with open(self.lap) as handle:
            text = handle.read().replace('"schema": "ttz.lap"', '"schema": "ttz.road"')
        with open(self.lap, "w") as handle:
            handle.write(text)
        self.assert_refused(self.calibrate(), "schema 'ttz.road'", absent=[self.out])

    def test_a_lap_that_exits_4_counts_and_laps_start_cold_by_default(self):
        self.assert_ok(self.calibrate(exit_code=4))
        self.assertTrue(os.path.exists(self.out))
        self.assertFalse(any("--init" in lap for lap in read_lines(self.log)))

    def test_parallel_start_solves_both_start_values_and_keeps_the_closest_lap(self):
        # The first start value already meets the target: both start laps run, the fit keeps the
        # first (1000 + 3e5 / 389 = 1771.2 s) and solves nothing more.
        self.assert_ok(self.calibrate("--parallel-start", "--start", "389", "300"))
        self.assertEqual(len(read_lines(self.log)), 2)
        self.assertEqual(read_lines(self.out)[-1], "motor.current_max_a=389")

    def test_a_lap_that_did_not_converge_ends_the_calibration(self):
        self.assert_refused(self.calibrate(exit_code=3), "exit 3", absent=[self.out])

    def test_running_out_of_laps_exits_3_without_output(self):
        result = self.calibrate("--max-evals", "2")
        self.assertEqual(result.returncode, 3, result.stderr)
        self.assert_refused(result, "after 2 laps", absent=[self.out])


if __name__ == "__main__":
    fx.main()
