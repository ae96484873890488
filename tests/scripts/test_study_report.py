#!/usr/bin/python3
"""study_report.py on tiny synthetic design studies (lap.h5 files with a bike_yaml attribute):
known optima found, the paper compared, non-converged points reported, bad input refused."""
import math
import os
import re
import shutil
import sys
import unittest

import h5py
import numpy as np

import ttz_fixtures as fx

CELL_J = 531250.0          # data/bx15.yaml: 4P24S of these cells is the 51 MJ pack
GEARS = [round(2.8 + 0.1 * k, 1) for k in range(11)]        # 2.8 ... 3.8
NOT_CONVERGED_GEAR = 3.5   # written with converged = 0 and the least lap time of all
NODES = 201


def gear_lap_time(gear):
    """Known optimum at gear 3.3 (1700 s); 1750 s at the reference 2.8."""
    return 1700.0 + 200.0 * (gear - 3.3) ** 2


def bike_yaml(gear=2.8, motors=2, parallel=4, series=24, cell_j=CELL_J, base_mass=168.0):
    """A bike in BikeToYaml's two-level layout, with the keys the studies read."""
    return (f"# bike.yaml (ttz lap): test fixture\nchassis:\n  base_mass_kg: {base_mass!r}\n"
            f"motor:\n  count: {motors}\n  mass_kg: 11\nbattery:\n  cells_series: {series}\n"
            f"  cells_parallel: {parallel}\n  cell_energy_j: {cell_j!r}\n"
            f"  energy_density_j_per_kg: 510000\ndrive:\n  gear_ratio: {gear!r}\n"
            "  efficiency: 0.95\n")


