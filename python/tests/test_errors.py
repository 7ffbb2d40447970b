"""Bad input raises ValueError naming it; numerical failures raise flexure.NumericalError."""

import numpy as np
import pytest

import flexure
from flexure import _flexure


@pytest.fixture
def small():
    return flexure.mesh("patch48", 2)  # 9 vertices, 8 faces


def test_wrong_shapes(small):
    V, F = small
    with pytest.raises(ValueError, match=r"^V_rest: shape \(9, 2\), expected \(#V, 3\)"):
        flexure.energy(V[:, :2], F, V)
    with pytest.raises(ValueError, match=r"^F: shape \(8, 4\)"):
        flexure.energy(V, np.hstack([F, F[:, :1]]), V)
    with pytest.raises(ValueError, match=r"^V: has 8 rows, the mesh 9 vertices"):
        flexure.energy(V, F, V[:8])
    with pytest.raises(ValueError, match=r"^boundary_positions: shape"):
        flexure.Problem(V, F, boundary_positions=V.ravel())


def test_wrong_dtypes(small):
    V, F = small
    with pytest.raises(ValueError, match=r"^V_rest: dtype <U"):
        flexure.energy(V.astype(str), F, V)
    with pytest.raises(ValueError, match=r"^F: dtype float64 is not an integer type"):
        flexure.energy(V, F.astype(float), V)
    # int64 and int32 faces, float32 positions are accepted and give the same energy.
    W = V.copy()
    W[4, 2] = 0.1
    e32 = flexure.energy(V, F.astype(np.int32), W, energy="hinge")["energy"]
    e64 = flexure.energy(V, F.astype(np.int64), W, energy="hinge")["energy"]
    assert e32 == e64 > 0


def test_faces_out_of_range(small):
    V, F = small
    F = F.copy()
    F[5, 1] = 12
    with pytest.raises(ValueError, match=r"^F: index 12 out of range for 9 vertices \(face 5\)"):
        flexure.Problem(V, F)
    F[5, 1] = -1
    with pytest.raises(ValueError, match=r"^F: index -1 out of range"):
        flexure.write_mesh("never.obj", V, F)


def test_nan_and_inf(small):
    V, F = small
    W = V.copy()
    W[3, 2] = np.nan
    with pytest.raises(ValueError, match=r"^V: vertex 3 coordinate 2 is NaN"):
        flexure.energy(V, F, W)
    W[3, 2] = np.inf
    with pytest.raises(ValueError, match=r"^V_rest: vertex 3 coordinate 2 is infinite"):
        flexure.Problem(W, F)
    problem = flexure.Problem(V, F, energy="hinge", fixed_rings=1)
    x = problem.x0()
    x[0] = np.nan
    with pytest.raises(ValueError, match=r"^x: entry 0 is NaN"):
        problem.gradient(x)
    with pytest.raises(ValueError, match=r"^x: shape \(2,\), expected \(1,\)"):
        problem.energy(np.zeros(2))


def test_library_input_errors_are_value_errors(small, tmp_path):
    V, F = small
    with pytest.raises(ValueError, match="hinge, triavg, cotan, midedge"):
        flexure.energy(V, F, V, energy="nosuch")
    with pytest.raises(ValueError, match="hinge"):
        flexure.energy(V, F, V, energy="hinge", poisson=0.3)
    with pytest.raises(ValueError, match="^dof xyz needs a membrane"):
        flexure.Problem(V, F, dof="xyz")
    with pytest.raises(ValueError, match="missing.obj"):
        flexure.read_mesh(tmp_path / "missing.obj")
    with pytest.raises(ValueError, match="patch48"):
        flexure.mesh("nosuch", 4)
    # A non-manifold mesh: an edge shared by three faces.
    Vn = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [1, 1, 1]], float)
    Fn = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    with pytest.raises(ValueError, match="V_rest, F"):
        flexure.Problem(Vn, Fn)


def test_numerical_error_is_its_own_class():
    assert issubclass(flexure.NumericalError, RuntimeError)
    assert not issubclass(flexure.NumericalError, ValueError)


def test_unconverged_solve_raises_numerical_error_with_report():
    V, F = flexure.mesh("patch48", 8)
    with pytest.raises(flexure.NumericalError, match="did not converge") as caught:
        flexure.minimize(V, F, energy="hinge", boundary_surface="quadratic:3,0,3",
                         start="given", max_iterations=1)
    report = caught.value.report
    assert report["converged"] is False and report["iterations"] == 1
    # check=False returns the unconverged state instead.
    _, report = flexure.minimize(V, F, energy="hinge", boundary_surface="quadratic:3,0,3",
                                 start="given", max_iterations=1, check=False)
    assert report["converged"] is False


def test_collapsed_face_raises_numerical_error(small):
    V, F = small
    W = V.copy()
    a, b, c = F[0]
    W[b] = W[a]
    W[c] = W[a]
    with pytest.raises(flexure.NumericalError):
        flexure.energy(V, F, W, energy="hinge")
