// Plasticity (optimize/inelastic/plasticity.h): the known answers of issue #29. Bending — a plate
// bent cylindrically to κ keeps (κ − κ_y) / (1 + γ), comes back flat below κ_y, gives the same
// result in 1 and 50 load steps, yields in reverse past γ(κ − κ_y)/(1 + γ) = κ_y; a sphere yields
// at κ_y / √3; cotan is refused; nothing changes when nothing yields. Membrane — a plate stretched
// with its width held (strain diag(ε, 0)) yields at ε_y, keeps (ε − ε_y)/(1 + γ) when released,
// the same in 1 and 50 load steps; a face inside the surface in each part alone yields under both
// when f_m + f_b > 1; a yield strain without a stvk membrane is refused.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <optional>
#include <utility>

#include "curvature/membrane_energy.h"
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
  // (7 % on this Delaunay plate, 25 % on patch48) and is checked on the criss mesh. The hinge's
  // per-face law (its angles read as face tensors, curvature/hinge_face_tensors.h) keeps, over
  // the expected, 1.003 / 0.966 (axis 0° / 30°) on Delaunay and 0.997 / 0.974 on criss (the old
  // per-edge scalar law: 1.17 / 1.18 and 1.33 / 1.39); on patch48 0.79 / 0.79, not checked: the
  // hinge energy's own equilibrium there is not the interpolated cylinder, and its face reads
  // are low (median 0.85 κ at κ = 0.09).
  struct Case {
    Discretization discretization;
    modeling::MeshFamily family;
    double tolerance;
  };
  const Case cases[] = {{Discretization::Midedge, modeling::MeshFamily::Delaunay, 0.02},
                        {Discretization::QuadraticFit, modeling::MeshFamily::Delaunay, 0.03},
                        {Discretization::TriangleAveraged, modeling::MeshFamily::Criss, 0.02},
                        {Discretization::Hinge, modeling::MeshFamily::Delaunay, 0.04},
                        {Discretization::Hinge, modeling::MeshFamily::Criss, 0.03}};
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
  for (const Discretization d : {Discretization::Midedge, Discretization::Hinge}) {
    const auto formed = form(d, cylinder(kappa, 0.0), yieldAt(kappaY, gamma), 5, true);
    ASSERT_TRUE(formed.report.converged) << curvature::discretizationName(d);
    const double kept = fitQuadratic(formed.positions, true).curvatures[1];
    EXPECT_NEAR(kept, kappaY / gamma, 0.02 * kappaY / gamma) << curvature::discretizationName(d);
    EXPECT_GT(std::abs(kept - (kappa - kappaY) / (1 + gamma)),
              0.5 * (kappa - kappaY) / (1 + gamma));
  }
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
  EXPECT_NO_THROW(strain.validate());
  strain.yieldStrain = 0.0;
  EXPECT_THROW(strain.validate(), InputError);
  FormingOptions forming;
  forming.loadSteps = 0;
  EXPECT_THROW(forming.validate(), InputError);
}

// ---- membrane plasticity -------------------------------------------------------------------

// A flat plate in xyz mode with a stvk membrane (Y = 1e3, ν = 0.3), `rings` boundary rings held at
// (λ x̄, ȳ, κ x̄²/2), λ = √(1 + 2 ε): with κ = 0, a homogeneous Green strain diag(ε, 0) (the width
// held), the free vertices starting there.
optimize::Problem stretchedPlate(Discretization d, modeling::MeshFamily family, double strain,
                                 double kappa = 0.0, int rings = 1) {
  const modeling::Mesh mesh = plateMesh(family);
  optimize::ProblemOptions o;
  o.bending.discretization = d;
  o.dof = optimize::DofMode::Xyz;
  o.membrane = curvature::MembraneOptions{};
  o.fixedRings = rings;
  o.boundaryNormals = optimize::BoundaryNormals::Free;  // midedge: ξ free
  o.boundaryPositions = mesh.positions;
  o.boundaryPositions.col(0) *= std::sqrt(1.0 + 2.0 * strain);
  o.boundaryPositions.col(2) = kappa / 2 * mesh.positions.col(0).array().square();
  return optimize::buildProblem(mesh, o);
}

PlasticityOptions strainYieldAt(double epsilonY, double gamma) {
  PlasticityOptions o;
  o.yieldStrain = epsilonY;
  o.hardening = gamma;
  return o;
}

