#include "optimize/assembly/energy_evaluation.h"

#include <ceres/problem.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>

#include "modeling/errors.h"

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

// The stacked residuals r and their Jacobian J at (x, ξ), element by element without a Ceres
// problem. Assembling one and having Ceres write its Jacobian as CRS took, for the rest Jacobian
// of the n = 512 patch in bench/solve_bench (linearized "evaluation"), hinge 3.5 s, cotan 2.7,
// quadfit 7.7, midedge 10; this took 1.3, 1.7, 4.4 and 5.6 s on one thread, and takes 0.5, 0.4,
// 1.0 and 1.4 s on two threads with height-mode derivatives (separate runs of the benchmark).
// Each term's elements are split into one contiguous range per thread; the ranges' rows are
// concatenated in element order, so J does not depend on the thread count.
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

SparseMatrix residualJacobian(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                              const Eigen::VectorXd& xi, curvature::Derivatives derivatives) {
  return linearize(terms, x, xi, derivatives).jacobian;
}

double linearizedEnergy(const SparseMatrix& jacobian, const Eigen::VectorXd& u) {
  return 0.5 * (jacobian * u).squaredNorm();
}

}  // namespace flexure::optimize
