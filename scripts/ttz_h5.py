"""Shared helpers of the TT Zero plotting scripts: reading the lap.h5 / road.h5 artefacts
(docs/lap_h5.md, docs/road_h5.md) and CSV files, writing outputs atomically, and reporting bad
input as one line on stderr.

Units are those of the artefacts: SI (m, s, m/s, V, A, W, J, rad), temperatures in degC.
"""
import argparse
import csv
import math
import os
import re
import sys
import tempfile

import numpy as np

LAP_SCHEMA = "ttz.lap"
# Version 1 had Omega_z in control/; version 2 has it in state/ (read by omega_z() below); version 3
# (docs/lap_h5.md) adds control_interval/, which the scripts do not read; version 4 sensitivity/, which
# reference_report.py, lap_plots.py and tracks_report.py read where it is (sensitivities() below; its
# sensitivity/kind came later within version 4). Any other version is refused.
LAP_VERSIONS = (1, 2, 3, 4)
# The kinds of sensitivity/kind (SensitivityKind, lap/sensitivity.h).
SENSITIVITY_KINDS = ("design", "rider", "condition", "reference")
ROAD_SCHEMA = "ttz.road"
# Version 2 (docs/road_h5.md) adds banking (road_banking() below reads version 1 as level).
ROAD_VERSIONS = (1, 2)
EARTH_RADIUS_M = 6371000.0


class InputError(Exception):
    """Bad input: the message names the file and what is wrong with it."""

    def __init__(self, path, what):
        super().__init__(f"{path}: {what}")


def run_cli(main):
    """Runs main(); an InputError (or a failed write) ends the program with one line on stderr
    and exit status 1 (argparse reports usage errors with 2)."""
    try:
        main()
    except InputError as err:
        sys.exit(f"error: {err}")
    except OSError as err:
        sys.exit(f"error: {err.filename or ''}: {err.strerror or err}")


class _OneLineParser(argparse.ArgumentParser):
    """argparse that reports a usage error as one line on stderr (exit status 2)."""

    def error(self, message):
        self.exit(2, f"error: {self.prog}: {message} (see --help)\n")


def argument_parser(doc):
    """Command-line parser whose --help shows the script's docstring."""
    return _OneLineParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)


def positive(kind):
    """argparse type: a positive finite number of `kind` (int: 1 or more)."""
    def parse(text):
        value = kind(text)
        if not (math.isfinite(value) and value > 0):
            raise ValueError(text)
        return value
    parse.__name__ = f"positive {kind.__name__}"
    return parse


def _text(value):
    """An HDF5 string attribute as str (h5py gives bytes or str)."""
    return value.decode() if isinstance(value, bytes) else str(value)


