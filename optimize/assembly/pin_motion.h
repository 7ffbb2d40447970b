// A prescribed rigid motion in time (of pinned vertices, or of a mesh obstacle).
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>

namespace flexure::optimize {

// A prescribed rigid motion of the pinned vertices in time: a pinned vertex at x₀ at time 0 is at
//   rotate:    p + R(ω t)(x₀ − p), R(φ) y = y cos φ + (a × y) sin φ + a (a·y)(1 − cos φ)
//              (Rodrigues; a the unit axis, p a point on it, ω the angular speed in rad/s,
//              counter-clockwise about a by the right-hand rule),
//   translate: x₀ + u t (u the velocity),
// with velocity ω a × (x − p) or u. None: the pinned vertices stay where they start.
struct PinMotion {
  enum class Kind { None, Rotate, Translate };
  Kind kind = Kind::None;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ(), point = Eigen::Vector3d::Zero();
  double omega = 0.0;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();

  Eigen::Vector3d position(const Eigen::Vector3d& start, double t) const;
  Eigen::Vector3d velocityAt(const Eigen::Vector3d& start, double t) const;

  // A rotation about `axis` (any length > 0; normalized here) through `point` at `omega`, and a
  // translation. InputError naming the field for a zero or non-finite axis, point, ω or velocity.
  static PinMotion rotation(const Eigen::Vector3d& axis, const Eigen::Vector3d& point,
                            double omega);
  static PinMotion translation(const Eigen::Vector3d& velocity);
};
// "none" | "rotate" | "translate"; InputError naming PinMotion.kind otherwise.
PinMotion::Kind parsePinMotionKind(std::string_view name);
// The motion of `kind` from its parameters (a rotation's axis, point and ω; a translation's
// velocity; the others ignored). InputError as parsePinMotionKind, rotation and translation give,
// prefixed by `place` (where the motion was given, e.g. "pin_groups[1] motion").
PinMotion makePinMotion(std::string_view kind, const Eigen::Vector3d& axis,
                        const Eigen::Vector3d& point, double omega, const Eigen::Vector3d& velocity,
                        const std::string& place);

}  // namespace flexure::optimize
