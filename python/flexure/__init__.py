"""flexure: static minimizers of discrete bending energies on triangle meshes, from numpy.

Meshes are libigl-style arrays: ``V`` (#V×3 float64, the vertex positions, in the mesh's length
unit L) and ``F`` (#F×3 int32 or int64, 0-based vertex indices, counter-clockwise). A
C-contiguous float64 ``V`` reaches the C++ library without a copy; other arrays are converted
once. Energies are in units of the bending stiffness k_B (energy = k_B × curvature² × area, so
k_B × L⁰ for a shell scaled uniformly); gradients in energy / L, Hessians in energy / L².

Errors: bad input raises ``ValueError`` naming the argument (or the file, element) and what is
wrong; a numerical failure raises ``flexure.NumericalError`` (with ``.report`` when a solve did
not converge).
"""

import warnings

import numpy as np
import scipy.sparse

from . import _checks
from . import _flexure

__version__ = _flexure.__version__

__all__ = [
    "NumericalError", "read_mesh", "write_mesh", "mesh", "energies", "energy", "Problem",
    "minimize", "form", "LinearizedSolver", "Simulation", "fair", "modes", "render", "write_png",
    "read_png", "png_bytes", "info", "boundary_rings", "vertex_rings", "boundary_loops",
    "converge", "c2_table", "compare_figure", "reuse_freed_memory", "sweep", "view", "View",
]

NumericalError = _flexure.NumericalError
NumericalError.__doc__ = (
    "A numerical failure: a solve that did not converge (``.report`` holds its report, as the "
    "CLI's exit 3 writes it), a degenerate element met during an evaluation.")


def read_mesh(path):
    """Read an OBJ, OFF, PLY or STL file with flexure's checked readers.

    Returns ``(V, F)``: V #V×3 float64 positions, F #F×3 int32 vertex indices. Polygons with
    more than three vertices are split into fans (a warning says so). ValueError naming the file,
    line and problem for a missing, malformed or non-manifold mesh.
    """
    V, F, notices = _flexure.read_mesh(str(path))
    for notice in notices:
        warnings.warn(notice, stacklevel=2)
    return V, F


def _mesh_arrays(V, F, V_name="V", F_name="F"):
    V = _checks.positions(V, V_name)
    F = _checks.faces(F, V.shape[0], F_name)
    return V, F


def write_mesh(path, V, F):
    """Write the mesh (V #V×3 float64, F #F×3 int) to ``path`` (.obj, .off or .ply, by extension).

    Coordinates are written as the shortest decimals that read back to the same doubles, so
    ``read_mesh`` returns V exactly. The file is replaced atomically. ValueError for bad arrays,
    an unknown extension or a mesh that is not a manifold triangle mesh.
    """
    V, F = _mesh_arrays(V, F)
    _flexure.write_mesh(str(path), V, F)


def mesh(family, n, seed=1, aspect=None):
    """A test mesh of the square [−1/2, 1/2]² at z = 0, or a shell (the generators of ``flexure mesh``).

    family: "patch48" | "stripe" | "criss" | "delaunay" | "cylinder" | "sphere" | "hemisphere";
    n: cells per side (delaunay: boundary segments per side; stripe: even; shells: edges around
    the circumference of radius 1/2, sphere and hemisphere a multiple of 4); seed: delaunay's
    sampling seed; aspect: cell height / width, a cylinder's length / diameter (None: the
    family's default). Returns ``(V, F)``: #V×3 float64 (unit length L = the square's
    side), #F×3 int32.
    """
    _checks.number(n, "n", positive=True, integer=True)
    _checks.number(seed, "seed", integer=True)
    if seed < 0:
        raise ValueError(f"seed: must be >= 0 (got {seed})")
    if aspect is not None:
        aspect = _checks.number(aspect, "aspect", positive=True)
    return _flexure.mesh(str(family), int(n), int(seed), aspect)


def energies():
    """The registered bending energies' names, in registry order (e.g. hinge, triavg, cotan,
    midedge, quadfit)."""
    return list(_flexure.energies())


