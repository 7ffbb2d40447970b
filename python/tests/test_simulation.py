"""flexure.Simulation against `flexure simulate`'s frames, its energy balance and its errors."""

import threading
import time

import numpy as np
import pytest

import flexure
from conftest import bent


@pytest.mark.parametrize("pairs", [0, 6])  # chord steps, L-BFGS steps on the kept factor
def test_steps_equal_the_cli_frames(cli, plate, tmp_path, pairs):
    V, F = plate
    flexure.write_mesh(tmp_path / "plate.obj", V, F)
    cli("-q", "simulate", "--rest", tmp_path / "plate.obj", "--energy", "midedge", "--membrane",
        "stvk", "--pin", "rings:2", "--gravity", "0,0,-9.81", "--damping", "rayleigh:2,0",
        "--dt", "0.01", "--duration", "0.05", "--fps", "100", "--render-style", "none",
        "--quasi-newton-pairs", str(pairs), "-o", tmp_path / "run")
    s = flexure.Simulation(V, F, energy="midedge", membrane="stvk", pinned=2,
                           gravity=[0, 0, -9.81], rayleigh=(2, 0), quasi_newton_pairs=pairs)
    chord = flexure.Simulation(V, F, energy="midedge", membrane="stvk", pinned=2,
                               gravity=[0, 0, -9.81], rayleigh=(2, 0))
    diagonal = np.linalg.norm(V.max(0) - V.min(0))
    frame0, _ = flexure.read_mesh(tmp_path / "run" / "frame-00000.obj")
    np.testing.assert_array_equal(s.positions, frame0)
    moved = 0.0
    for k in range(1, 6):
        report = s.step(0.01)
        assert report["completed"] and report["steps"] >= 1
        frame, _ = flexure.read_mesh(tmp_path / "run" / f"frame-{k:05d}.obj")
        assert np.abs(s.positions - frame).max() <= 1e-12
        moved = max(moved, np.abs(frame - V).max())
        chord.step(0.01)  # L-BFGS steps follow the chord steps' motion
        assert np.abs(s.positions - chord.positions).max() <= 1e-3 * diagonal
    assert moved > 1e-4  # gravity moved the plate: the comparison is not of rest with rest
    assert s.time == pytest.approx(0.05)
    assert s.pinned.sum() == flexure.boundary_rings(V, F, 2).sum()


def test_start_positions_and_voronoi_masses_equal_the_cli(cli, plate, tmp_path):
    V, F = plate
    W = bent(V, 11, amplitude=0.01)
    flexure.write_mesh(tmp_path / "plate.obj", V, F)
    flexure.write_mesh(tmp_path / "init.obj", W, F)
    cli("-q", "simulate", "--rest", tmp_path / "plate.obj", "--init", tmp_path / "init.obj",
        "--energy", "cotan", "--membrane", "conformal", "--shape-stiffness", "50", "--pin",
        "rings:2", "--mass", "voronoi", "--density", "3", "--integrator", "backward-euler",
        "--dt", "0.01", "--duration", "0.03", "--fps", "100", "--render-style", "none",
        "--energy-tolerance", "10", "-o", tmp_path / "run")  # backward Euler's loss: not checked
    s = flexure.Simulation(V, F, energy="cotan", membrane={"model": "conformal",
                                                           "shape_stiffness": 50},
                           pinned="rings:2", V_start=W, mass="voronoi", density=3,
                           integrator="backward-euler")
    np.testing.assert_array_equal(s.positions, W)
    for k in range(1, 4):
        s.step(0.01)
        frame, _ = flexure.read_mesh(tmp_path / "run" / f"frame-{k:05d}.obj")
        assert np.abs(s.positions - frame).max() <= 1e-12
    np.testing.assert_array_equal(s.positions[s.pinned], W[s.pinned])
    assert s.masses.sum() == pytest.approx(3.0)


@pytest.mark.parametrize("motion, cli_motion", [
    ({"translate": [0.0, 0.0, 0.5]}, "translate:0,0,0.5"),
    ({"rotate": ([0, 1, 0], [-0.5, 0, 0], 2.0)}, "rotate:0,1,0,-0.5,0,0,2"),
])
def test_pin_motion_equals_the_cli(cli, plate, tmp_path, motion, cli_motion):
    V, F = plate
    flexure.write_mesh(tmp_path / "plate.obj", V, F)
    cli("-q", "simulate", "--rest", tmp_path / "plate.obj", "--energy", "hinge", "--membrane",
        "springs", "--pin", "rings:1", "--pin-motion", cli_motion, "--dt", "0.01",
        "--duration", "0.03", "--fps", "100", "--render-style", "none", "-o", tmp_path / "run")
    s = flexure.Simulation(V, F, energy="hinge", membrane="springs", pinned=1, pin_motion=motion)
    for k in range(1, 4):
        s.step(0.01)
        frame, _ = flexure.read_mesh(tmp_path / "run" / f"frame-{k:05d}.obj")
        assert np.abs(s.positions - frame).max() <= 1e-12
    assert np.abs(s.positions[s.pinned] - V[s.pinned]).max() > 1e-3  # the pins moved


