"""Pins, plasticity and fracture from Python (issue #29), on the real library, with known answers:
a plate bent cylindrically to κ springs back to (κ − κ_y)/(1 + γ) (statics); a free plate released
from a bend keeps kinetic + elastic + plastic dissipation at its start (undamped Newmark); a strip
held at one end and pulled at the other by its own pin group tears into two fragments whose rest
areas add to the strip's; bad options raise the library's ValueError naming the field."""

import csv
import json

import numpy as np
import pytest

import flexure

LEFT, RIGHT = "box:-0.6,-0.45,-1,1,-1,1", "box:0.45,0.6,-1,1,-1,1"


def fitted_curvatures(X):
    """Eigenvalues (ascending) of the Hessian of the least-squares
    z = ½ (A x² + 2 B x y + C y²) + D x + E y + F over all vertices."""
    x, y, z = X[:, 0], X[:, 1], X[:, 2]
    M = np.column_stack([np.ones_like(x), x, y, x * x / 2, x * y, y * y / 2])
    c = np.linalg.lstsq(M, z, rcond=None)[0]
    return np.linalg.eigvalsh([[c[3], c[4]], [c[4], c[5]]])


def total_area(V, F):
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    return 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1).sum()


def strip():
    """patch48 n = 8 with y scaled by ¼: the strip [−½, ½] × [−⅛, ⅛] of tests/cli_pin_groups.sh."""
    V, F = flexure.mesh("patch48", 8)
    V[:, 1] *= 0.25
    return V, F


def pulled_strip(V, F, fracture_strain):
    """tests/cli_pin_groups.sh's tear: one end still, the other pulled at 0.05 L/s."""
    return flexure.Simulation(V, F, energy="hinge",
                              pin_groups=[LEFT, (RIGHT, {"translate": (0.05, 0, 0)})],
                              rayleigh=(5, 0.01), fracture_strain=fracture_strain, thickness=0.01)


def test_springback_keeps_the_reduced_curvature():
    # tests/test_plasticity.cpp CylinderSpringsBackToTheReducedCurvature (midedge, Delaunay, 2 %).
    kappa, kappa_y, gamma = 0.2, 0.1, 0.5
    assert gamma * (kappa - kappa_y) / (1 + gamma) < kappa_y  # no reverse yield
    V, F = flexure.mesh("delaunay", 12)
    problem = flexure.Problem(V, F, energy="midedge", boundary_surface=f"quadratic:{kappa / 2},0,0")
    before = problem.start_positions.copy()
    formed, report = flexure.form(problem, yield_curvature=kappa_y, hardening=gamma,
                                  load_steps=4, release=True)
    expected = (kappa - kappa_y) / (1 + gamma)
    curvatures = fitted_curvatures(formed)
    assert curvatures[1] == pytest.approx(expected, rel=0.02)
    assert abs(curvatures[0]) < 0.02 * expected
    assert report["converged"] and report["dissipation"] > 0 and len(report["release_pins"]) == 3
    assert report["plastic_strain"].shape == (F.shape[0], 3) and report["yielded"].any()
    # The equivalent plastic curvature is the kept curvature (plasticity.h) in the interior.
    assert np.median(report["plastic_curvature"][report["yielded"]]) == pytest.approx(
        expected, rel=0.05)
    assert np.array_equal(problem.start_positions, before)  # the Problem given is not changed


def test_below_the_yield_curvature_it_comes_back_flat():
    V, F = flexure.mesh("delaunay", 12)
    formed, report = flexure.form(V, F, energy="midedge", boundary_surface="quadratic:0.045,0,0",
                                  yield_curvature=0.1, hardening=0.5, load_steps=3, release=True)
    assert report["yielded_elements"] == 0 and report["dissipation"] == 0.0
    M = np.column_stack([np.ones(len(formed)), formed[:, 0], formed[:, 1]])
    plane = M @ np.linalg.lstsq(M, formed[:, 2], rcond=None)[0]
    assert np.abs(plane - formed[:, 2]).max() < 1e-8


def face_green_strains(V_rest, F, X):
    """Per face the Green strain ½(DᵀD − I) of X against the flat rest mesh, (ε_xx, ε_xy, ε_yy)."""
    rest = np.stack([V_rest[F[:, 1]] - V_rest[F[:, 0]], V_rest[F[:, 2]] - V_rest[F[:, 0]]], 2)
    now = np.stack([X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]], 2)
    D = now @ np.linalg.inv(rest[:, :2, :])
    E = 0.5 * (np.transpose(D, (0, 2, 1)) @ D - np.eye(2))
    return np.column_stack([E[:, 0, 0], E[:, 0, 1], E[:, 1, 1]])


