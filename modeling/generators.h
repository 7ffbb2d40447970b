// The test-problem meshes: flat triangulations of the square [−1/2, 1/2]² (z = 0), and shells.
//
// patch48   4-8 mesh: n × n square cells, the diagonal of cell (i, j) runs from its lower-left to
//           its upper-right corner when i + j is even and from lower-right to upper-left when odd,
//           so interior vertices have valence 8 (i + j even) or 4 (odd).
// stripe    the same 4-8 pattern on cells of aspect ratio 1:2 (width 1/n, height 2/n; n even).
// criss     n × n/aspect cells, every cell split by the same (lower-left → upper-right) diagonal.
// delaunay  an irregular CGAL Delaunay triangulation with edge length about 1/n: boundary vertices
//           spaced 1/n along the square's sides, interior points by seeded Poisson-disk sampling.
//
// cylinder  open tube of radius 1/2 about the z axis, length = aspect (default 1, the diameter;
//           z in [−length/2, length/2]): rings of n vertices, every other ring turned
//           by half a step, ring spacing (π/n)·√3 so that the triangles are nearly equilateral;
//           two boundary loops.
// sphere    closed sphere of radius 1/2 about the origin: rings of latitude at polar angles
//           θ_k = kπ/(2m), m = n/4, each with round(4m sin θ_k) vertices (1 at the poles, n on
//           the equator), neighbouring rings joined by a zipper ordered by longitude.
// hemisphere its upper half (z ≥ 0): the rings k = 0 .. m, one boundary loop (the equator).
// Shells are counter-clockwise seen from outside (normals point away from the axis / centre); n is
// the number of edges around the circumference (sphere, hemisphere: a multiple of 4).
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

enum class MeshFamily { Patch48, Stripe, Criss, Delaunay, Cylinder, Sphere, Hemisphere };

struct GeneratorOptions {
  MeshFamily family = MeshFamily::Patch48;
  int n = 8;               // cells per side (delaunay: boundary segments per side; shells:
                           // edges around the circumference)
  std::uint64_t seed = 1;  // delaunay only
  std::optional<double>
      aspect;  // cell height / width (cylinder: length / diameter); family default when empty

  // Throws InputError, naming the family and the field, for n < 1, an odd n for stripe, an
  // aspect that is not positive or does not tile the square, an aspect given to delaunay, a
  // sphere or hemisphere, n < 3 for a cylinder, n not a multiple of 4 for a sphere or
  // hemisphere, or a mesh too large to index.
  void validate() const;
};

// "patch48" | "stripe" | "criss" | "delaunay" | "cylinder" | "sphere" | "hemisphere"; throws
// InputError listing the names otherwise.
MeshFamily parseMeshFamily(std::string_view name);
// The same for the plate problems (studies, comparisons, plate modes): a shell's name is refused
// with an InputError saying that they take the square's families.
MeshFamily parsePlateFamily(std::string_view name);
bool isShellFamily(MeshFamily family);
std::string_view meshFamilyName(MeshFamily family);

// Throws InputError when the options do not validate.
Mesh generateMesh(const GeneratorOptions& options);

// `levels` meshes with n, 2n, 4n, ... (same family, seed and aspect).
std::vector<Mesh> refinementSequence(const GeneratorOptions& coarsest, int levels);

// The shells behind MeshFamily::Cylinder (length = aspect), Sphere and Hemisphere
// (options validated).
Mesh cylinderMesh(int n, double length);
Mesh sphereMesh(int n, bool upperHalfOnly);

// The CGAL Delaunay mesh behind MeshFamily::Delaunay (delaunay_mesh.cpp).
Mesh delaunayMesh(int n, std::uint64_t seed);

}  // namespace flexure::modeling
