#include "optimize/dynamics/time_stepping.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>

#include "modeling/errors.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/linear/least_squares.h"
#include "optimize/solvers/hessian_factorization.h"
#include "optimize/solvers/newton_loop.h"

namespace flexure::optimize {
namespace {

// ε_v of the obstacles' friction per unit of the rest diagonal L: the slip speed, 1e-3 L per
// second, below which it is mollified (DynamicsOptions::friction, friction.h).
constexpr double frictionSlipSpeed = 1e-3;

}  // namespace

const char* integratorName(Integrator integrator) {
  switch (integrator) {
    case Integrator::Newmark:
      return "newmark";
    case Integrator::BackwardEuler:
      return "backward-euler";
    case Integrator::CentralDifference:
      return "central-difference";
  }
  return "";
}

Integrator parseIntegrator(std::string_view name) {
  for (Integrator i :
       {Integrator::Newmark, Integrator::BackwardEuler, Integrator::CentralDifference})
    if (name == integratorName(i)) return i;
  throw InputError("DynamicsOptions.integrator " + std::string(name) +
                   ": expected newmark, backward-euler or central-difference");
}

double EnergySample::total() const {
  double sum = kinetic + gravity + contact;
  for (double e : terms) sum += e;
  return sum;
}

// The implicit step's Newton machinery, built once per run: the Hessian pattern over the free
// unknowns (unpinned vertex coordinates, then ξ), its CHOLMOD analysis, and the free unknowns'
// masses and rest stiffness K̄ (for Rayleigh damping) in the pattern's order; with bending
// damping, the bending term's own pattern and where its entries sit in the full one.
struct TimeStepper::Implicit {
  HessianAssembly assembly;
  HessianFactorization factorization;
  Eigen::VectorXd mass;            // per free unknown: m_v, or 0 for ξ
  std::vector<double> restValues;  // K̄ on the vertex unknowns, in the pattern; empty: β = 0
  std::vector<int> diagonal;       // per free unknown: its diagonal entry in the pattern
  std::unique_ptr<HessianAssembly> bending;  // the first term alone; null without bend damping
  std::vector<int> bendingEntry;             // per entry of its pattern: the full pattern's entry
  // The Newton loop, which keeps the last factor of ∇²Φ, and the step h it was made for (Φ's
  // inertia M/(βh²) depends on h): chord steps reuse it across time steps of the same h.
  NewtonLoop loop;
  double factorStep = 0.0;

  Implicit(const std::vector<const curvature::EnergyTerm*>& terms, const std::vector<bool>& free,
           int vertexCount, const Positions& orderAt,
           const std::vector<std::array<int, 2>>& couplings)
      : assembly(terms, free, vertexCount, curvature::Derivatives::All, couplings),
        factorization(assembly, hessianOrder(assembly, orderAt)),
        loop(assembly, factorization) {}

  // The matrix K (stiffness-proportional damping, on the pattern) times y over the free unknowns.
  Eigen::VectorXd multiply(const std::vector<double>& values, const Eigen::VectorXd& y) const {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(y.size());
    if (values.empty()) return out;
    const std::vector<int>& start = assembly.columnStart();
    const std::vector<int>& row = assembly.rowIndex();
    for (int j = 0; j < assembly.size(); ++j)
      for (int p = start[j]; p < start[j + 1]; ++p) {
        const int i = row[p];
        out[i] += values[p] * y[j];
        if (i != j) out[j] += values[p] * y[i];
      }
    return out;
  }

  // C y = α M y + K y over the free unknowns (K: `stiffness`, as multiply takes it; ξ rows 0).
  Eigen::VectorXd damping(double alpha, const std::vector<double>& stiffness,
                          const Eigen::VectorXd& y) const {
    return Eigen::VectorXd(alpha * mass.cwiseProduct(y) + multiply(stiffness, y));
  }

  // K_B(x) = J_Bᵀ J_B of the bending term at (x, ξ) on the full pattern, vertex unknowns only.
  std::vector<double> bendingStiffness(const Positions& x, const Eigen::VectorXd& xi) const {
    const HessianEvaluation e = bending->evaluate(x, xi, HessianProjection::Exact, nullptr,
                                                  curvature::SecondDerivatives::GaussNewton);
    std::vector<double> values(assembly.rowIndex().size(), 0.0);
    for (size_t p = 0; p < e.values.size(); ++p) values[bendingEntry[p]] = e.values[p];
    keepVertexEntries(values);
    return values;
  }

