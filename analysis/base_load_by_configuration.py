"""Which random configurations load the base most (the paper's MODE 1 arms).

    python analysis/base_load_by_configuration.py [--quick] [--runs N] [--out analysis_out]

Simulates N random runs (the data set's runs, seed 1, noise off) and, for each, the peak force
and moment of the base wrench, the arm's reach (sum of its link lengths and the tool) and its
joint types. Writes ``base_load_by_configuration.csv`` (largest moment first) and
``base_load_by_configuration.png`` (peak moment against reach, by number of prismatic joints).
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="20 runs of 2 s")
    parser.add_argument("--runs", type=int, default=200)
    parser.add_argument("--out", type=Path, default=Path("analysis_out"))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    runs = 20 if args.quick else args.runs
    spec = DhDatasetSpec(
        n_runs=runs, seed=1, duration=2.0 if args.quick else 10.0, noise=False, dtype="float64"
    )
    rows = []
    for k in range(runs):
        record = spec.make_run(k)
        table = record.tables["senSenDH"]
        used = table[:6, 4] > 0
        wrench = record.base_wrench
        rows.append(
            {
                "run": k,
                "types": "".join("-RP"[int(t)] for t in table[:6, 4]),
                "prismatic": int(np.sum(table[:6, 4] == 2)),
                "reach_m": float(table[:6, 1][used].sum() + table[6, 1]),
                "peak_force_N": float(np.linalg.norm(wrench[:, :3], axis=1).max()),
                "peak_moment_Nm": float(np.linalg.norm(wrench[:, 3:], axis=1).max()),
            }
        )
    rows.sort(key=lambda row: row["peak_moment_Nm"], reverse=True)
    with open(args.out / "base_load_by_configuration.csv", "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    figure, axes = plt.subplots(figsize=(6, 4), dpi=100)
    for count in sorted({row["prismatic"] for row in rows}):
        chosen = [row for row in rows if row["prismatic"] == count]
        axes.scatter(
            [row["reach_m"] for row in chosen],
            [row["peak_moment_Nm"] for row in chosen],
            label=f"{count} prismatic",
        )
    axes.set_xlabel("reach: sum of link lengths and tool [m]")
    axes.set_ylabel("peak base moment [N*m]")
    axes.set_title(f"base load of {runs} random arms")
    axes.legend()
    figure.tight_layout()
    figure.savefig(args.out / "base_load_by_configuration.png")
    for row in rows[:5]:
        print(
            f"run {row['run']:>4} {row['types']}  reach {row['reach_m']:.2f} m  "
            f"peak moment {row['peak_moment_Nm']:.0f} N*m  force {row['peak_force_N']:.0f} N"
        )


if __name__ == "__main__":
    main()
