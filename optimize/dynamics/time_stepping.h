// Shell dynamics: Discrete Shells' time stepping (Grinspun et al. 2003; seeds 001, 003) with any
// of flexure's energies. Every coordinate of every unpinned vertex moves; midedge ξ are massless
// unknowns solved with each step.
//
// What moves is a Problem (problem.h) in xyz: its terms, its held vertices (pinned) and held ξ, its
// lumped masses M (m_v = ρ × the vertex's rest area) and gravity g, its obstacles. How it moves is
// DynamicsOptions.
//
// Equations of motion, lumped mass M,
// damping C = α M + β K̄ + c K_B(x_n) (Rayleigh's α, β with K̄ the Hessian at rest; c the bending
// damping below; all on the vertex unknowns), gravity g:
//
//   M a + C v + ∇E(x, ξ) − M g = 0,   ∇_ξ E(x, ξ) = 0.
//
// Newmark (β, γ), from (x_n, v_n, a_n) with the predictors x̂ = x_n + h v_n + h² (½ − β) a_n and
// v̂ = v_n + h (1 − γ) a_n:  a = (x − x̂) / (β h²),  v = v̂ + γ h a. With β > 0 the step is the
// minimizer over (x, ξ) of the incremental potential
//
//   Φ = (x − x̂)ᵀ M (x − x̂) / (2 β h²) + γ (x − x̂)ᵀ C (x − x̂) / (2 β h) + (C v̂)ᵀ x + E − (M g)ᵀ x
//       + B(x) + D(x),
//
// (B the obstacles' barrier, obstacles.h, D their lagged friction, friction.h; their forces −∇B,
// −∇D join ∇E in the equation of motion)
//
// whose gradient is the equation above; the Newton loop (solvers/newton_loop.h, its step stop
// rule) on its exact Hessian M/(βh²) + γC/(βh) + ∇²E (pattern and CHOLMOD analysis once per run). β
// = ¼, γ = ½ (average acceleration, the default) conserves the energy of a linear undamped system;
// backward Euler is the same minimization with β = γ = 1 and x̂ = x_n + h v_n, v̂ = v_n (it
// dissipates); β = 0, γ = ½ is explicit central differences (x = x̂, then a from the forces; ξ from
// minimizeEdgeUnknowns).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "curvature/energy_term.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "optimize/assembly/friction.h"
#include "optimize/assembly/obstacles.h"
#include "optimize/assembly/pin_motion.h"
#include "optimize/assembly/self_contact.h"
#include "optimize/problem.h"
#include "optimize/solvers/newton_stop.h"

