// The energy registry: lookups, the built-ins' order, the default lists generated from the
// entries, and a test-only energy — registered here and defined nowhere else — run through
// energy, gradient, Hessian, minimize, time stepping, vibration modes and the spectrum study.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "curvature/element_term.h"
#include "curvature/energy_registry.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/boundary_conditions.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/modes/vibration_modes.h"
#include "optimize/problem.h"
#include "optimize/solvers/minimize.h"
#include "optimize/studies/spectrum_study.h"
#include "support/plate.h"

namespace flexure {
namespace {

using curvature::Discretization;
using curvature::EnergyEntry;
using modeling::Positions;

// The test-only energy: the Dirichlet energy of the height over the flat rest metric,
//   E = k_B Σ_T Ā_T |∇z|²,   ∇z = Σ_i z_i ∇φ_i,   ∇φ_i = J n̄-rotated edge i / (2 Ā_T),
// with φ_i the rest hat functions (∇φ_i = (ȳ_{i+1} − ȳ_{i+2}, x̄_{i+2} − x̄_{i+1}) / (2 Ā_T) on a
// counter-clockwise face). Residuals r = √(2 k_B Ā_T) ∇z, so ½ |r|² is the face's energy. On
// z = a x + b y, E = k_B (a² + b²) Σ Ā_T; its minimizer with the boundary on a plane is the plane.
struct HeightDirichletResidual {
  static constexpr int kResiduals = 2;
  using BlockSizes = std::integer_sequence<int, 3, 3, 3>;
  std::array<int, 3> vertices;
  std::array<std::array<double, 2>, 3> hatGradients;  // √(2 k_B Ā_T) ∇φ_i

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    r[0] = T(0.0);
    r[1] = T(0.0);
    for (int i = 0; i < 3; ++i) {
      r[0] += T(hatGradients[i][0]) * x[i][2];
      r[1] += T(hatGradients[i][1]) * x[i][2];
    }
    return true;
  }
};

std::unique_ptr<curvature::EnergyTerm> makeHeightDirichlet(const modeling::Stencils& s,
                                                           const modeling::RestState& rest,
                                                           const curvature::BendingOptions& o,
                                                           double /*poisson*/) {
  std::vector<HeightDirichletResidual> elements;
  std::vector<int> ids;
  for (int f = 0; f < s.faceCount(); ++f) {
    HeightDirichletResidual r;
    const double area = rest.faceAreas[f];
    const double scale = std::sqrt(2.0 * o.stiffness * area) / (2.0 * area);
    for (int i = 0; i < 3; ++i) r.vertices[i] = s.faces(f, i);
    for (int i = 0; i < 3; ++i) {
      const int next = r.vertices[(i + 1) % 3], last = r.vertices[(i + 2) % 3];
      r.hatGradients[i] = {scale * (rest.positions(next, 1) - rest.positions(last, 1)),
                           scale * (rest.positions(last, 0) - rest.positions(next, 0))};
    }
    elements.push_back(r);
    ids.push_back(f);
  }
  return std::make_unique<curvature::ElementTerm<HeightDirichletResidual>>(
      "dirichlet", "face", std::move(elements), std::move(ids), rest.faceAreas.sum(), false);
}

EnergyEntry heightDirichletEntry(std::string name) {
  EnergyEntry e;
  e.name = std::move(name);
  e.description = "Dirichlet energy of the height (test only)";
  e.poissonRule = curvature::PoissonRule::MeanCurvatureOnly;
  e.elementKind = curvature::ElementKind::Face;
  e.make = makeHeightDirichlet;
  return e;
}

// Registered once per test binary, by the one registration line an energy needs.
Discretization heightDirichlet() {
  static const Discretization d = curvature::registerEnergy(heightDirichletEntry("dirichlet"));
  return d;
}

struct PlateSetup {
  modeling::Mesh mesh;
  modeling::Stencils stencils;
  modeling::RestState rest;
  std::unique_ptr<curvature::EnergyTerm> term;

