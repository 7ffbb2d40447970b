"""The package's surface: docstrings, mesh IO, generators, and the GIL released during solves."""

import inspect
import threading
import time

import numpy as np
import pytest

import flexure


def test_every_public_function_has_a_docstring():
    for name in flexure.__all__:
        thing = getattr(flexure, name)
        assert inspect.getdoc(thing), name
        if inspect.isclass(thing):
            for member, value in vars(thing).items():
                if not member.startswith("_") and callable(value) or isinstance(value, property):
                    assert inspect.getdoc(value), f"{name}.{member}"


@pytest.mark.parametrize("suffix", [".obj", ".off", ".ply"])
def test_write_read_round_trip_is_exact(suffix, tmp_path):
    V, F = flexure.mesh("delaunay", 6, seed=3)
    V = V + np.random.default_rng(0).standard_normal(V.shape) * 1e-3
    flexure.write_mesh(tmp_path / ("m" + suffix), V, F.astype(np.int64))
    V2, F2 = flexure.read_mesh(tmp_path / ("m" + suffix))
    assert np.array_equal(V2, V) and np.array_equal(F2, F)
    assert V2.dtype == np.float64 and F2.dtype == np.int32


def test_generators():
    for family, n in [("patch48", 4), ("stripe", 4), ("criss", 4), ("delaunay", 4)]:
        V, F = flexure.mesh(family, n)
        assert V.shape[1] == 3 and F.shape[1] == 3
        assert np.all(V[:, 2] == 0)
        assert V[:, :2].min() == -0.5 and V[:, :2].max() == 0.5
    V, F = flexure.mesh("patch48", 4)
    assert V.shape == (25, 3) and F.shape == (32, 3)
    a, _ = flexure.mesh("delaunay", 6, seed=1)
    b, _ = flexure.mesh("delaunay", 6, seed=2)
    assert not np.array_equal(a, b)
    with pytest.raises(ValueError, match="^n: 0.5 is not"):
        flexure.mesh("patch48", 0.5)


def test_gil_is_released_during_minimize():
    # While minimize runs in a worker thread, the main thread keeps running Python: the longest
    # pause between its steps stays well below the solve's duration.
    V, F = flexure.mesh("patch48", 96)
    problem = flexure.Problem(V, F, energy="midedge", boundary_surface="quadratic:1,0,1")
    done = {}

    def solve():
        start = time.perf_counter()
        flexure.minimize(problem)
        done["seconds"] = time.perf_counter() - start

    worker = threading.Thread(target=solve)
    worker.start()
    last, longest = time.perf_counter(), 0.0
    while worker.is_alive():
        now = time.perf_counter()
        longest, last = max(longest, now - last), now
    worker.join()
    assert done["seconds"] > 0.2, "the solve is too short to show anything"
    print(f"solve {done['seconds']:.3f} s, longest main-thread pause {longest:.4f} s")
    assert longest < 0.5 * done["seconds"]
