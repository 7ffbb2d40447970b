// The exact Hessian of a sum of energy terms, assembled from the element Hessians
// (curvature/element_hessian.h) into one sparse symmetric matrix over the free unknowns, and its
// sparse Cholesky factorization with the symbolic analysis done once per problem.
//
// Unknowns are those of energy_evaluation.h: 3v + c for coordinate c of vertex v, then 3 #V + e
// for ξ_e. The free ones are renumbered 0 .. n − 1 in that order; the matrix keeps its upper
// triangle in compressed columns (CHOLMOD's stype = 1).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "curvature/energy_term.h"
#include "optimize/linear/cholesky_factor.h"
#include "optimize/solvers/elimination_order.h"

namespace flexure::optimize {

using curvature::EnergyTerm;
using modeling::Positions;

// How element Hessians enter: as they are (exact), or each projected to its nearest positive
// semidefinite matrix (eigen-decomposition of the small element matrix, negative eigenvalues set
// to zero), which makes the sum positive semidefinite away from minimizers.
enum class HessianProjection { Exact, PositiveSemidefinite };

struct HessianEvaluation {
  double energy = 0.0;         // E at the point
  Eigen::VectorXd gradient;    // n: ∂E over the free unknowns
  std::vector<double> values;  // the upper triangle's entries, in the pattern's order
  // n: Σ_j H_ij d_j over the fixed unknowns j, for a move d of the fixed unknowns (the
  // linearized predictor's right-hand side); empty unless a move was given.
  Eigen::VectorXd fixedCoupling;
};

class HessianAssembly {
 public:
  // `free` has one entry per unknown (3 #V, + #E when a term uses ξ). Builds the pattern.
  HessianAssembly(std::vector<const EnergyTerm*> terms, const std::vector<bool>& free,
                  int vertexCount, curvature::Derivatives derivatives);

  int size() const { return static_cast<int>(freeUnknowns_.size()); }
  // freeUnknowns()[k] = the unknown renumbered k.
  const std::vector<int>& freeUnknowns() const { return freeUnknowns_; }
  const std::vector<int>& columnStart() const { return columnStart_; }
  const std::vector<int>& rowIndex() const { return rowIndex_; }

  // E, ∇E and ∇²E at (x, ξ), on the machine's cores. `fixedMove` (all unknowns; read at the fixed
  // ones) fills fixedCoupling. Throws NumericalError naming a degenerate element.
  // GaussNewton: JᵀJ in place of ∇²E; None: E and ∇E only, `values` empty
  // (curvature/element_hessian.h).
  HessianEvaluation evaluate(
      const Positions& x, const Eigen::VectorXd& xi, HessianProjection projection,
      const Eigen::VectorXd* fixedMove = nullptr,
      curvature::SecondDerivatives kind = curvature::SecondDerivatives::Exact) const;

  // Which free vertices each element reads (nodes = vertex indices), for elimination orders.
  const Incidence& freeVertexIncidence() const { return freeVertices_; }

 private:
  std::vector<const EnergyTerm*> terms_;
  curvature::Derivatives derivatives_;
  int vertexCount_;
  std::vector<int> freeUnknowns_, newIndex_;  // newIndex_[unknown] = k, or −1 when fixed
  std::vector<int> columnStart_, rowIndex_;
  Incidence freeVertices_;
};

// A sparse Cholesky factorization (CHOLMOD, supernodal) of the assembled Hessian whose symbolic
// analysis — the fill-reducing order and the factor's structure — is computed once, at
// construction, and reused by every numerical factorization.
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

  // Factors H + μ I. false when it is not positive definite (or CHOLMOD fails).
  bool factor(const std::vector<double>& values, double shift = 0.0);
  // H⁻¹ b with the last successful factor.
  Eigen::VectorXd solve(const Eigen::VectorXd& b);

 private:
  struct Cholmod;
  struct Simplicial;
  std::unique_ptr<Cholmod> cholmod_;
  std::unique_ptr<Simplicial> simplicial_;
  const HessianAssembly& assembly_;
};

// The fill-reducing order for `assembly`'s free unknowns: geometric nested dissection of the free
// vertices (elimination_order.h) at `at` when every free unknown is a vertex coordinate; empty
// (CHOLMOD's nested dissection, HessianFactorization) when a ξ is free.
std::vector<int> hessianOrder(const HessianAssembly& assembly, const Positions& at);

}  // namespace flexure::optimize