class Artefact:
    """An open lap.h5 or road.h5 whose schema and version were checked; read by name."""

    def __init__(self, path, schema, versions):
        import h5py  # imported here so the CSV-only scripts start fast

        if not os.path.isfile(path):
            raise InputError(path, "no such file")
        try:
            self.h5 = h5py.File(path, "r")
        except OSError as err:
            raise InputError(path, f"not a readable HDF5 file ({err})") from None
        self.path = path
        self._check_schema(schema, versions)

    def _check_schema(self, schema, versions):
        found = _text(self.h5.attrs.get("schema", "(none)"))
        version = self.h5.attrs.get("schema_version", None)
        if found != schema or version is None or int(version) not in versions:
            wanted = " or ".join(str(v) for v in versions)
            raise InputError(self.path, f"schema '{found}' version {version} is not "
                             f"'{schema}' version {wanted}")
        self.version = int(version)

    def has(self, name):
        """True if the dataset exists."""
        return name in self.h5 and hasattr(self.h5[name], "shape")

    def strings(self, name, length=None):
        """String dataset `name` as a list of str; checks its length."""
        if not self.has(name):
            raise InputError(self.path, f"missing dataset '{name}'")
        return [_text(value) for value in self._checked_length(name, np.asarray(self.h5[name][()]).reshape(-1), length)]

    def data(self, name, length=None):
        """Dataset `name` as a float array (its units: docs/*_h5.md); checks its length."""
        if not self.has(name):
            raise InputError(self.path, f"missing dataset '{name}'")
        try:
            values = np.asarray(self.h5[name][()], dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise InputError(self.path, f"dataset '{name}' is not numeric") from None
        return self._checked_length(name, values, length)

    def _checked_length(self, name, values, length):
        """`values` of dataset `name`, unless `length` is given and they are not that many."""
        if length is not None and values.size != length:
            raise InputError(self.path, f"dataset '{name}' has {values.size} values, "
                             f"expected {length}")
        return values

    def first_of(self, names, length=None):
        """The first dataset of `names` that exists (for channels that moved between groups)."""
        for name in names:
            if self.has(name):
                return self.data(name, length)
        raise InputError(self.path, "missing dataset " + " or ".join(f"'{n}'" for n in names))

    def attr(self, name, kind=float):
        """File attribute `name` converted by `kind` (float, int or str)."""
        if name not in self.h5.attrs:
            raise InputError(self.path, f"missing attribute '{name}'")
        value = self.h5.attrs[name]
        if kind is str:
            return _text(value)
        try:
            return kind(np.asarray(value).reshape(-1)[0])
        except (TypeError, ValueError, IndexError):
            raise InputError(self.path, f"attribute '{name}' is not a number") from None

    def optional_attr(self, name, kind=float, default=None):
        """attr(), or `default` for an attribute that older or partial files may lack."""
        return self.attr(name, kind) if name in self.h5.attrs else default


def require_finite(path, name, values):
    """`values` (dataset `name` of the file at `path`), or InputError when any is not finite."""
    if not np.all(np.isfinite(values)):
        raise InputError(path, f"dataset '{name}' has non-finite values")
    return values


def open_lap(path):
    """lap.h5 (schema ttz.lap)."""
    return Artefact(path, LAP_SCHEMA, LAP_VERSIONS)


def open_road(path):
    """road.h5 (schema ttz.road)."""
    return Artefact(path, ROAD_SCHEMA, ROAD_VERSIONS)


def road_banking(road, length):
    """The road's banking [rad]: zero in version 1, which had none (docs/road_h5.md)."""
    return road.data("banking", length) if road.version >= 2 else np.zeros(length)


def sensitivities(lap):
    """[(key, value, seconds per 1 % more, kind)] of the lap's design sensitivities (sensitivity/*,
    docs/lap_h5.md; version 4, the indirect solver's converged laps), [] for a lap without them.
    kind is design, rider, condition or reference (sensitivity/kind); "design" for every row of a
    lap written before sensitivity/kind."""
    if not lap.has("sensitivity/key"):
        return []
    keys = lap.strings("sensitivity/key")
    kinds = lap.strings("sensitivity/kind", len(keys)) if lap.has("sensitivity/kind") else ["design"] * len(keys)
    unknown = sorted(set(kinds) - set(SENSITIVITY_KINDS))
    if unknown:
        raise InputError(lap.path, f"dataset 'sensitivity/kind': unknown kind '{unknown[0]}', expected one of "
                         + ", ".join(SENSITIVITY_KINDS))
    return list(zip(keys, lap.data("sensitivity/value", len(keys)),
                    lap.data("sensitivity/per_percent", len(keys)), kinds))


def largest_sensitivities(rows, count, kind="design"):
    """The `count` rows of sensitivities() of that kind with the largest finite figure by size,
    largest first, and the keys of its rows without a finite one."""
    rows = [row for row in rows if row[3] == kind]
    finite = [row for row in rows if math.isfinite(row[2])]
    missing = [row[0] for row in rows if not math.isfinite(row[2])]
    return sorted(finite, key=lambda row: -abs(row[2]))[:count], missing


def omega_z(lap, length=None):
    """Yaw rate Omega_z [rad/s], a control in version 1 and a state after the move."""
    return lap.first_of(("control/Omega_z", "state/Omega_z"), length)


# --- CSV -------------------------------------------------------------------------------------

def _is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def _comment_header(comments):
    """Column names from the last '#' comment line that lists them comma-separated; each name is
    the leading identifier of its field ('distance_m (lap distance ...)' -> 'distance_m')."""
    for line in reversed(comments):
        fields = next(csv.reader([line.lstrip("#").strip()]))
        names = [re.match(r"\s*([A-Za-z_][A-Za-z0-9_]*)", f) for f in fields]
        if len(fields) > 1 and all(names):
            return [m.group(1) for m in names]
    return None


def _split_rows(path):
    """(comment lines, [(line number, fields)]) of a CSV file, blank lines skipped."""
    comments, rows = [], []
    try:
        with open(path, newline="") as handle:
            for number, line in enumerate(handle, start=1):
                if line.startswith("#"):
                    comments.append(line)
                elif line.strip():
                    rows.append((number, next(csv.reader([line]))))
    except FileNotFoundError:
        raise InputError(path, "no such file") from None
    except UnicodeDecodeError:
        raise InputError(path, "not a text CSV file") from None
    return comments, rows


def _header_and_rows(path):
    """Header names and data rows: the header is the first non-comment line when it is not
    numeric, else the column list of a '#' comment line."""
    comments, rows = _split_rows(path)
    if rows and not all(_is_number(f) for f in rows[0][1]):
        return [f.strip() for f in rows[0][1]], rows[1:]
    header = _comment_header(comments)
    if header is None:
        raise InputError(path, "malformed CSV: no header line and no column list in a '#' line")
    return header, rows


def _column(path, header, rows, name):
    """Column `name` as floats; any empty or non-numeric value is an error naming its line."""
    if name not in header:
        raise InputError(path, f"malformed CSV: no column '{name}' (columns: {', '.join(header)})")
    index = header.index(name)
    values = np.empty(len(rows))
    for k, (number, fields) in enumerate(rows):
        text = fields[index].strip() if index < len(fields) else ""
        if not _is_number(text) or not math.isfinite(float(text)):
            raise InputError(path, f"malformed CSV: line {number}, column '{name}': "
                             f"'{text}' is not a finite number")
        values[k] = float(text)
    return values


def csv_header(path):
    """The column names of a CSV file."""
    return _header_and_rows(path)[0]


def read_csv_columns(path, names, min_rows=2):
    """The named numeric columns of a CSV file as {name: float array}; other columns may hold
    text. Comment lines start with '#'."""
    header, rows = _header_and_rows(path)
    if len(rows) < min_rows:
        raise InputError(path, f"malformed CSV: {len(rows)} data rows, need at least {min_rows}")
    return {name: _column(path, header, rows, name) for name in names}


# --- geometry --------------------------------------------------------------------------------

def local_xy(lat_deg, lon_deg, lat0_deg, lon0_deg):
    """Equirectangular projection about (lat0, lon0): east and north [m] of WGS84 degrees,
    sphere of radius 6,371 km (errors ~0.1 % over the 20 km of the TT course)."""
    x = np.radians(lon_deg - lon0_deg) * EARTH_RADIUS_M * math.cos(math.radians(lat0_deg))
    y = np.radians(lat_deg - lat0_deg) * EARTH_RADIUS_M
    return x, y


# --- output ----------------------------------------------------------------------------------

def _umask():
    """The process's file-creation mask (mkstemp makes files 0600; outputs get the usual mode)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_atomically(path, write):
    """Calls write(temporary path) for a temporary file beside `path` (its folder created if
    missing), then renames it to `path`; on any failure the temporary file is removed and `path`
    is untouched (a folder created for it stays, empty)."""
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    handle, temp = tempfile.mkstemp(dir=folder, prefix="." + os.path.basename(path) + ".",
                                    suffix=".tmp")
    os.close(handle)
    try:
        write(temp)
        os.chmod(temp, 0o666 & ~_umask())
        os.replace(temp, path)
    except BaseException:
        if os.path.exists(temp):
            os.remove(temp)
        raise


def save_figure(figure, path):
    """Writes a matplotlib figure as PNG, atomically, and closes it."""
    import matplotlib.pyplot as plt

    try:
        write_atomically(path, lambda temp: figure.savefig(temp, format="png", dpi=110))
    finally:
        plt.close(figure)


def write_text(path, text):
    """Writes a text file atomically."""
    def write(temp):
        with open(temp, "w") as handle:
            handle.write(text)
    write_atomically(path, write)


def pyplot():
    """matplotlib.pyplot on the Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
