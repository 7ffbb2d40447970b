// The one implementation of EnergyTerm: a list of element residual functors of one type, each
// with a templated operator()(T const* const* blocks, T* residuals). The same functor is called
// with doubles for values and wrapped in Ceres autodiff for derivatives.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/dynamic_autodiff_cost_function.h>
#include <ceres/problem.h>
#include <Eigen/LU>

#include <algorithm>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "curvature/cotan_mean_curvature.h"
#include "curvature/energy_term.h"
#include "curvature/height_only_cost.h"
#include "curvature/hinge_bending.h"
#include "curvature/membrane.h"
#include "curvature/midedge_normals.h"
#include "curvature/quadratic_fit.h"
#include "curvature/shared_block_cost.h"
#include "curvature/triangle_averaged.h"
#include "modeling/errors.h"

namespace flexure::curvature {

// Ceres' fixed-arity autodiff calls functor(b0, b1, …, b_{n−1}, residuals); this forwards to the
// residual's array form. The residual array arrives last and is handed on writable.
template <class Residual>
struct FixedArity {
  Residual residual;
  template <class T, class... Rest>
  bool operator()(const T* first, Rest... rest) const {
    const T* blocks[] = {first, rest...};
    return residual(blocks, const_cast<T*>(blocks[sizeof...(Rest)]));
  }
};

template <class Residual, int... BlockSizes>
ceres::CostFunction* fixedArityCost(const Residual& r) {
  return new ceres::AutoDiffCostFunction<FixedArity<Residual>, Residual::kResiduals, BlockSizes...>(
      new FixedArity<Residual>{r});
}

// A residual type that declares its blocks' sizes (`using BlockSizes =
// std::integer_sequence<int, 3, 3, 3>;`) needs no overload below: a new energy's kernel file
// stays self-contained.
template <class Residual, int... Sizes>
ceres::CostFunction* fixedArityCost(const Residual& r, std::integer_sequence<int, Sizes...>) {
  return fixedArityCost<Residual, Sizes...>(r);
}
template <class Residual, class Sizes = typename Residual::BlockSizes>
ceres::CostFunction* costFunction(const Residual& r) {
  return fixedArityCost(r, Sizes());
}

// The cost function and parameter blocks of each residual type.
inline ceres::CostFunction* costFunction(const HingeBendingResidual& r) {
  return fixedArityCost<HingeBendingResidual, 3, 3, 3, 3>(r);
}
inline ceres::CostFunction* costFunction(const TriangleAveragedResidual& r) {
  return fixedArityCost<TriangleAveragedResidual, 3, 3, 3, 3, 3, 3>(r);
}
inline ceres::CostFunction* costFunction(const QuadraticFitResidual& r) {
  return fixedArityCost<QuadraticFitResidual, 3, 3, 3, 3, 3, 3>(r);
}
inline ceres::CostFunction* costFunction(const StvkMembraneResidual& r) {
  return fixedArityCost<StvkMembraneResidual, 3, 3, 3>(r);
}
inline ceres::CostFunction* costFunction(const ConformalMembraneResidual& r) {
  return fixedArityCost<ConformalMembraneResidual, 3, 3, 3>(r);
}
inline ceres::CostFunction* costFunction(const AngleBarrierResidual& r) {
  return fixedArityCost<AngleBarrierResidual, 3, 3, 3>(r);
}
inline ceres::CostFunction* costFunction(const EdgeSpringResidual& r) {
  return fixedArityCost<EdgeSpringResidual, 3, 3>(r);
}
inline ceres::CostFunction* costFunction(const AreaSpringResidual& r) {
  return fixedArityCost<AreaSpringResidual, 3, 3, 3>(r);
}
// A midedge face reads its three ξ, its three vertices and 0 to 3 flap vertices (boundary faces
// lack some): `make(std::integral_constant<int, flaps>())`.
template <class Make>
ceres::CostFunction* withMidedgeFlaps(const MidedgeResidual& r, Make make) {
  switch (r.flapCount) {
    case 0:
      return make(std::integral_constant<int, 0>());
    case 1:
      return make(std::integral_constant<int, 1>());
    case 2:
      return make(std::integral_constant<int, 2>());
    default:
      return make(std::integral_constant<int, 3>());
  }
}
template <size_t... Flap>
ceres::CostFunction* midedgeFixedCost(const MidedgeResidual& r, std::index_sequence<Flap...>) {
  return fixedArityCost<MidedgeResidual, 1, 1, 1, 3, 3, 3, (static_cast<int>(Flap) * 0 + 3)...>(r);
}
inline ceres::CostFunction* costFunction(const MidedgeResidual& r) {
  return withMidedgeFlaps(r, [&](auto flaps) {
    return midedgeFixedCost(r, std::make_index_sequence<decltype(flaps)::value>());
  });
}
// Cotan residuals read a vertex and its ring, so their arity is the valence + 1. Valences 3 to 8
// (all of a 4-8 patch's, nearly all of a real mesh's) take fixed-size autodiff, one instantiation
// per arity; rarer ones Ceres' dynamic autodiff (27 derivatives per pass, strided), which took
// 1.5× as long per evaluation at valence 6. `make(std::integral_constant<int, arity>())` for an
// arity of 4 to 9, else nullptr.
template <class Make>
ceres::CostFunction* withCotanArity(const CotanMeanCurvatureResidual& r, Make make) {
  switch (r.vertices.size()) {
    case 4:
      return make(std::integral_constant<int, 4>());
    case 5:
      return make(std::integral_constant<int, 5>());
    case 6:
      return make(std::integral_constant<int, 6>());
    case 7:
      return make(std::integral_constant<int, 7>());
    case 8:
      return make(std::integral_constant<int, 8>());
    case 9:
      return make(std::integral_constant<int, 9>());
    default:
      return nullptr;
  }
}
template <size_t... Slot>
ceres::CostFunction* cotanFixedCost(const CotanMeanCurvatureResidual& r,
                                    std::index_sequence<Slot...>) {
  return fixedArityCost<CotanMeanCurvatureResidual, (static_cast<int>(Slot) * 0 + 3)...>(r);
}
inline ceres::CostFunction* costFunction(const CotanMeanCurvatureResidual& r) {
  if (ceres::CostFunction* fixed = withCotanArity(r, [&](auto arity) {
        return cotanFixedCost(r, std::make_index_sequence<decltype(arity)::value>());
      }))
    return fixed;
  auto* cost = new ceres::DynamicAutoDiffCostFunction<CotanMeanCurvatureResidual, 27>(
      new CotanMeanCurvatureResidual(r));
  for (size_t k = 0; k < r.vertices.size(); ++k) cost->AddParameterBlock(3);
  cost->SetNumResiduals(1);
  return cost;
}

// Height-mode cost functions (height_only_cost.h), one derivative per block; nullptr where the
// full cost serves: membranes (only in xyz mode) and cotan rings of valence above 8.
template <class Residual, int kBlocks>
ceres::CostFunction* heightOnlyCost(const Residual& r, int xiBlocks = 0) {
  std::vector<int32_t> sizes(kBlocks, 3);
  std::fill(sizes.begin(), sizes.begin() + xiBlocks, 1);
  return new HeightOnlyCost<Residual, kBlocks>(r, sizes);
}
inline ceres::CostFunction* heightOnlyCost(const HingeBendingResidual& r) {
  return heightOnlyCost<HingeBendingResidual, 4>(r);
}
inline ceres::CostFunction* heightOnlyCost(const TriangleAveragedResidual& r) {
  return heightOnlyCost<TriangleAveragedResidual, 6>(r);
}
inline ceres::CostFunction* heightOnlyCost(const QuadraticFitResidual& r) {
  return heightOnlyCost<QuadraticFitResidual, 6>(r);
}
inline ceres::CostFunction* heightOnlyCost(const MidedgeResidual& r) {
  return withMidedgeFlaps(r, [&](auto flaps) {
    return heightOnlyCost<MidedgeResidual, 6 + decltype(flaps)::value>(r, 3);
  });
}
inline ceres::CostFunction* heightOnlyCost(const CotanMeanCurvatureResidual& r) {
  return withCotanArity(r, [&](auto arity) {
    return heightOnlyCost<CotanMeanCurvatureResidual, decltype(arity)::value>(r);
  });
}
template <class Membrane>
ceres::CostFunction* heightOnlyCost(const Membrane&) {
  return nullptr;
}

template <class Residual>
ceres::CostFunction* costFunction(const Residual& r, Derivatives derivatives) {
  ceres::CostFunction* height =
      derivatives == Derivatives::HeightOnly ? heightOnlyCost(r) : nullptr;
  return height != nullptr ? height : costFunction(r);
}

template <class Residual, class Pointer>
void parameterBlocks(const Residual& r, Pointer positions, Pointer, std::vector<Pointer>& out) {
  out.clear();
  for (int v : r.vertices) out.push_back(positions + 3 * v);
}
template <class Pointer>
void parameterBlocks(const MidedgeResidual& r, Pointer positions, Pointer xi,
                     std::vector<Pointer>& out) {
  out.clear();
  for (int e : r.edges) out.push_back(xi + e);
  for (int k = 0; k < 3 + r.flapCount; ++k) out.push_back(positions + 3 * r.vertices[k]);
}

// The vertices an element reads: all of `vertices`, except for midedge, whose array has room for
// three flaps it may not have.
template <class Residual>
int elementVertexCount(const Residual& r) {
  return static_cast<int>(r.vertices.size());
}
inline int elementVertexCount(const MidedgeResidual& r) {
  return 3 + r.flapCount;
}

// Residuals whose rest curvature a plastic update can move: a face's S̄_T (restShapeOperator,
// with shapeOperator(blocks)). The hinge's term reads its angles as face tensors itself
// (hinge_energy.cpp, HingeFaceTensors).
template <class Residual, class = void>
struct HasRestShapeOperator : std::false_type {};
template <class Residual>
struct HasRestShapeOperator<Residual,
                            std::void_t<decltype(std::declval<Residual&>().restShapeOperator)>>
    : std::true_type {};

// Residuals whose rest metric a membrane plastic update can move: a face's rest strain P_T
// (restStrain, with strain(blocks) and restEdgeInverse).
template <class Residual, class = void>
struct HasRestStrain : std::false_type {};
template <class Residual>
struct HasRestStrain<Residual, std::void_t<decltype(std::declval<Residual&>().restStrain)>>
    : std::true_type {};

template <class Residual>
class ElementTerm : public EnergyTerm, public RestCurvatureState, public RestMetricState {
 public:
  // Element e is mesh element `elementIds[e]` of kind `elementKind` ("edge", "face", "vertex"),
  // which messages name.
  ElementTerm(std::string name, std::string elementKind, std::vector<Residual> elements,
              std::vector<int> elementIds, double coveredArea, bool usesEdgeUnknowns)
      : name_(std::move(name)),
        elementKind_(std::move(elementKind)),
        elements_(std::move(elements)),
        elementIds_(std::move(elementIds)),
        coveredArea_(coveredArea),
        usesEdgeUnknowns_(usesEdgeUnknowns) {}