  explicit PlateSetup(double stiffness) {
    modeling::GeneratorOptions g;
    g.n = 6;
    mesh = modeling::generateMesh(g);
    stencils = modeling::compileStencils(mesh);
    rest = modeling::precomputeRestState(stencils, mesh.positions);
    curvature::BendingOptions o;
    o.discretization = heightDirichlet();
    o.stiffness = stiffness;
    term = curvature::makeBendingEnergy(stencils, rest, o);
  }
};

// z = a x + b y, and a curved z for the derivative checks.
constexpr double kA = 0.7, kB = -0.4;
Positions onPlane(const Positions& rest) {
  Positions x = rest;
  for (int v = 0; v < x.rows(); ++v) x(v, 2) = kA * rest(v, 0) + kB * rest(v, 1);
  return x;
}
Positions curved(const Positions& rest) {
  Positions x = rest;
  for (int v = 0; v < x.rows(); ++v)
    x(v, 2) = std::sin(2.0 * rest(v, 0)) * rest(v, 1) + 0.3 * rest(v, 0) * rest(v, 0);
  return x;
}

TEST(EnergyRegistry, BuiltinsAreInDocsOrder) {
  const auto& entries = curvature::registeredEnergies();
  ASSERT_GE(entries.size(), 5u);
  const std::vector<std::string> docsOrder = {"hinge", "triavg", "cotan", "midedge", "quadfit"};
  for (size_t k = 0; k < docsOrder.size(); ++k) {
    EXPECT_EQ(entries[k].name, docsOrder[k]);
    EXPECT_EQ(curvature::discretizationName(curvature::builtinDiscretizations()[k]), docsOrder[k]);
  }
  EXPECT_EQ(curvature::parseDiscretization("MidEdge"), Discretization::Midedge);
  EXPECT_TRUE(curvature::energyEntry(Discretization::Midedge).restEdgeUnknowns);
  EXPECT_FALSE(curvature::energyEntry(Discretization::Cotan).restEdgeUnknowns);
  EXPECT_EQ(curvature::energyEntry(Discretization::Hinge).poissonRule,
            curvature::PoissonRule::MeanCurvatureOnly);
  EXPECT_EQ(curvature::energyEntry(Discretization::QuadraticFit).poissonRule,
            curvature::PoissonRule::Koiter);
  heightDirichlet();  // a run-time energy is not a built-in
  EXPECT_EQ(curvature::builtinDiscretizations().size(), docsOrder.size());
  EXPECT_EQ(curvature::findEnergy("QuadFit"), &entries[4]);
  EXPECT_EQ(curvature::findEnergy("membrane"), nullptr);
}

// The lists other parts take from the entries: the spectrum study's default energies and labels,
// the energy curvature maps measure H with, the names messages give.
TEST(EnergyRegistry, DefaultListsComeFromTheEntries) {
  heightDirichlet();  // registered without a spectrum rank or a mean-curvature field
  std::vector<std::string> spectrum;
  for (const optimize::EnergyVariant& v : optimize::defaultSpectrumEnergies())
    spectrum.push_back(optimize::spectrumLabel(v));
  EXPECT_EQ(spectrum,
            (std::vector<std::string>{"midedge", "cotan(voronoi)", "quadfit", "triavg", "hinge"}));
  EXPECT_EQ(optimize::spectrumLabel(optimize::parseEnergyVariant("midedge:free")),
            "midedge(free)");  // the study refuses it, by this name
  EXPECT_EQ(optimize::spectrumLabel(optimize::parseEnergyVariant("dirichlet")), "dirichlet");

  EXPECT_EQ(curvature::defaultMeanCurvatureEnergy().name, "cotan");
  EXPECT_EQ(curvature::energyNamesWhere(
                [](const EnergyEntry& e) { return static_cast<bool>(e.meanCurvatureField); }),
            "cotan");
  EXPECT_EQ(curvature::energyNamesWhere(&EnergyEntry::hasEdgeUnknowns), "midedge");

  // A normals clamp names the energies that have normals to hold.
  optimize::ModesSpec spec;
  spec.clamp = optimize::Clamp::Normals;
  curvature::BendingOptions dirichlet;
  dirichlet.discretization = heightDirichlet();
  try {
    spec.forEnergy(dirichlet);
    ADD_FAILURE() << "a normals clamp was accepted for an energy without edge unknowns";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("holds the midedge normals: dirichlet has none"));
  }
}

TEST(EnergyRegistry, UnknownNameListsTheRegisteredNames) {
  heightDirichlet();
  try {
    curvature::parseDiscretization("membrane");
    ADD_FAILURE() << "an unknown energy was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("'membrane'"));
    EXPECT_THAT(e.what(),
                ::testing::HasSubstr("hinge, triavg, cotan, midedge, quadfit or dirichlet"));
  }
  EXPECT_THROW(curvature::registerEnergy(heightDirichletEntry("Hinge")), InputError);
}

