#!/usr/bin/python3
"""lap_plots.py on tiny lap.h5 / road.h5 fixtures: every file written, bad input refused."""
import os
import sys
import unittest

import numpy as np

import ttz_fixtures as fx

PNGS_LAP = ("speed.png", "battery.png", "motor.png", "power.png", "yaw_roll.png")
PNGS_ROAD = ("map.png", "elevation.png")


class LapPlotsTest(fx.TempFolder, fx.ScriptAssertions, unittest.TestCase):
    def setUp(self):
        super().setUp()
        self.out = self.path("out")

    def assert_files(self, names):
        """Each file written and non-empty (PNGs: a plot, over 1 kB)."""
        for name in names:
            path = os.path.join(self.out, name)
            self.assertTrue(os.path.isfile(path), name)
            self.assertGreater(os.path.getsize(path), 1000 if name.endswith(".png") else 0, name)

    def test_all_plots_and_summary(self):
        lap = fx.write_lap(self.path("lap.h5"))
        road = fx.write_road(self.path("road.h5"))
        self.assert_ok(fx.run("lap_plots.py", lap, "--road", road, "-o", self.out))
        self.assert_files(PNGS_LAP + PNGS_ROAD)
        self.assertFalse(os.path.exists(os.path.join(self.out, "resim.png")))  # no resim/* in the lap
        self.assertFalse(os.path.exists(os.path.join(self.out, "sensitivity.png")))  # nor sensitivity/*
        with open(os.path.join(self.out, "summary.md")) as handle:
            summary = handle.read()
        self.assertIn("1:40.0", summary)       # lap_time 100 s
        self.assertIn("3.00 MJ", summary)      # energy_used 3e6 J
        self.assertIn("25.0 %", summary)       # energy_fraction 0.25
        self.assertIn("30.0 m/s", summary)     # top_speed
        self.assert_no_temporaries(self.out)

    def test_banking_is_plotted_when_the_road_has_it(self):
        lap = fx.write_lap(self.path("lap.h5"))
        banked = fx.write_road(self.path("banked.h5"), banking=-0.2)
        self.assert_ok(fx.run("lap_plots.py", lap, "--road", banked, "-o", self.out))
        self.assert_files(PNGS_ROAD)
        sys.path.insert(0, fx.SCRIPTS)
        import lap_plots
        for road, labels in ((banked, ["elevation z [m]", "slope [%]", "banking [deg]"]),
                             (fx.write_road(self.path("level.h5")), ["elevation z [m]", "slope [%]"])):
            channels = lap_plots.read_road(road, fx.LAP_LENGTH_M)
            panels, _ = lap_plots.road_panels(channels)
            self.assertEqual([label for label, _, _ in panels], labels)
        self.assertAlmostEqual(float(lap_plots.road_panels(lap_plots.read_road(banked, fx.LAP_LENGTH_M))[0][2][1][0]),
                               -11.459, places=3)

    def test_the_path_moves_across_the_banked_surface(self):
        """On a level road n moves the bike along the horizontal right normal; banked 60 degrees,
        half as far in the plane (the rest is height)."""
        sys.path.insert(0, fx.SCRIPTS)
        import lap_plots
        s = np.array([0.0, 10.0])
        lap = {"s": s, "state/n": np.array([2.0, 2.0])}
        road = {"s": s, "x": s, "y": np.zeros(2), "theta": np.zeros(2), "sigma": np.zeros(2), "banking": np.zeros(2)}
        x, y = lap_plots.bike_path(lap, road)  # heading east: right is south
        np.testing.assert_allclose(y, [-2.0, -2.0], atol=1e-12)
        road["banking"] = np.full(2, np.pi / 3)
        x, y = lap_plots.bike_path(lap, road)
        np.testing.assert_allclose(x, s, atol=1e-12)
        np.testing.assert_allclose(y, [-1.0, -1.0], atol=1e-12)

    def test_omega_z_as_state_and_no_road(self):
        for version in (2, 3):  # version 3 adds control_interval/, which the plots do not read
            lap = fx.write_lap(self.path("lap%d.h5" % version), omega_group="state", version=version)
            self.assert_ok(fx.run("lap_plots.py", lap, "-o", self.out))
            self.assert_files(PNGS_LAP + ("summary.md",))
            for name in PNGS_ROAD:
                self.assertFalse(os.path.exists(os.path.join(self.out, name)))

    def test_the_re_simulations_differences_when_the_lap_has_them(self):
        lap = fx.write_lap(self.path("lap.h5"), version=3, resim=True)
        self.assert_ok(fx.run("lap_plots.py", lap, "-o", self.out))
        self.assert_files(PNGS_LAP + ("resim.png", "summary.md"))

    def refused(self, lap, *words, road=None):
        args = [lap, "-o", self.out] + (["--road", road] if road else [])
        line = self.assert_refused(fx.run("lap_plots.py", *args), *words)
        self.assertFalse(os.path.exists(self.out) and os.listdir(self.out), "output written")
        return line

    def test_what_buys_lap_time_when_the_lap_has_sensitivities(self):
        lap = fx.add_sensitivities(fx.write_lap(self.path("lap.h5"), version=4), [0.5, -1.2, float("nan"), 0.0])
        self.assert_ok(fx.run("lap_plots.py", lap, "-o", self.out))
        self.assert_files(PNGS_LAP + ("sensitivity.png", "summary.md"))

    def test_no_sensitivity_plot_without_a_finite_figure(self):
        lap = fx.add_sensitivities(fx.write_lap(self.path("lap.h5"), version=4), [float("nan")])
        self.assert_ok(fx.run("lap_plots.py", lap, "-o", self.out))
        self.assertFalse(os.path.exists(os.path.join(self.out, "sensitivity.png")))

    def test_missing_file(self):
        self.refused(self.path("absent.h5"), "absent.h5", "no such file")

    def test_missing_dataset(self):
        lap = fx.write_lap(self.path("lap.h5"), drop=("wheel/power",))
        self.refused(lap, "lap.h5", "wheel/power")

    def test_missing_omega_z(self):
        lap = fx.write_lap(self.path("lap.h5"), drop=("control/Omega_z",))
        self.refused(lap, "control/Omega_z", "state/Omega_z")

    def test_wrong_schema(self):
        lap = fx.write_lap(self.path("lap.h5"), schema="ttz.road")
        self.refused(lap, "lap.h5", "ttz.road", "ttz.lap")

    def test_wrong_version(self):
        self.refused(fx.write_lap(self.path("lap.h5"), version=7), "version 7")

    def test_road_of_another_lap(self):
        lap = fx.write_lap(self.path("lap.h5"))
        road = fx.write_road(self.path("road.h5"), length=2000.0)
        self.refused(lap, "road.h5", "another road", road=road)

    def test_not_hdf5(self):
        with open(self.path("lap.h5"), "w") as handle:
            handle.write("not hdf5\n")
        self.refused(self.path("lap.h5"), "lap.h5", "HDF5")


if __name__ == "__main__":
    fx.main()
