"""The run file: the one file of one :class:`~aaria_pin.core.record.RunRecord`, for every robot.

Two formats, chosen by the file suffix, holding the same names and shapes (T samples, n joints,
S IMUs; the record's module docstring gives units and frames):

``.h5`` / ``.hdf5`` (HDF5, through h5py)
    Float64 datasets at the root: ``time`` (T), ``q``, ``qd``, ``qdd``, ``tau`` (T × n),
    ``base_pose`` (T × 4 × 4), ``base_wrench`` (T × 6), ``tool_pose`` (T × 4 × 4), ``imu``
    (T × S × 6), ``imu_mount`` (S × 4 × 4), then each input table under its name (e.g.
    ``senSenDH``, ``senSenJ``, ``senSenB``, ``joint_table``, ``base_table``; a table of fewer
    than two axes is stored, and reads back, as a 1 × k row, as in MATLAB); each has a ``units``
    attribute (a string). Each column view (e.g. the Aaria ``senSen``, T × 91) is an HDF5
    **virtual dataset** over those series in the same file (source file ``"."``, so it stays
    valid when the file is renamed or copied; h5py and MATLAB's ``h5read`` read it as a plain
    T × C array), with ``units`` and ``columns``, its column names as variable-length UTF-8
    strings. ``joint_names`` (n), ``imu_names`` and ``imu_parents`` (S, ``""`` for an empty
    slot) are UTF-8 string datasets and ``urdf`` a UTF-8 string dataset (``""`` if none).
    By default every dataset is contiguous and uncompressed (writing is then bound by the disk:
    a 200,000-sample run writes in about 0.4 s uncompressed, 4.8 s with gzip). With
    ``compression="gzip"`` (level 1 after the shuffle filter, the one filter every HDF5 build
    has, MATLAB included; about 30 % smaller) or ``"lzf"`` (h5py only, faster) the series are
    chunked along time, up to 4096 rows and at most 1 MiB per chunk.
    The root group carries ``format = "aaria_pin run"``, ``format_version = 2`` and one
    attribute per item of ``RunRecord.attributes`` (insertion order kept; ``kind``, ``robot``,
    ``rate``, ... are ordinary attributes).

``.mat`` (MATLAB v5 through ``scipy.io.savemat``, compressed; or MATLAB v7.3)
    The same arrays under the same names (3-D arrays stay 3-D, ``time`` is 1 × T), each view
    materialised as a real T × C array with its column names as the 1 × C cell array
    ``<view>_columns`` (``senSen_columns``), ``joint_names``, ``imu_names``, ``imu_parents`` as
    1 × n / 1 × S cell arrays, ``urdf`` a char array, and every attribute as a variable
    ``attr_<name>``, including ``attr_format`` and ``attr_format_version``. A run of more than
    :data:`~aaria_pin.core.run.CHUNK_SAMPLES` samples is written as a MAT-file v7.3 (an HDF5
    file MATLAB's ``load`` reads; the layout: :mod:`._mat73`), streamed piece by piece, with
    the same variables and the sizes MATLAB shows for the v5 file; a shorter one as v5 (why:
    :func:`mat_version_for`; ``mat_version`` asks for either). :func:`read_run` reads both.

Views are read back from their column names (both formats): ``time`` → ``time``; ``q<j>``
(1-based) or ``q:<joint>`` → a column of ``q`` (also ``qd``, ``qdd``, ``tau``);
``<imu>_<signal>`` → one signal of one IMU. :func:`write_run` refuses a view whose column names
do not read back as its columns. Any other numeric array of the file reads back as a table.

Attribute encoding (both formats): a str, bool, int (64-bit) or float is stored as a plain
scalar attribute (an HDF5 bool is an enum that MATLAB reads as ``'TRUE'``/``'FALSE'``); a list,
tuple or 1-D array of two or more numbers (no bools) as a numeric vector (int64 if all are
integers, else float64; it reads back as a list). Anything else (a dict, a list of strings,
a one-item list, None, ...) and every attribute whose name already ends in ``_json`` is stored
as a JSON string under its name plus the suffix ``_json``, e.g. ``noise_parameters`` →
``noise_parameters_json`` (``attr_noise_parameters_json`` in a ``.mat``), and is JSON-decoded
when read back (so tuples come back as lists and dict keys as strings). The names ``format``
and ``format_version`` are reserved; in a ``.mat`` file ``attr_<name>`` must be a MATLAB
variable name (letters, digits and ``_``, at most 63 characters).

A long run is written in time pieces (:func:`write_run_chunks`, :class:`RunFileWriter`): the
HDF5 datasets are preallocated at the run's full length and filled piece by piece, so memory
does not grow with the run's length; the file is the same as :func:`write_run` makes of the
whole record (which is the one-piece case of the same writer). So is a ``.mat`` v7.3 file; a
``.mat`` v5 file is written whole.

:func:`read_run` also reads every run file aaria_pin 0.1.0 wrote (:mod:`._legacy`: Aaria DH
``.h5``/``.mat``, URDF robot and pick-place ``.h5``, wrist ``.h5``/``.mat``).
"""

