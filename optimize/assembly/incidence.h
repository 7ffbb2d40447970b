// Which unknowns' nodes each element reads: the coupling graph fill-reducing orders work on
// (linear/elimination_order.h), recorded by the Hessian assembly.
#pragma once

#include <algorithm>
#include <vector>

namespace flexure::optimize {

// Which nodes (blocks of unknowns: a vertex, a midedge ξ) each residual reads, compressed:
// residual k reads nodes[start[k] .. start[k + 1]).
struct Incidence {
  std::vector<int> start{0}, nodes;

  // Appends a residual reading `read` (sorted and deduplicated in place).
  void append(std::vector<int>& read) {
    std::sort(read.begin(), read.end());
    read.erase(std::unique(read.begin(), read.end()), read.end());
    nodes.insert(nodes.end(), read.begin(), read.end());
    start.push_back(static_cast<int>(nodes.size()));
  }
};

}  // namespace flexure::optimize
