// The secure metric of the current-metric energies (curvature/current_metric.h): faces whose
// angles are all at least α_s = arccos 0.999 keep their exact tensors and hinge factors, bit for
// bit; on a sliver every edge factor ℓ² / (2A) is capped at 2 cot α_s, the value of a face with
// angles α_s at the edge, so the capped factor is continuous as a face thins through α_s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "curvature/current_metric.h"
#include "support/energy_fixtures.h"
#include "support/small_meshes.h"

namespace flexure {
namespace {

using curvature::Sym2;
using curvature::Vec3;

constexpr double kPi = 3.14159265358979323846;
const double kSecureAngle = curvature::kSecureAngleDegrees * kPi / 180.0;

// The isosceles face over the edge (0,0,0)–(1,0,0) with base angles `angle`, apex above.
struct Face {
  Vec3<double> x[3];
};
Face isosceles(double angle) {
  return {{{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.5, 0.5 * std::tan(angle), 0.0}}};
}

// ℓ_i / A_T times the trace of the edge's n̂ n̂ᵀ (= 1): the edge factor the shape operators use.
double edgeFactor(const Face& f, int i, bool secure) {
  const curvature::CurrentFrame<double> frame = curvature::currentFrame(f.x[0], f.x[1], f.x[2]);
  const auto t = curvature::currentEdgeTensors(f.x, frame, secure);
  return (t[i].a + t[i].c) / frame.area;
}

TEST(SecureMetric, TheCapIsTwiceCotangentOfTheSecureAngle) {
  EXPECT_NEAR(std::cos(kSecureAngle), 0.999, 1e-7);
  EXPECT_NEAR(curvature::kSecureEdgeFactor, 2.0 / std::tan(kSecureAngle), 1e-3);
}

TEST(SecureMetric, FacesWithEveryAngleAboveTheSecureAngleAreExact) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  int tested = 0;
  while (tested < 200) {
    Face f;
    Vec3<double> flap;
    for (int v = 0; v < 3; ++v) f.x[v] = {coordinate(rng), coordinate(rng), coordinate(rng)};
    flap = {coordinate(rng), coordinate(rng), coordinate(rng)};
    const Face g{{f.x[1], f.x[0], flap}};
    bool wellShaped = true;
    const Face* faces[] = {&f, &g};
    for (const Face* h : faces) {
      for (int i = 0; i < 3; ++i) {
        const Vec3<double> a = h->x[(i + 1) % 3] - h->x[i], b = h->x[(i + 2) % 3] - h->x[i];
        const double angle =
            std::acos(curvature::dot(a, b) / (curvature::norm(a) * curvature::norm(b)));
        wellShaped = wellShaped && angle >= kSecureAngle;
      }
    }
    if (!wellShaped) continue;
    ++tested;
    const auto frame = curvature::currentFrame(f.x[0], f.x[1], f.x[2]);
    const auto exact = curvature::currentEdgeTensors(f.x, frame);
    const auto secure = curvature::currentEdgeTensors(f.x, frame, true);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(secure[i].a, exact[i].a);
      EXPECT_EQ(secure[i].b, exact[i].b);
      EXPECT_EQ(secure[i].c, exact[i].c);
    }
    EXPECT_EQ(curvature::hingeMetricFactor(f.x[0], f.x[1], f.x[2], flap, true),
              curvature::hingeMetricFactor(f.x[0], f.x[1], f.x[2], flap));
  }
}

TEST(SecureMetric, ASliverTakesTheFactorOfAFaceOfSecureAngles) {
  // Base edge 2 runs x0 → x1 (length 1); its factor ℓ / A = 2 (ℓ² / 2A) / ℓ.
  const double atTheCap = edgeFactor(isosceles(kSecureAngle), 2, false);
  EXPECT_NEAR(atTheCap, 2.0 * curvature::kSecureEdgeFactor, 1e-3 * atTheCap);
  for (double degrees : {2.0, 0.5, 0.05}) {
    SCOPED_TRACE(degrees);
    const Face sliver = isosceles(degrees * kPi / 180.0);
    EXPECT_GT(edgeFactor(sliver, 2, false), atTheCap * 1.2);  // the exact factor grows as 1 / α
    EXPECT_DOUBLE_EQ(edgeFactor(sliver, 2, true), 2.0 * curvature::kSecureEdgeFactor);
    // Every edge: ℓ / A capped at 2 cap / ℓ. The legs' ℓ² / 2A = cot α − cot 2α = 1 / sin 2α is
    // below the cap at 2° (14.3) and above it at 0.5° (57.3).
    for (int i = 0; i < 3; ++i) {
      const double length = curvature::norm(sliver.x[(i + 2) % 3] - sliver.x[(i + 1) % 3]);
      EXPECT_NEAR(
          edgeFactor(sliver, i, true),
          std::min(edgeFactor(sliver, i, false), 2.0 * curvature::kSecureEdgeFactor / length),
          1e-12 * edgeFactor(sliver, i, false));
    }
  }
  // Continuous through the cap: just above α_s the exact factor, just below the cap.
  const double above = edgeFactor(isosceles(kSecureAngle * 1.0001), 2, true);
  const double below = edgeFactor(isosceles(kSecureAngle * 0.9999), 2, true);
  EXPECT_NEAR(above, below, 1e-3 * atTheCap);
}