  std::string name() const override { return name_; }
  std::string elementKind() const override { return elementKind_; }
  int elementCount() const override { return static_cast<int>(elements_.size()); }
  double coveredArea() const override { return coveredArea_; }
  bool usesEdgeUnknowns() const override { return usesEdgeUnknowns_; }
  const std::vector<Residual>& elements() const { return elements_; }

  RestCurvatureState* restCurvatureState() override {
    if constexpr (HasRestShapeOperator<Residual>::value) return this;
    return nullptr;
  }
  int elementId(int e) const override { return elementIds_[e]; }
  Eigen::MatrixXd elementCurvatures(const Positions& x, const Eigen::VectorXd& xi) const override {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(elements_.size(), 3);
    if constexpr (HasRestShapeOperator<Residual>::value) {
      std::vector<const double*> blocks;
      for (size_t e = 0; e < elements_.size(); ++e) {
        parameterBlocks(elements_[e], x.data(), xi.data(), blocks);
        const Sym2<double> s = elements_[e].shapeOperator(blocks.data());
        out.row(static_cast<Eigen::Index>(e)) << s.a, s.b, s.c;
      }
    }
    return out;
  }
  Eigen::MatrixXd restCurvatures() const override {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(elements_.size(), 3);
    if constexpr (HasRestShapeOperator<Residual>::value) {
      for (size_t e = 0; e < elements_.size(); ++e) {
        const Sym2<double>& s = elements_[e].restShapeOperator;
        out.row(static_cast<Eigen::Index>(e)) << s.a, s.b, s.c;
      }
    }
    return out;
  }
  void setRestCurvatures(const Eigen::MatrixXd& rest) override {
    if constexpr (HasRestShapeOperator<Residual>::value) {
      for (size_t e = 0; e < elements_.size(); ++e) {
        const auto row = static_cast<Eigen::Index>(e);
        elements_[e].restShapeOperator = {rest(row, 0), rest(row, 1), rest(row, 2)};
      }
    }
  }

