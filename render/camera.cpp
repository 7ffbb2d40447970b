// The render's camera: the view rotation from azimuth and elevation, and the orthographic or
// perspective framing of a set of points with a margin.
#include "render/camera.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "modeling/errors.h"

namespace flexure::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFramingMargin = 1.06;           // orthographic: extents × 1.06
constexpr double kPerspectiveFieldOfView = 30.0;  // degrees, vertical

Eigen::Matrix3d viewRotation(double azimuthDegrees, double elevationDegrees) {
  const double a = azimuthDegrees * kPi / 180.0, e = elevationDegrees * kPi / 180.0;
  const Eigen::Vector3d toViewer(std::cos(e) * std::sin(a), -std::cos(e) * std::cos(a),
                                 std::sin(e));
  const Eigen::Vector3d right(std::cos(a), std::sin(a), 0.0);
  const Eigen::Vector3d up = toViewer.cross(right);
  Eigen::Matrix3d rows;
  rows.row(0) = right;
  rows.row(1) = up;
  rows.row(2) = toViewer;
  return rows;
}

}  // namespace

Camera frameCamera(const modeling::Positions& points, const RenderOptions& o, int width,
                   int height) {
  const Eigen::Vector3d lo = points.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = points.colwise().maxCoeff().transpose();
  Camera camera;
  camera.centre = 0.5 * (lo + hi);
  const double radius = (points.rowwise() - camera.centre.transpose()).rowwise().norm().maxCoeff();
  if (!(radius > 0.0) || !std::isfinite(radius)) {
    throw InputError("render: the mesh has no extent (all vertices coincide) or is not finite");
  }
  camera.rotation = viewRotation(o.azimuthDegrees, o.elevationDegrees);
  camera.worldToFrame = camera.rotation / radius;
  const double aspect = static_cast<double>(width) / height;
  Eigen::Matrix4d clip = Eigen::Matrix4d::Zero();
  const Eigen::MatrixXd frame =
      (points.rowwise() - camera.centre.transpose()) * camera.worldToFrame.transpose();
  if (o.projection == Projection::Orthographic) {
    // Fit the projected extents: x ↦ (x − cx) / halfWidth, y ↦ (y − cy) / halfHeight; depth
    // z ∈ [−1.5, 1.5] (the frame's unit ball with room) ↦ −z / 1.5, nearer = smaller.
    const double x0 = frame.col(0).minCoeff(), x1 = frame.col(0).maxCoeff();
    const double y0 = frame.col(1).minCoeff(), y1 = frame.col(1).maxCoeff();
    const double halfWidth =
        kFramingMargin * std::max({0.5 * (x1 - x0), 0.5 * (y1 - y0) * aspect, 1e-6});
    const double halfHeight = halfWidth / aspect;
    clip(0, 0) = 1.0 / halfWidth;
    clip(0, 3) = -0.5 * (x0 + x1) / halfWidth;
    clip(1, 1) = 1.0 / halfHeight;
    clip(1, 3) = -0.5 * (y0 + y1) / halfHeight;
    clip(2, 2) = -1.0 / 1.5;
    clip(3, 3) = 1.0;
  } else {
    // The eye at (0, 0, D) looking down −z, D the smallest distance at which every vertex lies
    // inside the field of view with the margin: |x| / (D − z) ≤ tan(fovX / 2) / margin, and the
    // same for y. Then the usual perspective matrix on eye coordinates (frame − eye), with the
    // near and far planes just outside the mesh's depth range.
    const double fovY = kPerspectiveFieldOfView * kPi / 180.0;
    const double tanY = std::tan(0.5 * fovY) / kFramingMargin, tanX = tanY * aspect;
    double distance = 0.0;
    for (Eigen::Index v = 0; v < frame.rows(); ++v) {
      distance = std::max({distance, frame(v, 2) + std::abs(frame(v, 0)) / tanX,
                           frame(v, 2) + std::abs(frame(v, 1)) / tanY});
    }
    distance = std::max(distance, frame.col(2).maxCoeff() + 0.05);
    camera.perspective = true;
    camera.eye = Eigen::Vector3d(0.0, 0.0, distance);
    const double nearPlane = 0.9 * (distance - frame.col(2).maxCoeff());
    const double farPlane = 1.1 * (distance - frame.col(2).minCoeff()) + 0.01;
    const double f = 1.0 / std::tan(0.5 * fovY);
    Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
    projection(0, 0) = f / aspect;
    projection(1, 1) = f;
    projection(2, 2) = (farPlane + nearPlane) / (nearPlane - farPlane);
    projection(2, 3) = 2.0 * farPlane * nearPlane / (nearPlane - farPlane);
    projection(3, 2) = -1.0;
    Eigen::Matrix4d translate = Eigen::Matrix4d::Identity();
    translate(2, 3) = -distance;
    clip = projection * translate;
  }
  camera.frameToClip = clip;
  return camera;
}

}  // namespace flexure::render
