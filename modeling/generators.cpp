#include "modeling/generators.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "modeling/errors.h"

namespace flexure::modeling {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Ring spacing of a tube of radius 1/2 with n vertices a ring: the height (√3/2)·(π/n) of an
// equilateral triangle on the ring's edge π/n.
double cylinderRingSpacing(int n) {
  return std::sqrt(3.0) / 2.0 * kPi / n;
}

// Shortest decimal that reads back to the same double, for messages quoting user values.
std::string formatNumber(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

// Rows and columns of a structured grid on the unit square.
struct GridSize {
  int nx = 0;
  int ny = 0;
};

// Meshes are indexed with int: the vertex and face counts must fit.
void requireIndexable(std::string_view family, std::int64_t vertices, std::int64_t faces) {
  constexpr std::int64_t kMax = std::numeric_limits<int>::max();
  if (vertices > kMax || faces > kMax) {
    throw InputError(std::string(family) + ": the mesh would have " + std::to_string(faces) +
                     " faces, more than a mesh can index");
  }
}

// nx = n columns of width 1/n; ny = n / aspect rows of height aspect/n, which must be a whole
// number ≥ 1 for the cells to tile the square.
GridSize gridSize(const GeneratorOptions& options, double defaultAspect) {
  const std::string family(meshFamilyName(options.family));
  const int n = options.n;
  if (options.family == MeshFamily::Stripe && !options.aspect && n % 2 != 0) {
    throw InputError("stripe: n = " + std::to_string(n) +
                     " is odd; the 1:2 cells (height 2/n) tile the square only for even n");
  }
  const double aspect = options.aspect.value_or(defaultAspect);
  if (!std::isfinite(aspect) || aspect <= 0.0) {
    throw InputError(family + ": GeneratorOptions.aspect must be a positive number, got " +
                     formatNumber(aspect));
  }
  const double rows = static_cast<double>(n) / aspect;
  const double wholeRows = std::round(rows);
  if (!(wholeRows >= 1.0) || std::abs(rows - wholeRows) > 1e-9 * wholeRows ||
      wholeRows > static_cast<double>(std::numeric_limits<int>::max())) {
    throw InputError(family + ": GeneratorOptions.aspect " + formatNumber(aspect) +
                     " does not tile the square with n = " + std::to_string(n) + " cells (" +
                     std::to_string(n) + "/" + formatNumber(aspect) + " is not a whole number)");
  }
  GridSize size{n, static_cast<int>(wholeRows)};
  requireIndexable(family, (std::int64_t{size.nx} + 1) * (std::int64_t{size.ny} + 1),
                   2 * std::int64_t{size.nx} * std::int64_t{size.ny});
  return size;
}

// Vertex (i, j) at (−1/2 + i/nx, −1/2 + j/ny), index j·(nx + 1) + i. Each cell gives two
// counter-clockwise triangles, split along the lower-left → upper-right diagonal, or along the
// lower-right → upper-left one where `alternate` is set and i + j is odd (the 4-8 pattern).
Mesh structuredGrid(GridSize size, bool alternate) {
  const int nx = size.nx;
  const int ny = size.ny;
  Mesh mesh;
  mesh.positions.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      mesh.positions.row(j * (nx + 1) + i) << -0.5 + static_cast<double>(i) / nx,
          -0.5 + static_cast<double>(j) / ny, 0.0;
    }
  }
  mesh.triangles.resize(2 * nx * ny, 3);
  int face = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int lowerLeft = j * (nx + 1) + i;
      const int lowerRight = lowerLeft + 1;
      const int upperLeft = lowerLeft + nx + 1;
      const int upperRight = upperLeft + 1;
      if (alternate && (i + j) % 2 != 0) {
        mesh.triangles.row(face++) << lowerLeft, lowerRight, upperLeft;
        mesh.triangles.row(face++) << lowerRight, upperRight, upperLeft;
      } else {
        mesh.triangles.row(face++) << lowerLeft, lowerRight, upperRight;
        mesh.triangles.row(face++) << lowerLeft, upperRight, upperLeft;
      }
    }
  }
  return mesh;
}

// Ring k of a shell of revolution: `count` vertices at height z and distance `radius` from the z
// axis, vertex i at longitude 2π (i + offset) / count (one vertex on the axis when count = 1).
struct Ring {
  int count = 1;
  double radius = 0.0;
  double z = 0.0;
  double offset = 0.0;
  int first = 0;  // index of its vertex 0

  double longitude(int i) const { return 2.0 * kPi * (i + offset) / count; }
};