  RestMetricState* restMetricState() override {
    if constexpr (HasRestStrain<Residual>::value) return this;
    return nullptr;
  }
  Eigen::MatrixXd elementStrains(const Positions& x) const override {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(elements_.size(), 3);
    if constexpr (HasRestStrain<Residual>::value) {
      std::vector<const double*> blocks;
      for (size_t e = 0; e < elements_.size(); ++e) {
        parameterBlocks(elements_[e], x.data(), static_cast<const double*>(nullptr), blocks);
        const Sym2<double> s = elements_[e].strain(blocks.data());
        out.row(static_cast<Eigen::Index>(e)) << s.a, s.b, s.c;
      }
    }
    return out;
  }
  Eigen::MatrixXd restStrains() const override {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(elements_.size(), 3);
    if constexpr (HasRestStrain<Residual>::value) {
      for (size_t e = 0; e < elements_.size(); ++e) {
        const Sym2<double>& s = elements_[e].restStrain;
        out.row(static_cast<Eigen::Index>(e)) << s.a, s.b, s.c;
      }
    }
    return out;
  }
  void setRestStrains(const Eigen::MatrixXd& rest) override {
    if constexpr (HasRestStrain<Residual>::value) {
      for (size_t e = 0; e < elements_.size(); ++e) {
        const auto row = static_cast<Eigen::Index>(e);
        elements_[e].restStrain = {rest(row, 0), rest(row, 1), rest(row, 2)};
      }
    }
  }
  Eigen::Matrix2d restEdgeMatrix(int e) const override {
    if constexpr (HasRestStrain<Residual>::value) {
      const std::array<double, 4>& m = elements_[e].restEdgeInverse;
      Eigen::Matrix2d inverse;
      inverse << m[0], m[1], m[2], m[3];
      return inverse.inverse();
    }
    return Eigen::Matrix2d::Zero();
  }

