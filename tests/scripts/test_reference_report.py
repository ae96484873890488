#!/usr/bin/python3
"""reference_report.py on a tiny synthetic lap.h5 whose figures are known: the paper's numbers
beside ours with the right differences, the calibration marking, bad input refused."""
import os
import unittest

import h5py
import numpy as np

import ttz_fixtures as fx

EFFICIENCY = 0.65            # wheel/power / battery/power where the bike drives
TYRE_EFFICIENCY = 0.55       # tyre/force_x x state/V / battery/power there
DRIVE_END_M = 800.0          # drives (battery/power > 0) before this s, regenerates after
CURRENT_PER_SPEED = 5.0      # battery/current = 5 V [A per m/s] where it drives
CURRENT_PER_VOLT = 0.5       # motor/voltage = 10 V [V]: 0.5 A per V
LAP_TIME = 1771.0 * 1.02     # +2.0 % of the paper's 1771 s
ENERGY_J = 36.72e6 * 1.1     # +10.0 % of the paper's 36.72 MJ
FRACTION = 0.792             # 79.2 % of a 51 MJ pack: +7.2 pp
AVERAGE_SPEED = 122.0 / 3.6 * 0.95   # -5.0 %


def bike_yaml(current_max=186.5):
    """A bike in BikeToYaml's two-level layout with the keys the scripts read."""
    return ("motor:\n  count: 2\n  current_max_a: {!r}\nbattery:\n  cells_series: 24\n"
            "  cells_parallel: 4\n  cell_energy_j: 531250.0\ndrive:\n  gear_ratio: 2.8\n"
            ).format(current_max)


def write_reference_lap(path, converged=1, resim_passed=1, drop=(), current_max=186.5):
    """fx.write_lap's lap (V = 20 + 0.01 s on 0 ... 1000 m) with channels of known figures: it
    drives before DRIVE_END_M (battery power 40 kW + 1 kW per m/s, current 5 V) and
    regenerates after (-5 kW, -20 A)."""
    fx.write_lap(path, omega_group="state", version=2, drop=drop)
    with h5py.File(path, "a") as h5:
        s = h5["s"][()]
        v = fx.lap_speed(s)
        drive = s < DRIVE_END_M
        battery = np.where(drive, 40e3 + 1e3 * v, -5e3)
        channels = {"battery/power": battery,
                    "wheel/power": np.where(drive, EFFICIENCY * battery, -2e3),
                    "tyre/force_x": np.where(drive, TYRE_EFFICIENCY * battery / v, -300.0),
                    "battery/current": np.where(drive, CURRENT_PER_SPEED * v, -20.0),
                    "motor/voltage": 10.0 * v,
                    "battery/voltage": 400.0 - 0.05 * s}
        for name, values in channels.items():
            if name in h5:
                del h5[name]
            if name not in drop:
                h5.create_dataset(name, data=values).attrs["units"] = "-"
        h5.attrs.update({"lap_time": LAP_TIME, "energy_used": ENERGY_J,
                         "energy_fraction": FRACTION, "average_speed": AVERAGE_SPEED,
                         "converged": np.int8(converged), "resim_passed": np.int8(resim_passed),
                         "resim_message": "" if resim_passed else "z_dot differs",
                         "message": "" if converged else "residual 3e-2",
                         "max_violation_adherence": 0.2, "max_violation_charge": -0.3,
                         "bike_yaml": bike_yaml(current_max)})
    return path


