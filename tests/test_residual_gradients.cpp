// Derivatives of the element residuals and of whole energy terms.
//
// 1. Every residual functor's Ceres cost function (autodiff) against Ceres' GradientChecker
//    (Ridders' extrapolated finite differences) at random non-degenerate configurations, with
//    hinge angles up to ±2.5 rad and element parameters taken from strongly curved rest meshes.
// 2. ∇E of each bending term (optimize::energyGradient, ξ included for midedge) against central
//    differences of EnergyTerm::energy: the error of (E(u + h e_k) − E(u − h e_k)) / 2h is
//    h²/6 · ∂³E + O(ε E / h), so it must shrink about 100-fold from h = 1e-4 to h = 1e-5 and stay
//    near roundoff at 1e-6.
#include <ceres/crs_matrix.h>
#include <ceres/gradient_checker.h>
#include <ceres/problem.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "curvature/element_term.h"
#include "curvature/membrane_energy.h"
#include "modeling/generators.h"
#include "modeling/stencils.h"
#include "support/energy_fixtures.h"
#include "support/small_meshes.h"

namespace flexure {
namespace {

using curvature::BendingOptions;
using curvature::CurvatureMetric;
using curvature::Discretization;
using curvature::ElementTerm;
using curvature::RestCurvature;
using Eigen::Vector3d;
using modeling::Mesh;
using modeling::Positions;
using testing::bendingOptions;
using testing::BendingSetup;

using Triangle = std::array<Vector3d, 3>;
using Blocks = std::vector<std::vector<double>>;

// ---------------------------------------------------------------------------------------------
// Random element configurations.

class Sampler {
 public:
  explicit Sampler(unsigned seed) : rng_(seed) {}

  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }

