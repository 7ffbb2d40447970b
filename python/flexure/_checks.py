"""Argument checks run before any call into C++: each error names the argument and what is wrong."""

import numbers

import numpy as np


def positions(V, name="V", rows=None):
    """V as a C-contiguous float64 #V×3 array: returned as is (no copy) when it already is one.

    ValueError naming `name` for a wrong shape, a non-real dtype, a NaN or an infinite entry,
    or (with `rows`) another vertex count.
    """
    A = np.asarray(V)
    if A.dtype.kind not in "fiu" or A.dtype == np.bool_:
        raise ValueError(f"{name}: dtype {A.dtype} is not a real number type (expected float64)")
    if A.ndim != 2 or A.shape[1] != 3:
        raise ValueError(f"{name}: shape {A.shape}, expected (#V, 3)")
    if rows is not None and A.shape[0] != rows:
        raise ValueError(f"{name}: has {A.shape[0]} rows, the mesh {rows} vertices")
    A = np.ascontiguousarray(A, dtype=np.float64)
    finite = np.isfinite(A)
    if not finite.all():
        v, c = np.argwhere(~finite)[0]
        kind = "NaN" if np.isnan(A[v, c]) else "infinite"
        raise ValueError(f"{name}: vertex {v} coordinate {c} is {kind}")
    return A


def faces(F, vertex_count, name="F"):
    """F as a C-contiguous int32 #F×3 array of vertex indices in [0, vertex_count).

    Accepts int32 and int64 (any integer dtype); ValueError naming `name` otherwise.
    """
    A = np.asarray(F)
    if A.dtype.kind not in "iu":
        raise ValueError(
            f"{name}: dtype {A.dtype} is not an integer type (expected int32 or int64)")
    if A.ndim != 2 or A.shape[1] != 3:
        raise ValueError(f"{name}: shape {A.shape}, expected (#F, 3)")
    if A.size:
        bad = np.argwhere((A < 0) | (A >= vertex_count))
        if len(bad):
            f, c = bad[0]
            raise ValueError(
                f"{name}: index {int(A[f, c])} out of range for {vertex_count} vertices "
                f"(face {f})")
    return np.ascontiguousarray(A, dtype=np.int32)


def vector(x, size, name):
    """x as a float64 vector of `size` finite entries."""
    A = np.asarray(x)
    if A.dtype.kind not in "fiu" or A.dtype == np.bool_:
        raise ValueError(f"{name}: dtype {A.dtype} is not a real number type (expected float64)")
    if A.ndim != 1 or A.shape[0] != size:
        raise ValueError(f"{name}: shape {A.shape}, expected ({size},)")
    A = np.ascontiguousarray(A, dtype=np.float64)
    finite = np.isfinite(A)
    if not finite.all():
        i = int(np.argwhere(~finite)[0][0])
        raise ValueError(f"{name}: entry {i} is {'NaN' if np.isnan(A[i]) else 'infinite'}")
    return A


def mask(m, size, name):
    """A boolean vector of `size` entries (bool or 0/1 integers)."""
    A = np.asarray(m)
    if A.ndim != 1 or A.shape[0] != size:
        raise ValueError(f"{name}: shape {A.shape}, expected ({size},)")
    if A.dtype != np.bool_:
        if A.dtype.kind not in "iu" or not np.isin(A, (0, 1)).all():
            raise ValueError(f"{name}: dtype {A.dtype}, expected a boolean mask")
        A = A.astype(bool)
    return A


def number(x, name, positive=False, integer=False):
    """A finite real (or integer) number."""
    kind = numbers.Integral if integer else numbers.Real
    if isinstance(x, bool) or not isinstance(x, kind) or not np.isfinite(x):
        raise ValueError(f"{name}: {x!r} is not a finite {'integer' if integer else 'number'}")
    if positive and not x > 0:
        raise ValueError(f"{name}: must be positive (got {x})")
    return int(x) if integer else float(x)


def progress(callback):
    """None or a callable (a long call's progress callback)."""
    if callback is not None and not callable(callback):
        raise ValueError(f"progress: expected a callable or None, got {callback!r}")
    return callback
