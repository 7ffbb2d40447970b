"""Shared fixtures: the flexure CLI the Python results are compared with, and small test meshes."""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import flexure


@pytest.fixture(scope="session")
def cli():
    """Runs `flexure ARGS…` (FLEXURE_CLI, else build/cli/flexure) and returns its stdout."""
    path = os.environ.get("FLEXURE_CLI") or str(pathlib.Path("cli/flexure").resolve())
    assert os.access(path, os.X_OK), f"the flexure CLI is not at {path} (set FLEXURE_CLI)"

    def run(*args):
        done = subprocess.run([path, *map(str, args)], capture_output=True, text=True)
        assert done.returncode == 0, f"flexure {' '.join(map(str, args))}: {done.stderr}"
        return done.stdout

    run.json = lambda *args: json.loads(run(*args))
    return run


def bent(V, seed, amplitude=0.05):
    """V lifted onto a smooth bump plus a seeded random height perturbation (a generic state)."""
    rng = np.random.default_rng(seed)
    W = V.copy()
    x, y = V[:, 0], V[:, 1]
    W[:, 2] += 0.3 * x * x - 0.2 * x * y + 0.1 * y * y + amplitude * rng.standard_normal(len(V))
    return W


@pytest.fixture
def plate():
    """patch48 with 6 × 6 cells: (V, F), 49 vertices."""
    return flexure.mesh("patch48", 6)
