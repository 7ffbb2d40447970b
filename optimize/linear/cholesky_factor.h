// The one sparse Cholesky factorization of flexure (CHOLMOD): the symbolic analysis of a pattern
// — the fill-reducing order and the factor's structure — once, then numerical factorizations of
// matrices with that pattern, each optionally shifted by β I, and solves with the last one.
// libigl's min_quad_with_fixed_precompute / _solve split, for any symmetric positive definite
// matrix of flexure: a Hessian, K − σM, or the normal matrix A Aᵀ of a least-squares problem.
//
// Every CHOLMOD call is made under SingleThreadedLinearAlgebra (linear_algebra_threads.h).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace flexure::optimize {

// Which matrix the compressed columns describe.
enum class CholeskyMatrix {
  // A symmetric n by n matrix of which CHOLMOD reads the upper triangle (entries below the
  // diagonal may be present and are ignored): stype = 1.
  SymmetricUpper,
  // A, n by m (m columns, often m > n): the factor is of A Aᵀ (+ β I), computed from A without
  // forming A Aᵀ. For least squares min |J u − b|², A = Jᵀ.
  Gram,
};

// CHOLMOD's fill-reducing orders, for a factor given no order of its own.
enum class FillReducingOrder {
  Amd,               // approximate minimum degree
  Metis,             // METIS' nested dissection (METIS_NodeND)
  NestedDissection,  // CHOLMOD's nested dissection (METIS partitions, constrained minimum degree)
};

struct CholeskyOptions {
  CholeskyMatrix matrix = CholeskyMatrix::SymmetricUpper;
  // Supernodal (BLAS on dense blocks), or CHOLMOD's choice between simplicial and supernodal by
  // the factor's density (CHOLMOD_AUTO).
  bool supernodal = true;
  // On a non-positive pivot stop at once (the factor is then unusable until the next success);
  // false: CHOLMOD's default, which completes the symbolic structure first.
  bool stopAtNonPositivePivot = false;
  // CHOLMOD's own warnings on stdout (its default), e.g. "not positive definite"; false: none,
  // where a failed factorization is an answer (Newton's indefinite-Hessian rule, a ridge retry).
  bool cholmodWarnings = true;
  // Whether the row indices of each column are sorted (CHOLMOD sorts a copy when not).
  bool sortedColumns = true;
  // The order CHOLMOD computes when the constructor is given none.
  FillReducingOrder ordering = FillReducingOrder::Amd;
};

class CholeskyFactor {
 public:
  // The pattern: `rows` rows and columnStart.size() − 1 columns, column j holding rows
  // rowIndex[columnStart[j] .. columnStart[j + 1]). `order`: the elimination order of
  // the n unknowns (order[k] = the unknown eliminated k-th), or empty for CHOLMOD's
  // options.ordering — one ordering method, never AMD then METIS. Throws NumericalError when the
  // analysis fails.
  CholeskyFactor(int rows, std::vector<int> columnStart, std::vector<int> rowIndex,
                 const std::vector<int>& order, const CholeskyOptions& options);
  ~CholeskyFactor();
  CholeskyFactor(const CholeskyFactor&) = delete;
  CholeskyFactor& operator=(const CholeskyFactor&) = delete;

  int size() const;  // n, the unknowns of a solve
  // The factor's nonzeros, nnz(L), as the analysis counted them.
  double factorNonzeros() const { return factorNonzeros_; }
  // The pattern as given.
  const std::vector<int>& columnStart() const;
  const std::vector<int>& rowIndex() const;

  // Factors the matrix with these entries (one per pattern entry, in the pattern's order) plus
  // shift × I. false when it is not positive definite or CHOLMOD fails: failure() says which.
  bool factor(const double* values, double shift = 0.0);
  // M⁻¹ b with the last successful factor. Throws NumericalError when CHOLMOD fails.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

  // Why the last factorization failed ("" after a success).
  const std::string& failure() const { return failure_; }
  // Numerical factorizations so far (the failed ones included).
  int factorizations() const { return factorizations_; }

 private:
  struct Cholmod;
  std::unique_ptr<Cholmod> cholmod_;
  CholeskyOptions options_;
  std::string failure_;
  int factorizations_ = 0;
  double factorNonzeros_ = 0.0;
};

}  // namespace flexure::optimize
