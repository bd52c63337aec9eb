from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.aaria.presets import get_preset
from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset, simulate_dataset_run
from aaria_pin.apps.remake import remake_record
from aaria_pin.cli import main
from aaria_pin.core.record import RunRecord
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.reader import DatasetReader

SHORT = {"duration": 0.5, "rate": 100.0}


def _arrays(path: Path) -> dict[str, np.ndarray]:
    with DatasetReader(path) as reader:
        names = reader.names  # the stored arrays and the views (senSen, signals)
    with h5py.File(path, "r") as handle:
        return {name: handle[name][()] for name in (*names, "complete", "failed")}


def _assert_same(a: Path, b: Path) -> None:
    left, right = _arrays(a), _arrays(b)
    for name in left:
        np.testing.assert_array_equal(left[name], right[name], err_msg=name)


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("ref") / "ref.h5"
    generate_dataset(path, DhDatasetSpec(n_runs=24, seed=7, **SHORT), workers=1)
    return path


def test_workers_do_not_change_the_arrays(reference: Path, tmp_path: Path) -> None:
    generate_dataset(tmp_path / "two.h5", DhDatasetSpec(n_runs=24, seed=7, **SHORT), workers=2)
    _assert_same(reference, tmp_path / "two.h5")
    assert _arrays(reference)["complete"].all()


def test_run_k_is_a_pure_function_of_seed_and_k(reference: Path) -> None:
    spec = DhDatasetSpec(n_runs=24, seed=7, **SHORT)
    with DatasetReader(reference) as reader:
        for k in (0, 13, 23):
            direct = simulate_dataset_run(spec, k)
            for name, array in reader.run(k).items():
                np.testing.assert_array_equal(array, direct[name])
    other = simulate_dataset_run(DhDatasetSpec(n_runs=24, seed=8, **SHORT), 0)
    assert not np.array_equal(simulate_dataset_run(spec, 0)["senSenDH"], other["senSenDH"])


def test_fixed_arm_many_trajectories(tmp_path: Path) -> None:
    preset = get_preset("aaria-fig3")
    spec = DhDatasetSpec(n_runs=5, seed=1, vary=("joints", "base"), dh_table=preset.table, **SHORT)
    generate_dataset(tmp_path / "mode2.h5", spec, workers=1)
    with DatasetReader(tmp_path / "mode2.h5") as reader:
        for k in range(5):
            run = reader.run(k, ("senSenDH", "senSen"))
            np.testing.assert_array_equal(run["senSenDH"], preset.table)
            assert not run["senSen"][:, 2].any()  # module 2 is empty
        assert not np.array_equal(reader.run(0)["senSenJ"], reader.run(1)["senSenJ"])


def test_reader_windows(reference: Path) -> None:
    with DatasetReader(reference) as reader:
        assert len(reader) == 24 and reader.samples == 51
        windows = list(reader.windows(20, stride=10, names=("senSen", "tau")))
        assert len(windows) == 24 * 4  # starts 0, 10, 20, 30
        run, start, window = windows[5]
        assert (run, start) == (1, 10)
        np.testing.assert_array_equal(window["senSen"], reader.run(1, ("senSen",))["senSen"][10:30])
        assert window["tau"].shape == (20, 6)
        with pytest.raises(ParameterError, match="run 24"):
            reader.run(24)


