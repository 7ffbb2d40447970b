#include "optimize/linear/cholesky_factor.h"

#include <cholmod.h>

#include "modeling/errors.h"
#include "optimize/linear/cholmod_view.h"
#include "optimize/linear/linear_algebra_threads.h"

namespace flexure::optimize {

struct CholeskyFactor::Cholmod {
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  size_t rows = 0;
  std::vector<int> columnStart, rowIndex;  // the pattern, which CHOLMOD views as non-const

  cholmod_sparse view(const CholeskyOptions& options, double* values) {
    cholmod_sparse matrix = cholmodView(rows, columnStart, rowIndex, values, options.sortedColumns);
    if (options.matrix == CholeskyMatrix::SymmetricUpper) matrix.stype = 1;
    return matrix;
  }
};

namespace {

std::string statusMessage(const cholmod_common& common, const cholmod_factor* factor) {
  switch (common.status) {
    case CHOLMOD_NOT_POSDEF:
      return "the matrix is not positive definite (a pivot ≤ 0 at unknown " +
             (factor != nullptr ? std::to_string(factor->minor) : "?") +
             " of the elimination order)";
    case CHOLMOD_OUT_OF_MEMORY:
      return "out of memory";
    case CHOLMOD_TOO_LARGE:
      return "the factor is too large for CHOLMOD's integers";
    default:
      return "CHOLMOD status " + std::to_string(common.status);
  }
}

int cholmodOrdering(FillReducingOrder ordering) {
  switch (ordering) {
    case FillReducingOrder::Metis:
      return CHOLMOD_METIS;
    case FillReducingOrder::NestedDissection:
      return CHOLMOD_NESDIS;
    case FillReducingOrder::Amd:
      break;
  }
  return CHOLMOD_AMD;
}

}  // namespace

CholeskyFactor::CholeskyFactor(int rows, std::vector<int> columnStart, std::vector<int> rowIndex,
                               const std::vector<int>& order, const CholeskyOptions& options)
    : cholmod_(std::make_unique<Cholmod>()), options_(options) {
  Cholmod& c = *cholmod_;
  c.rows = static_cast<size_t>(rows);
  c.columnStart = std::move(columnStart);
  c.rowIndex = std::move(rowIndex);
  const SingleThreadedLinearAlgebra oneThread;
  cholmod_start(&c.common);
  if (options.supernodal) c.common.supernodal = CHOLMOD_SUPERNODAL;
  if (options.stopAtNonPositivePivot) c.common.quick_return_if_not_posdef = 1;
  if (!options.cholmodWarnings) c.common.print = 0;
  // One ordering, not CHOLMOD's default of AMD and then METIS when AMD's fill is high: METIS on
  // A Aᵀ took 2.8 s of the n = 512 cotan least-squares solve's 7.5 and 16 s of midedge's 34.6.
  c.common.nmethods = 1;
  c.common.method[0].ordering = order.empty() ? cholmodOrdering(options.ordering) : CHOLMOD_GIVEN;
  cholmod_sparse pattern = c.view(options, nullptr);
  std::vector<int> given = order;
  c.factor =
      cholmod_analyze_p(&pattern, given.empty() ? nullptr : given.data(), nullptr, 0, &c.common);
  if (c.factor == nullptr) {
    const std::string why = statusMessage(c.common, nullptr);
    cholmod_finish(&c.common);
    throw NumericalError("the sparse Cholesky analysis failed (" + why + ")");
  }
  factorNonzeros_ = c.common.lnz;
}

CholeskyFactor::~CholeskyFactor() {
  const SingleThreadedLinearAlgebra oneThread;
  cholmod_free_factor(&cholmod_->factor, &cholmod_->common);
  cholmod_finish(&cholmod_->common);
}

int CholeskyFactor::size() const {
  return static_cast<int>(cholmod_->factor->n);
}

const std::vector<int>& CholeskyFactor::columnStart() const {
  return cholmod_->columnStart;
}

const std::vector<int>& CholeskyFactor::rowIndex() const {
  return cholmod_->rowIndex;
}

bool CholeskyFactor::factor(const double* values, double shift) {
  Cholmod& c = *cholmod_;
  cholmod_sparse matrix = c.view(options_, const_cast<double*>(values));
  double beta[2] = {shift, 0.0};  // β (real, imaginary)
  const SingleThreadedLinearAlgebra oneThread;
  ++factorizations_;
  const int ok = cholmod_factorize_p(&matrix, beta, nullptr, 0, c.factor, &c.common);
  const bool factored = ok && c.common.status == CHOLMOD_OK && c.factor->minor == c.factor->n;
  failure_ = factored ? "" : statusMessage(c.common, c.factor);
  return factored;
}

Eigen::VectorXd CholeskyFactor::solve(const Eigen::VectorXd& b) const {
  Cholmod& c = *cholmod_;
  Eigen::VectorXd rhs = b;
  cholmod_dense view{};
  view.nrow = view.d = view.nzmax = static_cast<size_t>(rhs.size());
  view.ncol = 1;
  view.x = rhs.data();
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  const SingleThreadedLinearAlgebra oneThread;
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, c.factor, &view, &c.common);
  if (x == nullptr)
    throw NumericalError("the sparse Cholesky solve failed (" + statusMessage(c.common, c.factor) +
                         ")");
  Eigen::VectorXd out = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(x->x), rhs.size());
  cholmod_free_dense(&x, &c.common);
  return out;
}

}  // namespace flexure::optimize
