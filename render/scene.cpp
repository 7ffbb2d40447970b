// The scene a render draws: the exaggerated mesh, the obstacles as triangle meshes (a
// latitude–longitude sphere, a plane's square) and the framed points.
#include "render/scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

namespace flexure::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A sphere of `radius` about `centre` as a latitude–longitude mesh, kSphereSlices around and
// kSphereStacks pole to pole, appended to `out`.
constexpr int kSphereSlices = 48, kSphereStacks = 24;
void appendSphere(const SphereObstacle& sphere, modeling::Mesh& out) {
  const int first = out.vertexCount();
  const int ringCount = kSphereStacks - 1;
  modeling::Positions points(2 + ringCount * kSphereSlices, 3);
  points.row(0) = (sphere.centre + sphere.radius * Eigen::Vector3d::UnitZ()).transpose();
  points.row(1) = (sphere.centre - sphere.radius * Eigen::Vector3d::UnitZ()).transpose();
  for (int i = 0; i < ringCount; ++i) {
    const double polar = kPi * (i + 1) / kSphereStacks;
    for (int j = 0; j < kSphereSlices; ++j) {
      const double around = 2.0 * kPi * j / kSphereSlices;
      const Eigen::Vector3d u(std::sin(polar) * std::cos(around),
                              std::sin(polar) * std::sin(around), std::cos(polar));
      points.row(2 + i * kSphereSlices + j) = (sphere.centre + sphere.radius * u).transpose();
    }
  }
  const auto ring = [&](int i, int j) { return first + 2 + i * kSphereSlices + j % kSphereSlices; };
  std::vector<Eigen::Vector3i> faces;
  for (int j = 0; j < kSphereSlices; ++j) {
    faces.emplace_back(first, ring(0, j), ring(0, j + 1));
    faces.emplace_back(first + 1, ring(ringCount - 1, j + 1), ring(ringCount - 1, j));
    for (int i = 0; i + 1 < ringCount; ++i) {
      faces.emplace_back(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      faces.emplace_back(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
  }
  out.positions.conservativeResize(first + points.rows(), 3);
  out.positions.bottomRows(points.rows()) = points;
  const Eigen::Index faceStart = out.triangles.rows();
  out.triangles.conservativeResize(faceStart + static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f)
    out.triangles.row(faceStart + static_cast<Eigen::Index>(f)) = faces[f].transpose();
}

// The plane as a square of half side `halfSide` centred on the foot of `centre` on the plane.
void appendPlane(const PlaneObstacle& plane, const Eigen::Vector3d& centre, double halfSide,
                 modeling::Mesh& out) {
  const Eigen::Vector3d n = plane.normal.normalized();
  const Eigen::Vector3d foot = centre - (n.dot(centre) - plane.offset / plane.normal.norm()) * n;
  const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
  const int first = out.vertexCount();
  out.positions.conservativeResize(first + 4, 3);
  const double signs[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int k = 0; k < 4; ++k)
    out.positions.row(first + k) =
        (foot + halfSide * (signs[k][0] * u + signs[k][1] * w)).transpose();
  const Eigen::Index faceStart = out.triangles.rows();
  out.triangles.conservativeResize(faceStart + 2, 3);
  out.triangles.row(faceStart) << first, first + 1, first + 2;
  out.triangles.row(faceStart + 1) << first, first + 2, first + 3;
}

}  // namespace

Scene buildScene(const modeling::Mesh& mesh, const RenderOptions& o) {
  Scene scene;
  scene.mesh = mesh;
  if (o.referencePositions.rows() > 0 && o.exaggeration != 1.0) {
    scene.mesh.positions =
        o.referencePositions + o.exaggeration * (mesh.positions - o.referencePositions);
  }
  const modeling::Positions& base =
      o.framingPoints.rows() > 0 ? o.framingPoints : scene.mesh.positions;
  scene.obstacles.positions.resize(0, 3);
  scene.obstacles.triangles.resize(0, 3);
  for (const SphereObstacle& sphere : o.spheres) appendSphere(sphere, scene.obstacles);
  for (const modeling::Mesh& obstacle : o.obstacleMeshes) {
    const int first = scene.obstacles.vertexCount(), faces = scene.obstacles.faceCount();
    scene.obstacles.positions.conservativeResize(first + obstacle.vertexCount(), 3);
    scene.obstacles.positions.bottomRows(obstacle.vertexCount()) = obstacle.positions;
    scene.obstacles.triangles.conservativeResize(faces + obstacle.faceCount(), 3);
    scene.obstacles.triangles.bottomRows(obstacle.faceCount()) = obstacle.triangles.array() + first;
  }
  if (!o.planes.empty()) {
    const Eigen::Vector3d lo = base.colwise().minCoeff().transpose();
    const Eigen::Vector3d hi = base.colwise().maxCoeff().transpose();
    const Eigen::Vector3d centre = 0.5 * (lo + hi);
    const double radius =
        std::max((base.rowwise() - centre.transpose()).rowwise().norm().maxCoeff(), 1e-9);
    for (const PlaneObstacle& plane : o.planes)
      appendPlane(plane, centre, kPlaneHalfSide * radius, scene.obstacles);
  }
  scene.framingPoints.resize(base.rows() + scene.obstacles.positions.rows(), 3);
  scene.framingPoints.topRows(base.rows()) = base;
  scene.framingPoints.bottomRows(scene.obstacles.positions.rows()) = scene.obstacles.positions;
  return scene;
}

}  // namespace flexure::render
