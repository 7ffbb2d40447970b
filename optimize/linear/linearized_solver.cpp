#include "optimize/linear/linearized_solver.h"

#include <chrono>
#include <cmath>

#include "modeling/errors.h"
#include "optimize/linear/cholesky_factor.h"
#include "optimize/linear/elimination_order.h"

namespace flexure::optimize {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The free unknowns' elimination order when they are all vertex coordinates: geometric nested
// dissection of the vertices (a vertex's free coordinates together, at its position `at`);
// order[k] = the renumbered free unknown eliminated k-th. Empty when a midedge ξ is free: there
// CHOLMOD's AMD leaves less fill — the one-sided geometric separators hold every node of a band
// as wide as the midedge stencil, 4× the nodes per length of a vertex energy's (n = 128, with ξ
// placed around their edges, measured before the cut kept ties on one side: factor nonzeros
// 1.1e7 geometric vs 4.6e6 AMD, where cotan's were 1.65e6 vs 1.9e6).
std::vector<int> eliminationOrder(const SparseMatrix& jacobian, const std::vector<int>& freeColumns,
                                  const std::vector<int>& newIndex, const Positions& at) {
  const int positionCount = static_cast<int>(at.size());
  if (freeColumns.back() >= positionCount) return {};
  std::vector<int> nodeOf(freeColumns.size()), firstUnknown, vertexNode(at.rows(), -1);
  std::vector<Eigen::Vector3d> points;
  for (size_t k = 0; k < freeColumns.size(); ++k) {
    const int v = freeColumns[k] / 3;
    if (vertexNode[v] < 0) {
      vertexNode[v] = static_cast<int>(points.size());
      firstUnknown.push_back(static_cast<int>(k));
      points.emplace_back(at.row(v).transpose());
    }
    nodeOf[k] = vertexNode[v];
  }
  firstUnknown.push_back(static_cast<int>(freeColumns.size()));
  // An element's residuals (up to three rows) read the same nodes: each such set enters once.
  Incidence incidence;
  std::vector<int> read, previous;
  for (int row = 0; row < jacobian.outerSize(); ++row) {
    for (SparseMatrix::InnerIterator it(jacobian, row); it; ++it)
      if (newIndex[it.col()] >= 0) read.push_back(nodeOf[newIndex[it.col()]]);
    if (read != previous) {
      previous = read;
      incidence.append(read);
    }
    read.clear();
  }
  std::vector<int> order;
  order.reserve(freeColumns.size());
  for (int node : geometricNestedDissection(points, incidence))
    for (int k = firstUnknown[node]; k < firstUnknown[node + 1]; ++k) order.push_back(k);
  return order;
}

// CHOLMOD's choice of simplicial or supernodal by the fill, and its warnings on: as the
// least-squares solve has always run.
CholeskyOptions gramCholeskyOptions() {
  CholeskyOptions options;
  options.matrix = CholeskyMatrix::Gram;
  options.supernodal = false;
  options.sortedColumns = false;
  return options;
}

}  // namespace

std::vector<bool> freeUnknownMask(const LinearizedUnknowns& unknowns, int edgeCount) {
  const std::vector<bool> heldEdge(unknowns.fixedEdge.begin(),
                                   unknowns.fixedEdge.begin() + edgeCount);
  return freeUnknownMask(unknowns.fixedVertex, heldEdge,
                         unknowns.heightOnly ? DofMode::Height : DofMode::Xyz);
}

LinearizedSolver::LinearizedSolver(const SparseMatrix& jacobian, const std::vector<bool>& free,
                                   const Positions& at, const Eigen::VectorXd& restXi)
    : jacobian_(&jacobian), restXi_(restXi) {
  precompute(free, at);
}

LinearizedSolver::LinearizedSolver(const std::vector<const EnergyTerm*>& terms,
                                   const Positions& rest, const Eigen::VectorXd& restXi,
                                   const LinearizedUnknowns& unknowns) {
  const auto start = Clock::now();
  checkInPlane_ = unknowns.heightOnly && !unknowns.fixedMoveInPlane;
  ownJacobian_ = residualJacobian(
      terms, rest, restXi,
      checkInPlane_ ? curvature::Derivatives::HeightOnly : curvature::Derivatives::All);
  jacobianSeconds_ = secondsSince(start);
  const bool withXi = usesEdgeUnknowns(terms);
  if (withXi) restXi_ = restXi;
  precompute(freeUnknownMask(unknowns, withXi ? static_cast<int>(restXi.size()) : 0), rest);
}

void LinearizedSolver::precompute(const std::vector<bool>& free, const Positions& at) {
  free_ = free;
  newIndex_.assign(free.size(), -1);
  rest_ = at;
  for (int c = 0; c < static_cast<int>(free.size()); ++c)
    if (free[c]) freeColumns_.push_back(c);
  if (freeColumns_.empty()) return;
  const auto start = Clock::now();
  const int freeCount = static_cast<int>(freeColumns_.size());
  for (int k = 0; k < freeCount; ++k) newIndex_[freeColumns_[k]] = k;
  // J is stored by rows, and its rows are the columns of J_freeᵀ.
  std::vector<int> columnStart(jacobian_->rows() + 1, 0), rowIndex;
  rowIndex.reserve(jacobian_->nonZeros());
  values_.reserve(jacobian_->nonZeros());
  double squaredSum = 0.0;  // the trace of J_freeᵀ J_free
  for (int row = 0; row < jacobian_->outerSize(); ++row) {
    for (SparseMatrix::InnerIterator it(*jacobian_, row); it; ++it) {
      const int k = newIndex_[it.col()];
      if (k < 0) continue;
      rowIndex.push_back(k);
      values_.push_back(it.value());
      squaredSum += it.value() * it.value();
    }
    columnStart[row + 1] = static_cast<int>(rowIndex.size());
  }
  factor_ = std::make_unique<CholeskyFactor>(
      freeCount, std::move(columnStart), std::move(rowIndex),
      eliminationOrder(*jacobian_, freeColumns_, newIndex_, at), gramCholeskyOptions());
  // β = 1e-13 of the mean diagonal; when rounding still leaves a pivot ≤ 0 (a null space of J, a
  // system near singular; how near depends on the BLAS's order of operations), β × 1000, twice.
  bool factored = false;
  double relativeRidge = 1e-13;
  for (int attempt = 0; !factored && attempt < 3; ++attempt, relativeRidge *= 1e3)
    factored = factor_->factor(values_.data(), relativeRidge * squaredSum / freeCount);
  if (!factored)
    throw NumericalError("the least-squares solve for the free unknowns failed (singular system: " +
                         factor_->failure() + ")");
  factorSeconds_ = secondsSince(start);
}

