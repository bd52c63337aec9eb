"""Writing run files: whole (:func:`write_run`) or in time pieces (:class:`RunFileWriter`).

The layout of both formats is described in :mod:`aaria_pin.files.runfile`.
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

from aaria_pin.core.arguments import checked
from aaria_pin.core.record import SERIES, RunRecord, record_shapes
from aaria_pin.errors import OutputFileError
from aaria_pin.files._space import check_space
from aaria_pin.files._stored import encode_attributes
from aaria_pin.files.detection import RUN_SUFFIXES
from aaria_pin.files.paths import atomic_output, no_space, write_failure
from aaria_pin.files.runfile._attributes import NOT_RECORD_ATTRIBUTES
from aaria_pin.files.runfile._checksums import CHECKSUMS_ATTRIBUTE, Checksums
from aaria_pin.files.runfile._columns import RunStream, checked_arrays
from aaria_pin.files.runfile._hdf5 import _Hdf5Stream
from aaria_pin.files.runfile._mat import _mat_contents, _write_mat, mat_attribute_variables
from aaria_pin.files.runfile._mat73 import _Mat73Stream, check_mat73_compression

COMPRESSIONS = (None, "gzip", "lzf")
"""HDF5 filters :func:`write_run` offers for the time series (None: uncompressed)."""

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
            f"compression {compression!r} is not allowed; allowed: None, 'gzip', 'lzf'",
            parameter="compression",
        )
    if suffix not in RUN_SUFFIXES:
        raise OutputFileError(
            f"{final}: unknown run file type {suffix!r}; allowed: {', '.join(RUN_SUFFIXES)}",
            parameter="path",
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


@checked
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
    checksums = Checksums()
    for name, data in arrays.items():
        checksums.update(name, data)
    attributes = encode_attributes(final, record.attributes, NOT_RECORD_ATTRIBUTES)
    attributes.append((CHECKSUMS_ATTRIBUTE, checksums.attribute()))
    contents = _mat_contents(final, record, arrays, attributes)
    with atomic_output(final) as temporary:
        try:
            _write_mat(temporary, contents)
        except OSError as exc:
            raise write_failure(final, exc) from None
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
        raise OutputFileError(
            f"{final}: a run of no piece; allowed: one piece or more", parameter="chunks"
        )
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
                ".mat v7.3 (write_run writes .mat v5)",
                parameter="mat_version",
            )
        if self._mat:
            check_mat73_compression(self.final, compression)
        if self.samples < first.n_samples:
            raise OutputFileError(
                f"{self.final}: a run of {self.samples} samples; allowed: at least the first "
                f"piece's {first.n_samples}",
                parameter="samples",
            )
        self._first = first
        from aaria_pin.core.run.sensor import is_sensor_table

        self._arrays = checked_arrays(self.final, first)
        self._sensors = [name for name in first.tables if is_sensor_table(name)]
        self._checksums = Checksums()  # of the inputs now, of the series piece by piece
        for name, data in self._arrays.items():
            if name not in SERIES and name not in self._sensors:
                self._checksums.update(name, data)
        for name in self._sensors:  # laid out at the run's length, filled piece by piece
            columns = self._arrays[name].shape[1]
            self._arrays[name] = np.zeros((self.samples, columns))
        self._encoded(first.attributes)  # refuse early, before any file
        self._compression = compression
        self._attributes: Mapping[str, Any] = first.attributes
        self._written = 0
        self._stack: contextlib.ExitStack | None = None
        self._stream: RunStream | None = None

    def _encoded(
        self, attributes: Mapping[str, Any], checksums: str | None = None
    ) -> list[tuple[str, Any]]:
        """The stored attributes: root attributes, or a ``.mat``'s ``attr_`` variables.

        Args:
            attributes: the record's attributes
            checksums: the ``checksums`` attribute, stored after them (None: left out)
        """
        encoded = encode_attributes(self.final, attributes, NOT_RECORD_ATTRIBUTES)
        if checksums is not None:
            encoded.append((CHECKSUMS_ATTRIBUTE, checksums))
        return mat_attribute_variables(self.final, encoded) if self._mat else encoded

    def _size(self) -> int:
        """The bytes the file's data take [bytes].

        Its series at full length, its tables, views (real arrays in a ``.mat``), names and
        URDF. An uncompressed file is that plus its metadata
        (:data:`~aaria_pin.files._space.METADATA_BYTES` at most), checked before the file is
        made; a compressed one is checked against it too, as a bound: its series are held in
        HDF5's chunk cache until the file is closed, and a full device met there (measured:
        "Can't destroy cache (slist already enabled?)") leaves identifiers no close can end.
        """
        total = len(self._first.urdf.encode("utf-8"))
        total += sum(len(name) + 8 for name in (*self._first.joint_names, *self._first.imu_names))
        for name, data in self._arrays.items():
            row = data.itemsize * int(np.prod(data.shape[1:], dtype=np.int64))
            total += row * self.samples if name in SERIES else data.nbytes
        if self._mat:
            views = self._first.views.values()
            total += sum(8 * len(view.columns) * self.samples for view in views)
        return int(total)

    def __enter__(self) -> RunFileWriter:
        check_space(self.final, self._size())  # a full device refused before any work
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
                raise write_failure(self.final, exc) from None
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
            raise OutputFileError(
                f"{self.final}: the writer is not open; allowed: inside with", parameter="start"
            )
        n = chunk.n_samples
        if start != self._written or start + n > self.samples:
            raise OutputFileError(
                f"{self.final}: piece of {n} samples at sample {start}; allowed: the next "
                f"piece, at sample {self._written}, ending by sample {self.samples}",
                parameter="start",
            )
        expected = record_shapes(n, len(self._first.joint_names), len(self._first.imu_mounts))
        arrays = {}
        for name in SERIES:
            data = np.ascontiguousarray(getattr(chunk, name), dtype=np.float64)
            if data.shape != expected[name]:
                raise OutputFileError(
                    f"{self.final}: piece array {name!r} has shape {data.shape}; "
                    f"allowed: {expected[name]} (the first piece's joints and IMUs)",
                    parameter="chunk",
                )
            arrays[name] = data
        try:
            self._stream.write(start, arrays)
            for name in self._sensors:
                self._write_sensor(name, start, chunk.tables.get(name), n)
            for name, data in arrays.items():
                self._checksums.update(name, data)
        except OSError as exc:
            raise write_failure(self.final, exc) from None
        self._written += n
        self._attributes = chunk.attributes

    def _write_sensor(self, name: str, start: int, rows: Any, n: int) -> None:
        """Store a piece's rows of the sensor table ``name`` (T × columns).

        A ``.mat`` stores it transposed (MATLAB's column-major order).
        """
        assert self._stream is not None
        dataset = self._stream.handle[name]
        columns = dataset.shape[0] if self._mat else dataset.shape[1]
        data = np.asarray(rows, dtype=np.float64) if rows is not None else None
        if data is None or data.shape != (n, columns):
            raise OutputFileError(
                f"{self.final}: piece table {name!r} has shape "
                f"{None if data is None else data.shape}; allowed: ({n}, {columns})",
                parameter="chunk",
            )
        if self._mat:
            dataset[:, start : start + n] = data.T
        else:
            dataset[start : start + n] = data
        self._checksums.update(name, data)

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
                    "allowed: every sample of the run",
                    parameter="path",
                )
            elif exc is None:
                attributes = self._encoded(self._attributes, self._checksums.attribute())
            stream.close(attributes)
        except BaseException as caught:
            if error is None:
                error = caught
                if isinstance(caught, OSError) or no_space(caught):
                    error = write_failure(self.final, caught)
        if error is None:
            stack.close()  # renames the file onto its destination
            return
        stack.__exit__(type(error), error, error.__traceback__)
        if error is not exc:
            raise error


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
                f"than one piece; allowed: pieces whose 'duration' and 'rate' cover the run",
                parameter="chunks",
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
