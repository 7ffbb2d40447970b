// The separable exact element Hessians of cotan and midedge (curvature/cotan_element_hessian.cpp,
// curvature/midedge_element_hessian.cpp: the chain rule through the elements' sums) equal the
// dense second-order jets of the same residual functors (element_hessian.h's templates) to
// roundoff: energies to 1e-14, gradients and Hessians to 1e-10 of their largest entry, on random
// and nearly flat stencils, in xyz and height mode; cotan rings of valence 3 to 10 on the rest and
// the current metric (both vertex areas) and a ring that reads a vertex twice; midedge faces with
// every pattern of boundary edges (0 to 3 flaps), on both metrics. (tests/test_hessians.cpp checks
// both against central differences of the gradient through the assembly.)
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "curvature/element_hessian.h"

namespace flexure {
namespace {

using curvature::CotanMeanCurvatureResidual;
using curvature::Derivatives;
using curvature::ElementHessian;
using curvature::MidedgeResidual;

// An element's blocks: values (3 per vertex, 1 per ξ) and their first unknowns, in block order.
struct Blocks {
  std::vector<std::vector<double>> values;
  std::vector<long> firstUnknown;
  std::vector<int> sizes;
  std::vector<const double*> pointers() const {
    std::vector<const double*> p;
    for (const auto& v : values) p.push_back(v.data());
    return p;
  }
  void add(std::vector<double> v, long first) {
    sizes.push_back(static_cast<int>(v.size()));
    values.push_back(std::move(v));
    firstUnknown.push_back(first);
  }
};

void expectSameDerivatives(const ElementHessian& separable, const ElementHessian& jets) {
  ASSERT_EQ(separable.unknowns, jets.unknowns);
  EXPECT_NEAR(separable.energy, jets.energy, 1e-14 * jets.energy + 1e-300);
  const double gradientScale = jets.gradient.cwiseAbs().maxCoeff();
  EXPECT_LE((separable.gradient - jets.gradient).cwiseAbs().maxCoeff(), 1e-10 * gradientScale);
  ASSERT_EQ(separable.hessian.rows(), jets.hessian.rows());
  ASSERT_EQ(separable.hessian.cols(), jets.hessian.cols());
  const double scale = jets.hessian.cwiseAbs().maxCoeff();
  EXPECT_GT(scale, 0.0);
  EXPECT_LE((separable.hessian - jets.hessian).cwiseAbs().maxCoeff(), 1e-10 * scale);
  EXPECT_EQ(separable.hessian, separable.hessian.transpose());
}

template <class Residual>
void compareWithJets(const Residual& residual, const Blocks& blocks) {
  for (Derivatives d : {Derivatives::All, Derivatives::HeightOnly}) {
    SCOPED_TRACE(d == Derivatives::All ? "xyz" : "height");
    ElementHessian separable, jets;
    ASSERT_TRUE(curvature::elementHessian(residual, blocks.pointers(), blocks.sizes,
                                          blocks.firstUnknown, d, separable));
    ASSERT_TRUE(curvature::elementHessian<Residual>(residual, blocks.pointers(), blocks.sizes,
                                                    blocks.firstUnknown, d, jets));
    expectSameDerivatives(separable, jets);
  }
}

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized())
      .toRotationMatrix();
}

// ---------------------------------------------------------------------------------------------
// Cotan.

// A vertex and its counter-clockwise ring of k vertices at radii 0.7 to 1.3, lifted by random
// heights of size `height` (1e-7: nearly flat), then moved rigidly.
Blocks cotanRing(std::mt19937& rng, int k, double height) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Matrix3d rotation = randomRotation(rng);
  const Eigen::Vector3d shift(u(rng), u(rng), u(rng));
  Blocks b;
  for (int j = 0; j <= k; ++j) {
    Eigen::Vector3d p(0.1 * u(rng), 0.1 * u(rng), height * u(rng));
    if (j > 0) {
      const double angle = 2.0 * M_PI * (j - 1 + 0.2 * u(rng)) / k, radius = 1.0 + 0.3 * u(rng);
      p.head<2>() = radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    }
    p = rotation * p + shift;
    b.add({p.x(), p.y(), p.z()}, 3L * j);
  }
  return b;
}

CotanMeanCurvatureResidual cotanResidual(std::mt19937& rng, int k, bool currentMetric, bool voronoi,
                                         bool restFlat) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  CotanMeanCurvatureResidual r;
  for (int j = 0; j <= k; ++j) r.vertices.push_back(j);
  r.sqrtWeight = 0.5 + std::abs(u(rng));
  r.restValue = restFlat ? 0.0 : u(rng);
  r.currentMetric = currentMetric;
  r.voronoiArea = voronoi;
  return r;
}

