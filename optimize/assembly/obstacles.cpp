#include "optimize/assembly/obstacles.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "modeling/errors.h"

namespace flexure::optimize {

double Obstacle::signedDistance(const Eigen::Vector3d& x, Eigen::Vector3d* gradient,
                                Eigen::Matrix3d* hessian) const {
  if (kind == Kind::Plane) {
    if (gradient != nullptr) *gradient = vector;
    if (hessian != nullptr) hessian->setZero();
    return vector.dot(x) - scalar;
  }
  const Eigen::Vector3d p = x - vector;
  const double length = p.norm();
  if (gradient != nullptr || hessian != nullptr) {
    const Eigen::Vector3d u = length > 0.0 ? Eigen::Vector3d(p / length) : Eigen::Vector3d::UnitZ();
    if (gradient != nullptr) *gradient = u;
    if (hessian != nullptr)
      *hessian = length > 0.0
                     ? Eigen::Matrix3d((Eigen::Matrix3d::Identity() - u * u.transpose()) / length)
                     : Eigen::Matrix3d::Zero();
  }
  return length - scalar;
}

double Obstacle::contactTime(const Eigen::Vector3d& x, const Eigen::Vector3d& delta) const {
  constexpr double never = std::numeric_limits<double>::infinity();
  if (kind == Kind::Plane) {
    // d(t) = d₀ + t n̂·δ reaches 0 at t = d₀ / (−n̂·δ) when moving towards the plane.
    const double approach = -vector.dot(delta);
    return approach > 0.0 ? std::max(0.0, signedDistance(x)) / approach : never;
  }
  // |p + t δ|² = r², p = x − c: a t² + 2 b t + c₀ = 0 with a = |δ|², b = p·δ, c₀ = |p|² − r² > 0.
  // The smaller root, when real and positive, is the first contact; written as c₀ / (−b + √D)
  // to avoid cancellation.
  const Eigen::Vector3d p = x - vector;
  const double a = delta.squaredNorm(), b = p.dot(delta), c0 = p.squaredNorm() - scalar * scalar;
  if (a == 0.0 || b >= 0.0) return never;  // not moving, or moving away from the centre
  const double discriminant = b * b - a * c0;
  if (discriminant < 0.0) return never;  // the line misses the sphere
  return std::max(0.0, c0) / (-b + std::sqrt(discriminant));
}

Obstacle parseObstacle(const std::string& option, const std::string& spec) {
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string expected = ": expected plane:nx,ny,nz,d or sphere:x,y,z,r";
  if (colon == std::string::npos || (kind != "plane" && kind != "sphere"))
    throw InputError(option + " " + spec + expected);
  double value[4];
  const std::string numbers = spec.substr(colon + 1);
  const char* cursor = numbers.c_str();
  for (int k = 0; k < 4; ++k) {
    char* end = nullptr;
    value[k] = std::strtod(cursor, &end);
    if (end == cursor || (k < 3 && *end != ',') || (k == 3 && *end != '\0') ||
        !std::isfinite(value[k]))
      throw InputError(option + " " + spec + expected + " (four finite numbers)");
    cursor = end + 1;
  }
  Obstacle o;
  o.label = option + " " + spec;
  const Eigen::Vector3d v(value[0], value[1], value[2]);
  if (kind == "plane") {
    const double length = v.norm();
    if (!(length > 0.0) || !std::isfinite(length))
      throw InputError(option + " " + spec + ": the plane's normal (nx, ny, nz) is zero");
    o.kind = Obstacle::Kind::Plane;
    o.vector = v / length;
    o.scalar = value[3] / length;
  } else {
    if (!(value[3] > 0.0)) throw InputError(option + " " + spec + ": the radius must be > 0");
    o.kind = Obstacle::Kind::Sphere;
    o.vector = v;
    o.scalar = value[3];
  }
  return o;
}

double barrierPotential(double d, double layer, double* d1, double* d2) {
  if (d1 != nullptr) *d1 = 0.0;
  if (d2 != nullptr) *d2 = 0.0;
  if (d <= 0.0) return std::numeric_limits<double>::infinity();
  if (d >= layer) return 0.0;
  const double s = d - layer, logRatio = std::log(d / layer);
  if (d1 != nullptr) *d1 = -(2.0 * s * logRatio + s * s / d);
  if (d2 != nullptr) *d2 = -(2.0 * logRatio + 4.0 * s / d - s * s / (d * d));
  return -s * s * logRatio;
}

ObstacleBarrier::ObstacleBarrier(std::vector<Obstacle> obstacles, double layer,
                                 Eigen::VectorXd stiffness)
    : obstacles_(std::move(obstacles)),
      layer_(layer),
      stiffness_(std::move(stiffness)),
      ruleStiffness_(stiffness_) {}

double adaptedStiffness(double stiffness, double ruleStiffness, const VertexApproach& a,
                        double layer, double budget, double& spent) {
  const double absorb = 2.0 / (layer * layer * std::log(2.0));  // κ per m w²
  if (a.closest >= layer) return std::max(ruleStiffness, absorb * a.impact);
  double raised = std::max(stiffness, absorb * a.nearImpact);
  if (a.closest < 0.1 * layer) raised *= std::min(2.0, 0.1 * layer / a.closest);
  // The raise adds (κ_new − κ_v) Σ b/κ_v to the motion: at most what is left of the budget.
  if (a.unitBarrier > 0.0)
    raised = std::min(raised, stiffness + std::max(0.0, budget - spent) / a.unitBarrier);
  spent += (raised - stiffness) * a.unitBarrier;
  return raised;
}

double ObstacleBarrier::adapt(const Positions& x, const Positions& velocity,
                              const Eigen::VectorXd& mass, double budget) {
  if (obstacles_.empty()) return 0.0;  // no stiffness to adapt
  double added = 0.0;
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    // m w² over every obstacle, and over those within 2 d̂; Σ_o b(d_o)/κ_v, the barrier per unit κ.
    VertexApproach a;
    for (const Obstacle& o : obstacles_) {
      Eigen::Vector3d n;
      const double d = o.signedDistance(x.row(v).transpose(), &n);
      a.closest = std::min(a.closest, d);
      const double w = std::max(0.0, -velocity.row(v).dot(n));
      a.impact = std::max(a.impact, mass[v] * w * w);
      if (d < 2.0 * layer_) a.nearImpact = std::max(a.nearImpact, mass[v] * w * w);
      a.unitBarrier += barrierPotential(d, layer_);
    }
    stiffness_[v] = adaptedStiffness(stiffness_[v], ruleStiffness_[v], a, layer_, budget, added);
  }
  return added;
}

