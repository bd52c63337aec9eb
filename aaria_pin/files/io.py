"""Reading tables from files; the input and output paths every command goes through.

Tables come as CSV (comma separated, ``#`` comments, an optional header row), ``.npy``, MATLAB
``.mat`` holding a named array (the paper's ``senSenDH``, ``senSenJ``, ``senSenB``), or a run
file (``.h5``, ``.hdf5``) holding the table among its inputs. Outputs are written atomically
under a lock (:mod:`aaria_pin.files.paths`, re-exported here).
"""

from __future__ import annotations

import os
import re
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.oscillation import BASE_COLUMNS, JOINT_COLUMNS
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError
from aaria_pin.files._stored import first_line
from aaria_pin.files.paths import (
    atomic_output,
    check_output,
    check_outputs,
    existing_input,
    output_lock,
    write_text_atomic,
)

__all__ = [
    "STORED_DH_COLUMNS",
    "TABLE_SUFFIXES",
    "atomic_output",
    "check_output",
    "check_outputs",
    "existing_input",
    "numeric_array",
    "output_lock",
    "read_csv_table",
    "read_table",
    "write_text_atomic",
]

TABLE_SUFFIXES = (".csv", ".txt", ".npy", ".mat", ".h5", ".hdf5")
"""The files :func:`read_table` reads."""

STORED_DH_COLUMNS = ("alpha", "a", "theta", "d", "link type")
"""Columns of a stored DH table (``senSenDH``; ``_stored.TABLE_UNITS`` gives their units): the
Aaria layer's ``AARIA_COLUMNS``, which this layer cannot import (a test keeps them equal)."""

_KNOWN_COLUMNS: dict[str, tuple[str, ...]] = {
    "senSenDH": STORED_DH_COLUMNS,
    "senSenJ": JOINT_COLUMNS,
    "joint_table": JOINT_COLUMNS,
    "senSenB": BASE_COLUMNS,
    "base_table": BASE_COLUMNS,
}
"""Column names of the stored input tables, by stored name (a caller may pass others)."""

_RUN_TABLE_ALIASES = {"senSenB": ("senSenB", "base_table"), "base_table": ("base_table", "senSenB")}
"""Stored names tried in a run file, in order: a DH run's base table is a URDF run's too."""


@checked
def read_table(
    path: str | os.PathLike[str],
    mat_name: str = "senSenDH",
    columns: Sequence[str] | None = None,
) -> Array:
    """Read a 2-D numeric table from a CSV, ``.npy``, ``.mat`` or run file.

    A CSV file may start with a header row (its first row that is not a comment, when none of
    its cells is a number). When the column names are known (``columns``, or those of a stored
    DH, joint or base table) the header's names are checked: the known names in any order
    are put in the known order, and a known name in another column than its own is refused; a
    header of other names is skipped and the columns taken in order. Names compare without
    case, units in brackets, ``_`` or extra spaces (``"Link_Type [-]"`` is ``"link type"``).

    Args:
        path: the file
        mat_name: name of the array in a ``.mat`` file, or of the table in a run file's inputs
        columns: the table's column names (None: the core's names for ``mat_name``, if any)

    Returns:
        The table as a 2-D float array, every entry finite (its shape is checked by the table's
        validator).

    Raises:
        InputFileError: the file is missing, not a regular file, unreadable, of an unknown
            kind, empty, not numeric (naming the row and column), holding a NaN or inf (naming
            the row and column), or a run file without the table.
    """
    file = existing_input(path, TABLE_SUFFIXES, "table")
    suffix = file.suffix.lower()
    names = tuple(columns) if columns is not None else _KNOWN_COLUMNS.get(mat_name)
    if file.stat().st_size == 0:
        raise InputFileError(
            f"{file}: is empty (0 bytes); allowed: a numeric table", parameter="file"
        )
    try:
        if suffix == ".npy":
            data = np.load(file, allow_pickle=False)
        elif suffix == ".mat":
            data = _read_mat_array(file, mat_name)
        elif suffix in (".h5", ".hdf5"):
            data = _read_run_table(file, mat_name)
        else:
            data = _read_csv(file, names)
        table = numeric_array(file, data)
    except InputFileError:
        raise
    except (OSError, ValueError, TypeError, EOFError) as exc:
        raise InputFileError(
            f"{file}: cannot be read as a numeric table ({first_line(exc)})", parameter="file"
        ) from None
    if table.size == 0:
        shape = " × ".join(str(n) for n in table.shape)
        raise InputFileError(
            f"{file}: is an empty table (shape {shape}); allowed: a numeric table",
            value=table.shape,
            parameter="file",
            allowed="a numeric table",
            element=str(file),
        )
    if table.ndim == 1:
        table = table.reshape(1, -1)
    if table.ndim != 2:
        raise InputFileError(
            f"{file}: holds a {table.ndim}-D array; expected a 2-D table", parameter="file"
        )
    _check_finite(file, table, names)
    return table