TEST(EnergyRegistry, TestEnergyHasItsKnownValueAndRule) {
  const Discretization d = heightDirichlet();
  EXPECT_EQ(curvature::parseDiscretization("Dirichlet"), d);
  curvature::BendingOptions o;
  o.discretization = d;
  EXPECT_EQ(curvature::effectivePoisson(o), 1.0);
  o.poisson = 0.3;
  EXPECT_THROW(curvature::effectivePoisson(o), InputError);  // a ν = 1 rule, from its entry

  const PlateSetup setup(1.5);
  EXPECT_EQ(setup.term->elementCount(), setup.stencils.faceCount());
  const double area = setup.rest.faceAreas.sum();
  const Eigen::VectorXd noXi;
  EXPECT_NEAR(setup.term->energy(onPlane(setup.rest.positions), noXi),
              1.5 * (kA * kA + kB * kB) * area, 1e-13);
  EXPECT_EQ(setup.term->energy(setup.rest.positions, noXi), 0.0);
}

// ∇E against central differences of E, and the exact Hessian against central differences of
// ∇E (E is quadratic: both agree to rounding).
TEST(EnergyRegistry, TestEnergyGradientAndHessianMatchFiniteDifferences) {
  const PlateSetup setup(1.0);
  const std::vector<const curvature::EnergyTerm*> terms = {setup.term.get()};
  const Positions x = curved(setup.rest.positions);
  const Eigen::VectorXd noXi;
  const optimize::EnergyGradient g = optimize::energyGradient(terms, x, noXi);
  const double h = 1e-5;
  double gradientError = 0.0, gradientScale = 0.0;
  for (int v = 0; v < x.rows(); ++v) {
    for (int c = 0; c < 3; ++c) {
      Positions plus = x, minus = x;
      plus(v, c) += h;
      minus(v, c) -= h;
      const double fd =
          (setup.term->energy(plus, noXi) - setup.term->energy(minus, noXi)) / (2.0 * h);
      gradientError = std::max(gradientError, std::abs(fd - g.gradient[3 * v + c]));
      gradientScale = std::max(gradientScale, std::abs(fd));
    }
  }
  EXPECT_GT(gradientScale, 0.1);
  EXPECT_LT(gradientError, 1e-8 * gradientScale);

  // Element Hessians summed into a dense matrix (147 unknowns on the 6 × 6 patch's 49 vertices),
  // then compared column by column with differences of the gradient.
  struct DenseSink : curvature::ElementHessianSink {
    Eigen::MatrixXd hessian;
    void add(const curvature::ElementHessian& e) override {
      for (size_t i = 0; i < e.unknowns.size(); ++i)
        for (size_t j = 0; j < e.unknowns.size(); ++j)
          hessian(e.unknowns[i], e.unknowns[j]) += e.hessian(i, j);
    }
  } sink;
  const long n = 3 * x.rows();
  sink.hessian = Eigen::MatrixXd::Zero(n, n);
  setup.term->elementHessians(x, noXi, 0, setup.term->elementCount(), curvature::Derivatives::All,
                              curvature::SecondDerivatives::Exact, sink);
  double hessianError = 0.0;
  for (long k = 0; k < n; ++k) {
    Positions plus = x, minus = x;
    plus(k / 3, k % 3) += h;
    minus(k / 3, k % 3) -= h;
    const Eigen::VectorXd column = (optimize::energyGradient(terms, plus, noXi).gradient -
                                    optimize::energyGradient(terms, minus, noXi).gradient) /
                                   (2.0 * h);
    hessianError = std::max(hessianError, (column - sink.hessian.col(k)).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(sink.hessian.cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LT(hessianError, 1e-7);
  EXPECT_LT((sink.hessian - sink.hessian.transpose()).cwiseAbs().maxCoeff(), 1e-14);
}

// With the boundary on the plane z = a x + b y, the minimizer is the plane (linear functions are
// discrete-harmonic) and E = k_B (a² + b²) Σ Ā_T: Newton and the linearized solve both find it.
TEST(EnergyRegistry, TestEnergyMinimizesToThePlane) {
  const PlateSetup setup(2.0);
  const modeling::PolynomialSurface plane(std::vector<modeling::Monomial>{{kA, 1, 0}, {kB, 0, 1}});
  const Positions expected = onPlane(setup.rest.positions);
  const double area = setup.rest.faceAreas.sum();
  for (bool linearized : {false, true}) {
    // The boundary ring held on the plane, through buildProblem like any built-in energy.
    optimize::ProblemOptions p;
    p.bending.discretization = heightDirichlet();
    p.bending.stiffness = 2.0;
    p.fixedRings = 1;
    p.boundarySurface = plane;
    p.linearizedClamp = linearized;
    const optimize::Problem problem = optimize::buildProblem(setup.mesh, p);
    optimize::MinimizeOptions options;
    options.linearized = linearized;
    options.start = optimize::Start::AsGiven;  // Newton starts from the flat interior
    options.threads = 1;
    const optimize::MinimizeResult result = optimize::minimize(problem, options);
    ASSERT_TRUE(result.report.converged) << result.report.termination;
    if (!linearized) {
      EXPECT_GE(result.report.iterations, 1);
    }
    EXPECT_LT((result.positions - expected).cwiseAbs().maxCoeff(), 1e-10)
        << (linearized ? "linearized" : "newton");
    EXPECT_NEAR(setup.term->energy(result.positions, Eigen::VectorXd()),
                2.0 * (kA * kA + kB * kB) * area, 1e-10);
  }
}

constexpr double kPi = 3.14159265358979323846;

// The vibration of E = k_B Σ Ā |∇z|² (a membrane under tension 2 k_B): ρ z̈ = 2 k_B Δz, so on the
// simply supported unit square (z = 0 on the boundary) ω² = 2 k_B π² (m² + n²) / ρ, and the
// study's λ = ω L² √(ρ/D), D = 2 k_B, is λ = π √(m² + n²): λ² = π² (m² + n²), the plate's λ.
// The first four: (1,1), (1,2) and (2,1), (2,2).
const std::vector<double> kSquaredLambdas = {2 * kPi * kPi, 5 * kPi* kPi, 5 * kPi* kPi,
                                             8 * kPi* kPi};

// Height modes of the run-time energy on patch48, n = 16: flexible, positive, ascending, the
// (1,2)/(2,1) pair double, each pair an eigenpair, λ² within 3 % of the membrane's.
TEST(EnergyRegistry, TestEnergyVibratesAsAMembrane) {
  const testing::Plate plate(modeling::MeshFamily::Patch48, 16, heightDirichlet());
  optimize::ModesOptions o;
  o.count = 4;
  o.support = optimize::Support::SimplySupported;
  const optimize::ModesResult r =
      optimize::vibrationModes(plate.terms(), plate.stencils, plate.rest, plate.restXi, o);
  ASSERT_EQ(r.modes.size(), 4u);
  EXPECT_EQ(r.spuriousZeroModes, 0);
  double previous = 0.0;
  for (size_t k = 0; k < r.modes.size(); ++k) {
    const optimize::VibrationMode& mode = r.modes[k];
    EXPECT_FALSE(mode.zero) << k;
    EXPECT_GT(mode.lambda, previous) << k;
    EXPECT_LE(mode.residual, 1e-8) << k;
    std::printf("dirichlet λ_%zu² = %.4f against π²(m² + n²) = %.4f\n", k + 1,
                mode.lambda * mode.lambda, kSquaredLambdas[k]);
    EXPECT_NEAR(mode.lambda * mode.lambda / kSquaredLambdas[k], 1.0, 0.03) << k;
    previous = mode.lambda * (1.0 - 1e-6);  // the double pair may come in either order
  }
  EXPECT_EQ(r.modes[1].multiplicity, 2);
  EXPECT_EQ(r.modes[0].multiplicity, 1);
}

// The spectrum study on the run-time energy: its λ² converge to the membrane's at order about 2
// (linear elements with a lumped mass), while the study, which compares λ with the plate's,
// finds that they do not converge to those.
TEST(EnergyRegistry, SpectrumStudyOfTheTestEnergy) {
  heightDirichlet();
  optimize::SpectrumStudyOptions o;
  o.energies = {optimize::parseEnergyVariant("dirichlet")};
  o.families = {modeling::MeshFamily::Patch48};
  o.count = 4;
  o.baseN = 8;
  o.levels = 3;
  o.support = optimize::Support::SimplySupported;
  const std::vector<optimize::SpectrumSeries> series = optimize::runSpectrumStudy(o);
  ASSERT_EQ(series.size(), 1u);
  const optimize::SpectrumSeries& s = series.front();
  EXPECT_EQ(s.clamp, optimize::Clamp::Rings);
  ASSERT_EQ(s.lambdas.size(), 3u);
  for (int k = 0; k < o.count; ++k) {
    std::vector<double> errors;
    for (const auto& level : s.lambdas)
      errors.push_back(std::abs(level[k] * level[k] / kSquaredLambdas[k] - 1.0));
    std::printf("dirichlet λ_%d²: errors %.2e %.2e %.2e\n", k + 1, errors[0], errors[1], errors[2]);
    EXPECT_GT(std::log2(errors[1] / errors[2]), 1.7) << k;
    EXPECT_LT(errors[2], 0.01) << k;
    EXPECT_EQ(s.verdicts[k], optimize::Refinement::DoesNotConverge) << k;
  }
}

// A shell of the run-time energy (and a StVK membrane, xyz; rings 0 and 1 pinned) released from
// its first mode: undamped Newmark keeps the total energy within 1 % and swings with the mode's
// period; backward Euler loses energy at every step.
TEST(EnergyRegistry, TestEnergyShellOscillatesWithItsModesPeriod) {
  const testing::Plate shell(
      modeling::MeshFamily::Delaunay, 8, heightDirichlet(), 1e3,
      [](optimize::ProblemOptions& p, const modeling::Stencils&) { p.fixedRings = 2; });
  optimize::ModesOptions modes;
  modes.count = 1;
  modes.dof = optimize::DofMode::Xyz;
  const optimize::VibrationMode mode =
      optimize::vibrationModes(shell.terms(), shell.stencils, shell.rest, shell.restXi, modes)
          .modes.front();
  ASSERT_GT(mode.omega, 0.0);
  const double period = 2.0 * kPi / mode.omega, h = period / 40.0;
  const modeling::Positions start =
      shell.rest.positions + (1e-4 / mode.shape.cwiseAbs().maxCoeff()) * mode.shape;
  const modeling::Positions still = modeling::Positions::Zero(shell.mesh.vertexCount(), 3);
  for (const optimize::Integrator integrator :
       {optimize::Integrator::Newmark, optimize::Integrator::BackwardEuler}) {
    SCOPED_TRACE(optimize::integratorName(integrator));
    optimize::DynamicsOptions d;
    d.integrator = integrator;
    optimize::TimeStepper stepper(shell.problem, d);
    stepper.start(start, still, Eigen::VectorXd());
    const double initial = stepper.energies().total();
    ASSERT_GT(initial, 0.0);
    double previous = initial, worst = 0.0, lastHeight = start.col(2).dot(mode.shape.col(2));
    std::vector<double> crossings;  // downward zero crossings of z along the mode's shape
    for (int k = 0; k < 120; ++k) {
      const auto outcome = stepper.step(h);
      ASSERT_TRUE(outcome.converged) << outcome.failure << " at step " << k;
      const double total = stepper.energies().total();
      ASSERT_TRUE(std::isfinite(total));
      worst = std::max(worst, std::abs(total / initial - 1.0));
      if (integrator == optimize::Integrator::BackwardEuler) {
        EXPECT_LE(total, previous * (1.0 + 1e-12)) << "step " << k;
      }
      previous = total;
      const double height =
          (stepper.positions() - shell.rest.positions).col(2).dot(mode.shape.col(2));
      if (lastHeight > 0.0 && height <= 0.0)
        crossings.push_back(stepper.time() - h * height / (height - lastHeight));
      lastHeight = height;
    }
    if (integrator == optimize::Integrator::Newmark) {
      EXPECT_LT(worst, 0.01);
      ASSERT_GE(crossings.size(), 2u);
      // Newmark's average acceleration lengthens the period to T (ωh/2) / atan(ωh/2).
      const double half = 0.5 * mode.omega * h;
      EXPECT_NEAR(
          (crossings.back() - crossings[crossings.size() - 2]) / (period * half / std::atan(half)),
          1.0, 0.01);
    } else {
      EXPECT_LT(previous, 0.5 * initial);
    }
  }
}

}  // namespace
}  // namespace flexure
