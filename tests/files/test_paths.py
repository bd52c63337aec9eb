"""Output paths (``files/paths.py``): over-long names and the error of a failed write."""

from __future__ import annotations

import errno
from pathlib import Path

import pytest

from aaria_pin.errors import NoSpaceError, OutputFileError
from aaria_pin.files.paths import check_name_lengths, check_output, write_failure


@pytest.mark.parametrize(
    "parts",
    [("a" * 300, "x.urdf"), ("ok", "b" * 256, "run.h5"), ("c" * 300 + ".h5",)],
    ids=["folder", "inner folder", "file"],
)
def test_a_name_over_the_limit_is_one_line_wherever_it_is(
    tmp_path: Path, parts: tuple[str, ...]
) -> None:
    path = tmp_path.joinpath(*parts)
    for check in (check_name_lengths, check_output):
        with pytest.raises(
            OutputFileError, match=r"is a name of \d+ bytes; allowed: at most 255"
        ) as raised:
            check(path)
        assert "\n" not in str(raised.value) and raised.value.parameter == "path"
    assert list(tmp_path.iterdir()) == []


def test_a_path_over_path_max_is_refused(tmp_path: Path) -> None:
    path = tmp_path.joinpath(*["d" * 200] * 25, "x.h5")  # every name fine, 5000+ bytes in all
    with pytest.raises(OutputFileError, match=r"is a path of \d+ bytes; allowed: at most 4095"):
        check_name_lengths(path)


def test_names_at_the_limit_pass(tmp_path: Path) -> None:
    check_name_lengths(tmp_path / ("a" * 255) / ("b" * 252 + ".h5"))


def test_write_failure_tells_a_full_device_from_other_errors(tmp_path: Path) -> None:
    final = tmp_path / "run.h5"
    full = write_failure(final, OSError(errno.ENOSPC, "Can't write data\nmore lines"))
    assert isinstance(full, NoSpaceError)
    assert str(full) == f"no space left on device writing {final}; nothing was replaced"
    other = write_failure(final, OSError(errno.EIO, "Can't write data\nmore lines"))
    assert type(other) is OutputFileError
    assert str(other) == f"{final}: cannot be written ([Errno 5] Can't write data)"


def test_an_output_on_a_device_all_but_full_is_refused_before_the_lock(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import shutil

    from aaria_pin.files import _space
    from aaria_pin.files.paths import atomic_output

    usage = shutil.disk_usage(tmp_path)
    low = type(usage)(usage.total, usage.used, _space.METADATA_BYTES - 1)
    monkeypatch.setattr(_space.shutil, "disk_usage", lambda _: low)
    with (
        pytest.raises(NoSpaceError, match="nothing was replaced"),
        atomic_output(tmp_path / "a.h5"),
    ):
        pytest.fail("the block must not run")
    assert list(tmp_path.iterdir()) == []
