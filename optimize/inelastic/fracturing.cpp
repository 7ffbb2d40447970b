#include "optimize/inelastic/fracturing.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <utility>

#include "modeling/errors.h"

namespace flexure::optimize {
namespace {

// A per-vertex quantity (#V by 3) of the mesh before a cut, carried to the cut mesh's vertices:
// row i = (1 − t) q_a + t q_b of its source.
modeling::Positions carried(const std::vector<modeling::VertexSource>& sources,
                            const modeling::Positions& q) {
  modeling::Positions out(static_cast<Eigen::Index>(sources.size()), 3);
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const modeling::VertexSource& s = sources[i];
    out.row(static_cast<Eigen::Index>(i)) = (1.0 - s.t) * q.row(s.a) + s.t * q.row(s.b);
  }
  return out;
}

// A per-vertex contact stiffness carried to the cut mesh: each new vertex keeps the larger of
// its sources' and its own (none when either side has none).
void carryStiffness(const std::vector<modeling::VertexSource>& sources, const Eigen::VectorXd& from,
                    Eigen::VectorXd& to) {
  if (from.size() == 0 || to.size() == 0) return;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const Eigen::Index k = static_cast<Eigen::Index>(i);
    to[k] = std::max({to[k], from[sources[i].a], from[sources[i].b]});
  }
}

// For each vertex of the cut mesh, the vertex of the mesh before the cut it copies, or −1 (a
// vertex the cut added on an edge).
std::vector<int> ancestors(const std::vector<modeling::VertexSource>& sources) {
  std::vector<int> out(sources.size(), -1);
  for (std::size_t i = 0; i < sources.size(); ++i)
    if (sources[i].a == sources[i].b) out[i] = sources[i].a;
  return out;
}

// A vertex set of the mesh before a cut, carried to the cut mesh: a vertex is in it when both ends
// of its source are (as the held vertices carry, fracture.h).
std::vector<bool> carriedSet(const std::vector<modeling::VertexSource>& sources,
                             const std::vector<bool>& set) {
  std::vector<bool> out(sources.size());
  for (std::size_t i = 0; i < sources.size(); ++i) out[i] = set[sources[i].a] && set[sources[i].b];
  return out;
}

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

FracturingDynamics::FracturingDynamics(modeling::Mesh rest, Problem problem, ProblemOptions options,
                                       DynamicsOptions dynamics,
                                       std::optional<FractureOptions> fracture)
    : rest_(std::move(rest)),
      options_(std::move(options)),
      dynamics_(dynamics),
      fracture_(fracture),
      problem_(std::make_unique<Problem>(std::move(problem))) {
  if (fracture_) {
    fracture_->validate();
    if (options_.membraneRest.size() > 0)
      throw InputError(
          "FractureOptions: a separate membrane rest shape does not carry across a "
          "cut (ProblemOptions.membraneRest)");
    criterion_ = std::make_unique<FractureCriterion>(rest_);
    eventFaces_ = fractureEventFaces(rest_, openTips_);
  }
  stepper_ = std::make_unique<TimeStepper>(*problem_, dynamics_);
}

void FracturingDynamics::start(const modeling::Positions& x, const modeling::Positions& v) {
  pinStart_ = x;
  stepper_->start(x, v, Eigen::VectorXd());
}

std::vector<double> FracturingDynamics::strainNow() const {
  const std::vector<FacePrincipalStrain> principal = criterion_->principalStrains(
      criterion_->strains(stepper_->positions()), fracture_->thickness);
  std::vector<double> strain(principal.size());
  for (std::size_t f = 0; f < principal.size(); ++f) strain[f] = principal[f].strain;
  return strain;
}

bool FracturingDynamics::overBand(const std::vector<double>& strain) const {
  const double band = fracture_->fractureStrain * (1.0 + kFractureOvershoot);
  for (std::size_t f = 0; f < strain.size(); ++f)
    if (eventFaces_[f] && strain[f] > band) return true;
  return false;
}

// A step whose end is over the fracture band is discarded and covered by two halves (down to
// kFractureSearchLevels halvings and the smallest step), as is one that starts over it.
TimeStepper::Advance FracturingDynamics::advance(double h, double minStep, long step) {
  TimeStepper::Advance total;
  total.smallestStep = h;
  total.completed = coverByHalving(h, 0, [&](double length, int level) {
    const bool canHalve = fracture_ && level < kFractureSearchLevels && length / 2.0 >= minStep;
    // Already over the band at the start: a step of h would be discarded, as would each shorter
    // one down to the shortest, whose end differs from this start by O(h / 2^levels).
    if (canHalve && overBand(strainNow())) return StepVerdict::Halve;
    const TimeStepper::State before = stepper_->state();
    const TimeStepper::Advance a = stepper_->advance(length, minStep);
    if (!a.completed) {
      total.addPart(a);
      return StepVerdict::Failed;
    }
    total.addTried(a);
    if (!fracture_) {
      total.addConverged(a);
      step += a.steps;
      return StepVerdict::Taken;
    }
    const std::vector<double> strain = strainNow();
    if (canHalve && overBand(strain)) {
      stepper_->restore(before);
      ++total.halvings;
      return StepVerdict::Halve;
    }
    total.addConverged(a);
    step += a.steps;
    checkFracture(step, strain);
    return StepVerdict::Taken;
  });
  return total;
}