namespace flexure::optimize {

struct NewtonResult;
struct StepStopRule;

enum class Integrator { Newmark, BackwardEuler, CentralDifference };
const char* integratorName(Integrator integrator);  // newmark | backward-euler | central-difference
// The integrator of that name; InputError naming DynamicsOptions.integrator otherwise.
Integrator parseIntegrator(std::string_view name);

// A group of pinned vertices with its own motion, held until its release time: from then on its
// vertices are free and go on with the velocity the motion gave them (releasePinGroups,
// TimeStepper::continueAfterRelease).
struct PinGroup {
  std::vector<bool> vertices;  // #V: the group's vertices (each also pinned by the problem)
  PinMotion motion;
  double releaseTime = std::numeric_limits<double>::infinity();  // +∞: held for the whole run
};

struct DynamicsOptions;
// Drops from `options.pinGroups` the groups released by time t (PinGroup::releaseTime ≤ t) and
// clears their vertices in `held` (the problem's boundary.fixedVertex). Returns the released
// vertices (#V), or an empty vector when no group was released.
std::vector<bool> releasePinGroups(DynamicsOptions& options, std::vector<bool>& held, double t);

struct DynamicsOptions {
  Integrator integrator = Integrator::Newmark;
  double beta = 0.25, gamma = 0.5;                     // Newmark's
  double rayleighMass = 0.0, rayleighStiffness = 0.0;  // α, β of C = α M + β K̄
  // c of the bending damping force −c K_B(x_n) v: K_B = J_Bᵀ J_B is the Gauss–Newton Hessian of
  // the first term (the bending energy, as flexure simulate orders the terms) at the step's start,
  // J_B the Jacobian of its residuals r_B (E_B = ½ |r_B|²). The force is −c J_Bᵀ ṙ_B: it opposes
  // the rate of the bending strain only. For hinge r_B ∝ (θ − θ̄) per hinge, so this is seed
  // 003's Discrete Shells damping −c Σ w (θ̇ − θ̄̇) ∇θ (θ̄̇ = 0); for the shape-operator energies
  // the rate of the shape-operator difference S − S̄, and likewise for every energy — the analogue
  // of Rayleigh's β K with the bending term's own Hessian. Positive semidefinite, so it only
  // dissipates; membrane stretching is not damped. Midedge's ξ rows are left out (massless,
  // solved with each step).
  double bendingDamping = 0.0;
  // How the pinned vertices (the problem's held ones) move from where start() puts them. Damping
  // acts on the free vertices' velocities only: a moving pin drags its neighbours through the
  // elastic forces. The problem's obstacles (their barrier B(x) joins Φ, and each Newton step is
  // capped so that no vertex reaches one) need an implicit integrator.
  PinMotion pinMotion;
  // Pinned vertices in a group follow its motion instead of pinMotion; the groups are disjoint.
  std::vector<PinGroup> pinGroups;
  // At most this many Newton steps (iterations that factor the Hessian) per step, and 4 × as many
  // iterations with the chord steps.
  int maxNewtonIterations = 30;
  // The Hessian of E in each Newton iteration: exact, or its Gauss–Newton part JᵀJ (first
  // derivatives only; the step's inertia M/(βh²) keeps it positive definite).
  curvature::SecondDerivatives hessian = curvature::SecondDerivatives::Exact;
  // ε_v of the time step's stop: Newton has converged when the largest remaining velocity
  // correction is below ε_v l per second, ‖δ‖∞ / h ≤ ε_v l (δ the Newton step, h the time step, l
  // the rest mesh's bounding-box diagonal; midedge's ξ rows, in radians, take the same bound) —
  // IPC's rule (Li et al. 2020, ε_d = 1e-2, 1e-3 in most of its examples). 1e-9 reproduces the
  // strict stepper of the earlier rule ‖δ‖∞ ≤ 1e-10 l, which at h = 0.005–0.01 is ε_v = 1e-8–2e-8.
  // The default, measured against 1e-9 (bench/step_tolerance_bench.cpp; docs/commands/simulate.md
  // "The step tolerance"): every scene within 1e-3 l of the reference with its energy balance;
  // 1e-3 also held the drape, fold and cantilever, but not the wrinkling soft drape (8.7e-3 l),
  // friction's stick (its slip speed is 1e-3 l per second, `friction`) nor a torn sheet's contact.
  double stepTolerance = 1e-4;
  // Chord steps (solvers/newton_loop.h): the last factor of the step's Hessian, from an earlier
  // iteration or an earlier step of the same h, serves while its steps contract; false: every
  // iteration factors the Hessian at its iterate (plain Newton, the reference the tests compare
  // with).
  bool chordSteps = true;
  // With chordSteps, a Newton iteration first solves with the step's Hessian by conjugate
  // gradients preconditioned by the kept factor, and factors it only when those do not converge
  // within a few iterations (StepStopRule::preconditionedSteps). Off by default: on the drape
  // benchmark it halves the factorizations but, each chord step then costing a few solves instead
  // of one, did not make steps faster (simulate_bench, PCG after/before: 0.7–1.0 at 2 500
  // vertices, midedge 0.84 at 10 000; machine loaded).
  bool preconditionedSteps = false;
  // With chordSteps, m > 0: the steps on the kept factor F are L-BFGS steps whose initial inverse
  // Hessian is F⁻¹, with the last m pairs of accepted steps since F was factored within the step
  // (StepStopRule::quasiNewtonPairs, solvers/lbfgs_update.h); 0: chord steps δ = −F⁻¹∇f.
  // 6 by default: on the drape benchmark 1.1–1.5× the chord steps' steps per second with
  // 0.5–0.8× their factorizations (2 401 and 10 000 vertices, docs/performance.md).
  int quasiNewtonPairs = 6;
  // Newton starts from x̂ + β h² a_n (the acceleration kept), and vertices within two barrier
  // layers of an obstacle from x_n, rather than everything from x̂ (a = 0).
  bool predictAcceleration = true;
  // A step over which the balanced total (EnergyBalance) grows by more than this fraction of the
  // energy scale fails, as a step whose Newton loop does not converge (advance halves it); not
  // checked while pins move (they do work). A run whose balance drifts by more (EnergyBalance::
  // relativeDrift) is one to repeat with smaller steps. The default, measured on the cotan drape
  // (a sheet dropped on a sphere, Rayleigh α = 2): its steps' largest rises are 0.7 % at 400
  // steps a second and 1.8 % at 200; at 100 they pass 5 % from t = 0.6 on and 50 % when it blows
  // up at t = 0.8.
  double energyTolerance = 0.05;
  // μ of the lagged smoothed Coulomb friction at every contact — the obstacles, the mesh
  // obstacles and the shell's own (assembly/friction.h): the potential D joins Φ, its contacts,
  // normal forces and tangent planes taken at each step's start, on the slip length ε = ε_v h with
  // the slip speed ε_v = 1e-3 L per second (L the rest mesh's bounding-box diagonal). 0:
  // frictionless.
  double friction = 0.0;

