"""flexure.fair: fairing a region of a mesh, as ``flexure fair --method flexure``."""

from . import _checks
from . import _flexure
from . import _bending


def fair(V, F, region, energy="midedge", poisson=None, stiffness=1.0, vertex_area=None,
         hinge_angle=None, membrane="mips", membrane_weight=None, start="best",
         metric="input", method="flexure", allow_slivers=False, max_iterations=None,
         remesh=False, remesh_edge_length=None, remesh_iterations=None, check=True,
         progress=None):
    """The region's vertices moved to minimize a bending energy (flat rest) + a membrane; the
    rest of the mesh (V #V×3 float64, F #F×3 int) is held, with the two rings around the region.

    region: a #V boolean mask of the vertices that move, or the CLI's spec: "sphere:x,y,z,r" |
    "around:VERTEX,R" | "rings:VERTEX,K" | "all-interior" | "vertices:FILE"; energy etc.: the
    bending energy as in ``flexure.energy`` (vertex_area None: the metric's default); membrane:
    "mips" | "conformal" | "stvk" | "springs", of weight ``membrane_weight`` (None: 1 on the
    input's metric, 0.1 on the current one); start: "best" | "biharmonic" | "input"; metric:
    "input" | "current" (capped on slivers) | "current-exact"; method: "flexure" (nonlinear
    bending + membrane) | "cgal" (CGAL's linear fair); allow_slivers: no angle barrier and the
    smallest-angle rule not applied (the CLI's --allow-slivers); max_iterations: the solver's
    (None: its default); remesh: the faces touching the region remeshed first by CGAL's
    isotropic remeshing, their border and the rest kept (the CLI's --remesh), to the target
    remesh_edge_length (None: the mean edge length of those faces) in remesh_iterations rounds
    (None: 3).

    Returns ``(V', report)``: V' #V×3 float64; report a dict: converged (the solve, the checks
    and the smallest-angle rule, as ``flexure fair``'s exit 0), failure (in words, "" when
    converged), method, solver_converged, and for method flexure termination, iterations,
    initial_energy, final_energy, seconds, start; energy_name, membrane_weight,
    region_vertices, patch_vertices, patch_faces; before / after / cgal (bending energies of
    every discretization (k_B units), min_angle_degrees, mean_shape, min_shape,
    max_displacement (L)); checks (passed, failure, gradient_passed, final_gradient_norm,
    triangles_passed, degenerate_faces, inverted_faces, input / result min angles) and slivers
    (input, cgal, result and limit degrees, passed). With ``check``, a fair that did not
    converge raises NumericalError with the report in ``.report``. progress and Ctrl-C as
    ``flexure.minimize``'s, over every stage of the solve. With remesh, V' is the remeshed mesh's
    (#V'×3), report["remesh"] has its faces F (#F'×3 int) and target_edge_length, iterations,
    faces_before, faces_after, hausdorff_distance (and its two one-sided parts),
    min_angle_degrees_before and min_angle_degrees_after, as the CLI's report.
    """
    V = _checks.positions(V, "V")
    F = _checks.faces(F, V.shape[0], "F")
    a = _flexure.FairArguments()
    spec = a.spec
    spec.bending = _bending(energy, poisson, stiffness, vertex_area, hinge_angle, True)
    if isinstance(region, str):
        a.region_spec = region
    else:
        a.region_mask = [bool(b) for b in _checks.mask(region, V.shape[0], "region")]
    spec.membrane = str(membrane)
    if membrane_weight is not None:
        spec.membrane_weight = _checks.number(membrane_weight, "membrane_weight")
    spec.start, spec.metric = str(start), str(metric)
    spec.method = str(method)
    spec.allow_slivers = bool(allow_slivers)
    spec.remesh = bool(remesh)
    if remesh_edge_length is not None:
        spec.remesh_edge_length = _checks.number(remesh_edge_length, "remesh_edge_length")
    if remesh_iterations is not None:
        spec.remesh_iterations = _checks.number(remesh_iterations, "remesh_iterations",
                                                integer=True)
    if max_iterations is not None:
        spec.max_iterations = _checks.number(max_iterations, "max_iterations", integer=True)
    faired, report = _flexure.fair(V, F, a, _checks.progress(progress))
    report = dict(report)
    if check and not report["converged"]:
        error = _flexure.NumericalError(f"the fair did not converge: {report['failure']}")
        error.report = report
        raise error
    return faired, report
