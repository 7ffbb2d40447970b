// The linear baselines flexure is measured against: the cotangent bi-Laplacian (the floor) and
// CGAL's Polygon_mesh_processing::fair.
#include <gtest/gtest.h>

#include "modeling/boundary_rings.h"
#include "modeling/cgal_fair.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "optimize/boundary_conditions.h"
#include "optimize/linear/biharmonic.h"

namespace flexure {
namespace {

using modeling::MeshFamily;
using modeling::PolynomialSurface;

struct Plate {
  modeling::Mesh mesh;
  modeling::Stencils stencils;
  modeling::RestState rest;
  explicit Plate(MeshFamily family, int n = 8)
      : mesh(modeling::generateMesh({family, n, 1, {}})),
        stencils(modeling::compileStencils(mesh)),
        rest(modeling::precomputeRestState(stencils, mesh.positions)) {}
};

Eigen::VectorXd sampled(const modeling::Positions& x, const PolynomialSurface& p) {
  Eigen::VectorXd z(x.rows());
  for (int v = 0; v < x.rows(); ++v) z[v] = p.height(x(v, 0), x(v, 1));
  return z;
}

TEST(CotanLaplacian, AnnihilatesConstantsAndInteriorLinearFunctions) {
  const Plate plate(MeshFamily::Delaunay);
  const optimize::SparseMatrix laplacian = optimize::cotanLaplacian(plate.stencils, plate.rest);
  EXPECT_LT((laplacian * Eigen::VectorXd::Ones(plate.mesh.vertexCount())).cwiseAbs().maxCoeff(),
            1e-12);
  const Eigen::VectorXd linear =
      sampled(plate.mesh.positions, PolynomialSurface::parse("polynomial:2*x-3*y+1"));
  const Eigen::VectorXd image = laplacian * linear;
  for (int v = 0; v < plate.mesh.vertexCount(); ++v)
    if (!plate.stencils.vertexOnBoundary[v]) {
      EXPECT_NEAR(image[v], 0.0, 1e-12);
    }
  EXPECT_LT(
      (Eigen::MatrixXd(laplacian) - Eigen::MatrixXd(laplacian).transpose()).cwiseAbs().maxCoeff(),
      1e-14);
}

TEST(CotanLaplacian, IsTheVoronoiAreaTimesTheLaplacianOfAQuadraticOnThe48Patch) {
  const Plate plate(MeshFamily::Patch48);
  const auto p = PolynomialSurface::quadratic(0.3, -0.7, 0.5);  // Δp = 2(0.3 + 0.5) = 1.6
  const Eigen::VectorXd image =
      optimize::cotanLaplacian(plate.stencils, plate.rest) * sampled(plate.mesh.positions, p);
  for (int v = 0; v < plate.mesh.vertexCount(); ++v)
    if (!plate.stencils.vertexOnBoundary[v]) {
      EXPECT_NEAR(image[v], 1.6 * plate.rest.vertexVoronoiAreas[v], 1e-12);
    }
}

TEST(Biharmonic, ReproducesQuadraticsWithTwoFixedRingsOnThe48Patch) {
  const Plate plate(MeshFamily::Patch48);
  const auto p = PolynomialSurface::quadratic(0.3, -0.7, 0.5);
  const std::vector<bool> fixed = optimize::fixedRings(plate.stencils, 2);
  Eigen::VectorXd heights = sampled(plate.mesh.positions, p);
  for (int v = 0; v < heights.size(); ++v)
    if (!fixed[v]) heights[v] = 0.0;  // the free heights start wrong
  const Eigen::VectorXd solved =
      optimize::solveBiharmonic(plate.stencils, plate.rest, fixed, heights);
  EXPECT_LT((solved - sampled(plate.mesh.positions, p)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(CgalFair, SolvesTheCotanBiharmonicSystemOfItsInputAndHoldsTheFixedVertices) {
  // CGAL's fair (continuity 1) makes L M⁻¹ L x vanish at the free vertices with the cotangent
  // weights and Voronoi areas of the mesh it is given — here a flat plate whose two outer rings
  // were lifted onto a cubic — for x, y and z alike. flexure's floor solve on that same mesh
  // must agree coordinate by coordinate.
  const Plate plate(MeshFamily::Delaunay, 10);
  const auto p = PolynomialSurface::parse("polynomial:x^3-3*x*y^2+0.5*x*y");
  const std::vector<bool> fixed = optimize::fixedRings(plate.stencils, 2);
  modeling::Mesh lifted = plate.mesh;
  lifted.positions = optimize::boundaryFromSurface(plate.mesh.positions, fixed, p);
  std::vector<bool> freeVertex(fixed.size());
  for (size_t v = 0; v < fixed.size(); ++v) freeVertex[v] = !fixed[v];
  const modeling::Positions faired = modeling::cgalFair(lifted, freeVertex);

  const modeling::RestState liftedState =
      modeling::precomputeRestState(plate.stencils, lifted.positions);
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd ours =
        optimize::solveBiharmonic(plate.stencils, liftedState, fixed, lifted.positions.col(c));
    EXPECT_LT((faired.col(c) - ours).cwiseAbs().maxCoeff(), 1e-9) << "coordinate " << c;
  }
  for (int v = 0; v < lifted.vertexCount(); ++v)
    if (fixed[v]) {
      EXPECT_EQ(faired.row(v), lifted.positions.row(v));
    }
}

}  // namespace
}  // namespace flexure
