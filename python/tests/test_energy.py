"""Energies from Python equal `flexure energy` on the same files (1e-14 relative)."""

import numpy as np
import pytest

import flexure
from conftest import bent

ENERGIES = flexure.energies()


def test_registry_lists_the_builtins():
    assert len(ENERGIES) >= 5
    for name in ("hinge", "triavg", "cotan", "midedge", "quadfit"):
        assert name in ENERGIES


def relative(a, b):
    return abs(a - b) / max(abs(a), abs(b))


@pytest.mark.parametrize("name", ENERGIES)
@pytest.mark.parametrize("linearized", [False, True])
def test_energy_equals_cli(name, linearized, plate, cli, tmp_path):
    V_rest, F = plate
    rest, current = tmp_path / "rest.obj", tmp_path / "current.obj"
    flexure.write_mesh(rest, V_rest, F)
    flexure.write_mesh(current, bent(V_rest, seed=7), F)
    args = ["energy", "--energy", name, "--rest", rest, "--current", current, "--json"]
    expected = cli.json(*args, *(["--linearized"] if linearized else []))

    V_rest, F = flexure.read_mesh(rest)
    V, _ = flexure.read_mesh(current)
    got = flexure.energy(V_rest, F, V, energy=name, linearized=linearized)
    assert got["energy"] > 0
    assert relative(got["energy"], expected["energy"]) <= 1e-14
    assert relative(got["energy_per_area"], expected["energy_per_area"]) <= 1e-14
    assert relative(got["covered_area"], expected["covered_area"]) <= 1e-14
    for key in ("energy_name", "elements", "element_kind", "poisson", "stiffness", "linearized"):
        assert got[key] == expected[key], key
    for key in ("vertex_area", "hinge_angle", "boundary_xi"):
        assert got.get(key) == expected.get(key), key


@pytest.mark.parametrize("linearized", [False, True])
def test_midedge_clamped_energy_equals_cli(linearized, plate, cli, tmp_path):
    V_rest, F = plate
    V = V_rest.copy()
    V[:, 2] = V[:, 0] ** 2 + 0.5 * V[:, 1] ** 2
    rest, current = tmp_path / "rest.obj", tmp_path / "current.obj"
    flexure.write_mesh(rest, V_rest, F)
    flexure.write_mesh(current, V, F)
    surface = "quadratic:1,0,0.5"
    expected = cli.json("energy", "--energy", "midedge", "--rest", rest, "--current", current,
                        "--boundary-surface", surface, "--json",
                        *(["--linearized"] if linearized else []))
    got = flexure.energy(V_rest, F, V, energy="midedge", boundary_surface=surface,
                         linearized=linearized)
    assert got["boundary_xi"] == expected["boundary_xi"] == "clamped to " + surface
    assert relative(got["energy"], expected["energy"]) <= 1e-14


def test_energy_options_reach_the_library(plate):
    V_rest, F = plate
    V = bent(V_rest, seed=3)
    base = flexure.energy(V_rest, F, V, energy="triavg")
    stiff = flexure.energy(V_rest, F, V, energy="triavg", stiffness=2.5)
    other_nu = flexure.energy(V_rest, F, V, energy="triavg", poisson=0.1)
    assert relative(stiff["energy"], 2.5 * base["energy"]) <= 1e-14
    assert other_nu["poisson"] == 0.1 and other_nu["energy"] != base["energy"]
    # Zero at rest, for every energy.
    for name in ENERGIES:
        at_rest = flexure.energy(V_rest, F, V_rest, energy=name)["energy"]
        assert at_rest == pytest.approx(0, abs=1e-20)


@pytest.mark.parametrize("name", ENERGIES)
@pytest.mark.parametrize("flat_rest", [False, True])
def test_curved_rest_energy_equals_cli(name, flat_rest, cli, tmp_path):
    # A shell: the rest mesh is curved; flat_rest keeps only its metric.
    V_flat, F = flexure.mesh("delaunay", 5, seed=2)
    V_rest = bent(V_flat, seed=1, amplitude=0.01)
    rest, current = tmp_path / "rest.off", tmp_path / "current.off"
    flexure.write_mesh(rest, V_rest, F)
    flexure.write_mesh(current, bent(V_rest, seed=9), F)
    expected = cli.json("energy", "--energy", name, "--rest", rest, "--current", current, "--json",
                        *(["--flat-rest"] if flat_rest else []))
    got = flexure.energy(V_rest, F, flexure.read_mesh(current)[0], energy=name,
                         flat_rest=flat_rest)
    assert relative(got["energy"], expected["energy"]) <= 1e-14
