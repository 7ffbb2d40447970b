// Exact Hessians (curvature/element_hessian.h, optimize/assembly/hessian_assembly.h) of every
// bending energy and membrane:
// 1. against central differences of the exact gradient (Ceres' autodiff, energyGradient):
//    column k of ∇²E is (∇E(u + h e_k) − ∇E(u − h e_k)) / 2h + O(h²) + O(ε |∇E| / h), on curved
//    rest shells and irregular meshes, in xyz and height mode, at cotan valences 3 to 11 and
//    for every midedge flap count (0 to 3);
// 2. element Hessians symmetric; the assembled gradient and energy equal Ceres';
// 3. at a stress-free rest (every residual zero) ∇²E = JᵀJ;
// 4. the coupling to moved fixed unknowns (the linearized predictor's right-hand side) equals
//    the full Hessian's off-diagonal block times the move;
// 5. the hinge's closed-form element derivatives (curvature/hinge_angle_derivatives.h) equal the
//    second-order jets' on random and nearly flat hinges, and central differences of their own
//    gradient.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "curvature/current_metric.h"
#include "curvature/element_hessian.h"
#include "curvature/membrane_energy.h"
#include "modeling/generators.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/boundary_conditions.h"
#include "optimize/linear/least_squares.h"
#include "support/assembled_derivatives.h"
#include "support/energy_fixtures.h"
#include "support/small_meshes.h"

namespace flexure {
namespace {

using curvature::BendingOptions;
using curvature::Derivatives;
using curvature::Discretization;
using curvature::EnergyTerm;
using modeling::Mesh;
using modeling::Positions;
using optimize::HessianAssembly;
using optimize::HessianProjection;

// ---------------------------------------------------------------------------------------------
// Meshes.

// A vertex of valence k at the origin, its ring of k vertices at radius 1 and an outer ring of
// 2k vertices at radius 2 (the boundary), so that the centre and the ring are interior.
Mesh fanMesh(int k) {
  Mesh m;
  m.positions.resize(1 + 3 * k, 3);
  m.positions.row(0) << 0.0, 0.0, 0.0;
  for (int j = 0; j < k; ++j) {
    const double a = 2.0 * M_PI * j / k;
    m.positions.row(1 + j) << std::cos(a), std::sin(a), 0.0;
  }
  for (int j = 0; j < 2 * k; ++j) {
    const double a = 2.0 * M_PI * (j - 0.5) / (2 * k);
    m.positions.row(1 + k + j) << 2.0 * std::cos(a), 2.0 * std::sin(a), 0.0;
  }
  std::vector<Eigen::Vector3i> faces;
  for (int j = 0; j < k; ++j) {
    const int r0 = 1 + j, r1 = 1 + (j + 1) % k;
    const int o0 = 1 + k + 2 * j, o1 = 1 + k + 2 * j + 1, o2 = 1 + k + (2 * j + 2) % (2 * k);
    faces.emplace_back(0, r0, r1);
    faces.emplace_back(r0, o0, o1);
    faces.emplace_back(r0, o1, r1);
    faces.emplace_back(r1, o1, o2);
  }
  m.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f)
    m.triangles.row(static_cast<Eigen::Index>(f)) = faces[f];
  return m;
}

Mesh singleTriangle() {
  Mesh m;
  m.positions.resize(3, 3);
  m.positions << 0.1, -0.2, 0.0, 1.2, 0.1, 0.0, 0.3, 0.9, 0.0;
  m.triangles.resize(1, 3);
  m.triangles << 0, 1, 2;
  return m;
}

Mesh delaunayPatch() {
  return modeling::generateMesh({modeling::MeshFamily::Delaunay, 4, 7, {}});
}

// ---------------------------------------------------------------------------------------------
// Terms under test.

struct Energy {
  std::string name;
  std::optional<BendingOptions> bending;               // a bending energy, or
  std::optional<curvature::MembraneOptions> membrane;  // a membrane (xyz mode only)
};

std::vector<Energy> allEnergies() {
  std::vector<Energy> out;
  const auto bending = [&](std::string name, Discretization d, auto adjust) {
    BendingOptions o = testing::bendingOptions(d);
    adjust(o);
    out.push_back({std::move(name), o, std::nullopt});
  };
  const auto same = [](BendingOptions&) {};
  bending("hinge theta", Discretization::Hinge, same);
  bending("hinge tan", Discretization::Hinge,
          [](BendingOptions& o) { o.hingeAngle = curvature::HingeAngle::Tan; });
  bending("triavg", Discretization::TriangleAveraged, same);
  bending("triavg nu=0", Discretization::TriangleAveraged,
          [](BendingOptions& o) { o.poisson = 0.0; });
  bending("cotan voronoi", Discretization::Cotan, same);
  bending("cotan barycentric", Discretization::Cotan,
          [](BendingOptions& o) { o.vertexArea = curvature::VertexArea::Barycentric; });
  bending("midedge", Discretization::Midedge, same);
  bending("midedge nu=1", Discretization::Midedge, [](BendingOptions& o) { o.poisson = 1.0; });
  bending("quadfit", Discretization::QuadraticFit, same);
  for (auto model : {curvature::MembraneModel::Stvk, curvature::MembraneModel::Springs,
                     curvature::MembraneModel::Conformal}) {
    curvature::MembraneOptions m;
    m.model = model;
    m.young = 3.0;
    m.lengthStiffness = 2.0;
    m.areaStiffness = 5.0;
    m.shapeStiffness = 4.0;
    out.push_back({model == curvature::MembraneModel::Stvk      ? "stvk"
                   : model == curvature::MembraneModel::Springs ? "springs"
                                                                : "conformal",
                   std::nullopt, m});
  }
  return out;
}

// The terms of `energy` on a rest mesh, with ξ̄ (zero size unless midedge).
struct TermSetup {
  modeling::Stencils stencils;
  modeling::RestState rest;
  std::vector<std::unique_ptr<EnergyTerm>> owned;
  Eigen::VectorXd restXi;