TEST(SecureMetric, AHingeOnASliverIsBoundedByItsOtherFace) {
  // 3 ℓ² / (A_f + A_g) = 6 / (1 / c_f + 1 / c_g) ≤ 6 c_g: the sliver's c_f capped, never above
  // 6 min(c_g, cap) and at least 3 of the cap against a well-shaped other face.
  const Face sliver = isosceles(0.1 * kPi / 180.0);
  const Vec3<double> below{0.5, -0.5, 0.1};  // the other face (x1, x0, below)
  const double exact = curvature::hingeMetricFactor(sliver.x[0], sliver.x[1], sliver.x[2], below);
  const double secure =
      curvature::hingeMetricFactor(sliver.x[0], sliver.x[1], sliver.x[2], below, true);
  const double cG =
      1.0 / curvature::norm(curvature::cross(below - sliver.x[0], sliver.x[1] - sliver.x[0]));
  EXPECT_NEAR(secure, 6.0 / (1.0 / curvature::kSecureEdgeFactor + 1.0 / cG), 1e-12 * secure);
  EXPECT_LT(secure, exact);
}

// A 4 × 4 grid of unit cells, its third column of cells `width` wide.
modeling::Mesh gridWithColumn(double width) {
  modeling::Mesh m = testing::gridMesh(4, 4);
  for (int v = 0; v < m.positions.rows(); ++v)
    if (m.positions(v, 0) > 2.5) m.positions(v, 0) -= 1.0 - width;
  return m;
}

// The whole energy on the current metric, flat rest, at a curved lift of `mesh`, with the cap or
// without (BendingOptions::secureMetric).
double currentMetricEnergy(const modeling::Mesh& mesh, curvature::Discretization d, bool secure) {
  curvature::BendingOptions o = testing::bendingOptions(d, curvature::RestCurvature::Flat);
  o.metric = curvature::CurvatureMetric::Current;
  o.secureMetric = secure;
  const testing::BendingSetup setup(mesh, o);
  modeling::Positions x =
      mesh.positions;  // z = 0.05 ((x − 2)² + (y − 2)²) + 0.02 x y: a gentle bowl
  for (int v = 0; v < x.rows(); ++v)
    x(v, 2) = 0.05 * ((x(v, 0) - 2.0) * (x(v, 0) - 2.0) + (x(v, 1) - 2.0) * (x(v, 1) - 2.0)) +
              0.02 * x(v, 0) * x(v, 1);
  return setup.term->energy(x, setup.restXi);
}

TEST(SecureMetric, TheEnergiesChangeOnlyOnMeshesWithSlivers) {
  for (curvature::Discretization d :
       {curvature::Discretization::Hinge, curvature::Discretization::TriangleAveraged,
        curvature::Discretization::Midedge}) {
    SCOPED_TRACE(std::string(curvature::discretizationName(d)));
    // Cells 0.3 wide: corners of atan 0.3 = 16.7°, every factor exact.
    const modeling::Mesh wellShaped = gridWithColumn(0.3);
    EXPECT_EQ(currentMetricEnergy(wellShaped, d, true), currentMetricEnergy(wellShaped, d, false));
    // Cells 0.01 wide: corners of 0.57°, the diagonals' factors capped.
    const modeling::Mesh slivers = gridWithColumn(0.01);
    const double secure = currentMetricEnergy(slivers, d, true);
    const double exact = currentMetricEnergy(slivers, d, false);
    EXPECT_GT(std::abs(secure - exact), 1e-3 * exact);
  }
}

}  // namespace
}  // namespace flexure
