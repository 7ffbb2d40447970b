// The cracks a render draws (internal to render/): per face, which of its edges and corners lie
// on a crack, for the fragment shader's crack band.
#pragma once

#include <array>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::render {

// Per face (#F), where cracks touch it: bit k set when the edge (t_{k+1}, t_{k+2}) opposite corner
// k is a crack edge, bit 3 + k when corner k is an end of one (its faces around the vertex fill the
// band's joints and caps). InputError for an edge that is no face's.
std::vector<int> faceCrackBits(const modeling::Mesh& mesh,
                               const std::vector<std::array<int, 2>>& crackEdges);

}  // namespace flexure::render
