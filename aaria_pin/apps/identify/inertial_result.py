"""What the dynamic identification found: the base parameters' estimates and the held-out errors."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from aaria_pin.apps.identify._json import json_number
from aaria_pin.apps.identify.inertial_base import BaseParameterSet
from aaria_pin.core.se3 import Array

__all__ = ["LOOSE", "DynamicIdentification", "StandardEstimate", "dynamics_summary"]


LOOSE = 0.01
"""Relative σ of a friction coefficient above which the summary calls it loosely determined."""


def _body(standard: Array) -> dict[str, Any]:
    """A body's mass [kg], centre of mass [m] and inertia about it [kg·m²], body axes."""
    from aaria_pin.apps.identify.inertial_consistent import pseudo_inertia

    mass = float(standard[0])
    com = standard[1:4] / mass if mass > 0 else np.full(3, np.nan)
    J = pseudo_inertia(standard)[0]
    origin = np.array(
        [[standard[4], standard[5], standard[7]],
         [standard[5], standard[6], standard[8]],
         [standard[7], standard[8], standard[9]]]
    )  # fmt: skip
    shift = mass * (float(com @ com) * np.eye(3) - np.outer(com, com)) if mass > 0 else 0.0
    return {
        "mass": mass,
        "com": [json_number(float(c)) for c in com],
        "inertia_com": (origin - shift).tolist(),  # parallel axis theorem
        "pseudo_inertia_min_eigenvalue": float(np.linalg.eigvalsh(J).min()),
    }


@dataclass(frozen=True)
class StandardEstimate:
    """Standard parameters that give the base estimate: per body, and friction per joint.

    Without ``consistent`` they are one of many sets giving the same torques (the parameters
    not determined by the data are 0); with it, a set of physical bodies.

    Attributes:
        values: the bodies' ten parameters each, then the joints' ``[Fv, Fc, Ia]`` each
        model: the same in the record's model (the truth of a simulated run)
        bodies: the bodies' names
        joints: the joints whose friction was fitted (empty: none)
        consistent: whether the bodies were constrained to be physical
        determined: per parameter, whether the data determine it alone
        free_flyer: whether the model had a free-flyer root (its first body the base's)
    """

    values: Array
    model: Array
    bodies: tuple[str, ...]
    joints: tuple[str, ...]
    consistent: bool
    determined: tuple[bool, ...]
    free_flyer: bool = False

    def friction(self) -> Array:
        """The joints' ``[Fv, Fc, Ia]``, (n, 3)."""
        return self.values[10 * len(self.bodies) :].reshape(-1, 3)

    def to_json(self) -> dict[str, Any]:
        """The bodies (with ``consistent``) and the friction as plain JSON types."""
        out: dict[str, Any] = {"consistent": self.consistent}
        if self.consistent:
            out["bodies"] = [
                {
                    "name": name,
                    **_body(self.values[10 * b : 10 * b + 10]),
                    "model": _body(self.model[10 * b : 10 * b + 10]),
                }
                for b, name in enumerate(self.bodies)
            ]
        first = 10 * len(self.bodies)
        model = self.model[first:].reshape(-1, 3)
        determined = np.reshape(self.determined[first:], (-1, 3))
        out["friction"] = [
            {
                "joint": joint,
                **{k: float(v) for k, v in zip(("Fv", "Fc", "Ia"), row, strict=True)},
                "model": {k: float(v) for k, v in zip(("Fv", "Fc", "Ia"), truth, strict=True)},
                "determined": {k: bool(v) for k, v in zip(("Fv", "Fc", "Ia"), d, strict=True)},
            }
            for joint, row, truth, d in zip(
                self.joints, self.friction(), model, determined, strict=True
            )
        ]
        return out