  // Zeroes the entries of a ξ row or column (ξ carry no mass and no damping).
  void keepVertexEntries(std::vector<double>& values) const {
    const std::vector<int>& start = assembly.columnStart();
    for (int j = 0; j < assembly.size(); ++j)
      for (int p = start[j]; p < start[j + 1]; ++p)
        if (mass[j] == 0.0 || mass[assembly.rowIndex()[p]] == 0.0) values[p] = 0.0;
  }
};

void DynamicsOptions::validatePinGroups(int vertexCount) const {
  std::vector<int> groupOf(vertexCount, -1);
  for (std::size_t g = 0; g < pinGroups.size(); ++g) {
    if (static_cast<int>(pinGroups[g].vertices.size()) != vertexCount)
      throw InputError("DynamicsOptions.pinGroups: group " + std::to_string(g) + " has " +
                       std::to_string(pinGroups[g].vertices.size()) + " entries, the mesh " +
                       std::to_string(vertexCount) + " vertices");
    for (int v = 0; v < vertexCount; ++v) {
      if (!pinGroups[g].vertices[v]) continue;
      if (groupOf[v] >= 0)
        throw InputError("DynamicsOptions.pinGroups: vertex " + std::to_string(v) +
                         " is in groups " + std::to_string(groupOf[v]) + " and " +
                         std::to_string(g));
      groupOf[v] = static_cast<int>(g);
    }
  }
}

double DynamicsOptions::nextRelease() const {
  double next = std::numeric_limits<double>::infinity();
  for (const PinGroup& group : pinGroups) next = std::min(next, group.releaseTime);
  return next;
}

std::vector<bool> releasePinGroups(DynamicsOptions& options, std::vector<bool>& held, double t) {
  std::vector<bool> released;
  std::vector<PinGroup> kept;
  for (PinGroup& group : options.pinGroups) {
    if (group.releaseTime > t) {
      kept.push_back(std::move(group));
      continue;
    }
    released.resize(held.size(), false);
    for (std::size_t v = 0; v < held.size(); ++v)
      if (group.vertices[v]) {
        held[v] = false;
        released[v] = true;
      }
  }
  options.pinGroups = std::move(kept);
  return released;
}

const PinMotion& DynamicsOptions::motionOf(int vertex) const {
  for (const PinGroup& group : pinGroups)
    if (group.vertices[vertex]) return group.motion;
  return pinMotion;
}

bool DynamicsOptions::pinsMove() const {
  return pinMotion.kind != PinMotion::Kind::None ||
         std::any_of(pinGroups.begin(), pinGroups.end(),
                     [](const PinGroup& g) { return g.motion.kind != PinMotion::Kind::None; });
}

void DynamicsOptions::validate() const {
  if (integrator == Integrator::Newmark && !(beta > 0.0 && beta <= 0.5))
    throw InputError("DynamicsOptions.beta " + numberText(beta) +
                     ": expected 0 < β ≤ 0.5 (β = 0 is DynamicsOptions.integrator "
                     "central-difference)");
  if (integrator == Integrator::Newmark && !(gamma >= 0.5 && gamma <= 1.0))
    throw InputError("DynamicsOptions.gamma " + numberText(gamma) + ": expected 0.5 ≤ γ ≤ 1");
  for (const PinGroup& group : pinGroups)
    if (!(group.releaseTime > 0.0))
      throw InputError("PinGroup.releaseTime " + numberText(group.releaseTime) +
                       ": expected a time > 0 (+inf: never released)");
  if (rayleighMass < 0.0 || rayleighStiffness < 0.0)
    throw InputError("DynamicsOptions.rayleighMass|rayleighStiffness: expected α, β ≥ 0");
  if (bendingDamping < 0.0) throw InputError("DynamicsOptions.bendingDamping: expected c ≥ 0");
  if (!(stepTolerance > 0.0) || !std::isfinite(stepTolerance))
    throw InputError("DynamicsOptions.stepTolerance " + numberText(stepTolerance) +
                     ": expected a velocity tolerance ε_v > 0 (per second, relative to the rest "
                     "mesh's bounding-box diagonal)");
  if (!(energyTolerance > 0.0))
    throw InputError("DynamicsOptions.energyTolerance: expected a fraction > 0");
  if (quasiNewtonPairs < 0 || quasiNewtonPairs > 100)
    throw InputError("DynamicsOptions.quasiNewtonPairs " + std::to_string(quasiNewtonPairs) +
                     ": expected 0 (chord steps on the kept factor) to 100 L-BFGS pairs");
  if (!(friction >= 0.0) || !std::isfinite(friction))
    throw InputError("DynamicsOptions.friction " + numberText(friction) +
                     ": expected a finite friction coefficient μ ≥ 0");
  if (integrator == Integrator::CentralDifference &&
      (rayleighMass != 0.0 || rayleighStiffness != 0.0 || bendingDamping != 0.0))
    throw InputError(
        "DynamicsOptions.rayleighMass|rayleighStiffness|bendingDamping: the explicit "
        "central-difference scheme takes no damping; use "
        "newmark or backward-euler");
}

TimeStepper::TimeStepper(const Problem& problem, const DynamicsOptions& options)
    : terms_(problem.termPointers()),
      pinned_(problem.boundary.fixedVertex),
      options_(options),
      mass_(problem.mass),
      gravity_(problem.gravity),
      barrier_(problem.obstacles),
      selfContact_(problem.selfContact) {
  const DynamicsOptions& o = options_;
  o.validate();
  if (problem.dof != DofMode::Xyz)
    throw InputError(
        "TimeStepper moves every coordinate: expected a problem of ProblemOptions.dof xyz");
  if (o.integrator == Integrator::CentralDifference && !barrier_.empty())
    throw InputError(
        "ProblemOptions.obstacles: the explicit central-difference scheme cannot keep vertices "
        "outside; use "
        "newmark or backward-euler");
  if (o.integrator == Integrator::CentralDifference && !selfContact_.empty())
    throw InputError(
        "ProblemOptions.selfContact: the explicit central-difference scheme cannot keep the shell "
        "from passing through itself; use newmark or backward-euler");
  const modeling::RestState& rest = problem.rest;
  const Eigen::VectorXd& restXi = problem.restXi;
  const int vertexCount = problem.stencils.vertexCount();
  o.validatePinGroups(vertexCount);
  if (std::count(pinned_.begin(), pinned_.end(), true) == vertexCount)
    throw InputError("every vertex is pinned: nothing can move");
  length_ = (rest.positions.colwise().maxCoeff() - rest.positions.colwise().minCoeff()).norm();
  xi_ = problem.boundary.xi;
  freeEdge_.resize(problem.boundary.fixedEdge.size());
  for (size_t e = 0; e < freeEdge_.size(); ++e) freeEdge_[e] = !problem.boundary.fixedEdge[e];
  if (o.integrator == Integrator::CentralDifference) return;

  free_ = freeUnknownMask(pinned_, problem.boundary.fixedEdge, DofMode::Xyz);
  restPositions_ = rest.positions;
  restXi_ = restXi;
  buildImplicit();
}

void TimeStepper::buildImplicit() {
  const DynamicsOptions& o = options_;
  const int vertexCount = static_cast<int>(restPositions_.rows());
  implicit_ = std::make_unique<Implicit>(terms_, free_, vertexCount, restPositions_, couplings_);
  Implicit& im = *implicit_;
  const std::vector<int>& unknowns = im.assembly.freeUnknowns();
  im.mass = Eigen::VectorXd::Zero(im.assembly.size());
  im.diagonal.resize(im.assembly.size());
  for (int k = 0; k < im.assembly.size(); ++k) {
    if (unknowns[k] < 3 * vertexCount) im.mass[k] = mass_[unknowns[k] / 3];
    im.diagonal[k] = im.assembly.columnStart()[k + 1] - 1;  // sorted upper columns end on it
  }
  if (o.rayleighStiffness > 0.0) {
    // K̄ = JᵀJ at rest (every residual vanishes there), kept on the vertex unknowns only.
    im.restValues = im.assembly
                        .evaluate(restPositions_, restXi_, HessianProjection::Exact, nullptr,
                                  curvature::SecondDerivatives::GaussNewton)
                        .values;
    im.keepVertexEntries(im.restValues);
  }
  if (o.bendingDamping > 0.0) {
    im.bending =
        std::make_unique<HessianAssembly>(std::vector<const curvature::EnergyTerm*>{terms_.front()},
                                          free_, vertexCount, curvature::Derivatives::All);
    const std::vector<int>& start = im.bending->columnStart();
    const std::vector<int>& row = im.bending->rowIndex();
    const std::vector<int>& fullStart = im.assembly.columnStart();
    const std::vector<int>& fullRow = im.assembly.rowIndex();
    im.bendingEntry.resize(row.size());
    for (int j = 0; j < im.bending->size(); ++j)
      for (int p = start[j]; p < start[j + 1]; ++p) {
        // The same free unknowns, numbered alike: the entry (row[p], j) of the full pattern.
        const auto begin = fullRow.begin() + fullStart[j], end = fullRow.begin() + fullStart[j + 1];
        im.bendingEntry[p] =
            static_cast<int>(std::lower_bound(begin, end, row[p]) - fullRow.begin());
      }
  }
}

TimeStepper::~TimeStepper() = default;

Positions TimeStepper::accelerationFromForces(const Positions& x, const Eigen::VectorXd& xi) const {
  const EnergyGradient e = energyGradient(terms_, x, xi);
  Positions contact = Positions::Zero(x.rows(), 3);
  barrier_.addGradient(x, contact);
  selfContact_.addGradient(x, contact);
  Positions a = Positions::Zero(x.rows(), 3);
  for (int v = 0; v < x.rows(); ++v) {
    if (pinned_[v]) continue;
    for (int c = 0; c < 3; ++c)
      a(v, c) = gravity_[c] - (e.gradient[3 * v + c] + contact(v, c)) / mass_[v];
  }
  return a;
}

void TimeStepper::movePins(Positions& x, Positions* v, double t) const {
  for (int k = 0; k < x.rows(); ++k) {
    if (!pinned_[k]) continue;
    const Eigen::Vector3d start = pinnedStart_.row(k).transpose();
    const PinMotion& motion = options_.motionOf(k);
    x.row(k) = motion.position(start, t).transpose();
    if (v != nullptr) v->row(k) = motion.velocityAt(start, t).transpose();
  }
}

void TimeStepper::start(const Positions& x, const Positions& v, const Eigen::VectorXd& xi) {
  startBeforeRestore(x, v, xi);
  selfContact_.requireApart(x_, "the start");
}

void TimeStepper::startBeforeRestore(const Positions& x, const Positions& v,
                                     const Eigen::VectorXd& xi) {
  const Eigen::Index n = static_cast<Eigen::Index>(pinned_.size());
  if (x.rows() != n || v.rows() != n)
    throw InputError("the start " + std::string(x.rows() != n ? "positions" : "velocities") +
                     " have " + std::to_string((x.rows() != n ? x : v).rows()) +
                     " rows, the mesh " + std::to_string(n) + " vertices");
  barrier_.requireOutside(x, "the start");
  x_ = x;
  v_ = v;
  pinnedStart_ = x;
  movePins(x_, &v_, 0.0);
  xi_ = xi.size() > 0 ? xi : xi_;
  if (xi_.size() > 0) xi_ = minimizeEdgeUnknowns(terms_, x_, xi_, freeEdge_);
  selfContact_.setObstacleTime(0.0);
  selfContact_.exemptClosePairs(x_);
  contactStatistics_ = ContactStatistics();
  time_ = 0.0;
  if (implicit_) implicit_->loop.forget();
  // The next step's contact stiffness (obstacles.h, self_contact.h).
  barrier_.resetStiffness();
  barrier_.adapt(x_, v_, mass_);
  selfContact_.resetStiffness();
  selfContact_.adapt(x_, v_, mass_, 0.0);
  // With damping the initial acceleration also carries −M⁻¹ C v₀; a start at rest (v₀ = 0, the
  // usual case) has none, and a moving start takes the undamped one.
  a_ = accelerationFromForces(x_, xi_);
  energies_ = energiesAt(time_, x_, v_, xi_);
  balance_.start(energies_);
}

Eigen::VectorXd TimeStepper::edgeUnknownsAt(const Positions& x, const Eigen::VectorXd& from) const {
  return from.size() > 0 ? minimizeEdgeUnknowns(terms_, x, from, freeEdge_) : from;
}

TimeStepper::State TimeStepper::state() const {
  const double obstacleStiffness =
      selfContact_.meshObstacles().empty() ? 0.0 : selfContact_.obstacleStiffness();
  return {time_,
          x_,
          v_,
          a_,
          xi_,
          barrier_.stiffness(),
          balance_,
          contactStatistics_,
          couplings_,
          obstacleStiffness,
          selfContact_.insets(),
          selfContact_.vertexStiffness()};
}

void TimeStepper::restore(const State& state) {
  const bool fits = state.x.rows() == x_.rows() && state.v.rows() == x_.rows() &&
                    state.a.rows() == x_.rows() && state.xi.size() == xi_.size() &&
                    state.x.allFinite() && state.v.allFinite() && state.a.allFinite() &&
                    std::isfinite(state.time);
  if (!fits)
    throw InputError("TimeStepper::restore: the state does not fit the problem (" +
                     std::to_string(x_.rows()) + " vertices, " + std::to_string(xi_.size()) +
                     " edge unknowns)");
  barrier_.requireOutside(state.x, "the restored state");
  selfContact_.setObstacleTime(state.time);
  if (state.obstacleStiffness > 0.0 && !selfContact_.meshObstacles().empty())
    selfContact_.setObstacleStiffness(state.obstacleStiffness);
  if (!barrier_.empty()) barrier_.setStiffness(state.contactStiffness);
  if (!selfContact_.empty() && state.selfContactStiffness.size() > 0)
    selfContact_.setVertexStiffness(state.selfContactStiffness);
  time_ = state.time;
  x_ = state.x;
  v_ = state.v;
  a_ = state.a;
  xi_ = state.xi;
  balance_ = state.balance;
  contactStatistics_ = state.contact;
  if (state.contactInsets)
    selfContact_.setInsets(*state.contactInsets);
  else
    selfContact_.exemptClosePairs(x_);  // a cut's fresh lips, and older ones still within d̂
  if (implicit_ && state.contactCouplings != couplings_) {
    couplings_ = state.contactCouplings;
    buildImplicit();
  }
  forgetFactor();
  energies_ = energiesAt(time_, x_, v_, xi_);
}

void TimeStepper::continueAfterRelease(const TimeStepper& from, const Positions& pinStart,
                                       const std::vector<bool>& released) {
  start(pinStart, from.v_, from.xi_);
  State s = from.state();
  const Positions forced = accelerationFromForces(s.x, s.xi);
  for (Eigen::Index v = 0; v < s.a.rows(); ++v)
    if (released[static_cast<std::size_t>(v)]) s.a.row(v) = forced.row(v);
  EnergyBalance& b = s.balance;
  b.pinWork += b.balanced(from.energies()) - b.initial;
  b.last = b.initial;
  b.largestDrift = 0.0;
  b.driftTime = s.time;
  b.driftStep = b.steps;
  restore(s);
  addDampingAtRelease(released);
}

// At the release T the velocities are continuous (a released vertex goes on with its pin's
// velocity v_R at T, which movePins left in v) but the acceleration jumps: before T, with F the
// free vertices and R the held ones, Newmark's last step solved
//   M a_F + C_FF v_F + ∇_F (E + B) − M g = 0   (damping acts on the free velocities only),
// and from T on the free vertices are F ∪ R, with C = α M + β K̄ + c K_B over all of them. The
// equation of motion at T⁺ then gives (C_FR: the coupling of F to R, none for α M)
//   a_F = a_F(T⁻) − M⁻¹ C_FR v_R,   a_R = g − M⁻¹ (∇_R (E + B) + C_RF v_F + C_RR v_R),
// the forces' part of a_R set by continueAfterRelease. Newmark's next step starts from this a_n
// (x̂, v̂, and the trapezoidal v_{n+1} = v_n + ½ h (a_n + a_{n+1})); with the damping left out of
// a_n, a piece let go gained ½ h 1ᵀ(C v) of spurious momentum in that step. (c K_B is taken at
// x(T), as the next step takes it.) Nothing changes without damping.
void TimeStepper::addDampingAtRelease(const std::vector<bool>& released) {
  if (!implicit_) return;
  const std::vector<double> stiffness = stiffnessDamping();
  if (options_.rayleighMass == 0.0 && stiffness.empty()) return;
  const Implicit& im = *implicit_;
  const std::vector<int>& unknowns = im.assembly.freeUnknowns();
  const long positionCount = x_.size();
  // C y over the free vertex coordinates, for y = v (all) and y = v on R only (coupling).
  Eigen::VectorXd all = Eigen::VectorXd::Zero(im.assembly.size()), onReleased = all;
  for (int k = 0; k < im.assembly.size(); ++k) {
    if (unknowns[k] >= positionCount) continue;
    all[k] = v_.data()[unknowns[k]];
    if (released[static_cast<std::size_t>(unknowns[k] / 3)]) onReleased[k] = all[k];
  }
  const Eigen::VectorXd cAll = im.damping(options_.rayleighMass, stiffness, all);
  const Eigen::VectorXd cCoupling = im.damping(options_.rayleighMass, stiffness, onReleased);
  for (int k = 0; k < im.assembly.size(); ++k) {
    if (unknowns[k] >= positionCount) continue;
    const int v = unknowns[k] / 3;
    a_.data()[unknowns[k]] -=
        (released[static_cast<std::size_t>(v)] ? cAll : cCoupling)[k] / mass_[v];
  }
}

void TimeStepper::forgetFactor() {
  if (implicit_) implicit_->loop.forget();
}

TimeStepper::Outcome TimeStepper::step(double h) {
  Outcome outcome;
  try {
    outcome = implicit_ ? implicitStep(h) : explicitStep(h);
  } catch (const NumericalError& e) {
    outcome = {false, 0, e.what(), 0, NewtonStop::NonFinite};
  }
  selfContact_.setObstacleTime(time_);  // where the current state has them, the step taken or not
  return outcome;
}

TimeStepper::Advance TimeStepper::advance(double h, double minStep) {
  // A bound below which halving stops must be positive, or a step that keeps failing would be
  // halved without end.
  if (!(h > 0.0) || !(minStep > 0.0) || !(minStep <= h) || !std::isfinite(h)) {
    throw InputError("TimeStepper::advance: expected 0 < minStep <= h (got h = " + numberText(h) +
                     ", minStep = " + numberText(minStep) + ")");
  }
  Advance advance;
  advance.smallestStep = h;
  advance.completed = coverByHalving(h, 0, [&](double length, int) {
    const double from = time_;
    const Outcome outcome = step(length);
    advance.attemptedIterations += outcome.newtonIterations;
    advance.factorizations += outcome.factorizations;
    advance.pcgSolves += outcome.pcgSolves;
    advance.pcgIterations += outcome.pcgIterations;
    advance.hessians += outcome.hessians;
    if (outcome.converged) {
      ++advance.steps;
      advance.newtonIterations += outcome.newtonIterations;
      advance.maxNewtonIterations = std::max(advance.maxNewtonIterations, outcome.newtonIterations);
      return StepVerdict::Taken;
    }
    if (length / 2.0 < minStep) {
      advance.failure = outcome;
      advance.failedStep = length;
      advance.failedTime = from;
      return StepVerdict::Failed;
    }
    ++advance.halvings;
    advance.smallestStep = std::min(advance.smallestStep, length / 2.0);
    return StepVerdict::Halve;
  });
  return advance;
}

TimeStepper::Outcome TimeStepper::explicitStep(double h) {
  Positions x = x_ + h * v_ + 0.5 * h * h * a_;
  movePins(x, nullptr, time_ + h);
  const Eigen::VectorXd xi = xi_.size() > 0 ? minimizeEdgeUnknowns(terms_, x, xi_, freeEdge_) : xi_;
  const Positions a = accelerationFromForces(x, xi);
  if (!a.allFinite())
    return {false, 0, "the forces are not finite (the step is unstable)", 0, NewtonStop::NonFinite};
  Positions v = v_ + 0.5 * h * (a_ + a);
  return commitStep(time_ + h, x, v, a, xi, 0.0, {true, 0, "", 0, NewtonStop::Converged});
}

TimeStepper::StepObjective TimeStepper::stepObjective(double h, const Positions& x,
                                                      const Eigen::VectorXd& xi) {
  if (!implicit_) throw InputError("the explicit scheme minimizes no step objective");
  StepObjective objective;
  objective.x = &x;
  objective.xi = &xi;
  implicitStep(h, &objective);
  return objective;
}

// The implicit step's objective (objective.h), over the free unknowns y (the ξ entries of `hat`
// and of the masses are 0):
//
//   Φ(y) = E + B + D + ½ dᵀ M d / (β h²) + γ dᵀ C d / (2 β h) + (C v̂)ᵀ d − (M g)ᵀ y,  d = y − x̂,
//
// (time_stepping.h; (C v̂)ᵀ x differs from (C v̂)ᵀ d by a constant) with C = α M + K_s, K_s the
// stiffness-proportional damping β K̄ + c K_B(x_n) of this step on the pattern (empty: none).
class TimeStepper::IncrementalPotential : public Objective {
 public:
  IncrementalPotential(const Implicit& im, Configuration fixedPart,
                       const std::vector<const curvature::EnergyTerm*>& terms,
                       const ObstacleBarrier& barrier, const SelfContact& selfContact,
                       const Friction& friction, const Eigen::Vector3d& gravity,
                       const DynamicsOptions& o, double h, const Positions& xHat,
                       const Positions& vHat, std::vector<double> stiffnessDamping)
      : Objective(im.assembly, std::move(fixedPart)),
        im_(im),
        terms_(terms),
        barrier_(barrier),
        selfContact_(selfContact),
        friction_(friction),
        rayleighMass_(o.rayleighMass),
        stiffnessDamping_(std::move(stiffnessDamping)) {
    const bool euler = o.integrator == Integrator::BackwardEuler;
    const double beta = euler ? 1.0 : o.beta, gamma = euler ? 1.0 : o.gamma;
    massWeight_ = 1.0 / (beta * h * h);
    dampingWeight_ = gamma / (beta * h);
    const std::vector<int>& unknowns = im.assembly.freeUnknowns();
    const int n = im.assembly.size();
    const long positionCount = xHat.size();
    hat_.resize(n);
    gravityForce_.resize(n);
    Eigen::VectorXd vHatFree(n);
    for (int k = 0; k < n; ++k) {
      const long u = unknowns[k];
      const bool vertex = u < positionCount;
      hat_[k] = vertex ? xHat.data()[u] : 0.0;
      vHatFree[k] = vertex ? vHat.data()[u] : 0.0;
      gravityForce_[k] = vertex ? im.mass[k] * gravity[u % 3] : 0.0;
    }
    dampingOfVHat_ = damping(vHatFree);
    // Every vertex free, no obstacle (fixed in space) and no friction: E, the self-contact
    // barrier and the stiffness damping K_s are invariant under a rigid translation τ, so
    // ∇²Φ τ = (1/(βh²) + γα/(βh)) M τ.
    int freeVertexCoordinates = 0;
    for (int k = 0; k < n; ++k) freeVertexCoordinates += unknowns[k] < positionCount;
    translationInvariant_ = freeVertexCoordinates == positionCount && barrier_.empty() &&
                            friction_.empty() && selfContact_.meshObstacles().empty();
  }

