// The test-problem meshes: flat triangulations of the square [−1/2, 1/2]² (z = 0).
//
// patch48   4-8 mesh: n × n square cells, the diagonal of cell (i, j) runs from its lower-left to
//           its upper-right corner when i + j is even and from lower-right to upper-left when odd,
//           so interior vertices have valence 8 (i + j even) or 4 (odd).
// stripe    the same 4-8 pattern on cells of aspect ratio 1:2 (width 1/n, height 2/n; n even).
// criss     n × n/aspect cells, every cell split by the same (lower-left → upper-right) diagonal.
// delaunay  an irregular CGAL Delaunay triangulation with edge length about 1/n: boundary vertices
//           spaced 1/n along the square's sides, interior points by seeded Poisson-disk sampling.
//
// `aspect` is cell height / cell width (patch48 and criss: default 1, stripe: 2; the square must
// hold a whole number of cells). `seed` drives the delaunay sampling; the same options give the
// same mesh, bit for bit.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

enum class MeshFamily { Patch48, Stripe, Criss, Delaunay };

struct GeneratorOptions {
  MeshFamily family = MeshFamily::Patch48;
  int n = 8;                     // cells per side (delaunay: boundary segments per side)
  std::uint64_t seed = 1;        // delaunay only
  std::optional<double> aspect;  // cell height / width; family default when empty

  // Throws InputError, naming the family and the field, for n < 1, an odd n for stripe, an
  // aspect that is not positive or does not tile the square, an aspect given to delaunay, or a
  // mesh too large to index.
  void validate() const;
};

// "patch48" | "stripe" | "criss" | "delaunay"; throws InputError listing the names otherwise.
MeshFamily parseMeshFamily(std::string_view name);
std::string_view meshFamilyName(MeshFamily family);

// Throws InputError when the options do not validate.
Mesh generateMesh(const GeneratorOptions& options);

// `levels` meshes with n, 2n, 4n, ... (same family, seed and aspect).
std::vector<Mesh> refinementSequence(const GeneratorOptions& coarsest, int levels);

// The CGAL Delaunay mesh behind MeshFamily::Delaunay (delaunay_mesh.cpp).
Mesh delaunayMesh(int n, std::uint64_t seed);

}  // namespace flexure::modeling