  // InputError naming the field for options no problem can satisfy (β outside (0, ½] for
  // Newmark, γ outside [½, 1], negative damping, damping with the explicit scheme, an energy
  // tolerance or step tolerance that is not > 0 and finite, a PinGroup.releaseTime that is not > 0
  // (finite, or +∞: never), a friction coefficient that is negative or not finite).
  void validate() const;
  // InputError naming DynamicsOptions.pinGroups for a group without #V entries or a vertex in two.
  void validatePinGroups(int vertexCount) const;
  // The earliest PinGroup::releaseTime (+∞ when no group is released).
  double nextRelease() const;
  // The motion the pinned vertex v follows: its group's, else pinMotion.
  const PinMotion& motionOf(int vertex) const;
  // Whether any pinned vertex moves (then the pins do work and the balance is not checked).
  bool pinsMove() const;
};

// The energies of the current state: kinetic ½ vᵀMv, each term's E, gravity −(M g)ᵀ x, the
// obstacles' barrier B(x).
struct EnergySample {
  double time = 0.0, kinetic = 0.0, gravity = 0.0, contact = 0.0;
  std::vector<double> terms;
  double total() const;
};

// The energy balance of a run. With E = EnergySample::total(), D the work done against damping
// so far (per step Δxᵀ C ((1 − γ) v_n + γ v_{n+1}), the damping force of Newmark's equation
// integrated by its own rule; backward Euler γ = 1) and against the obstacles' friction (per step
// ∇D(x_{n+1})·Δx, friction.h) and S the energy added by raising the
// contact stiffness inside the barrier layer (obstacles.h: B(x; κ_new) − B(x; κ_old) at each
// adaptation) and P the energy plastic updates released (plastic_dynamics.h; 0 without), the
// balanced total
//   E_b(t) = E(t) + D(t) + P(t) − S(t) − W
// stays E(0) along the exact motion of a system without moving pins (W, below: the work pins let
// go mid-run did until then; 0 without). Its drift |E_b(t) − E(0)| is
// measured against the scale max(K_peak, 1e-6 max(|E(0)|, U_peak)): K_peak the largest kinetic
// energy so far, U_peak the largest energy of the terms and the barrier (the guard for a run that
// barely moves).
struct EnergyBalance {
  double initial = 0.0;     // E(0)
  double dissipated = 0.0;  // D
  double stiffening = 0.0;  // S
  double peakKinetic = 0.0, peakElastic = 0.0;
  double last = 0.0;          // E_b after the last step
  double largestDrift = 0.0;  // max |E_b − E(0)|, signed as E_b − E(0) at that time
  double driftTime = 0.0;     // when, and after which step
  long driftStep = 0;
  long steps = 0;        // steps recorded
  double plastic = 0.0;  // P
  // W: the work the pins did until their release (TimeStepper::continueAfterRelease), booked at
  // the release as the rise of E_b until then (so it includes the time stepping's drift, which a
  // run with moving pins does not check): from the release on E_b, with W taken out, is E(0).
  double pinWork = 0.0;
  // The largest step's round-off floor, 1e-12 M (L/h)² (TimeStepper: the kinetic energy of the
  // whole mass moving 1e-6 L per step): a drift below it is round-off, as in a body at rest.
  double roundoff = 0.0;