def test_a_released_stretched_strip_keeps_the_reduced_strain():
    # tests/test_plasticity.cpp ReleasedStripKeepsTheReducedStrain: stretched to ε with its width
    # held, released, every face keeps diag((ε − ε_y)/(1 + γ), 0) to 2 %.
    epsilon, epsilon_y, gamma = 0.03, 0.01, 0.5
    kept = (epsilon - epsilon_y) / (1 + gamma)
    V, F = flexure.mesh("criss", 12)
    stretched = V.copy()
    stretched[:, 0] *= np.sqrt(1 + 2 * epsilon)
    formed, report = flexure.form(V, F, energy="hinge", dof="xyz", membrane="stvk",
                                  fixed_rings=1, boundary_positions=stretched,
                                  yield_strain=epsilon_y, hardening=gamma, load_steps=3,
                                  release=True)
    strain = face_green_strains(V, F, formed)
    assert np.abs(strain[:, 0] - kept).max() < 0.02 * kept
    assert np.abs(strain[:, 1:]).max() < 0.02 * kept
    assert report["yielded_faces"] == F.shape[0] and report["membrane_yielded"].all()
    assert report["membrane_plastic_strain"].shape == (F.shape[0], 3)
    assert report["yielded_elements"] == 0 and report["plastic_strain"].shape[0] == 0


@pytest.mark.parametrize("energy", ["hinge", "midedge"])
def test_undamped_membrane_plastic_run_balances(energy):
    # tests/test_plastic_dynamics.cpp (MembranePlasticDynamics): a free plate at rest given the
    # stretching velocity (3 x̄, 0, 0); measured 0.015 % at h = 0.001, 87 % dissipated.
    V, F = flexure.mesh("delaunay", 10)
    velocities = np.zeros_like(V)
    velocities[:, 0] = 3.0 * V[:, 0]
    s = flexure.Simulation(V, F, energy=energy, velocities=velocities, yield_strain=0.01,
                           hardening=0.5)

    def kinetic_and_elastic():
        e = s.energies()
        return e["total"] - e["gravity"] - e["contact"]

    start = kinetic_and_elastic()
    assert s.plastic_dissipation == 0.0  # the start is unstrained
    dissipation, largest_error = 0.0, 0.0
    for _ in range(100):
        s.step(0.001)
        assert s.plastic_dissipation >= dissipation  # never decreases
        dissipation = s.plastic_dissipation
        largest_error = max(largest_error,
                            abs(kinetic_and_elastic() + dissipation - start) / start)
    assert largest_error < 0.01
    assert dissipation > 0.5 * start
    assert s.membrane_plastic_strain.shape == (F.shape[0],)
    assert s.membrane_plastic_strain.max() > 0.0
    assert s.vertex_membrane_plastic_strain.shape == (V.shape[0],)
    assert (s.plastic_curvature == 0).all()  # no yield curvature: bending stays elastic


def bent(V, kappa):
    """V rolled isometrically onto a cylinder of curvature κ about the y axis."""
    X = V.copy()
    angle = kappa * V[:, 0]
    X[:, 0] = np.sin(angle) / kappa
    X[:, 2] = (1 - np.cos(angle)) / kappa
    return X


@pytest.mark.parametrize("energy", ["hinge", "midedge"])
def test_undamped_plastic_run_balances_kinetic_elastic_and_dissipation(energy):
    # tests/test_plastic_dynamics.cpp: measured 0.004 % (hinge), 0.42 % (midedge) at h = 0.005.
    V, F = flexure.mesh("delaunay", 10)
    s = flexure.Simulation(V, F, energy=energy, V_start=bent(V, 0.1), yield_curvature=0.05,
                           hardening=0.5)

    def kinetic_and_elastic():
        e = s.energies()
        return e["total"] - e["gravity"] - e["contact"]

    # The start is outside the yield surface: it yields at once, before the first step.
    start = kinetic_and_elastic() + s.plastic_dissipation
    dissipation, largest_error = 0.0, 0.0
    for _ in range(80):
        s.step(0.005)
        assert s.plastic_dissipation >= dissipation  # never decreases
        dissipation = s.plastic_dissipation
        assert s.energies()["plastic_dissipation"] == dissipation
        largest_error = max(largest_error,
                            abs(kinetic_and_elastic() + dissipation - start) / start)
    assert largest_error < 0.01
    assert dissipation > 0.3 * start
    assert s.balance()["plastic_dissipation"] == dissipation
    # Per face for every energy: the hinge's angles read as a tensor per face (every face of the
    # plate has an interior edge).
    assert s.plastic_strain.shape == (F.shape[0], 3)
    assert s.yielded.shape == s.plastic_curvature.shape == (F.shape[0],)
    assert s.plastic_element == "face"
    assert s.yielded.any() and (s.plastic_curvature[~s.yielded] == 0).all()
    assert s.vertex_plastic_curvature.shape == (V.shape[0],)