from __future__ import annotations

import contextlib
import itertools
import os
from collections.abc import Callable, Iterable, Iterator, Mapping
from pathlib import Path
from types import TracebackType
from typing import Any

import numpy as np

from aaria_pin.core.record import SERIES, RunRecord, record_shapes
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files._stored import JSON_SUFFIX, NAME_LISTS, encode_attributes, first_line
from aaria_pin.files.paths import atomic_output, existing_input
from aaria_pin.files.runfile._attributes import RUN_FORMAT, RUN_FORMAT_VERSION
from aaria_pin.files.runfile._hdf5 import (
    _hdf5_errors,
    _Hdf5Stream,
    _read_hdf5_v2,
    _summarise_hdf5_v2,
)
from aaria_pin.files.runfile._layout import (
    COLUMNS_SUFFIX,
    checked_arrays,
    column_source,
    view_from_columns,
)
from aaria_pin.files.runfile._legacy import (
    LAYOUT_V2,
    URDF_V1_FORMAT,
    hdf5_layout,
    mat_layout,
    read_legacy_hdf5,
    read_legacy_mat,
)
from aaria_pin.files.runfile._mat import (
    MAT_ATTRIBUTE_PREFIX,
    _mat_contents,
    _read_mat_v2,
    _summarise_mat_v2,
    _write_mat,
    load_mat,
    mat_attribute_variables,
    mat_variables,
)
from aaria_pin.files.runfile._mat73 import _Mat73Stream, check_mat73_compression, is_mat73

__all__ = [
    "COMPRESSIONS",
    "JSON_SUFFIX",
    "MAT_VERSIONS",
    "RUN_FORMAT",
    "RUN_FORMAT_VERSION",
    "RUN_SUFFIXES",
    "URDF_V1_FORMAT",
    "RunFileWriter",
    "column_source",
    "is_run_file",
    "mat_version_for",
    "read_run",
    "read_run_inputs",
    "run_file_summary",
    "view_from_columns",
    "write_run",
    "write_run_chunks",
    "write_run_pieces",
]

COMPRESSIONS = (None, "gzip", "lzf")
"""HDF5 filters :func:`write_run` offers for the time series (None: uncompressed)."""

RUN_SUFFIXES = (".h5", ".hdf5", ".mat")
"""File suffixes of run files (case-insensitive)."""

MAT_VERSIONS = ("5", "7.3")
"""MAT-file versions a ``.mat`` run file is written as (:func:`mat_version_for` chooses)."""


def mat_version_for(samples: int) -> str:
    """The MAT-file version a ``.mat`` run of ``samples`` is written as, unless one is asked.

    ``"7.3"`` (HDF5, streamed piece by piece into preallocated datasets) for a run longer
    than :data:`~aaria_pin.core.run.CHUNK_SAMPLES` samples, the runs ``aaria simulate``
    computes in pieces; ``"5"`` (scipy's ``savemat``, compressed) for a shorter one. The
    reason is structural: scipy writes a v5 file only whole, from arrays in memory, each at
    most 2 GiB (a ``senSen`` of 2.9 M samples), so a v5 run's memory grows with its length
    (``aaria simulate --preset aaria-fig2 --duration 1.99999 --rate 100000 -o run.mat``,
    200,000 samples with noise: 1.12 GB peak and 20 s as v5, 0.34 GB and 4 s as v7.3), while a
    short run keeps the format every earlier file has, which scipy and every MATLAB read
    (scipy cannot read v7.3) and which is compressed (that run's v5 file is 139 MB, its
    uncompressed v7.3 381 MB; ``compression="gzip"`` compresses a v7.3).
    """
    from aaria_pin.core.run import CHUNK_SAMPLES

    return "7.3" if samples > CHUNK_SAMPLES else "5"