  void start(const EnergySample& e);
  double balanced(const EnergySample& e) const {
    return e.total() + dissipated + plastic - stiffening - pinWork;
  }
  // The scale with a state e counted in.
  double scale(const EnergySample& e) const;
  double scale() const;
  // How far E_b would rise over a step ending in e that did `dissipation` work against damping,
  // relative to the scale.
  double growth(const EnergySample& e, double dissipation) const;
  // Counts a step ending in e (its dissipation, the stiffening after it, its round-off floor).
  void record(const EnergySample& e, double dissipation, double stiffeningWork,
              double stepRoundoff);
  // The largest drift relative to the scale.
  double relativeDrift() const { return std::abs(largestDrift) / scale(); }
  // Whether the largest drift is within `tolerance` of the scale, or round-off.
  bool balancedWithin(double tolerance) const {
    return relativeDrift() <= tolerance || std::abs(largestDrift) <= roundoff;
  }
};

// The verdict on a run's energy balance: Balanced when its largest drift is within the tolerance
// (EnergyBalance::balancedWithin: or round-off), Gained or Lost (the drift's sign) beyond it — a
// numerical failure: the motion was not followed closely enough, the run is one to repeat with
// smaller steps — and Driven when moving pins do work (not checked). Backward Euler and Newmark
// with γ > ½ damp by construction (their numerical dissipation grows with h ω): a loss beyond the
// tolerance there is Dissipated, what the scheme asked for does, not a failure; a gain is one all
// the same.
enum class BalanceVerdict { Balanced, Gained, Lost, Dissipated, Driven };
// balanced | gained | lost | dissipated | driven
const char* balanceVerdictName(BalanceVerdict verdict);

// What an attempt at a step of length h did: taken; declined, to be covered by two steps of h/2;
// or failed, ending the advance.
enum class StepVerdict { Taken, Halve, Failed };

// Covers a step of h by halving: attempt(h, level) tries it (level = the halvings above it), and
// a step it declines is covered by two of h/2, the second only after the first was covered.
// Whether the whole h was covered. The attempt decides when it may halve (the smallest step).
template <class Attempt>
bool coverByHalving(double h, int level, const Attempt& attempt) {
  switch (attempt(h, level)) {
    case StepVerdict::Taken:
      return true;
    case StepVerdict::Failed:
      return false;
    case StepVerdict::Halve:
      break;
  }
  return coverByHalving(h / 2.0, level + 1, attempt) && coverByHalving(h / 2.0, level + 1, attempt);
}

class TimeStepper {
 public:
  // `problem` (xyz; it outlives the stepper): its held vertices are pinned at their start
  // positions, or follow options.pinMotion from them; its held ξ keep their values. Throws
  // InputError for a bad option (DynamicsOptions::validate), obstacles with the explicit scheme,
  // a height problem, or nothing free.
  TimeStepper(const Problem& problem, const DynamicsOptions& options);
  ~TimeStepper();
  TimeStepper(const TimeStepper&) = delete;
  TimeStepper& operator=(const TimeStepper&) = delete;

  // The state at time 0: positions, velocities (#V by 3; pinned rows of v are ignored), ξ (#E or
  // empty: minimized for x). The acceleration comes from the forces. InputError when a vertex is
  // inside or on an obstacle.
  void start(const Positions& x, const Positions& v, const Eigen::VectorXd& xi);
  // As start(), without the test that the shell does not pass through itself or a mesh obstacle:
  // the start that places the pins' rest positions before restore() continues from a state a run
  // reached. After a cut that start is the run's start carried onto the cut mesh, whose lips meet
  // only up to rounding (coplanar faces that overlap by an ulp on a flat sheet).
  void startBeforeRestore(const Positions& x, const Positions& v, const Eigen::VectorXd& xi);

