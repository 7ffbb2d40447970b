"""flexure.Simulation's contact options (mesh obstacles, self-contact, friction) against
`flexure simulate --obstacle mesh:FILE@MOTION`, and their refusals."""

import json

import numpy as np
import pytest

import flexure


def box(lo, hi):
    """The box [lo, hi] as 12 outward triangles: (V, F)."""
    V = np.array([[(hi if v & 1 else lo)[0], (hi if v & 2 else lo)[1], (hi if v & 4 else lo)[2]]
                  for v in range(8)], dtype=float)
    F = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
    return V, F


def test_a_moving_mesh_obstacle_equals_the_cli(cli, plate, tmp_path):
    # A box rising at 0.5 under a plate held by its boundary ring, with friction: the same frames
    # and the same contact report from the command and from Python.
    V, F = plate
    B, G = box([-0.2, -0.2, -0.3], [0.2, 0.2, -0.02])
    flexure.write_mesh(tmp_path / "plate.obj", V, F)
    flexure.write_mesh(tmp_path / "box.obj", B, G)
    cli("-q", "simulate", "--rest", tmp_path / "plate.obj", "--energy", "hinge", "--membrane",
        "stvk", "--pin", "rings:1", "--obstacle", f"mesh:{tmp_path / 'box.obj'}@translate:0,0,0.5",
        "--friction", "0.3", "--dt", "0.01", "--duration", "0.1", "--fps", "100",
        "--render-style", "none", "-o", tmp_path / "run")
    s = flexure.Simulation(V, F, energy="hinge", membrane="stvk", pinned=1, friction=0.3,
                           mesh_obstacles=[(B, G, {"translate": [0, 0, 0.5]})])
    for k in range(1, 11):
        s.step(0.01)
        frame, _ = flexure.read_mesh(tmp_path / "run" / f"frame-{k:05d}.obj")
        assert np.abs(s.positions - frame).max() <= 1e-12
    # The box's top is at 0.03 at t = 0.1: it lifted the plate's middle above it.
    assert s.positions[:, 2].max() > 0.03
    report = json.loads((tmp_path / "run" / "report.json").read_text())
    contact = s.contact()
    assert contact["peak_pairs"] == report["contact"]["pairs_per_step"]["peak"] > 0
    assert contact["mean_pairs"] == pytest.approx(report["contact"]["pairs_per_step"]["mean"])
    assert contact["smallest_distance"] == pytest.approx(report["contact"]["smallest_distance"],
                                                         rel=1e-12)
    assert 0.0 < contact["smallest_distance"] < contact["offset"]


def test_self_contact_off_and_offset(plate):
    V, F = plate
    on = flexure.Simulation(V, F, energy="hinge", membrane="stvk", pinned=1,
                            contact_offset=0.02)
    off = flexure.Simulation(V, F, energy="hinge", membrane="stvk", pinned=1,
                             self_contact=False)
    assert on.contact()["self_contact"] and on.contact()["offset"] == 0.02
    assert not off.contact()["self_contact"]


@pytest.mark.parametrize("obstacles, name", [
    ([(np.zeros((3, 3)), np.array([[0, 1, 2, 0]]), None)], r"mesh_obstacles\[0\] F"),
    ([(np.eye(3), np.array([[0, 1, 3]]), None)], r"mesh_obstacles\[0\] F"),
    ([(np.eye(3), np.array([[0, 1, 2]]), {"spin": 1})], r"mesh_obstacles\[0\] motion"),
    ([(np.eye(3), np.array([[0, 1, 2]]))], r"mesh_obstacles\[0\]"),
    ("box.obj", "mesh_obstacles"),
    # A box through the plate at the start.
    ([box([-0.2, -0.2, -0.1], [0.2, 0.2, 0.1]) + (None,)], "mesh_obstacles"),
])
def test_bad_mesh_obstacles_name_themselves(plate, obstacles, name):
    V, F = plate
    with pytest.raises(ValueError, match=name):
        flexure.Simulation(V, F, energy="hinge", membrane="stvk", pinned=1,
                           mesh_obstacles=obstacles)


@pytest.mark.parametrize("arguments, name", [
    ({"contact_offset": 0.0}, "contact_offset"),
    ({"contact_offset": -1.0}, "contact_offset"),
    ({"friction": -0.5}, "friction"),
])
def test_bad_contact_options_name_themselves(plate, arguments, name):
    V, F = plate
    with pytest.raises(ValueError, match=name):
        flexure.Simulation(V, F, energy="hinge", membrane="stvk", pinned=1, **arguments)