def test_half_written_and_corrupted_runs_are_redone(reference: Path, tmp_path: Path) -> None:
    path = tmp_path / "damaged.h5"
    path.write_bytes(reference.read_bytes())
    with h5py.File(path, "r+") as handle:
        handle["complete"][3] = 0  # half-written: never marked complete
        handle["imu"][3] = 0.0
        info = handle["imu"].id.get_chunk_info_by_coord((9, 0, 0, 0))
    with open(path, "r+b") as raw:  # a damaged chunk: its checksum no longer matches
        raw.seek(info.byte_offset + info.size // 2)
        raw.write(b"\xff" * 16)
    with pytest.raises(OSError):
        _arrays(path)
    report = generate_dataset(
        path, DhDatasetSpec(n_runs=24, seed=7, **SHORT), workers=1, resume=True
    )
    assert report.written == 2
    _assert_same(reference, path)


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGINT])
def test_killed_job_resumes_to_the_uninterrupted_result(tmp_path: Path, sig: int) -> None:
    args = [
        "-n",
        "600",
        "--seed",
        "3",
        "--duration",
        "2",
        "--rate",
        "100",
        "--workers",
        "2",
        "--quiet",
    ]
    uninterrupted = tmp_path / "full.h5"
    assert CliRunner().invoke(main, ["dataset", *args, "-o", str(uninterrupted)]).exit_code == 0
    # The kill must land mid-way: some runs flagged complete, not all. How long that takes
    # depends on the machine's load, so the wait after the file appears adapts and is retried.
    wait, redone = 0.8, -1
    for attempt in range(4):
        killed = tmp_path / f"killed{attempt}.h5"
        process = subprocess.Popen(
            [sys.executable, "-m", "aaria_pin.cli", "dataset", *args, "-o", str(killed)],
            start_new_session=True,
        )
        deadline = time.monotonic() + 120
        while not killed.exists() and time.monotonic() < deadline:  # the file is laid out
            time.sleep(0.02)
        time.sleep(wait)  # some runs are written, most are not
        os.killpg(process.pid, sig)
        process.wait()
        result = CliRunner().invoke(main, ["dataset", *args, "-o", str(killed), "--resume"])
        assert result.exit_code == 0, result.output
        redone = int(result.stdout.split("(")[1].split()[0])
        if 0 < redone < 600:
            break
        wait = wait * 2 if redone == 600 else wait / 2
    assert 0 < redone < 600, result.stdout  # the kill landed mid-way
    _assert_same(uninterrupted, killed)


def test_failing_runs_are_reported_and_the_others_go_on(tmp_path: Path) -> None:
    joints = np.zeros((8, 5))
    joints[:6] = [0.5, 0.2, 0.0, 1.0, 0.0]  # 0.2 m off a rail of d <= 0.3 m: prismatic runs fail
    path = tmp_path / "failing.h5"
    np.savetxt(tmp_path / "j.csv", joints, delimiter=",")
    result = CliRunner().invoke(
        main,
        [
            "dataset",
            "-n",
            "12",
            "--seed",
            "2",
            "--duration",
            "0.5",
            "--vary",
            "structure,base",
            "--joints",
            str(tmp_path / "j.csv"),
            "--workers",
            "1",
            "-o",
            str(path),
        ],
    )
    assert result.exit_code == 1
    with DatasetReader(path) as reader:
        failed = sorted(reader.attributes["failures"])
        assert failed and len(failed) < 12
        assert reader.complete.sum() == 12 - len(failed)
    assert "failed runs:" in result.stderr and "prismatic module" in result.stderr


def test_resume_with_other_settings_is_refused(reference: Path, tmp_path: Path) -> None:
    path = tmp_path / "copy.h5"
    path.write_bytes(reference.read_bytes())
    with pytest.raises(ParameterError, match="other settings \\(seed\\)"):
        generate_dataset(path, DhDatasetSpec(n_runs=24, seed=8, **SHORT), resume=True)