// Places the rings' vertices (numbering them ring after ring) and joins each ring to the next by a
// zipper: walking both rings by longitude, each step adds the triangle over the edge of the ring
// whose next vertex comes first. Rings are listed from the top (largest z) down, so each triangle
// (upper i, lower j, upper i + 1) or (lower j, lower j + 1, upper i) faces away from the axis.
Mesh ringMesh(std::vector<Ring> rings) {
  int vertices = 0;
  for (Ring& ring : rings) {
    ring.first = vertices;
    vertices += ring.count;
  }
  Mesh mesh;
  mesh.positions.resize(vertices, 3);
  for (const Ring& ring : rings) {
    for (int i = 0; i < ring.count; ++i) {
      const double phi = ring.longitude(i);
      mesh.positions.row(ring.first + i) << ring.radius * std::cos(phi),
          ring.radius * std::sin(phi), ring.z;
    }
  }
  std::vector<Eigen::Vector3i> faces;
  for (std::size_t k = 0; k + 1 < rings.size(); ++k) {
    const Ring& upper = rings[k];
    const Ring& lower = rings[k + 1];
    int i = 0;
    int j = 0;
    while (i < upper.count || j < lower.count) {
      const bool upperFirst =
          j == lower.count || (i < upper.count && upper.longitude(i + 1) < lower.longitude(j + 1));
      const int a = upper.first + i % upper.count;
      const int b = lower.first + j % lower.count;
      if (upperFirst && upper.count > 1) {
        faces.emplace_back(a, b, upper.first + (i + 1) % upper.count);
      } else if (!upperFirst && lower.count > 1) {
        faces.emplace_back(b, lower.first + (j + 1) % lower.count, a);
      }
      (upperFirst ? i : j) += 1;
    }
  }
  mesh.triangles.resize(static_cast<int>(faces.size()), 3);
  for (int f = 0; f < mesh.faceCount(); ++f) mesh.triangles.row(f) = faces[f].transpose();
  return mesh;
}

void requireShellSize(const GeneratorOptions& options) {
  const std::string name(meshFamilyName(options.family));
  if (options.family == MeshFamily::Cylinder) {
    if (options.n < 3) {
      throw InputError(name + ": n = " + std::to_string(options.n) +
                       " edges around the tube; at least 3 are needed");
    }
    const double length = options.aspect.value_or(1.0);
    if (!std::isfinite(length) || length <= 0.0) {
      throw InputError(name + ": GeneratorOptions.aspect (length / diameter) must be a positive " +
                       "number, got " + formatNumber(length));
    }
    const double rows = std::ceil(length / cylinderRingSpacing(options.n));
    if (!(rows < 1e9)) {
      throw InputError(name + ": GeneratorOptions.aspect " + formatNumber(length) +
                       " makes too many rings for n = " + std::to_string(options.n));
    }
    requireIndexable(name, std::int64_t{options.n} * (static_cast<std::int64_t>(rows) + 1),
                     2 * std::int64_t{options.n} * static_cast<std::int64_t>(rows));
    return;
  }
  if (options.aspect) {
    throw InputError(name + ": GeneratorOptions.aspect " + formatNumber(*options.aspect) +
                     " does not apply to a " + name + " (omit GeneratorOptions.aspect)");
  }
  if (options.n < 4 || options.n % 4 != 0) {
    throw InputError(name + ": n = " + std::to_string(options.n) +
                     " edges around the equator must be a positive multiple of 4");
  }
  // About n²/π vertices on the sphere (area π over an equilateral cell of edge π/n).
  requireIndexable(name, std::int64_t{options.n} * options.n,
                   2 * std::int64_t{options.n} * options.n);
}

}  // namespace

Mesh cylinderMesh(int n, double length) {
  const int rows = std::max(1, static_cast<int>(std::lround(length / cylinderRingSpacing(n))));
  std::vector<Ring> rings(rows + 1);
  for (int k = 0; k <= rows; ++k) {
    rings[k] = Ring{n, 0.5, 0.5 * length - length * k / rows, 0.5 * (k % 2)};
  }
  return ringMesh(std::move(rings));
}

Mesh sphereMesh(int n, bool upperHalfOnly) {
  const int m = n / 4;  // rings from the pole to the equator
  const int last = upperHalfOnly ? m : 2 * m;
  std::vector<Ring> rings(last + 1);
  for (int k = 0; k <= last; ++k) {
    const double theta = kPi * k / (2.0 * m);
    const double sine = k == 0 || k == 2 * m ? 0.0 : std::sin(theta);
    const int count = std::max(1, static_cast<int>(std::lround(4.0 * m * sine)));
    // cos θ_k as sin(π/2 − θ_k): the equator at z = 0 exactly.
    rings[k] = Ring{count, 0.5 * sine, 0.5 * std::sin(kPi * (m - k) / (2.0 * m)), 0.5 * (k % 2)};
  }
  return ringMesh(std::move(rings));
}

