#include "optimize/solvers/energy_evaluation.h"

#include <ceres/problem.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>

#include "modeling/errors.h"
#include "optimize/linear/cholmod_view.h"
#include "optimize/linear/linear_algebra_threads.h"
#include "optimize/solvers/elimination_order.h"

namespace flexure::optimize {
namespace {

// Threads for evaluating energies and Jacobians: the machine's cores (flexure's targets have 2).
int evaluationThreads() {
  return std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, 16);
}

// A Ceres problem over copies of x and ξ holding every term's residuals.
struct AssembledProblem {
  Positions x;
  Eigen::VectorXd xi;
  ceres::Problem problem;

  AssembledProblem(const std::vector<const EnergyTerm*>& terms, const Positions& positions,
                   const Eigen::VectorXd& edgeUnknowns)
      : x(positions), xi(edgeUnknowns) {
    for (int v = 0; v < x.rows(); ++v) problem.AddParameterBlock(x.data() + 3 * v, 3);
    if (usesEdgeUnknowns(terms)) {
      for (int e = 0; e < xi.size(); ++e) problem.AddParameterBlock(xi.data() + e, 1);
    }
    for (const EnergyTerm* term : terms)
      term->addResidualBlocks(problem, x.data(), xi.data(), curvature::Derivatives::All);
  }

  // No explicit parameter_blocks: Ceres then orders the unknowns as the blocks were added, which
  // is the unknown order above, and skips a costly lookup per block on every call.
  ceres::Problem::EvaluateOptions options() const {
    ceres::Problem::EvaluateOptions o;
    o.apply_loss_function = false;
    o.num_threads = evaluationThreads();
    return o;
  }
};

}  // namespace

bool usesEdgeUnknowns(const std::vector<const EnergyTerm*>& terms) {
  return std::any_of(terms.begin(), terms.end(),
                     [](const EnergyTerm* t) { return t->usesEdgeUnknowns(); });
}

EnergyGradient energyGradient(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                              const Eigen::VectorXd& xi) {
  AssembledProblem assembled(terms, x, xi);
  EnergyGradient out;
  std::vector<double> gradient;
  if (!assembled.problem.Evaluate(assembled.options(), &out.energy, nullptr, &gradient, nullptr)) {
    throw NumericalError(
        "the energy or its gradient is undefined at this configuration (a "
        "degenerate element)");
  }
  out.gradient =
      Eigen::Map<Eigen::VectorXd>(gradient.data(), static_cast<Eigen::Index>(gradient.size()));
  return out;
}

