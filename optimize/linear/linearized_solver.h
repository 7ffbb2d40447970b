// The linearized energy's minimizer as a precompute/solve pair (libigl's
// min_quad_with_fixed_precompute / _solve): E_lin(u) = ½ |J u + r0|² over the unknowns u, J the
// residual Jacobian at rest (energy_evaluation.h), the free unknowns solved for and the fixed ones
// given. The normal matrix J_freeᵀ J_free depends only on J and on which unknowns are free, so it
// is ordered and factored once; every solve (a new set of boundary values) is then one pair of
// triangular solves. u = (X − X̄, ξ − ξ̄): vertex displacements row by row (3 #V), then the
// midedge ξ (#E) when a term uses them.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "optimize/assembly/energy_evaluation.h"
#include "optimize/boundary_conditions.h"

namespace flexure::optimize {

class CholeskyFactor;

// Which unknowns a linearized solve leaves free.
struct LinearizedUnknowns {
  std::vector<bool> fixedVertex;  // #V
  std::vector<bool> fixedEdge;    // #E: held ξ (ignored when no term uses ξ)
  bool heightOnly = true;         // the free vertices move in z only (height field)
  // Whether the fixed vertices' boundary values may move them in x or y. false with heightOnly:
  // J's x and y columns would multiply only zeros, so they are not evaluated.
  bool fixedMoveInPlane = false;
};

// The free mask over the unknowns (3 #V, then the first `edgeCount` ξ; 0 when no term uses ξ)
// that `unknowns` leaves free: boundary_conditions.h's freeUnknownMask of its held sets.
std::vector<bool> freeUnknownMask(const LinearizedUnknowns& unknowns, int edgeCount);

// The minimizer of a linearized solve and its energies.
struct LinearizedSolution {
  Positions positions;         // #V by 3: X̄ + the displacement
  Eigen::VectorXd xi;          // #E: ξ̄ + δξ when a term uses ξ, else empty
  double initialEnergy = 0.0;  // E_lin of the boundary values with the free unknowns at rest
  double energy = 0.0;         // E_lin of the minimizer
  double gradientNorm = 0.0;   // |Jᵀ J u| over the free unknowns (2-norm)
  // The same at the start (the free unknowns at rest, the fixed ones at their values): the
  // scale a solve's remaining gradient is judged against.
  double initialGradientNorm = 0.0;
};

class LinearizedSolver {
 public:
  // From a residual Jacobian: `free` has one entry per column of J; `at` (#V by 3) places the
  // vertices for the elimination order. When every free unknown is a vertex coordinate the order
  // is the geometric nested dissection of the free vertices (elimination_order.h); when a ξ is
  // free, CHOLMOD's AMD, which leaves less fill there (the .cpp). CHOLMOD factors
  // J_freeᵀ J_free + β I from J_freeᵀ itself, without forming the normal matrix; the ridge β,
  // 1e-13 of its mean diagonal, keeps it defined where Ψ_ν ignores some ξ (e.g. ν = 1).
  // Throws NumericalError when the matrix cannot be factored (a null space of J_free).
  // `jacobian` is kept by reference and must outlive the solver; `restXi` (#E, when J has ξ
  // columns) is needed by solve(bc) only.
  LinearizedSolver(const SparseMatrix& jacobian, const std::vector<bool>& free, const Positions& at,
                   const Eigen::VectorXd& restXi = Eigen::VectorXd());
  LinearizedSolver(SparseMatrix&& jacobian, const std::vector<bool>& free, const Positions& at,
                   const Eigen::VectorXd& restXi = Eigen::VectorXd()) = delete;
  // From the terms: J at (rest, restXi) over the unknowns `unknowns` leaves free.
  LinearizedSolver(const std::vector<const EnergyTerm*>& terms, const Positions& rest,
                   const Eigen::VectorXd& restXi, const LinearizedUnknowns& unknowns);
  ~LinearizedSolver();
  LinearizedSolver(const LinearizedSolver&) = delete;
  LinearizedSolver& operator=(const LinearizedSolver&) = delete;

  // argmin over the free entries of ½ |J u + r0|², the fixed entries of `u` kept; `r0` may be
  // empty (zero).
  Eigen::VectorXd solve(Eigen::VectorXd u, const Eigen::VectorXd& r0 = Eigen::VectorXd()) const;
  // The minimizer for boundary conditions (fixed vertices at bc.start, held ξ at bc.xi; the
  // masks must be those of the precompute: InputError otherwise). Needs the terms' constructor.
  LinearizedSolution solve(const BoundaryConditions& bc) const;

  double energy(const Eigen::VectorXd& u) const;  // ½ |J u|²
  const SparseMatrix& jacobian() const { return *jacobian_; }
  const std::vector<bool>& free() const { return free_; }
  int freeCount() const { return static_cast<int>(freeColumns_.size()); }
  // Numerical factorizations made (the ridge's retries included): 1 when the first succeeded.
  int factorizations() const;
  // Wall-clock seconds of the precompute: evaluating J (terms' constructor only), and ordering,
  // analyzing and factoring J_freeᵀ J_free.
  double jacobianSeconds() const { return jacobianSeconds_; }
  double factorSeconds() const { return factorSeconds_; }

 private:
  // Renumbers the free unknowns, orders, analyzes and factors J_freeᵀ J_free (+ β I).
  void precompute(const std::vector<bool>& free, const Positions& at);

  SparseMatrix ownJacobian_;  // the terms' constructor's J
  const SparseMatrix* jacobian_ = &ownJacobian_;
  std::vector<bool> free_;
  std::vector<int> freeColumns_, newIndex_;
  // J_freeᵀ's entries in compressed columns (its pattern is the factor's): column r = the free
  // entries of J's row r, renumbered.
  std::vector<double> values_;
  std::unique_ptr<CholeskyFactor> factor_;
  Positions rest_;
  Eigen::VectorXd restXi_;
  bool checkInPlane_ = false;  // solve(bc) refuses fixed x, y moves J was not evaluated for
  double jacobianSeconds_ = 0.0, factorSeconds_ = 0.0;
  // |Jᵀ J u| over the free unknowns.
  double freeGradientNorm(const Eigen::VectorXd& u) const;
  // InputError when `bc` holds other unknowns (or has other sizes) than the factored masks.
  void requireFactoredMasks(const BoundaryConditions& bc) const;
};

}  // namespace flexure::optimize
