"""Peak memory of long runs: ``aaria simulate`` computes and writes them in time chunks.

    python benchmarks/bench_memory.py            # full: 200,000 and 2,000,000 samples
    python benchmarks/bench_memory.py --smoke    # CI: 2,000 and 6,000 samples, chunks of 500

Each run is one fresh process doing what ``aaria simulate --preset aaria-fig2 --rate 100000
-o run.h5`` (or ``-o run.mat``) does (``simulate_run_chunks`` written by ``write_run_pieces``:
whole if one chunk, else streamed into preallocated HDF5 datasets, or a MAT-file v7.3); the
process prints its own peak RSS (``resource.getrusage``, ``ru_maxrss``) and its wall time. The
cases: ``.h5`` noise off, ``.h5`` noise on, ``.mat`` noise on (written as v7.3, as a run of more
than one chunk is; in ``--smoke`` mode asked for, the runs being short). The goal of issue 15:
2 M samples within 600 MB, and the peak independent of the run's length. The wall time is a
figure, not a target (the other benchmarks measure speed against the floor).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

RATE = 100_000.0
CASES = ((".h5", False), (".h5", True), (".mat", True))
"""(output suffix, noise) of each measured case."""

CHILD = """
import json, resource, sys, time
start = time.perf_counter()
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run_chunks
from aaria_pin.files.runfile import write_run_pieces
from aaria_pin.core._malloc import tune_malloc
from aaria_pin.core.run import CHUNK_SAMPLES

tune_malloc()
output, duration, rate, noise, chunk = sys.argv[1:6]
preset = get_preset("aaria-fig2")
chunks = simulate_run_chunks(
    preset.table, preset.joint_table, preset.base_table, duration=float(duration),
    rate=float(rate), noise=noise == "on", robot_name="aaria-fig2",
    chunk=CHUNK_SAMPLES if chunk == "default" else int(chunk),
)
_, samples, _ = write_run_pieces(output, chunks, None, mat_version="7.3")
print(json.dumps({"samples": samples, "peak_mb": resource.getrusage(resource.RUSAGE_SELF)
                  .ru_maxrss / 1024, "seconds": time.perf_counter() - start}))
"""


def measure(
    duration: float, rate: float, noise: bool, chunk: str, output: Path
) -> dict[str, float]:
    """Peak RSS [MB], samples and wall time [s] of one run in a fresh process."""
    result = subprocess.run(
        [sys.executable, "-c", CHILD, str(output), repr(duration), repr(rate),
         "on" if noise else "off", chunk],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    output.unlink()
    figure: dict[str, float] = json.loads(result.stdout.strip().splitlines()[-1])
    return figure


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="tiny sizes (CI)")
    args = parser.parse_args()
    if args.smoke:
        rate, durations, chunk = 1000.0, (1.999, 5.999), "500"
    else:
        rate, durations, chunk = RATE, (1.99999, 19.99999), "default"
    print(f"aaria-fig2 on a moving base at {rate:g} Hz, chunks of {chunk} samples")
    with tempfile.TemporaryDirectory() as name:
        for suffix, noise in CASES:
            label = f"{suffix:<4} noise {'on ' if noise else 'off'}"
            peaks = []
            for duration in durations:
                figure = measure(duration, rate, noise, chunk, Path(name) / f"run{suffix}")
                peaks.append(figure["peak_mb"])
                print(
                    f"{label} {figure['samples']:>9,.0f} samples: "
                    f"peak RSS {figure['peak_mb']:7.1f} MB, {figure['seconds']:6.2f} s wall, "
                    f"{figure['samples'] / figure['seconds']:,.0f} samples/s"
                )
            print(f"{label} growth long - short: {peaks[1] - peaks[0]:+.1f} MB")


if __name__ == "__main__":
    main()
