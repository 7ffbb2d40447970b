#include "optimize/assembly/hessian_assembly.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>

#include "curvature/projected_hessian.h"
#include "modeling/errors.h"

namespace flexure::optimize {
namespace {

// The elements of each term are split into this many contiguous parts, each summed into its own
// arrays, and the parts added in order: the result is the same bits on any machine and thread
// count. Two, the cores of flexure's target machines; each part costs a copy of the matrix's
// entries.
constexpr int kAssemblyParts = 2;

int assemblyThreads() {
  return std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, kAssemblyParts);
}

// One thread's share of an evaluation: element contributions summed into its own arrays.
class Accumulator : public curvature::ElementHessianSink {
 public:
  Accumulator(const std::vector<int>& newIndex, const std::vector<int>& columnStart,
              const std::vector<int>& rowIndex, HessianProjection projection,
              const Eigen::VectorXd* fixedMove, bool withHessian)
      : newIndex_(newIndex),
        columnStart_(columnStart),
        rowIndex_(rowIndex),
        projection_(projection),
        fixedMove_(fixedMove) {
    const int n = static_cast<int>(columnStart.size()) - 1;
    out.gradient = Eigen::VectorXd::Zero(n);
    if (withHessian) out.values.assign(rowIndex.size(), 0.0);
    if (fixedMove != nullptr) out.fixedCoupling = Eigen::VectorXd::Zero(n);
  }

  void add(const curvature::ElementHessian& element) override {
    out.energy += element.energy;
    if (element.hessian.size() == 0) {  // energy and gradient only
      for (size_t i = 0; i < element.unknowns.size(); ++i)
        if (const int p = newIndex_[element.unknowns[i]]; p >= 0)
          out.gradient[p] += element.gradient[static_cast<Eigen::Index>(i)];
      return;
    }
    const Eigen::MatrixXd& h =
        projection_ == HessianProjection::PositiveSemidefinite
            ? (projected_ = curvature::projectedToPositiveSemidefinite(element.hessian))
            : element.hessian;
    const int count = static_cast<int>(element.unknowns.size());
    for (int i = 0; i < count; ++i) {
      const int p = newIndex_[element.unknowns[i]];
      if (p < 0) continue;
      out.gradient[p] += element.gradient[i];
      for (int j = 0; j < count; ++j) {
        const int q = newIndex_[element.unknowns[j]];
        if (q < 0) {
          if (fixedMove_ != nullptr)
            out.fixedCoupling[p] += h(i, j) * (*fixedMove_)[element.unknowns[j]];
        } else if (p <= q) {
          // Two slots of one unknown (p = q from i ≠ j) both land here, as the chain rule sums.
          const auto begin = rowIndex_.begin() + columnStart_[q];
          const auto end = rowIndex_.begin() + columnStart_[q + 1];
          out.values[std::lower_bound(begin, end, p) - rowIndex_.begin()] += h(i, j);
        }
      }
    }
  }

  HessianEvaluation out;

 private:
  const std::vector<int>& newIndex_;
  const std::vector<int>& columnStart_;
  const std::vector<int>& rowIndex_;
  HessianProjection projection_;
  const Eigen::VectorXd* fixedMove_;
  Eigen::MatrixXd projected_;
};

}  // namespace

