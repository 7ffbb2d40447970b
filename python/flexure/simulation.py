"""flexure.Simulation: a plate or shell in time, as ``flexure simulate`` steps it."""

import numpy as np

from . import _MEMBRANE_FIELDS, _bending, _plasticity_options
from . import _checks
from . import _flexure


def _set_membrane(a, membrane):
    """Sets a's membrane model and the parameters given (a name, or a dict with "model"); the
    others keep the library's defaults (curvature::MembraneOptions, as the CLI's)."""
    spec = {"model": membrane} if isinstance(membrane, str) else dict(membrane)
    if "model" not in spec:
        raise ValueError("membrane: a dict needs a \"model\" entry")
    a.membrane = str(spec.pop("model"))
    for key, value in spec.items():
        if key not in _MEMBRANE_FIELDS:
            raise ValueError(f"membrane: unknown parameter {key!r} (known: "
                             f"{', '.join(_MEMBRANE_FIELDS)})")
        setattr(a, _MEMBRANE_FIELDS[key], _checks.number(value, f"membrane {key}"))


def _set_motion(target, motion, name):
    """Sets target's motion (pin_motion's or a group's) from {"rotate": (axis, point, omega)} or
    {"translate": velocity}; `name` names the argument in errors."""
    if not isinstance(motion, dict) or len(motion) != 1:
        raise ValueError(f"{name}: expected {{\"rotate\": (axis, point, omega)}} or "
                         "{\"translate\": velocity}")
    (kind, value), = motion.items()
    if kind == "rotate":
        try:
            axis, point, omega = value
        except (TypeError, ValueError):
            raise ValueError(f"{name}: rotate takes (axis, point, omega)") from None
        target.axis = _checks.vector(axis, 3, f"{name} axis")
        target.point = _checks.vector(point, 3, f"{name} point")
        target.omega = _checks.number(omega, f"{name} omega")
    elif kind == "translate":
        target.velocity = _checks.vector(value, 3, f"{name} velocity")
    else:
        raise ValueError(f"{name}: {kind!r}, expected rotate or translate")
    return kind


def _set_pin_motion(a, pin_motion, pinned):
    if pinned is None:
        raise ValueError("pin_motion: moves the pinned vertices; give them with pinned")
    a.pin_motion = _set_motion(a, pin_motion, "pin_motion")


def _mesh_obstacles(obstacles):
    """The mesh obstacles: each a triple (V #W×3, F #T×3, motion as pin_motion's or None)."""
    if isinstance(obstacles, (str, dict)) or not hasattr(obstacles, "__len__"):
        raise ValueError("mesh_obstacles: expected a list of triples (V, F, motion or None)")
    out = []
    for k, obstacle in enumerate(obstacles):
        name = f"mesh_obstacles[{k}]"
        if not isinstance(obstacle, tuple) or len(obstacle) != 3:
            raise ValueError(f"{name}: expected a triple (V, F, motion or None)")
        V, F, motion = obstacle
        g = _flexure.MeshObstacleArguments()
        V = _checks.positions(V, f"{name} V")
        g.positions = V
        g.faces = _checks.faces(F, V.shape[0], f"{name} F")
        if motion is not None:
            g.motion = _set_motion(g, motion, f"{name} motion")
        out.append(g)
    return out


def _set_pinned(target, pinned, n, name):
    """target's vertices (a spec or a mask) from an int K (rings), a spec or a #V mask."""
    if isinstance(pinned, str):
        target.spec = pinned
    elif isinstance(pinned, (int, np.integer)) and not isinstance(pinned, bool):
        if pinned < 0:
            raise ValueError(f"{name}: rings must be >= 0 (got {pinned})")
        target.spec = f"rings:{int(pinned)}" if pinned > 0 else "none"
    else:
        target.mask = [bool(b) for b in _checks.mask(pinned, n, name)]


def _pin_groups(groups, n):
    """The pin groups: each a vertex set (as ``pinned`` takes it), a pair (set, motion or None) or
    a triple (set, motion or None, release time); the library checks that they are disjoint
    (pin_groups) and the release times."""
    if isinstance(groups, (str, dict)) or not hasattr(groups, "__len__"):
        raise ValueError("pin_groups: expected a list of groups, each a vertex set, a pair "
                         "(vertex set, motion) or a triple (vertex set, motion, release time)")
    out = []
    for k, group in enumerate(groups):
        name = f"pin_groups[{k}]"
        g = _flexure.PinGroupArguments()
        if isinstance(group, tuple) and len(group) not in (2, 3):
            raise ValueError(f"{name}: expected a vertex set, a pair (vertex set, motion) or a "
                             "triple (vertex set, motion, release time)")
        vertices, motion, release = (group + (None,))[:3] if isinstance(group, tuple) else (
            group, None, None)
        _set_pinned(g, vertices, n, name)
        if motion is not None:
            g.motion = _set_motion(g, motion, f"{name} motion")
        if release is not None:
            g.release_time = _checks.number(release, f"{name} release time")
        out.append(g)
    return out


