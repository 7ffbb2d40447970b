// CGAL's Polygon_mesh_processing::fair — the linear fairing users reach for today, and the
// baseline flexure's nonlinear solves are measured against: the selected vertices move so that
// a bi-Laplacian (continuity 1) of the input's cotangent weights vanishes (Botsch & Kobbelt;
// Botsch et al. 2008, "On linear variational surface deformation methods"), solved by CGAL's
// default sparse LU.
#pragma once

#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

// Positions after fairing the vertices with freeVertex[v] = true; the others are held.
// Throws NumericalError when CGAL reports that the system could not be solved (too few fixed
// vertices around a region, for instance).
Positions cgalFair(const Mesh& mesh, const std::vector<bool>& freeVertex, int continuity = 1);

}  // namespace flexure::modeling