optimize::FormingResult formStretched(optimize::Problem problem, PlasticityOptions plasticity,
                                      int steps, bool release) {
  FormingOptions forming;
  forming.loadSteps = steps;
  forming.release = release;
  return optimize::formPlastically(problem, plasticity, forming, {});
}

// Per face, the Green strain ½(FᵀF − I) of `x` against the rest plate, (ε_xx, ε_xy, ε_yy) in the
// rest's x, y axes.
Eigen::MatrixXd faceGreenStrains(const optimize::Problem& problem, const modeling::Positions& x) {
  Eigen::MatrixXd out(problem.stencils.faceCount(), 3);
  for (int f = 0; f < problem.stencils.faceCount(); ++f) {
    const int v0 = problem.stencils.faces(f, 0), v1 = problem.stencils.faces(f, 1),
              v2 = problem.stencils.faces(f, 2);
    Eigen::Matrix2d rest;
    rest.col(0) = (problem.rest.positions.row(v1) - problem.rest.positions.row(v0)).head<2>();
    rest.col(1) = (problem.rest.positions.row(v2) - problem.rest.positions.row(v0)).head<2>();
    Eigen::Matrix<double, 3, 2> current;
    current.col(0) = (x.row(v1) - x.row(v0)).transpose();
    current.col(1) = (x.row(v2) - x.row(v0)).transpose();
    const Eigen::Matrix<double, 3, 2> deformation = current * rest.inverse();
    const Eigen::Matrix2d strain =
        0.5 * (deformation.transpose() * deformation - Eigen::Matrix2d::Identity());
    out.row(f) << strain(0, 0), strain(0, 1), strain(1, 1);
  }
  return out;
}

TEST(MembranePlasticity, StretchWithTheWidthHeldYieldsAtTheYieldStrain) {
  const double epsilonY = 0.01;
  for (double ratio : {0.99, 1.01}) {
    const auto formed = formStretched(
        stretchedPlate(Discretization::Hinge, modeling::MeshFamily::Delaunay, ratio * epsilonY),
        strainYieldAt(epsilonY, 0.0), 1, false);
    ASSERT_TRUE(formed.report.converged) << ratio;
    if (ratio < 1) {
      EXPECT_EQ(formed.report.yieldedFaces, 0);
      EXPECT_EQ(formed.state.membranePlasticStrain.cwiseAbs().maxCoeff(), 0.0);
    } else {
      // Homogeneous: every face yields, to P = diag(ε − ε_y, 0).
      EXPECT_EQ(formed.report.yieldedFaces, static_cast<int>(formed.state.membraneYielded.size()));
      const Eigen::VectorXd trace =
          formed.state.membranePlasticStrain.col(0) + formed.state.membranePlasticStrain.col(2);
      EXPECT_NEAR(trace.minCoeff(), 0.01 * epsilonY, 1e-3 * epsilonY);
      EXPECT_NEAR(trace.maxCoeff(), 0.01 * epsilonY, 1e-3 * epsilonY);
    }
    EXPECT_EQ(formed.report.yieldedElements, 0);  // no yield curvature: bending elastic
  }
}

TEST(MembranePlasticity, ReleasedStripKeepsTheReducedStrain) {
  const double epsilon = 0.03, epsilonY = 0.01, gamma = 0.5;
  const double kept = (epsilon - epsilonY) / (1 + gamma);
  ASSERT_LT(gamma * kept, epsilonY);  // the release does not yield in reverse
  for (auto family : {modeling::MeshFamily::Criss, modeling::MeshFamily::Delaunay}) {
    optimize::Problem problem = stretchedPlate(Discretization::Hinge, family, epsilon);
    const auto formed = formStretched(std::move(problem), strainYieldAt(epsilonY, gamma), 3, true);
    ASSERT_TRUE(formed.report.converged);
    const Eigen::MatrixXd strain =
        faceGreenStrains(stretchedPlate(Discretization::Hinge, family, 0.0), formed.positions);
    // Every face, the three pinned ones included, keeps diag(kept, 0) to 2 % of kept.
    EXPECT_NEAR(strain.col(0).minCoeff(), kept, 0.02 * kept);
    EXPECT_NEAR(strain.col(0).maxCoeff(), kept, 0.02 * kept);
    EXPECT_LT(strain.col(1).cwiseAbs().maxCoeff(), 0.02 * kept);
    EXPECT_LT(strain.col(2).cwiseAbs().maxCoeff(), 0.02 * kept);
    EXPECT_GT(formed.report.dissipation, 0.0);
  }
}

