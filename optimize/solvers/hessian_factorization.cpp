#include "optimize/solvers/hessian_factorization.h"

#include <Eigen/SparseCholesky>

#include "optimize/linear/elimination_order.h"

namespace flexure::optimize {

struct HessianFactorization::Cholmod {
  CholeskyFactor factor;
};

struct HessianFactorization::Simplicial {
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  std::vector<int> columnStart, rowIndex;
  Eigen::SimplicialLLT<Matrix, Eigen::Upper, Eigen::AMDOrdering<int>> llt;

  Eigen::Map<const Matrix> matrix(const double* values) const {
    const int n = static_cast<int>(columnStart.size()) - 1;
    return {n, n, static_cast<int>(rowIndex.size()), columnStart.data(), rowIndex.data(), values};
  }
};

namespace {

// Supernodal; a matrix that is not positive definite is an answer here (Newton's
// indefinite-Hessian rule), not a warning.
CholeskyOptions hessianCholeskyOptions(FillReducingOrder computed) {
  CholeskyOptions options;
  options.matrix = CholeskyMatrix::SymmetricUpper;
  options.supernodal = true;
  options.stopAtNonPositivePivot = true;
  options.cholmodWarnings = false;
  options.ordering = computed;
  return options;
}

}  // namespace

HessianFactorization::HessianFactorization(const HessianAssembly& assembly,
                                           const std::vector<int>& order,
                                           FillReducingOrder computed, bool simplicial)
    : cholmod_(
          new Cholmod{CholeskyFactor(assembly.size(), assembly.columnStart(), assembly.rowIndex(),
                                     order, hessianCholeskyOptions(computed))}) {
  if (simplicial) {
    simplicial_ = std::make_unique<Simplicial>();
    simplicial_->columnStart = assembly.columnStart();
    simplicial_->rowIndex = assembly.rowIndex();
    const std::vector<double> ones(simplicial_->rowIndex.size(), 1.0);
    simplicial_->llt.analyzePattern(simplicial_->matrix(ones.data()));
  }
}

HessianFactorization::~HessianFactorization() = default;

bool HessianFactorization::serves(const HessianAssembly& assembly) const {
  if (simplicial_)
    return simplicial_->columnStart == assembly.columnStart() &&
           simplicial_->rowIndex == assembly.rowIndex();
  return cholmod_->factor.columnStart() == assembly.columnStart() &&
         cholmod_->factor.rowIndex() == assembly.rowIndex();
}

bool HessianFactorization::factor(const std::vector<double>& values, double shift) {
  if (simplicial_) {
    simplicial_->llt.setShift(shift);
    simplicial_->llt.factorize(simplicial_->matrix(values.data()));
    return simplicial_->llt.info() == Eigen::Success;
  }
  return cholmod_->factor.factor(values.data(), shift);
}

Eigen::VectorXd HessianFactorization::solve(const Eigen::VectorXd& b) {
  if (simplicial_) return simplicial_->llt.solve(b);
  return cholmod_->factor.solve(b);
}

std::vector<int> hessianOrder(const HessianAssembly& assembly, const Positions& at) {
  const std::vector<int>& unknowns = assembly.freeUnknowns();
  if (unknowns.empty() || unknowns.back() >= 3 * at.rows()) return {};
  // Nodes: the free vertices in index order, as the assembly numbered them.
  std::vector<Eigen::Vector3d> points;
  std::vector<int> firstUnknown;
  for (int k = 0; k < static_cast<int>(unknowns.size()); ++k) {
    if (k > 0 && unknowns[k] / 3 == unknowns[k - 1] / 3) continue;
    points.emplace_back(at.row(unknowns[k] / 3).transpose());
    firstUnknown.push_back(k);
  }
  firstUnknown.push_back(static_cast<int>(unknowns.size()));
  std::vector<int> order;
  order.reserve(unknowns.size());
  for (int node : geometricNestedDissection(points, assembly.freeVertexIncidence()))
    for (int k = firstUnknown[node]; k < firstUnknown[node + 1]; ++k) order.push_back(k);
  return order;
}

}  // namespace flexure::optimize