def reuse_freed_memory():
    """Opt in, once per process, to the allocator setting the flexure command and benchmarks
    use: glibc serves blocks below 1 GiB from its heap instead of fresh mmap'ed pages, so the
    10–100 MB buffers of evaluations and solves stop paying their page faults again at every call
    (measured from Python on a 10 000-vertex plate, one process each, fastest of 30 calls:
    midedge energy + gradient 31.5 → 26.4 ms; hinge unchanged at 11 ms).
    It changes malloc for the whole Python process (freed memory is kept for reuse rather than
    unmapped), so it is not done on import."""
    _flexure.reuse_freed_memory()


def _plasticity_options(yield_curvature, yield_strain, hardening):
    """PlasticityOptions with the yield values given (None: that part elastic); the library's
    checks name the keyword (yield_curvature, …)."""
    plasticity = _flexure.PlasticityOptions()
    if yield_curvature is not None:
        plasticity.yield_curvature = _checks.number(yield_curvature, "yield_curvature")
    if yield_strain is not None:
        plasticity.yield_strain = _checks.number(yield_strain, "yield_strain")
    plasticity.hardening = _checks.number(hardening, "hardening")
    return plasticity


def _bending(energy, poisson, stiffness, vertex_area, hinge_angle, flat_rest):
    b = _flexure.BendingArguments()
    b.energy = str(energy)
    b.poisson = None if poisson is None else _checks.number(poisson, "poisson")
    b.stiffness = _checks.number(stiffness, "stiffness")
    b.vertex_area = "" if vertex_area is None else str(vertex_area)  # "": the energy's default
    b.hinge_angle = "" if hinge_angle is None else str(hinge_angle)
    b.flat_rest = bool(flat_rest)
    return b


def energy(V_rest, F, V, energy="midedge", poisson=None, stiffness=1.0, vertex_area=None,
           hinge_angle=None, flat_rest=False, boundary_surface=None, linearized=False):
    """The bending energy of the current positions V against the rest mesh (V_rest, F).

    The same computation and report as ``flexure energy --json``: nothing is held; midedge's edge
    unknowns ξ are minimized over (the boundary ones clamped to ``boundary_surface``'s normals,
    e.g. "quadratic:1,0,1", when given). ``linearized``: the second-order expansion about rest,
    E_lin(δ) = ½ |J δ|².

    V_rest, V: #V×3 float64 (length L); F: #F×3 int32/int64. poisson: ν (None: the energy's rule,
    0.3 for the Koiter energies; hinge and cotan accept only 1); stiffness: k_B; vertex_area:
    "voronoi" | "barycentric" (cotan only; None: voronoi); hinge_angle: "theta" | "tan" (hinge
    only; None: theta) — given to an energy that does not read it, ValueError; flat_rest: take
    only the metric from the rest mesh, its rest curvature zero (fairing).

    Returns a dict: energy (k_B units), energy_name, elements, element_kind, covered_area (L²),
    energy_per_area, poisson, stiffness, linearized, and vertex_area / hinge_angle / boundary_xi
    where the energy reads them.
    """
    V_rest, F = _mesh_arrays(V_rest, F, "V_rest")
    V = _checks.positions(V, "V", rows=V_rest.shape[0])
    b = _bending(energy, poisson, stiffness, vertex_area, hinge_angle, flat_rest)
    return dict(_flexure.energy(V_rest, F, V, b, boundary_surface, bool(linearized)))


_MEMBRANE_FIELDS = {"young": "young", "poisson": "membrane_poisson",
                    "length_stiffness": "length_stiffness", "area_stiffness": "area_stiffness",
                    "shape_stiffness": "shape_stiffness"}


