#include "optimize/elimination_order.h"

#include <algorithm>
#include <unordered_map>
#include <vector>

#include "modeling/errors.h"
#include "optimize/cholmod_view.h"

namespace flexure::optimize {
namespace {

// A pattern in compressed columns, built column by column.
struct Incidence {
  std::vector<int> columnStart{0}, rows;

  // Sorts `column`, drops repeats, and appends it.
  void append(std::vector<int>& column) {
    std::sort(column.begin(), column.end());
    column.erase(std::unique(column.begin(), column.end()), column.end());
    rows.insert(rows.end(), column.begin(), column.end());
    columnStart.push_back(static_cast<int>(rows.size()));
  }
};

// METIS nested dissection of A Aᵀ, A the n-row incidence pattern: Perm[k] = the k-th row.
std::vector<int> nestedDissection(Incidence& a, int n) {
  cholmod_sparse view = cholmodView(static_cast<size_t>(n), a.columnStart, a.rows, nullptr, true);
  cholmod_common common;
  cholmod_start(&common);
  std::vector<int> order(n);
  const int ok = cholmod_metis(&view, nullptr, 0, /*postorder=*/1, order.data(), &common);
  const int status = common.status;
  cholmod_finish(&common);
  if (!ok) {
    throw NumericalError("METIS could not order the " + std::to_string(n) +
                         " vertex blocks of the solve (CHOLMOD status " + std::to_string(status) +
                         ")");
  }
  return order;
}

}  // namespace

std::shared_ptr<ceres::ParameterBlockOrdering> nestedDissectionGroups(const ceres::Problem& problem,
                                                                      int groupCount) {
  std::vector<double*> blocks;
  problem.GetParameterBlocks(&blocks);
  std::unordered_map<const double*, int> vertexIndex;
  std::vector<double*> vertices;
  for (double* block : blocks) {
    if (problem.IsParameterBlockConstant(block)) continue;
    if (problem.ParameterBlockSize(block) != 3) return nullptr;
    vertexIndex.emplace(block, static_cast<int>(vertices.size()));
    vertices.push_back(block);
  }
  const int n = static_cast<int>(vertices.size());
  if (n < kNestedDissectionMinBlocks) return nullptr;

  // A: a column per residual block, the free vertices it reads.
  std::vector<ceres::ResidualBlockId> residualBlocks;
  problem.GetResidualBlocks(&residualBlocks);
  Incidence a;
  a.rows.reserve(residualBlocks.size() * 6);
  std::vector<double*> read;
  std::vector<int> column;
  for (ceres::ResidualBlockId id : residualBlocks) {
    problem.GetParameterBlocksForResidualBlock(id, &read);
    for (double* block : read)
      if (const auto v = vertexIndex.find(block); v != vertexIndex.end())
        column.push_back(v->second);
    a.append(column);
    column.clear();
  }
  const std::vector<int> order = nestedDissection(a, n);

  // Vertex k of the order goes to group ⌊k G / n⌋.
  const int groups = std::min(groupCount, n);
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (int position = 0; position < n; ++position) {
    ordering->AddElementToGroup(vertices[order[position]],
                                static_cast<int>(static_cast<long>(position) * groups / n));
  }
  for (double* block : blocks)
    if (problem.IsParameterBlockConstant(block)) ordering->AddElementToGroup(block, 0);
  return ordering;
}

}  // namespace flexure::optimize