def _check_output(final: Path, compression: str | None, mat_version: str | None = None) -> str:
    """The output's lower-case suffix; OutputFileError for an unknown suffix, filter or version."""
    suffix = final.suffix.lower()
    if compression not in COMPRESSIONS:
        raise OutputFileError(
            f"compression {compression!r} is not allowed; allowed: None, 'gzip', 'lzf'"
        )
    if suffix not in RUN_SUFFIXES:
        raise OutputFileError(
            f"{final}: unknown run file type {suffix!r}; allowed: {', '.join(RUN_SUFFIXES)}"
        )
    if mat_version is not None and mat_version not in MAT_VERSIONS:
        raise OutputFileError(
            f"{final}: MAT-file version {mat_version!r} is not allowed; allowed: None, "
            + ", ".join(repr(v) for v in MAT_VERSIONS),
            parameter="mat_version",
            value=mat_version,
            allowed="None, " + ", ".join(repr(v) for v in MAT_VERSIONS),
        )
    return suffix


def write_run(
    path: str | os.PathLike[str],
    record: RunRecord,
    compression: str | None = None,
    mat_version: str | None = None,
) -> Path:
    """Write a run record to an HDF5 (``.h5``, ``.hdf5``) or MATLAB (``.mat``) file.

    The file is written beside its destination and renamed when complete, so a failure never
    leaves a partial file (see :func:`aaria_pin.files.io.atomic_output`). The layout is described in
    the module docstring. An HDF5 file, and a ``.mat`` v7.3, is written by
    :class:`RunFileWriter` in one piece.

    Args:
        path: the run file; its suffix selects the format
        record: the run to write
        compression: HDF5 filter of the time series: ``None`` (default, fastest), ``"gzip"``
            or ``"lzf"``; a ``.mat`` v5 file is always compressed, a v7.3 one takes None or
            ``"gzip"``
        mat_version: ``"5"`` or ``"7.3"`` for a ``.mat`` file; None (default): by the run's
            length (:func:`mat_version_for`)

    Returns:
        The path written.

    Raises:
        OutputFileError: unknown suffix, missing folder, an array of the wrong shape, a table or
            view that cannot be stored, an attribute that cannot be stored, or a write failure.
    """
    final = Path(path)
    suffix = _check_output(final, compression, mat_version)
    if suffix != ".mat" or (mat_version or mat_version_for(record.n_samples)) == "7.3":
        version = "7.3" if suffix == ".mat" else mat_version
        with RunFileWriter(final, record, compression=compression, mat_version=version) as writer:
            writer.write(0, record)
        return final
    arrays = checked_arrays(final, record)
    attributes = encode_attributes(final, record.attributes)
    contents = _mat_contents(final, record, arrays, attributes)
    with atomic_output(final) as temporary:
        try:
            _write_mat(temporary, contents)
        except OSError as exc:
            raise OutputFileError(f"{final}: cannot be written ({first_line(exc)})") from None
    return final