class Problem:
    """A static problem: the rest mesh, its energy terms, the held unknowns and their values.

    Arguments: V_rest #V×3 float64, F #F×3 int; energy (a name of ``energies()``), poisson,
    stiffness, vertex_area, hinge_angle, flat_rest as in ``energy``; dof: "height" (z free, x
    and y held at rest) or "xyz" (needs ``membrane``); fixed: a #V boolean mask of held
    vertices, else ``fixed_rings`` (rings 0 .. K−1 from the boundary; 2 holds positions and
    slopes); the held values: ``boundary_positions`` (#V×3: held rows are the values, free rows
    the start) or ``boundary_surface`` ("quadratic:a,b,c" or "polynomial:EXPR": held vertices
    lifted onto z = p(x̄, ȳ)), neither: rest; boundary_normals (midedge): "clamped" (default
    with a surface) | "free"; linearized_clamp: the clamp linearized about rest (for a
    linearized solve); membrane: None, a model name ("stvk" | "springs" | "conformal" | "mips")
    or a dict with "model" and young, poisson, length_stiffness, area_stiffness, shape_stiffness
    (the library's defaults, as the CLI's: 1000, 0.3, 1000, 1000, 1000); gravity: a 3-vector g (load m_v g on
    the lumped masses, density ρ per unit rest area).

    The unknowns: coordinate c of vertex v is unknown 3v + c, midedge's ξ_e is 3 #V + e. The free
    ones (``free_unknowns``, n of them) in that order make the vector x (n,) that ``energy``,
    ``gradient`` and ``hessian`` take; ``to_free`` and ``from_free`` map between x and (V, ξ).
    The objective is E(V, ξ) − fᵀV (+ the obstacles' barrier), exactly what ``minimize`` minimizes.
    """

    def __init__(self, V_rest, F, energy="midedge", poisson=None, stiffness=1.0,
                 vertex_area=None, hinge_angle=None, flat_rest=False, dof="height",
                 fixed=None,
                 fixed_rings=2, boundary_positions=None, boundary_surface=None,
                 boundary_normals=None, linearized_clamp=False, membrane=None, gravity=None,
                 density=1.0):
        V_rest, F = _mesh_arrays(V_rest, F, "V_rest")
        n = V_rest.shape[0]
        a = _flexure.ProblemArguments()
        a.bending = _bending(energy, poisson, stiffness, vertex_area, hinge_angle, flat_rest)
        a.dof = str(dof)
        if fixed is not None:
            a.fixed = [bool(b) for b in _checks.mask(fixed, n, "fixed")]
        a.fixed_rings = _checks.number(fixed_rings, "fixed_rings", integer=True)
        if fixed_rings < 0:
            raise ValueError(f"fixed_rings: must be >= 0 (got {fixed_rings})")
        if boundary_positions is not None:
            a.boundary_positions = _checks.positions(boundary_positions, "boundary_positions",
                                                     rows=n)
        if boundary_surface is not None:
            a.boundary_surface = str(boundary_surface)
        if boundary_normals is not None:
            a.boundary_normals = str(boundary_normals)
        a.linearized_clamp = bool(linearized_clamp)
        if membrane is not None:
            spec = {"model": membrane} if isinstance(membrane, str) else dict(membrane)
            if "model" not in spec:
                raise ValueError("membrane: a dict needs a \"model\" entry")
            a.membrane = str(spec.pop("model"))
            for key, value in spec.items():
                if key not in _MEMBRANE_FIELDS:
                    raise ValueError(f"membrane: unknown parameter {key!r} (known: "
                                     f"{', '.join(_MEMBRANE_FIELDS)})")
                setattr(a, _MEMBRANE_FIELDS[key], _checks.number(value, f"membrane {key}"))
        if gravity is not None:
            a.gravity = _checks.vector(gravity, 3, "gravity")
        a.density = _checks.number(density, "density", positive=True)
        self._p = _flexure.Problem(V_rest, F, a)
        self._arguments = a  # form builds its own problem from them
        self.V_rest, self.F = V_rest, F
        self.energy_name = a.bending.energy
        self.dof = a.dof
        n_free = self._p.size
        self._pattern = (np.asarray(self._p.row_index, dtype=np.int32),
                         np.asarray(self._p.column_start, dtype=np.int32), (n_free, n_free))

    @property
    def n_free(self):
        """n: the number of free unknowns (the length of x)."""
        return self._p.size

    @property
    def free_unknowns(self):
        """(n,) int: free_unknowns[k] is the unknown x[k] holds (3v + c, or 3 #V + e for ξ_e)."""
        return np.asarray(self._p.free_unknowns, dtype=np.int64)

    @property
    def fixed(self):
        """(#V,) bool: the held vertices."""
        return np.asarray(self._p.fixed_vertex, dtype=bool)

    @property
    def start_positions(self):
        """#V×3 float64: the held vertices' values and the free ones' start."""
        return self._p.start_positions

    @property
    def rest_xi(self):
        """(#E,) float64: midedge's rest ξ̄ (empty for the other energies)."""
        return self._p.rest_xi

    @property
    def start_xi(self):
        """(#E,) float64: the held ξ's values and the free ones' start (empty without ξ)."""
        return self._p.start_xi

    def x0(self):
        """(n,) the free unknowns at the start (``start_positions``, ``start_xi``)."""
        return self.to_free(self.start_positions, self.start_xi)

    def to_free(self, V, xi=None):
        """x (n,) of positions V (#V×3) and midedge ξ ((#E,); the start's when None)."""
        V = _checks.positions(V, "V", rows=self.V_rest.shape[0])
        start = self.start_xi
        xi = start if xi is None else _checks.vector(xi, start.shape[0], "xi")
        return self._p.free_values(V, xi)

    def from_free(self, x):
        """(V #V×3, ξ (#E,)) of x (n,): the free unknowns from x, the held ones at their values."""
        return self._p.configuration(self._x(x))

    def _x(self, x):
        return _checks.vector(x, self.n_free, "x")

    def energy(self, x):
        """The objective at x (n,): E − fᵀV in k_B units."""
        return self._p.evaluate(self._x(x), "none")[0]

    def gradient(self, x):
        """(n,) the objective's gradient over the free unknowns at x (energy / L)."""
        return self._p.evaluate(self._x(x), "none")[1]

    def energy_and_gradient(self, x):
        """(E, gradient (n,)) at x in one evaluation."""
        e, g, _ = self._p.evaluate(self._x(x), "none")
        return e, g

    def hessian(self, x, kind="exact"):
        """The n×n Hessian over the free unknowns at x, a symmetric scipy.sparse.csc_matrix.

        kind: "exact" (∇²E, element by element) or "gauss-newton" (JᵀJ of the residuals).
        """
        if kind not in ("exact", "gauss-newton"):
            raise ValueError(f"kind: {kind!r}, expected 'exact' or 'gauss-newton'")
        _, _, values = self._p.evaluate(self._x(x), kind)
        rows, starts, shape = self._pattern
        upper = scipy.sparse.csc_matrix((values, rows, starts), shape=shape)
        diagonal = scipy.sparse.diags(upper.diagonal())
        return scipy.sparse.csc_matrix(upper + upper.T - diagonal)


