// A flat plate seen from above (+z, x to the right, y up): a per-vertex scalar interpolated across
// the faces on the diverging colour map (blue negative, white 0, red positive, over [−m, m],
// m = max |value|), the boundary outlined in grey and given line segments (a mode's nodal lines)
// drawn black — Chladni's figures, where the sand settles. Drawn with Cairo, no GL.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "modeling/mesh.h"
#include "render/image.h"

namespace flexure::render {

using Segment = std::pair<Eigen::Vector3d, Eigen::Vector3d>;

struct FieldMap {
  const modeling::Mesh* mesh = nullptr;  // drawn at its x, y
  std::vector<double> values;            // #V
  std::vector<Segment> lines;            // at their x, y
  int size = 256;                        // pixels, square, in [32, 8192]
};

// Throws InputError for a missing mesh, a value count that is not #V, or a size out of range.
Image renderFieldMap(const FieldMap& map);

}  // namespace flexure::render