  // δ + Σ_d c_d τ_d with τ_dᵀ W (δ + c_d τ_d) = −τ_dᵀ∇Φ, W = (1/(βh²) + γα/(βh)) M, for the
  // translations τ_d along each axis d (Objective::keepTranslationResidual).
  void keepTranslationResidual(const Eigen::VectorXd& gradient,
                               Eigen::VectorXd& delta) const override {
    if (!translationInvariant_) return;
    const std::vector<int>& unknowns = im_.assembly.freeUnknowns();
    const long positionCount = fixedPart().positions.size();
    const double w = massWeight_ + dampingWeight_ * rayleighMass_;
    double residual[3] = {0.0, 0.0, 0.0}, mass[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < size(); ++k) {
      if (unknowns[k] >= positionCount) continue;
      const int d = unknowns[k] % 3;
      residual[d] += gradient[k] + w * im_.mass[k] * delta[k];
      mass[d] += w * im_.mass[k];
    }
    for (int k = 0; k < size(); ++k)
      if (unknowns[k] < positionCount && mass[unknowns[k] % 3] > 0.0)
        delta[k] -= residual[unknowns[k] % 3] / mass[unknowns[k] % 3];
  }

  const Eigen::VectorXd& hat() const { return hat_; }

  // Φ and ∇Φ at y, and ∇²Φ on the pattern with ∇²E exact or its Gauss–Newton part (`kind`):
  // ∇²E + ∇²B + M/(βh²) + γ C/(βh) (C's α M on the diagonal, its stiffness part everywhere); the
  // contact barriers' ∇²B exact with the exact ∇²E, else each vertex's or pair's projected to
  // positive semidefinite.
  HessianEvaluation evaluate(const Eigen::VectorXd& y, curvature::SecondDerivatives kind) override {
    const Configuration at = configuration(y);
    HessianEvaluation e =
        im_.assembly.evaluate(at.positions, at.xi, HessianProjection::Exact, nullptr, kind);
    barrier_.add(im_.assembly, at.positions, e, kind != curvature::SecondDerivatives::Exact);
    selfContact_.add(im_.assembly, at.positions, e, kind != curvature::SecondDerivatives::Exact);
    if (!friction_.empty()) friction_.add(im_.assembly, at.positions, e);
    Eigen::VectorXd extraGradient;
    e.energy += inertiaDampingGravity(y, &extraGradient);
    e.gradient += extraGradient;
    if (kind == curvature::SecondDerivatives::None) return e;
    for (int k = 0; k < size(); ++k)
      e.values[im_.diagonal[k]] += (massWeight_ + dampingWeight_ * rayleighMass_) * im_.mass[k];
    for (size_t p = 0; p < stiffnessDamping_.size(); ++p)
      e.values[p] += dampingWeight_ * stiffnessDamping_[p];
    return e;
  }