def write_run_chunks(
    path: str | os.PathLike[str],
    chunks: Iterable[RunRecord],
    samples: int,
    compression: str | None = None,
    mat_version: str | None = None,
) -> Path:
    """Write a run that comes in time pieces (e.g. ``simulate_run_chunks``) to a run file.

    An HDF5 file, and a ``.mat`` v7.3 (the version of a run longer than one chunk,
    :func:`mat_version_for`), is written piece by piece into preallocated datasets
    (:class:`RunFileWriter`), so memory does not grow with the run's length. A ``.mat`` v5
    file (which scipy writes only whole) is written from the pieces joined in memory.

    Args:
        path: the run file; its suffix selects the format
        chunks: the run's pieces in time order, each a record of its samples; the attributes
            of the last piece are stored (they cover the whole run)
        samples: T, the run's number of samples (the pieces' lengths add up to it)
        compression: as in :func:`write_run`
        mat_version: as in :func:`write_run` (None: by ``samples``)

    Returns:
        The path written.

    Raises:
        OutputFileError: as :func:`write_run`; no piece, pieces of other joints or IMUs than
            the first, or pieces that do not add up to ``samples`` (nothing is left).
    """
    from aaria_pin.core.run import join_chunks

    final = Path(path)
    suffix = _check_output(final, compression, mat_version)
    pieces = iter(chunks)
    first = next(pieces, None)
    if first is None:
        raise OutputFileError(f"{final}: a run of no piece; allowed: one piece or more")
    version = mat_version or mat_version_for(samples)
    if suffix == ".mat" and version == "5":
        return write_run(final, join_chunks([first, *pieces]), compression, "5")
    with RunFileWriter(final, first, samples, compression, version) as writer:
        start = 0
        for chunk in itertools.chain([first], pieces):
            writer.write(start, chunk)
            start += chunk.n_samples
    return final


