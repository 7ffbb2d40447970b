#include "optimize/dynamics/time_stepping.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "modeling/errors.h"
#include "optimize/solvers/energy_evaluation.h"
#include "optimize/solvers/hessian_assembly.h"

namespace flexure::optimize {

Integrator parseIntegrator(const std::string& name) {
  if (name == "newmark") return Integrator::Newmark;
  if (name == "backward-euler") return Integrator::BackwardEuler;
  if (name == "central-difference") return Integrator::CentralDifference;
  throw InputError("--integrator " + name +
                   ": expected newmark, backward-euler or central-difference");
}

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

Eigen::Vector3d PinMotion::position(const Eigen::Vector3d& start, double t) const {
  switch (kind) {
    case Kind::None:
      return start;
    case Kind::Translate:
      return start + t * velocity;
    case Kind::Rotate: {
      const Eigen::Vector3d y = start - point;
      const double phi = omega * t, c = std::cos(phi), s = std::sin(phi);
      return point + c * y + s * axis.cross(y) + (1.0 - c) * axis.dot(y) * axis;
    }
  }
  return start;
}

Eigen::Vector3d PinMotion::velocityAt(const Eigen::Vector3d& start, double t) const {
  switch (kind) {
    case Kind::None:
      return Eigen::Vector3d::Zero();
    case Kind::Translate:
      return velocity;
    case Kind::Rotate:
      return omega * axis.cross(position(start, t) - point);
  }
  return Eigen::Vector3d::Zero();
}

PinMotion parsePinMotion(const std::string& spec) {
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string expected = ": expected rotate:ax,ay,az,px,py,pz,omega or translate:vx,vy,vz";
  const int count = kind == "rotate" ? 7 : kind == "translate" ? 3 : 0;
  if (colon == std::string::npos || count == 0) throw InputError("--pin-motion " + spec + expected);
  std::vector<double> value;
  const std::string numbers = spec.substr(colon + 1);
  const char* cursor = numbers.c_str();
  for (int k = 0; k < count; ++k) {
    char* end = nullptr;
    value.push_back(std::strtod(cursor, &end));
    if (end == cursor || (k < count - 1 && *end != ',') || (k == count - 1 && *end != '\0') ||
        !std::isfinite(value.back()))
      throw InputError("--pin-motion " + spec + expected + " (" + std::to_string(count) +
                       " finite numbers)");
    cursor = end + 1;
  }
  PinMotion m;
  if (kind == "translate") {
    m.kind = PinMotion::Kind::Translate;
    m.velocity = Eigen::Vector3d(value[0], value[1], value[2]);
    return m;
  }
  const Eigen::Vector3d axis(value[0], value[1], value[2]);
  if (!(axis.norm() > 0.0)) throw InputError("--pin-motion " + spec + ": the axis is zero");
  m.kind = PinMotion::Kind::Rotate;
  m.axis = axis.normalized();
  m.point = Eigen::Vector3d(value[3], value[4], value[5]);
  m.omega = value[6];
  return m;
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
  // Whether `factorization` holds a factor of ∇²Φ, and the step h it was made for (Φ's inertia
  // M/(βh²) depends on h): chord steps reuse it across time steps of the same h.
  bool haveFactor = false;
  double factorStep = 0.0;

  Implicit(const std::vector<const curvature::EnergyTerm*>& terms, const std::vector<bool>& free,
           int vertexCount, const Positions& rest)
      : assembly(terms, free, vertexCount, curvature::Derivatives::All),
        factorization(assembly, hessianOrder(assembly, rest)) {}

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

TimeStepper::TimeStepper(std::vector<const curvature::EnergyTerm*> terms,
                         const modeling::Stencils& stencils, const modeling::RestState& rest,
                         const Eigen::VectorXd& restXi, std::vector<bool> pinned,
                         const DynamicsOptions& options)
    : terms_(std::move(terms)), pinned_(std::move(pinned)), options_(options) {
  const DynamicsOptions& o = options_;
  if (o.integrator == Integrator::Newmark && !(o.beta > 0.0 && o.beta <= 0.5))
    throw InputError("--beta: expected 0 < β ≤ 0.5 (β = 0 is --integrator central-difference)");
  if (o.integrator == Integrator::Newmark && !(o.gamma >= 0.5 && o.gamma <= 1.0))
    throw InputError("--gamma: expected 0.5 ≤ γ ≤ 1");
  if (o.integrator == Integrator::CentralDifference &&
      (o.rayleighMass != 0.0 || o.rayleighStiffness != 0.0))
    throw InputError(
        "--damping: the explicit central-difference scheme takes no damping; use "
        "newmark or backward-euler");
  if (o.integrator == Integrator::CentralDifference && !o.obstacles.empty())
    throw InputError(
        "--obstacle: the explicit central-difference scheme cannot keep vertices outside; use "
        "newmark or backward-euler");
  if (!(o.density > 0.0)) throw InputError("--density: expected a value > 0");
  if (o.rayleighMass < 0.0 || o.rayleighStiffness < 0.0)
    throw InputError("--damping rayleigh:α,β: expected α, β ≥ 0");
  if (o.bendingDamping < 0.0) throw InputError("--damping bend:c: expected c ≥ 0");
  if (o.integrator == Integrator::CentralDifference && o.bendingDamping != 0.0)
    throw InputError(
        "--damping: the explicit central-difference scheme takes no damping; use "
        "newmark or backward-euler");
  const int vertexCount = stencils.vertexCount();
  if (static_cast<int>(pinned_.size()) != vertexCount)
    throw InputError("pinned vertices: expected one flag per vertex");
  if (std::count(pinned_.begin(), pinned_.end(), true) == vertexCount)
    throw InputError("every vertex is pinned: nothing can move");
  mass_ = lumpedVertexMasses(rest, o.mass, o.density);
  barrier_ = makeObstacleBarrier(o.obstacles, rest, mass_, o.gravity);
  length_ = (rest.positions.colwise().maxCoeff() - rest.positions.colwise().minCoeff()).norm();
  xi_ = restXi;
  freeEdge_.assign(restXi.size(), true);
  if (!o.heldEdges.empty()) {
    if (o.heldEdges.size() != freeEdge_.size())
      throw InputError("held edges: expected one flag per edge of a midedge energy");
    for (size_t e = 0; e < freeEdge_.size(); ++e) freeEdge_[e] = !o.heldEdges[e];
  }
  if (o.integrator == Integrator::CentralDifference) return;

  std::vector<bool> free(3 * vertexCount + restXi.size(), false);
  for (int v = 0; v < vertexCount; ++v)
    for (int c = 0; c < 3; ++c) free[3 * v + c] = !pinned_[v];
  for (int e = 0; e < restXi.size(); ++e) free[3 * vertexCount + e] = freeEdge_[e];
  implicit_ = std::make_unique<Implicit>(terms_, free, vertexCount, rest.positions);
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
                        .evaluate(rest.positions, restXi, HessianProjection::Exact, nullptr,
                                  curvature::SecondDerivatives::GaussNewton)
                        .values;
    im.keepVertexEntries(im.restValues);
  }
  if (o.bendingDamping > 0.0) {
    im.bending =
        std::make_unique<HessianAssembly>(std::vector<const curvature::EnergyTerm*>{terms_.front()},
                                          free, vertexCount, curvature::Derivatives::All);
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
  Positions a = Positions::Zero(x.rows(), 3);
  for (int v = 0; v < x.rows(); ++v) {
    if (pinned_[v]) continue;
    for (int c = 0; c < 3; ++c)
      a(v, c) = options_.gravity[c] - (e.gradient[3 * v + c] + contact(v, c)) / mass_[v];
  }
  return a;
}

void TimeStepper::movePins(Positions& x, Positions* v, double t) const {
  for (int k = 0; k < x.rows(); ++k) {
    if (!pinned_[k]) continue;
    const Eigen::Vector3d start = pinnedStart_.row(k).transpose();
    x.row(k) = options_.pinMotion.position(start, t).transpose();
    if (v != nullptr) v->row(k) = options_.pinMotion.velocityAt(start, t).transpose();
  }
}

void TimeStepper::start(const Positions& x, const Positions& v, const Eigen::VectorXd& xi) {
  barrier_.requireOutside(x, "the start");
  x_ = x;
  v_ = v;
  pinnedStart_ = x;
  movePins(x_, &v_, 0.0);
  xi_ = xi.size() > 0 ? xi : xi_;
  if (xi_.size() > 0) xi_ = minimizeEdgeUnknowns(terms_, x_, xi_, freeEdge_);
  time_ = 0.0;
  if (implicit_) implicit_->haveFactor = false;
  barrier_.resetStiffness();
  barrier_.adapt(x_, v_, mass_);  // the next step's contact stiffness (obstacles.h)
  // With damping the initial acceleration also carries −M⁻¹ C v₀; a start at rest (v₀ = 0, the
  // usual case) has none, and a moving start takes the undamped one.
  a_ = accelerationFromForces(x_, xi_);
}

TimeStepper::Outcome TimeStepper::step(double h) {
  try {
    return implicit_ ? implicitStep(h) : explicitStep(h);
  } catch (const NumericalError& e) {
    return {false, 0, e.what()};
  }
}

TimeStepper::Outcome TimeStepper::explicitStep(double h) {
  Positions x = x_ + h * v_ + 0.5 * h * h * a_;
  movePins(x, nullptr, time_ + h);
  const Eigen::VectorXd xi = xi_.size() > 0 ? minimizeEdgeUnknowns(terms_, x, xi_, freeEdge_) : xi_;
  const Positions a = accelerationFromForces(x, xi);
  if (!a.allFinite()) return {false, 0, "the forces are not finite (the step is unstable)"};
  v_ += 0.5 * h * (a_ + a);
  x_ = x;
  xi_ = xi;
  a_ = a;
  time_ += h;
  movePins(x_, &v_, time_);
  return {true, 0, ""};
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

TimeStepper::Outcome TimeStepper::implicitStep(double h, StepObjective* probe) {
  Implicit& im = *implicit_;
  const DynamicsOptions& o = options_;
  const bool euler = o.integrator == Integrator::BackwardEuler;
  const double beta = euler ? 1.0 : o.beta, gamma = euler ? 1.0 : o.gamma;
  const double p = euler ? 0.0 : 0.5 - beta, q = euler ? 0.0 : 1.0 - gamma;
  const double massWeight = 1.0 / (beta * h * h), dampingWeight = gamma / (beta * h);
  const std::vector<int>& unknowns = im.assembly.freeUnknowns();
  const int n = im.assembly.size();
  const long positionCount = x_.size();

  // The predictors and the linear parts of Φ over the free unknowns.
  const Positions xHat = x_ + h * v_ + p * h * h * a_;
  const Positions vHat = v_ + q * h * a_;
  Eigen::VectorXd hat(n), vHatFree(n), gravityForce(n);
  for (int k = 0; k < n; ++k) {
    const long u = unknowns[k];
    const bool vertex = u < positionCount;
    hat[k] = vertex ? xHat.data()[u] : 0.0;
    vHatFree[k] = vertex ? vHat.data()[u] : 0.0;
    gravityForce[k] = vertex ? im.mass[k] * o.gravity[u % 3] : 0.0;
  }
  // The stiffness-proportional damping of this step, β K̄ + c K_B(x_n), on the pattern (empty:
  // none); C = α M + that.
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
  auto damping = [&](const Eigen::VectorXd& y) {  // C y, ξ rows 0
    return Eigen::VectorXd(o.rayleighMass * im.mass.cwiseProduct(y) +
                           im.multiply(stiffnessDamping, y));
  };
  const Eigen::VectorXd dampingOfVHat = damping(vHatFree);

  // x_n with the pinned vertices where they are at t + h: the fixed part of every iterate.
  Positions moved = x_;
  movePins(moved, nullptr, time_ + h);
  if (!barrier_.empty() && options_.pinMotion.kind != PinMotion::Kind::None) {
    int vertex = -1;
    if (barrier_.smallestDistance(moved, &vertex) <= 0.0 && pinned_[vertex])
      return {false, 0, "pinned vertex " + std::to_string(vertex) + " is moved into an obstacle"};
  }

  // (x, ξ) from the free unknowns and back.
  auto values = [&](const Positions& x, const Eigen::VectorXd& xi) {
    Eigen::VectorXd y(n);
    for (int k = 0; k < n; ++k) {
      const long u = unknowns[k];
      y[k] = u < positionCount ? x.data()[u] : xi[u - positionCount];
    }
    return y;
  };
  auto place = [&](const Eigen::VectorXd& y, Positions& x, Eigen::VectorXd& xi) {
    for (int k = 0; k < n; ++k) {
      const long u = unknowns[k];
      (u < positionCount ? x.data()[u] : xi[u - positionCount]) = y[k];
    }
  };
  // Φ's inertial, damping and gravity parts at y (the ξ entries of `hat` and `mass` are 0).
  auto extra = [&](const Eigen::VectorXd& y, Eigen::VectorXd* gradient) {
    const Eigen::VectorXd d = (y - hat).cwiseProduct(im.mass.cwiseSign());  // 0 on ξ
    const Eigen::VectorXd cd = damping(d);
    if (gradient != nullptr)
      *gradient =
          massWeight * im.mass.cwiseProduct(d) + dampingWeight * cd + dampingOfVHat - gravityForce;
    return 0.5 * massWeight * d.dot(im.mass.cwiseProduct(d)) + 0.5 * dampingWeight * d.dot(cd) +
           dampingOfVHat.dot(d) - gravityForce.dot(y);
  };
  // Φ at y alone (no derivatives: the line search's later trials).
  auto phi = [&](const Eigen::VectorXd& y) {
    Positions x = moved;
    Eigen::VectorXd xi = xi_;
    place(y, x, xi);
    double e = 0.0;
    for (const curvature::EnergyTerm* term : terms_) e += term->energy(x, xi);
    return e + extra(y, nullptr) + barrier_.energy(x);  // +∞ inside an obstacle
  };
  // Per vertex v, the largest fraction α_v ≤ 1 of the step δ from y that keeps it outside the
  // obstacles (obstacles.h, with its margin); empty without obstacles.
  auto vertexBounds = [&](const Eigen::VectorXd& y, const Eigen::VectorXd& delta) {
    if (barrier_.empty()) return Eigen::VectorXd();
    Positions from = moved, dx = Positions::Zero(x_.rows(), 3);
    Eigen::VectorXd unusedXi = xi_;
    place(y, from, unusedXi);
    for (int k = 0; k < n; ++k)
      if (unknowns[k] < positionCount) dx.data()[unknowns[k]] = delta[k];
    return barrier_.vertexStepBounds(from, dx);
  };
  // The largest fraction of the whole step that keeps every vertex outside: min_v α_v.
  auto feasible = [&](const Eigen::VectorXd& y, const Eigen::VectorXd& delta) {
    const Eigen::VectorXd bounds = vertexBounds(y, delta);
    return bounds.size() == 0 ? 1.0 : bounds.minCoeff();
  };

  // Newton starts at x̂ + β h² a_n, the solution if the acceleration stayed a_n (x_n + h v_n +
  // ½ h² a_n for Newmark: Taylor to second order; x̂ itself assumes a = 0), except at vertices
  // within two barrier layers of an obstacle, which start where they are, at x_n: their
  // acceleration flips from step to step with the contact (Newmark's average acceleration does
  // not damp the barrier's stiff mode), and measured on the drape benchmark, starting them at x̂
  // made every other step cost several times the Newton steps. With obstacles, y moves from x_n
  // towards the guess as far as they allow (x_n is outside every obstacle; the guess need not be).
  Positions x = moved;
  Eigen::VectorXd xi = xi_;
  Eigen::VectorXd y = values(x, xi);
  Eigen::VectorXd guess = hat;
  if (o.predictAcceleration) {
    for (int k = 0; k < n; ++k) {
      if (unknowns[k] >= positionCount) continue;
      const int v = unknowns[k] / 3;
      bool near = false;
      for (const Obstacle& obstacle : barrier_.obstacles())
        near = near || obstacle.signedDistance(x_.row(v).transpose()) < 2.0 * barrier_.layer();
      guess[k] = near ? x_.data()[unknowns[k]] : guess[k] + beta * h * h * a_.data()[unknowns[k]];
    }
  }
  const Eigen::VectorXd toGuess = (guess - y).cwiseProduct(im.mass.cwiseSign());  // 0 on ξ
  y += feasible(y, toGuess) * toGuess;
  // Φ and ∇Φ at y, and ∇²Φ on the pattern with ∇²E exact or its Gauss–Newton part (`kind`):
  // ∇²E + ∇²B + M/(βh²) + γ C/(βh) (C's α M on the diagonal, its stiffness part everywhere).
  // SecondDerivatives::None: Φ and ∇Φ only (first derivatives, much cheaper), `values` empty.
  auto evaluate = [&](const Eigen::VectorXd& point, curvature::SecondDerivatives kind,
                      double& energy, Eigen::VectorXd& gradient) {
    place(point, x, xi);
    HessianEvaluation at = im.assembly.evaluate(x, xi, HessianProjection::Exact, nullptr, kind);
    barrier_.add(im.assembly, x, at, kind != curvature::SecondDerivatives::Exact);
    Eigen::VectorXd extraGradient;
    energy = at.energy + extra(point, &extraGradient);
    gradient = at.gradient + extraGradient;
    if (kind == curvature::SecondDerivatives::None) return at;
    for (int k = 0; k < n; ++k)
      at.values[im.diagonal[k]] += (massWeight + dampingWeight * o.rayleighMass) * im.mass[k];
    for (size_t e = 0; e < stiffnessDamping.size(); ++e)
      at.values[e] += dampingWeight * stiffnessDamping[e];
    return at;
  };
  if (probe != nullptr) {  // Φ at the probe's (x, ξ), the state unchanged
    y = values(*probe->x, *probe->xi);
    const HessianEvaluation at =
        evaluate(y, curvature::SecondDerivatives::Exact, probe->value, probe->gradient);
    probe->unknowns = unknowns;
    probe->hessian = Eigen::MatrixXd::Zero(n, n);
    for (int j = 0; j < n; ++j)
      for (int e = im.assembly.columnStart()[j]; e < im.assembly.columnStart()[j + 1]; ++e) {
        const int i = im.assembly.rowIndex()[e];
        probe->hessian(i, j) = probe->hessian(j, i) = at.values[e];
      }
    return {};
  }

  // Newton with chord steps (as newton_solver.h, and across time steps): every iteration
  // evaluates Φ and ∇Φ (first derivatives) and, with the last factor F of ∇²Φ — from an earlier
  // iterate of this step or, with the same h, of an earlier step — the step δ = −F⁻¹∇Φ and its
  // decrement λ² = −∇Φᵀδ. δ is taken as a chord step while λ² shrinks at least
  // kChordContraction-fold per iteration (the first iteration of a step has nothing to compare
  // with and tries the factor it has); otherwise ∇²Φ at the iterate is assembled and factored for
  // a Newton step. Converged when the step moves no unknown more than `tolerance` × the rest
  // diagonal and F is known to describe Φ near the iterate: factored at an iterate of this step,
  // or its chord steps in this step contracted. A factor from an earlier step is never trusted
  // alone (it may be stiffer than Φ is now, e.g. from a contact since released, which would make
  // δ small without the iterate being close).
  constexpr double kChordContraction = 0.1;
  if (im.factorStep != h) im.haveFactor = false;
  Outcome outcome;
  const double stepTolerance = o.tolerance * length_;
  double energy = 0.0, previousDecrement = std::numeric_limits<double>::infinity();
  Eigen::VectorXd gradient;
  evaluate(y, curvature::SecondDerivatives::None, energy, gradient);
  bool freshFactor = false;  // F was factored at an iterate of this step
  // At most maxNewtonIterations Newton steps (each factoring once, or twice when the exact
  // Hessian is indefinite) and 4 × as many iterations in all.
  int newtonSteps = 0;
  // The Hessian of E the Newton steps factor: o.hessian until the exact one is found indefinite;
  // then its Gauss–Newton part directly (one factorization per Newton step instead of two) for
  // as long as those Newton steps contract tenfold (previousNewtonDecrement: the last one's λ²).
  curvature::SecondDerivatives hessian = o.hessian;
  double previousNewtonDecrement = std::numeric_limits<double>::infinity();
  for (int iteration = 1;
       iteration <= 4 * o.maxNewtonIterations && newtonSteps < o.maxNewtonIterations; ++iteration) {
    outcome.newtonIterations = iteration;
    Eigen::VectorXd delta;
    double decrement = 0.0;
    bool chord = false;
    if (o.chordSteps && im.haveFactor) {
      delta = -im.factorization.solve(gradient);
      decrement = -gradient.dot(delta);
      chord = decrement > 0.0 && decrement <= kChordContraction * previousDecrement;
    }
    bool trusted = chord && (freshFactor || std::isfinite(previousDecrement));
    if (!chord) {
      ++newtonSteps;
      const bool gaussNewton = hessian != o.hessian;  // a fallback carried over
      HessianEvaluation at = evaluate(y, hessian, energy, gradient);
      bool factored = im.factorization.factor(at.values);
      ++outcome.factorizations;
      if (!factored && !gaussNewton) {  // indefinite ∇²E (buckling, a compressed membrane)
        double unused = 0.0;
        Eigen::VectorXd unusedGradient;
        const HessianEvaluation gn =
            evaluate(y, curvature::SecondDerivatives::GaussNewton, unused, unusedGradient);
        factored = im.factorization.factor(gn.values);
        ++outcome.factorizations;
        hessian = curvature::SecondDerivatives::GaussNewton;
      }
      im.haveFactor = factored;
      im.factorStep = h;
      if (!factored) return {false, iteration, "the step's Hessian is not positive definite"};
      freshFactor = trusted = true;
      delta = -im.factorization.solve(gradient);
      decrement = -gradient.dot(delta);
      // The fallback's Newton steps converge only linearly: it stays while they contract
      // tenfold, and the next Newton step tries o.hessian again once one does not (near the
      // solution the exact Hessian is often definite again; measured on the drape benchmark,
      // cotan at 2 500 vertices, Gauss–Newton steps alone stalled at |δ| ≈ 1e-8).
      if (gaussNewton && decrement > kChordContraction * previousNewtonDecrement)
        hessian = o.hessian;
      if (hessian != o.hessian) previousNewtonDecrement = decrement;
    }
    const double bound = feasible(y, delta);
    // Converged: the step itself is below the tolerance (taken whole, or as far as the obstacles
    // allow: near the minimizer Φ's change is at its roundoff, where a line search cannot judge);
    // or the decrease it predicts, ½ λ², is below Φ's roundoff (contact's stiff barrier can leave
    // a step above the tolerance whose gain no line search can measure).
    if (trusted && (delta.cwiseAbs().maxCoeff() <= stepTolerance ||
                    0.5 * decrement <= 1e-15 * std::abs(energy))) {
      y += bound * delta;
      outcome.converged = true;
      break;
    }
    // Φ's roundoff: 1e-14 of the sum of its parts' magnitudes (E, B and the inertia are ≥ 0;
    // the linear gravity and damping parts can cancel them, leaving |Φ| far below the parts).
    const Eigen::VectorXd d = (y - hat).cwiseProduct(im.mass.cwiseSign());
    const double roundoff = 1e-14 * (std::abs(energy) + 2.0 * std::abs(gravityForce.dot(y)) +
                                     2.0 * std::abs(dampingOfVHat.dot(d)));
    // Armijo on Φ, α halved. The first trial evaluates ∇Φ too, which the next iteration uses
    // when it passes (it usually does); later ones Φ alone, and ∇Φ where one passes. A chord step
    // gets two trials: one that fails them asks for a Newton step rather than a short step.
    // The direction searched: δ, from α = bound; or, when an obstacle bounds the step, δ with
    // each vertex's move scaled by its own bound α_v, from α = 1, when that is still a descent
    // direction — a vertex about to touch an obstacle then no longer holds every other vertex
    // back to its fraction of the step (measured on the drape benchmark: the capped Newton steps
    // of a contact step fell from tens to a few). `slope` = −∇Φᵀ direction.
    double alpha = bound, trialEnergy = 0.0, slope = decrement;
    Eigen::VectorXd direction = delta;
    bool scaledDirection = false;
    if (bound < 1.0) {
      const Eigen::VectorXd bounds = vertexBounds(y, delta);
      Eigen::VectorXd scaled = delta;
      for (int k = 0; k < n; ++k)
        if (unknowns[k] < positionCount) scaled[k] *= bounds[unknowns[k] / 3];
      const double scaledSlope = -gradient.dot(scaled);
      if (scaledSlope > 0.0) {
        direction = std::move(scaled);
        slope = scaledSlope;
        alpha = 1.0;
        scaledDirection = true;
      }
    }
    Eigen::VectorXd trial, trialGradient;
    bool decreased = true;
    for (int trials = 1;; ++trials, alpha *= 0.5) {
      trial = y + alpha * direction;
      if (trials == 1)
        evaluate(trial, curvature::SecondDerivatives::None, trialEnergy, trialGradient);
      else
        trialEnergy = phi(trial);
      // +∞ inside an obstacle; NaN never passes. A decrease at Φ's roundoff passes: the
      // comparison cannot judge it, and the step is a descent direction of a positive definite
      // model.
      if (trialEnergy <= energy - 1e-4 * alpha * slope + roundoff ||
          (std::isfinite(trialEnergy) && 0.5 * alpha * slope <= roundoff)) {
        if (trials > 1)
          evaluate(trial, curvature::SecondDerivatives::None, trialEnergy, trialGradient);
        break;
      }
      if (scaledDirection && trials == 3) {  // back to δ itself, from α = bound
        scaledDirection = false;
        direction = delta;
        slope = decrement;
        alpha = 2.0 * bound;
        continue;
      }
      if (chord ? trials == 2 : alpha < 1e-10) {
        decreased = false;
        break;
      }
    }
    if (!decreased && !chord) return {false, iteration, "the line search found no decrease of Φ"};
    // A chord step that needed damping or scaling (or failed) asks for a new factor next time.
    previousDecrement = chord && (alpha < 1.0 || scaledDirection) ? 0.0 : decrement;
    if (!decreased) continue;
    y = std::move(trial);
    energy = trialEnergy;
    gradient = std::move(trialGradient);
  }
  if (!outcome.converged) {
    outcome.failure = "Newton did not converge in " + std::to_string(outcome.newtonIterations) +
                      " iterations (" + std::to_string(newtonSteps) + " Newton steps)";
    return outcome;
  }
  place(y, x, xi);
  Positions a = (x - xHat) * massWeight;
  for (int v = 0; v < x.rows(); ++v)
    if (pinned_[v]) a.row(v).setZero();
  v_ = vHat + gamma * h * a;
  x_ = x;
  xi_ = xi;
  a_ = a;
  time_ += h;
  movePins(x_, &v_, time_);
  barrier_.adapt(x_, v_, mass_);
  return outcome;
}

EnergySample TimeStepper::energies() const {
  EnergySample s;
  s.time = time_;
  for (int v = 0; v < x_.rows(); ++v) {
    s.kinetic += 0.5 * mass_[v] * v_.row(v).squaredNorm();
    s.gravity -= mass_[v] * options_.gravity.dot(x_.row(v).transpose());
  }
  for (const curvature::EnergyTerm* term : terms_) s.terms.push_back(term->energy(x_, xi_));
  s.contact = barrier_.energy(x_);
  return s;
}

}  // namespace flexure::optimize
