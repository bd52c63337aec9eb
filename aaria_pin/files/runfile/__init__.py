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

Every numeric array (the series, ``imu_mount``, the tables) has a checksum: the root attribute
``checksums`` (``attr_checksums`` in a ``.mat``) maps each name to ``"crc32:<hex>"``, the CRC-32 of
its values (:mod:`._checksums`). :func:`read_run` verifies every array it reads, then checks the
record (:func:`aaria_pin.core.record_checks.check_record`: the kind's tables, the attributes'
types, finite values); a file of 0.3.0 or earlier (no checksums) reads with an
:class:`UnverifiedFileWarning`. A damaged file is one line: an :class:`InputFileError`
(:class:`~aaria_pin.files._stored.DamagedFileError` when HDF5 or scipy cannot read it).

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

:func:`read_run` also reads every run file aaria_pin 0.1.0 wrote (:mod:`._legacy_runs`: Aaria DH
``.h5``/``.mat``, URDF robot and pick-place ``.h5``, wrist ``.h5``/``.mat``).

A recorded run (``kind = "recorded"``, what ``aaria import`` writes: measured signals, each
sensor at its own time stamps, no truth) is read by :func:`read_recorded_run` and written by
:func:`write_recorded_run` (:mod:`._recorded`); :func:`read_run` refuses it in one line.
"""

from aaria_pin.files._stored import JSON_SUFFIX
from aaria_pin.files.detection import RUN_SUFFIXES
from aaria_pin.files.runfile._attributes import RUN_FORMAT, RUN_FORMAT_VERSION
from aaria_pin.files.runfile._checksums import CHECKSUMS_ATTRIBUTE, UnverifiedFileWarning
from aaria_pin.files.runfile._columns import column_source, view_from_columns
from aaria_pin.files.runfile._legacy_runs import URDF_V1_FORMAT
from aaria_pin.files.runfile._read import is_run_file, read_run, read_run_inputs, run_file_summary
from aaria_pin.files.runfile._recorded import (
    RECORDED_KIND,
    is_recorded_file,
    read_recorded_run,
    recorded_summary,
    stream_line,
    stream_summary,
    write_recorded_run,
)
from aaria_pin.files.runfile._write import (
    COMPRESSIONS,
    MAT_VERSIONS,
    RunFileWriter,
    mat_version_for,
    write_run,
    write_run_chunks,
    write_run_pieces,
)

__all__ = [
    "CHECKSUMS_ATTRIBUTE",
    "COMPRESSIONS",
    "JSON_SUFFIX",
    "MAT_VERSIONS",
    "RECORDED_KIND",
    "RUN_FORMAT",
    "RUN_FORMAT_VERSION",
    "RUN_SUFFIXES",
    "URDF_V1_FORMAT",
    "RunFileWriter",
    "UnverifiedFileWarning",
    "column_source",
    "is_recorded_file",
    "is_run_file",
    "mat_version_for",
    "read_recorded_run",
    "read_run",
    "read_run_inputs",
    "recorded_summary",
    "run_file_summary",
    "stream_line",
    "stream_summary",
    "view_from_columns",
    "write_recorded_run",
    "write_run",
    "write_run_chunks",
    "write_run_pieces",
]
