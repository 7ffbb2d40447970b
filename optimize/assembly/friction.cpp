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

std::vector<FrictionContact> obstacleFrictionContacts(const ObstacleBarrier& barrier,
                                                      const Positions& start,
                                                      const std::vector<bool>& held) {
  std::vector<FrictionContact> contacts;
  for (const Obstacle& o : barrier.obstacles())
    for (Eigen::Index v = 0; v < start.rows(); ++v) {
      if (held[static_cast<size_t>(v)]) continue;
      Eigen::Vector3d n;
      const double d = o.signedDistance(start.row(v).transpose(), &n);
      if (d >= barrier.layer()) continue;
      double d1 = 0.0;
      barrierPotential(d, barrier.layer(), &d1);
      FrictionContact c;
      c.vertices[0] = static_cast<int>(v);
      c.weights[0] = 1.0;
      c.normalForce = -barrier.stiffness(v) * d1;
      c.basis = tangentBasis(n);
      if (c.normalForce > 0.0) contacts.push_back(c);
    }
  return contacts;
}

Friction::Friction(std::vector<FrictionContact> contacts, const Positions& start,
                   double coefficient, double slip)
    : start_(start), coefficient_(coefficient), slip_(slip) {
  if (coefficient > 0.0) contacts_ = std::move(contacts);
}

Eigen::Vector2d Friction::tangential(const FrictionContact& c, const Positions& x) const {
  Eigen::Vector3d r = c.offset;
  for (int i = 0; i < 4; ++i)
    if (c.vertices[i] >= 0)
      r += c.weights[i] * (x.row(c.vertices[i]) - start_.row(c.vertices[i])).transpose();
  return c.basis.transpose() * r;
}

double Friction::contactFriction(const FrictionContact& c, const Eigen::Vector2d& u,
                                 Eigen::Vector2d& gradient, Eigen::Matrix2d* hessian) const {
  const double y = u.norm(), weight = coefficient_ * c.normalForce;
  double f1 = 0.0;
  const double f0 = frictionMollifier(y, slip_, &f1);
  // f₁(y)/y and the rank-one coefficient (f₁′ y − f₁)/y³ times u uᵀ, as above.
  const bool mollified = y < slip_;
  const double f1OverY = mollified ? (2.0 - y / slip_) / slip_ : 1.0 / y;
  gradient = weight * f1OverY * u;
  if (hessian != nullptr) {
    Eigen::Matrix2d inPlane = f1OverY * Eigen::Matrix2d::Identity();
    if (mollified) {
      if (y > 0.0) inPlane -= (u * u.transpose()) / (y * slip_ * slip_);
    } else {
      inPlane -= (u * u.transpose()) / (y * y * y);
    }
    *hessian = weight * inPlane;
  }
  return weight * f0;
}

double Friction::energy(const Positions& x) const {
  double sum = 0.0;
  Eigen::Vector2d g;
  for (const FrictionContact& c : contacts_)
    sum += contactFriction(c, tangential(c, x), g, nullptr);
  return sum;
}

void Friction::add(const HessianAssembly& assembly, const Positions& x,
                   HessianEvaluation& e) const {
  if (contacts_.empty()) return;
  const std::vector<int> index = vertexUnknownIndex(assembly, x.rows());
  for (const FrictionContact& c : contacts_) {
    Eigen::Vector2d g;
    Eigen::Matrix2d h;
    e.energy += contactFriction(c, tangential(c, x), g, &h);
    // The chain rule through r = Σ_i w_i x_{v_i} + …: blocks w_i T g and w_i w_j T h Tᵀ.
    Eigen::Matrix<double, 12, 3> spread = Eigen::Matrix<double, 12, 3>::Zero();
    for (int i = 0; i < 4; ++i)
      spread.middleRows<3>(3 * i) = c.weights[i] * Eigen::Matrix3d::Identity();
    const Eigen::Matrix<double, 12, 2> chain = spread * c.basis;
    addFourVertexBlock(assembly, index, c.vertices, chain * g, chain * h * chain.transpose(), e);
  }
}

void Friction::addGradient(const Positions& x, Positions& gradient) const {
  for (const FrictionContact& c : contacts_) {
    Eigen::Vector2d g;
    contactFriction(c, tangential(c, x), g, nullptr);
    const Eigen::Vector3d force = c.basis * g;
    for (int i = 0; i < 4; ++i)
      if (c.vertices[i] >= 0) gradient.row(c.vertices[i]) += c.weights[i] * force.transpose();
  }
}

double Friction::work(const Positions& x) const {
  double sum = 0.0;
  for (const FrictionContact& c : contacts_) {
    const Eigen::Vector2d u = tangential(c, x);
    Eigen::Vector2d g;
    contactFriction(c, u, g, nullptr);
    sum += g.dot(u - c.basis.transpose() * c.offset);
  }
  return sum;
}

}  // namespace flexure::optimize
