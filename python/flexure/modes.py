"""flexure.modes: vibration modes (Chladni figures) of a plate or shell, as ``flexure modes``."""

import numpy as np

from . import _checks
from . import _flexure
from . import _bending
from .simulation import _set_membrane


def modes(V, F, energy="midedge", count=12, support="clamped", clamp=None, fixed=None,
          dof="height", membrane=None, poisson=None, stiffness=1.0, vertex_area=None,
          hinge_angle=None, mass="barycentric", density=1.0, length=None, nodal_lines=True):
    """The smallest ``count`` flexible vibration modes (and the zero modes) of the rest mesh
    (V #V×3 float64, L; F #F×3 int), for one bending energy, as ``flexure modes`` computes them.

    support: "clamped" | "simply-supported" | "free"; clamp (clamped only): "rings" | "normals"
    (default normals for midedge, else rings); fixed: a #V mask held in addition; dof: "height"
    | "xyz" (needs membrane, a name or a dict as in Simulation); mass: "barycentric" |
    "voronoi"; density: ρh (mass per unit area); stiffness: k_B (D = 2 k_B); length: L of
    λ = ω L² √(ρh / D) (None: the bounding box's largest side).

    Returns a dict: energy, poisson, support, clamp, rigid_modes, zero_modes,
    spurious_zero_modes, flexible_modes, length, flexural_rigidity, shift, unknowns,
    vertex_unknowns, fixed_vertices, lanczos_solves, lanczos_restarts, seconds, and "modes": a
    list in ascending ω² (zero modes first) of dicts with omega_squared (1/s²), omega (rad/s),
    lambda, zero, multiplicity, residual, nodal_length (L), shape (#V×3 displacement,
    M-normalized) and, with nodal_lines, nodal_lines (#S×2×3: segment ends on the rest mesh).
    Also "eigenvalues" ((#modes,) ω²), "omegas" and "shapes" (#modes×#V×3) as arrays.
    """
    V = _checks.positions(V, "V")
    F = _checks.faces(F, V.shape[0], "F")
    a = _flexure.ModesArguments()
    a.bending = _bending(energy, poisson, stiffness, vertex_area, hinge_angle, False)
    a.count = _checks.number(count, "count", positive=True, integer=True)
    a.support = str(support)
    if clamp is not None:
        a.clamp = str(clamp)
    if fixed is not None:
        a.fixed = [bool(b) for b in _checks.mask(fixed, V.shape[0], "fixed")]
    a.dof = str(dof)
    if membrane is not None:
        _set_membrane(a, membrane)
    a.mass = str(mass)
    a.density = _checks.number(density, "density", positive=True)
    if length is not None:
        a.length = _checks.number(length, "length", positive=True)
    a.nodal_lines = bool(nodal_lines)
    result = dict(_flexure.modes(V, F, a))
    result["modes"] = [dict(m) for m in result["modes"]]
    result["eigenvalues"] = np.array([m["omega_squared"] for m in result["modes"]])
    result["omegas"] = np.array([m["omega"] for m in result["modes"]])
    result["shapes"] = np.array([m["shape"] for m in result["modes"]]).reshape(-1, V.shape[0], 3)
    return result