  struct Outcome {
    bool converged = false;
    int newtonIterations = 0;  // chord and Newton steps, and the last, converged, iteration
    std::string failure;       // why it did not converge, for users
    int factorizations = 0;    // Hessians assembled and factored
    NewtonStop stop = NewtonStop::Running;  // why Newton stopped (Converged on success)
    // > 0: Newton converged but the step was refused, the balanced total having grown by this
    // fraction of the energy scale (DynamicsOptions::energyTolerance).
    double energyGrowth = 0.0;
    int pcgSolves = 0, pcgIterations = 0;  // Newton steps solved by PCG instead, its iterations
    int hessians = 0;  // Hessians assembled (Newton steps and their Gauss–Newton retries)
  };
  // Advances by h. On failure the state is unchanged.
  Outcome step(double h);

  // Where a run is, to continue it later exactly (a checkpoint): the state, the contact
  // stiffness κ_v and the energy balance.
  // The self-contact over the steps taken (assembly/self_contact.h; zeros when it is off).
  struct ContactStatistics {
    long steps = 0;      // steps counted
    double pairs = 0.0;  // the pairs within the layer, summed over the steps
    int peakPairs = 0;   // and their largest count after one step
    double smallestDistance = std::numeric_limits<double>::infinity();  // over the steps' ends
    double detectionSeconds = 0.0;  // in the broad phase and the collision filter
    int patternGrowths = 0;         // Hessian patterns rebuilt with new contact couplings
  };
  struct State {
    double time = 0.0;
    Positions x, v, a;
    Eigen::VectorXd xi, contactStiffness;
    EnergyBalance balance;
    ContactStatistics contact;
    // The contact couplings of the Hessian pattern (vertex pairs i < j, sorted).
    std::vector<std::array<int, 2>> contactCouplings;
    double obstacleStiffness = 0.0;  // SelfContact::obstacleStiffness (0: no mesh obstacles)
    // The self-contact's inset pairs (SelfContact::insets); none: inset anew where the state is
    // (a cut's state, whose mesh has other pairs).
    std::optional<std::vector<InsetPair>> contactInsets;
    // SelfContact::vertexStiffness (empty: κ at every vertex).
    Eigen::VectorXd selfContactStiffness;
  };
  State state() const;
  // Continues from `state` (after start() with the run's own start, which places the pins' rest
  // positions): InputError when its sizes do not fit the problem. The kept factor of the step's
  // Hessian is dropped, as forgetFactor() does. A state is one a run reached (a cut's, a
  // checkpoint's): the shell's self-contact is not checked again (a cut's lips start together);
  // the inset pairs are the state's, or when it has none those close at rest and in the state
  // (SelfContact::exemptClosePairs).
  void restore(const State& state);
  // Continues `from`, a stepper of the same problem before its pin groups' vertices `released`
  // (#V) were let go (releasePinGroups; this stepper built without them): its state, with
  // Newmark's a_n that of the equation of motion after the release (the released vertices'
  // M a = M g − ∇E − ∇B − C v, the others' a_n less M⁻¹ C's coupling to the released velocities;
  // addDampingAtRelease) and the pins' work until now booked in the balance
  // (EnergyBalance::pinWork), whose drift is measured from here on. `pinStart`: the positions
  // from's start() took (the remaining pins' time-0 positions).
  void continueAfterRelease(const TimeStepper& from, const Positions& pinStart,
                            const std::vector<bool>& released);
  // Drops the kept factor of the step's Hessian (chord steps start afresh at the next step), so
  // that a run continued from state() follows the same steps as this one.
  void forgetFactor();