namespace {

// The stacked residuals r and their Jacobian J at (x, ξ), element by element without a Ceres
// problem. Assembling one and having Ceres write its Jacobian as CRS took, for the rest Jacobian
// of the n = 512 patch in bench/solve_bench (linearized "evaluation"), hinge 3.5 s, cotan 2.7,
// quadfit 7.7, midedge 10; this took 1.3, 1.7, 4.4 and 5.6 s on one thread, and takes 0.5, 0.4,
// 1.0 and 1.4 s on two threads with height-mode derivatives (separate runs of the benchmark).
// Each term's elements are split into one contiguous range per thread; the ranges' rows are
// concatenated in element order, so J does not depend on the thread count.
struct Linearization {
  Eigen::VectorXd residuals;
  SparseMatrix jacobian;
};

Linearization linearize(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                        const Eigen::VectorXd& xi, curvature::Derivatives derivatives) {
  struct Range {
    const EnergyTerm* term;
    int begin, end;
    curvature::JacobianRows rows;
    std::exception_ptr error;
  };
  const int threads = evaluationThreads();
  std::vector<Range> ranges;
  for (const EnergyTerm* term : terms) {
    const long count = term->elementCount();
    for (int t = 0; t < threads; ++t)
      ranges.push_back({term,
                        static_cast<int>(count * t / threads),
                        static_cast<int>(count * (t + 1) / threads),
                        {},
                        nullptr});
  }
  std::atomic<size_t> next{0};
  const auto work = [&] {
    for (size_t k = next++; k < ranges.size(); k = next++) {
      Range& range = ranges[k];
      try {
        range.term->appendJacobianRows(x, xi, range.begin, range.end, derivatives, range.rows);
      } catch (...) {
        range.error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work);
  work();
  for (std::thread& helper : helpers) helper.join();
  for (const Range& range : ranges)
    if (range.error) std::rethrow_exception(range.error);  // the first degenerate element

  Eigen::Index rowCount = 0, entryCount = 0;
  for (const Range& range : ranges) {
    rowCount += static_cast<Eigen::Index>(range.rows.residuals.size());
    entryCount += static_cast<Eigen::Index>(range.rows.values.size());
  }
  const Eigen::Index columnCount = 3 * x.rows() + (usesEdgeUnknowns(terms) ? xi.size() : 0);
  Linearization out;
  out.residuals.resize(rowCount);
  out.jacobian.resize(rowCount, columnCount);
  out.jacobian.resizeNonZeros(entryCount);
  int* rowStart = out.jacobian.outerIndexPtr();
  rowStart[0] = 0;
  Eigen::Index row = 0;
  int entry = 0;
  for (const Range& range : ranges) {
    const curvature::JacobianRows& part = range.rows;
    std::copy(part.columns.begin(), part.columns.end(), out.jacobian.innerIndexPtr() + entry);
    std::copy(part.values.begin(), part.values.end(), out.jacobian.valuePtr() + entry);
    for (size_t k = 0; k < part.residuals.size(); ++k, ++row) {
      out.residuals[row] = part.residuals[k];
      rowStart[row + 1] = entry + part.rowStart[k + 1];
    }
    entry += static_cast<int>(part.values.size());
  }
  return out;
}

}  // namespace

SparseMatrix residualJacobian(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                              const Eigen::VectorXd& xi, curvature::Derivatives derivatives) {
  return linearize(terms, x, xi, derivatives).jacobian;
}

namespace {

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

}  // namespace

Eigen::VectorXd minimizeLeastSquares(const SparseMatrix& jacobian, const Eigen::VectorXd& r0,
                                     Eigen::VectorXd u, const std::vector<bool>& free,
                                     const Positions& at) {
  std::vector<int> freeColumns;
  for (int c = 0; c < static_cast<int>(free.size()); ++c)
    if (free[c]) freeColumns.push_back(c);
  if (freeColumns.empty()) return u;
  const int freeCount = static_cast<int>(freeColumns.size());
  Eigen::VectorXd fixedPart = u;
  for (int c : freeColumns) fixedPart[c] = 0.0;
  Eigen::VectorXd rhs = jacobian * fixedPart;
  if (r0.size() > 0) rhs += r0;

  // J_freeᵀ in compressed columns, the free unknowns renumbered: J is stored by rows, and its
  // rows are the columns of Jᵀ. CHOLMOD factors A Aᵀ + β I from A = J_freeᵀ itself, without
  // forming the normal matrix; β is a tiny ridge, 1e-13 of the normal matrix's mean diagonal.
  std::vector<int> newIndex(free.size(), -1);
  for (int k = 0; k < freeCount; ++k) newIndex[freeColumns[k]] = k;
  std::vector<int> columnStart(jacobian.rows() + 1, 0), rowIndex;
  std::vector<double> values;
  rowIndex.reserve(jacobian.nonZeros());
  values.reserve(jacobian.nonZeros());
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(freeCount);  // J_freeᵀ rhs
  double squaredSum = 0.0;
  for (int row = 0; row < jacobian.outerSize(); ++row) {
    for (SparseMatrix::InnerIterator it(jacobian, row); it; ++it) {
      const int k = newIndex[it.col()];
      if (k < 0) continue;
      rowIndex.push_back(k);
      values.push_back(it.value());
      gradient[k] += it.value() * rhs[row];
      squaredSum += it.value() * it.value();
    }
    columnStart[row + 1] = static_cast<int>(rowIndex.size());
  }
  cholmod_sparse transposed =
      cholmodView(static_cast<size_t>(freeCount), columnStart, rowIndex, values.data(), false);
  std::vector<int> order = eliminationOrder(jacobian, freeColumns, newIndex, at);
  const SingleThreadedLinearAlgebra oneThread;
  cholmod_common common;
  cholmod_start(&common);
  // One ordering, not CHOLMOD's default of AMD and then METIS when AMD's fill is high: METIS on
  // A Aᵀ took 2.8 s of the n = 512 cotan solve's 7.5 and 16 s of midedge's 34.6.
  common.nmethods = 1;
  common.method[0].ordering = order.empty() ? CHOLMOD_AMD : CHOLMOD_GIVEN;
  cholmod_factor* factor =
      cholmod_analyze_p(&transposed, order.empty() ? nullptr : order.data(), nullptr, 0, &common);
  // β = 1e-13 of the mean diagonal; when rounding still leaves a pivot ≤ 0 (a null space of J, a
  // system near singular; how near depends on the BLAS's order of operations), β × 1000, twice.
  bool solved = false;
  double relativeRidge = 1e-13;
  for (int attempt = 0; factor != nullptr && !solved && attempt < 3;
       ++attempt, relativeRidge *= 1e3) {
    double ridge[2] = {relativeRidge * squaredSum / freeCount, 0.0};  // β (real, imaginary)
    solved = cholmod_factorize_p(&transposed, ridge, nullptr, 0, factor, &common) &&
             common.status == CHOLMOD_OK;
  }
  Eigen::VectorXd step;
  if (solved) {
    gradient = -gradient;
    cholmod_dense b{};
    b.nrow = b.d = b.nzmax = static_cast<size_t>(freeCount);
    b.ncol = 1;
    b.x = gradient.data();
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* x = cholmod_solve(CHOLMOD_A, factor, &b, &common);
    if (x != nullptr)
      step = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(x->x), freeCount);
    cholmod_free_dense(&x, &common);
  }
  cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);
  if (step.size() != freeCount || !step.allFinite()) {
    throw NumericalError("the least-squares solve for the free unknowns failed (singular system)");
  }
  for (int k = 0; k < freeCount; ++k) u[freeColumns[k]] = step[k];
  return u;
}