  TermSetup(const Mesh& restMesh, const Energy& energy)
      : stencils(modeling::compileStencils(restMesh)),
        rest(modeling::precomputeRestState(stencils, restMesh.positions)) {
    if (energy.bending) {
      owned.push_back(curvature::makeBendingEnergy(stencils, rest, *energy.bending));
      restXi = curvature::midedgeRestXi(stencils, rest, energy.bending->restCurvature);
    } else {
      owned = curvature::makeMembraneEnergy(stencils, rest, *energy.membrane);
    }
  }

  std::vector<const EnergyTerm*> terms() const {
    std::vector<const EnergyTerm*> t;
    for (const auto& term : owned) t.push_back(term.get());
    return t;
  }
  bool withXi() const { return optimize::usesEdgeUnknowns(terms()); }
};

Eigen::VectorXd unknownsOf(const Positions& x, const Eigen::VectorXd& xi, bool withXi) {
  Eigen::VectorXd u(x.size() + (withXi ? xi.size() : 0));
  u.head(x.size()) = Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
  if (withXi) u.tail(xi.size()) = xi;
  return u;
}

// Which unknowns are free: all (xyz), or z and ξ (height).
std::vector<bool> freeSet(int vertexCount, Eigen::Index unknowns, Derivatives derivatives) {
  std::vector<bool> free(unknowns, true);
  if (derivatives == Derivatives::HeightOnly)
    for (int v = 0; v < vertexCount; ++v) free[3 * v] = free[3 * v + 1] = false;
  return free;
}

// Collects the element Hessians' largest asymmetry.
class AsymmetrySink : public curvature::ElementHessianSink {
 public:
  void add(const curvature::ElementHessian& e) override {
    worst = std::max(worst, (e.hessian - e.hessian.transpose()).cwiseAbs().maxCoeff());
    ++elements;
  }
  double worst = 0.0;
  int elements = 0;
};

struct Comparison {
  double hessianError = 0.0;   // max |H − FD| / max |H|
  double gradientError = 0.0;  // max |∇E − Ceres ∇E| / max |∇E|
  double energyError = 0.0;    // |E − Ceres E| / E
  double asymmetry = 0.0;      // max over elements of |H_e − H_eᵀ|, / max |H|
  int unknowns = 0;
};

// ∇²E at a deformed configuration of `restMesh` against central differences of Ceres' ∇E.
Comparison compare(const Mesh& restMesh, const Energy& energy, Derivatives derivatives,
                   unsigned seed, double jitter = 0.02) {
  std::mt19937 rng(seed);
  const TermSetup setup(restMesh, energy);
  const auto terms = setup.terms();
  Mesh flat = restMesh;
  flat.positions.col(2).setZero();
  const Positions x = testing::jittered(
      testing::lifted(flat, testing::randomCubic(rng, 0.8)).positions, rng, jitter);
  Eigen::VectorXd xi = setup.restXi;
  std::uniform_real_distribution<double> offset(-0.2, 0.2);
  for (Eigen::Index e = 0; e < xi.size(); ++e) xi[e] += offset(rng);
  const bool withXi = setup.withXi();
  const Eigen::VectorXd u = unknownsOf(x, xi, withXi);
  const std::vector<bool> free = freeSet(static_cast<int>(x.rows()), u.size(), derivatives);
  const HessianAssembly assembly(terms, free, static_cast<int>(x.rows()), derivatives);
  const optimize::HessianEvaluation h = assembly.evaluate(x, xi, HessianProjection::Exact);
  const Eigen::MatrixXd hessian = testing::denseHessian(assembly, h.values);

  const auto gradientAt = [&](const Eigen::VectorXd& at) {
    const Positions px = Eigen::Map<const Positions>(at.data(), x.rows(), 3);
    const Eigen::VectorXd pxi = withXi ? Eigen::VectorXd(at.tail(xi.size())) : xi;
    const Eigen::VectorXd g = optimize::energyGradient(terms, px, pxi).gradient;
    Eigen::VectorXd out(assembly.size());
    for (int k = 0; k < assembly.size(); ++k) out[k] = g[assembly.freeUnknowns()[k]];
    return out;
  };
  Comparison c;
  c.unknowns = assembly.size();
  const optimize::EnergyGradient reference = optimize::energyGradient(terms, x, xi);
  const Eigen::VectorXd referenceGradient = gradientAt(u);
  c.energyError = std::abs(h.energy - reference.energy) / reference.energy;
  c.gradientError = (h.gradient - referenceGradient).cwiseAbs().maxCoeff() /
                    referenceGradient.cwiseAbs().maxCoeff();
  const double step = 1e-6, scale = hessian.cwiseAbs().maxCoeff();
  for (int k = 0; k < assembly.size(); ++k) {
    Eigen::VectorXd plus = u, minus = u;
    plus[assembly.freeUnknowns()[k]] += step;
    minus[assembly.freeUnknowns()[k]] -= step;
    const Eigen::VectorXd column = (gradientAt(plus) - gradientAt(minus)) / (2.0 * step);
    c.hessianError = std::max(c.hessianError, (hessian.col(k) - column).cwiseAbs().maxCoeff());
  }
  c.hessianError /= scale;
  AsymmetrySink sink;
  for (const EnergyTerm* term : terms)
    term->elementHessians(x, xi, 0, term->elementCount(), derivatives,
                          curvature::SecondDerivatives::Exact, sink);
  c.asymmetry = sink.worst / scale;
  return c;
}

// Central differences of the exact gradient with h = 1e-6 on these O(1) meshes: truncation
// h² |∂³∇E| and roundoff ε |∇E| / h, both ≈ 1e-10 of max |H|; measured 1e-11 to 3.3e-10 over
// every case here. A wrong second-derivative term is O(1) of an entry.
constexpr double kDifferenceTolerance = 1e-8;

void expectExact(const Mesh& restMesh, const Energy& energy, Derivatives derivatives, unsigned seed,
                 double jitter = 0.02, double tolerance = kDifferenceTolerance) {
  SCOPED_TRACE(energy.name + (derivatives == Derivatives::All ? ", xyz" : ", height"));
  const Comparison c = compare(restMesh, energy, derivatives, seed, jitter);
  EXPECT_GT(c.unknowns, 0);
  EXPECT_LT(c.hessianError, tolerance);
  EXPECT_LT(c.gradientError, 1e-12);
  EXPECT_LT(c.energyError, 1e-13);
  EXPECT_LE(c.asymmetry, 1e-15);
}

Mesh curvedRest(const Mesh& flat, unsigned seed) {
  std::mt19937 rng(seed);
  return testing::lifted(flat, testing::randomCubic(rng, 1.2));
}

TEST(Hessians, EveryEnergyOnACurvedIrregularShell) {
  const Mesh rest = curvedRest(delaunayPatch(), 3);
  unsigned seed = 100;
  for (const Energy& energy : allEnergies()) {
    expectExact(rest, energy, Derivatives::All, seed++);
    if (energy.bending) expectExact(rest, energy, Derivatives::HeightOnly, seed++);
  }
}

// The current metric (curvature/current_metric.h: areas, frames and fits as functions of x) adds
// second derivatives through the metric; flat rest curvature, as fairing uses it.
TEST(Hessians, EveryEnergyOnTheCurrentMetric) {
  const Mesh rest = curvedRest(delaunayPatch(), 4);
  unsigned seed = 300;
  for (Energy energy : allEnergies()) {
    if (!energy.bending) continue;
    energy.name += ", current metric";
    energy.bending->restCurvature = curvature::RestCurvature::Flat;
    energy.bending->metric = curvature::CurvatureMetric::Current;
    expectExact(rest, energy, Derivatives::All, seed++);
  }
}

// On slivers the current metric's edge factors are capped (current_metric.h, the secure metric):
// a 4 × 4 grid whose third column of cells is 0.01 wide has faces of 0.57°, whose long edges are
// capped, lifted without jitter so they stay slivers. The cap's branch is differentiated as it is
// evaluated. The differences' truncation grows as (h / width)² = (1e-6 / 0.01)² = 1e-8 of max |H|
// on these cells, so they are held to 1e-7 (a wrong term is still O(1) of an entry).
TEST(Hessians, SecureMetricOnSlivers) {
  Mesh rest = testing::gridMesh(4, 4);
  for (int v = 0; v < rest.positions.rows(); ++v)
    if (rest.positions(v, 0) > 2.5) rest.positions(v, 0) -= 0.99;
  double largestFactor = 0.0;  // max ℓ² / 2A: ≈ 100 on the diagonals of the thin cells
  for (int f = 0; f < rest.triangles.rows(); ++f) {
    const Eigen::Vector3d a = rest.positions.row(rest.triangles(f, 0));
    const Eigen::Vector3d ab = Eigen::Vector3d(rest.positions.row(rest.triangles(f, 1))) - a;
    const Eigen::Vector3d ac = Eigen::Vector3d(rest.positions.row(rest.triangles(f, 2))) - a;
    const double twiceArea = ab.cross(ac).norm();
    for (double squaredLength : {ab.squaredNorm(), (ac - ab).squaredNorm(), ac.squaredNorm()})
      largestFactor = std::max(largestFactor, squaredLength / twiceArea);
  }
  ASSERT_GT(largestFactor, 2.0 * curvature::kSecureEdgeFactor);
  unsigned seed = 500;
  for (Energy energy : allEnergies()) {
    const bool capped = energy.name.rfind("midedge", 0) == 0 ||
                        energy.name.rfind("triavg", 0) == 0 || energy.name.rfind("hinge", 0) == 0;
    if (!energy.bending || !capped) continue;
    energy.name += ", current metric, slivers";
    energy.bending->restCurvature = curvature::RestCurvature::Flat;
    energy.bending->metric = curvature::CurvatureMetric::Current;
    expectExact(rest, energy, Derivatives::All, seed++, 0.0, 1e-7);
  }
}

TEST(Hessians, RepeatedFlapVertex) {
  const Mesh rest = curvedRest(testing::withValenceThreeVertex(delaunayPatch()), 5);
  unsigned seed = 200;
  // quadfit refuses these stencils: a repeated point leaves five for six coefficients.
  for (const Energy& energy : allEnergies())
    if (energy.bending && energy.name != "quadfit")
      expectExact(rest, energy, Derivatives::All, seed++);
}

// Cotan rings of valence 3 to 11 (jet sizes 12 to 36 in xyz mode), and the other vertex
// energies on the same fans.
TEST(Hessians, EveryValenceThreeToEleven) {
  for (int k = 3; k <= 11; ++k) {
    SCOPED_TRACE("valence " + std::to_string(k));
    const Mesh rest = curvedRest(fanMesh(k), 10 + static_cast<unsigned>(k));
    for (const Energy& energy : allEnergies()) {
      if (energy.name != "cotan voronoi" && energy.name != "cotan barycentric" &&
          !(k == 5 && energy.bending))
        continue;
      expectExact(rest, energy, Derivatives::All, 300 + static_cast<unsigned>(k));
      expectExact(rest, energy, Derivatives::HeightOnly, 400 + static_cast<unsigned>(k));
    }
  }
}

// Midedge faces with 0 (a lone triangle), 1 (gridMesh(2, 2) has two faces with two boundary
// edges), 2 and 3 flaps.
TEST(Hessians, MidedgeEveryFlapCount) {
  std::mt19937 rng(12);
  const std::vector<Mesh> meshes = {singleTriangle(), curvedRest(testing::gridMesh(2, 2), 13)};
  const Energy midedge = allEnergies()[6];
  ASSERT_EQ(midedge.name, "midedge");
  for (const Mesh& mesh : meshes) {
    expectExact(mesh, midedge, Derivatives::All, 500);
    expectExact(mesh, midedge, Derivatives::HeightOnly, 501);
  }
}

// At a stress-free rest every residual is zero, so ∇²E = JᵀJ: the Gauss–Newton matrix the
// linearized solve factors.
TEST(Hessians, AtRestTheHessianIsJTJ) {
  const Mesh rest = curvedRest(delaunayPatch(), 21);
  for (const Energy& energy : allEnergies()) {
    SCOPED_TRACE(energy.name);
    const TermSetup setup(rest, energy);
    const auto terms = setup.terms();
    const Positions& x = setup.rest.positions;
    Eigen::VectorXd xi = setup.restXi;
    if (setup.withXi()) {
      // ξ̄ at a curved rest is the ξ that makes S = S̄: the residuals vanish.
      const std::vector<bool> allFree(xi.size(), true);
      xi = optimize::minimizeEdgeUnknowns(terms, x, xi, allFree);
    }
    const Eigen::VectorXd u = unknownsOf(x, xi, setup.withXi());
    const std::vector<bool> free(u.size(), true);
    const HessianAssembly assembly(terms, free, static_cast<int>(x.rows()), Derivatives::All);
    const optimize::HessianEvaluation h = assembly.evaluate(x, xi, HessianProjection::Exact);
    EXPECT_LT(h.energy, 1e-20);
    const Eigen::MatrixXd j = optimize::residualJacobian(terms, x, xi).toDense();
    const Eigen::MatrixXd jtj = j.transpose() * j;
    const Eigen::MatrixXd hessian = testing::denseHessian(assembly, h.values);
    ASSERT_EQ(hessian.rows(), jtj.rows());
    EXPECT_LE((hessian - jtj).cwiseAbs().maxCoeff(), 1e-12 * jtj.cwiseAbs().maxCoeff());
  }
}

// fixedCoupling = H_free,fixed d for a move d of the fixed unknowns; the free block is the full
// Hessian's.
TEST(Hessians, FixedCouplingIsTheOffDiagonalBlock) {
  const Mesh rest = curvedRest(delaunayPatch(), 31);
  std::mt19937 rng(32);
  for (const Energy& energy : allEnergies()) {
    if (!energy.bending) continue;
    SCOPED_TRACE(energy.name);
    const TermSetup setup(rest, energy);
    const auto terms = setup.terms();
    const Positions x = testing::jittered(setup.rest.positions, rng, 0.05);
    const Eigen::VectorXd xi = setup.restXi;
    const Eigen::VectorXd u = unknownsOf(x, xi, setup.withXi());
    const std::vector<bool> fixedRing = optimize::fixedRings(setup.stencils, 1);
    std::vector<bool> free(u.size(), true);
    for (int v = 0; v < x.rows(); ++v)
      for (int c = 0; c < 3; ++c) free[3 * v + c] = !fixedRing[v];
    const int n = static_cast<int>(x.rows());
    const HessianAssembly full(terms, std::vector<bool>(u.size(), true), n, Derivatives::All);
    const HessianAssembly part(terms, free, n, Derivatives::All);
    Eigen::VectorXd move = Eigen::VectorXd::Random(u.size());
    const Eigen::MatrixXd h =
        testing::denseHessian(full, full.evaluate(x, xi, HessianProjection::Exact).values);
    const optimize::HessianEvaluation p = part.evaluate(x, xi, HessianProjection::Exact, &move);
    const Eigen::MatrixXd hp = testing::denseHessian(part, p.values);
    Eigen::VectorXd fixedMove = move;
    for (Eigen::Index k = 0; k < u.size(); ++k)
      if (free[k]) fixedMove[k] = 0.0;
    const Eigen::VectorXd coupled = h * fixedMove;
    const double scale = h.cwiseAbs().maxCoeff();
    for (int k = 0; k < part.size(); ++k) {
      const int uk = part.freeUnknowns()[k];
      EXPECT_NEAR(p.fixedCoupling[k], coupled[uk], 1e-12 * scale * u.size());
      for (int l = 0; l < part.size(); ++l)
        ASSERT_NEAR(hp(k, l), h(uk, part.freeUnknowns()[l]), 1e-13 * scale);
    }
  }
}

// Element projection to positive semidefinite: the assembled matrix has no negative eigenvalue,
// and at a configuration where the exact one is indefinite the two differ.
TEST(Hessians, ProjectionIsPositiveSemidefinite) {
  const Mesh rest = curvedRest(delaunayPatch(), 41);
  std::mt19937 rng(42);
  const Energy hinge = allEnergies()[0];
  const TermSetup setup(rest, hinge);
  Mesh flat = rest;
  flat.positions.col(2).setZero();
  const Positions x =
      testing::jittered(testing::lifted(flat, testing::randomCubic(rng, 2.0)).positions, rng, 0.05);
  const std::vector<bool> free(x.size(), true);
  const HessianAssembly a(setup.terms(), free, static_cast<int>(x.rows()), Derivatives::All);
  const Eigen::VectorXd noXi;
  const Eigen::MatrixXd exact =
      testing::denseHessian(a, a.evaluate(x, noXi, HessianProjection::Exact).values);
  const Eigen::MatrixXd projected =
      testing::denseHessian(a, a.evaluate(x, noXi, HessianProjection::PositiveSemidefinite).values);
  const double scale = exact.cwiseAbs().maxCoeff();
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(exact).eigenvalues().minCoeff(),
            -1e-6 * scale);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(projected).eigenvalues().minCoeff(),
            -1e-12 * scale);
}