LinearizedSolver::~LinearizedSolver() = default;

int LinearizedSolver::factorizations() const {
  return factor_ ? factor_->factorizations() : 0;
}

Eigen::VectorXd LinearizedSolver::solve(Eigen::VectorXd u, const Eigen::VectorXd& r0) const {
  if (freeColumns_.empty()) return u;
  const int freeCount = static_cast<int>(freeColumns_.size());
  Eigen::VectorXd fixedPart = u;
  for (int c : freeColumns_) fixedPart[c] = 0.0;
  Eigen::VectorXd rhs = *jacobian_ * fixedPart;
  if (r0.size() > 0) rhs += r0;
  // The normal equations' right-hand side −J_freeᵀ (J u_fixed + r0), row by row of J.
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(freeCount);
  const std::vector<int>& columnStart = factor_->columnStart();
  const std::vector<int>& rowIndex = factor_->rowIndex();
  for (size_t row = 0; row + 1 < columnStart.size(); ++row)
    for (int entry = columnStart[row]; entry < columnStart[row + 1]; ++entry)
      gradient[rowIndex[entry]] += values_[entry] * rhs[static_cast<Eigen::Index>(row)];
  gradient = -gradient;
  const Eigen::VectorXd step = factor_->solve(gradient);
  if (step.size() != freeCount || !step.allFinite())
    throw NumericalError("the least-squares solve for the free unknowns failed (singular system)");
  for (int k = 0; k < freeCount; ++k) u[freeColumns_[k]] = step[k];
  return u;
}

// The held vertices and ξ of `bc` must be those the solver was factored for.
void LinearizedSolver::requireFactoredMasks(const BoundaryConditions& bc) const {
  const int vertexCount = static_cast<int>(rest_.rows());
  const bool sizes =
      bc.start.rows() == vertexCount && static_cast<int>(bc.fixedVertex.size()) == vertexCount &&
      (restXi_.size() == 0 ||
       (bc.xi.size() == restXi_.size() && bc.fixedEdge.size() == size_t(restXi_.size())));
  bool same = sizes;
  for (int v = 0; same && v < vertexCount; ++v) same = free_[3 * v + 2] == !bc.fixedVertex[v];
  for (Eigen::Index e = 0; same && e < restXi_.size(); ++e)
    same = free_[3 * vertexCount + e] == !bc.fixedEdge[e];
  if (!same) {
    throw InputError(
        "linearized solve: the boundary conditions hold other vertices or ξ (or have other sizes) "
        "than the solver was factored for; precompute a solver for them");
  }
}

LinearizedSolution LinearizedSolver::solve(const BoundaryConditions& bc) const {
  requireFactoredMasks(bc);
  const int positionCount = static_cast<int>(rest_.size());
  const Positions displacement = bc.start - rest_;
  if (checkInPlane_ && displacement.leftCols(2).cwiseAbs().maxCoeff() != 0.0)
    throw InputError(
        "linearized solve: the boundary values move vertices in x or y, which a height-field "
        "solve precomputed without LinearizedUnknowns.fixedMoveInPlane cannot represent");
  Eigen::VectorXd u = Eigen::VectorXd::Zero(jacobian_->cols());
  u.head(positionCount) = Eigen::Map<const Eigen::VectorXd>(displacement.data(), positionCount);
  if (restXi_.size() > 0) u.tail(restXi_.size()) = bc.xi - restXi_;
  LinearizedSolution out;
  out.initialEnergy = energy(u);
  Eigen::VectorXd atRest = u;  // the free unknowns at rest
  for (int c : freeColumns_) atRest[c] = 0.0;
  out.initialGradientNorm = freeGradientNorm(atRest);
  u = solve(u);
  out.energy = energy(u);
  out.gradientNorm = freeGradientNorm(u);
  out.positions = rest_ + Eigen::Map<const Positions>(u.data(), rest_.rows(), 3);
  if (restXi_.size() > 0) out.xi = restXi_ + u.tail(restXi_.size());
  return out;
}

double LinearizedSolver::freeGradientNorm(const Eigen::VectorXd& u) const {
  const Eigen::VectorXd gradient = jacobian_->transpose() * (*jacobian_ * u);
  double squared = 0.0;
  for (int k = 0; k < gradient.size(); ++k)
    if (free_[k]) squared += gradient[k] * gradient[k];
  return std::sqrt(squared);
}

double LinearizedSolver::energy(const Eigen::VectorXd& u) const {
  return linearizedEnergy(*jacobian_, u);
}

}  // namespace flexure::optimize
