// Elements that read one vertex through two slots. A face's two flap vertices are the same vertex
// where a vertex has valence 3 (real meshes have them), but Ceres refuses a residual block that
// lists a parameter block twice. The adapter gives Ceres each distinct block once and calls the
// element with the block in every slot; by the chain rule the Jacobian of a distinct block is the
// sum of its slots' Jacobians, ∂r/∂x = Σ_{k: slot k reads x} ∂r/∂(slot k).
#pragma once

#include <ceres/cost_function.h>

#include <memory>
#include <vector>

namespace flexure::curvature {

class SharedBlockCost : public ceres::CostFunction {
 public:
  // `slotBlock[k]`: the distinct block slot k of `element` reads (blocks numbered in order of
  // first appearance). Takes ownership of `element`.
  SharedBlockCost(ceres::CostFunction* element, std::vector<int> slotBlock);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  std::unique_ptr<ceres::CostFunction> element_;
  std::vector<int> slotBlock_;
};

// `cost` itself when `blocks` are distinct; otherwise removes the repeats from `blocks` (keeping
// first appearances in order) and returns a SharedBlockCost that owns `cost`.
ceres::CostFunction* shareRepeatedBlocks(ceres::CostFunction* cost, std::vector<double*>& blocks);

}  // namespace flexure::curvature