  // What advance() did: the steps taken, and where it stopped when it could not go on.
  struct Advance {
    bool completed = false;       // the whole h was advanced
    int steps = 0;                // converged steps (h, or halves of it)
    int halvings = 0;             // failed steps that were split into two halves
    double smallestStep = 0.0;    // the shortest step tried (h when none was halved)
    int newtonIterations = 0;     // over the converged steps
    int maxNewtonIterations = 0;  // of one converged step
    int attemptedIterations = 0;  // over every step tried, failed ones too
    int factorizations = 0;       // over every step tried
    int pcgSolves = 0, pcgIterations = 0, hessians = 0;  // over every step tried
    Outcome failure;          // the last failed step's outcome (completed: none)
    double failedStep = 0.0;  // its length, and the time it started from
    double failedTime = 0.0;

    // Adds `part`'s counts over every step it tried (failed and discarded ones too).
    void addTried(const Advance& part);
    // Adds `part`'s converged steps and their Newton iterations.
    void addConverged(const Advance& part);
    // Adds both, and ends as `part` did (completed, or its failure).
    void addPart(const Advance& part);
  };
  // Advances by h; a step that fails is replaced by two of h/2, recursively, while h/2 ≥ minStep.
  // On failure the state is that after the steps that converged.
  Advance advance(double h, double minStep);

  // The implicit step's objective Φ for a step of h from the current state, at (x, ξ) (#V by 3,
  // #E or empty; the pinned rows are replaced by where the pins are at t + h): its value,
  // gradient and Hessian (dense) over the free unknowns — vertex coordinates 3v + c of unpinned
  // vertices, then 3 #V + e for free ξ_e (`unknowns`) — as each Newton iteration assembles them.
  // For tests; the state is unchanged.
  struct StepObjective {
    const Positions* x = nullptr;
    const Eigen::VectorXd* xi = nullptr;
    double value = 0.0;
    Eigen::VectorXd gradient;
    Eigen::MatrixXd hessian;
    std::vector<int> unknowns;
  };
  StepObjective stepObjective(double h, const Positions& x, const Eigen::VectorXd& xi);

  double time() const { return time_; }
  const Positions& positions() const { return x_; }
  const Positions& velocities() const { return v_; }
  const Eigen::VectorXd& xi() const { return xi_; }
  // Midedge's ξ minimizing E at positions x (#V by 3), the held ones kept from `from`
  // (least_squares.h minimizeEdgeUnknowns); empty for an energy without edge unknowns.
  Eigen::VectorXd edgeUnknownsAt(const Positions& x, const Eigen::VectorXd& from) const;
  const Eigen::VectorXd& masses() const { return mass_; }
  const ObstacleBarrier& barrier() const { return barrier_; }
  const SelfContact& selfContact() const { return selfContact_; }
  const ContactStatistics& contactStatistics() const { return contactStatistics_; }
  // The energies of the current state (computed with each step).
  const EnergySample& energies() const { return energies_; }
  const EnergyBalance& balance() const { return balance_; }
  // Whether the balance's growth is checked (no moving pins or mesh obstacles: they do work).
  bool balanceChecked() const;
  // The balance so far against DynamicsOptions::energyTolerance.
  BalanceVerdict balanceVerdict() const;
  // For a Gained or Lost verdict, what failed: "energy balance: gained 7.3 % of the peak kinetic
  // energy (the largest drift, at t = 0.42, step 84), beyond the 5 % tolerance"; empty otherwise.
  std::string balanceFailure() const;