HessianAssembly::HessianAssembly(std::vector<const EnergyTerm*> terms,
                                 const std::vector<bool>& free, int vertexCount,
                                 curvature::Derivatives derivatives,
                                 const std::vector<std::array<int, 2>>& vertexCouplings)
    : terms_(std::move(terms)),
      derivatives_(derivatives),
      vertexCount_(vertexCount),
      newIndex_(free.size(), -1) {
  for (int u = 0; u < static_cast<int>(free.size()); ++u) {
    if (!free[u]) continue;
    newIndex_[u] = static_cast<int>(freeUnknowns_.size());
    freeUnknowns_.push_back(u);
  }
  std::vector<int> freeVertexNode(vertexCount, -1);
  for (int u : freeUnknowns_)
    if (u < 3 * vertexCount && freeVertexNode[u / 3] < 0) freeVertexNode[u / 3] = 0;
  for (int v = 0, node = 0; v < vertexCount; ++v)
    if (freeVertexNode[v] == 0) freeVertexNode[v] = node++;

  // The pattern: every pair of free unknowns some element reads, upper triangle. Two passes over
  // the elements (count per column, then fill), then each column sorted and deduplicated.
  const int n = size();
  std::vector<long> unknowns;
  std::vector<int> local, count(n + 1, 0), vertices;
  const auto forEachElement = [&](auto visit) {
    for (const EnergyTerm* term : terms_) {
      for (int e = 0; e < term->elementCount(); ++e) {
        term->elementUnknowns(e, derivatives_, vertexCount_, unknowns);
        local.clear();
        for (long u : unknowns)
          if (newIndex_[u] >= 0) local.push_back(newIndex_[u]);
        visit(unknowns, local);
      }
    }
    for (const std::array<int, 2>& pair : vertexCouplings) {
      unknowns.clear();
      for (int v : pair)
        for (int c = 0; c < 3; ++c) unknowns.push_back(3L * v + c);
      local.clear();
      for (long u : unknowns)
        if (newIndex_[u] >= 0) local.push_back(newIndex_[u]);
      visit(unknowns, local);
    }
  };
  forEachElement([&](const std::vector<long>& all, const std::vector<int>& freeLocal) {
    for (int q : freeLocal)
      for (int p : freeLocal) count[q + 1] += p <= q;
    vertices.clear();
    for (long u : all)
      if (u < 3L * vertexCount_ && newIndex_[u] >= 0) vertices.push_back(freeVertexNode[u / 3]);
    freeVertices_.append(vertices);
  });
  for (int q = 0; q < n; ++q) count[q + 1] += count[q];
  std::vector<int> rows(count[n]);
  std::vector<int> fill(count.begin(), count.end() - 1);
  forEachElement([&](const std::vector<long>&, const std::vector<int>& freeLocal) {
    for (int q : freeLocal)
      for (int p : freeLocal)
        if (p <= q) rows[fill[q]++] = p;
  });
  columnStart_.assign(n + 1, 0);
  rowIndex_.reserve(rows.size() / 4);
  for (int q = 0; q < n; ++q) {
    const auto begin = rows.begin() + count[q], end = rows.begin() + count[q + 1];
    std::sort(begin, end);
    rowIndex_.insert(rowIndex_.end(), begin, std::unique(begin, end));
    columnStart_[q + 1] = static_cast<int>(rowIndex_.size());
  }
}

int HessianAssembly::entry(int p, int q) const {
  const auto begin = rowIndex_.begin() + columnStart_[q],
             end = rowIndex_.begin() + columnStart_[q + 1];
  const auto at = std::lower_bound(begin, end, p);
  return at == end || *at != p ? -1 : static_cast<int>(at - rowIndex_.begin());
}

HessianEvaluation HessianAssembly::evaluate(const Positions& x, const Eigen::VectorXd& xi,
                                            HessianProjection projection,
                                            const Eigen::VectorXd* fixedMove,
                                            curvature::SecondDerivatives kind) const {
  if (kind == curvature::SecondDerivatives::Projected) {  // exact, then projected per element
    projection = HessianProjection::PositiveSemidefinite;
    kind = curvature::SecondDerivatives::Exact;
  }
  std::vector<Accumulator> accumulators;
  accumulators.reserve(kAssemblyParts);
  for (int part = 0; part < kAssemblyParts; ++part)
    accumulators.emplace_back(newIndex_, columnStart_, rowIndex_, projection, fixedMove,
                              kind != curvature::SecondDerivatives::None);
  std::vector<std::exception_ptr> errors(kAssemblyParts);
  std::atomic<int> next{0};
  const auto work = [&] {
    for (int part = next++; part < kAssemblyParts; part = next++) {
      try {
        for (const EnergyTerm* term : terms_) {
          const long count = term->elementCount();
          term->elementHessians(x, xi, static_cast<int>(count * part / kAssemblyParts),
                                static_cast<int>(count * (part + 1) / kAssemblyParts), derivatives_,
                                kind, accumulators[part]);
        }
      } catch (...) {
        errors[part] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < assemblyThreads(); ++t) helpers.emplace_back(work);
  work();
  for (std::thread& helper : helpers) helper.join();
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);  // the first failing part in element order

  HessianEvaluation total = std::move(accumulators[0].out);
  for (int t = 1; t < kAssemblyParts; ++t) {
    const HessianEvaluation& part = accumulators[t].out;
    total.energy += part.energy;
    total.gradient += part.gradient;
    for (size_t k = 0; k < total.values.size(); ++k) total.values[k] += part.values[k];
    if (fixedMove != nullptr) total.fixedCoupling += part.fixedCoupling;
  }
  return total;
}

}  // namespace flexure::optimize
