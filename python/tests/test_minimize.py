"""minimize from Python equals `flexure minimize`'s output mesh; the linearized solver's many
solves equal one-off solves."""

import json

import numpy as np
import pytest

import flexure


@pytest.mark.parametrize("name", ["hinge", "midedge", "cotan"])
def test_minimize_equals_cli(name, cli, tmp_path):
    V_rest, F = flexure.mesh("patch48", 8)
    rest, out, report_file = tmp_path / "rest.obj", tmp_path / "out.obj", tmp_path / "r.json"
    flexure.write_mesh(rest, V_rest, F)
    surface = "quadratic:1,0.3,0.5"
    cli("minimize", "--quiet", "--rest", rest, "--energy", name, "--boundary", surface,
        "-o", out, "--report", report_file)
    expected_V, expected_F = flexure.read_mesh(out)
    expected = json.loads(report_file.read_text())

    V, report = flexure.minimize(V_rest, F, energy=name, boundary_surface=surface)
    assert np.array_equal(expected_F, F)
    assert report["converged"] and expected["converged"]
    assert np.array_equal(V, expected_V)  # the CLI writes round-trip decimals: exact
    assert report["final_energy"] == expected["final_energy"]
    assert report["iterations"] == expected["iterations"]
    assert report["problem"] == expected["problem"]
    if name == "midedge":
        assert np.array_equal(report["xi"], expected["xi"])
    # A Problem object gives the same.
    problem = flexure.Problem(V_rest, F, energy=name, boundary_surface=surface)
    V2, _ = flexure.minimize(problem)
    assert np.array_equal(V2, V)
    # The Problem's own gradient at the minimizer is the solver's final one.
    g = problem.gradient(problem.to_free(V, report.get("xi")))
    assert np.linalg.norm(g) == pytest.approx(report["final_gradient_norm"], rel=1e-6)


def test_threads_do_not_change_the_minimizer():
    V_rest, F = flexure.mesh("patch48", 8)
    one, _ = flexure.minimize(V_rest, F, energy="hinge", boundary_surface="quadratic:1,0,1",
                              threads=1)
    two, _ = flexure.minimize(V_rest, F, energy="hinge", boundary_surface="quadratic:1,0,1",
                              threads=2)
    assert np.abs(one - two).max() <= 1e-12


SURFACES = ["quadratic:1,0,1", "quadratic:0.2,-0.5,0.7", "quadratic:-1,0.4,0",
            "polynomial:x^3-3*x*y^2", "quadratic:0,1,0"]


@pytest.mark.parametrize("name", ["hinge", "midedge", "quadfit"])
def test_many_linearized_solves_equal_one_off_solves(name):
    V_rest, F = flexure.mesh("patch48", 8)
    problems = [flexure.Problem(V_rest, F, energy=name, boundary_surface=s, linearized_clamp=True)
                for s in SURFACES]
    solver = flexure.LinearizedSolver(problems[0])
    assert solver.factorizations == 1
    for problem in problems:
        V, info = solver.solve(problem.start_positions, problem.start_xi)
        one_off, report = flexure.minimize(problem, linearized=True)
        assert report["solver"] == "linearized"
        scale = np.abs(one_off).max()
        assert np.abs(V - one_off).max() <= 1e-12 * scale
        assert info["energy"] == pytest.approx(report["final_energy"], rel=1e-10)
        if name == "midedge":
            assert np.abs(info["xi"] - report["xi"]).max() <= 1e-10 * np.abs(report["xi"]).max()
    assert solver.factorizations == 1  # solves never refactor


def test_linearized_solver_clamp_follows_the_boundary_values():
    # midedge holds its boundary ξ at the clamp of the problem's surface: other held values
    # without their ξ would keep that clamp (off by about 1 %), so they are refused; with their ξ
    # the solve equals the one-off solve of their problem.
    V_rest, F = flexure.mesh("patch48", 8)
    first, other = (flexure.Problem(V_rest, F, energy="midedge", boundary_surface=s,
                                    linearized_clamp=True) for s in SURFACES[:2])
    solver = flexure.LinearizedSolver(first)
    with pytest.raises(ValueError, match="^held ξ: the problem holds ξ on its boundary edges"):
        solver.solve(other.start_positions)
    V, _ = solver.solve(other.start_positions, other.start_xi)
    one_off, _ = flexure.minimize(other, linearized=True)
    assert np.abs(V - one_off).max() <= 1e-12 * np.abs(one_off).max()
    V, _ = solver.solve(first.start_positions)  # its own values: its own clamp
    one_off, _ = flexure.minimize(first, linearized=True)
    assert np.abs(V - one_off).max() <= 1e-12 * np.abs(one_off).max()


def test_linearized_solver_refuses_in_plane_moves_it_was_not_built_for():
    V_rest, F = flexure.mesh("patch48", 6)
    problem = flexure.Problem(V_rest, F, energy="hinge")
    B = V_rest.copy()
    B[0, 0] += 0.1
    with pytest.raises(ValueError):
        flexure.LinearizedSolver(problem).solve(B)
    V, info = flexure.LinearizedSolver(problem, in_plane=True).solve(B)
    assert V[0, 0] == B[0, 0]


def test_minimize_with_gravity_equals_cli(cli, tmp_path):
    V_rest, F = flexure.mesh("patch48", 8)
    rest, out = tmp_path / "rest.obj", tmp_path / "out.obj"
    flexure.write_mesh(rest, V_rest, F)
    cli("minimize", "--quiet", "--rest", rest, "--energy", "triavg", "--boundary",
        "quadratic:0.5,0,0", "--gravity", "0,0,-9.81", "-o", out)
    V, report = flexure.minimize(V_rest, F, energy="triavg", boundary_surface="quadratic:0.5,0,0",
                                 gravity=(0, 0, -9.81))
    assert np.array_equal(V, flexure.read_mesh(out)[0])
    no_load, _ = flexure.minimize(V_rest, F, energy="triavg", boundary_surface="quadratic:0.5,0,0")
    free = ~flexure.Problem(V_rest, F, energy="triavg").fixed
    assert np.all(V[free, 2] < no_load[free, 2])  # the load pulls the free vertices down


def test_minimize_xyz_membrane_from_positions_equals_cli(cli, tmp_path):
    V_rest, F = flexure.mesh("patch48", 6)
    init = V_rest.copy()
    init[:, :2] *= 0.9  # the held rings pushed inwards: the plate buckles
    init[:, 2] = 0.05 * (0.25 - V_rest[:, 0] ** 2)
    rest, start, out = tmp_path / "rest.obj", tmp_path / "init.obj", tmp_path / "out.obj"
    flexure.write_mesh(rest, V_rest, F)
    flexure.write_mesh(start, init, F)
    cli("minimize", "--quiet", "--rest", rest, "--energy", "hinge", "--dof", "xyz", "--membrane",
        "stvk", "--init", start, "-o", out)
    V, report = flexure.minimize(V_rest, F, energy="hinge", dof="xyz", membrane="stvk",
                                 boundary_positions=init, start="given")
    assert report["dof"] == "xyz" and report["converged"]
    assert np.array_equal(V, flexure.read_mesh(out)[0])