def test_a_step_that_cannot_converge_raises_with_the_report(plate):
    V, F = plate
    s = flexure.Simulation(V, F, energy="hinge", pinned=2, gravity=[0, 0, -1e4],
                           max_newton_iterations=1, step_tolerance=1e-13)
    with pytest.raises(flexure.NumericalError) as caught:
        s.step(0.1, min_dt=0.05)
    report = caught.value.report
    assert report["completed"] is False and report["failure"]
    assert report["failed_step"] <= 0.1 and report["halvings"] >= 1
    assert s.advance(0.1, 0.05)["completed"] is False  # advance reports, never raises


def test_energies_csv_columns(cli, plate, tmp_path):
    V, F = plate
    flexure.write_mesh(tmp_path / "plate.obj", V, F)
    cli("-q", "simulate", "--rest", tmp_path / "plate.obj", "--energy", "hinge", "--membrane",
        "springs", "--pin", "rings:1", "--gravity", "0,0,-1", "--dt", "0.02", "--duration",
        "0.04", "--render-style", "none", "-o", tmp_path / "run")
    lines = (tmp_path / "run" / "energies.csv").read_text().splitlines()
    header = lines[0].split(",")
    last = dict(zip(header, map(float, lines[-1].split(","))))
    s = flexure.Simulation(V, F, energy="hinge", membrane="springs", pinned=1, gravity=[0, 0, -1])
    s.step(0.02)
    s.step(0.02)
    e = s.energies()
    for key in header:
        assert e[key] == pytest.approx(last[key], rel=1e-12, abs=1e-15), key


def test_newmark_undamped_conserves_energy(plate):
    V, F = plate
    rings = flexure.vertex_rings(V, F)
    velocities = np.zeros_like(V)
    velocities[rings >= 2, 2] = 0.5 * np.cos(np.pi * V[rings >= 2, 0])
    s = flexure.Simulation(V, F, energy="hinge", membrane="stvk", pinned=2,
                           velocities=velocities)
    start = s.energies()["total"]
    assert start > 0
    totals = []
    for _ in range(30):
        s.step(0.002)
        totals.append(s.energies()["total"])
    assert np.abs(np.array(totals) / start - 1).max() < 0.01
    assert s.energies()["hinge"] > 0.01 * start  # energy moved into bending and back
    # The balance's largest drift is the largest |E(t) - E(0)| (no damping), against the peak
    # kinetic energy (here the start's).
    b = s.balance()
    drifts = np.array(totals) - start
    assert b["largest_drift"] == pytest.approx(drifts[np.abs(drifts).argmax()], abs=1e-15)
    assert start <= b["peak_kinetic"] <= 1.01 * start
    assert b["relative_drift"] == pytest.approx(abs(b["largest_drift"]) / b["peak_kinetic"])
    assert b["checked"] and b["dissipated"] == 0


def test_masses_and_state_shapes(plate):
    V, F = plate
    s = flexure.Simulation(V, F, energy="midedge", density=2.0, pinned=np.arange(49) < 7)
    assert s.masses.shape == (49,)
    assert s.masses.sum() == pytest.approx(2.0)  # ρ × the unit square's area
    assert s.positions.shape == s.velocities.shape == (49, 3)
    assert s.xi.ndim == 1 and s.xi.size > 0
    assert s.term_names == ["midedge", "stvk"]


def test_obstacle_is_respected(plate):
    V, F = plate
    s = flexure.Simulation(bent(V, 3, 0.0), F, energy="hinge", pinned=None,
                           gravity=[0, 0, -9.81], obstacles=["plane:0,0,1,-0.05"])
    for _ in range(10):
        s.step(0.01)
    assert s.positions[:, 2].min() > -0.05
    assert s.energies()["contact"] >= 0


def test_friction_is_counted_as_dissipated(plate):
    # A sheet landing on a floor under gravity tilted along x: friction holds it back and its work
    # is part of the balance's dissipated work (no damping).
    V, F = plate
    runs = {}
    for mu in (0.0, 0.8):
        s = flexure.Simulation(V, F, energy="hinge", gravity=[3.0, 0, -9.81], friction=mu,
                               obstacles=["plane:0,0,1,-0.01"], integrator="backward-euler")
        for _ in range(10):
            s.step(0.01)
        runs[mu] = (s.positions[:, 0].mean(), s.balance()["dissipated"])
    assert runs[0.8][0] < runs[0.0][0]
    assert runs[0.0][1] == 0.0 and runs[0.8][1] > 0.0


