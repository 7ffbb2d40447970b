#include "optimize/assembly/pin_motion.h"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "modeling/errors.h"

namespace flexure::optimize {

PinMotion PinMotion::rotation(const Eigen::Vector3d& axis, const Eigen::Vector3d& point,
                              double omega) {
  if (!axis.allFinite() || !(axis.norm() > 0.0))
    throw InputError("PinMotion.axis: the axis is zero or not finite");
  if (!point.allFinite()) throw InputError("PinMotion.point: the point is not finite");
  if (!std::isfinite(omega)) throw InputError("PinMotion.omega: the angular speed is not finite");
  PinMotion m;
  m.kind = Kind::Rotate;
  m.axis = axis.normalized();
  m.point = point;
  m.omega = omega;
  return m;
}

PinMotion PinMotion::translation(const Eigen::Vector3d& velocity) {
  if (!velocity.allFinite()) throw InputError("PinMotion.velocity: the velocity is not finite");
  PinMotion m;
  m.kind = Kind::Translate;
  m.velocity = velocity;
  return m;
}

PinMotion::Kind parsePinMotionKind(std::string_view name) {
  if (name == "none") return PinMotion::Kind::None;
  if (name == "rotate") return PinMotion::Kind::Rotate;
  if (name == "translate") return PinMotion::Kind::Translate;
  throw InputError("PinMotion.kind " + std::string(name) + ": expected none, rotate or translate");
}

PinMotion makePinMotion(std::string_view kind, const Eigen::Vector3d& axis,
                        const Eigen::Vector3d& point, double omega, const Eigen::Vector3d& velocity,
                        const std::string& place) {
  try {
    switch (parsePinMotionKind(kind)) {
      case PinMotion::Kind::Rotate:
        return PinMotion::rotation(axis, point, omega);
      case PinMotion::Kind::Translate:
        return PinMotion::translation(velocity);
      case PinMotion::Kind::None:
        break;
    }
  } catch (const InputError& e) {
    throw InputError(place + ": " + e.what());
  }
  return {};
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

}  // namespace flexure::optimize