double linearizedEnergy(const SparseMatrix& jacobian, const Eigen::VectorXd& u) {
  return 0.5 * (jacobian * u).squaredNorm();
}

double linearizedEnergyOfDisplacement(const SparseMatrix& jacobian, const Positions& rest,
                                      const Positions& delta, const Eigen::VectorXd& deltaXi,
                                      const std::vector<bool>& freeEdge) {
  const int positionCount = static_cast<int>(delta.size());
  const int edgeCount = static_cast<int>(jacobian.cols()) - positionCount;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(jacobian.cols());
  u.head(positionCount) = Eigen::Map<const Eigen::VectorXd>(delta.data(), positionCount);
  if (edgeCount > 0) {
    if (deltaXi.size() > 0) u.tail(edgeCount) = deltaXi;
    std::vector<bool> free(u.size(), false);
    for (int e = 0; e < edgeCount; ++e) free[positionCount + e] = freeEdge[e];
    u = minimizeLeastSquares(jacobian, Eigen::VectorXd(), u, free, rest);
  }
  return linearizedEnergy(jacobian, u);
}

Eigen::VectorXd minimizeEdgeUnknowns(const std::vector<const EnergyTerm*>& terms,
                                     const Positions& x, const Eigen::VectorXd& xi,
                                     const std::vector<bool>& freeEdge) {
  // Residuals are affine in ξ: r(ξ) = r(ξ0) + J_ξ (ξ − ξ0). Solve for the free part of ξ in the
  // unknown vector (positions fixed).
  // Positions fixed: only the ξ columns matter, which the height-mode Jacobian holds.
  const Linearization at = linearize(terms, x, xi, curvature::Derivatives::HeightOnly);
  const int positionCount = static_cast<int>(3 * x.rows());
  Eigen::VectorXd u = Eigen::VectorXd::Zero(at.jacobian.cols());
  std::vector<bool> free(at.jacobian.cols(), false);
  for (int e = 0; e < xi.size(); ++e) free[positionCount + e] = freeEdge[e];
  const Eigen::VectorXd step = minimizeLeastSquares(at.jacobian, at.residuals, u, free, x);
  return xi + step.tail(xi.size());
}

double relaxedEnergy(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                     const Eigen::VectorXd& xi, const std::vector<bool>& freeEdge) {
  const Eigen::VectorXd relaxed =
      usesEdgeUnknowns(terms) ? minimizeEdgeUnknowns(terms, x, xi, freeEdge) : xi;
  double energy = 0.0;
  for (const EnergyTerm* term : terms) energy += term->energy(x, relaxed);
  return energy;
}

}  // namespace flexure::optimize