  void markTouchedVertices(std::vector<bool>& touched) const override {
    for (const Residual& element : elements_)
      for (int k = 0; k < elementVertexCount(element); ++k) touched[element.vertices[k]] = true;
  }

  double energy(const Positions& x, const Eigen::VectorXd& xi) const override {
    return elementEnergies(x, xi).sum();
  }

  Eigen::VectorXd elementEnergies(const Positions& x, const Eigen::VectorXd& xi) const override {
    Eigen::VectorXd energies(elements_.size());
    std::vector<const double*> blocks;
    double r[Residual::kResiduals];
    for (size_t e = 0; e < elements_.size(); ++e) {
      parameterBlocks(elements_[e], x.data(), xi.data(), blocks);
      if (!elements_[e](blocks.data(), r)) throw degenerate(static_cast<size_t>(e));
      double sum = 0.0;
      for (double value : r) sum += value * value;
      energies[static_cast<Eigen::Index>(e)] = 0.5 * sum;
    }
    return energies;
  }

  void appendJacobianRows(const Positions& x, const Eigen::VectorXd& xi, int begin, int end,
                          Derivatives derivatives, JacobianRows& out) const override {
    const long xiColumn = 3 * static_cast<long>(x.rows());
    std::vector<const double*> blocks;
    std::vector<long> firstColumn;  // the same slots as column offsets
    std::vector<double> storage;
    std::vector<double*> jacobians;
    std::vector<std::pair<long, double>> row;
    double r[Residual::kResiduals];
    for (int e = begin; e < end; ++e) {
      parameterBlocks(elements_[e], x.data(), xi.data(), blocks);
      parameterBlocks(elements_[e], 0L, xiColumn, firstColumn);
      const std::unique_ptr<ceres::CostFunction> cost(costFunction(elements_[e], derivatives));
      const std::vector<int32_t>& sizes = cost->parameter_block_sizes();
      size_t total = 0;
      for (int32_t size : sizes) total += static_cast<size_t>(size) * Residual::kResiduals;
      storage.resize(total);
      jacobians.clear();
      for (size_t b = 0, offset = 0; b < sizes.size();
           offset += sizes[b] * Residual::kResiduals, ++b)
        jacobians.push_back(storage.data() + offset);
      if (!cost->Evaluate(blocks.data(), r, jacobians.data()))
        throw degenerate(static_cast<size_t>(e));
      for (int i = 0; i < Residual::kResiduals; ++i) {
        // A block read through two slots (shared_block_cost.h) appears twice: sum its columns.
        row.clear();
        for (size_t b = 0; b < sizes.size(); ++b)
          for (int c = skipped(derivatives, sizes[b]); c < sizes[b]; ++c)
            row.emplace_back(firstColumn[b] + c, jacobians[b][i * sizes[b] + c]);
        std::sort(row.begin(), row.end(),
                  [](const auto& a, const auto& b) { return a.first < b.first; });
        for (size_t k = 0; k < row.size(); ++k) {
          if (k > 0 && row[k].first == row[k - 1].first) {
            out.values.back() += row[k].second;
            continue;
          }
          out.columns.push_back(static_cast<int>(row[k].first));
          out.values.push_back(row[k].second);
        }
        out.rowStart.push_back(static_cast<int>(out.columns.size()));
        out.residuals.push_back(r[i]);
      }
      if (e == begin) reserveLike(out, static_cast<size_t>(end - begin), total);
    }
  }

