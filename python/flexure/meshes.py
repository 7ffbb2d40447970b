"""flexure.info, boundary_rings, boundary_loops: what ``flexure info`` says of a mesh, and the
boundary rings that pins and clamps hold."""

import numpy as np

from . import _checks
from . import _flexure


def info(V, F):
    """``flexure info --json``'s report of the mesh (V #V×3 float64, F #F×3 int) as a dict:
    vertices, faces, validation (valid, problem_counts, problems) and, for a valid mesh, edges,
    components, euler_characteristic, boundary_loops (vertices per loop, longest first),
    valence_histogram (interior / boundary: valence → count), edge_length (min, mean, max; L),
    area (L²), bounding_box (min, max)."""
    V = _checks.positions(V, "V")
    F = _checks.faces(F, V.shape[0], "F")
    return dict(_flexure.info(V, F))


def vertex_rings(V, F):
    """(#V,) int: each vertex's ring around the boundary (0 on it, 1 next to it, …; −1 where no
    boundary reaches)."""
    V = _checks.positions(V, "V")
    F = _checks.faces(F, V.shape[0], "F")
    return np.asarray(_flexure.vertex_rings(V, F))


def boundary_rings(V, F, k):
    """(#V,) bool: the vertices in rings 0 .. k−1 from the boundary, what ``pinned=k`` (the CLI's
    rings:K) holds; k = 2 clamps positions and slopes."""
    k = _checks.number(k, "k", integer=True)
    if k < 0:
        raise ValueError(f"k: must be >= 0 (got {k})")
    rings = vertex_rings(V, F)
    return (rings >= 0) & (rings < k)


def boundary_loops(V, F):
    """Each boundary loop as a list of vertex indices in order (following the faces'
    orientation)."""
    V = _checks.positions(V, "V")
    F = _checks.faces(F, V.shape[0], "F")
    return [list(loop) for loop in _flexure.boundary_loops(V, F)]
