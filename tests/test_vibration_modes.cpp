// Vibration modes (optimize/modes/vibration_modes.h) judged by known spectra: the simply supported
// square (exact λ_mn = π²(m² + n²)), the clamped square (Leissa's tables), the free plate's
// rigid zero modes, residuals of every returned pair, and the nodal lines of the (1,2)/(2,1)
// pair.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/QR>

#include <cmath>
#include <cstdio>
#include <functional>

#include "curvature/bending_energy.h"
#include "curvature/membrane_energy.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "optimize/modes/vibration_modes.h"
#include "optimize/studies/spectrum_study.h"
#include "support/plate.h"

namespace flexure {
namespace {

using curvature::Discretization;
using modeling::MeshFamily;
using optimize::Clamp;
using optimize::ModesOptions;
using optimize::ModesResult;
using optimize::Support;

constexpr double kPi = 3.14159265358979323846;

// The plate of each test, and its modes.
struct Plate : testing::Plate {
  using testing::Plate::Plate;
  ModesResult modes(const ModesOptions& o) const {
    return optimize::vibrationModes(terms(), stencils, rest, restXi, o);
  }
};

std::string nameOf(Discretization d) {
  return std::string(curvature::discretizationName(d));
}

// Every returned pair solves K v = ω² M v to 1e-8.
void expectSmallResiduals(const ModesResult& r, const std::string& what) {
  for (size_t k = 0; k < r.modes.size(); ++k)
    EXPECT_LE(r.modes[k].residual, 1e-8) << what << " mode " << k;
}

// The flexible modes' λ at each level n = 8, 16, 32 (patch48).
std::vector<std::vector<double>> spectra(Discretization d, const ModesOptions& o,
                                         const std::vector<int>& levels) {
  std::vector<std::vector<double>> out;
  for (int n : levels) {
    const ModesResult r = Plate(MeshFamily::Patch48, n, d).modes(o);
    expectSmallResiduals(r, nameOf(d) + " n = " + std::to_string(n));
    std::vector<double> lambdas;
    for (const auto& mode : r.modes)
      if (!mode.zero) lambdas.push_back(mode.lambda);
    out.push_back(lambdas);
  }
  return out;
}

const std::vector<double> kSimplySupported = {2 * kPi * kPi, 5 * kPi* kPi,  5 * kPi* kPi,
                                              8 * kPi* kPi,  10 * kPi* kPi, 10 * kPi* kPi};

TEST(VibrationModes, SimplySupportedSquareConvergesForTheEnergiesThatPassC1) {
  ModesOptions o;
  o.count = 6;
  o.support = Support::SimplySupported;
  for (Discretization d : {Discretization::Cotan, Discretization::Midedge}) {
    const auto lambda = spectra(d, o, {8, 16, 32});
    for (int k = 0; k < 6; ++k) {
      const double e1 = std::abs(lambda[1][k] / kSimplySupported[k] - 1.0);
      const double e2 = std::abs(lambda[2][k] / kSimplySupported[k] - 1.0);
      const double order = std::log2(e1 / e2);
      std::printf("%s simply supported λ_%d = %.4f (exact %.4f): error %.2e, order %.2f\n",
                  nameOf(d).c_str(), k + 1, lambda[2][k], kSimplySupported[k], e2, order);
      EXPECT_GT(order, 0.8) << nameOf(d) << " mode " << k + 1;
      EXPECT_LT(e2, 0.02) << nameOf(d) << " mode " << k + 1;
    }
  }
}

// Quadratic reproduction is not enough: quadfit passes C1 on the 4-8 patch, hinge and triavg do
// not, and none of the three approaches π²(m² + n²) (measured at n = 32: λ₁ = 14.4, 39.4, 24.3
// against 19.74).
TEST(VibrationModes, SimplySupportedSquareIsWrongForHingeTriavgAndQuadfit) {
  ModesOptions o;
  o.count = 1;
  o.support = Support::SimplySupported;
  for (Discretization d :
       {Discretization::Hinge, Discretization::TriangleAveraged, Discretization::QuadraticFit}) {
    const auto lambda = spectra(d, o, {16, 32});
    const double e1 = std::abs(lambda[0][0] / kSimplySupported[0] - 1.0);
    const double e2 = std::abs(lambda[1][0] / kSimplySupported[0] - 1.0);
    std::printf("%s simply supported λ_1 = %.4f at n = 32: error %.2e (n = 16: %.2e)\n",
                nameOf(d).c_str(), lambda[1][0], e2, e1);
    EXPECT_GT(e2, 0.1) << nameOf(d);
    EXPECT_GT(e2, 0.7 * e1) << nameOf(d) << ": the error does not halve under refinement";
  }
}

// Leissa, "The free vibration of rectangular plates", J. Sound Vib. 31(3), 1973, Table for the
// square plate clamped on all four edges (ν-independent): λ = ω a² √(ρh/D).
const std::vector<double> kClamped = {35.992, 73.413, 73.413, 108.27, 131.64, 132.24};

TEST(VibrationModes, ClampedSquareRichardsonExtrapolationMatchesLeissa) {
  struct Case {
    Discretization energy;
    Clamp clamp;
  };
  for (const Case c :
       {Case{Discretization::Midedge, Clamp::Normals}, Case{Discretization::Cotan, Clamp::Rings}}) {
    ModesOptions o;
    o.count = 6;
    o.support = Support::Clamped;
    o.clamp = c.clamp;
    const auto lambda = spectra(c.energy, o, {16, 32, 64});
    for (int k = 0; k < 6; ++k) {
      // The order from three levels, then Richardson from the two finest.
      const double d1 = lambda[1][k] - lambda[0][k], d2 = lambda[2][k] - lambda[1][k];
      const double order = std::log2(d1 / d2);
      const double extrapolated = lambda[2][k] + d2 / (std::pow(2.0, order) - 1.0);
      const double error = std::abs(extrapolated / kClamped[k] - 1.0);
      std::printf("%s clamp %s λ_%d: %.3f %.3f %.3f, order %.2f, extrapolated %.3f (%.2e)\n",
                  nameOf(c.energy).c_str(), optimize::clampName(c.clamp), k + 1, lambda[0][k],
                  lambda[1][k], lambda[2][k], order, extrapolated, error);
      EXPECT_GT(order, 0.8);
      EXPECT_LT(error, 0.01) << nameOf(c.energy) << " mode " << k + 1;
    }
  }
}

// Fixing rings 0 and 1 clamps a plate one edge smaller: λ converges from above at first order,
// and midedge's higher modes are not yet in their asymptotic range at n = 64 (measured: λ₁ 39.36,
// 37.65, 36.81, order 1.03; λ₅ 136.6, 135.9, 134.2). Clamping the midedge normals converges at
// second order from below (the test above).
TEST(VibrationModes, ClampingRingsConvergesFromAboveAtFirstOrder) {
  ModesOptions o;
  o.count = 1;
  o.support = Support::Clamped;
  o.clamp = Clamp::Rings;
  const auto lambda = spectra(Discretization::Midedge, o, {16, 32, 64});
  const double d1 = lambda[1][0] - lambda[0][0], d2 = lambda[2][0] - lambda[1][0];
  EXPECT_GT(lambda[2][0], kClamped[0]);
  EXPECT_LT(d2, 0.0);
  EXPECT_NEAR(std::log2(d1 / d2), 1.0, 0.2);
}

// A free plate in height mode has exactly three rigid zero modes (w = a + bx + cy). midedge and
// hinge have no others; triavg and quadfit leave the 4-8 patch's four corner vertices to no
// element (their faces have boundary edges): four spurious zero modes; cotan measures no
// boundary vertex's curvature, so every discrete harmonic function is a zero mode: one per
// boundary vertex, the rigid three among them.
TEST(VibrationModes, FreePlateHasTheRigidZeroModesAndReportsSpuriousOnes) {
  ModesOptions o;
  o.count = 6;
  o.support = Support::Free;
  const int boundaryVertices = 4 * 16;
  struct Expected {
    Discretization energy;
    int spurious;
  };
  for (const Expected e :
       {Expected{Discretization::Midedge, 0}, Expected{Discretization::Hinge, 0},
        Expected{Discretization::TriangleAveraged, 4}, Expected{Discretization::QuadraticFit, 4},
        Expected{Discretization::Cotan, boundaryVertices - 3}}) {
    const Plate plate(MeshFamily::Patch48, 16, e.energy);
    const ModesResult r = plate.modes(o);
    expectSmallResiduals(r, nameOf(e.energy));
    EXPECT_EQ(r.rigidModes, 3);
    EXPECT_EQ(r.spuriousZeroModes, e.spurious) << nameOf(e.energy);
    EXPECT_EQ(r.flexibleModes, o.count) << nameOf(e.energy);
    if (e.spurious > 0) continue;
    // The zero modes are rigid: each lies in span{1, x, y}.
    Eigen::MatrixXd basis(plate.mesh.vertexCount(), 3);
    basis << Eigen::VectorXd::Ones(plate.mesh.vertexCount()), plate.mesh.positions.col(0),
        plate.mesh.positions.col(1);
    for (int k = 0; k < 3; ++k) {
      const Eigen::VectorXd w = r.modes[k].shape.col(2);
      const Eigen::VectorXd fit = basis * basis.colPivHouseholderQr().solve(w);
      EXPECT_LE((w - fit).norm(), 1e-8 * w.norm()) << nameOf(e.energy) << " zero mode " << k;
    }
  }
  // One vertex held at the centre, as Chladni held his plates: the two tilts about it remain.
  Plate plate(MeshFamily::Patch48, 8, Discretization::Midedge);
  o.extraFixed.assign(plate.mesh.vertexCount(), false);
  for (int v = 0; v < plate.mesh.vertexCount(); ++v)
    if (plate.mesh.positions.row(v).norm() < 1e-12) o.extraFixed[v] = true;
  const ModesResult held = plate.modes(o);
  EXPECT_EQ(held.rigidModes, 2);
  EXPECT_EQ(held.spuriousZeroModes, 0);
}

// The (1,2)/(2,1) pair of the simply supported square: sin πx sin 2πy has the straight nodal
// line y = ½, and (1,2) + (2,1) = 2 sin πx sin πy (cos πx + cos πy) the diagonal x + y = 1
// (coordinates on [0, 1]²; the mesh is [−½, ½]²).
TEST(VibrationModes, NodalLinesOfTheSquaresSecondModesAreStraightOrDiagonal) {
  const int n = 32;
  const Plate plate(MeshFamily::Patch48, n, Discretization::Cotan);
  ModesOptions o;
  o.count = 3;
  o.support = Support::SimplySupported;
  const ModesResult r = plate.modes(o);
  EXPECT_EQ(r.modes[1].multiplicity, 2);
  EXPECT_EQ(r.modes[2].multiplicity, 2);
  const int count = plate.mesh.vertexCount();
  Eigen::MatrixXd pair(count, 2);
  pair << r.modes[1].shape.col(2), r.modes[2].shape.col(2);
  auto analytic = [&](int a, int b) {
    Eigen::VectorXd w(count);
    for (int v = 0; v < count; ++v) {
      const double x = plate.mesh.positions(v, 0) + 0.5, y = plate.mesh.positions(v, 1) + 0.5;
      w[v] = std::sin(a * kPi * x) * std::sin(b * kPi * y);
    }
    return w;
  };
  struct Line {
    Eigen::VectorXd target;
    std::function<double(const Eigen::Vector3d&)> distance;  // from the exact nodal line
  };
  const std::vector<Line> lines = {
      {analytic(1, 2), [](const Eigen::Vector3d& p) { return std::abs(p.y()); }},
      {analytic(2, 1), [](const Eigen::Vector3d& p) { return std::abs(p.x()); }},
      {analytic(1, 2) + analytic(2, 1),
       [](const Eigen::Vector3d& p) { return std::abs(p.x() + p.y()) / std::sqrt(2.0); }},
      {analytic(1, 2) - analytic(2, 1),
       [](const Eigen::Vector3d& p) { return std::abs(p.x() - p.y()) / std::sqrt(2.0); }}};
  for (const Line& line : lines) {
    // The member of the computed eigenspace closest to the analytic mode.
    const Eigen::Vector2d c = pair.colPivHouseholderQr().solve(line.target);
    const Eigen::VectorXd w = pair * c;
    EXPECT_LE((w - line.target).norm(), 0.02 * line.target.norm());
    modeling::Positions shape = modeling::Positions::Zero(count, 3);
    shape.col(2) = w;
    double farthest = 0.0, length = 0.0;
    for (const auto& [a, b] : optimize::nodalSegments(plate.stencils, plate.rest, shape)) {
      // Within two edges of the held boundary the piecewise-linear zero set bends to the held
      // vertices (s = 0 there); the nodal line is judged inside.
      for (const Eigen::Vector3d& p : {a, b})
        if (p.cwiseAbs().maxCoeff() < 0.5 - 2.0 / n)
          farthest = std::max(farthest, line.distance(p));
      length += (b - a).norm();
    }
    std::printf("nodal line: length %.4f, farthest point %.2e from the exact line\n", length,
                farthest);
    EXPECT_LE(farthest, 0.1 / n);
  }
}

// A flat plate in xyz with a membrane: at rest the out-of-plane motion decouples from the
// in-plane one, so with a membrane much stiffer than bending the smallest modes are the bending
// modes of height mode; a free plate has the six rigid motions of space.
TEST(VibrationModes, XyzModeOfAFlatPlateHasTheHeightModeSpectrum) {
  const Plate withMembrane(MeshFamily::Delaunay, 12, Discretization::Midedge, 1e6);
  const Plate plate(MeshFamily::Delaunay, 12, Discretization::Midedge);
  const std::vector<const curvature::EnergyTerm*> terms = withMembrane.terms();
  for (const Support support : {Support::SimplySupported, Support::Free}) {
    ModesOptions o;
    o.count = 4;
    o.support = support;
    const ModesResult height = plate.modes(o);
    o.dof = optimize::DofMode::Xyz;
    const ModesResult xyz =
        optimize::vibrationModes(terms, plate.stencils, plate.rest, plate.restXi, o);
    expectSmallResiduals(xyz, "xyz");
    EXPECT_EQ(xyz.rigidModes, support == Support::Free ? 6 : 0);
    EXPECT_EQ(xyz.spuriousZeroModes, 0);
    std::vector<double> a, b;
    for (const auto& mode : height.modes)
      if (!mode.zero) a.push_back(mode.lambda);
    for (const auto& mode : xyz.modes)
      if (!mode.zero) b.push_back(mode.lambda);
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k) {
      EXPECT_NEAR(b[k] / a[k], 1.0, 1e-8) << optimize::supportName(support) << " mode " << k;
      // A bending mode moves along the normal only.
      const auto& shape = xyz.modes[xyz.rigidModes + k].shape;
      EXPECT_LE(shape.leftCols(2).norm(), 1e-6 * shape.norm());
    }
  }
}

// Voronoi lumping converges to the same spectrum (cotan, simply supported).
TEST(VibrationModes, VoronoiMassesConvergeToo) {
  ModesOptions o;
  o.count = 1;
  o.support = Support::SimplySupported;
  o.mass = optimize::MassLumping::Voronoi;
  const auto lambda = spectra(Discretization::Cotan, o, {16, 32});
  const double e1 = std::abs(lambda[0][0] / kSimplySupported[0] - 1.0);
  const double e2 = std::abs(lambda[1][0] / kSimplySupported[0] - 1.0);
  EXPECT_LT(e2, 2e-3);
  EXPECT_GT(std::log2(e1 / e2), 1.5);
}

// The spectrum study (flexure converge --measure modes) measures what the tests above assert.
TEST(VibrationModes, SpectrumStudyMeasuresTheOrders) {
  EXPECT_NEAR(optimize::squarePlateLambdas(Support::SimplySupported, 6)[5], 10 * kPi * kPi, 1e-12);
  EXPECT_THROW(optimize::squarePlateLambdas(Support::Clamped, 7), InputError);
  EXPECT_THROW(optimize::squarePlateLambdas(Support::Free, 1), InputError);
  optimize::SpectrumStudyOptions o;
  o.energies = {optimize::parseEnergyVariant("midedge"), optimize::parseEnergyVariant("hinge")};
  o.families = {MeshFamily::Patch48};
  o.count = 3;
  o.support = Support::Clamped;
  const auto series = optimize::runSpectrumStudy(o);
  ASSERT_EQ(series.size(), 2u);
  EXPECT_EQ(series[0].clamp, Clamp::Normals);
  for (int k = 0; k < o.count; ++k) {
    ASSERT_TRUE(series[0].orders[k].has_value());
    EXPECT_GT(*series[0].orders[k], 1.5);
    EXPECT_EQ(series[0].verdicts[k], optimize::Refinement::Converges);
    EXPECT_EQ(series[1].verdicts[k], optimize::Refinement::DoesNotConverge);
  }
  o.energies = {optimize::parseEnergyVariant("midedge:free")};
  EXPECT_THROW(optimize::runSpectrumStudy(o), InputError);
}

TEST(VibrationModes, RefusesWhatCannotBeComputed) {
  const Plate hinge(MeshFamily::Patch48, 4, Discretization::Hinge);
  ModesOptions o;
  o.clamp = Clamp::Normals;
  EXPECT_THROW(hinge.modes(o), InputError);  // no midedge normals to clamp
  o.clamp = Clamp::Rings;
  o.count = 1000;
  EXPECT_THROW(hinge.modes(o), InputError);  // more modes than unknowns
  o.count = 0;
  EXPECT_THROW(hinge.modes(o), InputError);
}

// A patch48 plate bent into z = bend x² (curved when bend ≠ 0), nothing held.
modeling::Mesh bentPlate(int n, double bend) {
  modeling::Mesh mesh = testing::generatedPlate(MeshFamily::Patch48, n);
  mesh.positions.col(2) = bend * mesh.positions.col(0).array().square();
  return mesh;
}

struct BentPlate {
  optimize::Problem problem;
  BentPlate(int n, Discretization d, double bend, double young = 0.0)
      : problem(
            testing::buildPlateProblem(bentPlate(n, bend), testing::plateProblem(d, young), {})) {}
  ModesResult modes(const ModesOptions& o) const {
    return optimize::vibrationModes(problem.termPointers(), problem.stencils, problem.rest,
                                    problem.restXi, o);
  }
};

std::string inputErrorOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(VibrationModes, HeightModeOnACurvedRestIsRefusedAndXyzIsNot) {
  const BentPlate curved(6, Discretization::Cotan, 0.2);
  ModesOptions o;
  o.count = 2;
  EXPECT_THAT(inputErrorOf([&] { curved.modes(o); }),
              ::testing::AllOf(::testing::StartsWith("ModesOptions.dof height"),
                               ::testing::HasSubstr("not flat (z spans 0.05 of a largest side 1)"),
                               ::testing::HasSubstr("ModesOptions.dof xyz with a membrane")));
  // Below the tolerance (relative to the plate's size) a rest is flat: round-off is no curvature.
  const BentPlate nearlyFlat(6, Discretization::Cotan, 0.5 * optimize::kFlatRestTolerance);
  EXPECT_TRUE(optimize::restIsFlatPlate(nearlyFlat.problem.rest.positions));
  EXPECT_EQ(nearlyFlat.modes(o).flexibleModes, 2);
  // The shell's modes in xyz; a normals clamp there is refused with what to do instead.
  const BentPlate shell(6, Discretization::Midedge, 0.2, 1e3);
  o.dof = optimize::DofMode::Xyz;
  EXPECT_EQ(shell.modes(o).flexibleModes, 2);
  o.clamp = Clamp::Normals;
  EXPECT_THAT(inputErrorOf([&] { shell.modes(o); }),
              ::testing::AllOf(::testing::StartsWith("ModesOptions.clamp normals"),
                               ::testing::HasSubstr("clamp with ModesOptions.clamp rings")));
}

TEST(VibrationModes, ParticipationRatioIsTheMovingShareOfTheMass) {
  modeling::Positions shape = modeling::Positions::Zero(10, 3);
  const Eigen::VectorXd equal = Eigen::VectorXd::Ones(10);
  shape.row(3) << 0.0, 0.0, 2.0;
  EXPECT_DOUBLE_EQ(optimize::participationRatio(shape, equal), 0.1);  // one vertex of ten
  shape.topRows(4).col(0).setConstant(-1.0);
  shape.row(3).setZero();
  shape(3, 0) = 1.0;
  EXPECT_DOUBLE_EQ(optimize::participationRatio(shape, equal), 0.4);  // four of ten, any sign
  shape.col(0).setConstant(0.5);
  EXPECT_DOUBLE_EQ(optimize::participationRatio(shape, equal), 1.0);
  EXPECT_EQ(optimize::participationRatio(modeling::Positions::Zero(10, 3), equal), 0.0);
}

// A clamped plate's modes spread over the plate; held everywhere but a small disc, its modes are
// the disc's, flagged as localized.
TEST(VibrationModes, ModesOnAFewVerticesAreFlaggedLocalized) {
  const Plate plate(MeshFamily::Patch48, 16, Discretization::Cotan);
  ModesOptions o;
  o.count = 6;
  const ModesResult spread = plate.modes(o);
  ASSERT_EQ(spread.flexibleModes, 6);
  for (const auto& mode : spread.modes) {
    EXPECT_FALSE(mode.localized) << mode.lambda;
    EXPECT_GT(mode.participation, 0.25) << mode.lambda;
  }
  o.extraFixed.assign(plate.mesh.vertexCount(), true);
  int free = 0;
  for (int v = 0; v < plate.mesh.vertexCount(); ++v)
    if (plate.rest.positions.row(v).head<2>().norm() < 0.16) o.extraFixed[v] = false, ++free;
  ASSERT_GE(free, 9);
  ASSERT_LE(free, 25);
  o.count = 2;
  const ModesResult disc = plate.modes(o);
  ASSERT_EQ(disc.flexibleModes, 2);
  for (const auto& mode : disc.modes) {
    EXPECT_TRUE(mode.localized) << mode.lambda;
    EXPECT_LT(mode.participation, 0.05) << mode.lambda;
  }
}

// The message of the InputError that `validate` throws, "" when it throws none.
template <typename Options>
std::string validationError(const Options& options) {
  try {
    options.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(VibrationModes, OptionsNameTheFieldTheyRefuse) {
  EXPECT_EQ(validationError(ModesOptions()), "");
  ModesOptions modes;
  modes.count = 0;
  EXPECT_EQ(validationError(modes), "ModesOptions.count 0: expected at least 1");
  modes.count = 1;
  for (const double density : {0.0, -1.0, std::nan("")}) {
    modes.density = density;
    EXPECT_EQ(validationError(modes), "ModesOptions.density: expected a value > 0") << density;
  }

  optimize::SpectrumStudyOptions study;
  study.energies = {optimize::parseEnergyVariant("hinge")};
  EXPECT_EQ(validationError(study), "");
  const std::vector<std::pair<std::function<void(optimize::SpectrumStudyOptions&)>, std::string>>
      cases = {
          {[](auto& o) { o.energies.clear(); }, "SpectrumStudyOptions.energies: "},
          {[](auto& o) { o.families.clear(); }, "SpectrumStudyOptions.families: "},
          {[](auto& o) { o.baseN = 3; }, "SpectrumStudyOptions.baseN 3: "},
          {[](auto& o) { o.levels = 9; }, "SpectrumStudyOptions.levels 9: "},
          {[](auto& o) { o.count = 13; }, "SpectrumStudyOptions.count 13: "},
          {[](auto& o) {
             o.support = Support::Clamped;
             o.count = 7;  // Leissa tabulates six
           },
           "SpectrumStudyOptions.count 7: "},
          {[](auto& o) { o.support = Support::Free; }, "SpectrumStudyOptions.support free: "},
          {[](auto& o) { o.energies = {optimize::parseEnergyVariant("midedge:free")}; },
           "SpectrumStudyOptions.energies midedge(free): "},
      };
  for (const auto& [spoil, start] : cases) {
    optimize::SpectrumStudyOptions bad = study;
    spoil(bad);
    EXPECT_THAT(validationError(bad), ::testing::StartsWith(start));
    EXPECT_THROW(optimize::runSpectrumStudy(bad), InputError) << start;
  }
}

}  // namespace
}  // namespace flexure