  double lineSearchValue(const Eigen::VectorXd& y) override {
    const Configuration at = configuration(y);
    double e = 0.0;
    for (const curvature::EnergyTerm* term : terms_) e += term->energy(at.positions, at.xi);
    const double phi = e + inertiaDampingGravity(y, nullptr) + barrier_.energy(at.positions) +
                       selfContact_.energy(at.positions);  // +∞ inside an obstacle or a touch
    return friction_.empty() ? phi : phi + friction_.energy(at.positions);
  }

  // The obstacles' per-vertex bounds α_v, all scaled by the self-contact's bound on the motion
  // they leave (each vertex moved by α_v δ_v), so that the scaled step is free of crossings too.
  Eigen::VectorXd vertexStepBounds(const Eigen::VectorXd& y,
                                   const Eigen::VectorXd& delta) override {
    if (barrier_.empty() && selfContact_.empty()) return Eigen::VectorXd();
    const Positions x = configuration(y).positions;
    Positions dx = displacement(delta);
    Eigen::VectorXd bounds =
        barrier_.empty() ? Eigen::VectorXd::Ones(x.rows()) : barrier_.vertexStepBounds(x, dx);
    if (selfContact_.empty()) return bounds;
    for (Eigen::Index v = 0; v < dx.rows(); ++v) dx.row(v) *= bounds[v];
    return bounds * selfContact_.stepBound(x, dx);
  }