double ObstacleBarrier::energy(const Positions& x) const {
  double sum = 0.0;
  for (const Obstacle& o : obstacles_)
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
      const double d = o.signedDistance(x.row(v).transpose());
      if (d >= layer_) continue;
      sum += stiffness_[v] * barrierPotential(d, layer_);
    }
  return sum;
}

double ObstacleBarrier::vertexBarrier(const Obstacle& o, Eigen::Index v, const Positions& x,
                                      Eigen::Vector3d& gradient, Eigen::Matrix3d* hessian,
                                      bool semidefinite) const {
  Eigen::Vector3d n;
  Eigen::Matrix3d curvature;
  const double d = o.signedDistance(x.row(v).transpose(), &n, &curvature);
  double d1 = 0.0, d2 = 0.0;
  const double b = d < layer_ ? stiffness_[v] * barrierPotential(d, layer_, &d1, &d2) : 0.0;
  gradient = stiffness_[v] * d1 * n;
  if (hessian != nullptr) {
    *hessian = stiffness_[v] * d2 * n * n.transpose();
    if (!semidefinite) *hessian += stiffness_[v] * d1 * curvature;
  }
  return b;
}

void ObstacleBarrier::addGradient(const Positions& x, Positions& gradient) const {
  for (const Obstacle& o : obstacles_)
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
      if (o.signedDistance(x.row(v).transpose()) >= layer_) continue;
      Eigen::Vector3d g;
      vertexBarrier(o, v, x, g, nullptr, false);
      gradient.row(v) += g.transpose();
    }
}

std::vector<int> vertexUnknownIndex(const HessianAssembly& assembly, Eigen::Index vertexCount) {
  const std::vector<int>& unknowns = assembly.freeUnknowns();
  std::vector<int> index(3 * vertexCount, -1);
  for (size_t k = 0; k < unknowns.size(); ++k)
    if (unknowns[k] < static_cast<int>(index.size())) index[unknowns[k]] = static_cast<int>(k);
  return index;
}

void addVertexBlock(const HessianAssembly& assembly, const std::vector<int>& index, Eigen::Index v,
                    const Eigen::Vector3d& gradient, const Eigen::Matrix3d& hessian,
                    HessianEvaluation& e) {
  const std::vector<int>& start = assembly.columnStart();
  const std::vector<int>& row = assembly.rowIndex();
  const bool withHessian = !e.values.empty();
  for (int a = 0; a < 3; ++a) {
    const int p = index[3 * v + a];
    if (p < 0) continue;
    e.gradient[p] += gradient[a];
    if (!withHessian) continue;
    for (int b = 0; b < 3; ++b) {
      const int q = index[3 * v + b];
      if (q < p) continue;  // the upper triangle: row p ≤ column q
      const auto begin = row.begin() + start[q], end = row.begin() + start[q + 1];
      const auto at = std::lower_bound(begin, end, p);
      if (at == end || *at != p)
        throw std::logic_error("obstacles: a vertex block is missing from the Hessian pattern");
      e.values[at - row.begin()] += hessian(a, b);
    }
  }
}

