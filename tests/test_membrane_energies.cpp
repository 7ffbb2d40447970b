// Known answers of the membrane energies (curvature/membrane.h):
//
//   stvk:    E = Y / (2 (1 − ν²)) Σ_T Ā_T Ψ_ν(ε_T),  ε = ½ (FᵀF − I) the Green strain,
//   springs: E = k_L Σ_e (ℓ_e − ℓ̄_e)² / ℓ̄_e + k_A Σ_T (A_T − Ā_T)² / Ā_T.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "curvature/dihedral_barrier.h"
#include "curvature/membrane_energy.h"
#include "curvature/projected_hessian.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "optimize/assembly/energy_evaluation.h"
#include "support/energy_fixtures.h"

namespace flexure {
namespace {

using curvature::EnergyTerm;
using curvature::MembraneModel;
using curvature::MembraneOptions;
using modeling::Mesh;
using modeling::MeshFamily;
using modeling::Positions;

// Membrane terms bound to a rest mesh.
struct MembraneSetup {
  modeling::Stencils stencils;
  modeling::RestState rest;
  std::vector<std::unique_ptr<EnergyTerm>> terms;

  MembraneSetup(const Mesh& restMesh, const MembraneOptions& options)
      : stencils(modeling::compileStencils(restMesh)),
        rest(modeling::precomputeRestState(stencils, restMesh.positions)),
        terms(curvature::makeMembraneEnergy(stencils, rest, options)) {}

