"""A real run file, damaged or edited in one way at a time, is refused in one line everywhere.

The run is made by ``aaria simulate`` (0.2 s at 100 Hz). Each mutation (an array deleted, of
text or of another shape, a text ``rate``, an unknown ``kind``, broken JSON, NaN or inf in a
series with its checksum made to match, a stale checksum, flipped bytes, a truncated file) is
read by :func:`open_record` (one-line :class:`InputFileError` naming the file) and by
``aaria torques``, ``aaria plot`` and ``aaria identify`` (exit 2, one ``aaria: error:`` line on
stderr, no traceback, nothing written).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import zlib
from collections.abc import Callable
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.cli import main
from aaria_pin.errors import InputFileError
from aaria_pin.files.source import open_record


def _refresh_checksum(handle: Any, name: str) -> None:
    """Make the stored checksum of ``name`` match its (edited) values."""
    sums = json.loads(handle.attrs["checksums"])
    values = np.ascontiguousarray(handle[name][()], dtype="<f8")
    sums[name] = f"crc32:{zlib.crc32(values.tobytes()):08x}"
    handle.attrs["checksums"] = json.dumps(sums)


def _replace(handle: Any, name: str, data: Any) -> None:
    del handle[name]
    handle[name] = data


def _nan_in_tau(handle: Any) -> None:
    handle["tau"][17, 2] = np.nan
    _refresh_checksum(handle, "tau")


def _inf_in_imu(handle: Any) -> None:
    handle["imu"][3, 4, 1] = np.inf
    _refresh_checksum(handle, "imu")


def _flip_in_tau(path: Path) -> None:
    with h5py.File(path, "r") as handle:
        offset = handle["tau"].id.get_offset()
    with path.open("r+b") as stream:
        stream.seek(offset + 45)
        byte = stream.read(1)[0]
        stream.seek(offset + 45)
        stream.write(bytes([byte ^ 0x01]))


def _truncate(path: Path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


HDF5_MUTATIONS: dict[str, tuple[Callable[[Any], None], str]] = {
    "table deleted": (
        lambda h: h.__delitem__("senSenDH"),
        r"array senSenDH is missing; allowed: a dh run file has senSenDH, senSenJ, senSenB",
    ),
    "series deleted": (lambda h: h.__delitem__("time"), r"no dataset 'time'"),
    "other table deleted": (
        lambda h: h.__delitem__("senSenB"),
        r"array senSenB is missing; allowed: a dh run file has",
    ),
    "text series": (
        lambda h: _replace(h, "tau", h["tau"][()].astype("S8")),
        r"array tau is of type \|S8; allowed: numbers",
    ),
    "bool table": (
        lambda h: _replace(h, "senSenJ", h["senSenJ"][()] > 0),
        r"array senSenJ is of type bool; allowed: numbers",
    ),
    "short series": (
        lambda h: _replace(h, "tau", h["tau"][:-1]),
        r"array 'tau' has shape \(20, 6\); expected \(21, 6\)",
    ),
    "text rate": (
        lambda h: h.attrs.__setitem__("rate", "100"),
        r"attribute 'rate' is '100'; allowed: a positive number",
    ),
    "negative duration": (
        lambda h: h.attrs.__setitem__("duration", -3.0),
        r"attribute 'duration' is -3\.0; allowed: a positive number",
    ),
    "bogus kind": (
        lambda h: h.attrs.__setitem__("kind", "bogus"),
        r"attribute 'kind' is 'bogus'; allowed: dh, urdf, wrist, pick-place",
    ),
    "broken JSON": (
        lambda h: h.attrs.__setitem__("noise_parameters_json", "{broken"),
        r"attribute 'noise_parameters_json' is not valid JSON",
    ),
    "NaN in tau": (_nan_in_tau, r"tau has NaN at sample 17, joint 2; allowed: finite values"),
    "inf in imu": (
        _inf_in_imu,
        r"imu has inf at sample 3, IMU 4, signal 1; allowed: finite values",
    ),
    "stale checksum": (
        lambda h: h["qd"].__setitem__((5, 0), 1e9),
        r"array qd is damaged \(checksum crc32:[0-9a-f]{8}, stored crc32:[0-9a-f]{8}\)",
    ),
}
"""Edits through h5py: (edit of the open file, the pattern of the one line)."""

FILE_MUTATIONS: dict[str, tuple[Callable[[Path], None], str]] = {
    "flipped byte": (_flip_in_tau, r"array tau is damaged \(checksum"),
    "truncated": (_truncate, r"is damaged \(Unable to synchronously open file \(truncated"),
}
"""Edits of the file's bytes."""