  void elementUnknowns(int e, Derivatives derivatives, int vertexCount,
                       std::vector<long>& out) const override {
    std::vector<long> firstColumn;
    std::vector<int> sizes;
    blockLayout(elements_[e], vertexCount, firstColumn, sizes);
    curvature::elementUnknowns(sizes, firstColumn, derivatives, out);
  }

  void elementHessians(const Positions& x, const Eigen::VectorXd& xi, int begin, int end,
                       Derivatives derivatives, SecondDerivatives kind,
                       ElementHessianSink& sink) const override {
    std::vector<const double*> blocks;
    std::vector<long> firstColumn;
    std::vector<int> sizes;
    ElementHessian hessian;
    for (int e = begin; e < end; ++e) {
      parameterBlocks(elements_[e], x.data(), xi.data(), blocks);
      blockLayout(elements_[e], static_cast<int>(x.rows()), firstColumn, sizes);
      if (kind != SecondDerivatives::Exact) {
        firstDerivatives(e, blocks, sizes, firstColumn, derivatives,
                         kind == SecondDerivatives::GaussNewton, hessian);
        sink.add(hessian);
        continue;
      }
      if (!elementHessian(elements_[e], blocks, sizes, firstColumn, derivatives, hessian)) {
        if (hessian.unknowns.size() > static_cast<size_t>(kMaxHessianUnknowns)) {
          throw InputError(name_ + ": " + elementKind_ + " " + std::to_string(elementIds_[e]) +
                           " has " + std::to_string(hessian.unknowns.size()) +
                           " unknowns, more than the exact Hessian supports (" +
                           std::to_string(kMaxHessianUnknowns) +
                           ": a vertex of valence 16 or more in ProblemOptions.dof xyz); use "
                           "MinimizeOptions.solver ceres");
        }
        throw degenerate(static_cast<size_t>(e));
      }
      sink.add(hessian);
    }
  }

  void addResidualBlocks(ceres::Problem& problem, double* positions, double* xi,
                         Derivatives derivatives) const override {
    std::vector<double*> blocks;
    for (const Residual& element : elements_) {
      parameterBlocks(element, positions, xi, blocks);
      ceres::CostFunction* cost = shareRepeatedBlocks(costFunction(element, derivatives), blocks);
      problem.AddResidualBlock(cost, nullptr, blocks);
    }
  }

