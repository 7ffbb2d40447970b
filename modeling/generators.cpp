#include "modeling/generators.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "modeling/errors.h"

namespace flexure::modeling {

namespace {

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

}  // namespace

MeshFamily parseMeshFamily(std::string_view name) {
  if (name == "patch48") return MeshFamily::Patch48;
  if (name == "stripe") return MeshFamily::Stripe;
  if (name == "criss") return MeshFamily::Criss;
  if (name == "delaunay") return MeshFamily::Delaunay;
  throw InputError("unknown mesh family '" + std::string(name) +
                   "'; expected patch48, stripe, criss or delaunay");
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
