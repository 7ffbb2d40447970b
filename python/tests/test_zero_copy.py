"""A C-contiguous float64 V reaches C++ without a copy; other layouts are converted once."""

import numpy as np

import flexure
from flexure import _checks, _flexure


def test_c_contiguous_float64_is_not_copied():
    V, _ = flexure.mesh("patch48", 16)
    assert V.flags["C_CONTIGUOUS"] and V.dtype == np.float64
    assert _flexure.data_address(V) == V.ctypes.data
    assert _checks.positions(V) is V  # the package's checks pass it through


def test_other_layouts_are_copied_once():
    V, _ = flexure.mesh("patch48", 16)
    fortran = np.asfortranarray(V)
    assert _flexure.data_address(fortran) != fortran.ctypes.data
    as_float32 = V.astype(np.float32)
    checked = _checks.positions(as_float32)
    assert checked.dtype == np.float64 and _flexure.data_address(checked) == checked.ctypes.data