// ---------------------------------------------------------------------------------------------
// The hinge's closed form against the jets it replaced.

using curvature::ElementHessian;
using curvature::HingeBendingResidual;
using curvature::SecondDerivatives;

// A hinge element on the four vertices of `x` (12 values: x_i, x_j, x_k, x_l).
struct LoneHinge {
  HingeBendingResidual residual;
  Eigen::Matrix<double, 12, 1> x;
  std::vector<const double*> blocks() const {
    return {x.data(), x.data() + 3, x.data() + 6, x.data() + 9};
  }
  static const std::vector<int>& sizes() {
    static const std::vector<int> s = {3, 3, 3, 3};
    return s;
  }
  static const std::vector<long>& firstUnknowns() {
    static const std::vector<long> f = {0, 3, 6, 9};
    return f;
  }
  // The overloads element_term.h calls: closed form for the hinge (jets on the current metric).
  ElementHessian closedForm(Derivatives d, SecondDerivatives kind) const {
    ElementHessian out;
    const bool ok =
        kind == SecondDerivatives::Exact
            ? curvature::elementHessian(residual, blocks(), sizes(), firstUnknowns(), d, out)
            : curvature::elementFirstDerivatives(residual, blocks(), sizes(), firstUnknowns(), d,
                                                 kind == SecondDerivatives::GaussNewton, out);
    EXPECT_TRUE(ok);
    return out;
  }
  // The generic templates: second-order jets (Exact), first-order jets (the others).
  ElementHessian jets(Derivatives d, SecondDerivatives kind) const {
    ElementHessian out;
    const bool ok = kind == SecondDerivatives::Exact
                        ? curvature::elementHessian<HingeBendingResidual>(
                              residual, blocks(), sizes(), firstUnknowns(), d, out)
                        : curvature::elementFirstDerivatives<HingeBendingResidual>(
                              residual, blocks(), sizes(), firstUnknowns(), d,
                              kind == SecondDerivatives::GaussNewton, out);
    EXPECT_TRUE(ok);
    return out;
  }
};

