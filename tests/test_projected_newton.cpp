// The projected Newton step (curvature/projected_hessian.h): the projection of an element
// matrix, the assembled projected Hessian of a buckled sheet, and the Newton loop's indefinite
// rule on the drape benchmark's cotan sheet.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "curvature/projected_hessian.h"
#include "modeling/generators.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/problem.h"
#include "optimize/solvers/minimize.h"
#include "support/plate.h"

namespace flexure {
namespace {

using curvature::Discretization;
using curvature::SecondDerivatives;

Eigen::MatrixXd orthogonal(int n) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::NullaryExpr(
      n, n, [](Eigen::Index i, Eigen::Index j) { return std::sin(1.0 + 3.0 * i + 7.0 * j * j); });
  return Eigen::HouseholderQR<Eigen::MatrixXd>(a).householderQ();
}

// h = Q Λ Qᵀ with Λ = (3, −2, 1, −0.5, 0): its projection is Q max(Λ, 0) Qᵀ, eigenvalues
// (0, 0, 0, 1, 3); a positive definite matrix comes back bit for bit.
TEST(ProjectedNewton, ProjectionClampsTheNegativeEigenvalues) {
  const Eigen::MatrixXd q = orthogonal(5);
  Eigen::VectorXd lambda(5);
  lambda << 3.0, -2.0, 1.0, -0.5, 0.0;
  const Eigen::MatrixXd h = q * lambda.asDiagonal() * q.transpose();
  const Eigen::MatrixXd p = curvature::projectedToPositiveSemidefinite(h);
  const Eigen::MatrixXd expected = q * lambda.cwiseMax(0.0).asDiagonal() * q.transpose();
  EXPECT_LT((p - expected).cwiseAbs().maxCoeff(), 1e-14);
  const Eigen::VectorXd eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(p).eigenvalues();
  Eigen::VectorXd sorted(5);
  sorted << 0.0, 0.0, 0.0, 1.0, 3.0;
  EXPECT_LT((eigenvalues - sorted).cwiseAbs().maxCoeff(), 1e-14);
  const Eigen::MatrixXd definite =
      q * (lambda.cwiseAbs().array() + 0.1).matrix().asDiagonal() * q.transpose();
  EXPECT_EQ(curvature::projectedToPositiveSemidefinite(definite), definite);
}

// A cotan + StVK sheet pressed to 90 % of its width and buckled into one wave: its exact Hessian
// is indefinite (the compressed membrane), the assembly's Projected one positive semidefinite,
// and asking for Projected is the same as the PositiveSemidefinite projection of the exact one.
TEST(ProjectedNewton, AssembledHessianOfABuckledSheetIsPositiveSemidefinite) {
  const testing::Plate plate(modeling::MeshFamily::Delaunay, 6, Discretization::Cotan, 1e3);
  modeling::Positions x = plate.rest.positions;
  for (int v = 0; v < x.rows(); ++v) {
    const double s = x(v, 0);
    x(v, 0) = 0.9 * s;
    x(v, 2) = 0.05 * std::cos(3.14159265358979 * s);
  }
  const std::vector<bool> free(x.size(), true);
  const optimize::HessianAssembly a(plate.terms(), free, static_cast<int>(x.rows()),
                                    curvature::Derivatives::All);
  const auto dense = [&](const std::vector<double>& values) {
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(a.size(), a.size());
    for (int c = 0; c < a.size(); ++c)
      for (int k = a.columnStart()[c]; k < a.columnStart()[c + 1]; ++k)
        h(a.rowIndex()[k], c) = h(c, a.rowIndex()[k]) = values[k];
    return h;
  };
  const Eigen::VectorXd noXi;
  const auto exact = a.evaluate(x, noXi, optimize::HessianProjection::Exact);
  const auto projected = a.evaluate(x, noXi, optimize::HessianProjection::Exact, nullptr,
                                    SecondDerivatives::Projected);
  const auto byProjection = a.evaluate(x, noXi, optimize::HessianProjection::PositiveSemidefinite);
  EXPECT_EQ(projected.values, byProjection.values);
  EXPECT_EQ(projected.gradient, exact.gradient);
  const Eigen::MatrixXd h = dense(exact.values), p = dense(projected.values);
  const double scale = h.cwiseAbs().maxCoeff();
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues()[0], -1e-3 * scale);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(p).eigenvalues()[0], -1e-12 * scale);
}

// The static rule's step where the Hessian is indefinite (newton_loop.h, IndefiniteHessian): hinge
// + StVK in xyz lifted onto a saddle, compressed near buckling, has indefinite iterates. Each
// choice — JᵀJ (Exact, the default), H + μI (Shifted), the projected element Hessians
// (ExactOrProjected) — takes its own steps there and reaches the same minimizer.
TEST(ProjectedNewton, EveryIndefiniteHessianRuleReachesTheSameStaticMinimizer) {
  const modeling::Mesh mesh = modeling::generateMesh({modeling::MeshFamily::Delaunay, 6, 4, {}});
  optimize::ProblemOptions shell;
  shell.bending.discretization = Discretization::Hinge;
  curvature::MembraneOptions membrane;
  membrane.model = curvature::MembraneModel::Stvk;
  membrane.young = membrane.lengthStiffness = membrane.areaStiffness = membrane.shapeStiffness =
      10.0;
  shell.membrane = membrane;
  shell.dof = optimize::DofMode::Xyz;
  shell.boundarySurface = modeling::PolynomialSurface::quadratic(1.0, 0.4, -0.8);
  const optimize::Problem problem = optimize::buildProblem(mesh, shell);
  optimize::MinimizeOptions options;
  options.functionTolerance = 1e-16;
  options.gradientTolerance = 1e-12;
  options.maxIterations = 400;
  const optimize::MinimizeResult reference = optimize::minimize(problem, options);
  ASSERT_TRUE(reference.report.converged) << reference.report.termination;
  EXPECT_NE(reference.report.termination.find("on J^T J where the Hessian was indefinite"),
            std::string::npos)
      << reference.report.termination;
  // Measured iterations: 18 on JᵀJ (3 of its Newton steps), 20 shifted (7), 65 projected (51).
  const std::pair<optimize::HessianMode, int> modes[] = {
      {optimize::HessianMode::Shifted, 25}, {optimize::HessianMode::ExactOrProjected, 80}};
  for (const auto& [mode, iterations] : modes) {
    SCOPED_TRACE(static_cast<int>(mode));
    options.hessian = mode;
    const optimize::MinimizeResult other = optimize::minimize(problem, options);
    ASSERT_TRUE(other.report.converged) << other.report.termination;
    EXPECT_LT((other.positions - reference.positions).cwiseAbs().maxCoeff(), 1e-7);
    EXPECT_LE(other.report.iterations, iterations) << other.report.termination;
    const std::string stepsTaken =
        mode == optimize::HessianMode::Shifted ? " 0 shifted by mu I" : "(0 projected where";
    EXPECT_EQ(other.report.termination.find(stepsTaken), std::string::npos)
        << other.report.termination;
    EXPECT_LT(other.report.gradientNorm, 1e-6);
  }
}

}  // namespace
}  // namespace flexure
