"""The long calls (minimize, form, fair, Simulation.run) report their progress to a callable and
stop on Ctrl-C: KeyboardInterrupt propagates and the call returns nothing to write."""

import math
import os
import signal

import numpy as np
import pytest

import flexure

from conftest import bent

SURFACE = "quadratic:1,0.3,0.5"


@pytest.fixture
def interruptible():
    """Python's own SIGINT handler (KeyboardInterrupt) for the test, whatever the runner set."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def recorder():
    calls = []
    return calls, calls.append


def assert_sane(calls, final_energy):
    assert calls, "the progress callback was never called"
    iterations = [c["iteration"] for c in calls]
    assert iterations == sorted(iterations) and iterations[0] == 0
    energies = [c["energy"] for c in calls]
    assert all(math.isfinite(e) for e in energies)
    assert all(math.isfinite(c["gradient_norm"]) and c["gradient_norm"] >= 0 for c in calls)
    assert energies == sorted(energies, reverse=True)  # each accepted step descends
    assert final_energy <= energies[0]


@pytest.mark.parametrize("solver", ["newton", "ceres"])
def test_minimize_reports_every_iteration(solver):
    V, F = flexure.mesh("patch48", 8)
    calls, progress = recorder()
    _, report = flexure.minimize(V, F, energy="hinge", boundary_surface=SURFACE, solver=solver,
                                 start="given", progress=progress)
    assert report["converged"]
    assert_sane(calls, report["final_energy"])
    assert len(calls) >= report["iterations"]


def test_an_exception_in_progress_stops_the_solve_and_propagates():
    V, F = flexure.mesh("patch48", 8)
    calls = []

    def stop(at):
        calls.append(at)
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        flexure.minimize(V, F, energy="hinge", boundary_surface=SURFACE, start="given",
                         progress=stop)
    assert len(calls) == 1  # stopped at the first iteration, not after the solve


def test_ctrl_c_stops_the_solve_within_an_iteration(interruptible):
    # SIGINT as Ctrl-C sends it, during the solve: the solve stops at its next iteration.
    V, F = flexure.mesh("patch48", 8)
    calls = []

    def interrupt(at):
        calls.append(at)
        if len(calls) == 2:
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        flexure.minimize(V, F, energy="hinge", boundary_surface=SURFACE, start="given",
                         progress=interrupt)
    assert len(calls) == 2  # the interrupt is seen before a third iteration
    # The module is usable afterwards.
    _, report = flexure.minimize(V, F, energy="hinge", boundary_surface=SURFACE)
    assert report["converged"]


def test_form_reports_the_iterations_of_every_solve():
    V, F = flexure.mesh("delaunay", 8)
    calls, progress = recorder()
    _, report = flexure.form(V, F, energy="midedge", boundary_surface="quadratic:0.1,0,0",
                             yield_curvature=0.1, load_steps=2, progress=progress)
    assert report["converged"] and calls
    assert all(math.isfinite(c["energy"]) for c in calls)
    assert sum(c["iteration"] == 0 for c in calls) >= report["solves"]  # each solve starts at 0


def test_form_stops_on_ctrl_c(interruptible):
    V, F = flexure.mesh("delaunay", 8)

    def interrupt(at):
        os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        flexure.form(V, F, energy="midedge", boundary_surface="quadratic:0.1,0,0",
                     yield_curvature=0.1, load_steps=2, progress=interrupt)


def test_fair_reports_progress_and_stops_on_ctrl_c(interruptible):
    V, F = flexure.mesh("delaunay", 8, seed=3)
    W = bent(V, 9, amplitude=0.02)
    calls, progress = recorder()
    _, report = flexure.fair(W, F, region="all-interior", start="input", progress=progress)
    assert report["converged"] and calls
    assert all(math.isfinite(c["energy"]) for c in calls)
    assert calls[-1]["energy"] <= calls[0]["energy"]

    interrupts = []

    def interrupt(at):
        interrupts.append(at)
        os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        flexure.fair(W, F, region="all-interior", start="input", progress=interrupt)
    assert len(interrupts) == 1  # stopped at the iteration the interrupt came in


def test_simulation_run_reports_every_step_and_stops_when_asked():
    V, F = flexure.mesh("patch48", 4)
    s = flexure.Simulation(V, F, energy="hinge", membrane="stvk", pinned=1,
                           gravity=[0, 0, -9.81])
    calls, progress = recorder()
    s.run(0.03, 0.01, progress=progress)
    assert [c["step"] for c in calls] == [1, 2, 3]
    assert np.allclose([c["time"] for c in calls], [0.01, 0.02, 0.03])
    assert all(math.isfinite(c["energy"]) for c in calls)

    def stop(at):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        s.run(0.03, 0.01, progress=stop)
    assert s.time == pytest.approx(0.04)  # the step under way finished, no more


def test_progress_must_be_callable():
    V, F = flexure.mesh("patch48", 4)
    with pytest.raises(ValueError, match="^progress: expected a callable"):
        flexure.minimize(V, F, energy="hinge", boundary_surface=SURFACE, progress=3)