def _set_inelastic(a, yield_curvature, yield_strain, hardening, fracture_strain, thickness):
    """The plasticity and fracture options, passed to the library as given (its checks name the
    keyword: yield_curvature, fracture_strain, …)."""
    a.plasticity = _plasticity_options(yield_curvature, yield_strain, hardening)
    if fracture_strain is None:
        if thickness:
            raise ValueError("thickness: the fibres of the fracture criterion; give "
                             "fracture_strain")
        return
    fracture = _flexure.FractureOptions()
    fracture.fracture_strain = _checks.number(fracture_strain, "fracture_strain")
    fracture.thickness = _checks.number(thickness, "thickness")
    a.fracture = fracture


class Simulation:
    """A shell in time (optimize/dynamics/time_stepping.h), set up as ``flexure simulate``.

    Every coordinate of every unpinned vertex moves; midedge's ξ are massless unknowns solved with
    each step. Equations of motion M a + C v + ∇E(x, ξ) − M g = 0 with lumped masses M.

    Arguments: V_rest #V×3 float64 (length L), F #F×3 int; energy, poisson, stiffness,
    vertex_area, hinge_angle: the bending energy as in ``flexure.energy`` (energy in k_B units);
    membrane: "stvk" | "springs" | "conformal" or a dict with "model" and young, poisson,
    length_stiffness, area_stiffness, shape_stiffness (the library's defaults, as the CLI's:
    1000 k_B);
    pinned: None (nothing), an int K (rings 0 .. K−1 from the boundary; K ≥ 2 also holds
    midedge's boundary ξ at rest, the clamp), a spec "rings:K" | "vertices:FILE", or a #V
    boolean mask; V_start: #V×3 start positions (the pins stay there; default V_rest);
    velocities: #V×3 start velocities (L/s; default 0); gravity: a 3-vector g (L/s²);
    density: ρ, mass per unit rest area; mass: "barycentric" | "voronoi" lumping; obstacles:
    a list of "plane:nx,ny,nz,d" | "sphere:x,y,z,r"; integrator: "newmark" | "backward-euler"
    | "central-difference"; beta, gamma: Newmark's; rayleigh: (α, β) of C = α M + β K̄;
    bending_damping: c of −c K_B(x_n) v; pin_motion: the pins' rigid motion from where they
    start, {"rotate": (axis 3-vector, point 3-vector, ω rad/s)} (counter-clockwise about the
    axis) or {"translate": velocity 3-vector (L/s)}; pin_groups (instead of pinned and
    pin_motion): a list of groups, each a vertex set as pinned takes it, a pair (set, motion as
    pin_motion's, or None: held still) or a triple (set, motion or None, release time T > 0: the
    group is let go at T, its vertices free from then on with their velocity, the plastic state
    kept), disjoint (``flexure simulate --pin SET@MOTION@release:T``, repeated);
    max_newton_iterations: per step; step_tolerance ε_v: a step's Newton iterations stop when the
    largest remaining velocity correction ‖Δx‖∞/h is below ε_v l per second (l the rest mesh's
    bounding-box diagonal; 1e-9 is the strict reference; docs/commands/simulate.md "Step
    tolerance"); quasi_newton_pairs m: with m > 0, between factorizations a step's iterations are
    L-BFGS steps on the kept factor with the last m iterate pairs (6 by default; 0: chord steps on
    the factor; docs/performance.md); energy_tolerance: a step over which the energy
    balance grows by more than this fraction of the peak kinetic energy is halved, and a run
    whose balance drifts more fails (``run`` raises NumericalError; ``balance()["verdict"]``).

    Plasticity (seed 002, docs/energies.md "Plasticity"): yield_curvature κ_y (1/L) and hardening γ
    ≥ 0; after each step the elements outside the yield surface return to it and their rest
    curvature moves (hinge, triavg, midedge, quadfit; cotan is refused); yield_strain ε_y (the
    stvk membrane's Green strain), either or both (one radial return per face for the combined
    yield): the rest metric moves. Fracture: fracture_strain ε_f and thickness
    h (fibres at ± h/2); a face whose principal fibre strain passes ε_f cracks across it, and the
    motion goes on on the cut mesh (midedge's ξ re-solved on it; with plasticity each piece of a
    cut face keeps its plastic strain). Bad values raise the library's ValueError naming the keyword
    (hardening, thickness).

    Self-contact (docs/dynamics.md "Self-contact"): self_contact True (the default) makes every
    vertex–face and edge–edge pair closer than contact_offset d̂ repel (default ¼ of the mean
    rest edge length), and no step lets two parts of the shell pass through each other.
    mesh_obstacles: rigid triangle meshes, a list of triples (V #W×3, F #T×3, motion as
    pin_motion's or None: static), that the shell may not pass through (the same barrier and
    offset, with self_contact on or off; ``flexure simulate --obstacle mesh:FILE@MOTION``).

    Friction (docs/commands/simulate.md "Friction"): friction μ ≥ 0 (default 0, frictionless) is
    the Coulomb coefficient at every contact (the obstacles, the mesh obstacles and the shell's
    own), smoothed and lagged per step
    as in incremental potential contact; its work counts as dissipated in ``balance()``.

    Not thread-safe: one thread at a time per Simulation (the GIL is released during steps).
    """

    def __init__(self, V_rest, F, energy="midedge", poisson=None, stiffness=1.0,
                 vertex_area=None, hinge_angle=None, membrane="stvk", pinned=None,
                 V_start=None, velocities=None, gravity=None, density=1.0, mass="barycentric",
                 obstacles=(), integrator="newmark", beta=0.25, gamma=0.5, rayleigh=(0.0, 0.0),
                 bending_damping=0.0, pin_motion=None, pin_groups=None,
                 max_newton_iterations=30, step_tolerance=1e-4, yield_curvature=None,
                 yield_strain=None, hardening=0.0, fracture_strain=None, thickness=0.0,
                 energy_tolerance=0.05, self_contact=True, contact_offset=None, friction=0.0,
                 mesh_obstacles=(), quasi_newton_pairs=6):
        V_rest = _checks.positions(V_rest, "V_rest")
        F = _checks.faces(F, V_rest.shape[0], "F")
        n = V_rest.shape[0]
        a = _flexure.SimulationArguments()
        a.bending = _bending(energy, poisson, stiffness, vertex_area, hinge_angle, False)
        if membrane is None:
            raise ValueError("membrane: a simulation moves every coordinate: give a membrane "
                             "(stvk, springs or conformal)")
        _set_membrane(a, membrane)
        if pinned is None:
            a.pinned_spec = "none"
        elif isinstance(pinned, str):
            a.pinned_spec = pinned
        elif isinstance(pinned, (int, np.integer)) and not isinstance(pinned, bool):
            if pinned < 0:
                raise ValueError(f"pinned: rings must be >= 0 (got {pinned})")
            a.pinned_spec = f"rings:{int(pinned)}" if pinned > 0 else "none"
        else:
            a.pinned_mask = [bool(b) for b in _checks.mask(pinned, n, "pinned")]
        if pin_groups is not None:
            if pinned is not None or pin_motion is not None:
                raise ValueError("pin_groups: give the pinned vertices either as pinned (with "
                                 "pin_motion) or as pin_groups, each with its motion")
            a.pin_groups = _pin_groups(pin_groups, n)
        if V_start is not None:
            V_start = _checks.positions(V_start, "V_start", rows=n)
        if velocities is not None:
            velocities = _checks.positions(velocities, "velocities", rows=n)
        if gravity is not None:
            a.gravity = _checks.vector(gravity, 3, "gravity")
        a.density = _checks.number(density, "density", positive=True)
        a.mass = str(mass)
        if isinstance(obstacles, str):
            raise ValueError("obstacles: expected a list of specs, e.g. [\"plane:0,0,1,-1\"]")
        a.obstacles = [str(o) for o in obstacles]
        a.mesh_obstacles = _mesh_obstacles(mesh_obstacles)
        a.self_contact = bool(self_contact)
        if contact_offset is not None:
            a.contact_offset = _checks.number(contact_offset, "contact_offset", positive=True)
        a.integrator = str(integrator)
        a.beta = _checks.number(beta, "beta")
        a.gamma = _checks.number(gamma, "gamma")
        rayleigh = _checks.vector(rayleigh, 2, "rayleigh")
        a.rayleigh_mass, a.rayleigh_stiffness = float(rayleigh[0]), float(rayleigh[1])
        a.bending_damping = _checks.number(bending_damping, "bending_damping")
        if pin_motion is not None:
            _set_pin_motion(a, pin_motion, pinned)
        a.max_newton_iterations = _checks.number(max_newton_iterations, "max_newton_iterations",
                                                 positive=True, integer=True)
        a.step_tolerance = _checks.number(step_tolerance, "step_tolerance")
        a.quasi_newton_pairs = _checks.number(quasi_newton_pairs, "quasi_newton_pairs",
                                              integer=True)
        a.energy_tolerance = _checks.number(energy_tolerance, "energy_tolerance")
        a.friction = _checks.number(friction, "friction")
        _set_inelastic(a, yield_curvature, yield_strain, hardening, fracture_strain, thickness)
        self._s = _flexure.Simulation(V_rest, F, a, V_start, velocities)

    def advance(self, h, min_dt=None):
        """Advances by h seconds; a step that fails is replaced by two of h/2, recursively, while
        h/2 ≥ min_dt (default h/64). Returns a dict: completed, time, steps, halvings,
        smallest_step, newton_iterations, max_newton_iterations, attempted_iterations,
        factorizations, and failure, failed_step, failed_time when it stopped. Never raises for
        a failed step (the state is that after the steps that converged)."""
        h = _checks.number(h, "h", positive=True)
        min_dt = 0.0 if min_dt is None else _checks.number(min_dt, "min_dt")
        return dict(self._s.advance(h, min_dt))  # 0: the library's default, h/64

    def step(self, dt, min_dt=None):
        """One step of dt seconds as ``flexure simulate`` takes each (``advance``, halving down to
        min_dt, default dt/64). Returns advance's dict; raises flexure.NumericalError (its
        ``.report`` the dict) when the step fails even at min_dt."""
        report = self.advance(dt, min_dt)
        if not report["completed"]:
            error = _flexure.NumericalError(
                f"the simulation could not proceed at t = {report['failed_time']:.6g}: a step of "
                f"{report['failed_step']:.3g} s failed ({report['failure']})")
            error.report = report
            raise error
        return report

    def run(self, duration, dt, min_dt=None, progress=None):
        """duration / dt steps of dt (ValueError when duration is not a whole number of steps, as
        ``flexure simulate`` refuses it); returns the list of their dicts.

        progress: None or a callable, called after every step with a dict (step, time, energy:
        the total of ``energies()``); an exception it raises stops the run there. Ctrl-C stops
        the run after the step under way (KeyboardInterrupt).

        A run whose energy balance ends beyond energy_tolerance (verdict "gained" or "lost", as
        ``flexure simulate`` exits 3 for it) raises flexure.NumericalError naming the drift, its
        ``.report`` a dict with the steps' dicts ("steps") and the balance ("balance"); the state
        is that at the end of the run."""
        steps = _flexure.step_count(_checks.number(dt, "dt"),
                                    _checks.number(duration, "duration", positive=True))
        progress = _checks.progress(progress)
        reports = []
        for k in range(steps):
            reports.append(self.step(dt, min_dt))
            if progress is not None:
                progress({"step": k + 1, "time": self.time, "energy": self.energies()["total"]})
        balance = self.balance()
        if balance["failure"] is not None:
            error = _flexure.NumericalError(balance["failure"])
            error.report = {"steps": reports, "balance": balance}
            raise error
        return reports

    @property
    def V_rest(self):
        """#V×3 float64: the rest positions of the current mesh (after cracks: the cut mesh's)."""
        return self._s.rest_positions

    @property
    def F(self):
        """#F×3 int32: the current mesh's triangles (after cracks: the cut mesh's)."""
        return self._s.triangles

    @property
    def mesh(self):
        """(V, F): the current positions on the current (cut) mesh."""
        return self._s.positions, self._s.triangles

    @property
    def plastic_dissipation(self):
        """The plastic dissipation D so far (k_B units; 0 without plasticity)."""
        return self.balance()["plastic_dissipation"]

    def _plastic(self, key):
        state = self._s.plastic_state()
        if state is None:
            raise ValueError(f"{key}: the simulation has no plasticity (give yield_curvature or "
                             "yield_strain)")
        return state[key]

    @property
    def plastic_element(self):
        """"face": what plastic_strain has a row per (for every energy, the hinge's included)."""
        return self._plastic("element")

    @property
    def plastic_strain(self):
        """#faces×3 float64: the bending plastic strain P_b per face (shape-operator components
        (a, b, c) in the face's rest frame; hinge: the tensor its edges' plastic angles read as,
        on the faces with an interior edge), a copy."""
        return self._plastic("plastic_strain")

    @property
    def plastic_curvature(self):
        """(#elements,) float64: the plastic strain as a curvature, √(‖P_b‖²_* / 2) (1/L)."""
        return self._plastic("plastic_curvature")

    @property
    def yielded(self):
        """(#elements,) bool: the elements that have yielded."""
        return np.asarray(self._plastic("yielded"), dtype=bool)

    @property
    def vertex_plastic_curvature(self):
        """(#V,) float64: per vertex the largest plastic_curvature of its faces or edges."""
        return self._plastic("vertex_plastic_curvature")

    @property
    def membrane_plastic_strain(self):
        """(#F,) float64: the membrane's plastic strain per face as a Green strain, √(‖P_m‖²_* / 2)
        (0 without yield_strain; a strip stretched to ε with its width held keeps
        (ε − ε_y)/(1 + γ))."""
        return self._plastic("membrane_plastic_strain")

    @property
    def vertex_membrane_plastic_strain(self):
        """(#V,) float64: per vertex the largest membrane_plastic_strain of its faces."""
        return self._plastic("vertex_membrane_plastic_strain")

    def cracks(self):
        """The cracks so far, in order: dicts with time, step, face and strain (where it started,
        on the mesh before the cut), strain_direction, crack_direction, fibre (+1 top, −1
        bottom), polyline_rest and polyline_current (k×3: the crack's points at rest and where
        they were), released_energy (the energy the cut took out of the balance's reference)
        and fragments (pieces after it): the entries of ``flexure simulate``'s report.json
        ``fracture.cracks``."""
        return [dict(c) for c in self._s.cracks()]

    def fragments(self, rest=False):
        """The connected pieces of the current mesh, each (V #V'×3, F #F'×3 int32) with its
        vertices renumbered in order: V the current positions, or with ``rest`` the rest ones
        (the same pieces in the same order)."""
        return list(self._s.fragments(bool(rest)))

    @property
    def time(self):
        """The simulated time t (s)."""
        return self._s.time

    @property
    def positions(self):
        """#V×3 float64: the positions x(t) (L), a copy."""
        return self._s.positions

    @property
    def velocities(self):
        """#V×3 float64: the velocities v(t) (L/s), a copy."""
        return self._s.velocities

    @property
    def xi(self):
        """(#E,) float64: midedge's ξ(t) (empty for the other energies)."""
        return self._s.xi

    @property
    def masses(self):
        """(#V,) float64: the lumped masses m_v = ρ × the vertex's rest area."""
        return self._s.masses

    @property
    def pinned(self):
        """(#V,) bool: the pinned vertices."""
        return np.asarray(self._s.pinned, dtype=bool)

    @property
    def term_names(self):
        """The energy terms' names (the bending energy first, then the membrane's)."""
        return list(self._s.term_names)

    def contact(self):
        """The self-contact over the steps taken, as ``flexure simulate``'s report.json
        ``contact``: whether it is on, its offset d̂ (L), the smallest distance between two
        repelling primitives at a step's end, the pairs within d̂ per step (mean and peak), the
        seconds spent in collision detection, and how often the Hessian pattern grew."""
        return dict(self._s.contact)

    def energies(self):
        """The energies of the current state (k_B units) as ``flexure simulate``'s energies.csv:
        time, kinetic ½ vᵀMv, each term by name, gravity −(M g)ᵀ x, contact (the obstacles'
        barrier), plastic_dissipation (with plasticity: the energy plastic updates released so
        far, not part of total) and total."""
        return dict(self._s.energies())

    def balance(self):
        """The run's energy balance, as ``flexure simulate``'s report.json ``energy_balance``: the
        largest drift of the total energy plus the work done against damping (minus what raising
        the contact stiffness added, plus the plastic dissipation ``plastic_dissipation``) from
        its start value, signed, its size relative to the peak
        kinetic energy, when (time, step), and whether it is checked (not while pins move). A
        step over which it grows by more than energy_tolerance (5 %) of the peak kinetic energy is
        refused (halved by ``advance``). verdict: "balanced", "gained" or "lost" beyond the
        tolerance (then failure names the drift, else None), "driven" while pins move."""
        return dict(self._s.balance())
