// A rest face's orthonormal 2D frame (u, v): u along x̄1 − x̄0, v = n̄ × u, so (u, v, n̄) is
// right-handed and the face is counter-clockwise in it. Shape operators S_T are 2×2 tensors in
// this frame; Ψ_ν only needs their invariants, so the choice of u does not change any energy.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace flexure::curvature {

struct FaceFrame {
  Eigen::Vector3d origin, u, v, normal;

  static FaceFrame of(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1,
                      const Eigen::Vector3d& x2) {
    FaceFrame f;
    f.origin = (x0 + x1 + x2) / 3.0;
    f.normal = (x1 - x0).cross(x2 - x0).normalized();
    f.u = (x1 - x0).normalized();
    f.v = f.normal.cross(f.u);
    return f;
  }
  Eigen::Vector2d coordinates(const Eigen::Vector3d& x) const {
    return {(x - origin).dot(u), (x - origin).dot(v)};
  }
  Eigen::Vector2d components(const Eigen::Vector3d& direction) const {
    return {direction.dot(u), direction.dot(v)};
  }
};

}  // namespace flexure::curvature
