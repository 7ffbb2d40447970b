// The precompute/solve linear algebra (optimize/linear/): CholeskyFactor against dense solves,
// its failure report and shift; LinearizedSolver's solves equal to the one-off minimize() bit for
// bit while factoring once; the convergence study's factorizations per case.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <map>
#include <numeric>

#include "modeling/errors.h"
#include "modeling/generators.h"
#include "optimize/linear/cholesky_factor.h"
#include "optimize/linear/linearized_solver.h"
#include "optimize/studies/convergence_study.h"

namespace flexure {
namespace {

using modeling::MeshFamily;
using modeling::PolynomialSurface;
using optimize::BoundaryNormals;
using optimize::CholeskyFactor;
using optimize::CholeskyMatrix;
using optimize::CholeskyOptions;
using optimize::FlatPlateProblem;
using optimize::FlatPlateSolves;

// The upper triangle of a dense symmetric matrix in compressed columns.
struct UpperColumns {
  std::vector<int> columnStart{0}, rowIndex;
  std::vector<double> values;
  explicit UpperColumns(const Eigen::MatrixXd& m) {
    for (int j = 0; j < m.cols(); ++j) {
      for (int i = 0; i <= j; ++i) {
        if (m(i, j) == 0.0) continue;
        rowIndex.push_back(i);
        values.push_back(m(i, j));
      }
      columnStart.push_back(static_cast<int>(rowIndex.size()));
    }
  }
};

// The 1D Laplacian tridiag(−1, 2, −1) of size n: positive definite.
Eigen::MatrixXd laplacian(int n) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    m(i, i) = 2.0;
    if (i + 1 < n) m(i, i + 1) = m(i + 1, i) = -1.0;
  }
  return m;
}

TEST(CholeskyFactor, SolvesASymmetricMatrixOnAnyOrder) {
  const int n = 12;
  const Eigen::MatrixXd m = laplacian(n);
  const UpperColumns upper(m);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  std::vector<int> reversed(n);
  std::iota(reversed.rbegin(), reversed.rend(), 0);
  for (const std::vector<int>& order : {std::vector<int>{}, reversed}) {
    CholeskyFactor factor(n, upper.columnStart, upper.rowIndex, order, CholeskyOptions{});
    ASSERT_TRUE(factor.factor(upper.values.data())) << factor.failure();
    EXPECT_EQ(factor.failure(), "");
    EXPECT_LT((m * factor.solve(b) - b).norm(), 1e-12 * b.norm());
    // The same analysis, factored again with a shift: (M + 3 I) x = b.
    ASSERT_TRUE(factor.factor(upper.values.data(), 3.0));
    const Eigen::MatrixXd shifted = m + 3.0 * Eigen::MatrixXd::Identity(n, n);
    EXPECT_LT((shifted * factor.solve(b) - b).norm(), 1e-12 * b.norm());
    EXPECT_EQ(factor.factorizations(), 2);
  }
}

// CHOLMOD's own orders (AMD, METIS, its nested dissection) solve the same system, and nnz(L)
// is counted: between the tridiagonal matrix's own 2n − 1 entries and a dense triangle's.
TEST(CholeskyFactor, SolvesOnEachFillReducingOrder) {
  const int n = 40;
  const Eigen::MatrixXd m = laplacian(n);
  const UpperColumns upper(m);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  for (const optimize::FillReducingOrder ordering :
       {optimize::FillReducingOrder::Amd, optimize::FillReducingOrder::Metis,
        optimize::FillReducingOrder::NestedDissection}) {
    CholeskyOptions options;
    options.ordering = ordering;
    CholeskyFactor factor(n, upper.columnStart, upper.rowIndex, {}, options);
    ASSERT_TRUE(factor.factor(upper.values.data())) << factor.failure();
    EXPECT_LT((m * factor.solve(b) - b).norm(), 1e-12 * b.norm());
    EXPECT_GE(factor.factorNonzeros(), 2 * n - 1);
    EXPECT_LE(factor.factorNonzeros(), n * (n + 1) / 2);
  }
}