TEST(SeparableHessians, CotanEveryValenceThreeToTen) {
  std::mt19937 rng(31);
  for (int k = 3; k <= 10; ++k)
    for (double height : {0.4, 1e-7})
      for (bool currentMetric : {false, true})
        for (bool voronoi : {true, false})
          for (int sample = 0; sample < 4; ++sample) {
            SCOPED_TRACE("valence " + std::to_string(k) + ", height " + std::to_string(height) +
                         (currentMetric ? ", current metric" : ", rest metric") +
                         (voronoi ? ", voronoi" : ", barycentric"));
            const Blocks ring = cotanRing(rng, k, height);
            compareWithJets(cotanResidual(rng, k, currentMetric, voronoi, sample % 2 == 0), ring);
          }
}

// A ring that reads one vertex through two blocks (shared_block_cost.h): both slots carry the
// same global unknown and the same values.
TEST(SeparableHessians, CotanRingReadingAVertexTwice) {
  std::mt19937 rng(32);
  for (bool currentMetric : {false, true}) {
    Blocks ring = cotanRing(rng, 6, 0.3);
    ring.values[4] = ring.values[1];
    ring.values[4][2] += 0.5;  // off the plane of its neighbours' faces
    ring.values[1] = ring.values[4];
    ring.firstUnknown[4] = ring.firstUnknown[1];
    compareWithJets(cotanResidual(rng, 6, currentMetric, true, false), ring);
  }
}

// ---------------------------------------------------------------------------------------------
// Midedge.

// A face (x0, x1, x2) with a flap across each edge i in `flaps` (the parallelogram's fourth
// vertex, lifted out of the face's plane by `fold`), random ξ, edge tensors, signs, rest shape
// operator and weights; moved rigidly.
struct MidedgeCase {
  MidedgeResidual residual;
  Blocks blocks;
};
MidedgeCase midedgeFace(std::mt19937& rng, const std::array<bool, 3>& flaps, double fold) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Matrix3d rotation = randomRotation(rng);
  const Eigen::Vector3d shift(u(rng), u(rng), u(rng));
  Eigen::Vector3d x[3] = {{0.1 * u(rng), 0.1 * u(rng), 0.0},
                          {1.0 + 0.2 * u(rng), 0.1 * u(rng), 0.0},
                          {0.3 + 0.2 * u(rng), 0.9 + 0.2 * u(rng), 0.0}};
  MidedgeCase c;
  MidedgeResidual& r = c.residual;
  r.flapCount = 0;
  for (int i = 0; i < 3; ++i) {
    r.edges[i] = i;
    r.signs[i] = u(rng) < 0.0 ? -1.0 : 1.0;
    r.hasFlap[i] = flaps[i];
    r.edgeTensors[i] = {u(rng), u(rng), u(rng)};
    c.blocks.add({0.3 * u(rng)}, 100 + i);
  }
  r.restShapeOperator = {0.5 * u(rng), 0.5 * u(rng), 0.5 * u(rng)};
  r.weights = curvature::KoiterWeights::make(0.9 * u(rng), 1.0 + std::abs(u(rng)));
  const auto place = [&](const Eigen::Vector3d& p, long first) {
    const Eigen::Vector3d q = rotation * p + shift;
    c.blocks.add({q.x(), q.y(), q.z()}, first);
  };
  for (int i = 0; i < 3; ++i) {
    r.vertices[i] = i;
    place(x[i], 3L * i);
  }
  for (int i = 0; i < 3; ++i) {
    if (!flaps[i]) continue;
    Eigen::Vector3d flap = x[(i + 1) % 3] + x[(i + 2) % 3] - x[i];
    flap += Eigen::Vector3d(0.1 * u(rng), 0.1 * u(rng), fold * (1.0 + 0.5 * u(rng)));
    r.vertices[3 + r.flapCount] = 3 + r.flapCount;
    place(flap, 3L * (3 + r.flapCount));
    ++r.flapCount;
  }
  return c;
}

TEST(SeparableHessians, MidedgeEveryBoundaryPattern) {
  std::mt19937 rng(33);
  for (bool currentMetric : {false, true})
    for (int pattern = 0; pattern < 8; ++pattern)
      for (double fold : {0.8, -1.5, 1e-7})
        for (int sample = 0; sample < 4; ++sample) {
          const std::array<bool, 3> flaps = {(pattern & 1) != 0, (pattern & 2) != 0,
                                             (pattern & 4) != 0};
          SCOPED_TRACE("flaps " + std::to_string(pattern) + ", fold " + std::to_string(fold) +
                       (currentMetric ? ", current metric" : ", rest metric"));
          MidedgeCase c = midedgeFace(rng, flaps, fold);
          c.residual.currentMetric = currentMetric;
          compareWithJets(c.residual, c.blocks);
        }
}

}  // namespace
}  // namespace flexure
