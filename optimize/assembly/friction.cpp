#include "optimize/assembly/friction.h"

#include <Eigen/Geometry>
#include <cmath>

namespace flexure::optimize {

double frictionMollifier(double y, double slip, double* derivative) {
  if (y >= slip) {
    if (derivative != nullptr) *derivative = 1.0;
    return y;
  }
  const double s = y / slip;
  if (derivative != nullptr) *derivative = s * (2.0 - s);
  return slip * (s * s * (1.0 - s / 3.0) + 1.0 / 3.0);
}

Eigen::Matrix<double, 3, 2> tangentBasis(const Eigen::Vector3d& n) {
  // The coordinate axis least aligned with n, made perpendicular to it.
  Eigen::Index axis = 0;
  n.cwiseAbs().minCoeff(&axis);
  const Eigen::Vector3d first = n.cross(Eigen::Vector3d::Unit(axis)).normalized();
  Eigen::Matrix<double, 3, 2> basis;
  basis.col(0) = first;
  basis.col(1) = n.cross(first);
  return basis;
}

ObstacleFriction::ObstacleFriction(const ObstacleBarrier& barrier, const Positions& start,
                                   const std::vector<bool>& held, double coefficient, double slip)
    : start_(start), coefficient_(coefficient), slip_(slip) {
  if (!(coefficient > 0.0)) return;
  for (const Obstacle& o : barrier.obstacles())
    for (Eigen::Index v = 0; v < start.rows(); ++v) {
      if (held[static_cast<size_t>(v)]) continue;
      Eigen::Vector3d n;
      const double d = o.signedDistance(start.row(v).transpose(), &n);
      if (d >= barrier.layer()) continue;
      double d1 = 0.0;
      barrierPotential(d, barrier.layer(), &d1);
      const double normalForce = -barrier.stiffness(v) * d1;
      if (normalForce > 0.0) contacts_.push_back({v, normalForce, tangentBasis(n)});
    }
}

double ObstacleFriction::contactFriction(const Contact& c, const Positions& x,
                                         Eigen::Vector3d& gradient,
                                         Eigen::Matrix3d* hessian) const {
  const Eigen::Vector2d u =
      c.basis.transpose() * (x.row(c.vertex) - start_.row(c.vertex)).transpose();
  const double y = u.norm(), weight = coefficient_ * c.normalForce;
  double f1 = 0.0;
  const double f0 = frictionMollifier(y, slip_, &f1);
  // f₁(y)/y and the rank-one coefficient (f₁′ y − f₁)/y³ times u uᵀ, as above.
  const bool mollified = y < slip_;
  const double f1OverY = mollified ? (2.0 - y / slip_) / slip_ : 1.0 / y;
  gradient = weight * f1OverY * (c.basis * u);
  if (hessian != nullptr) {
    Eigen::Matrix2d inPlane = f1OverY * Eigen::Matrix2d::Identity();
    if (mollified) {
      if (y > 0.0) inPlane -= (u * u.transpose()) / (y * slip_ * slip_);
    } else {
      inPlane -= (u * u.transpose()) / (y * y * y);
    }
    *hessian = weight * c.basis * inPlane * c.basis.transpose();
  }
  return weight * f0;
}

double ObstacleFriction::energy(const Positions& x) const {
  double sum = 0.0;
  Eigen::Vector3d g;
  for (const Contact& c : contacts_) sum += contactFriction(c, x, g, nullptr);
  return sum;
}

void ObstacleFriction::add(const HessianAssembly& assembly, const Positions& x,
                           HessianEvaluation& e) const {
  if (contacts_.empty()) return;
  const std::vector<int> index = vertexUnknownIndex(assembly, x.rows());
  for (const Contact& c : contacts_) {
    Eigen::Vector3d g;
    Eigen::Matrix3d h;
    e.energy += contactFriction(c, x, g, &h);
    addVertexBlock(assembly, index, c.vertex, g, h, e);
  }
}

void ObstacleFriction::addGradient(const Positions& x, Positions& gradient) const {
  for (const Contact& c : contacts_) {
    Eigen::Vector3d g;
    contactFriction(c, x, g, nullptr);
    gradient.row(c.vertex) += g.transpose();
  }
}

double ObstacleFriction::work(const Positions& x) const {
  double sum = 0.0;
  for (const Contact& c : contacts_) {
    Eigen::Vector3d g;
    contactFriction(c, x, g, nullptr);
    sum += g.dot((x.row(c.vertex) - start_.row(c.vertex)).transpose());
  }
  return sum;
}

}  // namespace flexure::optimize