TEST(CholeskyFactor, ReportsAMatrixThatIsNotPositiveDefinite) {
  const int n = 6;
  const Eigen::MatrixXd m = laplacian(n) - 1.0 * Eigen::MatrixXd::Identity(n, n);  // λ_min < 0
  const UpperColumns upper(m);
  CholeskyOptions options;
  options.cholmodWarnings = false;
  CholeskyFactor factor(n, upper.columnStart, upper.rowIndex, {}, options);
  EXPECT_FALSE(factor.factor(upper.values.data()));
  EXPECT_NE(factor.failure().find("not positive definite"), std::string::npos) << factor.failure();
  // Shifted past the smallest eigenvalue 2 − 2 cos(π/7) − 1 ≈ −0.80 it factors.
  EXPECT_TRUE(factor.factor(upper.values.data(), 1.0));
  EXPECT_EQ(factor.failure(), "");
}

TEST(CholeskyFactor, FactorsTheGramMatrixOfARectangularMatrix) {
  // A is 4 × 7: A Aᵀ + β I from A's columns.
  Eigen::MatrixXd a(4, 7);
  a << 1, 0, 2, 0, 1, 0, 3,  //
      0, 1, 0, 1, 2, 0, 0,   //
      1, 1, 0, 0, 0, 4, 1,   //
      0, 0, 1, 2, 0, 1, 1;
  std::vector<int> columnStart{0}, rowIndex;
  std::vector<double> values;
  for (int j = 0; j < a.cols(); ++j) {
    for (int i = 0; i < a.rows(); ++i) {
      if (a(i, j) == 0.0) continue;
      rowIndex.push_back(i);
      values.push_back(a(i, j));
    }
    columnStart.push_back(static_cast<int>(rowIndex.size()));
  }
  CholeskyOptions options;
  options.matrix = CholeskyMatrix::Gram;
  CholeskyFactor factor(4, columnStart, rowIndex, {}, options);
  ASSERT_EQ(factor.size(), 4);
  ASSERT_TRUE(factor.factor(values.data(), 0.5));
  const Eigen::VectorXd b(Eigen::Vector4d(1, -2, 0.5, 3));
  const Eigen::MatrixXd gram = a * a.transpose() + 0.5 * Eigen::MatrixXd::Identity(4, 4);
  EXPECT_LT((gram * factor.solve(b) - b).norm(), 1e-12 * b.norm());
}

// The one-off linearized minimize() and the precomputed solver give the same bits, and the
// solver factors once for any number of boundary data.
void expectSolvesEqualMinimize(const char* energy, BoundaryNormals normals, MeshFamily family) {
  const auto variant = optimize::parseEnergyVariant(energy);
  const FlatPlateProblem problem(modeling::generateMesh({family, 8, 1, {}}), variant.bending);
  const FlatPlateSolves solves(problem, normals);
  const optimize::FlatPlateEnergyPerArea energyPerArea(problem);
  for (const auto& q : optimize::defaultQuadratics()) {
    const PolynomialSurface p = q.surface();
    const optimize::MinimizeResult once =
        optimize::solveWithSurfaceBoundary(problem, p, normals, true);
    const optimize::LinearizedSolution reused = solves.surface(p);
    EXPECT_EQ(once.report.factorizations, 1);
    EXPECT_TRUE(reused.positions == once.positions) << energy << " " << p.spec();
    EXPECT_TRUE(reused.xi == once.xi) << energy << " " << p.spec();
    EXPECT_EQ(reused.energy, once.report.finalEnergy) << energy << " " << p.spec();
    EXPECT_EQ(reused.gradientNorm, once.report.gradientNorm) << energy << " " << p.spec();
    EXPECT_EQ(energyPerArea(p), optimize::linearizedEnergyPerArea(problem, p))
        << energy << " " << p.spec();
  }
  EXPECT_EQ(solves.factorizations(), 1) << energy;
  EXPECT_EQ(energyPerArea.factorizations(), problem.bending().usesEdgeUnknowns() ? 1 : 0) << energy;
}

TEST(LinearizedSolver, ReusedFactorGivesTheOneOffSolvesBitForBit) {
  for (MeshFamily family : {MeshFamily::Patch48, MeshFamily::Delaunay}) {
    for (const char* energy : {"hinge", "triavg", "cotan", "cotan:barycentric", "quadfit"})
      expectSolvesEqualMinimize(energy, BoundaryNormals::Clamped, family);
    expectSolvesEqualMinimize("midedge", BoundaryNormals::Clamped, family);
    expectSolvesEqualMinimize("midedge:free", BoundaryNormals::Free, family);
  }
}