class RunFileWriter:
    """A run file written in time pieces into preallocated HDF5 datasets (a context manager).

    Entering it creates the file beside its destination (:func:`~aaria_pin.files.io.atomic_output`)
    with the one layout of the module docstring: every series preallocated at the run's full
    length, ``imu_mount``, the tables, the views (virtual datasets over the full series; in a
    ``.mat`` v7.3, real arrays filled piece by piece), the names and the URDF, from the first
    piece. :meth:`write` stores the series of a piece; leaving the block writes the root
    attributes (the ``attr_`` variables of a ``.mat``: those of the last piece written, which
    cover the whole run) and renames the file onto its destination. On any failure, or if the
    pieces do not add up to the run, nothing is left. :func:`write_run` of an HDF5 file is the
    one-piece case.

    Example::

        with RunFileWriter("run.h5", first, samples) as writer:
            writer.write(0, first)
            writer.write(first.n_samples, second)

    Args:
        path: the ``.h5``, ``.hdf5`` or ``.mat`` (v7.3) file
        first: the first piece (its names, mounts, URDF, tables and views are the run's)
        samples: T, the run's number of samples (default ``first.n_samples``)
        compression: as in :func:`write_run`
        mat_version: for a ``.mat``, as in :func:`write_run` (None: by ``samples``); only
            ``"7.3"`` is written in pieces

    Raises:
        OutputFileError: an unknown suffix, a ``.mat`` of version 5 (written whole by
            :func:`write_run`), ``samples`` < the first piece, or any error of
            :func:`write_run`.
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        first: RunRecord,
        samples: int | None = None,
        compression: str | None = None,
        mat_version: str | None = None,
    ) -> None:
        self.final = Path(path)
        self.samples = first.n_samples if samples is None else int(samples)
        self._mat = _check_output(self.final, compression, mat_version) == ".mat"
        if self._mat and (mat_version or mat_version_for(self.samples)) != "7.3":
            raise OutputFileError(
                f"{self.final}: a MATLAB v5 file is written whole; allowed: .h5, .hdf5, "
                ".mat v7.3 (write_run writes .mat v5)"
            )
        if self._mat:
            check_mat73_compression(self.final, compression)
        if self.samples < first.n_samples:
            raise OutputFileError(
                f"{self.final}: a run of {self.samples} samples; allowed: at least the first "
                f"piece's {first.n_samples}"
            )
        self._first = first
        self._arrays = checked_arrays(self.final, first)
        self._encoded(first.attributes)  # refuse early, before any file
        self._compression = compression
        self._attributes: Mapping[str, Any] = first.attributes
        self._written = 0
        self._stack: contextlib.ExitStack | None = None
        self._stream: _Hdf5Stream | _Mat73Stream | None = None

    def _encoded(self, attributes: Mapping[str, Any]) -> list[tuple[str, Any]]:
        """The stored attributes: root attributes, or a ``.mat``'s ``attr_`` variables."""
        encoded = encode_attributes(self.final, attributes)
        return mat_attribute_variables(self.final, encoded) if self._mat else encoded

    def __enter__(self) -> RunFileWriter:
        stack = contextlib.ExitStack()
        temporary = stack.enter_context(atomic_output(self.final))
        try:
            stream = _Mat73Stream if self._mat else _Hdf5Stream
            self._stream = stream(
                temporary, self._first, self._arrays, self.samples, self._compression
            )
        except BaseException as exc:
            stack.__exit__(type(exc), exc, exc.__traceback__)
            if isinstance(exc, OSError):
                raise OutputFileError(
                    f"{self.final}: cannot be written ({first_line(exc)})"
                ) from None
            raise
        self._stack = stack
        self._arrays = {}  # the first piece's copies are not needed again
        return self

    def write(self, start: int, chunk: RunRecord) -> None:
        """Store the series of one piece: samples ``start`` … ``start + chunk.n_samples - 1``.

        Args:
            start: the index of the piece's first sample; pieces come in time order, each
                starting where the last ended
            chunk: the piece (the same joints and IMUs as the first)

        Raises:
            OutputFileError: the writer is not open, a piece out of order or past the run's
                end, of other joints or IMUs, or a write failure.
        """
        if self._stream is None:
            raise OutputFileError(f"{self.final}: the writer is not open; allowed: inside with")
        n = chunk.n_samples
        if start != self._written or start + n > self.samples:
            raise OutputFileError(
                f"{self.final}: piece of {n} samples at sample {start}; allowed: the next "
                f"piece, at sample {self._written}, ending by sample {self.samples}"
            )
        expected = record_shapes(n, len(self._first.joint_names), len(self._first.imu_mounts))
        arrays = {}
        for name in SERIES:
            data = np.ascontiguousarray(getattr(chunk, name), dtype=np.float64)
            if data.shape != expected[name]:
                raise OutputFileError(
                    f"{self.final}: piece array {name!r} has shape {data.shape}; "
                    f"allowed: {expected[name]} (the first piece's joints and IMUs)"
                )
            arrays[name] = data
        try:
            self._stream.write(start, arrays)
        except OSError as exc:
            raise OutputFileError(f"{self.final}: cannot be written ({first_line(exc)})") from None
        self._written += n
        self._attributes = chunk.attributes

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        stream, stack = self._stream, self._stack
        self._stream, self._stack = None, None
        if stream is None or stack is None:
            return
        error: BaseException | None = exc
        try:
            attributes = None
            if exc is None and self._written != self.samples:
                error = OutputFileError(
                    f"{self.final}: {self._written} of {self.samples} samples written; "
                    "allowed: every sample of the run"
                )
            elif exc is None:
                attributes = self._encoded(self._attributes)
            stream.close(attributes)
        except BaseException as caught:
            if error is None:
                error = caught
                if isinstance(caught, OSError):
                    error = OutputFileError(
                        f"{self.final}: cannot be written ({first_line(caught)})"
                    )
        if error is None:
            stack.close()  # renames the file onto its destination
            return
        stack.__exit__(type(error), error, error.__traceback__)
        if error is not exc:
            raise error


def read_run(path: str | os.PathLike[str]) -> RunRecord:
    """Read any run file: written by :func:`write_run`, or by aaria_pin 0.1.0 (every kind).

    Shapes are restored from the known layout, so a ``.mat`` file re-saved by MATLAB (or a
    one-sample run) gives back the record's shapes.

    Args:
        path: the run file

    Returns:
        The run record, attributes decoded as described in the module docstring.

    Raises:
        InputFileError: the file is missing, unreadable, of an unknown kind, not a run file,
            of a newer format version, or holds an array of the wrong shape.
    """
    return _read(path, series=True)