MAT_MUTATIONS: dict[str, tuple[Callable[[Path], None], str]] = {
    "truncated .mat": (_truncate, r"run\.mat is damaged \(its variables end at byte \d+"),
    "flipped .mat": (
        lambda p: p.write_bytes(
            p.read_bytes()[:3000]
            + bytes(b ^ 0x55 for b in p.read_bytes()[3000:3100])
            + p.read_bytes()[3100:]
        ),
        r"run\.mat is damaged \(",
    ),
}
"""Edits of a ``.mat`` run file's bytes (inside its compressed variables)."""


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("runs")
    for name in ("run.h5", "run.mat"):
        result = CliRunner().invoke(
            main,
            [
                *("simulate", "--preset", "aaria-fig2", "--duration", "0.2", "--rate", "100"),
                *("-o", str(folder / name)),
            ],
        )
        assert result.exit_code == 0, result.output
    return folder


def _mutated(runs: Path, folder: Path, case: str) -> tuple[Path, str]:
    """A copy of the run with one mutation, and the pattern its one-line error matches."""
    if case in MAT_MUTATIONS:
        path = folder / "run.mat"
        shutil.copy(runs / "run.mat", path)
        edit, pattern = MAT_MUTATIONS[case]
        edit(path)
        return path, pattern
    path = folder / "run.h5"
    shutil.copy(runs / "run.h5", path)
    if case in FILE_MUTATIONS:
        file_edit, pattern = FILE_MUTATIONS[case]
        file_edit(path)
        return path, pattern
    edit, pattern = HDF5_MUTATIONS[case]
    with h5py.File(path, "r+") as handle:
        edit(handle)
    return path, pattern


CASES = [*HDF5_MUTATIONS, *FILE_MUTATIONS, *MAT_MUTATIONS]


@pytest.mark.parametrize("case", CASES)
def test_the_reader_refuses_the_mutation_in_one_line(runs: Path, tmp_path: Path, case: str) -> None:
    path, pattern = _mutated(runs, tmp_path, case)
    with pytest.raises(InputFileError) as error:
        open_record(path)
    message = str(error.value)
    assert message.startswith(str(path)) and "\n" not in message, message
    assert re.search(pattern, message), message
    assert error.value.parameter == "file"


@pytest.mark.parametrize("case", CASES)
def test_every_analysis_command_exits_2_in_one_line_and_writes_nothing(
    runs: Path, tmp_path: Path, case: str
) -> None:
    path, pattern = _mutated(runs, tmp_path, case)
    old = Path.cwd()
    os.chdir(tmp_path)
    try:
        for argv in (
            ["torques", path.name],
            ["plot", path.name, "-o", "x.png"],
            ["identify", path.name],
        ):
            before = sorted(os.listdir(tmp_path))
            result = CliRunner().invoke(main, argv)
            lines = result.stderr.splitlines()
            assert result.exit_code == 2, (argv, result.output, result.exception)
            assert isinstance(result.exception, SystemExit), result.exception
            assert len(lines) == 1 and lines[0].startswith("aaria: error: "), result.stderr
            assert re.search(pattern, lines[0]), (argv, lines[0])
            assert "Traceback" not in result.output
            assert sorted(os.listdir(tmp_path)) == before
    finally:
        os.chdir(old)


def test_the_unmutated_run_reads_and_its_commands_succeed(runs: Path, tmp_path: Path) -> None:
    for name in ("run.h5", "run.mat"):
        record = open_record(runs / name)
        assert record.n_samples == 21 and np.isfinite(record.tau).all()
        result = CliRunner().invoke(main, ["torques", str(runs / name)])
        assert result.exit_code == 0, result.output


def test_a_damaged_run_file_is_neither_a_run_file_nor_another_file(
    runs: Path, tmp_path: Path
) -> None:
    from aaria_pin.files._stored import DamagedFileError
    from aaria_pin.files.runfile import is_run_file

    for case in ("truncated", "truncated .mat", "flipped .mat"):
        path, pattern = _mutated(runs, tmp_path, case)
        with pytest.raises(DamagedFileError, match=pattern):
            is_run_file(path)
    text = tmp_path / "text.h5"
    text.write_text("not HDF5\n")
    assert not is_run_file(text) and is_run_file(runs / "run.h5")
