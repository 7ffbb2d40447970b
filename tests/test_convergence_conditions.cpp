#include <gtest/gtest.h>

#include <cstdio>

#include "modeling/generators.h"
#include "support/linearized.h"

namespace flexure {
namespace {

using curvature::BendingOptions;
using curvature::Discretization;
using modeling::PolynomialSurface;

TEST(Scratch, C1Table) {
  const modeling::Mesh mesh = modeling::generateMesh({modeling::MeshFamily::Patch48, 8, 1, {}});
  for (auto d : {Discretization::Hinge, Discretization::TriangleAveraged, Discretization::Cotan,
                 Discretization::Midedge, Discretization::QuadraticFit}) {
    for (auto area : {curvature::VertexArea::Voronoi, curvature::VertexArea::Barycentric}) {
      if (d != Discretization::Cotan && area == curvature::VertexArea::Barycentric) continue;
      BendingOptions o;
      o.discretization = d;
      o.vertexArea = area;
      testing::LinearizedSetup setup(mesh, o);
      const double nu = curvature::effectivePoisson(o);
      for (auto q : {std::array<double, 3>{1, 0, 0}, {0, 1, 0}, {1, 0, 1}, {1, 0, -1}, {0.3, -0.7, 0.5}}) {
        const double a = q[0], b = q[1], c = q[2];
        const double rho = (1 - nu) * (4 * a * a + 2 * b * b + 4 * c * c) + nu * (2 * a + 2 * c) * (2 * a + 2 * c);
        const double got = setup.energyPerArea(PolynomialSurface::quadratic(a, b, c));
        std::printf("%-8s %d  (%g,%g,%g)  rho=%.12g  got=%.12g  ratio=%.9f\n",
                    std::string(curvature::discretizationName(d)).c_str(), (int)area, a, b, c, rho, got, got / rho);
      }
    }
  }
}

}  // namespace
}  // namespace flexure