  // A counter-clockwise triangle with corners at polar angles 2πk/3 ± 0.4 and radii in
  // [0.7, 1.3] (so every angle exceeds ~0.6 rad), then randomly rotated and translated.
  Triangle triangle() {
    const Eigen::Matrix3d rotation = testing::randomRotation(rng_);
    const Vector3d shift(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    Triangle t;
    for (int k = 0; k < 3; ++k) {
      const double angle = 2.0 * M_PI * k / 3.0 + uniform(-0.4, 0.4), radius = uniform(0.7, 1.3);
      t[k] = rotation * Vector3d(radius * std::cos(angle), radius * std::sin(angle), 0.0) + shift;
    }
    return t;
  }

  // The flap vertex across edge i (x_{i+1} → x_{i+2}) of t, folded so that the hinge angle of
  // docs/energies.md across that edge is α: p = a + s (b − a) + d ℓ (cos α m̂ + sin α n̂), with
  // m̂ the outward in-plane normal of the edge and n̂ the face normal.
  Vector3d flap(const Triangle& t, int i, double alpha) {
    const Vector3d a = t[(i + 1) % 3], b = t[(i + 2) % 3];
    const Vector3d n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
    const Vector3d m = (b - a).cross(n).normalized();
    const double length = (b - a).norm();
    return a + uniform(0.2, 0.8) * (b - a) +
           uniform(0.6, 1.2) * length * (std::cos(alpha) * m + std::sin(alpha) * n);
  }

  // Fold angles: the first configuration of every element probes ±2.5 rad, the others are
  // uniform in [−2.5, 2.5].
  double foldAngle(int configuration, int edge) {
    static constexpr double kLarge[3] = {2.5, -2.5, 2.4};
    return configuration == 0 ? kLarge[edge] : uniform(-2.5, 2.5);
  }

  std::mt19937& rng() { return rng_; }

 private:
  std::mt19937 rng_;
};

std::vector<double> block(const Vector3d& x) {
  return {x.x(), x.y(), x.z()};
}

// Blocks x0, x1, x2, then the flaps across edges 0, 1, 2 (triavg, quadfit).
Blocks faceWithFlaps(Sampler& s, int configuration) {
  const Triangle t = s.triangle();
  Blocks b{block(t[0]), block(t[1]), block(t[2])};
  for (int i = 0; i < 3; ++i) b.push_back(block(s.flap(t, i, s.foldAngle(configuration, i))));
  return b;
}

Blocks configurationFor(const curvature::HingeBendingResidual&, Sampler& s, int configuration) {
  // Hinge (i, j, k, l): f = (i, j, k) and l across f's edge 2 (i → j).
  const Triangle t = s.triangle();
  return {block(t[0]), block(t[1]), block(t[2]),
          block(s.flap(t, 2, s.foldAngle(configuration, 0)))};
}
Blocks configurationFor(const curvature::TriangleAveragedResidual&, Sampler& s, int c) {
  return faceWithFlaps(s, c);
}
Blocks configurationFor(const curvature::QuadraticFitResidual&, Sampler& s, int c) {
  return faceWithFlaps(s, c);
}
Blocks configurationFor(const curvature::MidedgeResidual& r, Sampler& s, int configuration) {
  const Triangle t = s.triangle();
  Blocks b;
  for (int i = 0; i < 3; ++i) b.push_back({s.uniform(-1.0, 1.0)});  // ξ0, ξ1, ξ2
  for (int i = 0; i < 3; ++i) b.push_back(block(t[i]));
  for (int i = 0; i < 3; ++i)
    if (r.hasFlap[i]) b.push_back(block(s.flap(t, i, s.foldAngle(configuration, i))));
  return b;
}
Blocks configurationFor(const curvature::CotanMeanCurvatureResidual& r, Sampler& s, int) {
  // A strongly curved, possibly saddle-shaped one-ring: ring vertex j at polar angle
  // 2πj/k ± 0.25 π/k, radius in [0.6, 1.4] and height in [−0.8, 0.8] about the centre.
  const int k = static_cast<int>(r.vertices.size()) - 1;
  const Eigen::Matrix3d rotation = testing::randomRotation(s.rng());
  const Vector3d shift(s.uniform(-1, 1), s.uniform(-1, 1), s.uniform(-1, 1));
  Blocks b{block(shift)};
  for (int j = 0; j < k; ++j) {
    const double angle = 2.0 * M_PI * (j + s.uniform(-0.125, 0.125)) / k;
    const double radius = s.uniform(0.6, 1.4);
    b.push_back(block(rotation * Vector3d(radius * std::cos(angle), radius * std::sin(angle),
                                          s.uniform(-0.8, 0.8)) +
                      shift));
  }
  return b;
}
Blocks triangleBlocks(Sampler& s) {
  const Triangle t = s.triangle();
  return {block(t[0]), block(t[1]), block(t[2])};
}
Blocks configurationFor(const curvature::StvkMembraneResidual&, Sampler& s, int) {
  return triangleBlocks(s);
}
Blocks configurationFor(const curvature::ConformalMembraneResidual&, Sampler& s, int) {
  return triangleBlocks(s);
}
Blocks configurationFor(const curvature::EdgeSpringResidual&, Sampler& s, int) {
  const Triangle t = s.triangle();
  return {block(t[0]), block(t[1])};
}
Blocks configurationFor(const curvature::AreaSpringResidual&, Sampler& s, int) {
  return triangleBlocks(s);
}

// ---------------------------------------------------------------------------------------------
// The gradient check.

// The bounds on the normwise error max |J − J_fd| / max |J| of a cost function and on the
// entrywise relative error |J − J_fd| / max(|J|, |J_fd|) of its significant entries, those above
// 1e-8 max |J|. (GradientChecker's own verdict is entrywise over every entry, which fails on
// entries that vanish analytically: 4e-16 against 2e-15 is a relative error of 0.8.) Measured
// worst over all probes: normwise 6e-13 (triavg), entrywise 3.4e-10 (triavg).
constexpr double kNormwisePrecision = 1e-9;
constexpr double kEntrywisePrecision = 1e-7;
constexpr double kSignificant = 1e-8;

// GradientChecker differentiates with Ridders' method, whose largest step is
// 2⁵ · ridders_relative_initial_step_size · max(|x|, 1): 0.32 by default, which on these unit-size
// elements folded by up to 2.5 rad can cross the ±π cut of the bending angle or fold a face
// through itself, and the extrapolation then picks a polluted value. A largest step of 0.032
// keeps every sample on the smooth branch.
ceres::NumericDiffOptions checkerOptions() {
  ceres::NumericDiffOptions o;
  o.ridders_relative_initial_step_size = 1e-3;
  return o;
}

// Probes `residual` at `configurations` random configurations; counts them in `probes`.
// The height-mode cost of a residual (curvature/height_only_cost.h; none for membranes and cotan
// rings above valence 8): each block's last column (z, or ξ) equal to the full Jacobian's, the
// columns before it (x, y) zero.
template <class Residual>
void expectHeightOnlyMatches(const Residual& residual, const std::vector<const double*>& blocks,
                             const std::vector<ceres::Matrix>& full, double jacobianMax) {
  const std::unique_ptr<ceres::CostFunction> height(curvature::heightOnlyCost(residual));
  if (!height) return;
  const std::vector<int32_t>& sizes = height->parameter_block_sizes();
  ASSERT_EQ(sizes.size(), full.size());
  std::vector<std::vector<double>> storage;
  std::vector<double*> jacobians;
  for (int32_t size : sizes) storage.emplace_back(size * Residual::kResiduals, -1.0);
  for (auto& s : storage) jacobians.push_back(s.data());
  double r[Residual::kResiduals];
  ASSERT_TRUE(height->Evaluate(blocks.data(), r, jacobians.data()));
  for (size_t b = 0; b < sizes.size(); ++b) {
    for (int i = 0; i < Residual::kResiduals; ++i) {
      for (int c = 0; c < sizes[b]; ++c) {
        const double value = storage[b][i * sizes[b] + c];
        if (c + 1 < sizes[b]) {
          EXPECT_EQ(value, 0.0) << "block " << b << " column " << c;
        } else {
          EXPECT_NEAR(value, full[b](i, c), 1e-13 * jacobianMax) << "block " << b;
        }
      }
    }
  }
}

template <class Residual>
void checkResidual(const Residual& residual, Sampler& sampler, int configurations, int& probes) {
  const std::unique_ptr<ceres::CostFunction> cost(curvature::costFunction(residual));
  const ceres::GradientChecker checker(
      cost.get(), static_cast<const std::vector<const ceres::Manifold*>*>(nullptr),
      checkerOptions());
  for (int c = 0; c < configurations; ++c) {
    const Blocks blocks = configurationFor(residual, sampler, c);
    ASSERT_EQ(blocks.size(), cost->parameter_block_sizes().size());
    std::vector<const double*> pointers;
    for (const auto& b : blocks) pointers.push_back(b.data());
    ceres::GradientChecker::ProbeResults results;
    checker.Probe(pointers.data(), kEntrywisePrecision, &results);
    ASSERT_TRUE(results.return_value) << "configuration " << c << " is degenerate";
    double jacobianMax = 0.0, differenceMax = 0.0, entrywise = 0.0;
    for (size_t k = 0; k < results.jacobians.size(); ++k) {
      jacobianMax = std::max(jacobianMax, results.jacobians[k].cwiseAbs().maxCoeff());
      differenceMax =
          std::max(differenceMax,
                   (results.jacobians[k] - results.numeric_jacobians[k]).cwiseAbs().maxCoeff());
    }
    ASSERT_GT(jacobianMax, 0.0);
    for (size_t k = 0; k < results.jacobians.size(); ++k) {
      const Eigen::MatrixXd& j = results.jacobians[k];
      const Eigen::MatrixXd& fd = results.numeric_jacobians[k];
      for (Eigen::Index row = 0; row < j.rows(); ++row) {
        for (Eigen::Index col = 0; col < j.cols(); ++col) {
          const double size = std::max(std::abs(j(row, col)), std::abs(fd(row, col)));
          if (size > kSignificant * jacobianMax)
            entrywise = std::max(entrywise, std::abs(j(row, col) - fd(row, col)) / size);
        }
      }
    }
    const double normwise = differenceMax / jacobianMax;
    EXPECT_LT(normwise, kNormwisePrecision) << "configuration " << c << "\n" << results.error_log;
    EXPECT_LT(entrywise, kEntrywisePrecision) << "configuration " << c << "\n" << results.error_log;
    expectHeightOnlyMatches(residual, pointers, results.jacobians, jacobianMax);
    ++probes;
  }
}

template <class Residual>
const std::vector<Residual>& elementsOf(const curvature::EnergyTerm& term) {
  const auto* typed = dynamic_cast<const ElementTerm<Residual>*>(&term);
  if (!typed) throw std::logic_error(term.name() + " holds another residual type");
  return typed->elements();
}

// Checks `elementCount` elements spread over the term, `configurations` random configurations
// each.
template <class Residual>
void checkTerm(const curvature::EnergyTerm& term, unsigned seed, int elementCount = 4,
               int configurations = 5) {
  const std::vector<Residual>& elements = elementsOf<Residual>(term);
  Sampler sampler(seed);
  int probes = 0;
  const size_t stride = std::max<size_t>(1, elements.size() / elementCount);
  for (size_t e = 0; e < elements.size() && probes < elementCount * configurations; e += stride)
    checkResidual(elements[e], sampler, configurations, probes);
  EXPECT_EQ(probes, elementCount * configurations);
}

// A strongly curved rest mesh: a delaunay patch on z = p(x, y), p a cubic with coefficients up
// to 1.5 (rest hinge angles up to 0.73 rad on this coarse mesh).
Mesh curvedRestMesh() {
  std::mt19937 rng(11);
  return testing::lifted(modeling::generateMesh({modeling::MeshFamily::Delaunay, 4, 7, {}}),
                         testing::randomCubic(rng, 1.5));
}

TEST(ResidualGradients, HingeTheta) {
  const BendingSetup setup(curvedRestMesh(), bendingOptions(Discretization::Hinge));
  checkTerm<curvature::HingeBendingResidual>(*setup.term, 1);
}

TEST(ResidualGradients, HingeTan) {
  BendingOptions o = bendingOptions(Discretization::Hinge);
  o.hingeAngle = curvature::HingeAngle::Tan;
  const BendingSetup setup(curvedRestMesh(), o);
  checkTerm<curvature::HingeBendingResidual>(*setup.term, 2);
}

TEST(ResidualGradients, TriangleAveraged) {
  const BendingSetup setup(curvedRestMesh(), bendingOptions(Discretization::TriangleAveraged));
  checkTerm<curvature::TriangleAveragedResidual>(*setup.term, 3);
}

TEST(ResidualGradients, CotanMeanCurvature) {
  const BendingSetup setup(curvedRestMesh(), bendingOptions(Discretization::Cotan));
  checkTerm<curvature::CotanMeanCurvatureResidual>(*setup.term, 4, 6);
}

// Cotan residuals of valence 3 to 8 take fixed-size autodiff, one arity each, and others the
// dynamic one (curvature/element_term.h): every arity from valence 3 to 11, on random one-rings.
TEST(ResidualGradients, CotanEveryValence) {
  int probes = 0;
  for (int valence = 3; valence <= 11; ++valence) {
    SCOPED_TRACE("valence " + std::to_string(valence));
    curvature::CotanMeanCurvatureResidual r;
    for (int k = 0; k <= valence; ++k) r.vertices.push_back(k);
    r.sqrtWeight = 0.7;
    r.restValue = 0.3;
    Sampler sampler(40 + static_cast<unsigned>(valence));
    checkResidual(r, sampler, 3, probes);
  }
  EXPECT_EQ(probes, 9 * 3);
}

TEST(ResidualGradients, QuadraticFit) {
  const BendingSetup setup(curvedRestMesh(), bendingOptions(Discretization::QuadraticFit));
  checkTerm<curvature::QuadraticFitResidual>(*setup.term, 5);
}

// Midedge faces with 0 (a lone triangle), 1 (a corner face), 2 (boundary faces) and 3 flaps
// (interior faces): one cost-function arity each.
TEST(ResidualGradients, MidedgeEveryFlapCount) {
  std::mt19937 rng(12);
  Mesh single;
  single.positions.resize(3, 3);
  single.positions << 0.1, -0.2, 0.3, 1.2, 0.1, -0.4, 0.3, 0.9, 0.5;
  single.triangles.resize(1, 3);
  single.triangles << 0, 1, 2;
  // gridMesh(2, 2): the faces (1, 2, 5) and (3, 7, 6) have two boundary edges.
  const std::vector<Mesh> meshes = {
      single, testing::lifted(testing::gridMesh(2, 2), testing::randomCubic(rng, 0.5)),
      curvedRestMesh()};
  std::array<int, 4> checked{};
  unsigned seed = 20;
  for (const Mesh& mesh : meshes) {
    const BendingSetup setup(mesh, bendingOptions(Discretization::Midedge));
    const auto& elements = elementsOf<curvature::MidedgeResidual>(*setup.term);
    for (int flaps = 0; flaps <= 3; ++flaps) {
      int taken = 0;
      for (const auto& r : elements) {
        if (r.flapCount != flaps || taken == 3) continue;
        Sampler sampler(seed++);
        checkResidual(r, sampler, 5, checked[flaps]);
        ++taken;
      }
    }
  }
  for (int flaps = 0; flaps <= 3; ++flaps)
    EXPECT_GT(checked[flaps], 0) << "no midedge face with " << flaps << " flaps was checked";
}

TEST(ResidualGradients, StvkMembrane) {
  const Mesh rest = curvedRestMesh();
  const modeling::Stencils s = modeling::compileStencils(rest);
  const modeling::RestState r = modeling::precomputeRestState(s, rest.positions);
  curvature::MembraneOptions o;
  o.young = 3.0;
  const auto terms = curvature::makeMembraneEnergy(s, r, o);
  ASSERT_EQ(terms.size(), 1u);
  checkTerm<curvature::StvkMembraneResidual>(*terms[0], 6);
}

TEST(ResidualGradients, ConformalMembrane) {
  const Mesh rest = curvedRestMesh();
  const modeling::Stencils s = modeling::compileStencils(rest);
  const modeling::RestState r = modeling::precomputeRestState(s, rest.positions);
  curvature::MembraneOptions o;
  o.model = curvature::MembraneModel::Conformal;
  o.shapeStiffness = 2.0;
  const auto terms = curvature::makeMembraneEnergy(s, r, o);
  ASSERT_EQ(terms.size(), 1u);
  checkTerm<curvature::ConformalMembraneResidual>(*terms[0], 9);
}

TEST(ResidualGradients, EdgeAndAreaSprings) {
  const Mesh rest = curvedRestMesh();
  const modeling::Stencils s = modeling::compileStencils(rest);
  const modeling::RestState r = modeling::precomputeRestState(s, rest.positions);
  curvature::MembraneOptions o;
  o.model = curvature::MembraneModel::Springs;
  o.lengthStiffness = 2.0;
  o.areaStiffness = 0.5;
  const auto terms = curvature::makeMembraneEnergy(s, r, o);
  ASSERT_EQ(terms.size(), 2u);
  checkTerm<curvature::EdgeSpringResidual>(*terms[0], 7);
  checkTerm<curvature::AreaSpringResidual>(*terms[1], 8);
}

// ---------------------------------------------------------------------------------------------
// Whole terms: ∇E against central differences of E.

// The unknown vector u = (x row by row, ξ) and its inverse.
Eigen::VectorXd unknownsOf(const Positions& x, const Eigen::VectorXd& xi, bool withXi) {
  Eigen::VectorXd u(x.size() + (withXi ? xi.size() : 0));
  u.head(x.size()) = Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
  if (withXi) u.tail(xi.size()) = xi;
  return u;
}

double energyAt(const curvature::EnergyTerm& term, const Eigen::VectorXd& u, Eigen::Index rows,
                const Eigen::VectorXd& xi) {
  const Positions x = Eigen::Map<const Positions>(u.data(), rows, 3);
  if (!term.usesEdgeUnknowns()) return term.energy(x, xi);
  return term.energy(x, u.tail(xi.size()));
}

// max_k |FD_h(u)_k − ∇E_k| / max_k |∇E_k| for h = 1e-4, 1e-5, 1e-6.
std::array<double, 3> differenceErrors(Discretization d, RestCurvature restCurvature,
                                       bool valenceThree = false,
                                       CurvatureMetric metric = CurvatureMetric::Rest) {
  std::mt19937 rng(100 + static_cast<unsigned>(d.index()));
  const Mesh delaunay = modeling::generateMesh({modeling::MeshFamily::Delaunay, 4, 3, {}});
  const Mesh flat = valenceThree ? testing::withValenceThreeVertex(delaunay) : delaunay;
  const Mesh restMesh = testing::lifted(flat, testing::randomCubic(rng, 1.0));
  BendingOptions options = bendingOptions(d, restCurvature);
  options.metric = metric;
  const BendingSetup setup(restMesh, options);
  // Current state: another cubic, plus in-plane and normal jitter of 0.02 (edges ~0.25).
  const Positions x =
      testing::jittered(testing::lifted(flat, testing::randomCubic(rng, 1.0)).positions, rng, 0.02);
  Eigen::VectorXd xi = setup.restXi;
  std::uniform_real_distribution<double> offset(-0.2, 0.2);
  if (setup.term->usesEdgeUnknowns())
    for (Eigen::Index e = 0; e < xi.size(); ++e) xi[e] += offset(rng);

  const optimize::EnergyGradient g = optimize::energyGradient(setup.terms(), x, xi);
  const double energy = setup.term->energy(x, xi);
  EXPECT_GT(energy, 0.0);
  EXPECT_NEAR(g.energy, energy, 1e-13 * energy) << "Ceres' cost is not the energy";
  const bool withXi = setup.term->usesEdgeUnknowns();
  const Eigen::VectorXd u = unknownsOf(x, xi, withXi);
  EXPECT_EQ(g.gradient.size(), u.size());
  const double scale = g.gradient.lpNorm<Eigen::Infinity>();
  EXPECT_GT(scale, 0.0);

  std::array<double, 3> errors{};
  const double steps[3] = {1e-4, 1e-5, 1e-6};
  for (int s = 0; s < 3; ++s) {
    const double h = steps[s];
    double worst = 0.0;
    for (Eigen::Index k = 0; k < u.size(); ++k) {
      Eigen::VectorXd plus = u, minus = u;
      plus[k] += h;
      minus[k] -= h;
      const double fd =
          (energyAt(*setup.term, plus, x.rows(), xi) - energyAt(*setup.term, minus, x.rows(), xi)) /
          (2.0 * h);
      worst = std::max(worst, std::abs(fd - g.gradient[k]));
    }
    errors[s] = worst / scale;
  }
  return errors;
}

// On the rest metric with either rest curvature, and on the current metric (flat rest only).
void expectSecondOrderDifferences(Discretization d) {
  for (int c = 0; c < 3; ++c) {
    const RestCurvature rc = c == 0 ? RestCurvature::FromRest : RestCurvature::Flat;
    const CurvatureMetric metric = c == 2 ? CurvatureMetric::Current : CurvatureMetric::Rest;
    SCOPED_TRACE(c == 0   ? "RestCurvature::FromRest"
                 : c == 1 ? "RestCurvature::Flat"
                          : "CurvatureMetric::Current");
    const std::array<double, 3> e = differenceErrors(d, rc, false, metric);
    // Measured on every energy and rest: 3e-7 – 9e-7, 3e-9 – 9e-9 (a ratio of 100.0, the h² law)
    // and 6e-11 – 1.1e-10, where roundoff ε E / h takes over.
    EXPECT_LT(e[0], 1e-5);
    EXPECT_GT(e[0] / e[1], 50.0);
    EXPECT_LT(e[1], 1e-7);
    EXPECT_LT(e[2], 1e-9);
  }
}

TEST(ResidualGradients, HingeEnergyGradient) {
  expectSecondOrderDifferences(Discretization::Hinge);
}
TEST(ResidualGradients, TriangleAveragedEnergyGradient) {
  expectSecondOrderDifferences(Discretization::TriangleAveraged);
}
TEST(ResidualGradients, CotanEnergyGradient) {
  expectSecondOrderDifferences(Discretization::Cotan);
}
TEST(ResidualGradients, MidedgeEnergyGradient) {
  expectSecondOrderDifferences(Discretization::Midedge);
}
TEST(ResidualGradients, QuadraticFitEnergyGradient) {
  expectSecondOrderDifferences(Discretization::QuadraticFit);
}

// A valence-3 vertex makes two flaps of a face one vertex: Ceres takes the vertex's block once
// (curvature/shared_block_cost.h) and its gradient must still be right. (quadfit refuses such a
// stencil: six points with one repeated fit no unique quadratic.)
TEST(ResidualGradients, RepeatedFlapVertexGradient) {
  for (Discretization d : {Discretization::Hinge, Discretization::TriangleAveraged,
                           Discretization::Cotan, Discretization::Midedge}) {
    SCOPED_TRACE(std::string(curvature::discretizationName(d)));
    const std::array<double, 3> e = differenceErrors(d, RestCurvature::Flat, true);
    EXPECT_LT(e[0], 1e-5);
    EXPECT_GT(e[0] / e[1], 50.0);
    EXPECT_LT(e[1], 1e-7);
  }
}

// optimize::residualJacobian assembles J element by element (EnergyTerm::appendJacobianRows); it
// must be the Jacobian Ceres evaluates from the residual blocks, row for row, also where a
// valence-3 vertex makes one block two slots of an element, and with membrane terms after the
// bending one.
TEST(ResidualJacobian, DirectAssemblyIsCeresJacobian) {
  std::mt19937 rng(7);
  const Mesh flat = testing::withValenceThreeVertex(
      modeling::generateMesh({modeling::MeshFamily::Delaunay, 4, 3, {}}));
  const Mesh restMesh = testing::lifted(flat, testing::randomCubic(rng, 1.0));
  const Positions x =
      testing::jittered(testing::lifted(flat, testing::randomCubic(rng, 1.0)).positions, rng, 0.02);
  for (Discretization d : {Discretization::Hinge, Discretization::TriangleAveraged,
                           Discretization::Cotan, Discretization::Midedge}) {
    SCOPED_TRACE(std::string(curvature::discretizationName(d)));
    const BendingSetup setup(restMesh, bendingOptions(d, RestCurvature::FromRest));
    curvature::MembraneOptions springs;
    springs.model = curvature::MembraneModel::Springs;
    const auto membrane = curvature::makeMembraneEnergy(setup.stencils, setup.rest, springs);
    std::vector<const curvature::EnergyTerm*> terms = {setup.term.get()};
    for (const auto& term : membrane) terms.push_back(term.get());
    Eigen::VectorXd xi = setup.restXi;
    for (Eigen::Index e = 0; e < xi.size(); ++e) xi[e] += 0.01 * static_cast<double>(e % 7);

    const auto ceresJacobian = [&](curvature::Derivatives derivatives) {
      Positions ceresX = x;
      Eigen::VectorXd ceresXi = xi;
      ceres::Problem problem;
      for (int v = 0; v < ceresX.rows(); ++v) problem.AddParameterBlock(ceresX.data() + 3 * v, 3);
      if (setup.term->usesEdgeUnknowns())
        for (Eigen::Index e = 0; e < ceresXi.size(); ++e)
          problem.AddParameterBlock(ceresXi.data() + e, 1);
      for (const auto* term : terms)
        term->addResidualBlocks(problem, ceresX.data(), ceresXi.data(), derivatives);
      ceres::CRSMatrix crs;
      EXPECT_TRUE(
          problem.Evaluate(ceres::Problem::EvaluateOptions(), nullptr, nullptr, nullptr, &crs));
      return Eigen::Map<const optimize::SparseMatrix>(
                 crs.num_rows, crs.num_cols, static_cast<Eigen::Index>(crs.values.size()),
                 crs.rows.data(), crs.cols.data(), crs.values.data())
          .toDense();
    };
    const Eigen::MatrixXd expected = ceresJacobian(curvature::Derivatives::All);
    const Eigen::MatrixXd direct = optimize::residualJacobian(terms, x, xi).toDense();
    ASSERT_EQ(direct.rows(), expected.rows());
    ASSERT_EQ(direct.cols(), expected.cols());
    const double scale = expected.cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 0.0);
    EXPECT_LE((direct - expected).cwiseAbs().maxCoeff(), 1e-14 * scale);

    // Height mode: the z and ξ columns of the same Jacobian, x and y columns zero (bending terms;
    // the membranes, only used in xyz mode, keep full derivatives that the direct rows drop).
    Eigen::MatrixXd heightColumns = expected;
    for (int v = 0; v < x.rows(); ++v) heightColumns.middleCols(3 * v, 2).setZero();
    const Eigen::MatrixXd height =
        optimize::residualJacobian(terms, x, xi, curvature::Derivatives::HeightOnly).toDense();
    EXPECT_LE((height - heightColumns).cwiseAbs().maxCoeff(), 1e-14 * scale);
    Eigen::MatrixXd ceresHeight = ceresJacobian(curvature::Derivatives::HeightOnly);
    const Eigen::Index bendingRows = optimize::residualJacobian({setup.term.get()}, x, xi).rows();
    for (int v = 0; v < x.rows(); ++v) {
      EXPECT_EQ(ceresHeight.block(0, 3 * v, bendingRows, 2).cwiseAbs().maxCoeff(), 0.0);
      ceresHeight.middleCols(3 * v, 2).setZero();
    }
    EXPECT_LE((ceresHeight - heightColumns).cwiseAbs().maxCoeff(), 1e-14 * scale);
  }
}

// A configuration where an element is undefined (here every vertex at one point: faces of zero
// area) is a NumericalError that names the term and the element, not NaN entries in J.
TEST(ResidualJacobian, DegenerateElementIsNamed) {
  const BendingSetup setup(curvedRestMesh(), bendingOptions(Discretization::TriangleAveraged));
  const Positions collapsed = Positions::Zero(setup.rest.positions.rows(), 3);
  try {
    optimize::residualJacobian(setup.terms(), collapsed, setup.restXi);
    FAIL() << "no error for a collapsed mesh";
  } catch (const NumericalError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("face"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("degenerate"));
  }
}

}  // namespace
}  // namespace flexure