class ReferenceReportTest(fx.TempFolder, fx.ScriptAssertions, unittest.TestCase):
    def setUp(self):
        super().setUp()
        self.report = self.path("out", "report.md")

    def run_report(self, lap, *args):
        result = fx.run("reference_report.py", lap, "-o", self.report, *args)
        self.assert_ok(result)
        with open(self.report) as handle:
            text = handle.read()
        self.assert_no_temporaries(os.path.dirname(self.report))
        return text, result.stdout

    def row(self, text, start):
        """The table row whose first cell starts with `start`."""
        return next(line for line in text.splitlines() if line.startswith("| " + start))

    def write_calibration(self, lines):
        path = self.path("calibration.txt")
        with open(path, "w") as handle:
            handle.write("\n".join(lines) + "\n")
        return path

    def test_known_figures(self):
        text, stdout = self.run_report(write_reference_lap(self.path("lap.h5")))
        self.assertIn("| figure | paper | ours | difference % |", stdout)
        self.assertIn("- converged: 1", text)
        self.assertIn("- resim_passed: 1 (passed)", text)
        self.assertIn("adherence 0.2", text)           # > 1e-4: listed
        self.assertNotIn("charge", text.split("| figure")[0])
        self.assertNotIn("WARNING", text)
        lap = self.row(text, "lap time |")
        self.assertIn("| 30:06.4 (1806.4 s) | +2.0 % |", lap)
        self.assertIn("validation (no --calibration given)", lap)
        self.assertIn("| +1.1 % |", self.row(text, "lap time vs the real 2015"))  # 1787 s
        self.assertIn("| 40.39 MJ | +10.0 % |", self.row(text, "energy used"))
        self.assertIn("| 79.2 % of 51.00 MJ | +7.2 pp (+10.0 %) |", self.row(text, "battery usage"))
        self.assertIn("| 115.9 km/h | -5.0 % |", self.row(text, "average speed"))
        efficiency = self.row(text, "overall power-train efficiency")
        self.assertIn("| 65.0 % | -5.0 pp (-7.1 %) |", efficiency)
        self.assertIn("tyre/force_x x state/V instead (after rolling resistance, slip and any "
                      "braking while driving): 55.0 %", efficiency)
        # only the driving nodes (battery/current > 0) are fitted: exactly linear
        speed = self.row(text, "battery current vs speed")
        self.assertIn("| r = 1.000, slope 5.00 A per m/s | - |", speed)
        self.assertIn("over the 80 nodes", speed)
        self.assertIn("| r = 1.000, slope 0.500 A per V | - |",
                      self.row(text, "battery current vs motor voltage"))
        self.assertIn("| graph only | 400.0 V | - | Fig. 8 |",
                      self.row(text, "battery voltage at the start"))
        self.assertIn("| graph only | 350.0 V |", self.row(text, "battery voltage at the end"))
        self.assertIn("| 120.0 A | - | Fig. 9 |", self.row(text, "motor current max"))
        self.assertIn("| 300.0 V |", self.row(text, "motor voltage max"))

    def test_calibrated_lap_marked_fitted(self):
        cal = self.write_calibration(["# motor.current_max_a fitted by scripts/calibrate.py",
                                      "# 186 1775.0 36.0 0", "motor.current_max_a=186.5"])
        text, _ = self.run_report(write_reference_lap(self.path("lap.h5")), "--calibration", cal)
        lap = self.row(text, "lap time |")
        self.assertIn("fitted (calibration: motor.current_max_a=186.5)", lap)
        self.assertIn("not a validation", lap)
        self.assertNotIn("fitted", self.row(text, "lap time vs the real 2015"))

    def test_lap_at_another_value_is_not_fitted(self):
        cal = self.write_calibration(["# fitted", "motor.current_max_a=186.5"])
        lap = write_reference_lap(self.path("lap.h5"), current_max=180.0)
        text, _ = self.run_report(lap, "--calibration", cal)
        row = self.row(text, "lap time |")
        self.assertNotIn("fitted (calibration", row)
        self.assertIn("NOT the calibrated one", row)
        self.assertIn("motor.current_max_a=180", row)

    def test_calibration_without_value_fits_nothing(self):
        cal = self.write_calibration(["# a piece of the course: no calibration"])
        text, _ = self.run_report(write_reference_lap(self.path("lap.h5")), "--calibration", cal)
        self.assertNotIn("fitted (calibration", text)
        self.assertIn("holds no key=value line", self.row(text, "lap time |"))

    def test_not_converged_flagged_at_the_top(self):
        lap = write_reference_lap(self.path("lap.h5"), converged=0, resim_passed=0)
        text, _ = self.run_report(lap)
        top = text.splitlines()[2]
        self.assertIn("WARNING: this lap did NOT converge", top)
        self.assertIn("residual 3e-2", top)
        self.assertIn("- resim_passed: 0 (failed: z_dot differs)", text)

    def test_the_largest_sensitivities_by_size(self):
        text, _ = self.run_report(write_reference_lap(self.path("plain.h5")))
        self.assertNotIn("What buys lap time", text)  # a lap without sensitivity/*
        sizes = [0.001 * (i if i % 2 else -i) for i in range(12)]  # key11 the largest, key0 and key1 the smallest
        text, _ = self.run_report(fx.add_sensitivities(write_reference_lap(self.path("lap.h5")), sizes))
        section = text.split("## What buys lap time")[1]
        self.assertIn("the 10 largest of the 12 design values", section)  # no sensitivity/kind: all design
        self.assertNotIn("Not changes to the bike", section)
        self.assertLess(section.index("`section.key11` | 12 | +0.011 s"), section.index("`section.key10` | 11 | -0.010 s"))
        self.assertNotIn("`section.key1`", section)
        self.assertNotIn("`section.key0`", section)

    def test_a_non_finite_sensitivity_is_named_not_ranked(self):
        lap = fx.add_sensitivities(write_reference_lap(self.path("lap.h5")), [0.1, np.nan])
        text, _ = self.run_report(lap)
        section = text.split("## What buys lap time")[1]
        self.assertIn("the 1 largest of the 2 design values", section)
        self.assertIn("`section.key0` | 1 | +0.100 s", section)
        self.assertIn("Without a finite figure (left out): `section.key1`", section)

    def test_only_design_values_rank_as_what_buys_lap_time(self):
        kinds = ["design", "condition", "design", "reference", "rider"]
        lap = fx.add_sensitivities(write_reference_lap(self.path("lap.h5")), [0.1, -9.0, -0.2, 0.5, np.nan], kinds)
        section = self.run_report(lap)[0].split("## What buys lap time")[1]
        design, others = section.split("Not changes to the bike")
        self.assertIn("the 2 largest of the 2 design values", design)
        self.assertLess(design.index("`section.key2` | 3 | -0.200 s"), design.index("`section.key0` | 1 | +0.100 s"))
        self.assertNotIn("`section.key1`", design)
        self.assertIn("| `section.key1` | condition | 2 | -9.000 s |", others)
        self.assertIn("| `section.key3` | reference | 4 | +0.500 s |", others)
        self.assertIn("Without a finite figure (left out): `section.key4`", others)

    def test_a_kind_for_each_key(self):
        lap = fx.add_sensitivities(write_reference_lap(self.path("lap.h5")), [0.1, 0.2], ["design"])
        self.refused(lap, "lap.h5", "dataset 'sensitivity/kind' has 1 values, expected 2")

    def test_an_unknown_kind_is_refused(self):
        lap = fx.add_sensitivities(write_reference_lap(self.path("lap.h5")), [0.1], ["weather"])
        self.refused(lap, "lap.h5", "unknown kind 'weather', expected one of design, rider, condition, reference")

    def refused(self, lap, *words, extra=()):
        result = fx.run("reference_report.py", lap, "-o", self.report, *extra)
        self.assert_refused(result, "error:", *words, absent=(self.report,))

    def test_missing_file(self):
        self.refused(self.path("absent.h5"), "absent.h5", "no such file")

    def test_missing_dataset(self):
        lap = write_reference_lap(self.path("lap.h5"), drop=("tyre/force_x",))
        self.refused(lap, "lap.h5", "missing dataset 'tyre/force_x'")

    def test_missing_attribute(self):
        lap = write_reference_lap(self.path("lap.h5"))
        with h5py.File(lap, "a") as h5:
            del h5.attrs["energy_used"]
        self.refused(lap, "missing attribute 'energy_used'")

    def test_not_a_lap(self):
        self.refused(fx.write_lap(self.path("road.h5"), schema="ttz.road"), "ttz.road", "ttz.lap")
        with open(self.path("text.h5"), "w") as handle:
            handle.write("not hdf5\n")
        self.refused(self.path("text.h5"), "text.h5", "HDF5")

    def test_non_finite_channel(self):
        lap = write_reference_lap(self.path("lap.h5"))
        with h5py.File(lap, "a") as h5:
            h5["battery/power"][3] = np.nan
        self.refused(lap, "battery/power", "non-finite")

    def test_missing_calibration_file(self):
        lap = write_reference_lap(self.path("lap.h5"))
        self.refused(lap, "nocal.txt", "no such file",
                     extra=("--calibration", self.path("nocal.txt")))

    def test_malformed_calibration(self):
        cal = self.write_calibration(["# x", "motor.current_max_a 186"])
        self.refused(write_reference_lap(self.path("lap.h5")), "calibration.txt", "line 2",
                     extra=("--calibration", cal))


if __name__ == "__main__":
    fx.main()