def test_nothing_yields_below_the_yield_curvature_and_the_motion_is_the_elastic_one():
    V, F = flexure.mesh("delaunay", 10)
    elastic = flexure.Simulation(V, F, energy="midedge", V_start=bent(V, 0.02))
    plastic = flexure.Simulation(V, F, energy="midedge", V_start=bent(V, 0.02),
                                 yield_curvature=0.1)
    elastic.run(0.1, 0.01)
    plastic.run(0.1, 0.01)
    assert np.array_equal(elastic.positions, plastic.positions)
    assert plastic.plastic_dissipation == 0.0 and not plastic.yielded.any()
    with pytest.raises(ValueError, match="no plasticity"):
        elastic.plastic_strain


def test_pin_groups_follow_their_own_motions():
    # tests/cli_pin_groups.sh: after 0.1 s the right end moved by (0.02, 0, 0.01) exactly.
    V, F = strip()
    s = flexure.Simulation(V, F, energy="hinge",
                           pin_groups=[LEFT, (RIGHT, {"translate": (0.2, 0, 0.1)})])
    s.run(0.1, 0.01)
    right, left = V[:, 0] >= 0.45, V[:, 0] <= -0.45
    assert np.abs(s.positions[right] - V[right] - [0.02, 0, 0.01]).max() < 1e-12
    assert np.array_equal(s.positions[left], V[left])
    assert np.array_equal(s.pinned, left | right)
    assert not s.balance()["checked"]  # moving pins do work


def test_a_group_let_go_at_its_release_time():
    # tests/cli_pin_groups.sh's dropped strip: both ends held under gravity, the right one let go
    # at 0.055 s (inside the sixth step, which is split there): it stays exactly at rest until
    # then, and falls after.
    V, F = strip()
    s = flexure.Simulation(V, F, energy="hinge", gravity=(0, 0, -9.81),
                           pin_groups=[LEFT, (RIGHT, None, 0.055)])
    right = V[:, 0] >= 0.45
    for k in range(10):
        assert s.advance(0.01)["completed"]
        if s.time < 0.055:
            assert np.array_equal(s.positions[right], V[right])
    assert s.time == pytest.approx(0.1)
    assert (s.positions[right][:, 2] < -1e-3).all()
    assert not s.pinned[right].any()
    assert s.balance()["checked"]  # no pin moves


def test_a_rotating_group_and_a_still_one():
    # The left end turns about the x axis through its centre (counter-clockwise, ω = 2 rad/s)
    # while the right one stays: after 0.1 s the left pins are rotated by 0.2 rad exactly.
    V, F = strip()
    s = flexure.Simulation(V, F, energy="hinge",
                           pin_groups=[(LEFT, {"rotate": ((1, 0, 0), (-0.5, 0, 0), 2.0)}),
                                       (RIGHT, None)])
    s.run(0.1, 0.01)
    left, right = V[:, 0] <= -0.45, V[:, 0] >= 0.45
    c, d = np.cos(0.2), np.sin(0.2)
    expected = V[left] @ np.array([[1, 0, 0], [0, c, d], [0, -d, c]])
    assert np.abs(s.positions[left] - expected).max() < 1e-12
    assert np.array_equal(s.positions[right], V[right])


def test_a_strip_pulled_apart_tears_into_two_fragments_that_keep_the_rest_area():
    V, F = strip()
    s = pulled_strip(V, F, 0.01)
    s.run(0.3, 0.005)
    cracks = s.cracks()
    assert cracks and all(c["strain"] >= 0.01 for c in cracks)
    assert [c["time"] for c in cracks] == sorted(c["time"] for c in cracks)
    # Across the load: every crack point off the outer boundary at x̄ = 0.375.
    inside = np.vstack([c["polyline_rest"] for c in cracks])
    inside = inside[np.abs(np.abs(inside[:, 1]) - 0.125) > 1e-12]
    assert len(inside) >= 7 and np.abs(inside[:, 0] - 0.375).max() < 1e-12
    assert cracks[-1]["polyline_current"].shape == cracks[-1]["polyline_rest"].shape
    fragments = s.fragments(rest=True)
    assert len(fragments) == 2 and cracks[-1]["fragments"] == 2
    assert sum(total_area(Vf, Ff) for Vf, Ff in fragments) == pytest.approx(
        total_area(V, F), rel=1e-12)
    # The current mesh is the cut one, and the fragments have its every vertex.
    X, T = s.mesh
    assert X.shape == s.V_rest.shape and X.shape[0] > V.shape[0] and T.shape[0] > F.shape[0]
    current = s.fragments()
    assert sum(len(Vf) for Vf, _ in current) == X.shape[0]
    # The pieces separate.
    a, b = (Vf for Vf, _ in current)
    assert np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2).min() > 0.005


