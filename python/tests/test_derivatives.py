"""Gradients and Hessians of Problem against central finite differences, for every energy."""

import numpy as np
import pytest
import scipy.sparse

import flexure
from conftest import bent


def relative_error(approx, exact):
    return np.linalg.norm(approx - exact) / np.linalg.norm(exact)


def generic_point(problem, seed):
    """x at a bent configuration: z bent, ξ (midedge) away from rest."""
    V = bent(problem.V_rest, seed=seed)
    xi = problem.start_xi
    if xi.size:
        xi = xi + 0.1 * np.random.default_rng(seed).standard_normal(xi.size)
    return problem.to_free(V, xi)


def check_derivatives(problem, x, h=1e-5):
    n = problem.n_free
    E, g = problem.energy_and_gradient(x)
    assert E == problem.energy(x) and np.array_equal(g, problem.gradient(x))
    assert g.shape == (n,) and np.linalg.norm(g) > 0
    g_fd = np.empty(n)
    H_fd = np.empty((n, n))
    for k in range(n):
        step = np.zeros(n)
        step[k] = h
        g_fd[k] = (problem.energy(x + step) - problem.energy(x - step)) / (2 * h)
        H_fd[:, k] = (problem.gradient(x + step) - problem.gradient(x - step)) / (2 * h)
    H = problem.hessian(x)
    assert isinstance(H, scipy.sparse.csc_matrix) and H.shape == (n, n)
    assert abs(H - H.T).max() == 0
    assert relative_error(g_fd, g) <= 1e-6
    assert relative_error(H_fd, H.toarray()) <= 1e-6


@pytest.mark.parametrize("name", flexure.energies())
def test_height_derivatives(name):
    V, F = flexure.mesh("patch48", 4)
    problem = flexure.Problem(V, F, energy=name, fixed_rings=1)
    assert (problem.free_unknowns < 3 * V.shape[0]).sum() == (~problem.fixed).sum() == 9
    check_derivatives(problem, generic_point(problem, seed=11))


@pytest.mark.parametrize("name", flexure.energies())
def test_xyz_derivatives_with_membrane(name):
    V, F = flexure.mesh("patch48", 4)
    problem = flexure.Problem(V, F, energy=name, dof="xyz", fixed_rings=1,
                              membrane={"model": "stvk", "young": 2.0})
    x = generic_point(problem, seed=5)
    x += 0.01 * np.random.default_rng(1).standard_normal(x.size)  # move x, y too
    check_derivatives(problem, x)


@pytest.mark.parametrize("name", flexure.energies())
def test_gauss_newton_is_exact_at_rest(name):
    # At a zero-residual point ∇²E = JᵀJ: the two kinds agree there, and Gauss–Newton is PSD.
    V, F = flexure.mesh("patch48", 4)
    problem = flexure.Problem(V, F, energy=name, fixed_rings=1)
    x = problem.x0()
    exact, gn = problem.hessian(x), problem.hessian(x, kind="gauss-newton")
    assert abs(exact - gn).max() <= 1e-12 * abs(exact).max()
    y = generic_point(problem, seed=2)
    gn = problem.hessian(y, kind="gauss-newton").toarray()
    assert np.linalg.eigvalsh(gn).min() >= -1e-10 * np.abs(gn).max()


def test_free_unknown_mapping():
    V, F = flexure.mesh("patch48", 4)
    problem = flexure.Problem(V, F, energy="midedge", fixed_rings=1)
    nv = V.shape[0]
    free = problem.free_unknowns
    assert np.all(np.diff(free) > 0)
    # Height mode: only z (3v + 2) of free vertices, then ξ (3 #V + e).
    vertex_part = free[free < 3 * nv]
    assert np.all(vertex_part % 3 == 2)
    assert np.array_equal(np.sort(vertex_part // 3), np.flatnonzero(~problem.fixed))
    x = generic_point(problem, seed=4)
    W, xi = problem.from_free(x)
    assert np.array_equal(problem.to_free(W, xi), x)
    assert np.array_equal(W[problem.fixed], problem.start_positions[problem.fixed])
    flat = np.concatenate([W.ravel(), xi])
    assert np.array_equal(flat[free], x)
