"""Peak memory of long runs: ``aaria simulate`` computes and writes them in time chunks.

    python benchmarks/bench_memory.py            # full: 200,000 and 2,000,000 samples
    python benchmarks/bench_memory.py --smoke    # CI: 2,000 and 6,000 samples, chunks of 500

Each run is one fresh process doing what ``aaria simulate --preset aaria-fig2 --rate 100000
-o run.h5`` does (``simulate_run_chunks`` written by ``write_run_pieces``: whole if one
chunk, else streamed into preallocated HDF5 datasets), noise off and on; the process prints its
own peak RSS (``resource.getrusage``, ``ru_maxrss``) and its wall time. The goal of issue 15:
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
_, samples, _ = write_run_pieces(output, chunks, None)
print(json.dumps({"samples": samples, "peak_mb": resource.getrusage(resource.RUSAGE_SELF)
                  .ru_maxrss / 1024, "seconds": time.perf_counter() - start}))
"""


def measure(duration: float, rate: float, noise: bool, chunk: str, folder: Path) -> dict:
    """Peak RSS [MB], samples and wall time [s] of one run in a fresh process."""
    output = folder / "run.h5"
    result = subprocess.run(
        [sys.executable, "-c", CHILD, str(output), repr(duration), repr(rate),
         "on" if noise else "off", chunk],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    output.unlink()
    return json.loads(result.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="tiny sizes (CI)")
    args = parser.parse_args()
    if args.smoke:
        rate, durations, chunk = 1000.0, (1.999, 5.999), "500"
    else:
        rate, durations, chunk = RATE, (1.99999, 19.99999), "default"
    print(f"aaria-fig2 on a moving base at {rate:g} Hz, chunks of {chunk} samples, .h5")
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        for noise in (False, True):
            peaks = []
            for duration in durations:
                figure = measure(duration, rate, noise, chunk, folder)
                peaks.append(figure["peak_mb"])
                print(
                    f"noise {'on ' if noise else 'off'} {figure['samples']:>9,} samples: "
                    f"peak RSS {figure['peak_mb']:7.1f} MB, {figure['seconds']:6.2f} s wall, "
                    f"{figure['samples'] / figure['seconds']:,.0f} samples/s"
                )
            label = "on " if noise else "off"
            print(f"noise {label} growth long - short: {peaks[1] - peaks[0]:+.1f} MB")


if __name__ == "__main__":
    main()