MeshFamily parseMeshFamily(std::string_view name) {
  if (name == "patch48") return MeshFamily::Patch48;
  if (name == "stripe") return MeshFamily::Stripe;
  if (name == "criss") return MeshFamily::Criss;
  if (name == "delaunay") return MeshFamily::Delaunay;
  if (name == "cylinder") return MeshFamily::Cylinder;
  if (name == "sphere") return MeshFamily::Sphere;
  if (name == "hemisphere") return MeshFamily::Hemisphere;
  throw InputError("unknown mesh family '" + std::string(name) +
                   "'; expected patch48, stripe, criss, delaunay, cylinder, sphere or hemisphere");
}

bool isShellFamily(MeshFamily family) {
  return family == MeshFamily::Cylinder || family == MeshFamily::Sphere ||
         family == MeshFamily::Hemisphere;
}

MeshFamily parsePlateFamily(std::string_view name) {
  const MeshFamily family = parseMeshFamily(name);
  if (isShellFamily(family)) {
    throw InputError("'" + std::string(name) +
                     "' is a shell; the plate problems take the square's families patch48, "
                     "stripe, criss or delaunay");
  }
  return family;
}

std::string_view meshFamilyName(MeshFamily family) {
  switch (family) {
    case MeshFamily::Patch48:
      return "patch48";
    case MeshFamily::Stripe:
      return "stripe";
    case MeshFamily::Criss:
      return "criss";
    case MeshFamily::Delaunay:
      return "delaunay";
    case MeshFamily::Cylinder:
      return "cylinder";
    case MeshFamily::Sphere:
      return "sphere";
    case MeshFamily::Hemisphere:
      return "hemisphere";
  }
  return "unknown";
}

void GeneratorOptions::validate() const {
  const std::string name(meshFamilyName(family));
  if (n < 1) throw InputError(name + ": n must be at least 1, got " + std::to_string(n));
  switch (family) {
    case MeshFamily::Patch48:
    case MeshFamily::Criss:
      gridSize(*this, 1.0);
      return;
    case MeshFamily::Stripe:
      gridSize(*this, 2.0);
      return;
    case MeshFamily::Delaunay:
      if (aspect) {
        throw InputError("delaunay: GeneratorOptions.aspect " + formatNumber(*aspect) +
                         " does not apply; the delaunay mesh has no cells (omit "
                         "GeneratorOptions.aspect)");
      }
      // About 1.1 n² vertices and twice as many faces.
      requireIndexable(name, 2 * std::int64_t{n} * n, 4 * std::int64_t{n} * n);
      return;
    case MeshFamily::Cylinder:
    case MeshFamily::Sphere:
    case MeshFamily::Hemisphere:
      requireShellSize(*this);
      return;
  }
  throw InputError("unknown mesh family");
}

Mesh generateMesh(const GeneratorOptions& options) {
  options.validate();
  switch (options.family) {
    case MeshFamily::Patch48:
      return structuredGrid(gridSize(options, 1.0), true);
    case MeshFamily::Stripe:
      return structuredGrid(gridSize(options, 2.0), true);
    case MeshFamily::Criss:
      return structuredGrid(gridSize(options, 1.0), false);
    case MeshFamily::Delaunay:
      return delaunayMesh(options.n, options.seed);
    case MeshFamily::Cylinder:
      return cylinderMesh(options.n, options.aspect.value_or(1.0));
    case MeshFamily::Sphere:
      return sphereMesh(options.n, false);
    case MeshFamily::Hemisphere:
      return sphereMesh(options.n, true);
  }
  throw InputError("unknown mesh family");
}

std::vector<Mesh> refinementSequence(const GeneratorOptions& coarsest, int levels) {
  if (levels < 1) {
    throw InputError("refinement sequence: levels must be at least 1, got " +
                     std::to_string(levels));
  }
  std::vector<Mesh> meshes;
  meshes.reserve(levels);
  GeneratorOptions options = coarsest;
  for (int level = 0; level < levels; ++level) {
    if (level > 0) {
      if (options.n > std::numeric_limits<int>::max() / 2) {
        throw InputError("refinement sequence: n = " + std::to_string(options.n) +
                         " cannot be doubled " + std::to_string(levels - level) + " more times");
      }
      options.n *= 2;
    }
    meshes.push_back(generateMesh(options));
  }
  return meshes;
}

}  // namespace flexure::modeling
