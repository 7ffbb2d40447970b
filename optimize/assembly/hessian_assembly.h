// The exact Hessian of a sum of energy terms, assembled from the element Hessians
// (curvature/element_hessian.h) into one sparse symmetric matrix over the free unknowns
// (solvers/hessian_factorization.h factors it).
//
// Unknowns are those of energy_evaluation.h: 3v + c for coordinate c of vertex v, then 3 #V + e
// for ξ_e. The free ones are renumbered 0 .. n − 1 in that order; the matrix keeps its upper
// triangle in compressed columns (CHOLMOD's stype = 1).
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "curvature/energy_term.h"
#include "optimize/assembly/incidence.h"

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
  // `free` has one entry per unknown (3 #V, + #E when a term uses ξ). Builds the pattern: the
  // pairs of free unknowns an element reads, and the 6 × 6 blocks of each vertex pair in
  // `vertexCouplings` (pairs that no element couples, e.g. the self-contact's, contact/; they
  // enter the pattern only, evaluate assembles none of their entries).
  HessianAssembly(std::vector<const EnergyTerm*> terms, const std::vector<bool>& free,
                  int vertexCount, curvature::Derivatives derivatives,
                  const std::vector<std::array<int, 2>>& vertexCouplings = {});

  int size() const { return static_cast<int>(freeUnknowns_.size()); }
  // freeUnknowns()[k] = the unknown renumbered k.
  const std::vector<int>& freeUnknowns() const { return freeUnknowns_; }
  const std::vector<int>& columnStart() const { return columnStart_; }
  const std::vector<int>& rowIndex() const { return rowIndex_; }
  // The entry of the upper triangle's (row p ≤ column q) in the pattern's order, −1 when absent.
  int entry(int p, int q) const;

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

}  // namespace flexure::optimize