def read_run_inputs(path: str | os.PathLike[str]) -> RunRecord:
    """The record of a run file without its time series: what re-making the run needs.

    A version 2 file's series and views are not read (a 2,000,000-sample ``.h5`` holds
    2.4 GB of them); the record has no samples (``n_samples == 0``, every series of length
    0) and the file's names, IMU mounts, URDF, tables, views and attributes (``duration``,
    ``rate``, ``seed``, ...). A 0.1.0 file, whose inputs partly live in its series (a wrist
    run's time grid), is read whole, as by :func:`read_run`.

    Args:
        path: the run file

    Raises:
        InputFileError: as :func:`read_run`.
    """
    return _read(path, series=False)


def _read(path: str | os.PathLike[str], series: bool) -> RunRecord:
    """:func:`read_run` (``series``) or :func:`read_run_inputs`."""
    file = existing_input(path, RUN_SUFFIXES, "run")
    if file.suffix.lower() == ".mat":
        variables = mat_variables(file)
        marks = [name for name in variables if name.startswith(MAT_ATTRIBUTE_PREFIX)]
        layout = mat_layout(file, load_mat(file, marks) if marks else {}, variables)
        if layout != LAYOUT_V2:
            return read_legacy_mat(file, load_mat(file), layout)
        views = [name for name in variables if name + COLUMNS_SUFFIX in variables]
        skipped = set(views) if series else {*views, *SERIES}
        contents = load_mat(file, [name for name in variables if name not in skipped])
        contents.update(dict.fromkeys(views))  # a view is read from its column names
        return _read_mat_v2(file, contents, None if series else variables)
    import h5py

    with _hdf5_errors(file), h5py.File(file, "r") as handle:
        layout = hdf5_layout(file, handle)
        if layout == LAYOUT_V2:
            return _read_hdf5_v2(file, handle, series)
        return read_legacy_hdf5(file, handle, layout)


