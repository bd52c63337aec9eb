"""How the peak torque at joint 2 grows with link length and density (aaria-fig2 motion).

    python analysis/peak_torque_vs_link.py [--quick] [--out analysis_out]

Every link of the Figure 2 arm gets the same length a (0.5 to 1.0 m) and the whole arm one of
three densities (ABS, aluminium, steel); the preset's joint and base motions are kept. Writes
``peak_torque_vs_link.csv`` (a, density, peak |tau| at joint 2) and ``peak_torque_vs_link.png``.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from aaria_pin.aaria.dh_robot import BodyDimensions
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run

DENSITIES = {"ABS plastic": 1040.0, "aluminium": 2700.0, "steel": 7850.0}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="three lengths, 2 s runs")
    parser.add_argument("--out", type=Path, default=Path("analysis_out"))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    lengths = np.linspace(0.5, 1.0, 3 if args.quick else 11)
    preset = get_preset("aaria-fig2")
    rows = []
    for name, density in DENSITIES.items():
        for a in lengths:
            table = preset.table.copy()
            table[:6, 1] = a
            record = simulate_run(
                table,
                preset.joint_table,
                preset.base_table,
                duration=2.0 if args.quick else 10.0,
                rate=100.0,
                noise=False,
                dims=BodyDimensions(density=density),
            )
            rows.append((float(a), name, density, float(np.abs(record.tau[:, 1]).max())))
    with open(args.out / "peak_torque_vs_link.csv", "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["a_m", "material", "density_kg_m3", "peak_tau_joint2_Nm"])
        writer.writerows(rows)
    figure, axes = plt.subplots(figsize=(6, 4), dpi=100)
    for name in DENSITIES:
        points = [(a, peak) for a, material, _, peak in rows if material == name]
        axes.plot(*zip(*points, strict=True), "o-", label=name)
    axes.set_xlabel("link length a [m]")
    axes.set_ylabel("peak |tau| at joint 2 [N*m]")
    axes.set_title("aaria-fig2: peak torque at joint 2")
    axes.legend()
    figure.tight_layout()
    figure.savefig(args.out / "peak_torque_vs_link.png")
    for row in rows:
        print(f"a {row[0]:.2f} m  {row[1]:<12} peak |tau2| {row[3]:10.1f} N*m")


if __name__ == "__main__":
    main()
