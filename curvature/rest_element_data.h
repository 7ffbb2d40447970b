// What the bending energies' factories read from the rest state, shared by their files
// (hinge_energy.cpp, triangle_averaged_energy.cpp, cotan_energy.cpp, midedge_energy.cpp,
// quadratic_fit_energy.cpp): an element's rest blocks, rest edge tensors and Koiter weights.
#pragma once

#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/current_metric.h"
#include "curvature/koiter_density.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"

namespace flexure::curvature {

// The rest positions of `count` vertices as parameter blocks (3 doubles each).
inline std::vector<const double*> restBlocks(const modeling::RestState& rest, const int* vertices,
                                             int count) {
  std::vector<const double*> blocks;
  for (int k = 0; k < count; ++k) blocks.push_back(rest.positions.data() + 3 * vertices[k]);
  return blocks;
}

inline Vec3<double> restPoint(const modeling::RestState& rest, int v) {
  return {rest.positions(v, 0), rest.positions(v, 1), rest.positions(v, 2)};
}

// scale · n̂_i n̂_iᵀ of face f's edge i in the face's rest frame: current_metric.h's ℓ_i n̂_i n̂_iᵀ
// at the rest positions (the same formula the current metric evaluates at x), times scale / ℓ̄_i.
inline Sym2<double> edgeTensor(const modeling::Stencils& s, const modeling::RestState& rest, int f,
                               int i, double scale) {
  const Vec3<double> x[3] = {restPoint(rest, s.faces(f, 0)), restPoint(rest, s.faces(f, 1)),
                             restPoint(rest, s.faces(f, 2))};
  const Sym2<double> t = currentEdgeTensors(x, currentFrame(x[0], x[1], x[2]))[i];
  const double c = scale / rest.faceEdgeLengths(f, i);
  return {c * t.a, c * t.b, c * t.c};
}

// The face energies' Koiter weights: make(ν, 2 k_B Ā_T), or per unit area on the current metric
// (the kernel multiplies by the current √A_T).
inline KoiterWeights koiterWeights(const BendingOptions& o, double poisson, double restArea) {
  const double area = o.metric == CurvatureMetric::Current ? 1.0 : restArea;
  return KoiterWeights::make(poisson, 2.0 * o.stiffness * area);
}

}  // namespace flexure::curvature