_NOT_NUMBERS = {"b": "bool", "U": "text", "S": "bytes", "O": "object", "M": "date", "m": "time"}
"""NumPy dtype kinds a numeric table does not hold (``V``, a record: "structured"), by name."""


def numeric_array(file: Path, data: object, name: str = "") -> Array:
    """The array read from ``file`` as float64, if it holds real numbers (ints or floats).

    ``np.asarray(..., dtype=float)`` alone would take booleans as 0 and 1 and text such as
    ``"1.5"`` as numbers; a file holding those is refused instead.

    Args:
        file: the file it was read from (named in the error)
        data: the array as read (any dtype)
        name: the array's name in the file, for the error ("" for a file of one array)

    Returns:
        The values as a float64 array.

    Raises:
        InputFileError: bool, text, object, date or structured values, or complex numbers
            (``parameter="file"``).
    """
    array = np.asarray(data)
    kind = array.dtype.kind
    holder = f"{file}: {name} holds" if name else f"{file}: holds"
    if kind == "c":
        raise InputFileError(f"{holder} complex numbers; allowed: a real table", parameter="file")
    if kind not in "iuf":
        values = _NOT_NUMBERS.get(kind, "structured")
        raise InputFileError(
            f"{holder} {values} values (dtype {array.dtype}); allowed: a numeric table",
            parameter="file",
            value=str(array.dtype),
            allowed="a numeric table",
            element=str(file),
        )
    return np.asarray(array, dtype=float)


def _check_finite(file: Path, table: Array, names: Sequence[str] | None) -> None:
    """Refuse a NaN or inf entry, naming its row and column (1-based, as in the file)."""
    bad = np.argwhere(~np.isfinite(table))
    if not bad.size:
        return
    row, col = (int(i) for i in bad[0])
    name = f" ({names[col]})" if names is not None and col < len(names) else ""
    where = f"row {row + 1}, column {col + 1}{name}"
    value = float(table[row, col])
    raise InputFileError(
        f"{file}: {where} is {value}; allowed: a finite number",
        parameter="file",
        value=value,
        allowed="a finite number",
        element=where,
    )


def _normal_name(name: str) -> str:
    """A column name as compared: lower case, no units in brackets, single spaces."""
    bare = re.sub(r"[\[(].*?[\])]", " ", name.strip().strip("'\"").lower())
    return " ".join(bare.replace("_", " ").split())


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _read_csv(file: Path, names: Sequence[str] | None) -> Array:
    """A CSV table, its optional header row checked against ``names`` (see :func:`read_table`)."""
    table, header = read_csv_table(file)
    if header is not None and names is not None:
        table = _ordered_by_header(file, table, header, names)
    return table


def read_csv_table(file: Path) -> tuple[Array, list[str] | None]:
    """The numbers of a CSV table and its header row's cells, if it has one.

    Comma separated, ``#`` comments (whole lines or the rest of a line); the header is the
    first row that is not a comment when none of its cells is a number. The numbers are parsed
    as Python's ``float`` parses them.

    Args:
        file: the CSV file (UTF-8, a byte-order mark allowed)

    Returns:
        The numbers, rows × columns (at least 2-D), and the header's cells (None: no header).

    Raises:
        InputFileError: no numbers, a cell that is not a number or a row of another width
            (naming the row and column), in one line naming the file.
        OSError, ValueError: the file cannot be read or decoded.
    """
    text = file.read_text(encoding="utf-8-sig")
    lines = text.splitlines()
    header_at, header = None, None
    for number, line in enumerate(lines):
        content = line.split("#", 1)[0].strip()
        if not content:
            continue
        cells = [cell.strip() for cell in content.split(",")]
        if not any(_is_number(cell) for cell in cells):  # a row of names, no number
            header_at, header = number, cells
        break
    start = 0 if header_at is None else header_at + 1
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # an empty file is an error, not a warning
            table = np.loadtxt(lines[start:], delimiter=",", comments="#", ndmin=2)
    except UserWarning:
        raise InputFileError(
            f"{file}: is empty; allowed: a numeric table"
            + (" (it has a header row and no numbers)" if header is not None else ""),
            parameter="file",
        ) from None
    except ValueError:
        raise _bad_cell(file, lines, start) from None
    return table, header