_SOLVER_FIELDS = ("solver", "hessian", "linearized", "start", "max_iterations",
                  "function_tolerance", "gradient_tolerance", "parameter_tolerance", "threads")


def _solver_arguments(solver, hessian, linearized, start, max_iterations, function_tolerance,
                      gradient_tolerance, parameter_tolerance, threads):
    s = _flexure.SolverArguments()
    s.solver, s.hessian, s.start = str(solver), str(hessian), str(start)
    s.linearized = bool(linearized)
    s.max_iterations = _checks.number(max_iterations, "max_iterations", positive=True,
                                      integer=True)
    s.function_tolerance = _checks.number(function_tolerance, "function_tolerance")
    s.gradient_tolerance = _checks.number(gradient_tolerance, "gradient_tolerance")
    s.parameter_tolerance = _checks.number(parameter_tolerance, "parameter_tolerance")
    s.threads = _checks.number(threads, "threads", positive=True, integer=True)
    return s


def _problem_of(problem, args, problem_arguments, caller):
    if not isinstance(problem, Problem):
        return Problem(problem, *args, **problem_arguments)
    if args or problem_arguments:
        raise ValueError(f"{caller}: give a Problem or the arguments of one, not both")
    return problem


def minimize(problem=None, *args, solver="newton", hessian="exact", linearized=False,
             start="linearized", max_iterations=200, function_tolerance=1e-12,
             gradient_tolerance=1e-10, parameter_tolerance=1e-12, threads=2, check=True,
             progress=None, **problem_arguments):
    """Minimize a problem's objective over its free unknowns (``flexure minimize``).

    ``problem``: a Problem, or the arguments of Problem (``minimize(V_rest, F, energy=…,
    boundary_surface=…)``). solver: "newton" | "ceres"; hessian (newton's matrix, as the
    CLI's --hessian): "exact" (JᵀJ where indefinite) | "projected" (element Hessians projected
    to positive semidefinite) | "shifted" (H + μI where indefinite) | "exact-projected";
    linearized: minimize E_lin exactly (one sparse solve; build the problem with
    linearized_clamp=True for midedge's clamp); start: "linearized" | "given"; tolerances as the
    CLI's; threads: worker threads. The GIL is released during the solve.

    Returns ``(V, report)``: V #V×3 float64 the minimizer; report a dict (converged, solver,
    termination, iterations, factorizations, initial_energy, final_energy, final_gradient_norm,
    seconds, problem counts, energy_name, poisson, dof, linearized, and "xi" (#E,) for midedge).
    With ``check`` (default), a solve that did not converge raises NumericalError whose
    ``.report`` is that dict.

    progress: None or a callable, called at every iteration of the nonlinear solvers with a dict
    (iteration, energy, gradient_norm); an exception it raises stops the solve and propagates.
    Ctrl-C stops the solve within an iteration and raises KeyboardInterrupt.
    """
    problem = _problem_of(problem, args, problem_arguments, "minimize")
    progress = _checks.progress(progress)
    s = _solver_arguments(solver, hessian, linearized, start, max_iterations, function_tolerance,
                          gradient_tolerance, parameter_tolerance, threads)
    V, xi, report = problem._p.minimize(s, progress)
    report = dict(report)
    if xi.size:
        report["xi"] = xi
    if check and not report["converged"]:
        error = NumericalError(f"the solve did not converge ({report['termination']})")
        error.report = report
        raise error
    return V, report