@dataclass(frozen=True)
class DynamicIdentification:
    """What :func:`~aaria_pin.apps.identify.inertial.identify_dynamics` found.

    Attributes:
        signals: the identified signals: the base wrench (:data:`BASE_WRENCH_SIGNALS`) when it
            was used, then the joints in model order
        base: the base parameter set (names and combinations)
        estimate: the base parameters' least-squares estimate, (r,)
        std: their standard deviations from the fit, (r,)
        model_values: their values in the record's model (the truth for a simulated run), (r,)
        samples_train: samples fitted (the first part of the run)
        samples_holdout: samples held out (the last part)
        holdout_relative_rms: per signal, RMS of the held-out prediction error over the RMS of
            the measured signal (NaN for a signal that is zero throughout)
        holdout_rms: per signal, RMS of the held-out prediction error [N·m, N]
        train_relative_rms: per signal, the same on the training samples
        total_mass: the estimated total moving mass [kg] (NaN when the data cannot determine
            it: a fixed base without the mount's wrench)
        total_mass_model: the model's total mass [kg]
        com_error: RMS and max over the run of the distance between the estimated and the
            model's centre of mass of the whole robot, base frame [m] (empty when not
            determined)
        com_start: estimated and model centre of mass at the first sample, base frame [m]
        standard: standard parameters giving the estimate (per body, friction per joint)
        extras: anything else reported (rank tolerance, regressor size)
    """

    signals: tuple[str, ...]
    base: BaseParameterSet
    estimate: Array
    std: Array
    model_values: Array
    samples_train: int
    samples_holdout: int
    holdout_relative_rms: Array
    holdout_rms: Array
    train_relative_rms: Array
    total_mass: float
    total_mass_model: float
    com_error: dict[str, float] = field(default_factory=dict)
    com_start: dict[str, list[float]] = field(default_factory=dict)
    standard: StandardEstimate | None = None
    extras: dict[str, Any] = field(default_factory=dict)

    @property
    def worst_holdout_relative_rms(self) -> float:
        """The largest held-out relative RMS error over the signals (NaNs skipped)."""
        finite = self.holdout_relative_rms[np.isfinite(self.holdout_relative_rms)]
        return float(finite.max()) if finite.size else float("nan")

    def to_json(self) -> dict[str, Any]:
        """The result as plain JSON types (NaN as None)."""
        return {
            "signals": list(self.signals),
            "n_standard": len(self.base.standard_names),
            "n_base": self.base.rank,
            "rank_tolerance": self.base.tolerance,
            "samples_train": self.samples_train,
            "samples_holdout": self.samples_holdout,
            "holdout_relative_rms": {
                s: json_number(x)
                for s, x in zip(self.signals, self.holdout_relative_rms, strict=True)
            },
            "holdout_rms": {
                s: json_number(x) for s, x in zip(self.signals, self.holdout_rms, strict=True)
            },
            "train_relative_rms": {
                s: json_number(x)
                for s, x in zip(self.signals, self.train_relative_rms, strict=True)
            },
            "worst_holdout_relative_rms": json_number(self.worst_holdout_relative_rms),
            "total_mass": {
                "estimate": json_number(self.total_mass),
                "model": self.total_mass_model,
                "error": json_number(self.total_mass - self.total_mass_model),
            },
            "centre_of_mass": {"error": self.com_error, **self.com_start},
            "base_parameters": [
                {
                    "name": name,
                    "combination": expression,
                    "estimate": float(value),
                    "std": json_number(float(std)),
                    "model": float(truth),
                }
                for name, expression, value, std, truth in zip(
                    self.base.names,
                    self.base.expressions,
                    self.estimate,
                    self.std,
                    self.model_values,
                    strict=True,
                )
            ],
            **({} if self.standard is None else self._with_friction_std(self.standard.to_json())),
            **self.extras,
        }

    def _with_friction_std(self, standard: dict[str, Any]) -> dict[str, Any]:
        """The friction rows with each coefficient's σ (None: not a base parameter alone).

        The unconstrained fit's σ of the base parameter that is the coefficient by itself
        (``Fv_<joint>`` and ``Fc_<joint>`` are, unless the motion leaves them tied to others):
        how well the excitation determines the friction.
        """
        alone = {
            name: json_number(float(std))
            for name, expression, std in zip(
                self.base.names, self.base.expressions, self.std, strict=True
            )
            if expression == name  # the base parameter is the coefficient, nothing added
        }
        for row in standard.get("friction", []):
            row["std"] = {k: alone.get(f"{k}_{row['joint']}") for k in ("Fv", "Fc", "Ia")}
        return standard


def _sigma(value: float | None) -> str:
    return "" if value is None else f" ± {value:.2g}"


