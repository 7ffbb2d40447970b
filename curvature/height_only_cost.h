// Derivatives for the height-field mode (DofMode::Height), where x and y of every vertex are held:
// only ∂r/∂z and ∂r/∂ξ are needed. Forward-mode autodiff with one derivative component per
// parameter block (a vertex block's z, or a ξ) instead of one per coordinate: a third of the
// derivative arithmetic of the full Jacobian for vertex-only elements. The x and y columns of a
// vertex block's Jacobian are written as zero; in a Ceres problem the SubsetManifold that holds
// x and y drops them. Evaluation seconds in bench/solve_bench at n = 512, before → after
// (separate runs): nonlinear cotan 7.0 → 3.0, triavg 9.0 → 4.8–6.4, midedge 10.9 → 4.9,
// quadfit 6.0 → 3.1–3.6; linearized triavg 3.4 → 1.3, quadfit 2.7 → 1.0.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/jet.h>

#include <array>
#include <cstdint>
#include <vector>

namespace flexure::curvature {

// Which derivatives an energy term's Jacobians hold: all coordinates, or only z (and ξ).
enum class Derivatives { All, HeightOnly };

// `Residual` has a templated operator()(T const* const* blocks, T* residuals) and kResiduals;
// `blockSizes` (kBlocks entries, each 3 for a vertex or 1 for a ξ) as in its full cost function.
template <class Residual, int kBlocks>
class HeightOnlyCost : public ceres::CostFunction {
 public:
  HeightOnlyCost(const Residual& residual, const std::vector<int32_t>& blockSizes)
      : residual_(residual) {
    *mutable_parameter_block_sizes() = blockSizes;
    set_num_residuals(Residual::kResiduals);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (jacobians == nullptr) return residual_(parameters, residuals);
    using Jet = ceres::Jet<double, kBlocks>;
    const std::vector<int32_t>& sizes = parameter_block_sizes();
    std::array<std::array<Jet, 3>, kBlocks> values;
    std::array<const Jet*, kBlocks> blocks;
    for (int b = 0; b < kBlocks; ++b) {
      const int last = sizes[b] - 1;  // z of a vertex block, or the ξ
      for (int c = 0; c < last; ++c) values[b][c] = Jet(parameters[b][c]);
      values[b][last] = Jet(parameters[b][last], b);
      blocks[b] = values[b].data();
    }
    std::array<Jet, Residual::kResiduals> r;
    if (!residual_(blocks.data(), r.data())) return false;
    for (int i = 0; i < Residual::kResiduals; ++i) residuals[i] = r[i].a;
    for (int b = 0; b < kBlocks; ++b) {
      if (jacobians[b] == nullptr) continue;
      for (int i = 0; i < Residual::kResiduals; ++i)
        for (int c = 0; c < sizes[b]; ++c)
          jacobians[b][i * sizes[b] + c] = c == sizes[b] - 1 ? r[i].v[b] : 0.0;
    }
    return true;
  }

 private:
  Residual residual_;
};

}  // namespace flexure::curvature