// Random hinges: an edge along a random direction, two opposite vertices on either side, then
// folded by a random angle in (−3, 3) (or, nearly flat, by a random 1e-7); jittered so nothing is
// symmetric. Random weights and rest measures; both angle measures.
std::vector<LoneHinge> randomHinges(std::mt19937& rng, bool nearlyFlat, int count) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<LoneHinge> out;
  for (int n = 0; n < count; ++n) {
    LoneHinge h;
    h.residual.vertices = {0, 1, 2, 3};
    h.residual.measure = n % 2 == 0 ? curvature::HingeAngle::Theta : curvature::HingeAngle::Tan;
    h.residual.sqrtWeight = 0.5 + 2.0 * std::abs(u(rng));
    h.residual.restMeasure = nearlyFlat && n % 4 < 2 ? 0.0 : 0.5 * u(rng);
    const double fold = nearlyFlat ? 1e-7 * u(rng) : 3.0 * u(rng);
    const double half = 0.5 * fold;  // each face's tilt out of the flat hinge's plane
    const Eigen::Vector3d k(0.3 + 0.4 * u(rng), std::cos(half),
                            std::sin(half) * (1.0 + 0.3 * u(rng)));
    const Eigen::Vector3d l(0.5 + 0.4 * u(rng), -std::cos(half), std::sin(half));
    Eigen::Matrix<double, 12, 1> x;
    x << 0, 0, 0, 1.0 + 0.3 * u(rng), 0, 0, k, l;
    // The faces (x_i, x_j, k) and (x_j, x_i, l) meet at π − fold (k's height jittered); then a
    // random rigid motion.
    const Eigen::Matrix3d rotation =
        Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized())
            .toRotationMatrix();
    const Eigen::Vector3d shift(u(rng), u(rng), u(rng));
    for (int v = 0; v < 4; ++v) h.x.segment<3>(3 * v) = rotation * x.segment<3>(3 * v) + shift;
    out.push_back(h);
  }
  return out;
}

