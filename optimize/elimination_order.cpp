#include "optimize/elimination_order.h"

#include <cholmod.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <unordered_map>
#include <vector>

#include "modeling/errors.h"

namespace flexure::optimize {

std::shared_ptr<ceres::ParameterBlockOrdering> nestedDissectionGroups(const ceres::Problem& problem,
                                                                      int groupCount) {
  std::vector<double*> blocks;
  problem.GetParameterBlocks(&blocks);
  std::unordered_map<const double*, int> freeIndex;
  std::vector<double*> freeBlocks;
  for (double* block : blocks) {
    if (problem.IsParameterBlockConstant(block)) continue;
    if (problem.ParameterBlockSize(block) != 3) return nullptr;
    freeIndex.emplace(block, static_cast<int>(freeBlocks.size()));
    freeBlocks.push_back(block);
  }
  const int n = static_cast<int>(freeBlocks.size());
  if (n < kNestedDissectionMinBlocks) return nullptr;

  // The coupling graph as the upper triangle of a symmetric pattern (CHOLMOD stype = 1).
  std::vector<ceres::ResidualBlockId> residualBlocks;
  problem.GetResidualBlocks(&residualBlocks);
  std::vector<Eigen::Triplet<double, int>> couplings;
  std::vector<double*> read;
  std::vector<int> readFree;
  for (ceres::ResidualBlockId id : residualBlocks) {
    problem.GetParameterBlocksForResidualBlock(id, &read);
    readFree.clear();
    for (double* block : read) {
      const auto found = freeIndex.find(block);
      if (found != freeIndex.end()) readFree.push_back(found->second);
    }
    for (size_t a = 0; a < readFree.size(); ++a)
      for (size_t b = a; b < readFree.size(); ++b)
        couplings.emplace_back(std::min(readFree[a], readFree[b]),
                               std::max(readFree[a], readFree[b]), 1.0);
  }
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> graph(n, n);
  graph.setFromTriplets(couplings.begin(), couplings.end());
  couplings = {};
  graph.makeCompressed();

  cholmod_sparse view{};
  view.nrow = view.ncol = static_cast<size_t>(n);
  view.nzmax = static_cast<size_t>(graph.nonZeros());
  view.p = graph.outerIndexPtr();
  view.i = graph.innerIndexPtr();
  view.x = graph.valuePtr();
  view.stype = 1;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_PATTERN;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;
  cholmod_common common;
  cholmod_start(&common);
  std::vector<int> order(n);
  const int ok = cholmod_metis(&view, nullptr, 0, /*postorder=*/1, order.data(), &common);
  cholmod_finish(&common);
  if (!ok) {
    throw NumericalError("METIS could not order the " + std::to_string(n) +
                         " unknown blocks of the solve (CHOLMOD status " +
                         std::to_string(common.status) + ")");
  }

  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  const int groups = std::min(groupCount, n);
  for (int position = 0; position < n; ++position) {
    const int group = static_cast<int>(static_cast<long>(position) * groups / n);
    ordering->AddElementToGroup(freeBlocks[order[position]], group);
  }
  for (double* block : blocks)
    if (problem.IsParameterBlockConstant(block)) ordering->AddElementToGroup(block, 0);
  return ordering;
}

}  // namespace flexure::optimize
