#include "curvature/shared_block_cost.h"

#include <algorithm>

namespace flexure::curvature {

SharedBlockCost::SharedBlockCost(ceres::CostFunction* element, std::vector<int> slotBlock)
    : element_(element), slotBlock_(std::move(slotBlock)) {
  set_num_residuals(element_->num_residuals());
  const std::vector<int>& slotSizes = element_->parameter_block_sizes();
  std::vector<int>& sizes = *mutable_parameter_block_sizes();
  sizes.assign(*std::max_element(slotBlock_.begin(), slotBlock_.end()) + 1, 0);
  for (std::size_t k = 0; k < slotBlock_.size(); ++k) sizes[slotBlock_[k]] = slotSizes[k];
}

bool SharedBlockCost::Evaluate(double const* const* parameters, double* residuals,
                               double** jacobians) const {
  const std::size_t slots = slotBlock_.size();
  std::vector<const double*> slotParameters(slots);
  for (std::size_t k = 0; k < slots; ++k) slotParameters[k] = parameters[slotBlock_[k]];
  if (jacobians == nullptr) return element_->Evaluate(slotParameters.data(), residuals, nullptr);

  const int rows = num_residuals();
  const std::vector<int>& slotSizes = element_->parameter_block_sizes();
  std::vector<std::vector<double>> slotJacobians(slots);
  std::vector<double*> slotJacobianPointers(slots);
  for (std::size_t k = 0; k < slots; ++k) {
    slotJacobians[k].resize(static_cast<std::size_t>(rows * slotSizes[k]));
    slotJacobianPointers[k] = slotJacobians[k].data();
  }
  if (!element_->Evaluate(slotParameters.data(), residuals, slotJacobianPointers.data()))
    return false;
  const std::vector<int>& sizes = parameter_block_sizes();
  for (std::size_t b = 0; b < sizes.size(); ++b)
    if (jacobians[b] != nullptr) std::fill_n(jacobians[b], rows * sizes[b], 0.0);
  for (std::size_t k = 0; k < slots; ++k) {
    double* target = jacobians[slotBlock_[k]];
    if (target == nullptr) continue;
    for (std::size_t i = 0; i < slotJacobians[k].size(); ++i) target[i] += slotJacobians[k][i];
  }
  return true;
}

ceres::CostFunction* shareRepeatedBlocks(ceres::CostFunction* cost, std::vector<double*>& blocks) {
  std::vector<double*> distinct;
  std::vector<int> slotBlock;
  for (double* block : blocks) {
    const auto found = std::find(distinct.begin(), distinct.end(), block);
    slotBlock.push_back(static_cast<int>(found - distinct.begin()));
    if (found == distinct.end()) distinct.push_back(block);
  }
  if (distinct.size() == blocks.size()) return cost;
  blocks = std::move(distinct);
  return new SharedBlockCost(cost, std::move(slotBlock));
}

}  // namespace flexure::curvature
