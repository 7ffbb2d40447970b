"""A user's own optimizer on flexure's energy: scipy.optimize.minimize (trust-ncg with flexure's
exact Hessian, and L-BFGS-B on the gradient alone) against flexure's Newton solver.

Run from the build tree: PYTHONPATH=build/python python3 examples/python/own_optimizer.py
Exits 1 when scipy's minimizers do not reach flexure's (a CTest test runs it).
"""

import sys

import numpy as np
import scipy.optimize

import flexure

V_rest, F = flexure.mesh("patch48", 12)
problem = flexure.Problem(V_rest, F, energy="midedge", boundary_surface="quadratic:1,0,0.5")

# flexure's own solve.
V_flexure, report = flexure.minimize(problem)
x_flexure = problem.to_free(V_flexure, report["xi"])
E_flexure = problem.energy(x_flexure)


class HessianProduct:
    """H(x) p for trust-ncg's conjugate gradients: the Hessian (scipy csc) evaluated once per x."""

    def __init__(self):
        self.x = self.H = None

    def __call__(self, x, p):
        if self.x is None or not np.array_equal(self.x, x):
            self.x, self.H = x.copy(), problem.hessian(x)
        return self.H @ p


# scipy on the free unknowns x (problem.free_unknowns: vertex z, then midedge ξ), from the start.
x0 = problem.x0()
runs = {
    "trust-ncg": scipy.optimize.minimize(
        problem.energy, x0, jac=problem.gradient, hessp=HessianProduct(), method="trust-ncg",
        options={"gtol": 1e-10, "maxiter": 200}),
    "L-BFGS-B": scipy.optimize.minimize(
        problem.energy, x0, jac=problem.gradient, method="L-BFGS-B",
        options={"gtol": 1e-12, "ftol": 1e-15, "maxiter": 20000, "maxcor": 30}),
}

print(f"flexure newton  E = {E_flexure:.15g}  ({report['iterations']} iterations, "
      f"{report['seconds']['total']:.3f} s)")
ok = True
for method, result in runs.items():
    V, _ = problem.from_free(result.x)
    dV = np.abs(V - V_flexure).max() / np.abs(V_flexure).max()
    dE = abs(result.fun - E_flexure) / E_flexure
    print(f"scipy {method:10s} E = {result.fun:.15g}  ({result.nit} iterations)  "
          f"|ΔE|/E = {dE:.1e}  max|ΔV|/max|V| = {dV:.1e}")
    tolerance = 1e-9 if method == "trust-ncg" else 1e-6
    ok &= dE <= tolerance and dV <= np.sqrt(tolerance)
sys.exit(0 if ok else 1)