bool FracturingDynamics::checkFracture(long step) {
  if (!fracture_) return false;
  return checkFracture(step, strainNow());
}

bool FracturingDynamics::checkFracture(long step, const std::vector<double>& strain) {
  if (std::none_of(strain.begin(), strain.end(),
                   [&](double s) { return s > fracture_->fractureStrain; }))
    return false;
  const TimeStepper::State before = stepper_->state();
  const double totalBefore = stepper_->energies().total();
  CrackEvent::Seconds seconds;
  Clock::time_point clock = Clock::now();
  std::optional<FracturedShell> shell = fractureShell(
      *criterion_, before.x, before.v, problem_->boundary.fixedVertex, *fracture_, openTips_);
  // A crack that runs only along edges already separated changes nothing: not a cut.
  if (!shell || (shell->cut.facesSplit == 0 && shell->cut.verticesAdded == 0 &&
                 shell->cut.verticesDuplicated == 0))
    return false;
  const std::vector<modeling::VertexSource>& sources = shell->cut.sources;
  // With self-contact, the lips open by a hundredth of its layer d̂ (openLips): apart, they
  // repel on their inset layers and cannot pass through each other. The problem's rest mesh is
  // the opened one; the fracture bookkeeping keeps the cut's, whose lips coincide (a lip is a rest
  // point of two or more vertices, a tip one of a single vertex).
  modeling::Mesh cutRest = shell->rest;
  const SelfContact& contact = stepper_->selfContact();
  if (!contact.empty() && contact.shellPairs())
    openLips(*shell, carried(sources, problem_->rest.positions), 1e-2 * contact.layer());
  seconds.cut = secondsSince(clock);

  ProblemOptions options = options_;
  options.fixedVertex = shell->heldVertex;
  options.boundaryPositions = shell->positions;
  clock = Clock::now();
  auto problem = std::make_unique<Problem>(buildProblem(shell->rest, options));
  seconds.problem = secondsSince(clock);
  DynamicsOptions dynamics = dynamics_;
  for (PinGroup& group : dynamics.pinGroups) group.vertices = carriedSet(sources, group.vertices);
  clock = Clock::now();
  auto stepper = std::make_unique<TimeStepper>(*problem, dynamics);
  seconds.stepper = secondsSince(clock);
  if (onCut_) onCut_(*problem, shell->cut);
  clock = Clock::now();
  const modeling::Positions pinStart = carried(sources, pinStart_);
  stepper->startBeforeRestore(pinStart, shell->velocities, Eigen::VectorXd());

  TimeStepper::State after = stepper->state();
  after.time = before.time;
  after.x = shell->positions;
  after.v = shell->velocities;
  // Midedge's ξ (massless) re-solved on the cut mesh at the carried positions, from the start's.
  after.xi = stepper->edgeUnknownsAt(after.x, after.xi);
  after.a = carried(sources, before.a);
  carryStiffness(sources, before.contactStiffness, after.contactStiffness);
  carryStiffness(sources, before.selfContactStiffness, after.selfContactStiffness);
  after.obstacleStiffness = std::max(after.obstacleStiffness, before.obstacleStiffness);
  after.balance = before.balance;
  after.contact = before.contact;  // the run's self-contact statistics go on
  after.contactInsets.reset();     // the cut mesh's pairs, inset where they are
  stepper->restore(after);
  // ... with the history of the pairs the cut leaves whole (a lip pressed shut keeps its layer).
  if (!stepper->selfContact().empty()) {
    after.contactInsets =
        stepper->selfContact().carriedInsets(stepper_->selfContact(), ancestors(sources));
    stepper->restore(after);
  }
  const double released = totalBefore - stepper->energies().total();
  after.balance.initial -= released;
  after.balance.last -= released;
  stepper->restore(after);
  seconds.start = secondsSince(clock);

  CrackEvent event;
  event.time = before.time;
  event.step = step;
  event.critical = shell->critical;
  event.rest = shell->cut.crackRest;
  event.current = shell->cut.crackCurrent;
  event.released = released;
  event.fragments = static_cast<int>(meshFragments(shell->rest).size());

  stepper_ = std::move(stepper);
  problem_ = std::move(problem);
  rest_ = std::move(cutRest);
  clock = Clock::now();
  criterion_ = std::make_unique<FractureCriterion>(rest_);
  dynamics_ = std::move(dynamics);
  openTips_ = std::move(shell->openTips);
  eventFaces_ = fractureEventFaces(rest_, openTips_);
  seconds.criterion = secondsSince(clock);
  event.seconds = seconds;
  cracks_.push_back(std::move(event));
  pinStart_ = pinStart;
  return true;
}

bool FracturingDynamics::releasePins(double time) {
  const std::vector<bool> released =
      releasePinGroups(dynamics_, problem_->boundary.fixedVertex, time);
  if (released.empty()) return false;
  auto stepper = std::make_unique<TimeStepper>(*problem_, dynamics_);
  stepper->continueAfterRelease(*stepper_, pinStart_, released);
  stepper_ = std::move(stepper);
  return true;
}

std::vector<modeling::Mesh> FracturingDynamics::fragments() const {
  modeling::Mesh current = rest_;
  current.positions = stepper_->positions();
  return meshFragments(current);
}

}  // namespace flexure::optimize