  // The obstacles' bound on δ itself and the self-contact's on the same motion.
  double stepBound(const Eigen::VectorXd& y, const Eigen::VectorXd& delta) override {
    const Positions x = configuration(y).positions, dx = displacement(delta);
    const double obstacles = barrier_.empty() ? 1.0 : barrier_.stepBound(x, dx);
    return std::min(obstacles, selfContact_.stepBound(x, dx));
  }

  // 1e-14 of the sum of Φ's parts' magnitudes (E, B and the inertia are ≥ 0; the linear gravity
  // and damping parts can cancel them, leaving |Φ| far below the parts).
  double roundoff(const Eigen::VectorXd& y, double value) const override {
    const Eigen::VectorXd d = (y - hat_).cwiseProduct(im_.mass.cwiseSign());
    return 1e-14 * (std::abs(value) + 2.0 * std::abs(gravityForce_.dot(y)) +
                    2.0 * std::abs(dampingOfVHat_.dot(d)));
  }

  double massWeight() const { return massWeight_; }

  // The work dxᵀ C v against the damping over the free vertex coordinates (dx, v: #V by 3).
  double dampingWork(const Positions& dx, const Positions& v, long positionCount) const {
    if (rayleighMass_ == 0.0 && stiffnessDamping_.empty()) return 0.0;
    const std::vector<int>& unknowns = im_.assembly.freeUnknowns();
    Eigen::VectorXd dxFree = Eigen::VectorXd::Zero(size()), vFree = Eigen::VectorXd::Zero(size());
    for (int k = 0; k < size(); ++k) {
      if (unknowns[k] >= positionCount) continue;
      dxFree[k] = dx.data()[unknowns[k]];
      vFree[k] = v.data()[unknowns[k]];
    }
    return dxFree.dot(damping(vFree));
  }

 private:
  Eigen::VectorXd damping(const Eigen::VectorXd& y) const {  // C y, ξ rows 0
    return im_.damping(rayleighMass_, stiffnessDamping_, y);
  }

