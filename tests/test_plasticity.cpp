// Plasticity of the bending part (optimize/inelastic/plasticity.h): springback known answers of
// issue #29 — a plate bent cylindrically to κ keeps (κ − κ_y) / (1 + γ), comes back flat below
// κ_y, gives the same result in 1 and 50 load steps, yields in reverse past γ(κ − κ_y)/(1 + γ) =
// κ_y; a sphere yields at κ_y / √3; cotan is refused; nothing changes when nothing yields.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <utility>

#include "modeling/errors.h"
#include "modeling/generators.h"
#include "optimize/inelastic/plasticity.h"
#include "optimize/problem.h"

namespace flexure {
namespace {

using curvature::Discretization;
using optimize::FormingOptions;
using optimize::PlasticityOptions;

modeling::Mesh plateMesh(modeling::MeshFamily family) {
  modeling::GeneratorOptions g;
  g.family = family;
  g.n = 12;
  return modeling::generateMesh(g);
}

// A flat plate (irregular Delaunay unless said) with two rings held on z = p(x, y).
optimize::Problem bentPlate(Discretization d, const modeling::PolynomialSurface& p,
                            modeling::MeshFamily family = modeling::MeshFamily::Delaunay) {
  optimize::ProblemOptions o;
  o.bending.discretization = d;
  o.fixedRings = 2;
  o.boundarySurface = p;
  return optimize::buildProblem(plateMesh(family), o);
}

// κ/2 (x cos α + y sin α)²: a cylinder of curvature κ bent about the axis at angle α + 90°.
modeling::PolynomialSurface cylinder(double kappa, double alpha) {
  const double c = std::cos(alpha), s = std::sin(alpha);
  return modeling::PolynomialSurface::quadratic(kappa / 2 * c * c, kappa * c * s,
                                                kappa / 2 * s * s);
}

struct QuadraticFit {
  Eigen::Vector2d curvatures;  // eigenvalues of the fitted Hessian, ascending
  double planeDeviation;       // max |z − the fitted plane| (the quadratic terms ignored)
};

// The least-squares z = ½ (A x² + 2 B x y + C y²) + D x + E y + F over all vertices.
QuadraticFit fitQuadratic(const modeling::Positions& x, bool withQuadratic) {
  const int columns = withQuadratic ? 6 : 3;
  Eigen::MatrixXd m(x.rows(), columns);
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    const double px = x(v, 0), py = x(v, 1);
    m(v, 0) = 1, m(v, 1) = px, m(v, 2) = py;
    if (withQuadratic) m(v, 3) = px * px / 2, m(v, 4) = px * py, m(v, 5) = py * py / 2;
  }
  const Eigen::VectorXd z = x.col(2);
  const Eigen::VectorXd c = m.colPivHouseholderQr().solve(z);
  QuadraticFit fit{Eigen::Vector2d::Zero(), (m * c - z).cwiseAbs().maxCoeff()};
  if (withQuadratic) {
    Eigen::Matrix2d h;
    h << c(3), c(4), c(4), c(5);
    fit.curvatures = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(h).eigenvalues();
  }
  return fit;
}

optimize::FormingResult form(Discretization d, const modeling::PolynomialSurface& p,
                             PlasticityOptions plasticity, int steps, bool release,
                             modeling::MeshFamily family = modeling::MeshFamily::Delaunay) {
  optimize::Problem problem = bentPlate(d, p, family);
  FormingOptions forming;
  forming.loadSteps = steps;
  forming.release = release;
  return optimize::formPlastically(problem, plasticity, forming, {});
}

PlasticityOptions yieldAt(double kappaY, double gamma) {
  PlasticityOptions o;
  o.yieldCurvature = kappaY;
  o.hardening = gamma;
  return o;
}

TEST(Plasticity, CylinderSpringsBackToTheReducedCurvature) {
  const double kappa = 0.2, kappaY = 0.1, gamma = 0.5;
  ASSERT_LT(gamma * (kappa - kappaY) / (1 + gamma), kappaY);  // no reverse yield
  // Measured relative errors of the kept curvature: midedge on the Delaunay plate below 1 %;
  // quadfit there 2.4 %; triavg's shape operator is not consistent on irregular or 4-8 meshes
  // (7 % on this Delaunay plate, 25 % on patch48) and is checked on the criss mesh; the hinge's
  // scalar law (an edge's angle over 2 h̄_e read as a curvature, whatever the edge's direction)
  // keeps 17 % too much on both meshes.
  struct Case {
    Discretization discretization;
    modeling::MeshFamily family;
    double tolerance;
  };
  const Case cases[] = {{Discretization::Midedge, modeling::MeshFamily::Delaunay, 0.02},
                        {Discretization::QuadraticFit, modeling::MeshFamily::Delaunay, 0.03},
                        {Discretization::TriangleAveraged, modeling::MeshFamily::Criss, 0.02},
                        {Discretization::Hinge, modeling::MeshFamily::Delaunay, 0.2}};
  for (const auto& [d, family, tolerance] : cases) {
    for (double alpha : {0.0, 0.5236}) {
      const auto formed = form(d, cylinder(kappa, alpha), yieldAt(kappaY, gamma), 4, true, family);
      ASSERT_TRUE(formed.report.converged);
      const QuadraticFit fit = fitQuadratic(formed.positions, true);
      const double expected = (kappa - kappaY) / (1 + gamma);
      EXPECT_NEAR(fit.curvatures[1], expected, tolerance * expected)
          << curvature::discretizationName(d) << " " << alpha;
      EXPECT_NEAR(fit.curvatures[0], 0.0, tolerance * expected)
          << curvature::discretizationName(d) << " " << alpha;
      EXPECT_GT(formed.report.dissipation, 0.0);
    }
  }
}

TEST(Plasticity, BelowYieldComesBackFlat) {
  const auto formed =
      form(Discretization::Midedge, cylinder(0.09, 0.3), yieldAt(0.1, 0.5), 3, true);
  ASSERT_TRUE(formed.report.converged);
  EXPECT_EQ(formed.report.yieldedElements, 0);
  EXPECT_LT(fitQuadratic(formed.positions, false).planeDeviation, 1e-8);
}

TEST(Plasticity, OneAndFiftyLoadStepsAgreeWithHardening) {
  const auto surface = cylinder(0.25, 0.2);
  const auto one = form(Discretization::Midedge, surface, yieldAt(0.1, 1.0), 1, true);
  const auto fifty = form(Discretization::Midedge, surface, yieldAt(0.1, 1.0), 50, true);
  ASSERT_TRUE(one.report.converged && fifty.report.converged);
  const double kappa1 = fitQuadratic(one.positions, true).curvatures[1];
  const double kappa50 = fitQuadratic(fifty.positions, true).curvatures[1];
  // Radial return is exact for proportional strain paths; on the discrete plate the faces beside
  // the held rings see a slightly non-proportional path (measured: kept curvatures 1.5e-5 apart,
  // plastic strains at most 1.7e-3 κ_y apart).
  EXPECT_NEAR(kappa1, kappa50, 1e-4 * kappa1);
  EXPECT_NEAR(kappa1, 0.15 / 2, 0.02 * 0.15 / 2);
  EXPECT_LT((one.state.plasticStrain - fifty.state.plasticStrain).cwiseAbs().maxCoeff(),
            5e-3 * 0.1);
}

// Past γ(κ − κ_y)/(1 + γ) = κ_y, unloading yields in reverse until γ |P| = κ_y: the free plate
// keeps κ_y / γ rather than (κ − κ_y) / (1 + γ).
TEST(Plasticity, ReverseYieldBeyondTheCondition) {
  const double kappa = 0.5, kappaY = 0.05, gamma = 4.0;
  ASSERT_GT(gamma * (kappa - kappaY) / (1 + gamma), kappaY);
  const auto formed =
      form(Discretization::Midedge, cylinder(kappa, 0.0), yieldAt(kappaY, gamma), 5, true);
  ASSERT_TRUE(formed.report.converged);
  const double kept = fitQuadratic(formed.positions, true).curvatures[1];
  EXPECT_NEAR(kept, kappaY / gamma, 0.02 * kappaY / gamma);
  EXPECT_GT(std::abs(kept - (kappa - kappaY) / (1 + gamma)), 0.5 * (kappa - kappaY) / (1 + gamma));
}

TEST(Plasticity, SphereYieldsAtKappaYOverRootThree) {
  const double kappaY = 0.1, onset = kappaY / std::sqrt(3.0);
  const auto sphere = [](double k) {
    return modeling::PolynomialSurface::quadratic(k / 2, 0, k / 2);
  };
  const auto below =
      form(Discretization::Midedge, sphere(0.9 * onset), yieldAt(kappaY, 0), 1, false);
  const auto above =
      form(Discretization::Midedge, sphere(1.1 * onset), yieldAt(kappaY, 0), 1, false);
  ASSERT_TRUE(below.report.converged && above.report.converged);
  EXPECT_EQ(below.report.yieldedElements, 0);
  EXPECT_GT(above.report.yieldedElements, 0);
}

TEST(Plasticity, NothingYieldingChangesNothing) {
  const auto surface = cylinder(0.2, 0.4);
  optimize::Problem problem = bentPlate(Discretization::TriangleAveraged, surface);
  const optimize::MinimizeResult elastic = optimize::minimize(problem, {});
  const auto formed = form(Discretization::TriangleAveraged, surface, yieldAt(1e3, 0), 1, false);
  ASSERT_TRUE(formed.report.converged);
  EXPECT_EQ(formed.report.solves, 1);
  EXPECT_TRUE(formed.positions == elastic.positions);  // bit for bit
}

TEST(Plasticity, CotanIsRefusedWithAReason) {
  optimize::Problem problem = bentPlate(Discretization::Cotan, cylinder(0.2, 0));
  EXPECT_THAT([&] { optimize::formPlastically(problem, yieldAt(0.1, 0), {}, {}); },
              ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("cotan")));
}

TEST(Plasticity, OptionsValidate) {
  EXPECT_THROW(yieldAt(-1, 0).validate(), InputError);
  EXPECT_THROW(yieldAt(0.1, -0.5).validate(), InputError);
  PlasticityOptions strain;
  strain.yieldStrain = 0.01;
  EXPECT_THROW(strain.validate(), InputError);
  FormingOptions forming;
  forming.loadSteps = 0;
  EXPECT_THROW(forming.validate(), InputError);
}

}  // namespace
}  // namespace flexure
