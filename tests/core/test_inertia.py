from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.core.inertia import Part, box_inertia, composite_inertia, cylinder_inertia
from aaria_pin.core.se3 import rot_x, rot_z, translation
from aaria_pin.errors import ParameterError


def _grid_inertia(points: np.ndarray, cell_mass: np.ndarray) -> np.ndarray:
    """Inertia about the origin of point masses (an independent quadrature)."""
    r2 = np.einsum("ni,ni->n", points, points)
    return np.einsum("n,n->", cell_mass, r2) * np.eye(3) - np.einsum(
        "n,ni,nj->ij", cell_mass, points, points
    )


def test_box_inertia_against_quadrature() -> None:
    size = np.array([0.9, 0.06, 0.04])
    n = 60
    axes = [(np.arange(n) + 0.5) / n * s - s / 2 for s in size]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    mass = 3.0
    numeric = _grid_inertia(grid, np.full(len(grid), mass / len(grid)))
    np.testing.assert_allclose(box_inertia(mass, tuple(size)), numeric, rtol=1e-3, atol=1e-12)


def test_cylinder_inertia_against_quadrature() -> None:
    radius, length, mass = 0.05, 0.3, 2.0
    nr, nt, nz = 80, 90, 80
    r = (np.arange(nr) + 0.5) / nr * radius
    t = np.arange(nt) / nt * 2 * np.pi
    z = (np.arange(nz) + 0.5) / nz * length - length / 2
    R, Th, Z = np.meshgrid(r, t, z, indexing="ij")
    points = np.stack([R * np.cos(Th), R * np.sin(Th), Z], axis=-1).reshape(-1, 3)
    weights = R.reshape(-1)  # area element r dr dθ
    numeric = _grid_inertia(points, mass * weights / weights.sum())
    np.testing.assert_allclose(
        cylinder_inertia(mass, radius, length), numeric, rtol=1e-3, atol=1e-9
    )


def test_two_half_boxes_combine_into_the_whole_box() -> None:
    rho = 2700.0
    half = (0.45, 0.06, 0.06)
    parts = [
        Part("box", half, translation(x=0.225), rho),
        Part("box", half, translation(x=0.675), rho),
    ]
    whole = Part("box", (0.9, 0.06, 0.06), translation(x=0.45), rho)
    combined = composite_inertia(parts)
    np.testing.assert_allclose(combined.mass, whole.mass)
    np.testing.assert_allclose(combined.com, [0.45, 0, 0])
    np.testing.assert_allclose(combined.inertia_com, whole.inertia().inertia_com, rtol=1e-12)


@settings(max_examples=50, deadline=None)
@given(
    angles=st.tuples(st.floats(-3.2, 3.2), st.floats(-3.2, 3.2)),
    offset=st.tuples(*[st.floats(-1, 1)] * 3),
)
def test_composite_matches_pinocchio_inertia_algebra(angles, offset) -> None:
    T = translation(*offset) @ rot_z(angles[0]) @ rot_x(angles[1])
    parts = [Part("cylinder", (0.05, 0.1), np.eye(4)), Part("box", (0.3, 0.05, 0.02), T)]
    ours = composite_inertia(parts)
    total = pin.Inertia.Zero()
    for part in parts:
        local = part.inertia()  # about the part centre, body axes
        total += pin.Inertia(local.mass, local.com, local.inertia_com)
    np.testing.assert_allclose(ours.mass, total.mass)
    np.testing.assert_allclose(ours.com, total.lever, atol=1e-12)
    np.testing.assert_allclose(ours.inertia_com, total.inertia, atol=1e-12)


def test_rotated_part_uses_rotated_tensor() -> None:
    part = Part("box", (1.0, 0.1, 0.2), rot_z(np.pi / 2))
    I = part.inertia().inertia_com
    I_local = box_inertia(part.mass, (1.0, 0.1, 0.2))
    np.testing.assert_allclose(
        np.diag(I), [I_local[1, 1], I_local[0, 0], I_local[2, 2]], atol=1e-15
    )


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3"])
@pytest.mark.parametrize("density", [2700.0, 7850.0])
def test_total_mass_is_density_times_volume(name: str, density: float) -> None:
    table = get_preset(name).table
    dims = BodyDimensions(density=density)
    volume = table[6, 1] * dims.link_width * dims.link_height  # tool
    for _alpha, a, _theta, d, link_type in table[:6]:
        if link_type == 0:
            continue
        volume += a * dims.link_width * dims.link_height
        if link_type == 1:
            volume += np.pi * dims.housing_radius**2 * dims.housing_length
        else:
            volume += dims.link_width**2 * dims.link_height + np.pi * dims.rail_radius**2 * d
    model = build_dh_robot(table, dims=dims).model(moving_base=True).model
    total = sum(inertia.mass for inertia in model.inertias)
    np.testing.assert_allclose(total, density * volume, rtol=1e-12)


def test_zero_length_link_gets_no_box_and_a_regular_inertia() -> None:
    table = get_preset("aaria-fig2").table.copy()
    table[2, 1] = 0.0
    robot = build_dh_robot(table)
    assert "link3_link" not in robot.urdf
    inertia = robot.model().model.inertias[3]
    assert inertia.mass > 0
    assert np.all(np.linalg.eigvalsh(inertia.inertia) > 0)


def test_density_override_per_link() -> None:
    table = get_preset("aaria-fig2").table
    base = build_dh_robot(table).model().model
    heavy = (
        build_dh_robot(table, dims=BodyDimensions(density_overrides={"link4": 5400.0}))
        .model()
        .model
    )
    np.testing.assert_allclose(heavy.inertias[4].mass, 2 * base.inertias[4].mass)
    np.testing.assert_allclose(heavy.inertias[3].mass, base.inertias[3].mass)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"density": -1.0},
        {"density": 0.0},
        {"link_width": -0.1},
        {"rail_radius": np.nan},
        {"density_overrides": {"link2": -3.0}},
    ],
)
def test_bad_dimensions_are_refused(kwargs) -> None:
    with pytest.raises(ParameterError, match="allowed"):
        BodyDimensions(**kwargs)