  std::vector<const EnergyTerm*> termPointers() const {
    std::vector<const EnergyTerm*> out;
    for (const auto& t : terms) out.push_back(t.get());
    return out;
  }
  double energy(const Positions& x) const {
    double e = 0.0;
    for (const auto& t : terms) e += t->energy(x, Eigen::VectorXd());
    return e;
  }
};

MembraneOptions stvk(double young, double poisson) {
  MembraneOptions o;
  o.young = young;
  o.poisson = poisson;
  return o;
}

MembraneOptions springs(double lengthStiffness, double areaStiffness) {
  MembraneOptions o;
  o.model = MembraneModel::Springs;
  o.lengthStiffness = lengthStiffness;
  o.areaStiffness = areaStiffness;
  return o;
}

MembraneOptions conformal(double shapeStiffness) {
  MembraneOptions o;
  o.model = MembraneModel::Conformal;
  o.shapeStiffness = shapeStiffness;
  return o;
}

// Ψ_ν(M) = (1 − ν) tr(M²) + ν (tr M)² for M = [[a, b], [b, c]].
double psi(double a, double b, double c, double nu) {
  return (1.0 - nu) * (a * a + 2.0 * b * b + c * c) + nu * (a + c) * (a + c);
}

// x ↦ F x in the plane for a 2×2 F (z kept).
Positions mapped(const Positions& flat, const Eigen::Matrix2d& f) {
  Positions x = flat;
  for (int v = 0; v < x.rows(); ++v)
    x.block<1, 2>(v, 0) = (f * flat.block<1, 2>(v, 0).transpose()).transpose();
  return x;
}

Mesh flatSquare() {
  return modeling::generateMesh({MeshFamily::Delaunay, 6, 9, {}});
}

Mesh curvedRest() {
  std::mt19937 rng(31);
  return testing::lifted(flatSquare(), testing::randomCubic(rng, 1.0));
}

TEST(MembraneEnergies, ZeroAtRest) {
  for (const MembraneOptions& o : {stvk(2.0, 0.3), springs(1.5, 0.7), conformal(0.8)}) {
    for (const Mesh& rest : {flatSquare(), curvedRest()}) {
      const MembraneSetup setup(rest, o);
      EXPECT_LE(setup.energy(rest.positions), 1e-28);
      const optimize::EnergyGradient g =
          optimize::energyGradient(setup.termPointers(), rest.positions, Eigen::VectorXd());
      EXPECT_LE(g.energy, 1e-28);
      EXPECT_LE(g.gradient.lpNorm<Eigen::Infinity>(), 1e-13);
    }
  }
}

// Rigid motions of a curved rest state cost nothing: F = Q, FᵀF = I; ℓ and A unchanged.
TEST(MembraneEnergies, ZeroUnderRigidMotions) {
  std::mt19937 rng(32);
  const Mesh rest = curvedRest();
  for (const MembraneOptions& o : {stvk(2.0, 0.3), springs(1.5, 0.7), conformal(0.8)}) {
    const MembraneSetup setup(rest, o);
    for (int trial = 0; trial < 3; ++trial) {
      const Positions moved =
          testing::transformed(rest.positions, testing::randomRotation(rng), {1.0, -4.0, 2.5});
      // Roundoff in the strain, ~1e-16, squared: measured below 1e-30.
      EXPECT_LE(setup.energy(moved), 1e-26);
    }
  }
}

// A uniform stretch F = diag(s, 1) of the flat unit square: ε = diag((s² − 1)/2, 0) on every
// face, Ψ_ν(ε) = ((s² − 1)/2)² for every ν, and A = 1.
TEST(MembraneEnergies, StvkUniaxialStretch) {
  const Mesh rest = flatSquare();
  for (double nu : {0.3, 0.0, -0.5, 0.5}) {
    const double young = 2.5;
    const MembraneSetup setup(rest, stvk(young, nu));
    ASSERT_NEAR(setup.rest.faceAreas.sum(), 1.0, 1e-14);
    for (double s : {0.7, 1.3, 2.0}) {
      const double strain = (s * s - 1.0) / 2.0;
      const double expected = young / (2.0 * (1.0 - nu * nu)) * strain * strain;
      const Positions x = mapped(rest.positions, Eigen::DiagonalMatrix<double, 2>(s, 1.0));
      EXPECT_NEAR(setup.energy(x), expected, 1e-13 * expected) << "ν " << nu << " s " << s;
    }
  }
}

// General homogeneous deformations F (biaxial, shear) have ε = ½ (FᵀF − I) on every face and
// E = Y / (2 (1 − ν²)) Ψ_ν(ε) · A; the same with the rest sheet and the deformed one placed
// anywhere in space (rest frame and current frame rotated independently).
TEST(MembraneEnergies, StvkHomogeneousDeformations) {
  std::mt19937 rng(33);
  const Mesh flat = flatSquare();
  const double young = 1.7, nu = 0.35;
  Mesh rest = flat;
  rest.positions = testing::transformed(flat.positions, testing::randomRotation(rng), {2, 1, -3});
  const MembraneSetup setup(rest, stvk(young, nu));
  std::vector<Eigen::Matrix2d> deformations(3);
  deformations[0] << 1.2, 0.0, 0.0, 0.8;  // biaxial
  deformations[1] << 1.0, 0.4, 0.0, 1.0;  // simple shear
  deformations[2] << 1.1, -0.3, 0.2, 0.9;
  for (const Eigen::Matrix2d& f : deformations) {
    const Eigen::Matrix2d strain = 0.5 * (f.transpose() * f - Eigen::Matrix2d::Identity());
    const double expected =
        young / (2.0 * (1.0 - nu * nu)) * psi(strain(0, 0), strain(0, 1), strain(1, 1), nu);
    const Positions x =
        testing::transformed(mapped(flat.positions, f), testing::randomRotation(rng), {-1, 0.5, 7});
    EXPECT_NEAR(setup.energy(x), expected, 1e-13 * expected) << f;
  }
}

// Scaling the whole mesh by s: ℓ = s ℓ̄ and A = s² Ā, so
// E = k_L Σ_e (s − 1)² ℓ̄_e + k_A Σ_T (s² − 1)² Ā_T.
TEST(MembraneEnergies, SpringsUniformScaling) {
  const Mesh rest = curvedRest();
  const double kL = 1.5, kA = 0.7;
  const MembraneSetup setup(rest, springs(kL, kA));
  ASSERT_EQ(setup.terms.size(), 2u);
  const double lengths = setup.rest.edgeLengths.sum(), area = setup.rest.faceAreas.sum();
  for (double s : {0.6, 1.1, 3.0}) {
    const Positions x = s * rest.positions;
    const double edges = kL * (s - 1.0) * (s - 1.0) * lengths;
    const double faces = kA * (s * s - 1.0) * (s * s - 1.0) * area;
    EXPECT_NEAR(setup.terms[0]->energy(x, Eigen::VectorXd()), edges, 1e-13 * edges) << s;
    EXPECT_NEAR(setup.terms[1]->energy(x, Eigen::VectorXd()), faces, 1e-13 * faces) << s;
  }
}

// F = diag(s, 1) on the n × n 4-8 patch (h = 1/n): the n (n + 1) edges along x become s h long,
// the n (n + 1) along y keep h, the n² diagonals go from √2 h to √(s² + 1) h; every area grows
// by s. E = k_L [n (n + 1) (s − 1)² h + n² h (√(s² + 1) − √2)² / √2] + k_A (s − 1)² · 1.
TEST(MembraneEnergies, SpringsUniaxialStretch) {
  const int n = 6;
  const double h = 1.0 / n, kL = 2.0, kA = 0.5;
  const Mesh rest = modeling::generateMesh({MeshFamily::Patch48, n, 1, {}});
  const MembraneSetup setup(rest, springs(kL, kA));
  for (double s : {0.5, 1.25, 2.0}) {
    const Positions x = mapped(rest.positions, Eigen::DiagonalMatrix<double, 2>(s, 1.0));
    const double diagonal = std::sqrt(s * s + 1.0) - std::sqrt(2.0);
    const double edges = kL * (n * (n + 1) * (s - 1.0) * (s - 1.0) * h +
                               n * n * h * diagonal * diagonal / std::sqrt(2.0));
    const double faces = kA * (s - 1.0) * (s - 1.0);
    EXPECT_NEAR(setup.terms[0]->energy(x, Eigen::VectorXd()), edges, 1e-13 * edges) << s;
    EXPECT_NEAR(setup.terms[1]->energy(x, Eigen::VectorXd()), faces, 1e-13 * faces) << s;
  }
}

std::string membraneErrorOf(const MembraneOptions& o) {
  const Mesh mesh = modeling::generateMesh({MeshFamily::Patch48, 2, 1, {}});
  const modeling::Stencils s = modeling::compileStencils(mesh);
  const modeling::RestState rest = modeling::precomputeRestState(s, mesh.positions);
  try {
    curvature::makeMembraneEnergy(s, rest, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MembraneEnergies, BadStvkParametersRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double young : {0.0, -1.0, nan, inf})
    EXPECT_THAT(membraneErrorOf(stvk(young, 0.3)), ::testing::StartsWith("MembraneOptions.young"))
        << young;
  // Plane-stress ν lies in (−1, 1/2]: 1 − ν² > 0 and a positive bulk modulus.
  for (double nu : {-1.0, -1.5, 0.51, 1.0, nan}) {
    EXPECT_THAT(membraneErrorOf(stvk(1.0, nu)), ::testing::StartsWith("MembraneOptions.poisson"))
        << nu;
  }
  for (double nu : {-0.99, 0.0, 0.5}) EXPECT_EQ(membraneErrorOf(stvk(1.0, nu)), "") << nu;
}

TEST(MembraneEnergies, BadSpringStiffnessRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double k : {0.0, -2.0, nan}) {
    EXPECT_THAT(
        membraneErrorOf(springs(k, 1.0)),
        ::testing::StartsWith("MembraneOptions.lengthStiffness (edge spring stiffness k_L)"))
        << k;
    EXPECT_THAT(membraneErrorOf(springs(1.0, k)),
                ::testing::StartsWith("MembraneOptions.areaStiffness (area spring stiffness k_A)"))
        << k;
  }
}

// Conformal: a similarity (rotation times any scale) of a curved rest state costs nothing; a
// shear F = [[1, γ], [0, 1]] of the flat square gives C = [[1, γ], [γ, 1 + γ²]] on every face, so
// q = (γ⁴ + 4γ²) / (2 + γ²)² per face and E = k_S · #F · q.
TEST(MembraneEnergies, ConformalKeepsShapesNotSizes) {
  std::mt19937 rng(33);
  const Mesh rest = curvedRest();
  const MembraneSetup curved(rest, conformal(0.8));
  for (double scale : {0.25, 1.0, 3.0}) {
    Positions moved =
        testing::transformed(rest.positions, testing::randomRotation(rng), {0.5, 2.0, -1.0});
    moved *= scale;
    EXPECT_LE(curved.energy(moved), 1e-26) << "scale " << scale;
  }
  const Mesh flat = flatSquare();
  const double k = 0.8;
  const MembraneSetup setup(flat, conformal(k));
  for (double gamma : {0.1, 0.5, 2.0}) {
    Eigen::Matrix2d shear;
    shear << 1.0, gamma, 0.0, 1.0;
    const double g2 = gamma * gamma;
    const double q = (g2 * g2 + 4.0 * g2) / ((2.0 + g2) * (2.0 + g2));
    EXPECT_NEAR(setup.energy(mapped(flat.positions, shear)), k * flat.faceCount() * q,
                1e-12 * flat.faceCount())
        << "shear " << gamma;
  }
  // An anisotropic stretch diag(s, 1): q = ((s² − 1) / (s² + 1))².
  const double s = 1.7, q = std::pow((s * s - 1.0) / (s * s + 1.0), 2);
  EXPECT_NEAR(setup.energy(mapped(flat.positions, Eigen::DiagonalMatrix<double, 2>(s, 1.0))),
              k * flat.faceCount() * q, 1e-12 * flat.faceCount());
}

TEST(MembraneEnergies, ParseModel) {
  EXPECT_EQ(curvature::parseMembraneModel("stvk"), MembraneModel::Stvk);
  EXPECT_EQ(curvature::parseMembraneModel("springs"), MembraneModel::Springs);
  EXPECT_EQ(curvature::parseMembraneModel("conformal"), MembraneModel::Conformal);
  try {
    curvature::parseMembraneModel("rubber");
    ADD_FAILURE() << "an unknown membrane was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("rubber"));
  }
}

// Keeps every element a term hands over.
struct CollectingSink : curvature::ElementHessianSink {
  std::vector<curvature::ElementHessian> elements;
  void add(const curvature::ElementHessian& e) override { elements.push_back(e); }
};

std::vector<curvature::ElementHessian> elementHessians(const EnergyTerm& term, const Positions& x,
                                                       curvature::SecondDerivatives kind) {
  CollectingSink sink;
  term.elementHessians(x, Eigen::VectorXd(), 0, term.elementCount(), curvature::Derivatives::All,
                       kind, sink);
  return sink.elements;
}

// The log barriers (barrier_term.h): asked for Gauss–Newton, each element's Hessian is its exact
// one projected to positive semidefinite — positive semidefinite, and the exact one bit for bit
// where that is (outside the band, where b = 0) — while the exact one is the derivative of the
// gradient (central differences, h = 1e-6). A 6 × 4 Delaunay sheet, every vertex moved by up to
// 0.04 in x, y, z: angle barrier α_min = 5°, band 50°; dihedral barrier
// ceiling 0.6 rad, band 0.5 rad, built flat (its hinges moved a quarter as far).
TEST(MembraneEnergies, BarriersProjectTheirExactHessianForGaussNewton) {
  const Mesh mesh = modeling::generateMesh({MeshFamily::Delaunay, 6, 4, {}});
  const modeling::Stencils s = modeling::compileStencils(mesh);
  Positions x = mesh.positions;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> move(-0.04, 0.04);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += move(random);
  std::vector<int> faces(s.faceCount()), hinges(s.hingeCount());
  for (int f = 0; f < s.faceCount(); ++f) faces[f] = f;
  for (int h = 0; h < s.hingeCount(); ++h) hinges[h] = h;
  constexpr double kDegree = 3.14159265358979323846 / 180.0;
  const Positions bent = mesh.positions + 0.25 * (x - mesh.positions);
  const std::pair<std::unique_ptr<EnergyTerm>, Positions> cases[] = {
      {curvature::makeAngleBarrier(s, faces, x, 2.0, 5.0 * kDegree, 50.0 * kDegree), x},
      {curvature::makeDihedralBarrier(s, hinges, mesh.positions, 2.0, 0.6, 0.5, 0.0), bent}};
  for (const auto& [term, at] : cases) {
    SCOPED_TRACE(term->name());
    const auto exact = elementHessians(*term, at, curvature::SecondDerivatives::Exact);
    const auto gaussNewton = elementHessians(*term, at, curvature::SecondDerivatives::GaussNewton);
    ASSERT_EQ(exact.size(), gaussNewton.size());
    int indefinite = 0, zero = 0;
    for (size_t e = 0; e < exact.size(); ++e) {
      const Eigen::MatrixXd& h = exact[e].hessian;
      const Eigen::MatrixXd& p = gaussNewton[e].hessian;
      EXPECT_EQ(gaussNewton[e].unknowns, exact[e].unknowns);
      EXPECT_EQ(gaussNewton[e].gradient, exact[e].gradient);
      const double scale = std::max(h.cwiseAbs().maxCoeff(), 1e-300);
      const double lowest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues()[0];
      EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(p).eigenvalues()[0], -1e-12 * scale);
      if (lowest >= 0.0) {
        EXPECT_EQ(p, h);
        zero += h.isZero(0.0);
      } else {
        ++indefinite;
        EXPECT_LT(lowest, -1e-6 * scale);  // a real negative curvature, projected away
        EXPECT_EQ(p, curvature::projectedToPositiveSemidefinite(h));
      }
    }
    EXPECT_GT(indefinite, static_cast<int>(exact.size()) / 4);
    if (term->name() == "angle barrier") {
      EXPECT_GT(zero, 0);
    }
    // ∇²E_e against central differences of ∇E_e, at a few elements in the band.
    for (size_t e = 0; e < exact.size(); e += 7) {
      const curvature::ElementHessian& element = exact[e];
      for (size_t k = 0; k < element.unknowns.size(); ++k) {
        const long u = element.unknowns[k];
        Positions plus = at, minus = at;
        plus.data()[u] += 1e-6;  // Positions is row-major: unknown 3v + c
        minus.data()[u] -= 1e-6;
        const auto gp = elementHessians(*term, plus, curvature::SecondDerivatives::None)[e];
        const auto gm = elementHessians(*term, minus, curvature::SecondDerivatives::None)[e];
        const Eigen::VectorXd column = (gp.gradient - gm.gradient) / 2e-6;
        EXPECT_LT(
            (column - element.hessian.col(static_cast<Eigen::Index>(k))).cwiseAbs().maxCoeff(),
            1e-5 * (1.0 + element.hessian.cwiseAbs().maxCoeff()))
            << "element " << e << " unknown " << u;
      }
    }
  }
}

}  // namespace
}  // namespace flexure
