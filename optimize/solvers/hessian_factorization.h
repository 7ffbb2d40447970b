// The sparse Cholesky factorization of an assembled Hessian (assembly/hessian_assembly.h), its
// symbolic analysis done once per problem, and the fill-reducing order it is analysed with.
#pragma once

#include <memory>
#include <vector>

#include "optimize/assembly/hessian_assembly.h"
#include "optimize/linear/cholesky_factor.h"

namespace flexure::optimize {

// A sparse Cholesky factorization (CHOLMOD, supernodal) of the assembled Hessian whose symbolic
// analysis — the fill-reducing order and the factor's structure — is computed once, at
// construction, and reused by every numerical factorization. It keeps its own copy of the
// pattern, so it serves any later assembly with the same pattern (KeptFactorization, minimize.h).
class HessianFactorization {
 public:
  // `order`: the elimination order of the free unknowns, or empty for the one CHOLMOD computes
  // by `computed`. `simplicial`: Eigen's SimplicialLLT on its AMD order instead (single-threaded,
  // column by column), the linear algebra of a plain Newton solver such as libshell's: a
  // benchmark baseline.
  HessianFactorization(const HessianAssembly& assembly, const std::vector<int>& order,
                       FillReducingOrder computed = FillReducingOrder::NestedDissection,
                       bool simplicial = false);
  ~HessianFactorization();
  HessianFactorization(const HessianFactorization&) = delete;
  HessianFactorization& operator=(const HessianFactorization&) = delete;

  // Whether `assembly` has the pattern this factorization was analysed for.
  bool serves(const HessianAssembly& assembly) const;

  // Factors H + μ I. false when it is not positive definite (or CHOLMOD fails).
  bool factor(const std::vector<double>& values, double shift = 0.0);
  // H⁻¹ b with the last successful factor.
  Eigen::VectorXd solve(const Eigen::VectorXd& b);

 private:
  struct Cholmod;
  struct Simplicial;
  std::unique_ptr<Cholmod> cholmod_;
  std::unique_ptr<Simplicial> simplicial_;
};

// The fill-reducing order for `assembly`'s free unknowns: geometric nested dissection of the free
// vertices (elimination_order.h) at `at` when every free unknown is a vertex coordinate; empty
// (CHOLMOD's nested dissection, HessianFactorization) when a ξ is free.
std::vector<int> hessianOrder(const HessianAssembly& assembly, const Positions& at);

}  // namespace flexure::optimize