@pytest.mark.parametrize(
    ("args", "pattern"),
    [
        (["-n", "-3"], "-n is -3"),
        (["-n", "0"], "-n is 0"),
        (["-n", "2", "--config", "CONFIG_UNKNOWN"], "unknown key 'speed'"),
        (["-n", "2", "--config", "CONFIG_EMPTY"], "allowed: a range"),
        (["-n", "2", "--config", "MISSING"], "no such file"),
        (["-n", "2", "--vary", "structure,colour"], "a part of --vary is 'colour'"),
        (["-n", "2", "--vary", "joints"], "needs --preset or --dh"),
        (["-n", "2", "--dtype", "float16"], "'float16' is not one of"),
    ],
)
def test_bad_input_exit_2_and_no_file(tmp_path: Path, args: list[str], pattern: str) -> None:
    (tmp_path / "unknown.toml").write_text("speed = [1, 2]\n")
    (tmp_path / "empty.toml").write_text("d = [0.3, 0.1]\n")
    names = {
        "CONFIG_UNKNOWN": "unknown.toml",
        "CONFIG_EMPTY": "empty.toml",
        "MISSING": "missing.toml",
    }
    args = [str(tmp_path / names[a]) if a in names else a for a in args]
    result = CliRunner().invoke(main, ["dataset", *args, "-o", str(tmp_path / "ds.h5")])
    assert result.exit_code == 2, result.output
    assert pattern in result.stderr and result.stderr.count("\n") == 1
    assert not (tmp_path / "ds.h5").exists()


def test_existing_output_is_not_touched(reference: Path, tmp_path: Path) -> None:
    path = tmp_path / "existing.h5"
    path.write_bytes(reference.read_bytes())
    before = (path.stat().st_mtime_ns, path.read_bytes())
    result = CliRunner().invoke(main, ["dataset", "-n", "2", "-o", str(path)])
    assert result.exit_code == 2 and "--resume" in result.stderr
    assert (path.stat().st_mtime_ns, path.read_bytes()) == before


def test_info_summarises_a_dataset(reference: Path) -> None:
    result = CliRunner().invoke(main, ["info", str(reference)])
    assert result.exit_code == 0
    assert re.search(
        r"data set of 24 (dh )?runs × 51 samples \(float32\), 24 complete", result.stdout
    )
    assert "seed 7" in result.stdout


@pytest.mark.slow
def test_peak_memory_does_not_grow_with_the_number_of_runs(tmp_path: Path) -> None:
    code = (
        "import resource, sys; "
        "from aaria_pin.apps.dataset.generate import DhDatasetSpec, generate_dataset; "
        "generate_dataset(sys.argv[1], DhDatasetSpec(n_runs=int(sys.argv[2]), duration=0.2), "
        "workers=1); print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)"
    )
    peaks = {}
    for n in (200, 2000):
        out = subprocess.run(
            [sys.executable, "-c", code, str(tmp_path / f"m{n}.h5"), str(n)],
            capture_output=True,
            text=True,
            check=True,
        )
        peaks[n] = int(out.stdout.strip()) / 1024  # MB (ru_maxrss is in kB on Linux)
    assert peaks[2000] - peaks[200] < 20, peaks


class _DeadlySpec(DhDatasetSpec):
    """Run 10's worker dies (as on a segfault); every other run is an ordinary one."""

    def make_run(self, run: int) -> RunRecord:
        if run == 10:
            os._exit(1)
        return super().make_run(run)


def test_a_worker_that_dies_fails_only_its_own_run(tmp_path: Path) -> None:
    settings = {"n_runs": 24, "seed": 7, **SHORT}
    whole = tmp_path / "whole.h5"
    generate_dataset(whole, DhDatasetSpec(**settings), workers=1)
    path = tmp_path / "deadly.h5"
    report = generate_dataset(path, _DeadlySpec(**settings), workers=2)
    assert sorted(report.failures) == [10]
    assert "worker process died" in report.failures[10]
    with DatasetReader(path) as got, DatasetReader(whole) as want:
        for k in range(24):
            if k != 10:  # its task-mates (several short runs a task) are kept, not failed
                np.testing.assert_array_equal(got.record(k).imu, want.record(k).imu)