def write_point(path, lap_time, energy_used, top_speed=60.0, converged=1, message="",
                accel=5.0, efficiency=0.7, schema="ttz.lap", without=(), timed=None, mesh=None, solver=None,
                **bike):
    """A lap.h5 of one design point: t uniform to lap_time, V = 5 + accel t (capped at 70 m/s),
    battery power 50 kW then -5 kW, wheel power efficiency x 50 kW then -8 kW (so the positive
    parts' ratio is `efficiency`); the motor current at its limit over the first half of the
    nodes' time, the motor voltage (rising 40 -> 80 V) at its 80 V limit from t = 0.9 lap_time
    on, the pack's voltage limit over the first tenth of the nodes. Attributes in `without` are left out; `timed` = (iterations,
    solve_seconds) writes those attributes, `mesh` = (ds, dt_max) mesh_ds and mesh_dt_max, `solver`
    the solver attribute."""
    pack_j = bike.get("series", 24) * bike.get("parallel", 4) * bike.get("cell_j", CELL_J)
    t = np.linspace(0.0, lap_time, NODES)
    half = np.arange(NODES) < NODES // 2
    channels = {"s": np.linspace(0.0, 60e3, NODES), "t": t,
                "state/V": np.minimum(5.0 + accel * t, 70.0),
                "battery/power": np.where(half, 50e3, -5e3),
                "wheel/power": np.where(half, efficiency * 50e3, -8e3),
                "motor/voltage": np.minimum(40.0 + 40.0 * t / (0.9 * lap_time), 80.0),
                "constraint/motor_current": np.where(half, 0.0, -0.5),
                "constraint/motor_voltage_pack": np.where(np.arange(NODES) < NODES // 10, 0.0, -0.2)}
    channels["constraint/motor_voltage_max"] = channels["motor/voltage"] / 80.0 - 1.0
    with h5py.File(path, "w") as h5:
        for name, values in channels.items():
            h5.create_dataset(name, data=values)
        attrs = {"schema": schema, "schema_version": 2, "lap_time": lap_time,
                 "top_speed": top_speed, "energy_used": energy_used,
                 "energy_fraction": energy_used / pack_j, "converged": np.int8(converged),
                 "message": message, "bike_yaml": bike_yaml(**bike), "road_sha256": "abc",
                 "road_length": 60e3}
        if timed:
            attrs.update(iterations=np.int32(timed[0]), solve_seconds=timed[1])
        if mesh:
            attrs.update(mesh_ds=mesh[0], mesh_dt_max=mesh[1])
        if solver:
            attrs.update(solver=solver)
        h5.attrs.update({k: v for k, v in attrs.items() if k not in without})
    return path


class StudyReportTest(fx.TempFolder, fx.ScriptAssertions, unittest.TestCase):
    def setUp(self):
        super().setUp()
        self.out = self.path("out")

    def gear_study(self):
        """A folder of 11 gear points (2.8 ... 3.8); gear 3.5 did not converge."""
        folder = self.path("gear")
        os.makedirs(folder)
        for gear in GEARS:
            bad = gear == NOT_CONVERGED_GEAR
            write_point(os.path.join(folder, f"g{gear}.h5"),
                        1600.0 if bad else gear_lap_time(gear),
                        41e6 - 5e6 * (gear - 3.3) ** 2, top_speed=70.0 - 10 * (gear - 3.1) ** 2,
                        accel=2.0 * gear, efficiency=0.6 + 0.05 * (gear - 2.8),
                        converged=0 if bad else 1, message="residual 3e-2" if bad else "",
                        gear=gear)
        return folder

    def battery_study(self):
        """4P24S packs of 25 ... 51 MJ; least lap time with 37 MJ."""
        paths = []
        for pack_mj in (25.0, 31.0, 37.0, 43.0, 51.0):
            paths.append(write_point(self.path(f"b{pack_mj:g}.h5"),
                                     1780.0 + 0.5 * (pack_mj - 37.0) ** 2,
                                     min(pack_mj, 37.0) * 1e6, cell_j=pack_mj * 1e6 / 96))
        return paths

    def grid_study(self, skip=()):
        """3 x 3 grid of gear 3.2/3.4/3.6 x pack 37/42/47 MJ; minimum 1654 s at (3.4, 42)."""
        paths = []
        for gear in (3.2, 3.4, 3.6):
            for pack_mj in (37.0, 42.0, 47.0):
                if (gear, pack_mj) in skip:
                    continue
                lap = 1654.0 + 300.0 * (gear - 3.4) ** 2 + 0.5 * (pack_mj - 42.0) ** 2
                paths.append(write_point(self.path(f"grid_{gear}_{pack_mj:g}.h5"), lap, 36e6,
                                         gear=gear, cell_j=pack_mj * 1e6 / 96))
        return paths

    def one_gear_grid(self):
        """The grid's three points at gear 3.2: a grid that does not vary the gear."""
        return self.grid_study(skip={(g, e) for g in (3.4, 3.6) for e in (37.0, 42.0, 47.0)})

    def motor_study(self):
        """The paper's three configurations, given out of order."""
        return [write_point(self.path("m3_5p.h5"), 1571.0, 0.85 * 5 * 24 * CELL_J, motors=3,
                            parallel=5),
                write_point(self.path("m2_4p.h5"), 1771.0, 0.72 * 96 * CELL_J),
                write_point(self.path("m3_4p.h5"), 1566.0, 96 * CELL_J, motors=3)]

    def read(self, name):
        with open(os.path.join(self.out, name)) as handle:
            return handle.read()

    def test_all_studies(self):
        result = fx.run("study_report.py", "--gear", self.gear_study(),
                        "--battery", *self.battery_study(), "--grid", *self.grid_study(),
                        "--motors", *self.motor_study(), "-o", self.out)
        self.assert_ok(result)
        for name in ("fig12_gear.png", "gear_gain.png", "fig14_battery.png", "fig15_grid.png"):
            self.assertGreater(os.path.getsize(os.path.join(self.out, name)), 1000, name)
        self.assert_no_temporaries(self.out)
        report = self.read("report.md")
        # where 3.3 gains on 2.8: the fixture's time runs uniformly along its 60 km, 1700 s
        # against 1750 s, so every km gains 50 / 60 s, at 123.4 -> 127.1 km/h
        self.assertIn("Where gear 3.3 gains its 50.0 s on gear 2.8 (gear_gain.png", report)
        self.assertEqual(report.count(": -0.83 s, 123.4 -> 127.1 km/h\n"), 3, report)
        # gear: optimum 3.3 (the unconverged 3.5 has a smaller lap time but must not win);
        # paper 3.4: -0.10 absolute, (3.3 - 3.4) / 3.4 = -2.9 %
        self.assertIn("| optimum gear ratio (least lap time) | 3.4 | 3.3 | -0.10 (-2.9 %) |",
                      report)
        # gain 1750 - 1700 = 50 s against the paper's 105 s
        self.assertIn("| 105 s (1:45, ~6 %) | 50.0 s (2.9 %) | -52.4 % |", report)
        self.assertIn("| gear of the highest top speed on course | 3.1 | 3.1 (252.0 km/h) |",
                      report)
        self.assertIn("| gear of the quickest 0-120 km/h | 4.3 (the shortest studied) | 3.8",
                      report)
        self.assertIn("| increases throughout 2.5-4.3 | increases throughout |", report)
        # gear 2.8: 0-120 km/h (33.33 - 5) / 5.6 = 5.06 s, efficiency 60 %
        row_28 = next(line for line in report.splitlines() if "g2.8.h5" in line and "|" in line)
        self.assertIn("| 5.06 |", row_28)
        self.assertIn("| 60.0 |", row_28)
        # current at its limit on nodes 0..99 of 201: (99 + 0.5) / 200 of the time = 50 %;
        # voltage: the pack's limit on nodes 0..19, 19.5 / 200, and the motor's from t = 0.9
        # lap_time (node 180) on, 20.5 / 200: 20 %; largest 80 V
        self.assertIn("| 60.0 | 50 | 20 | 80.0 | yes |", row_28)
        self.assertRegex(report, r"NOT CONVERGED: `[^`]*g3\.5\.h5`: residual 3e-2")
        row_35 = next(line for line in report.splitlines() if "g3.5.h5" in line and "|" in line)
        self.assertIn("**NO**", row_35)
        # the columns read for the gear study only are left out of the other studies' tables
        self.assertIn("| gear | motors | pack | pack MJ | lap time | top speed km/h | energy MJ | "
                      "usage % | converged | file |", report)
        # battery: least lap with the 37 MJ pack, as in the paper
        self.assertIn("| 37.00 MJ | +0.00 MJ (+0.0 %) |", report)
        self.assertIn("| 100.0 % of 25.00 MJ | +0.0 pp (+0.0 %) |", report)
        # grid: 1654 s at gear 3.4, 42 MJ
        self.assertIn("| least lap time | 27:34 (1654 s) | 27:34.0 (1654.0 s) | +0.0 % |", report)
        self.assertIn("| its gear ratio | 3.4 | 3.4 | +0.00 (+0.0 %) |", report)
        # reference lap from the 2-motor 4P24S point at gear 2.8 (the gear study's 2.8 point)
        self.assertIn("| lap time | 29:31 (1771 s) | 29:10.0 (1750.0 s) | -1.2 % |", report)
        # Table 1 in the paper's order, whatever the order given
        table = [line for line in self.read("table1.md").splitlines() if re.match(r"\| \d", line)]
        self.assertEqual([line.split("|")[1:6] for line in table],
                         [[" 2 ", " 4P24S ", " 51.0 ", " 29:31 ", " 72 "],
                          [" 3 ", " 4P24S ", " 51.0 ", " 26:06 ", " 100 "],
                          [" 3 ", " 5P24S ", " 63.8 ", " 26:11 ", " 85 "]])
        self.assertIn("| 26:06 (1566 s) | 26:06 (1566.0 s) | +0.0 % |", report)
        lines = result.stdout.splitlines()
        self.assertTrue(lines[0].startswith("gear: optimum 3.3 (lap 28:20.0), gain over 2.8 "
                                            "50.0 s; 1 of 11 points NOT converged"), lines[0])
        self.assertTrue(lines[1].startswith("battery: minimum lap 29:40.0 with a 37.00 MJ"),
                        lines[1])
        self.assertTrue(lines[2].startswith("grid: minimum lap 27:34.0 at gear 3.4, 42.00 MJ"),
                        lines[2])
        self.assertTrue(lines[3].startswith("motors: 2 motors 4P24S 29:31 72 %"), lines[3])

    def test_solve_cost_counts_a_copied_lap_once(self):
        gear = [write_point(self.path(f"g{g}.h5"), gear_lap_time(g), 36e6, gear=g,
                            timed=(100 * (k + 1), 1800.0 * (k + 1)))
                for k, g in enumerate((2.8, 3.1, 3.4))]
        battery = [shutil.copy(gear[0], self.path("b51.h5")),
                   write_point(self.path("b37.h5"), 1790.0, 36e6, cell_j=37e6 / 96,
                               timed=(50, 720.0)),
                   write_point(self.path("b30.h5"), 1800.0, 30e6, cell_j=30e6 / 96)]
        result = fx.run("study_report.py", "--gear", *gear, "--battery", *battery, "-o", self.out)
        self.assert_ok(result)
        report = self.read("report.md")
        # gear: 100 + 200 + 300 iterations, 1800 + 3600 + 5400 s = 3 h; battery: the copy of
        # g2.8 counted already, b30 untimed, so b37 alone: 50 iterations, 0.2 h
        self.assertIn("| gear | 3 | 3 | 0 | 600 | 3.00 |", report)
        self.assertIn("| battery | 3 | 1 | 0 | 50 | 0.20 |", report)
        self.assertIn("| all | 6 | 4 | 0 | 650 | 3.20 |", report)
        self.assertIn("Points without `iterations`/`solve_seconds`, not counted: 1.", report)
        self.assertEqual(result.stdout.splitlines()[2], "solve cost: 4 laps, 650 iterations, 3.20 h")

    def test_solve_cost_counts_the_attempts_set_aside_with_their_lap(self):
        # pipeline layout: gear 3.4 solved at its third attempt, battery/51 a copy of gear 2.8
        def point(folder, lap_time, **values):
            os.makedirs(self.path(folder))
            return write_point(self.path(folder, "lap.h5"), lap_time, 36e6, **values)
        gear = [point("gear/2.8", gear_lap_time(2.8), gear=2.8, timed=(100, 360.0)),
                point("gear/3.4", gear_lap_time(3.4), gear=3.4, timed=(60, 180.0))]
        for name, timed in (("first", (800, 1800.0)), ("second", (800, 1620.0))):
            write_point(self.path("gear/3.4", f"lap-{name}-attempt.h5"), 1500.0, 36e6, converged=0,
                        gear=3.4, timed=timed)
        os.makedirs(self.path("battery/51"))
        battery = [shutil.copy(gear[0], self.path("battery/51", "lap.h5")),
                   point("battery/37", 1790.0, cell_j=37e6 / 96, timed=(50, 720.0))]
        result = fx.run("study_report.py", "--gear", *gear, "--battery", *battery, "-o", self.out)
        self.assert_ok(result)
        report = self.read("report.md")
        # gear: 100 + 60 + 800 + 800 iterations, 360 + 180 + 1800 + 1620 s = 1.10 h
        self.assertIn("| gear | 2 | 2 | 2 | 1760 | 1.10 |", report)
        self.assertIn("| all | 4 | 3 | 2 | 1810 | 1.30 |", report)
        self.assertEqual(result.stdout.splitlines()[2],
                         "solve cost: 3 laps, 1810 iterations, 1.30 h (2 attempts set aside included)")

    def test_a_point_solved_otherwise_is_named(self):
        # the 37 MJ point on a finer mesh, the 40 MJ one by Ipopt (the pipelines' retry)
        paths = []
        for pack_mj, dt_max, solver in ((31.0, 0.5, "indirect"), (37.0, 0.25, "indirect"),
                                        (40.0, 0.5, "ipopt"), (43.0, 0.5, "indirect")):
            paths.append(write_point(self.path(f"b{pack_mj:g}.h5"), 1780.0 + 0.5 * (pack_mj - 37.0) ** 2,
                                     min(pack_mj, 37.0) * 1e6, cell_j=pack_mj * 1e6 / 96,
                                     mesh=(20.0, dt_max), solver=solver))
        self.assert_ok(fx.run("study_report.py", "--battery", *paths, "-o", self.out))
        report = self.read("report.md")
        self.assertIn("**2 of 4 points solved otherwise** than the others "
                      "(--solver indirect --ds 20 --dt-max 0.5)", report)
        self.assertIn("- `" + paths[1] + "`: --solver indirect --ds 20 --dt-max 0.25", report)
        self.assertIn("- `" + paths[2] + "`: --solver ipopt --ds 20 --dt-max 0.5", report)
        self.assert_ok(fx.run("study_report.py", "--battery", paths[0], paths[3], "-o", self.out))
        self.assertNotIn("solved otherwise", self.read("report.md"))
        # on a tie the first point's method is the others' (whatever the hash seed)
        for seed in ("1", "2", "3"):
            self.assert_ok(fx.run("study_report.py", "--battery", paths[2], paths[0], "-o", self.out,
                                  env={"PYTHONHASHSEED": seed}))
            self.assertIn("- `" + paths[0] + "`: --solver indirect", self.read("report.md"))

    def test_incomplete_grid_with_unconverged_point(self):
        paths = self.grid_study(skip={(3.6, 47.0)})
        write_point(self.path("grid_bad.h5"), 1500.0, 36e6, converged=0, message="stalled",
                    gear=3.6, cell_j=47e6 / 96)
        self.assert_ok(fx.run("study_report.py", "--grid", *paths, self.path("grid_bad.h5"),
                              "-o", self.out))
        self.assertGreater(os.path.getsize(os.path.join(self.out, "fig15_grid.png")), 1000)
        report = self.read("report.md")
        self.assertIn("27:34.0 (1654.0 s)", report)    # not the unconverged 1500 s
        self.assertIn("NOT CONVERGED: `", report)
        self.assertFalse(os.path.exists(os.path.join(self.out, "fig12_gear.png")))

    def refused(self, *args_and_words):
        """Runs with args (up to the '--' marker), expects exit 1, one stderr line with the
        words, and no output folder."""
        split = args_and_words.index("--")
        args, words = args_and_words[:split], args_and_words[split + 1:]
        result = fx.run("study_report.py", *args, "-o", self.out)
        self.assertEqual(result.returncode, 1, result.stderr)
        line = self.assert_refused(result, *words)
        self.assertFalse(os.path.exists(self.out), "output written")
        return line

    def test_no_gain_figure_without_the_reference_gear(self):
        folder = self.gear_study()
        os.remove(os.path.join(folder, "g2.8.h5"))
        self.assert_ok(fx.run("study_report.py", "--gear", folder, "-o", self.out))
        self.assertTrue(os.path.exists(os.path.join(self.out, "fig12_gear.png")))
        self.assertFalse(os.path.exists(os.path.join(self.out, "gear_gain.png")))
        self.assertNotIn("Where gear", self.read("report.md"))

    def test_missing_file_spoils_every_study(self):
        self.refused("--gear", self.gear_study(), "--battery", self.path("absent.h5"),
                     self.battery_study()[0], "--", "absent.h5", "no such file")

    def test_wrong_schema(self):
        bad = write_point(self.path("road.h5"), 1700.0, 3e7, schema="ttz.road")
        self.refused("--battery", bad, *self.battery_study(), "--", "road.h5", "ttz.lap")

    def test_missing_bike_yaml(self):
        bad = write_point(self.path("nobike.h5"), 1700.0, 3e7, without=("bike_yaml",), gear=3.0)
        self.refused("--gear", bad, *self.grid_study()[:1], "--", "nobike.h5", "bike_yaml")

    def test_gear_study_varying_another_key(self):
        paths = self.battery_study()[:2]   # same gear, different cells: not a gear study
        self.refused("--gear", *paths, "--", "b31.h5", "battery.cell_energy_j", "drive.gear_ratio")

    def test_study_not_varying_its_key(self):
        self.refused("--grid", *self.one_gear_grid(), "--", "--grid", "same drive.gear_ratio")

    def test_same_pack_energy_is_the_same_design(self):
        same_pack = [write_point(self.path("p4.h5"), 1700.0, 3e7),
                     write_point(self.path("p8.h5"), 1700.0, 3e7, parallel=8, series=12)]
        self.refused("--battery", *same_pack, "--", "p8.h5", "same design", "pack energy")

    def test_same_design_twice(self):
        one = write_point(self.path("a.h5"), 1700.0, 3e7, gear=3.0)
        other = write_point(self.path("b.h5"), 1700.0, 3e7, gear=3.1)
        self.refused("--gear", one, other, one, "--", "a.h5", "same design", "drive.gear_ratio = 3")

    def test_fewer_than_two_points(self):
        self.refused("--motors", self.motor_study()[0], "--", "--motors", "at least 2")

    def test_grid_on_one_line(self):
        diagonal = [write_point(self.path(f"d{k}.h5"), 1700.0, 3e7, gear=3.0 + 0.1 * k,
                                cell_j=(40.0 + k) * 1e6 / 96) for k in range(3)]
        self.refused("--grid", *diagonal, "--", "--grid", "one line")

    def test_partial_leaves_out_studies_with_too_few_points(self):
        on_a_line = self.grid_study(skip={(3.2, 42.0), (3.2, 47.0), (3.4, 37.0), (3.4, 47.0),
                                          (3.6, 37.0), (3.6, 42.0)})  # the diagonal
        gear = self.gear_study()
        result = fx.run("study_report.py", "--partial", "--gear", gear,
                        "--battery", self.battery_study()[0], "--grid", *on_a_line,
                        "-o", self.out)
        self.assert_ok(result)
        lines = result.stdout.splitlines()
        self.assertRegex(lines[0], r"^battery: left out, --battery: 1 lap.h5 given")
        self.assertRegex(lines[1], r"^grid: left out, --grid: the 3 points lie on one line")
        self.assertTrue(lines[2].startswith("gear: optimum 3.3"), lines[2])
        report = self.read("report.md")
        self.assertIn("## Gear ratio", report)
        self.assertNotIn("## Battery", report)
        self.assertFalse(os.path.exists(os.path.join(self.out, "fig15_grid.png")))
        result = fx.run("study_report.py", "--partial", "--gear", gear,
                        "--grid", *self.one_gear_grid(), "-o", self.out)
        self.assert_ok(result)
        self.assertRegex(result.stdout, r"(?m)^grid: left out, --grid: all 3 points have the same "
                                        r"drive\.gear_ratio")

    def test_partial_with_no_study_left_writes_nothing(self):
        for studies in (["--motors", self.motor_study()[0]], []):  # one point; none at all
            result = fx.run("study_report.py", "--partial", *studies, "-o", self.out)
            self.assert_ok(result)
            self.assertIn("no study has enough points yet: nothing written", result.stdout)
            self.assertFalse(os.path.exists(self.out), "output written")

    def test_partial_still_refuses_bad_points(self):
        same_gear = [write_point(self.path(f"s{k}.h5"), 1700.0, 3e7, gear=3.0) for k in range(2)]
        self.refused("--partial", "--gear", *same_gear, "--", "s1.h5", "same design")
        self.refused("--partial", "--gear", *self.battery_study()[:2], "--", "b31.h5",
                     "battery.cell_energy_j")


class BindingShareTest(unittest.TestCase):
    """The share of the lap time at a limit weighs each node by the time it stands for."""

    def test_each_node_stands_for_half_of_each_interval_beside_it(self):
        sys.path.insert(0, fx.SCRIPTS)
        import study_report
        # t = 0, 1, 3 s: the nodes stand for 0.5, 1.5 and 1 s; at the limit at the first and the
        # last: 1.5 of 3 s (counting nodes would say 2 of 3)
        self.assertAlmostEqual(study_report.binding_share(np.array([0.0, 1.0, 3.0]),
                                                          np.array([0.0, -1.0, -5e-4])), 0.5)
        self.assertTrue(math.isnan(study_report.binding_share(np.array([2.0]), np.array([0.0]))))


if __name__ == "__main__":
    fx.main()