 private:
  EnergySample energiesAt(double t, const Positions& x, const Positions& v,
                          const Eigen::VectorXd& xi) const;
  // Counts the step to (x, v, a, ξ) at t: refuses it (an outcome with its energyGrowth, the state
  // unchanged) when the balanced total grows beyond the tolerance, else makes it the current
  // state, adapts the contact stiffness and records the balance.
  Outcome commitStep(double t, Positions& x, Positions& v, Positions a, Eigen::VectorXd xi,
                     double dissipation, Outcome outcome);
  struct Implicit;
  class IncrementalPotential;
  // Builds the implicit scheme's Hessian pattern (the terms' and the contact couplings'), its
  // fill-reducing order (at rest, so that it depends on the pattern alone: a run continued from a
  // state follows the same steps), the rest stiffness and the bending damping on it.
  void buildImplicit();
  // Before a step moving the free vertices by about `motion` from x_: lifts the exemptions of
  // pairs now apart and grows the pattern by the couplings of the pairs the motion may bring
  // within the layer (a rebuild when any is new).
  void prepareContact(const Positions& motion);
  // Adds the current state's self-contact census to contactStatistics_.
  void countContact();
  // One step; with `probe`, only Φ and its derivatives at the probe's point (stepObjective).
  Outcome implicitStep(double h, StepObjective* probe = nullptr);
  // The stiffness-proportional damping β K̄ + c K_B(x_n) of the next step on the pattern (empty:
  // none).
  std::vector<double> stiffnessDamping() const;
  // Where the step's Newton loop starts (free unknowns).
  Eigen::VectorXd startingPoint(IncrementalPotential& phi, double h) const;
  static std::string stepFailure(const NewtonResult& newton);
  // Adds a Newton loop's counts to `outcome`, which ends as the loop did.
  static void addNewtonCounts(const NewtonResult& newton, Outcome& outcome);
  // With mesh obstacles, "; the closest pair: … at d" of the contact pairs at x (empty: none).
  std::string closestPairText(const Positions& x) const;
  // The lagged friction of a step of h from the current state (DynamicsOptions::friction): the
  // free vertices' contacts with the analytic obstacles and the collision mesh's pairs within the
  // layer (shell against shell and against the mesh obstacles, these moving until time_ + h).
  Friction stepFriction(double h) const;
  // "t = 0.1 to 0.105" for a step of h from the current time.
  std::string stepSpan(double h) const;
  // Moves the mesh obstacles from where they are at t to where they are at t + h, from the
  // iterate y (free of crossings with them at t), in stages: each moves them as far as continuous
  // collision detection lets them go with the shell held where the last stage left it (every
  // pair keeping a tenth of its distance), then solves the step's Φ from y with them there, so
  // that the shell gives way before the next; a stage that can go less than half the remaining
  // way doubles the obstacles' barrier stiffness κ_o first (never lowered: SelfContact::
  // obstacleStiffness). The stages only give the step a start free of
  // crossings with the obstacles at t + h, where they end (the step is Φ's minimizer with them
  // there). Fails, naming a pair, when the pair that stops a stage has only pinned shell vertices
  // (they cannot give way), when a stage moves them less than 1e-3 of the step (a step too long
  // for the shell to follow) or after 24 stages.
  Outcome moveObstacles(IncrementalPotential& phi, Eigen::VectorXd& y, double h,
                        const StepStopRule& rule);
  Outcome explicitStep(double h);
  Positions accelerationFromForces(const Positions& x, const Eigen::VectorXd& xi) const;
  // Takes the damping force −C v at the current state into a_n after a release (the released
  // vertices' whole C v, the others' coupling to the released velocities); none without damping.
  void addDampingAtRelease(const std::vector<bool>& released);
  // Puts the pinned rows of x (and of v, when given) where the pin motion has them at time t.
  void movePins(Positions& x, Positions* v, double t) const;

  std::vector<const curvature::EnergyTerm*> terms_;
  std::vector<bool> pinned_;
  DynamicsOptions options_;
  Eigen::VectorXd mass_;
  Eigen::Vector3d gravity_;
  double length_ = 1.0;
  std::vector<bool> freeEdge_;
  ObstacleBarrier barrier_;
  SelfContact selfContact_;
  std::vector<std::array<int, 2>> couplings_;  // the contact couplings in the pattern, sorted
  ContactStatistics contactStatistics_;
  std::vector<bool> free_;  // the free unknowns (freeUnknownMask)
  Positions restPositions_;
  Eigen::VectorXd restXi_;
  std::unique_ptr<Implicit> implicit_;
  double time_ = 0.0;
  Positions x_, v_, a_;
  Positions pinnedStart_;  // the positions at time 0 (the pinned rows are read)
  Eigen::VectorXd xi_;
  EnergySample energies_;
  EnergyBalance balance_;
};

}  // namespace flexure::optimize
