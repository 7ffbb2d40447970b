#include "modeling/willmore_surfaces.h"

#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <utility>

#include "modeling/cgal_surface_mesh.h"
#include "modeling/errors.h"

namespace flexure::modeling {
namespace {

constexpr double kPi = 3.14159265358979323846;
const double kTorusRadius = std::sqrt(2.0);  // the centre circle's; the tube's is 1

// A point uniform in the unit disk, from `random`.
Eigen::Vector2d inDisk(std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (;;) {
    const Eigen::Vector2d p(unit(random), unit(random));
    if (p.squaredNorm() <= 1.0) return p;
  }
}

Mesh meshOf(const std::vector<Eigen::Vector3d>& points,
            const std::vector<std::array<int, 3>>& faces) {
  Mesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t v = 0; v < points.size(); ++v)
    mesh.positions.row(static_cast<Eigen::Index>(v)) = points[v].transpose();
  mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    mesh.triangles.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  return mesh;
}

// (u, v) of a point near the torus: u its longitude, v the angle about the centre circle.
Eigen::Vector2d torusParameters(const Eigen::Vector3d& p) {
  const double rho = std::hypot(p.x(), p.y());
  return {std::atan2(p.y(), p.x()), std::atan2(p.z(), rho - kTorusRadius)};
}

Eigen::Vector3d torusPoint(double u, double v) {
  return {(kTorusRadius + std::cos(v)) * std::cos(u), (kTorusRadius + std::cos(v)) * std::sin(u),
          std::sin(v)};
}

}  // namespace

Mesh irregularSphere(int levels, double jitter, std::uint64_t seed) {
  if (levels < 0 || levels > 8)
    throw InputError("irregular sphere: levels must be in [0, 8] (got " + std::to_string(levels) +
                     ")");
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;  // golden ratio: vertices (0, ±1, ±t) cyclic
  std::vector<Eigen::Vector3d> points = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                         {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                         {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& p : points) p.normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    const auto midpoint = [&](int a, int b) {
      const auto [found, added] =
          midpoints.emplace(std::minmax(a, b), static_cast<int>(points.size()));
      if (added) points.push_back((points[a] + points[b]).normalized());
      return found->second;
    };
    std::vector<std::array<int, 3>> refined;
    for (const auto& f : faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      refined.push_back({f[0], ab, ca});
      refined.push_back({f[1], bc, ab});
      refined.push_back({f[2], ca, bc});
      refined.push_back({ab, bc, ca});
    }
    faces = std::move(refined);
  }
  // The icosahedron's edge subtends 1.1071 rad; each split halves it.
  const double edge = 1.1071487177940904 / std::pow(2.0, levels);
  std::mt19937_64 random(seed);
  for (Eigen::Vector3d& p : points) {
    const Eigen::Vector3d a = p.unitOrthogonal(), b = p.cross(a);
    const Eigen::Vector2d d = jitter * edge * inDisk(random);
    p = (p + d.x() * a + d.y() * b).normalized();
  }
  return meshOf(points, faces);
}

Mesh remeshedSphere(double edge) {
  if (!(edge >= 0.02 && edge <= 1.0))
    throw InputError("remeshed sphere: the target edge length must be in [0.02, 1] (got " +
                     std::to_string(edge) + ")");
  CgalSurfaceMesh sm = toCgalSurfaceMesh(irregularSphere(6, 0.0, 0), "remeshed sphere");
  CGAL::Polygon_mesh_processing::isotropic_remeshing(faces(sm), edge, sm,
                                                     CGAL::parameters::number_of_iterations(5));
  sm.collect_garbage();
  Mesh mesh = fromCgalSurfaceMesh(sm);
  mesh.positions.rowwise().normalize();
  return mesh;
}

Mesh cliffordTorus(int n, double jitter, std::uint64_t seed) {
  if (n < 3 || n > 2000)
    throw InputError("Clifford torus: n must be in [3, 2000] (got " + std::to_string(n) + ")");
  const int nu = static_cast<int>(std::lround(kTorusRadius * n)), nv = n;
  const double du = 2.0 * kPi / nu, dv = 2.0 * kPi / nv;
  std::mt19937_64 random(seed);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const Eigen::Vector2d d = jitter * inDisk(random);
      points.push_back(torusPoint((i + d.x()) * du, (j + d.y()) * dv));
    }
  }
  const auto at = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  std::vector<std::array<int, 3>> faces;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      // Counter-clockwise seen from outside: x_u × x_v points out of the tube.
      if ((i + j) % 2 == 0) {
        faces.push_back({a, b, c});
        faces.push_back({a, c, d});
      } else {
        faces.push_back({a, b, d});
        faces.push_back({b, c, d});
      }
    }
  }
  return meshOf(points, faces);
}

Eigen::Vector3d closestPoint(WillmoreSurface surface, const Eigen::Vector3d& p) {
  if (surface == WillmoreSurface::Sphere) return p.normalized();
  const Eigen::Vector2d uv = torusParameters(p);
  return torusPoint(uv.x(), uv.y());
}

Eigen::Vector3d outwardNormal(WillmoreSurface surface, const Eigen::Vector3d& p) {
  if (surface == WillmoreSurface::Sphere) return p.normalized();
  const Eigen::Vector2d uv = torusParameters(p);
  return {std::cos(uv.y()) * std::cos(uv.x()), std::cos(uv.y()) * std::sin(uv.x()),
          std::sin(uv.y())};
}

double relativeDistance(WillmoreSurface surface, const Eigen::Vector3d& p) {
  if (surface == WillmoreSurface::Sphere) return std::abs(p.norm() - 1.0);
  return std::abs(std::hypot(std::hypot(p.x(), p.y()) - kTorusRadius, p.z()) - 1.0);
}

std::vector<bool> capRegion(WillmoreSurface surface, const Mesh& mesh,
                            const Eigen::Vector3d& centre, double radius) {
  std::vector<bool> region(mesh.vertexCount());
  const Eigen::Vector2d c = torusParameters(centre);
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3d p = mesh.positions.row(v);
    double distance;
    if (surface == WillmoreSurface::Sphere) {
      distance = std::atan2(p.cross(centre).norm(), p.dot(centre));
    } else {
      const Eigen::Vector2d uv = torusParameters(p);
      const auto wrapped = [](double a) { return std::remainder(a, 2.0 * kPi); };
      // Arc lengths: along u at the centre's circle of radius √2 + cos v_c, along v on the tube.
      distance = std::hypot((kTorusRadius + std::cos(c.y())) * wrapped(uv.x() - c.x()),
                            wrapped(uv.y() - c.y()));
    }
    region[v] = distance < radius;
  }
  return region;
}

Positions perturbRegion(WillmoreSurface surface, const Mesh& mesh, const std::vector<bool>& region,
                        const Eigen::Vector3d& centre, Perturbation perturbation, double amplitude,
                        std::uint64_t seed) {
  Positions x = mesh.positions;
  const Eigen::Vector3d n = outwardNormal(surface, centre);
  double rim = std::numeric_limits<double>::infinity();  // lowest region vertex along n
  for (int v = 0; v < mesh.vertexCount(); ++v)
    if (region[v]) rim = std::min(rim, n.dot(mesh.positions.row(v).transpose()));
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    if (!region[v]) continue;
    const Eigen::Vector3d p = mesh.positions.row(v);
    if (perturbation == Perturbation::Noise) {
      x.row(v) = (p + amplitude * unit(random) * outwardNormal(surface, p)).transpose();
    } else {
      x.row(v) = (p - (n.dot(p) - rim) * n).transpose();
    }
  }
  return x;
}

}  // namespace flexure::modeling
