// Surfaces with a known fair answer, for measuring fairing: the round sphere and the Clifford
// torus are Willmore surfaces (critical points of ∫ H² dA; Willmore 1965, Marques & Neves 2014 for
// the torus' minimality), so with flat rest curvature every bending energy of docs/energies.md —
// a discretization of ∫ (4H² − 2(1 − ν)K) dA, whose K part is a boundary term — is stationary on
// them: a fairing of a perturbed region of either should give the surface back.
//
// Meshes are irregular on purpose (a regular one hides discretization errors): vertices of a
// regular tessellation moved tangentially by a seeded random fraction of the local edge length and
// put back on the surface. Both are closed; a region is a cap of them (fairing_region.h holds two
// rings around it).
#pragma once

#include <cstdint>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

enum class WillmoreSurface { Sphere, CliffordTorus };

// The unit sphere: an icosphere of `levels` 1 → 4 splits (10 · 4^levels + 2 vertices), each vertex
// moved in its tangent plane by up to `jitter` × the level's edge length (uniform in a disk,
// seeded) and projected back.
Mesh irregularSphere(int levels, double jitter, std::uint64_t seed);

// The unit sphere remeshed by CGAL (Polygon_mesh_processing::isotropic_remeshing, 5 iterations, on
// a level-6 icosphere, target edge length `edge`; then every vertex projected onto the sphere):
// CGAL's connectivity, valences 4 to 8 spread over the surface, instead of the icosphere's
// semi-regular one. edge in [0.02, 1].
Mesh remeshedSphere(double edge);

// The Clifford torus of radii √2 : 1, x(u, v) = ((√2 + cos v) cos u, (√2 + cos v) sin u, sin v):
// an n·√2-by-n grid in (u, v) (rounded; square cells on the surface's mean scale), each cell split
// along alternating diagonals, the parameters jittered by up to `jitter` cells (seeded).
Mesh cliffordTorus(int n, double jitter, std::uint64_t seed);

// |distance of p to the exact surface| divided by its scale (the sphere's radius 1, the torus'
// tube radius 1).
double relativeDistance(WillmoreSurface surface, const Eigen::Vector3d& p);

// The exact surface's closest point to p and its unit outward normal there.
Eigen::Vector3d closestPoint(WillmoreSurface surface, const Eigen::Vector3d& p);
Eigen::Vector3d outwardNormal(WillmoreSurface surface, const Eigen::Vector3d& p);

// A geodesic cap: the vertices whose geodesic distance on the exact surface from `centre` (a
// point on it) is below `radius`. Sphere: the angle to the centre; torus: the flat (u, v)
// parameter distance scaled by the tube radius — geodesic near the centre and a simple, stated
// region elsewhere.
std::vector<bool> capRegion(WillmoreSurface surface, const Mesh& mesh,
                            const Eigen::Vector3d& centre, double radius);

// How a region is spoiled before fairing it.
enum class Perturbation {
  Noise,    // each region vertex moved along the surface normal by a seeded uniform amount in
            // [−amplitude, amplitude] (relative to the scale)
  Flatten,  // each region vertex projected onto the plane through the centre's tangent
            // direction that holds the cap's boundary: the cap pressed flat (amplitude unused)
};

Positions perturbRegion(WillmoreSurface surface, const Mesh& mesh, const std::vector<bool>& region,
                        const Eigen::Vector3d& centre, Perturbation perturbation, double amplitude,
                        std::uint64_t seed);

}  // namespace flexure::modeling
