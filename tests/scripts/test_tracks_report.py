#!/usr/bin/python3
"""tracks_report.py on tiny lap.h5 / road.h5 fixtures: a row per circuit, bad input refused."""
import os
import unittest

import h5py

import ttz_fixtures as fx


class TracksReportTest(fx.TempFolder, fx.ScriptAssertions, unittest.TestCase):
    def circuit(self, name, resim=None, road_length=fx.LAP_LENGTH_M, start=None, banking=None):
        """folder `name` with the fixture lap (resim: (passed, lap time, state, worst) attributes;
        start: its `start` attribute) and a road of `road_length` beside it (banked `banking` rad,
        version 1 without); the lap's path."""
        os.makedirs(self.path(name))
        lap = fx.write_lap(self.path(name, "lap.h5"), version=4)
        with h5py.File(lap, "a") as h5:
            if resim is not None:
                passed, time, state, worst = resim
                h5.attrs.update({"resim_passed": passed, "resim_lap_time_relative": time,
                                 "resim_max_state_difference": state, "resim_worst_state": worst})
            if start is not None:
                h5.attrs["start"] = start
        fx.write_road(self.path(name, "road.h5"), road_length, banking)
        return lap

    def test_a_row_per_circuit(self):
        laps = [fx.add_sensitivities(self.circuit("hill", (0, 3.2e-5, 0.48, "z_dot"), start="flying", banking=-0.2),
                                     [0.5, -1.25, float("nan"), -3.0], ["design", "design", "design", "condition"]),
                self.circuit("flat", (1, 1e-6, 5e-4, "V"), start="standing"), self.circuit("old")]
        out = self.path("report", "report.md")
        self.assert_ok(fx.run("tracks_report.py", *laps, "-o", out))
        with open(out) as handle:
            rows = [line for line in handle.read().splitlines() if line.startswith("| ")]
        # the fixture: 1 km rising 1 % on a 500 m radius, 100 s, 3 MJ of a 12 MJ pack, top 30 m/s,
        # 20 m/s at the first node
        # (the hill banked 0.2 rad, 11.5 deg; the others version 1, level across)
        road, lap = "| 1.00 | 10 | 500.0 |", "| 1:40.0 | 36.0 | 108.0 | 3.00 (25.0 %) |"
        # (the hill's sensitivities: of the design values section.key1 buys most, 1.25 s, a condition
        # more; the others have none)
        self.assertEqual(rows[1:], [f"| hill {road} 11.5 {lap} flying at 72.0 km/h | yes | lap time 0.0032 %, z_dot 48.0 % "
                                    "(failed) | `section.key1` -1.25 s |",
                                    f"| flat {road} 0.0 {lap} standing at 72.0 km/h | yes | lap time 0.0001 %, passed | - |",
                                    f"| old {road} 0.0 {lap} standing at 72.0 km/h | yes | not run | - |"])
        self.assert_no_temporaries(os.path.dirname(out))

    def test_bad_input_is_one_line_and_no_report(self):
        out = self.path("report.md")
        good = self.circuit("good")
        other = self.circuit("other", road_length=2 * fx.LAP_LENGTH_M)
        self.assert_refused(fx.run("tracks_report.py", good, other, "-o", out), "other", "a lap of another road",
                            absent=[out])
        os.remove(self.path("good", "road.h5"))
        self.assert_refused(fx.run("tracks_report.py", good, "-o", out), "road.h5", "no such file", absent=[out])
        not_lap = fx.write_road(self.path("not_a_lap.h5"))
        self.assert_refused(fx.run("tracks_report.py", not_lap, "-o", out), "not_a_lap.h5", absent=[out])

    def test_figures_that_are_not_numbers_are_refused(self):
        out = self.path("report.md")
        for case, (name, value), words in (
                ("zero_time", ("lap_time", 0.0), ["'lap_time' is 0.0, expected a finite positive number"]),
                ("nan_time", ("lap_time", float("nan")), ["'lap_time' is nan"]),
                ("text_speed", ("top_speed", "fast"), ["attribute 'top_speed' is not a number"]),
                ("verdict_alone", ("resim_passed", 0), ["missing attribute 'resim_lap_time_relative'"])):
            lap = self.circuit(case)
            with h5py.File(lap, "a") as h5:
                h5.attrs[name] = value
            self.assert_refused(fx.run("tracks_report.py", lap, "-o", out), case, *words, absent=[out])
        empty = self.circuit("empty_speed")
        with h5py.File(empty, "a") as h5:
            del h5["state/V"]
            h5.create_dataset("state/V", data=[])
        self.assert_refused(fx.run("tracks_report.py", empty, "-o", out), "'state/V' is nan", absent=[out])
        bent = self.circuit("nan_kappa")
        with h5py.File(self.path("nan_kappa", "road.h5"), "a") as h5:
            h5["kappa"][3] = float("nan")
        self.assert_refused(fx.run("tracks_report.py", bent, "-o", out), "road.h5", "'kappa' has non-finite values",
                            absent=[out])


if __name__ == "__main__":
    fx.main()