TEST(Hessians, HingeClosedFormEqualsJets) {
  std::mt19937 rng(71);
  for (bool nearlyFlat : {false, true}) {
    for (const LoneHinge& h : randomHinges(rng, nearlyFlat, 200)) {
      for (Derivatives d : {Derivatives::All, Derivatives::HeightOnly}) {
        for (SecondDerivatives kind :
             {SecondDerivatives::Exact, SecondDerivatives::GaussNewton, SecondDerivatives::None}) {
          SCOPED_TRACE(std::string(nearlyFlat ? "nearly flat" : "random") +
                       (d == Derivatives::All ? ", xyz" : ", height") + ", kind " +
                       std::to_string(static_cast<int>(kind)));
          const ElementHessian closed = h.closedForm(d, kind), jets = h.jets(d, kind);
          ASSERT_EQ(closed.unknowns, jets.unknowns);
          // |r| = √(2 E_e) to roundoff of w (φ − φ̄): r is small where φ ≈ φ̄.
          const double w = h.residual.sqrtWeight, r = std::sqrt(2.0 * jets.energy);
          EXPECT_NEAR(std::sqrt(2.0 * closed.energy), r,
                      1e-14 * (r + w * (1.0 + 2.0 * std::abs(h.residual.restMeasure))));
          const double gradientScale = jets.gradient.cwiseAbs().maxCoeff();
          EXPECT_LE((closed.gradient - jets.gradient).cwiseAbs().maxCoeff(),
                    1e-10 * gradientScale + 1e-300);
          ASSERT_EQ(closed.hessian.rows(), jets.hessian.rows());
          if (kind == SecondDerivatives::None) continue;
          const double scale = jets.hessian.cwiseAbs().maxCoeff();
          EXPECT_LE((closed.hessian - jets.hessian).cwiseAbs().maxCoeff(), 1e-10 * scale);
          EXPECT_EQ(closed.hessian, closed.hessian.transpose());
        }
      }
    }
  }
}

