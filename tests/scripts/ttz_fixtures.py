"""Fixtures of the script tests: tiny lap.h5 / road.h5 files following docs/lap_h5.md and
docs/road_h5.md (only the datasets the scripts read, plus the schema attributes), and a runner
of the scripts under /usr/bin/python3."""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

PYTHON = "/usr/bin/python3"
SCRIPTS = os.environ.get("TTZ_SCRIPTS_DIR") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts")

LAP_LENGTH_M = 1000.0
LAP_NODES = 101


def lap_speed(s):
    """The known speed profile of the fixture lap [m/s] at s [m]."""
    return 20.0 + 0.01 * s


def _dataset(h5, name, values, units):
    dataset = h5.create_dataset(name, data=np.asarray(values, dtype=float))
    dataset.attrs["units"] = units
    dataset.attrs["description"] = name


def lap_channels(s):
    """{dataset: (values, units)} of the fixture lap on nodes s [m]."""
    v = lap_speed(s)
    ones = np.ones_like(s)
    return {"s": (s, "m"), "t": (np.concatenate([[0], np.cumsum(np.diff(s) / v[1:])]), "s"),
            "state/V": (v, "m/s"), "qss/s": (s, "m"), "qss/V": (0.95 * v, "m/s"),
            "state/n": (0.5 * np.sin(s / 100), "m"), "state/phi": (0.3 * np.sin(s / 100), "rad"),
            "battery/voltage": (400 * ones, "V"), "battery/current": (100 * ones, "A"),
            "battery/power": (40e3 * ones, "W"), "motor/voltage": (300 * ones, "V"),
            "motor/current": (120 * ones, "A"), "motor/power": (36e3 * ones, "W"),
            "wheel/power": (32e3 * ones, "W")}


RESIM_STATES = ("n", "alpha", "V", "beta", "z", "phi", "omega_w", "T", "e", "omega_phi", "z_dot",
                "Omega_z", "tau_w")


def write_lap(path, omega_group="control", schema="ttz.lap", version=1, drop=(), resim=False):
    """A lap of LAP_LENGTH_M with speed lap_speed(s); Omega_z under `omega_group`; with `resim`,
    the re-simulation's differences resim/<state> (0 at the start, 1e-4 to 1e-2 along s);
    datasets in `drop` left out."""
    s = np.linspace(0.0, LAP_LENGTH_M, LAP_NODES)
    channels = lap_channels(s)
    channels[f"{omega_group}/Omega_z"] = (0.1 * np.cos(s / 100), "rad/s")
    if resim:
        difference = np.where(s > 0.0, 1e-4 * 100.0 ** (s / LAP_LENGTH_M), 0.0)
        channels.update({f"resim/{name}": (difference, "1") for name in RESIM_STATES})
    with h5py.File(path, "w") as h5:
        for name, (values, units) in channels.items():
            if name not in drop:
                _dataset(h5, name, values, units)
        h5.attrs.update({"schema": schema, "schema_version": version, "lap_time": 100.0,
                         "energy_used": 3.0e6, "energy_fraction": 0.25, "top_speed": 30.0,
                         "road_length": LAP_LENGTH_M, "converged": np.int8(1), "message": ""})
    return path


def add_sensitivities(path, per_percent, kinds=None):
    """Adds sensitivity/* to the lap.h5 at `path`: keys section.key0, section.key1, ... with values
    1, 2, ..., these seconds per 1 % more and, when given, these kinds (else no sensitivity/kind,
    as in the laps written before it)."""
    with h5py.File(path, "a") as h5:
        h5.create_dataset("sensitivity/key", data=[f"section.key{i}" for i in range(len(per_percent))])
        h5.create_dataset("sensitivity/value", data=np.arange(1.0, len(per_percent) + 1))
        h5.create_dataset("sensitivity/per_percent", data=np.asarray(per_percent, dtype=float))
        if kinds is not None:
            h5.create_dataset("sensitivity/kind", data=list(kinds))
    return path


def write_road(path, length=LAP_LENGTH_M, banking=None, closed=False):
    """A road of `length` [m] curving left on a 500 m radius, rising 1 % (x east, y north, z up);
    version 1 (level across) or, with `banking` [rad], version 2 banked so all along; with
    `closed`, the attribute closed = 1 (the geometry stays open: enough for the scripts)."""
    s = np.linspace(0.0, length, 201)
    theta = s / 500.0
    channels = {"s": (s, "m"), "x": (500 * np.sin(theta), "m"), "y": (500 * (1 - np.cos(theta)), "m"),
                "z": (0.01 * s, "m"), "theta": (theta, "rad"), "sigma": (np.arcsin(0.01) * np.ones_like(s), "rad"),
                "kappa": (np.full_like(s, 1 / 500.0), "1/m")}
    with h5py.File(path, "w") as h5:
        for name, (values, units) in channels.items():
            _dataset(h5, name, values, units)
        if banking is not None:
            _dataset(h5, "banking", np.full_like(s, banking), "rad")
        h5.attrs.update({"schema": "ttz.road", "schema_version": 1 if banking is None else 2, "length_m": length,
                         "closed": np.int8(closed)})
    return path


def run(script, *args, env=None):
    """Runs scripts/<script> with args (and `env` added to the environment); the CompletedProcess
    (text stdout and stderr)."""
    env = dict(os.environ, MPLBACKEND="Agg", **(env or {}))
    return subprocess.run([PYTHON, os.path.join(SCRIPTS, script), *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=120)


class TempFolder:
    """Mixin of unittest.TestCase: a temporary folder self.dir per test, removed afterwards."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def path(self, *names):
        return os.path.join(self.dir, *names)


class ScriptAssertions:
    """Mixin of unittest.TestCase checks on a script's run."""

    def assert_ok(self, result):
        self.assertEqual(result.returncode, 0, result.stderr)

    def assert_refused(self, result, *words, absent=()):
        """Exit != 0, exactly one line on stderr containing every word, no file of `absent`."""
        self.assertNotEqual(result.returncode, 0, result.stdout)
        lines = result.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, result.stderr)
        for word in words:
            self.assertIn(word, lines[0])
        for path in absent:
            self.assertFalse(os.path.exists(path), f"{path} was written")
        return lines[0]

    def assert_no_temporaries(self, folder):
        self.assertEqual([f for f in os.listdir(folder) if f.endswith(".tmp")], [])


def main():
    """unittest.main, with the test module's own arguments removed (ctest passes the data dir)."""
    import unittest

    unittest.main(argv=sys.argv[:1], verbosity=2)