def test_no_crack_below_the_fracture_strain():
    V, F = strip()
    s = pulled_strip(V, F, 0.5)
    s.run(0.1, 0.01)
    assert s.cracks() == [] and len(s.fragments()) == 1
    assert np.array_equal(s.F, F)


@pytest.mark.parametrize("arguments, field", [
    ({"yield_curvature": -1.0}, "^yield_curvature"),
    ({"yield_curvature": 0.1, "hardening": -0.5}, "^hardening"),
    ({"fracture_strain": 0.0}, "^fracture_strain"),
    ({"fracture_strain": 0.01, "thickness": -0.01}, "^thickness"),
    ({"yield_curvature": 0.1, "energy": "cotan"}, "cotan"),
    ({"hardening": 0.5}, "hardening"),
    ({"thickness": 0.01}, "thickness"),
    ({"yield_strain": 0.01, "membrane": "mips"},
     "^yield_strain: membrane plasticity moves the rest metric of membrane stvk"),
    ({"pin_groups": [LEFT, "box:-0.6,-0.4,-1,1,-1,1"]}, "^pin_groups"),
    ({"pin_groups": [LEFT, (RIGHT, {"rotate": ((0, 0, 0), (0, 0, 0), 1.0)})]},
     r"pin_groups\[1\] motion: axis: the axis is zero"),
    ({"pin_groups": [LEFT, (RIGHT, {"spin": 1.0})]}, r"pin_groups\[1\] motion"),
    ({"pin_groups": [LEFT, "box:nonsense"]}, r"pin_groups\[1\]"),
    ({"pin_groups": [LEFT, (RIGHT, None, 0.0)]}, "pin_groups release time 0: expected a time > 0"),
    ({"pin_groups": [LEFT, (RIGHT, None, float("nan"))]}, r"pin_groups\[1\] release time"),
    ({"pin_groups": [LEFT, (RIGHT, None, 1.0, 2.0)]}, r"pin_groups\[1\]: expected"),
    ({"pin_groups": [LEFT], "pinned": 1}, "pin_groups"),
])
def test_bad_simulation_options_raise_naming_the_field(arguments, field):
    V, F = strip()
    arguments = {"energy": "hinge", **arguments}
    with pytest.raises(ValueError, match=field):
        flexure.Simulation(V, F, **arguments)


@pytest.mark.parametrize("arguments, field", [
    ({"yield_curvature": 0.0}, "^yield_curvature"),
    ({"yield_curvature": 0.1, "load_steps": 0}, "^load_steps"),
    ({"yield_curvature": 0.1, "hardening": -1.0}, "^hardening"),
    ({}, "neither is given"),
])
def test_bad_forming_options_raise_naming_the_field(plate, arguments, field):
    V, F = plate
    with pytest.raises(ValueError, match=field):
        flexure.form(V, F, energy="midedge", boundary_surface="quadratic:0.1,0,0", **arguments)


def test_the_tear_equals_the_cli(cli, tmp_path):
    # The same run as flexure simulate's: the cracks of report.json and the fragment meshes.
    V, F = strip()
    flexure.write_mesh(tmp_path / "strip.obj", V, F)
    cli("-q", "simulate", "--rest", tmp_path / "strip.obj", "--energy", "hinge", "--membrane",
        "stvk", "--pin", LEFT, "--pin", RIGHT + "@translate:0.05,0,0", "--damping",
        "rayleigh:5,0.01", "--fracture-strain", "0.01", "--thickness", "0.01", "--dt", "0.005",
        "--duration", "0.3", "--fps", "20", "--render-style", "none", "-o", tmp_path / "tear")
    report = json.loads((tmp_path / "tear" / "report.json").read_text())["fracture"]
    s = pulled_strip(V, F, 0.01)
    s.run(0.3, 0.005)
    cracks = s.cracks()
    assert len(cracks) == len(report["cracks"]) >= 1
    for mine, theirs in zip(cracks, report["cracks"]):
        assert mine["time"] == theirs["time"] and mine["step"] == theirs["step"]
        assert mine["face"] == theirs["face"] and mine["fibre"] == theirs["fibre"]
        np.testing.assert_array_equal(mine["polyline_rest"], theirs["polyline_rest"])
        np.testing.assert_array_equal(mine["polyline_current"], theirs["polyline_current"])
        assert mine["released_energy"] == theirs["released_energy"]
    fragments = s.fragments()
    assert len(fragments) == report["fragments"]
    for k, (Vf, Ff) in enumerate(fragments):
        written, written_F = flexure.read_mesh(tmp_path / "tear" / f"fragment-{k}.obj")
        np.testing.assert_array_equal(Vf, written)
        np.testing.assert_array_equal(Ff, written_F)