TEST(LinearizedSolver, ReproducesAQuadraticAndKeepsTheFixedUnknowns) {
  // cotan passes C2 on the 4-8 patch: the interior lands on z = p up to round-off.
  const FlatPlateProblem problem(modeling::generateMesh({MeshFamily::Patch48, 8, 1, {}}),
                                 optimize::parseEnergyVariant("cotan").bending);
  const FlatPlateSolves solves(problem, BoundaryNormals::Clamped);
  const PolynomialSurface p = PolynomialSurface::quadratic(0.3, -0.7, 0.5);
  const optimize::LinearizedSolution s = solves.surface(p);
  const auto& rest = problem.rest.positions;
  for (int v = 0; v < rest.rows(); ++v) {
    EXPECT_NEAR(s.positions(v, 2), p.height(rest(v, 0), rest(v, 1)), 1e-11) << v;
    EXPECT_EQ(s.positions(v, 0), rest(v, 0));
    EXPECT_EQ(s.positions(v, 1), rest(v, 1));
  }
  EXPECT_LT(s.gradientNorm, 1e-9);
}

// A small height-field plate of one energy, two rings held, with its LinearizedSolver factored for
// those rings; `bc` holds the same rings at rest (a test moves them).
struct HeightFieldSolve {
  FlatPlateProblem problem;
  optimize::LinearizedSolver solver;
  optimize::BoundaryConditions bc;

  explicit HeightFieldSolve(const char* energy)
      : problem(modeling::generateMesh({MeshFamily::Patch48, 4, 1, {}}),
                optimize::parseEnergyVariant(energy).bending),
        solver({&problem.bending()}, problem.rest.positions, problem.restXi,
               optimize::LinearizedUnknowns{problem.boundary.fixedVertex, {}, true}) {
    bc.fixedVertex = problem.boundary.fixedVertex;
    bc.start = problem.rest.positions;
  }
};

TEST(LinearizedSolver, HeightFieldSolverRefusesInPlaneBoundaryMoves) {
  HeightFieldSolve plate("hinge");
  const FlatPlateProblem& problem = plate.problem;
  const optimize::LinearizedSolver& solver = plate.solver;
  optimize::BoundaryConditions& bc = plate.bc;
  bc.start(0, 0) += 0.1;  // vertex 0 is on the boundary
  ASSERT_TRUE(problem.boundary.fixedVertex[0]);
  EXPECT_THROW(solver.solve(bc), InputError);
}

TEST(LinearizedSolver, RefusesBoundaryConditionsItWasNotFactoredFor) {
  HeightFieldSolve plate("cotan");
  const optimize::LinearizedSolver& solver = plate.solver;
  optimize::BoundaryConditions& bc = plate.bc;
  bc.start.col(2).array() += 0.25;  // a lifted boundary: the factored masks, a proper solve
  const optimize::LinearizedSolution s = solver.solve(bc);
  EXPECT_GT(s.initialGradientNorm, 0.0);
  EXPECT_LT(s.gradientNorm, 1e-10 * s.initialGradientNorm);
  // Another held set, or other sizes, would be solved with the wrong factor.
  int interior = 0;
  while (bc.fixedVertex[interior]) ++interior;
  bc.fixedVertex[interior] = true;
  EXPECT_THROW(solver.solve(bc), InputError);
  bc.fixedVertex[interior] = false;
  bc.start.conservativeResize(bc.start.rows() - 1, 3);
  EXPECT_THROW(solver.solve(bc), InputError);
}

TEST(Study, EachCaseFactorsItsLinearizedSystemOnce) {
  optimize::StudyOptions o;
  o.energies = {optimize::parseEnergyVariant("cotan"), optimize::parseEnergyVariant("midedge")};
  o.families = {MeshFamily::Patch48};
  o.levels = 2;
  o.amplitudes = 0;
  const optimize::StudyResults results = optimize::runConvergenceStudy(o);
  std::map<std::pair<int, int>, int> perCase;  // (energy, level) → factorizations
  for (const optimize::StudyRecord& r : results.records)
    perCase[{r.energy, r.level}] += r.factorizations;
  ASSERT_EQ(perCase.size(), 4u);
  for (int level = 0; level < 2; ++level) {
    EXPECT_EQ((perCase[{0, level}]), 1) << "cotan level " << level;    // C2 and refinement
    EXPECT_EQ((perCase[{1, level}]), 2) << "midedge level " << level;  // and C1's ξ solve
  }
}

}  // namespace
}  // namespace flexure