void addFourVertexBlock(const HessianAssembly& assembly, const std::vector<int>& index,
                        const std::array<int, 4>& v, const Eigen::Matrix<double, 12, 1>& gradient,
                        const Eigen::Matrix<double, 12, 12>& hessian, HessianEvaluation& e) {
  // The free index of coordinate i of the term (−1: none).
  std::array<int, 12> free{};
  for (int i = 0; i < 12; ++i) {
    const int vertex = v[i / 3];
    const std::size_t at = 3 * static_cast<std::size_t>(vertex) + i % 3;
    free[i] = vertex >= 0 && at < index.size() ? index[at] : -1;
  }
  for (int i = 0; i < 12; ++i)
    if (free[i] >= 0) e.gradient[free[i]] += gradient[i];
  if (e.values.empty()) return;
  bool coupled = true;
  for (int a = 0; a < 4 && coupled; ++a)
    for (int b = a + 1; b < 4; ++b) {
      const int p = free[3 * a], q = free[3 * b];
      if (p >= 0 && q >= 0 && v[a] != v[b] && assembly.entry(std::min(p, q), std::max(p, q)) < 0)
        coupled = false;
    }
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      const int p = free[i], q = free[j];
      if (p < 0 || q < 0 || p > q || (!coupled && v[i / 3] != v[j / 3])) continue;
      e.values[assembly.entry(p, q)] += hessian(i, j);
    }
}

void ObstacleBarrier::add(const HessianAssembly& assembly, const Positions& x, HessianEvaluation& e,
                          bool semidefinite) const {
  if (obstacles_.empty()) return;
  const std::vector<int> index = vertexUnknownIndex(assembly, x.rows());
  for (const Obstacle& o : obstacles_)
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
      if (o.signedDistance(x.row(v).transpose()) >= layer_) continue;
      Eigen::Vector3d g;
      Eigen::Matrix3d h;
      e.energy += vertexBarrier(o, v, x, g, &h, semidefinite);
      addVertexBlock(assembly, index, v, g, h, e);
    }
}

Eigen::VectorXd ObstacleBarrier::vertexStepBounds(const Positions& x, const Positions& dx) const {
  Eigen::VectorXd bound = Eigen::VectorXd::Ones(x.rows());
  for (const Obstacle& o : obstacles_)
    for (Eigen::Index v = 0; v < x.rows(); ++v)
      bound[v] =
          std::min(bound[v], 0.9 * o.contactTime(x.row(v).transpose(), dx.row(v).transpose()));
  return bound;
}

double ObstacleBarrier::stepBound(const Positions& x, const Positions& dx) const {
  return x.rows() == 0 ? 1.0 : vertexStepBounds(x, dx).minCoeff();
}

double ObstacleBarrier::smallestDistance(const Positions& x, int* vertex) const {
  double smallest = std::numeric_limits<double>::infinity();
  for (const Obstacle& o : obstacles_)
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
      const double d = o.signedDistance(x.row(v).transpose());
      if (d < smallest) {
        smallest = d;
        if (vertex != nullptr) *vertex = static_cast<int>(v);
      }
    }
  return smallest;
}

void ObstacleBarrier::requireOutside(const Positions& x, const std::string& what) const {
  for (const Obstacle& o : obstacles_)
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
      const double d = o.signedDistance(x.row(v).transpose());
      if (d > 0.0) continue;
      char text[200];
      std::snprintf(text, sizeof text,
                    ": vertex %ld of %s is inside or on the obstacle (signed distance %.6g); "
                    "every vertex must start outside",
                    static_cast<long>(v), what.c_str(), d);
      throw InputError(o.label + text);
    }
}

ObstacleBarrier makeObstacleBarrier(std::vector<Obstacle> obstacles,
                                    const modeling::RestState& rest, const Eigen::VectorXd& mass,
                                    const Eigen::Vector3d& gravity) {
  const double layer = 0.25 * rest.edgeLengths.mean();
  const double acceleration = std::max(gravity.norm(), 1.0);
  return ObstacleBarrier(std::move(obstacles), layer, mass * (acceleration / layer));
}

void ObstacleBarrier::setStiffness(const Eigen::VectorXd& stiffness) {
  if (stiffness.size() != stiffness_.size() || !stiffness.allFinite() ||
      (stiffness.size() > 0 && !(stiffness.minCoeff() > 0.0)))
    throw InputError("ObstacleBarrier::setStiffness: expected " +
                     std::to_string(stiffness_.size()) + " finite stiffnesses > 0");
  stiffness_ = stiffness;
}

}  // namespace flexure::optimize