def test_plastic_dissipation_equals_the_cli(cli, tmp_path):
    # flexure simulate --yield-curvature on the bent free plate: energies.csv's
    # plastic_dissipation column, step by step, and report.json's plasticity section.
    V, F = flexure.mesh("delaunay", 10)
    flexure.write_mesh(tmp_path / "plate.obj", V, F)
    flexure.write_mesh(tmp_path / "bent.obj", bent(V, 0.1), F)
    cli("-q", "simulate", "--rest", tmp_path / "plate.obj", "--init", tmp_path / "bent.obj",
        "--energy", "midedge", "--membrane", "stvk", "--yield-curvature", "0.05", "--hardening",
        "0.5", "--dt", "0.005", "--duration", "0.05", "--fps", "20", "--render-style", "none",
        "-o", tmp_path / "run")
    rows = list(csv.DictReader((tmp_path / "run" / "energies.csv").open()))
    report = json.loads((tmp_path / "run" / "report.json").read_text())["plasticity"]
    s = flexure.Simulation(V, F, energy="midedge", V_start=bent(V, 0.1), yield_curvature=0.05,
                           hardening=0.5)
    assert s.energies()["plastic_dissipation"] == pytest.approx(
        float(rows[0]["plastic_dissipation"]), rel=1e-12)
    for row in rows[1:]:
        s.step(0.005)
        assert s.energies()["plastic_dissipation"] == pytest.approx(
            float(row["plastic_dissipation"]), rel=1e-12)
    assert s.plastic_dissipation == pytest.approx(report["plastic_dissipation"], rel=1e-12)
    assert list(np.flatnonzero(s.yielded)) == report["yielded"]
    assert s.plastic_curvature.max() == pytest.approx(report["largest_plastic_curvature"],
                                                      rel=1e-12)


def test_plastic_tear_equals_the_cli(cli, tmp_path):
    # Plasticity with fracture (the cuts carry the plastic strains, plastic_dynamics.h): the
    # pulled strip with yield_curvature and yield_strain yields, then tears, as flexure simulate
    # runs it — the same cracks, dissipation and yielded faces on the cut mesh.
    V, F = strip()
    flexure.write_mesh(tmp_path / "strip.obj", V, F)
    cli("-q", "simulate", "--rest", tmp_path / "strip.obj", "--energy", "hinge", "--membrane",
        "stvk", "--pin", LEFT, "--pin", RIGHT + "@translate:0.05,0,0", "--damping",
        "rayleigh:5,0.01", "--fracture-strain", "0.01", "--thickness", "0.01", "--yield-curvature",
        "0.02", "--yield-strain", "0.005", "--dt", "0.005", "--duration", "0.3", "--fps", "20",
        "--render-style", "none", "-o", tmp_path / "tear")
    report = json.loads((tmp_path / "tear" / "report.json").read_text())
    s = flexure.Simulation(V, F, energy="hinge",
                           pin_groups=[LEFT, (RIGHT, {"translate": (0.05, 0, 0)})],
                           rayleigh=(5, 0.01), fracture_strain=0.01, thickness=0.01,
                           yield_curvature=0.02, yield_strain=0.005)
    dissipation = []
    for _ in range(60):
        s.step(0.005)
        dissipation.append(s.plastic_dissipation)
    cracks = s.cracks()
    assert len(cracks) == len(report["fracture"]["cracks"]) >= 1
    assert [c["time"] for c in cracks] == [c["time"] for c in report["fracture"]["cracks"]]
    first = int(round(cracks[0]["time"] / 0.005))
    assert dissipation[first - 2] > 0  # yielded before the tear
    assert all(b >= a for a, b in zip(dissipation, dissipation[1:]))
    assert s.plastic_dissipation == pytest.approx(report["plasticity"]["plastic_dissipation"],
                                                  rel=1e-12)
    assert list(np.flatnonzero(s.yielded)) == report["plasticity"]["yielded"]
    assert s.membrane_plastic_strain.shape == (s.F.shape[0],)
