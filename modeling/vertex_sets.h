// Sets of vertices a user names: a list of indices in a file, or the vertices inside a sphere.
// A set is a #V mask (std::vector<bool>).
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

// Vertex indices from a text file: integers separated by white space or commas, '#' starts a
// comment. `what` names the list in messages ("fixed-vertex list", "region"). Throws InputError
// naming the file and line for a malformed entry or an index out of range.
std::vector<bool> readVertexSet(const std::string& path, int vertexCount, std::string_view what);

// The vertices with |x_v − centre| ≤ radius.
std::vector<bool> verticesInSphere(const Positions& positions, const Eigen::Vector3d& centre,
                                   double radius);

// How many entries of `set` are true.
int countVertices(const std::vector<bool>& set);

}  // namespace flexure::modeling