// Central differences of the closed-form gradient, step 1e-6 on these O(1) hinges: truncation
// and roundoff both ≈ 1e-10 of max |H| (as kDifferenceTolerance above).
TEST(Hessians, HingeClosedFormAgainstDifferencesOfItsGradient) {
  std::mt19937 rng(72);
  for (bool nearlyFlat : {false, true}) {
    for (const LoneHinge& h : randomHinges(rng, nearlyFlat, 50)) {
      const ElementHessian exact = h.closedForm(Derivatives::All, SecondDerivatives::Exact);
      const double step = 1e-6, scale = exact.hessian.cwiseAbs().maxCoeff();
      for (int k = 0; k < 12; ++k) {
        LoneHinge plus = h, minus = h;
        plus.x[k] += step;
        minus.x[k] -= step;
        const Eigen::VectorXd column =
            (plus.closedForm(Derivatives::All, SecondDerivatives::None).gradient -
             minus.closedForm(Derivatives::All, SecondDerivatives::None).gradient) /
            (2.0 * step);
        EXPECT_LE((exact.hessian.col(k) - column).cwiseAbs().maxCoeff(),
                  kDifferenceTolerance * scale)
            << (nearlyFlat ? "nearly flat" : "random") << ", column " << k;
      }
    }
  }
}

}  // namespace
}  // namespace flexure