def run_file_summary(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Describe a run file (for ``aaria info``); a version 2 file's arrays are not read.

    Args:
        path: the run file (any kind :func:`read_run` reads)

    Returns:
        ``path`` (str), ``format`` (``"HDF5"``, ``"MATLAB v5"`` or ``"MATLAB v7.3"``),
        ``format_version`` (int; 1 for every 0.1.0 file), ``layout`` (``"aaria_pin run"`` or
        the 0.1.0 layout, e.g. ``"0.1.0 wrist run"``), ``kind``, ``robot``, ``samples`` (T),
        ``rate`` [Hz] (the attribute, else from the first two sample times; None for one
        sample), ``joints`` and
        ``imus`` (names), ``arrays`` (name → shape, as :func:`read_run` gives them: the series,
        ``imu_mount`` and the tables), ``views`` (name → shape) and ``attributes`` (decoded as
        by :func:`read_run`).

    Raises:
        InputFileError: as :func:`read_run`.
    """
    file = existing_input(path, RUN_SUFFIXES, "run")
    time_head: Any
    if file.suffix.lower() == ".mat":
        kind = "MATLAB v7.3" if is_mat73(file) else "MATLAB v5"
        variables = mat_variables(file)
        small = [
            name
            for name in variables
            if name.startswith(MAT_ATTRIBUTE_PREFIX)
            or name in NAME_LISTS
            or name.endswith(COLUMNS_SUFFIX)
        ]
        contents = load_mat(file, small) if small else {}
        layout = mat_layout(file, contents, variables)
        if layout == LAYOUT_V2:
            parts = _summarise_mat_v2(file, variables, contents)
            time_head = (
                load_mat(file, ["time"])["time"] if "rate" not in parts["attributes"] else None
            )
        else:
            parts = _record_parts(read_legacy_mat(file, load_mat(file), layout))
            time_head = parts.pop("time")
    else:
        import h5py

        kind = "HDF5"
        with _hdf5_errors(file), h5py.File(file, "r") as handle:
            layout = hdf5_layout(file, handle)
            if layout == LAYOUT_V2:
                parts = _summarise_hdf5_v2(file, handle)
                time_head = handle["time"][:2] if handle["time"].ndim == 1 else None
            else:
                parts = _record_parts(read_legacy_hdf5(file, handle, layout))
                time_head = parts.pop("time")
    attributes = parts["attributes"]
    return {
        "path": str(file),
        "format": kind,
        "format_version": RUN_FORMAT_VERSION if layout == LAYOUT_V2 else 1,
        "layout": layout,
        "kind": attributes.get("kind"),
        "robot": attributes.get("robot"),
        "samples": parts["arrays"]["time"][0],
        "rate": _rate(attributes, time_head),
        **parts,
    }


def is_run_file(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is an existing run file :func:`read_run` reads (any version or kind).

    Only the file's marks and names are looked at, not its arrays; a data set is not a run file.
    """
    try:
        file = existing_input(path, RUN_SUFFIXES, "run")
        if file.suffix.lower() == ".mat":
            variables = mat_variables(file)
            attribute_names = [n for n in variables if n.startswith(MAT_ATTRIBUTE_PREFIX)]
            mat_layout(file, load_mat(file, attribute_names) if attribute_names else {}, variables)
            return True
        import h5py

        with _hdf5_errors(file), h5py.File(file, "r") as handle:
            hdf5_layout(file, handle)
        return True
    except InputFileError:
        return False


# --- helpers -------------------------------------------------------------------------------------


def _record_parts(record: RunRecord) -> dict[str, Any]:
    """The summary parts of a record read in full (a 0.1.0 file), plus its first sample times."""
    return {
        "joints": list(record.joint_names),
        "imus": list(record.imu_names),
        "arrays": {name: tuple(np.shape(array)) for name, array in record.arrays().items()},
        "views": {
            name: (record.n_samples, len(view.columns)) for name, view in record.views.items()
        },
        "attributes": record.attributes,
        "time": record.time[:2],
    }


def _rate(attributes: Mapping[str, Any], time_head: Any) -> float | None:
    """The sample rate [Hz]: the ``rate`` attribute, else from the first two sample times."""
    rate = attributes.get("rate")
    if isinstance(rate, (int, float)) and not isinstance(rate, bool):
        return float(rate)
    head = np.ravel(np.asarray(time_head, dtype=float)) if time_head is not None else np.empty(0)
    if head.size < 2 or not head[1] > head[0]:
        return None
    return float(round(1.0 / (head[1] - head[0]), 9))


def write_run_pieces(
    output: Path,
    chunks: Iterable[RunRecord],
    compression: str | None,
    announce: Callable[[RunRecord], None] | None = None,
    mat_version: str | None = None,
) -> tuple[RunRecord, int, float]:
    """Compute a run's pieces and write them: whole if one piece, else streamed.

    A run of one piece (:data:`~aaria_pin.core.run.CHUNK_SAMPLES` samples or fewer) is written
    by ``write_run`` as before (a ``.mat`` as v5); a longer one by ``write_run_chunks`` piece
    by piece into an HDF5 file or a ``.mat`` v7.3, so memory does not grow with its length.

    Args:
        output: the run file
        chunks: the run's pieces in time order (e.g. ``simulate_run_chunks``)
        compression: HDF5 filter (None, ``"gzip"``, ``"lzf"``)
        announce: called with the last piece (whose attributes cover the run) before a
            one-piece run is written, or after a streamed run is (for the command's warnings)
        mat_version: for a ``.mat``, as in :func:`write_run` (None: by the run's length)

    Returns:
        The last piece, the run's samples and its peak |tau| [N·m or N].
    """
    from aaria_pin.core.run import run_length

    pieces = iter(chunks)
    first = next(pieces)
    samples = run_length(first)
    if samples <= first.n_samples:
        if next(pieces, None) is not None:
            raise OutputFileError(
                f"{output}: the run's attributes give {samples} samples but it came in more "
                f"than one piece; allowed: pieces whose 'duration' and 'rate' cover the run"
            )
        if announce is not None:
            announce(first)
        write_run(output, first, compression=compression, mat_version=mat_version)
        return first, first.n_samples, float(np.abs(first.tau).max())
    peaks: list[float] = []
    last = [first]

    def counted() -> Iterator[RunRecord]:
        for piece in itertools.chain([first], pieces):
            peaks.append(float(np.abs(piece.tau).max()))
            last[0] = piece
            yield piece

    write_run_chunks(output, counted(), samples, compression, mat_version)
    if announce is not None:
        announce(last[0])
    return last[0], samples, max(peaks)