def form(problem=None, *args, yield_curvature=None, yield_strain=None, hardening=0.0,
         load_steps=1, release=False, max_updates_per_step=200, update_tolerance=1e-9,
         solver="newton", hessian="exact", start="linearized", max_iterations=200,
         function_tolerance=1e-12, gradient_tolerance=1e-10, parameter_tolerance=1e-12,
         threads=2, check=True, progress=None, **problem_arguments):
    """Quasi-static plastic forming with springback (``flexure minimize --yield-curvature …
    --load-steps K --release``; optimize/inelastic/plasticity.h formPlastically).

    ``problem``: a Problem or its arguments, as ``minimize`` takes them; the problem given is not
    changed (forming builds its own from the same arguments, whose rest curvature it moves). The
    held values are reached from rest in ``load_steps`` equal steps, each a static solve followed
    by the plastic update (repeated until no element's increment exceeds ``update_tolerance``
    times its yield value, at most ``max_updates_per_step`` times); with ``release`` only the
    three vertices of the face nearest the centroid stay held and the shape relaxes: the
    sprung-back shape. yield_curvature κ_y (1/L) for bending (not cotan), yield_strain ε_y (Green
    strain) for a stvk membrane (dof "xyz"), hardening γ ≥ 0 (seed 002's linear kinematic
    hardening). A plate bent cylindrically to κ keeps (κ − κ_y)/(1 + γ) while γ(κ − κ_y)/(1 + γ)
    < κ_y. Solver arguments as ``minimize``'s (not linearized). Bad values raise the library's
    ValueError naming the keyword (yield_curvature, load_steps, …).

    Returns ``(V, report)``: V #V×3 float64 the formed (released: sprung-back) positions; report a
    dict: converged, solves, yielded_elements, yielded_faces, dissipation (k_B units),
    release_pins, last_solve (``minimize``'s report of the last solve), plastic_strain
    (#faces×3: P_b per face; hinge: per face with an interior edge), plastic_curvature ((#faces,):
    √(‖P_b‖²_* / 2)), yielded, membrane_plastic_strain (#F×3: (a, b, c) of P_m in each face's rest
    frame; empty without yield_strain), membrane_yielded, and "xi" (#E,) for midedge. With
    ``check`` (default), a forming that did not converge raises NumericalError with ``.report``.
    progress and Ctrl-C as ``minimize``'s, over every solve of the forming.
    """
    problem = _problem_of(problem, args, problem_arguments, "form")
    progress = _checks.progress(progress)
    s = _solver_arguments(solver, hessian, False, start, max_iterations, function_tolerance,
                          gradient_tolerance, parameter_tolerance, threads)
    plasticity = _plasticity_options(yield_curvature, yield_strain, hardening)
    forming = _flexure.FormingOptions()
    forming.load_steps = _checks.number(load_steps, "load_steps", integer=True)
    forming.release = bool(release)
    forming.max_updates_per_step = _checks.number(max_updates_per_step, "max_updates_per_step",
                                                  integer=True)
    forming.tolerance = _checks.number(update_tolerance, "update_tolerance")
    V, xi, report = _flexure.form(problem.V_rest, problem.F, problem._arguments, s, plasticity,
                                  forming, progress)
    report = dict(report)
    report["last_solve"] = dict(report["last_solve"])
    report["yielded"] = np.asarray(report["yielded"], dtype=bool)
    report["membrane_yielded"] = np.asarray(report["membrane_yielded"], dtype=bool)
    if xi.size:
        report["xi"] = xi
    if check and not report["converged"]:
        error = NumericalError("the forming did not converge (a solve, or a step's plastic "
                               "updates, did not settle)")
        error.report = report
        raise error
    return V, report


