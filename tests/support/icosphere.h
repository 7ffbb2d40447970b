// A closed test surface with a known curvature: the icosphere, a regular icosahedron whose faces
// are split 1 → 4 at the edge midpoints `levels` times, every vertex projected onto the sphere of
// radius R about the origin. Faces are counter-clockwise seen from outside (outward normals).
// Level k has 20 · 4^k faces, 30 · 4^k edges and 10 · 4^k + 2 vertices.
#pragma once

#include "modeling/mesh.h"
#include "modeling/willmore_surfaces.h"

namespace flexure::testing {

inline modeling::Mesh icosphere(int levels, double radius) {
  modeling::Mesh mesh = modeling::irregularSphere(levels, 0.0, 0);  // no jitter: the icosphere
  mesh.positions *= radius;
  return mesh;
}

}  // namespace flexure::testing
