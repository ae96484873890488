#!/usr/bin/python3
"""telemetry_overlay.py: RMS speed difference against hand-computed values, bad CSVs refused."""
import json
import math
import os
import unittest

import numpy as np

import ttz_fixtures as fx

NODES_S = np.linspace(0.0, fx.LAP_LENGTH_M, fx.LAP_NODES)  # the fixture lap's nodes, 10 m apart
ODOMETER = 1.01                                            # the telemetry reads 1 % long


def telemetry_rows(offset_m, deltas, nodes=NODES_S):
    """(distance, speed) rows at the lap's nodes: distance read 1 % long from offset_m, speed
    the lap's V plus deltas [m/s]."""
    return [(offset_m + ODOMETER * s, fx.lap_speed(s) + d) for s, d in zip(nodes, deltas)]


def write_csv(path, rows, header="t_s,distance_m,v_wheel_mps", comments=()):
    with open(path, "w") as handle:
        handle.writelines(f"{c}\n" for c in comments)
        if header:
            handle.write(header + "\n")
        handle.writelines(f"{0.1 * k:.1f},{d!r},{v!r}\n" for k, (d, v) in enumerate(rows))
    return path


class TelemetryOverlayTest(fx.TempFolder, fx.ScriptAssertions, unittest.TestCase):
    def setUp(self):
        super().setUp()
        self.lap = fx.write_lap(self.path("lap.h5"))
        self.png = self.path("overlay.png")

    def overlay(self, csv_path, *options):
        return fx.run("telemetry_overlay.py", self.lap, csv_path, "-o", self.png, *options)

    def rms_of(self, result):
        self.assert_ok(result)
        self.assertTrue(os.path.getsize(self.png) > 1000)
        key, value = result.stdout.strip().split("=")
        self.assertEqual(key, "rms_speed_difference_mps")
        return float(value)

    def test_rms_hand_computed(self):
        # +1 m/s at even nodes (51 of 101), 0 at odd ones: RMS = sqrt(51 / 101). Samples before
        # the start line (negative distance) are wildly off and must be ignored.
        deltas = [1.0 if i % 2 == 0 else 0.0 for i in range(fx.LAP_NODES)]
        rows = [(-20.0, 99.0), (-10.0, 99.0)] + telemetry_rows(0.0, deltas)
        csv_path = write_csv(self.path("tel.csv"), rows, comments=("# a comment",))
        self.assertAlmostEqual(self.rms_of(self.overlay(csv_path)), math.sqrt(51 / 101), places=4)

    def test_json_and_comment_header(self):
        rows = telemetry_rows(0.0, [0.5, -0.5] * 50 + [0.5])
        csv_path = write_csv(self.path("tel.csv"), rows, header=None,
                             comments=("# logger dump", "# t_s,distance_m (lap),v_wheel_mps=rpm (derived)"))
        result = self.overlay(csv_path, "--json")
        self.assert_ok(result)
        answer = json.loads(result.stdout)
        self.assertAlmostEqual(answer["rms_speed_difference_mps"], 0.5, places=6)
        self.assertEqual(answer["nodes"], fx.LAP_NODES)
        self.assertAlmostEqual(answer["distance_scale"], 1 / ODOMETER, places=9)

    def test_second_of_two_laps(self):
        # lap 1: +1 m/s, nodes 0..990 m; lap 2: +2 m/s; the file starts at 50 m (no 0 in it).
        lap_length = ODOMETER * fx.LAP_LENGTH_M
        rows = (telemetry_rows(50.0, [1.0] * 100, NODES_S[:-1])
                + telemetry_rows(50.0 + lap_length, [2.0] * fx.LAP_NODES))
        csv_path = write_csv(self.path("tel.csv"), rows, header="t_s,distance_m,v_gps_mps")
        self.assertAlmostEqual(self.rms_of(self.overlay(csv_path, "--lap", "2")), 2.0, places=4)
        self.assert_refused(self.overlay(csv_path, "--lap", "3"), "tel.csv", "no lap 3")

    def refused(self, text, *words):
        with open(self.path("bad.csv"), "w") as handle:
            handle.write(text)
        self.assert_refused(self.overlay(self.path("bad.csv")), "bad.csv", *words,
                            absent=(self.png,))
        self.assert_no_temporaries(self.dir)

    def test_not_a_number(self):
        self.refused("t_s,distance_m,v_wheel_mps\n0,0,10\n0.1,1,ten\n0.2,2,10\n", "line 3", "ten")

    def test_missing_value(self):
        self.refused("t_s,distance_m,v_wheel_mps\n0,0,10\n0.1,1\n0.2,2,10\n", "line 3")

    def test_no_speed_column(self):
        self.refused("t_s,distance_m,rpm\n0,0,10\n0.1,1,10\n", "v_wheel_mps")

    def test_no_header(self):
        self.refused("0,0,10\n0.1,1,10\n", "header")

    def test_distance_decreases(self):
        self.refused("t_s,distance_m,v_wheel_mps\n0,0,10\n0.1,5,10\n0.2,4,10\n", "decreases")

    def test_named_column_absent(self):
        csv_path = write_csv(self.path("tel.csv"), telemetry_rows(0.0, [0.0] * fx.LAP_NODES))
        self.assert_refused(self.overlay(csv_path, "--speed-column", "v_x"), "tel.csv", "v_x",
                            absent=(self.png,))

    def test_missing_lap(self):
        csv_path = write_csv(self.path("tel.csv"), telemetry_rows(0.0, [0.0] * fx.LAP_NODES))
        self.lap = self.path("absent.h5")
        self.assert_refused(self.overlay(csv_path), "absent.h5", absent=(self.png,))


if __name__ == "__main__":
    fx.main()
