#include "curvature/mean_curvature_field.h"

#include "curvature/cotan_mean_curvature.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"

namespace flexure::curvature {

std::vector<double> cotanVertexMeanCurvature(const modeling::Mesh& mesh) {
  const modeling::Stencils stencils = modeling::compileStencils(mesh);
  const modeling::RestState state = modeling::precomputeRestState(stencils, mesh.positions);
  std::vector<double> h(mesh.vertexCount(), 0.0);
  std::vector<const double*> blocks;
  for (int v = 0; v < stencils.vertexCount(); ++v) {
    if (stencils.vertexOnBoundary[v]) continue;
    blocks.assign(1, state.positions.data() + 3 * v);
    for (int k = stencils.oneRingOffsets[v]; k < stencils.oneRingOffsets[v + 1]; ++k)
      blocks.push_back(state.positions.data() + 3 * stencils.oneRingVertices[k]);
    h[v] = 0.5 * cotanMeanCurvatureNormal(blocks.data(), static_cast<int>(blocks.size()) - 1) /
           state.vertexVoronoiAreas[v];
  }
  return h;
}

}  // namespace flexure::curvature