@pytest.mark.parametrize("arguments, name", [
    ({"pinned": np.ones(3, dtype=bool)}, "pinned"),
    ({"integrator": "rk4"}, "integrator"),
    ({"membrane": None}, "membrane"),
    ({"membrane": "rubber"}, "rubber"),
    ({"gravity": [0, 0]}, "gravity"),
    ({"density": -1}, "density"),
    ({"obstacles": ["cube:1"]}, "obstacles"),
    ({"V_start": np.zeros((3, 3))}, "V_start"),
    ({"beta": 0.9}, "beta"),
    ({"pinned": "rings:x"}, "pinned"),
    ({"pinned": 2, "pin_motion": {"spin": 1}}, "pin_motion"),
    ({"pin_motion": {"translate": [0, 0, 1]}}, "pin_motion"),
    ({"pinned": 2, "pin_motion": {"rotate": ([0, 0, 0], [0, 0, 0], 1)}}, "pin_motion"),
    ({"friction": -0.1}, "friction"),
    ({"friction": float("nan")}, "friction"),
    ({"step_tolerance": 0}, "step_tolerance"),
    ({"step_tolerance": -1e-3}, "step_tolerance"),
    ({"step_tolerance": float("inf")}, "step_tolerance"),
    ({"quasi_newton_pairs": -1}, "quasi_newton_pairs"),
    ({"quasi_newton_pairs": 101}, "quasi_newton_pairs"),
    ({"quasi_newton_pairs": 2.5}, "quasi_newton_pairs"),
])
def test_bad_arguments_name_themselves(plate, arguments, name):
    V, F = plate
    with pytest.raises(ValueError, match=name):
        flexure.Simulation(V, F, energy="hinge", **arguments)


def test_step_arguments(plate):
    V, F = plate
    s = flexure.Simulation(V, F, energy="hinge", pinned=2)
    with pytest.raises(ValueError, match="h"):
        s.step(-1.0)
    with pytest.raises(ValueError, match="min_dt"):
        s.step(0.01, min_dt=0.1)


def test_the_gil_is_released_during_a_step():
    # A step of ~0.1 s in a thread: with the GIL held the main loop would stall for the whole
    # step; released, it keeps running (its longest pause is a thread switch).
    V, F = flexure.mesh("patch48", 40)

    def make():
        return flexure.Simulation(V, F, energy="midedge", pinned=2, gravity=[0, 0, -9.81])

    s = make()
    start = time.perf_counter()
    s.advance(0.01)
    alone = time.perf_counter() - start
    s = make()
    worker = threading.Thread(target=lambda: s.advance(0.01))
    longest, last = 0.0, time.perf_counter()
    worker.start()
    while worker.is_alive():
        now = time.perf_counter()
        longest, last = max(longest, now - last), now
    worker.join()
    assert s.time == pytest.approx(0.01)
    assert longest < 0.5 * alone, (longest, alone)


def test_a_run_whose_balance_drifts_beyond_the_tolerance_raises():
    # A sphere shattering on a floor with its fragments passing through each other (no
    # self-contact) gains more than 5 % of its peak kinetic energy: a numerical failure, as
    # `flexure simulate` exits 3 for it; with a loose tolerance the same run is balanced.
    V, F = flexure.mesh("sphere", 16)
    kwargs = dict(energy="hinge", membrane={"model": "stvk", "young": 1000.0},
                  gravity=[0, 0, -9.81], obstacles=["plane:0,0,1,-0.6"], fracture_strain=0.02,
                  thickness=0.01, self_contact=False)
    s = flexure.Simulation(V, F, **kwargs)
    with pytest.raises(flexure.NumericalError, match="^energy balance: gained .* beyond the 5 % "
                       "tolerance") as caught:
        s.run(0.4, 0.005)
    report = caught.value.report
    assert report["balance"]["verdict"] == "gained"
    assert report["balance"]["relative_drift"] > 0.05 and s.time == pytest.approx(0.4)
    loose = flexure.Simulation(V, F, energy_tolerance=0.5, **kwargs)
    loose.run(0.4, 0.005)
    balance = loose.balance()
    assert balance["verdict"] == "balanced" and balance["failure"] is None
    assert balance["tolerance"] == 0.5


def test_backward_euler_dissipates_without_failing(plate):
    # Undamped backward Euler dissipates numerically what no damping accounts for: the balance
    # ends "dissipated" beyond 5 %, what the scheme does; the run returns.
    V, F = plate
    s = flexure.Simulation(V, F, energy="hinge", membrane="stvk", pinned=2,
                           gravity=[0, 0, -9.81], integrator="backward-euler")
    assert len(s.run(0.2, 0.01)) == 20
    balance = s.balance()
    assert balance["verdict"] == "dissipated" and balance["failure"] is None
    assert balance["relative_drift"] > 0.05


def test_time_stepping_defaults_are_the_library_s():
    # Simulation's keyword defaults restate DynamicsOptions' (the arguments start from them): a
    # change of the library's default must reach Python too.
    import inspect
    from flexure import _flexure
    defaults = inspect.signature(flexure.Simulation.__init__).parameters
    library = _flexure.SimulationArguments()
    for name in ("step_tolerance", "quasi_newton_pairs", "energy_tolerance",
                 "max_newton_iterations", "beta", "gamma"):
        assert defaults[name].default == getattr(library, name), name