def _bad_cell(file: Path, lines: list[str], start: int) -> InputFileError:
    """The first cell that is not a number (or the first row of another width), as an error."""
    width = None
    row = 0
    for line in lines[start:]:
        content = line.split("#", 1)[0].strip()
        if not content:
            continue
        row += 1
        cells = [cell.strip() for cell in content.split(",")]
        for col, cell in enumerate(cells):
            if not _is_number(cell):
                where = f"row {row}, column {col + 1}"
                return InputFileError(
                    f"{file}: {where} is {cell!r}; allowed: a number",
                    parameter="file",
                    value=cell,
                    allowed="a number",
                    element=where,
                )
        if width is not None and len(cells) != width:
            return InputFileError(
                f"{file}: row {row} has {len(cells)} columns; allowed: {width}, as the rows "
                "before it",
                parameter="file",
                value=len(cells),
                allowed=str(width),
                element=f"row {row}",
            )
        width = len(cells)
    return InputFileError(f"{file}: cannot be read as a numeric table", parameter="file")


def _ordered_by_header(
    file: Path, table: Array, header: Sequence[str], names: Sequence[str]
) -> Array:
    """The table's columns in the known order, after checking the header's names."""
    given = [_normal_name(h) for h in header]
    known = [_normal_name(n) for n in names]
    if sorted(given) == sorted(known):
        return table[:, [given.index(name) for name in known]]
    for col, name in enumerate(given):
        if name in known and (col >= len(known) or known[col] != name):
            where = f"header, column {col + 1}"
            raise InputFileError(
                f"{file}: {where} is {header[col]!r}, which is column {known.index(name) + 1}; "
                f"allowed: the columns {', '.join(names)} in this order (or all of them in any "
                "order, or a header of other names)",
                parameter="file",
                value=header[col],
                allowed=", ".join(names),
                element=where,
            )
    return table


def _read_run_table(file: Path, name: str) -> Array:
    """A table among a run file's inputs (``senSenDH``, ``senSenJ``, ``senSenB``, ...)."""
    from aaria_pin.files.runfile import read_run_inputs

    tables = read_run_inputs(file).tables
    for stored in _RUN_TABLE_ALIASES.get(name, (name,)):
        if stored in tables:
            return np.asarray(tables[stored])
    raise InputFileError(
        f"{file}: a run file without the table {name!r}; allowed: a run that has it "
        f"(this one has {', '.join(sorted(tables)) or 'no tables'})",
        parameter="mat_name",
        value=name,
        allowed=", ".join(sorted(tables)) or "none",
        element=str(file),
    )


def _read_mat_array(file: Path, name: str) -> Array:
    """One array of a MATLAB file: v4–v7 through scipy, v7.3 (HDF5) through h5py."""
    from aaria_pin.files.detection import is_mat73

    if is_mat73(file):  # HDF5, stored column-major
        import h5py

        with h5py.File(file, "r") as handle:
            if name not in handle:
                raise InputFileError(
                    f"{file}: no array {name!r} in the .mat file; has {sorted(handle)}",
                    parameter="mat_name",
                )
            return _mat73_array(file, handle[name])
    from scipy.io import loadmat
    from scipy.io.matlab import MatReadError

    try:
        contents = loadmat(file)
    except MatReadError as exc:
        raise ValueError(str(exc)) from None
    if name not in contents:
        names = sorted(k for k in contents if not k.startswith("__"))
        raise InputFileError(
            f"{file}: no array {name!r} in the .mat file; has {names}", parameter="mat_name"
        )
    return np.asarray(contents[name])


def _mat73_array(file: Path, dataset: Any) -> Array:
    """An array of a v7.3 MATLAB file, transposed (it is stored column-major).

    Logical and char arrays, stored as integers, are refused by their ``MATLAB_class``.
    """
    matlab_class = dataset.attrs.get("MATLAB_class", b"double")
    name = matlab_class.decode() if isinstance(matlab_class, bytes) else str(matlab_class)
    if name in ("logical", "char", "cell", "struct"):
        kind = {"logical": "bool", "char": "text"}.get(name, name)
        raise InputFileError(
            f"{file}: holds {kind} values (MATLAB {name}); allowed: a numeric table",
            parameter="file",
            value=name,
            allowed="a numeric table",
            element=str(file),
        )
    return np.asarray(dataset[()]).T