 protected:
  std::vector<Residual>& mutableElements() { return elements_; }

 private:
  // Room for `elements` more elements of `entries` Jacobian entries each (the first one's count).
  static void reserveLike(JacobianRows& out, size_t elements, size_t entries) {
    out.columns.reserve(out.columns.size() + elements * entries);
    out.values.reserve(out.values.size() + elements * entries);
    out.rowStart.reserve(out.rowStart.size() + elements * Residual::kResiduals);
    out.residuals.reserve(out.residuals.size() + elements * Residual::kResiduals);
  }

  // ½|r_e|², J_eᵀr_e and (gaussNewton) J_eᵀJ_e of element e (first derivatives: forward-mode
  // jets of the element's size, element_hessian.h; Ceres' cost function where those refuse it),
  // over the unknowns of elementUnknowns (a slot's columns; in height mode its last one).
  void firstDerivatives(int e, const std::vector<const double*>& blocks,
                        const std::vector<int>& sizes, const std::vector<long>& firstColumn,
                        Derivatives derivatives, bool gaussNewton, ElementHessian& out) const {
    if (elementFirstDerivatives(elements_[e], blocks, sizes, firstColumn, derivatives, gaussNewton,
                                out))
      return;
    // Refused: degenerate, or more unknowns than the jets hold (a cotan vertex of valence 16 or
    // more), which Ceres' cost function (dynamic for cotan rings) evaluates.
    curvature::elementUnknowns(sizes, firstColumn, derivatives, out.unknowns);
    const std::unique_ptr<ceres::CostFunction> cost(costFunction(elements_[e], derivatives));
    const int count = static_cast<int>(out.unknowns.size());
    std::vector<double> storage;
    std::vector<double*> jacobians;
    for (int size : sizes) storage.resize(storage.size() + size * Residual::kResiduals);
    for (size_t b = 0, offset = 0; b < sizes.size(); offset += sizes[b] * Residual::kResiduals, ++b)
      jacobians.push_back(storage.data() + offset);
    Eigen::Matrix<double, Residual::kResiduals, 1> r;
    if (!cost->Evaluate(blocks.data(), r.data(), jacobians.data()))
      throw degenerate(static_cast<size_t>(e));
    Eigen::MatrixXd j(Residual::kResiduals, count);
    for (size_t b = 0, slot = 0; b < sizes.size(); ++b)
      for (int c = 0; c < sizes[b]; ++c)
        if (isElementUnknown(derivatives, c, sizes[b])) {
          for (int i = 0; i < Residual::kResiduals; ++i)
            j(i, static_cast<Eigen::Index>(slot)) = jacobians[b][i * sizes[b] + c];
          ++slot;
        }
    out.energy = 0.5 * r.squaredNorm();
    out.gradient = j.transpose() * r;
    if (gaussNewton)
      out.hessian = j.transpose() * j;
    else
      out.hessian.resize(0, 0);
  }

  // The first global unknown of each block the element reads, and the block's size (a vertex 3,
  // a ξ 1).
  static void blockLayout(const Residual& element, int vertexCount, std::vector<long>& firstColumn,
                          std::vector<int>& sizes) {
    const long xiColumn = 3 * static_cast<long>(vertexCount);
    parameterBlocks(element, 0L, xiColumn, firstColumn);
    sizes.clear();
    for (long column : firstColumn) sizes.push_back(column >= xiColumn ? 1 : 3);
  }

  // The leading columns of a block not in the Jacobian rows: a vertex's x and y in height mode.
  static int skipped(Derivatives derivatives, int blockSize) {
    return derivatives == Derivatives::HeightOnly ? blockSize - 1 : 0;
  }

  NumericalError degenerate(size_t e) const {
    return NumericalError(name_ + ": " + elementKind_ + " " + std::to_string(elementIds_[e]) +
                          " is degenerate in the current configuration (a collapsed edge or "
                          "face): its energy is undefined");
  }

  std::string name_, elementKind_;
  std::vector<Residual> elements_;
  std::vector<int> elementIds_;
  double coveredArea_;
  bool usesEdgeUnknowns_;
};

}  // namespace flexure::curvature