TEST(MembranePlasticity, OneAndFiftyLoadStepsAgreeWithHardening) {
  const double epsilon = 0.025, epsilonY = 0.01, gamma = 1.0;
  const auto problem = [&] {
    return stretchedPlate(Discretization::Hinge, modeling::MeshFamily::Delaunay, epsilon);
  };
  const auto one = formStretched(problem(), strainYieldAt(epsilonY, gamma), 1, true);
  const auto fifty = formStretched(problem(), strainYieldAt(epsilonY, gamma), 50, true);
  ASSERT_TRUE(one.report.converged && fifty.report.converged);
  const double kept = (epsilon - epsilonY) / (1 + gamma);
  // P = diag(kept, 0) in x, y: its trace in each face's frame.
  const Eigen::VectorXd trace =
      one.state.membranePlasticStrain.col(0) + one.state.membranePlasticStrain.col(2);
  EXPECT_NEAR(trace.minCoeff(), kept, 0.02 * kept);
  EXPECT_NEAR(trace.maxCoeff(), kept, 0.02 * kept);
  EXPECT_LT(
      (one.state.membranePlasticStrain - fifty.state.membranePlasticStrain).cwiseAbs().maxCoeff(),
      1e-6 * kept);
  EXPECT_LT((one.positions - fifty.positions).cwiseAbs().maxCoeff(), 1e-6);
}

// Stretched to 0.8 ε_y and bent to 0.8 κ_y: f_m ≈ f_b ≈ 0.64, each inside the surface, f_m + f_b
// ≈ 1.3 outside it.
TEST(MembranePlasticity, CombinedLoadingYieldsWhereNeitherPartAlone) {
  const double epsilonY = 0.01, kappaY = 0.1;
  const auto formWith = [&](std::optional<double> strain, std::optional<double> curvature) {
    PlasticityOptions o;
    o.yieldStrain = strain;
    o.yieldCurvature = curvature;
    return formStretched(stretchedPlate(Discretization::Midedge, modeling::MeshFamily::Delaunay,
                                        0.8 * epsilonY, 0.8 * kappaY, 2),
                         o, 1, false);
  };
  const auto membraneAlone = formWith(epsilonY, std::nullopt);
  const auto bendingAlone = formWith(std::nullopt, kappaY);
  const auto both = formWith(epsilonY, kappaY);
  ASSERT_TRUE(membraneAlone.report.converged && bendingAlone.report.converged &&
              both.report.converged);
  EXPECT_EQ(membraneAlone.report.yieldedFaces, 0);
  EXPECT_EQ(bendingAlone.report.yieldedElements, 0);
  EXPECT_GT(both.report.yieldedFaces, 0);
  EXPECT_GT(both.report.yieldedElements, 0);
  EXPECT_GT(both.report.dissipation, 0.0);
}

TEST(MembranePlasticity, AYieldStrainNeedsAStvkMembrane) {
  optimize::Problem height = bentPlate(Discretization::Midedge, cylinder(0.2, 0));
  EXPECT_THAT([&] { optimize::formPlastically(height, strainYieldAt(0.01, 0), {}, {}); },
              ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("no membrane")));
  optimize::ProblemOptions o;
  o.dof = optimize::DofMode::Xyz;
  o.membrane = curvature::MembraneOptions{};
  o.membrane->model = curvature::MembraneModel::Springs;
  optimize::Problem springs = optimize::buildProblem(plateMesh(modeling::MeshFamily::Criss), o);
  EXPECT_THAT([&] { optimize::formPlastically(springs, strainYieldAt(0.01, 0), {}, {}); },
              ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("edge springs membrane")));
}

TEST(MembranePlasticity, NothingYieldingChangesNothing) {
  optimize::Problem problem =
      stretchedPlate(Discretization::Hinge, modeling::MeshFamily::Delaunay, 0.02, 0.1, 2);
  const optimize::MinimizeResult elastic = optimize::minimize(problem, {});
  PlasticityOptions high = strainYieldAt(1e3, 0);
  high.yieldCurvature = 1e3;
  const auto formed = formStretched(
      stretchedPlate(Discretization::Hinge, modeling::MeshFamily::Delaunay, 0.02, 0.1, 2), high, 1,
      false);
  ASSERT_TRUE(formed.report.converged);
  EXPECT_EQ(formed.report.solves, 1);
  EXPECT_TRUE(formed.positions == elastic.positions);  // bit for bit
}

}  // namespace
}  // namespace flexure