class LinearizedSolver:
    """The linearized energy's minimizer as a precompute/solve pair (libigl's min_quad_with_fixed).

    ``LinearizedSolver(problem)`` evaluates the residual Jacobian J at rest and factors
    J_freeᵀ J_free once (for the problem's held vertices and ξ); ``solve(boundary_values)`` then
    minimizes E_lin(u) = ½ |J (u − ū)|² for new held values with two triangular solves.
    ``in_plane``: allow held vertices to move in x, y in height mode (J's x, y columns are
    evaluated too); without it such values raise ValueError.
    """

    def __init__(self, problem, in_plane=False):
        if not isinstance(problem, Problem):
            raise ValueError("problem: expected a flexure.Problem")
        self.problem = problem
        self._s = _flexure.LinearizedSolver(problem._p, bool(in_plane))

    @property
    def factorizations(self):
        """Numerical factorizations made by the precompute (1 when the first succeeded)."""
        return self._s.factorizations

    def solve(self, boundary_values, xi=None):
        """The minimizer for held vertices at ``boundary_values``' rows (#V×3; free rows ignored)
        and held ξ at ``xi`` ((#E,); the problem's when None). A problem that holds ξ (midedge's
        clamp of its boundary) needs ``xi`` for held values other than its own (ValueError
        otherwise: its clamp would not follow them), e.g. the ``start_xi`` of a Problem with their
        ``boundary_surface``.

        Returns ``(V, info)``: V #V×3 float64; info a dict with "xi" ((#E,) or empty),
        "initial_energy", "energy", "gradient_norm", "initial_gradient_norm". GIL released.
        """
        n = self.problem.V_rest.shape[0]
        B = _checks.positions(boundary_values, "boundary_values", rows=n)
        if xi is not None:
            xi = _checks.vector(xi, self.problem.start_xi.shape[0], "xi")
        V, solved_xi, info = self._s.solve(B, xi)
        info = dict(info)
        info["xi"] = solved_xi
        return V, info


from .simulation import Simulation  # noqa: E402
from .fairing import fair  # noqa: E402
from .modes import modes  # noqa: E402
from .render import render, write_png, read_png, png_bytes  # noqa: E402
from .meshes import info, boundary_rings, vertex_rings, boundary_loops  # noqa: E402
from .study import converge, c2_table, compare_figure  # noqa: E402
from .sweep import sweep  # noqa: E402
from .viewer import view, View  # noqa: E402