def _vector(values: list[float | None]) -> str:
    return "[" + " ".join(_shown(v, ".4g") for v in values) + "]"


def _shown(value: float | None, spec: str = ".3g") -> str:
    return "n/a" if value is None else format(value, spec)


def dynamics_summary(report: dict[str, Any], show_parameters: bool = False) -> list[str]:
    """A :meth:`DynamicIdentification.to_json` report as a few lines of text.

    Args:
        report: the report
        show_parameters: a line for every base parameter (its combination, estimate, std,
            model value)

    Returns:
        The lines: counts, held-out errors per signal, total mass, centre of mass.
    """
    lines = [
        f"base parameters: {report['n_base']} of {report['n_standard']} standard "
        f"(rank tolerance {report['rank_tolerance']:g}); fitted on "
        f"{report['samples_train']} samples, tested on {report['samples_holdout']}"
    ]
    width = max(len(name) for name in report["signals"])
    lines.append(f"{'signal':<{width}} {'held-out rel. RMS':>18} {'held-out RMS':>13}")
    for name in report["signals"]:
        lines.append(
            f"{name:<{width}} {_shown(report['holdout_relative_rms'][name]):>18} "
            f"{_shown(report['holdout_rms'][name]):>13}"
        )
    mass = report["total_mass"]
    if mass["estimate"] is None:
        lines.append(f"total mass: not determined by the data (model {mass['model']:.6g} kg)")
    else:
        lines.append(
            f"total mass: {mass['estimate']:.6g} kg (model {mass['model']:.6g} kg, "
            f"error {mass['error']:.3g} kg)"
        )
    com = report["centre_of_mass"]
    if com["error"]:
        lines.append(
            f"centre of mass error over the run: RMS {com['error']['rms']:.3g} m, "
            f"max {com['error']['max']:.3g} m"
        )
    else:
        lines.append("centre of mass: not determined by the data")
    if report.get("torques"):
        lines.append(f"torques fitted: {report['torques']}")
    from aaria_pin.apps.identify.inertial_scale import scale_line, scale_off

    if report.get("torque_scale"):
        lines.append(scale_line(report["torque_scale"]))
    if report.get("torque_scale_unchecked"):
        lines.append(f"torque constant × gear ratio: {report['torque_scale_unchecked']}")
    for row in report.get("friction", []):
        std = row.get("std", {})
        values = ", ".join(
            f"{k} {row[k]:.4g}{_sigma(std.get(k))} (model {row['model'][k]:.4g})"
            if row["determined"][k]
            else f"{k} not determined"
            for k in ("Fv", "Fc", "Ia")
        )
        lines.append(f"friction {row['joint']}: {values}")
    loose = [
        f"{k} {row['joint']} {100 * row['std'][k] / abs(row[k]):.2g} %"
        for row in report.get("friction", [])
        for k in ("Fv", "Fc")
        if row.get("std", {}).get(k) is not None and row["std"][k] > LOOSE * abs(row[k])
    ]
    if loose:
        lines.append(
            f"friction loosely determined (σ above {100 * LOOSE:g} %): {', '.join(loose)}; "
            + (
                "set torque_constant and gear_ratio first (the friction was fitted with the "
                "wrong ones)"
                if scale_off(report.get("torque_scale", []))
                else "a faster motion within the joints' limits (--base-frequency) or a longer "
                "run tightens it"
            )
        )
    if report.get("bodies"):
        smallest = min(body["pseudo_inertia_min_eigenvalue"] for body in report["bodies"])
        lines.append(
            f"bodies: {len(report['bodies'])} physically consistent "
            f"(smallest pseudo-inertia eigenvalue {smallest:.3g} kg·m²)"
        )
    if show_parameters:
        lines += [
            f"{body['name']}: mass {body['mass']:.6g} kg (model {body['model']['mass']:.6g}), "
            f"com {_vector(body['com'])} m (model {_vector(body['model']['com'])})"
            for body in report.get("bodies", [])
        ]
        lines += [
            f"{parameter['name']}: {parameter['estimate']:.6g} ± "
            f"{_shown(parameter['std'])} (model {parameter['model']:.6g}) = "
            f"{parameter['combination']}"
            for parameter in report["base_parameters"]
        ]
    return lines