  // Φ's inertial, damping and gravity parts at y, and their gradient.
  double inertiaDampingGravity(const Eigen::VectorXd& y, Eigen::VectorXd* gradient) const {
    const Eigen::VectorXd d = (y - hat_).cwiseProduct(im_.mass.cwiseSign());  // 0 on ξ
    const Eigen::VectorXd cd = damping(d);
    if (gradient != nullptr)
      *gradient = massWeight_ * im_.mass.cwiseProduct(d) + dampingWeight_ * cd + dampingOfVHat_ -
                  gravityForce_;
    return 0.5 * massWeight_ * d.dot(im_.mass.cwiseProduct(d)) + 0.5 * dampingWeight_ * d.dot(cd) +
           dampingOfVHat_.dot(d) - gravityForce_.dot(y);
  }

  const Implicit& im_;
  const std::vector<const curvature::EnergyTerm*>& terms_;
  const ObstacleBarrier& barrier_;
  const SelfContact& selfContact_;
  const Friction& friction_;
  const double rayleighMass_;
  const std::vector<double> stiffnessDamping_;
  double massWeight_ = 0.0, dampingWeight_ = 0.0;
  Eigen::VectorXd hat_, gravityForce_, dampingOfVHat_;
  bool translationInvariant_ = false;  // keepTranslationResidual applies
};

std::vector<double> TimeStepper::stiffnessDamping() const {
  const Implicit& im = *implicit_;
  const DynamicsOptions& o = options_;
  std::vector<double> stiffnessDamping;
  if (!im.restValues.empty() && o.rayleighStiffness > 0.0) {
    stiffnessDamping = im.restValues;
    for (double& value : stiffnessDamping) value *= o.rayleighStiffness;
  }
  if (im.bending) {
    const std::vector<double> kb = im.bendingStiffness(x_, xi_);
    if (stiffnessDamping.empty()) stiffnessDamping.assign(kb.size(), 0.0);
    for (size_t e = 0; e < kb.size(); ++e) stiffnessDamping[e] += o.bendingDamping * kb[e];
  }
  return stiffnessDamping;
}

// Newton starts at x̂ + β h² a_n, the solution if the acceleration stayed a_n (x_n + h v_n +
// ½ h² a_n for Newmark: Taylor to second order; x̂ itself assumes a = 0), except at vertices
// within two barrier layers of an obstacle, which start where they are, at x_n: their
// acceleration flips from step to step with the contact (Newmark's average acceleration does
// not damp the barrier's stiff mode), and measured on the drape benchmark, starting them at x̂
// made every other step cost several times the Newton steps. With obstacles, y moves from x_n
// towards the guess as far as they allow (x_n is outside every obstacle; the guess need not be).
Eigen::VectorXd TimeStepper::startingPoint(IncrementalPotential& phi, double h) const {
  const Implicit& im = *implicit_;
  const bool euler = options_.integrator == Integrator::BackwardEuler;
  const double beta = euler ? 1.0 : options_.beta;
  const std::vector<int>& unknowns = im.assembly.freeUnknowns();
  const long positionCount = x_.size();
  Eigen::VectorXd y = phi.freeValues(phi.fixedPart());
  Eigen::VectorXd guess = phi.hat();
  if (options_.predictAcceleration) {
    for (int k = 0; k < im.assembly.size(); ++k) {
      if (unknowns[k] >= positionCount) continue;
      const int v = unknowns[k] / 3;
      bool near = false;
      for (const Obstacle& obstacle : barrier_.obstacles())
        near = near || obstacle.signedDistance(x_.row(v).transpose()) < 2.0 * barrier_.layer();
      guess[k] = near ? x_.data()[unknowns[k]] : guess[k] + beta * h * h * a_.data()[unknowns[k]];
    }
  }
  const Eigen::VectorXd toGuess = (guess - y).cwiseProduct(im.mass.cwiseSign());  // 0 on ξ
  y += phi.stepBound(y, toGuess) * toGuess;
  return y;
}

void TimeStepper::prepareContact(const Positions& motion) {
  selfContact_.liftExemptions(x_);
  std::vector<std::array<int, 2>> wanted = selfContact_.couplings(x_, motion);
  std::vector<std::array<int, 2>> merged;
  std::set_union(couplings_.begin(), couplings_.end(), wanted.begin(), wanted.end(),
                 std::back_inserter(merged));
  if (merged.size() == couplings_.size()) return;
  couplings_ = std::move(merged);
  buildImplicit();
  ++contactStatistics_.patternGrowths;
}

void TimeStepper::countContact() {
  if (selfContact_.empty()) return;
  const ContactCensus census = selfContact_.census(x_);
  ContactStatistics& c = contactStatistics_;
  ++c.steps;
  c.pairs += census.pairs;
  c.peakPairs = std::max(c.peakPairs, census.pairs);
  c.smallestDistance = std::min(c.smallestDistance, census.smallestDistance);
  c.detectionSeconds += selfContact_.takeDetectionSeconds();
}

TimeStepper::Outcome TimeStepper::implicitStep(double h, StepObjective* probe) {
  const DynamicsOptions& o = options_;
  const bool euler = o.integrator == Integrator::BackwardEuler;
  const double beta = euler ? 1.0 : o.beta, gamma = euler ? 1.0 : o.gamma;
  const double p = euler ? 0.0 : 0.5 - beta, q = euler ? 0.0 : 1.0 - gamma;
  // The predictors x̂ = x_n + h v_n + h² (½ − β) a_n, v̂ = v_n + h (1 − γ) a_n.
  const Positions xHat = x_ + h * v_ + p * h * h * a_;
  const Positions vHat = v_ + q * h * a_;

  // x_n with the pinned vertices where they are at t + h: the fixed part of every iterate.
  Positions moved = x_;
  movePins(moved, nullptr, time_ + h);
  if (!barrier_.empty() && options_.pinsMove()) {
    int vertex = -1;
    if (barrier_.smallestDistance(moved, &vertex) <= 0.0 && pinned_[vertex])
      return {false, 0, "pinned vertex " + std::to_string(vertex) + " is moved into an obstacle", 0,
              NewtonStop::Infeasible};
  }
  if (!selfContact_.empty()) {
    // A pin moved through the shell (or a mesh obstacle, where it is at t) would start every
    // iterate on the far side of a pair.
    selfContact_.setObstacleTime(time_);
    ContactPair limiting;
    if (selfContact_.stepBound(x_, moved - x_, time_, &limiting) < 1.0)
      return {false, 0,
              "the pins' motion over the step from " + stepSpan(h) + " brings " +
                  selfContact_.describe(limiting) + " into contact",
              0, NewtonStop::Infeasible};
    prepareContact(xHat - x_);
  }
  Implicit& im = *implicit_;  // after prepareContact, which may rebuild it
  const Friction friction = stepFriction(h);
  IncrementalPotential phi(im, Configuration{moved, xi_}, terms_, barrier_, selfContact_, friction,
                           gravity_, o, h, xHat, vHat, stiffnessDamping());
  if (probe != nullptr) {  // Φ at the probe's (x, ξ), the state unchanged
    const Eigen::VectorXd y = phi.freeValues(Configuration{*probe->x, *probe->xi});
    const HessianEvaluation at = phi.evaluate(y, curvature::SecondDerivatives::Exact);
    probe->value = at.energy;
    probe->gradient = at.gradient;
    probe->unknowns = im.assembly.freeUnknowns();
    const int n = im.assembly.size();
    probe->hessian = Eigen::MatrixXd::Zero(n, n);
    for (int j = 0; j < n; ++j)
      for (int e = im.assembly.columnStart()[j]; e < im.assembly.columnStart()[j + 1]; ++e) {
        const int i = im.assembly.rowIndex()[e];
        probe->hessian(i, j) = probe->hessian(j, i) = at.values[e];
      }
    return {};
  }

  Eigen::VectorXd y = startingPoint(phi, h);
  if (im.factorStep != h) im.loop.forget();
  im.factorStep = h;  // the h of every factor this step makes
  StepStopRule rule;
  rule.step = o.stepTolerance * length_ * h;  // ‖δ‖∞ / h ≤ ε_v l
  rule.maxNewtonSteps = o.maxNewtonIterations;
  rule.chordSteps = o.chordSteps;
  rule.hessian = o.hessian;
  rule.preconditionedSteps = o.preconditionedSteps;
  rule.quasiNewtonPairs = o.quasiNewtonPairs;
  Outcome outcome = moveObstacles(phi, y, h, rule);
  if (!outcome.converged) return outcome;
  const NewtonResult newton = im.loop.run(phi, y, rule);
  addNewtonCounts(newton, outcome);
  if (!outcome.converged) {
    outcome.failure = stepFailure(newton) + closestPairText(phi.configuration(y).positions);
    return outcome;
  }
  Configuration end = phi.configuration(y);
  Positions a = (end.positions - xHat) * phi.massWeight();
  for (int v = 0; v < a.rows(); ++v)
    if (pinned_[v]) a.row(v).setZero();
  Positions v = vHat + gamma * h * a;
  double dissipation =
      phi.dampingWork(end.positions - x_, (1.0 - gamma) * v_ + gamma * v, x_.size());
  if (!friction.empty()) dissipation += friction.work(end.positions);
  return commitStep(time_ + h, end.positions, v, std::move(a), std::move(end.xi), dissipation,
                    outcome);
}

void TimeStepper::addNewtonCounts(const NewtonResult& newton, Outcome& outcome) {
  outcome.converged = newton.stop == NewtonStop::Converged;
  outcome.newtonIterations += newton.iterations;
  outcome.factorizations += newton.factorizations;
  outcome.pcgSolves += newton.pcgSolves;
  outcome.pcgIterations += newton.pcgIterations;
  outcome.hessians += newton.newtonSteps + newton.gaussNewtonSteps;
  outcome.stop = newton.stop;
}

Friction TimeStepper::stepFriction(double h) const {
  const double mu = options_.friction, slip = frictionSlipSpeed * length_ * h;
  if (!(mu > 0.0)) return {};
  std::vector<FrictionContact> contacts = obstacleFrictionContacts(barrier_, x_, pinned_);
  if (!selfContact_.empty()) {
    std::vector<FrictionContact> pairs = selfContact_.frictionContacts(x_, time_ + h);
    contacts.insert(contacts.end(), pairs.begin(), pairs.end());
  }
  return Friction(std::move(contacts), x_, mu, slip);
}

std::string TimeStepper::closestPairText(const Positions& x) const {
  if (selfContact_.meshObstacles().empty()) return {};
  const ContactCensus census = selfContact_.census(x);
  if (census.pairs == 0) return {};
  char distance[40];
  std::snprintf(distance, sizeof distance, " at %.3g", census.smallestDistance);
  return "; the closest pair: " + selfContact_.describe(census.closest) + distance;
}

std::string TimeStepper::stepSpan(double h) const {
  char text[120];
  std::snprintf(text, sizeof text, "t = %.6g to %.6g", time_, time_ + h);
  return text;
}

TimeStepper::Outcome TimeStepper::moveObstacles(IncrementalPotential& phi, Eigen::VectorXd& y,
                                                double h, const StepStopRule& rule) {
  constexpr int kMaxStages = 24;
  constexpr double kLeastAdvance = 1e-3;  // of the step
  Outcome outcome;
  outcome.converged = true;
  outcome.stop = NewtonStop::Converged;
  if (!selfContact_.obstaclesMove()) return outcome;
  const Positions still = Positions::Zero(x_.rows(), 3);
  double reached = 0.0;  // the fraction of the step the obstacles have gone
  for (int stage = 0;; ++stage) {
    ContactPair limiting;
    const double bound =
        selfContact_.stepBound(phi.configuration(y).positions, still, time_ + h, &limiting);
    if (bound >= 1.0) break;
    const std::vector<int> shell = selfContact_.shellVerticesOf(limiting);
    const bool held = std::all_of(shell.begin(), shell.end(), [&](int v) { return pinned_[v]; });
    if (bound < 0.5 && !held)
      selfContact_.setObstacleStiffness(2.0 * selfContact_.obstacleStiffness());
    const double next = reached + bound * (1.0 - reached);
    if (held || next - reached < kLeastAdvance || stage == kMaxStages) {
      char part[80];
      std::snprintf(part, sizeof part, " (after %.3g of the step, %d stages)", reached, stage);
      return {false, outcome.newtonIterations,
              "the mesh obstacles' motion over the step from " + stepSpan(h) + " drives " +
                  selfContact_.describe(limiting) + " into contact: the shell does not give way" +
                  part,
              outcome.factorizations, NewtonStop::Infeasible};
    }
    reached = next;
    selfContact_.setObstacleTime(time_ + reached * h);
    addNewtonCounts(implicit_->loop.run(phi, y, rule), outcome);
    if (!outcome.converged) {
      outcome.failure = "with the mesh obstacles part of the way: " + outcome.failure;
      return outcome;
    }
  }
  selfContact_.setObstacleTime(time_ + h);
  return outcome;
}

std::string TimeStepper::stepFailure(const NewtonResult& newton) {
  switch (newton.stop) {
    case NewtonStop::NotPositiveDefinite:
      return "the step's Hessian is not positive definite";
    case NewtonStop::LineSearchFailed:
      return "the line search found no decrease of Φ";
    case NewtonStop::MaxIterations:
      return "Newton did not converge in " + std::to_string(newton.iterations) + " iterations (" +
             std::to_string(newton.newtonSteps) + " Newton steps)";
    default:
      return newtonStopMessage(newton.stop);
  }
}

EnergySample TimeStepper::energiesAt(double t, const Positions& x, const Positions& v,
                                     const Eigen::VectorXd& xi) const {
  EnergySample s;
  s.time = t;
  for (int k = 0; k < x.rows(); ++k) {
    s.kinetic += 0.5 * mass_[k] * v.row(k).squaredNorm();
    s.gravity -= mass_[k] * gravity_.dot(x.row(k).transpose());
  }
  for (const curvature::EnergyTerm* term : terms_) s.terms.push_back(term->energy(x, xi));
  s.contact = barrier_.energy(x) + selfContact_.energy(x);
  return s;
}

bool TimeStepper::balanceChecked() const {
  return !options_.pinsMove() && !selfContact_.obstaclesMove();
}

const char* balanceVerdictName(BalanceVerdict verdict) {
  switch (verdict) {
    case BalanceVerdict::Balanced:
      return "balanced";
    case BalanceVerdict::Gained:
      return "gained";
    case BalanceVerdict::Lost:
      return "lost";
    case BalanceVerdict::Dissipated:
      return "dissipated";
    case BalanceVerdict::Driven:
      return "driven";
  }
  return "balanced";
}

BalanceVerdict TimeStepper::balanceVerdict() const {
  if (!balanceChecked()) return BalanceVerdict::Driven;
  if (balance_.balancedWithin(options_.energyTolerance)) return BalanceVerdict::Balanced;
  if (balance_.largestDrift > 0.0) return BalanceVerdict::Gained;
  const bool dissipative = options_.integrator == Integrator::BackwardEuler ||
                           (options_.integrator == Integrator::Newmark && options_.gamma > 0.5);
  return dissipative ? BalanceVerdict::Dissipated : BalanceVerdict::Lost;
}

std::string TimeStepper::balanceFailure() const {
  const BalanceVerdict verdict = balanceVerdict();
  if (verdict != BalanceVerdict::Gained && verdict != BalanceVerdict::Lost) return {};
  const char* scale =
      balance_.scale() == balance_.peakKinetic ? "the peak kinetic energy" : "the energy scale";
  char text[240];
  std::snprintf(text, sizeof text,
                "energy balance: %s %.3g %% of %s (the largest drift, at t = %.6g, step %ld), "
                "beyond the %.3g %% tolerance",
                balanceVerdictName(verdict), 100.0 * balance_.relativeDrift(), scale,
                balance_.driftTime, balance_.driftStep, 100.0 * options_.energyTolerance);
  return text;
}

TimeStepper::Outcome TimeStepper::commitStep(double t, Positions& x, Positions& v, Positions a,
                                             Eigen::VectorXd xi, double dissipation,
                                             Outcome outcome) {
  movePins(x, &v, t);
  EnergySample e = energiesAt(t, x, v, xi);
  const double growth = balance_.growth(e, dissipation);
  // A rise below 1e-12 M (L/h)² (M the total mass, L the rest diagonal: the kinetic energy of the
  // whole mass moving 1e-6 L per step) is round-off, as in a body at rest with no load.
  const double h = t - time_;
  const double roundoff = 1e-12 * mass_.sum() * (length_ / h) * (length_ / h);
  const double rise = growth * balance_.scale(e);
  if (balanceChecked() && !(growth <= options_.energyTolerance || rise <= roundoff)) {
    char text[200];
    if (std::isfinite(growth))
      std::snprintf(text, sizeof text,
                    "the total energy grew by %.3g (%.3g %% of the energy scale %.3g; the "
                    "tolerance is %.3g %%)",
                    growth * balance_.scale(e), 100.0 * growth, balance_.scale(e),
                    100.0 * options_.energyTolerance);
    else
      std::snprintf(text, sizeof text, "the energies after the step are not finite");
    outcome.converged = false;
    outcome.energyGrowth = std::isfinite(growth) ? growth : std::numeric_limits<double>::infinity();
    outcome.failure = text;
    return outcome;
  }
  x_ = std::move(x);
  v_ = std::move(v);
  a_ = std::move(a);
  xi_ = std::move(xi);
  time_ = t;
  double stiffeningWork = 0.0;
  if (!barrier_.empty() || !selfContact_.empty()) {
    // The next step's contact stiffness (obstacles.h, self_contact.h). Its raises inside the layer
    // add energy: with S at most D + ½ tolerance × the scale they never lift the total above E(0)
    // by more than half the tolerance (damping's work D pays for the rest).
    const double budget =
        std::max(0.0, 0.5 * options_.energyTolerance * balance_.scale(e) + balance_.dissipated +
                          dissipation - balance_.stiffening);
    const double before = barrier_.energy(x_) + selfContact_.energy(x_);
    const double spent = barrier_.adapt(x_, v_, mass_, budget);
    selfContact_.adapt(x_, v_, mass_, h, std::max(0.0, budget - spent));
    stiffeningWork = barrier_.energy(x_) + selfContact_.energy(x_) - before;
  }
  balance_.record(e, dissipation, stiffeningWork, roundoff);
  e.contact += stiffeningWork;
  countContact();
  energies_ = std::move(e);
  return outcome;
}

namespace {

double elasticEnergy(const EnergySample& e) {
  double u = e.contact;
  for (double term : e.terms) u += term;
  return u;
}

// max(K_peak, 1e-6 max(|E(0)|, U_peak)), never 0.
double energyScale(double peakKinetic, double peakElastic, double initial) {
  return std::max({peakKinetic, 1e-6 * std::max(std::abs(initial), peakElastic),
                   std::numeric_limits<double>::min()});
}

}  // namespace

void EnergyBalance::start(const EnergySample& e) {
  *this = EnergyBalance();
  initial = last = e.total();
  peakKinetic = e.kinetic;
  peakElastic = elasticEnergy(e);
  driftTime = e.time;
}

double EnergyBalance::scale(const EnergySample& e) const {
  return energyScale(std::max(peakKinetic, e.kinetic), std::max(peakElastic, elasticEnergy(e)),
                     initial);
}

double EnergyBalance::scale() const {
  return energyScale(peakKinetic, peakElastic, initial);
}

double EnergyBalance::growth(const EnergySample& e, double dissipation) const {
  return (balanced(e) + dissipation - last) / scale(e);
}

void EnergyBalance::record(const EnergySample& e, double dissipation, double stiffeningWork,
                           double stepRoundoff) {
  dissipated += dissipation;
  roundoff = std::max(roundoff, stepRoundoff);
  ++steps;
  peakKinetic = std::max(peakKinetic, e.kinetic);
  peakElastic = std::max(peakElastic, elasticEnergy(e));
  const double b = balanced(e);
  last = b;
  if (std::abs(b - initial) > std::abs(largestDrift)) {
    largestDrift = b - initial;
    driftTime = e.time;
    driftStep = steps;
  }
  stiffening += stiffeningWork;
}

void TimeStepper::Advance::addTried(const Advance& part) {
  halvings += part.halvings;
  smallestStep = std::min(smallestStep, part.smallestStep);
  attemptedIterations += part.attemptedIterations;
  factorizations += part.factorizations;
  pcgSolves += part.pcgSolves;
  pcgIterations += part.pcgIterations;
  hessians += part.hessians;
}

void TimeStepper::Advance::addConverged(const Advance& part) {
  steps += part.steps;
  newtonIterations += part.newtonIterations;
  maxNewtonIterations = std::max(maxNewtonIterations, part.maxNewtonIterations);
}

void TimeStepper::Advance::addPart(const Advance& part) {
  addTried(part);
  addConverged(part);
  completed = part.completed;
  failure = part.failure;
  failedStep = part.failedStep;
  failedTime = part.failedTime;
}

}  // namespace flexure::optimize