def test_a_logged_job_prints_its_estimate_and_progress_lines(tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    args = ["dataset", "-n", "12", "--seed", "7", "--duration", "0.5", "--workers", "2"]
    result = CliRunner().invoke(main, [*args, "--progress-every", "0", "-o", str(path)])
    assert result.exit_code == 0, result.output
    lines = result.stderr.splitlines()  # stderr is not a terminal here: lines, not a bar
    estimate = [line for line in lines if line.startswith("aaria: estimate for 12 runs: ")]
    assert len(estimate) == 1 and re.search(r" kB, (about \d+ s|under 1 s) ", estimate[0])
    assert "on 2 workers" in estimate[0]
    progress = [
        line for line in lines if re.fullmatch(r"aaria: \d+/12 runs, .* runs/s, ETA .*", line)
    ]
    assert len(progress) >= 2 and progress[-1].startswith("aaria: 12/12 runs")
    assert "\r" not in result.stderr
    size = int(re.search(r"estimate for 12 runs: ([\d.]+) kB", estimate[0]).group(1).split(".")[0])
    assert 0.5 < size * 1000 / path.stat().st_size < 2  # within a factor of two of the file
    quiet = CliRunner().invoke(main, [*args, "--quiet", "--overwrite", "-o", str(path)])
    assert quiet.exit_code == 0 and quiet.stderr == ""


def test_dataset_records_its_command_and_versions(tmp_path: Path) -> None:
    import platform

    path = tmp_path / "ds.h5"
    generate_dataset(
        path, DhDatasetSpec(n_runs=2, **SHORT), workers=1, command="aaria dataset -n 2"
    )
    with DatasetReader(path) as reader:
        attributes = reader.attributes
        assert attributes["command"] == "aaria dataset -n 2"
        versions = attributes["versions"]
        assert versions["numpy"] == np.__version__ and versions["h5py"] == h5py.__version__
        assert versions["python"] == platform.python_version() and versions["pinocchio"]
        assert "command" not in reader.record(0).attributes  # the data set's, not a run's
    generate_dataset(path, DhDatasetSpec(n_runs=2, **SHORT), workers=1, overwrite=True)
    with DatasetReader(path) as reader:
        assert reader.attributes["command"] == ""  # the library's default


def test_fourier_runs_are_drawn_from_their_joint_stream_within_the_limits(tmp_path: Path) -> None:
    """--motion fourier: random arms follow their stored series, the same whatever the workers."""
    settings = {"n_runs": 6, "seed": 4, "duration": 2.0, "rate": 50.0, "noise": False}
    spec = DhDatasetSpec(**settings, motion="fourier", harmonics=3)
    generate_dataset(tmp_path / "one.h5", spec, workers=1)
    generate_dataset(tmp_path / "two.h5", spec, workers=2)
    _assert_same(tmp_path / "one.h5", tmp_path / "two.h5")
    with DatasetReader(tmp_path / "one.h5") as reader:
        assert reader.attributes["fourier"] == {"base_frequency": 0.5, "harmonics": 3}
        coefficients = [reader.run(k)["fourier_coefficients"] for k in range(6)]
        for k in range(6):
            run = reader.run(k, ["time", "q", "qd", "senSenDH", "fourier_coefficients"])
            table, t = run["fourier_coefficients"], run["time"].astype(float)
            assert table.shape == (6, 7)
            w = 2 * np.pi * 0.5 * np.arange(1, 4)
            angle = t[:, None] * w  # the series by hand: offset + sum a/w sin - b/w cos
            q = table[:, 0] + np.sin(angle) @ (table[:, 1:4] / w).T
            q -= np.cos(angle) @ (table[:, 4:7] / w).T
            np.testing.assert_allclose(run["q"], q, atol=1e-6)  # float32 series
            for module, (_, _, _, d, code) in enumerate(run["senSenDH"][:6]):
                bound = {0: 0.0, 1: 1.0, 2: d / 2}[int(code)]  # empty, ±1 rad, the rail ±d/2
                assert np.abs(run["q"][:, module]).max() <= bound + 1e-6
                assert np.abs(run["qd"][:, module]).max() <= (1.5 if code == 1 else 0.5) + 1e-6
    assert not np.allclose(coefficients[0][:, 1:], coefficients[1][:, 1:])  # drawn per run
    code = CliRunner().invoke(
        main, ["dataset", "-n", "2", "--harmonics", "3", "--quiet", "-o", str(tmp_path / "x.h5")]
    )
    assert code.exit_code == 2 and "--harmonics is 3; allowed: only with motion fourier" in (
        code.stderr
    )
    assert not (tmp_path / "x.h5").exists()


def test_fourier_runs_of_a_urdf_robot(tmp_path: Path) -> None:
    from aaria_pin.apps.dataset.urdf_spec import UrdfDatasetSpec, UrdfSource
    from aaria_pin.core.catalogue import find_robot
    from aaria_pin.core.urdf_robot import read_urdf_file

    entry = find_robot("ur5")
    source = UrdfSource(read_urdf_file(entry.urdf), "ur5", str(entry.urdf.parent))
    spec = UrdfDatasetSpec(
        n_runs=3,
        seed=1,
        duration=2.0,
        rate=50.0,
        robot=source,
        motion="fourier",
        vary=("joints", "base"),
    )
    generate_dataset(tmp_path / "ur5.h5", spec, workers=1)
    with DatasetReader(tmp_path / "ur5.h5") as reader:
        for k in range(3):
            run = reader.run(k, ["q", "qd", "qdd", "fourier_coefficients"])
            assert run["fourier_coefficients"].shape == (6, 11)
            assert np.abs(run["q"][:, 2]).max() <= np.pi  # ur5.urdf: the elbow within ±π
            assert np.abs(run["qd"]).max() <= 1.5 + 1e-6 and np.abs(run["qdd"]).max() <= 5 + 1e-5
        record = reader.record(2)
    assert record.attributes["motion"] == "fourier"
    remade = remake_record(record)
    assert np.array_equal(remade.q.astype(np.float32), record.q)


FIXTURES_0_3 = Path(__file__).resolve().parent.parent / "fixtures" / "v0_3_0"


@pytest.mark.parametrize(
    ("name", "args"),
    [
        ("dh_dataset.h5", ["-n", "3"]),
        ("ur5_dataset.h5", ["-n", "2", "--robot", "ur5"]),
        ("dh_fourier_dataset.h5", ["-n", "2", "--motion", "fourier"]),
    ],
)
def test_the_0_3_data_sets_are_made_again_bit_for_bit(
    tmp_path: Path, name: str, args: list[str]
) -> None:
    """The commands of tests/fixtures/v0_3_0/README.md write the same arrays and settings.

    And one array more, the table ``inertial_parameters`` (added after 0.3): the layout lists it
    last among the tables, and the checksum has its column last.
    """
    path = tmp_path / name
    common = ["--duration", "0.2", "--seed", "7", "--workers", "1", "--quiet"]
    result = CliRunner().invoke(main, ["dataset", *args, *common, "-o", str(path)])
    assert result.exit_code == 0, result.output
    added = "inertial_parameters"
    with h5py.File(FIXTURES_0_3 / name, "r") as want, h5py.File(path, "r") as got:
        names: list[str] = []
        want.visit(names.append)
        assert sorted([*names, added]) == sorted(_names(got))
        for array in names:
            made = got[array][()]
            if array == "checksum":  # a column per stored array: the new one's last
                assert made.shape[1] == want[array].shape[1] + 1
                made = made[:, :-1]
            np.testing.assert_array_equal(made, want[array][()], err_msg=array)
        # this job's, not the data; the layout: compared without the new table below
        changed = {"version", "versions_json", "command", "card_json", "layout_json"}
        for key in set(want.attrs) - changed:
            assert np.array_equal(got.attrs[key], want.attrs[key]), key
        layout = json.loads(got.attrs["layout_json"])
        assert list(layout["tables"])[-1] == added
        del layout["tables"][added]
        assert layout == json.loads(want.attrs["layout_json"])


def _names(handle: h5py.File) -> list[str]:
    names: list[str] = []
    handle.visit(names.append)
    return names
