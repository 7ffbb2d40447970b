// Contact geometry (optimize/contact/): the squared distances of every distance type against known
// answers and their gradients and Hessians against finite differences, parallel and nearly
// parallel edges with the mollifier, the additive CCD's guarantee on dense samples of random
// motions and its impact times in head-on collisions, and the broad phase against brute force.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <set>

#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/stencils.h"
#include "optimize/contact/broad_phase.h"
#include "optimize/contact/continuous_collision.h"
#include "optimize/contact/primitive_distance.h"

namespace flexure {
namespace {

using Eigen::Vector3d;
using optimize::Matrix12;
using optimize::Vector12;

// f(x) over the 12 stacked coordinates of four points, with its exact gradient and Hessian.
using Function12 = std::function<double(const Vector12&, Vector12*, Matrix12*)>;

Vector12 stacked(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& d) {
  Vector12 x;
  x << a, b, c, d;
  return x;
}

Function12 pointTriangle() {
  return [](const Vector12& x, Vector12* g, Matrix12* h) {
    return optimize::pointTriangleDistanceSquared(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6),
                                                  x.segment<3>(9), g, h);
  };
}
Function12 edgeEdge() {
  return [](const Vector12& x, Vector12* g, Matrix12* h) {
    return optimize::edgeEdgeDistanceSquared(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6),
                                             x.segment<3>(9), g, h);
  };
}
Function12 mollifier(double threshold) {
  return [threshold](const Vector12& x, Vector12* g, Matrix12* h) {
    return optimize::edgeEdgeMollifier(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6),
                                       x.segment<3>(9), threshold, g, h);
  };
}

// Central differences with step `step`: the gradient from values, the Hessian from gradients,
// each within `tolerance` × (the largest entry + 1e-300) of the exact ones; the value without
// derivatives equals the one with them.
void expectDerivativesMatch(const Function12& f, const Vector12& x, double step, double tolerance) {
  Vector12 gradient;
  Matrix12 hessian;
  const double value = f(x, &gradient, &hessian);
  EXPECT_EQ(value, f(x, nullptr, nullptr));
  Vector12 fdGradient;
  Matrix12 fdHessian;
  for (int i = 0; i < 12; ++i) {
    Vector12 plus = x, minus = x;
    plus[i] += step, minus[i] -= step;
    Vector12 gPlus, gMinus;
    fdGradient[i] = (f(plus, &gPlus, nullptr) - f(minus, &gMinus, nullptr)) / (2 * step);
    fdHessian.col(i) = (gPlus - gMinus) / (2 * step);
  }
  const double gScale = gradient.cwiseAbs().maxCoeff() + 1e-300;
  const double hScale = hessian.cwiseAbs().maxCoeff() + 1e-300;
  EXPECT_LE((fdGradient - gradient).cwiseAbs().maxCoeff(), tolerance * gScale)
      << "gradient\n"
      << gradient.transpose() << "\nfinite differences\n"
      << fdGradient.transpose();
  EXPECT_LE((fdHessian - hessian).cwiseAbs().maxCoeff(), tolerance * hScale)
      << "hessian\n"
      << hessian << "\nfinite differences\n"
      << fdHessian;
  EXPECT_LE((hessian - hessian.transpose()).cwiseAbs().maxCoeff(), 1e-12 * hScale);
}

// A rigid motion: the distances are invariant, so each case is checked in a generic frame too.
struct RigidMotion {
  Eigen::Matrix3d rotation;
  Vector3d translation;
  Vector3d operator()(const Vector3d& x) const { return rotation * x + translation; }
};
RigidMotion someRigidMotion() {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()) *
                             Eigen::AngleAxisd(-1.1, Vector3d::UnitZ()))
                                .toRotationMatrix();
  return {r, Vector3d(0.3, -1.2, 2.5)};
}

// The reference triangle (0,0,0), (1,0,0), (0,1,0) and points above each of its seven regions.
struct PointTriangleCase {
  const char* region;
  Vector3d p;
  double distanceSquared;
};
const PointTriangleCase kPointTriangleCases[] = {
    {"interior", {0.2, 0.2, 0.5}, 0.25},           {"vertex t0", {-0.5, -0.5, 0.3}, 0.59},
    {"vertex t1", {1.5, -0.5, 0.3}, 0.59},         {"vertex t2", {-0.5, 1.5, 0.3}, 0.59},
    {"edge t0 t1", {0.5, -0.5, 0.3}, 0.34},        {"edge t0 t2", {-0.5, 0.5, 0.3}, 0.34},
    {"edge t1 t2", {0.8, 0.8, -0.3}, 0.18 + 0.09},
};

TEST(ContactGeometry, PointTriangleDistanceOfEveryRegionAndItsDerivatives) {
  const Vector3d t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  const RigidMotion motion = someRigidMotion();
  for (const PointTriangleCase& c : kPointTriangleCases) {
    SCOPED_TRACE(c.region);
    EXPECT_NEAR(optimize::pointTriangleDistanceSquared(c.p, t0, t1, t2), c.distanceSquared, 1e-15);
    const Vector12 x = stacked(motion(c.p), motion(t0), motion(t1), motion(t2));
    EXPECT_NEAR(pointTriangle()(x, nullptr, nullptr), c.distanceSquared, 1e-14);
    expectDerivativesMatch(pointTriangle(), x, 1e-5, 1e-7);
  }
}

// The gradient of a squared distance is 2 (closest point difference): zero under a common
// translation, and of length 2 d on the point.
TEST(ContactGeometry, PointTriangleGradientIsTwiceTheOffsetToTheClosestPoint) {
  Vector12 g;
  optimize::pointTriangleDistanceSquared({0.2, 0.2, 0.5}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, &g);
  EXPECT_NEAR((g.segment<3>(0) - Vector3d(0, 0, 1.0)).norm(), 0.0, 1e-14);
  EXPECT_NEAR((g.segment<3>(0) + g.segment<3>(3) + g.segment<3>(6) + g.segment<3>(9)).norm(), 0.0,
              1e-14);
}

struct EdgeEdgeCase {
  const char* type;
  Vector3d b0, b1;  // against a = (0,0,0) – (1,0,0)
  double distanceSquared;
};
const EdgeEdgeCase kEdgeEdgeCases[] = {
    {"line-line", {0.4, -0.5, 0.3}, {0.6, 0.5, 0.3}, 0.09},
    {"point a1 - edge b", {1.5, -0.5, 0.3}, {1.5, 0.5, 0.3}, 0.34},
    {"point b0 - edge a", {0.5, 0.2, 0.3}, {0.5, 1.2, 0.9}, 0.04 + 0.09},
    {"point a1 - point b0", {1.5, 0.5, 0.3}, {1.5, 1.5, 0.5}, 0.59},
    {"parallel, apart: point a1 - point b0", {1.3, 0, 0.2}, {2.3, 0, 0.2}, 0.13},
    {"skew, beyond a0: point a0 - edge b", {-0.5, -0.5, 0.3}, {-0.7, 0.5, -0.3}, -1.0},
};

TEST(ContactGeometry, EdgeEdgeDistanceOfEveryTypeAndItsDerivatives) {
  const Vector3d a0(0, 0, 0), a1(1, 0, 0);
  const RigidMotion motion = someRigidMotion();
  for (const EdgeEdgeCase& c : kEdgeEdgeCases) {
    SCOPED_TRACE(c.type);
    const double d2 = optimize::edgeEdgeDistanceSquared(a0, a1, c.b0, c.b1);
    if (c.distanceSquared >= 0) {
      EXPECT_NEAR(d2, c.distanceSquared, 1e-15);
    }
    // Never above any sample of the segments' distance, and within 1e-3 of their minimum.
    double sampled = INFINITY;
    for (int i = 0; i <= 1000; ++i)
      for (int j = 0; j <= 1000; ++j)
        sampled = std::min(
            sampled,
            (a0 + (a1 - a0) * i / 1000.0 - c.b0 - (c.b1 - c.b0) * j / 1000.0).squaredNorm());
    EXPECT_LE(d2, sampled + 1e-15);
    EXPECT_GE(d2, sampled - 1e-3);
    const Vector12 x = stacked(motion(a0), motion(a1), motion(c.b0), motion(c.b1));
    EXPECT_NEAR(edgeEdge()(x, nullptr, nullptr), d2, 1e-14);
    expectDerivativesMatch(edgeEdge(), x, 1e-5, 1e-7);
  }
}

// Overlapping parallel segments: the distance is attained along the overlap and is not
// differentiable in every direction (tilting one segment brings an end closer), but it is along
// translations of b: d²(δ) = (0.2 + δ_z)² + δ_y², and sliding along the segments changes nothing.
TEST(ContactGeometry, ParallelEdgesTakeAnEndpointDistanceAndItsDerivativesAlongTranslations) {
  const Vector3d a0(0, 0, 0), a1(1, 0, 0), b0(0.5, 0, 0.2), b1(1.5, 0, 0.2);
  Vector12 g;
  Matrix12 h;
  EXPECT_NEAR(optimize::edgeEdgeDistanceSquared(a0, a1, b0, b1, &g, &h), 0.04, 1e-15);
  const auto translationOfB = [](int axis) {
    Vector12 t = Vector12::Zero();
    t[6 + axis] = t[9 + axis] = 1.0;
    return t;
  };
  EXPECT_NEAR(g.dot(translationOfB(0)), 0.0, 1e-14);
  EXPECT_NEAR(g.dot(translationOfB(1)), 0.0, 1e-14);
  EXPECT_NEAR(g.dot(translationOfB(2)), 0.4, 1e-14);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(translationOfB(axis).dot(h * translationOfB(axis)), axis == 0 ? 0.0 : 2.0, 1e-12);
  EXPECT_TRUE(g.allFinite() && h.allFinite());
}

// Edges crossing at an angle θ with sin θ = 1e-4 (distance 0.1 between their lines, closest points
// inside both): the line–line distance, its derivatives (of order 1/sin θ and 1/sin² θ), and the
// mollifier, which is (2 − r) r with r = sin² θ / 10⁻³ there.
TEST(ContactGeometry, NearlyParallelEdgesWithTheMollifier) {
  const double sine = 1e-4, cosine = std::sqrt(1 - sine * sine);
  const Vector3d a0(-0.5, 0, 0), a1(0.5, 0, 0);
  const Vector3d b0(0.1 - 0.6 * cosine, -0.6 * sine, 0.1), b1(0.1 + 0.6 * cosine, 0.6 * sine, 0.1);
  EXPECT_NEAR(optimize::edgeEdgeDistanceSquared(a0, a1, b0, b1), 0.01, 1e-12);
  const RigidMotion motion = someRigidMotion();
  const Vector12 x = stacked(motion(a0), motion(a1), motion(b0), motion(b1));
  expectDerivativesMatch(edgeEdge(), x, 1e-9, 1e-4);

  const double threshold = optimize::edgeEdgeMollifierThreshold(a0, a1, b0, b1);
  EXPECT_NEAR(threshold, 1e-3 * 1.0 * 1.44, 1e-15);
  const double r = sine * sine / 1e-3;
  EXPECT_NEAR(mollifier(threshold)(x, nullptr, nullptr), (2 - r) * r, 1e-9 * r);
  expectDerivativesMatch(mollifier(threshold), x, 1e-6, 1e-6);
  // The distance's Hessian grows as 1/sin² θ; the mollified m d²'s stays bounded as sin θ → 0.
  for (const double s : {1e-4, 1e-5}) {
    const double c = std::sqrt(1 - s * s);
    const Vector12 y = stacked(a0, a1, Vector3d(0.1 - 0.6 * c, -0.6 * s, 0.1),
                               Vector3d(0.1 + 0.6 * c, 0.6 * s, 0.1));
    Vector12 gm, gd;
    Matrix12 hm, hd;
    const double m = mollifier(threshold)(y, &gm, &hm), d2 = edgeEdge()(y, &gd, &hd);
    const Matrix12 product = m * hd + d2 * hm + gm * gd.transpose() + gd * gm.transpose();
    EXPECT_GT(hd.cwiseAbs().maxCoeff(), 1e-2 / (s * s)) << "sin θ = " << s;
    EXPECT_LT(product.cwiseAbs().maxCoeff(), 100.0) << "sin θ = " << s;
  }
}

TEST(ContactGeometry, MollifierIsOneAwayFromParallelAndC1AtTheThreshold) {
  const Vector3d a0(0, 0, 0), a1(1, 0, 0), b0(0.5, -0.5, 0.3), b1(0.5, 0.5, 0.3);
  Vector12 g;
  Matrix12 h;
  const double threshold = optimize::edgeEdgeMollifierThreshold(a0, a1, b0, b1);
  EXPECT_EQ(optimize::edgeEdgeMollifier(a0, a1, b0, b1, threshold, &g, &h), 1.0);
  EXPECT_EQ(g.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(h.cwiseAbs().maxCoeff(), 0.0);
  // Just below c = ε (c = 1 here): m → 1 and ∇m → 0.
  optimize::edgeEdgeMollifier(a0, a1, b0, b1, 1.0 + 1e-9, &g);
  EXPECT_NEAR(optimize::edgeEdgeMollifier(a0, a1, b0, b1, 1.0 + 1e-9), 1.0, 1e-15);
  EXPECT_LT(g.cwiseAbs().maxCoeff(), 1e-8);
}

// --- Continuous collision detection ---

double pointTriangleDistanceAt(const std::array<Vector3d, 8>& m, double t) {
  return std::sqrt(optimize::pointTriangleDistanceSquared(m[0] + t * m[4], m[1] + t * m[5],
                                                          m[2] + t * m[6], m[3] + t * m[7]));
}
double edgeEdgeDistanceAt(const std::array<Vector3d, 8>& m, double t) {
  return std::sqrt(optimize::edgeEdgeDistanceSquared(m[0] + t * m[4], m[1] + t * m[5],
                                                     m[2] + t * m[6], m[3] + t * m[7]));
}
double pointTriangleTime(const std::array<Vector3d, 8>& m, double s = 0.1) {
  return optimize::pointTriangleImpactTime(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], s);
}
double edgeEdgeTime(const std::array<Vector3d, 8>& m, double s = 0.1) {
  return optimize::edgeEdgeImpactTime(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], s);
}

TEST(ContactGeometry, ImpactTimesKeepTheGapOnDenseSamplesOfRandomMotions) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto randomPoint = [&](double scale) -> Vector3d {
    return Vector3d(unit(random), unit(random), unit(random)) * scale;
  };
  int stopped = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::array<Vector3d, 8> m;
    for (int i = 0; i < 4; ++i) m[i] = randomPoint(0.5);
    const double motion = trial % 2 == 0 ? 0.5 : 2.0;
    for (int i = 4; i < 8; ++i) m[i] = randomPoint(motion);
    for (const bool edges : {false, true}) {
      const auto distanceAt = edges ? edgeEdgeDistanceAt : pointTriangleDistanceAt;
      for (const double s : {0.1, 0.5}) {
        const double t = edges ? edgeEdgeTime(m, s) : pointTriangleTime(m, s);
        ASSERT_GE(t, 0.0);
        ASSERT_LE(t, 1.0);
        const double gap = s * distanceAt(m, 0.0);
        for (int k = 0; k <= 2000; ++k)
          ASSERT_GE(distanceAt(m, t * k / 2000.0), gap * (1 - 1e-12))
              << "trial " << trial << (edges ? " edges" : " point") << " s " << s << " t " << t;
        if (t < 1.0) {
          ++stopped;
          // The advancement stopped close to the gap: the distance at t is within 0.1 (d0 − g) of
          // it.
          EXPECT_LE(distanceAt(m, t), gap + 0.1 * (distanceAt(m, 0.0) - gap) * (1 + 1e-9));
        }
      }
    }
  }
  EXPECT_GT(stopped, 100);  // the random motions do bring many pairs together
}

TEST(ContactGeometry, HeadOnImpactTimesAreBelowButNearTheContactTime) {
  // A point falling onto a resting triangle, contact at t = 0.5.
  const std::array<Vector3d, 8> fall = {
      Vector3d(0.2, 0.2, 1), Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0),
      Vector3d(0, 0, -2),    Vector3d::Zero(),  Vector3d::Zero(),  Vector3d::Zero()};
  EXPECT_LT(pointTriangleTime(fall), 0.5);
  EXPECT_GT(pointTriangleTime(fall), 0.4);
  // The triangle rising to meet it: the same contact at t = 0.5 (a common translation is removed).
  std::array<Vector3d, 8> meet = fall;
  meet[4] = Vector3d(0, 0, -1);
  for (int i = 5; i < 8; ++i) meet[i] = Vector3d(0, 0, 1);
  EXPECT_LT(pointTriangleTime(meet), 0.5);
  EXPECT_GT(pointTriangleTime(meet), 0.4);
  // Crossing edges, one rising to the other: contact at t = 0.25.
  const std::array<Vector3d, 8> cross = {
      Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0.5, -0.5, -0.5), Vector3d(0.5, 0.5, -0.5),
      Vector3d::Zero(),  Vector3d::Zero(),  Vector3d(0, 0, 2),         Vector3d(0, 0, 2)};
  EXPECT_LT(edgeEdgeTime(cross), 0.25);
  EXPECT_GT(edgeEdgeTime(cross), 0.2);
  // The same edges turning into each other about the vertical through the crossing point.
  std::array<Vector3d, 8> turn = cross;
  turn[6] = Vector3d(0.3, 0, 1), turn[7] = Vector3d(-0.3, 0, 1);
  const double t = edgeEdgeTime(turn);
  double contact = 1.0;
  for (int k = 0; k <= 100000; ++k)
    if (edgeEdgeDistanceAt(turn, k / 100000.0) <= 1e-9) {
      contact = k / 100000.0;
      break;
    }
  EXPECT_LT(t, contact);
  EXPECT_GT(t, 0.5 * contact);
}

TEST(ContactGeometry, ImpactTimeIsOneForMotionsThatStayApart) {
  // Sliding over the triangle at height 0.5 (above the gap 0.1 √1.25), and moving away.
  const std::array<Vector3d, 8> slide = {
      Vector3d(-1, 0.2, 0.5), Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0),
      Vector3d(2, 0, 0),      Vector3d::Zero(),  Vector3d::Zero(),  Vector3d::Zero()};
  EXPECT_EQ(pointTriangleTime(slide), 1.0);
  std::array<Vector3d, 8> away = slide;
  away[4] = Vector3d(0, 0, 3);
  EXPECT_EQ(pointTriangleTime(away), 1.0);
  std::array<Vector3d, 8> still = slide;
  still[4] = Vector3d::Zero();
  EXPECT_EQ(edgeEdgeTime(still), 1.0);
}

// A point 10⁻⁶ above the triangle sliding 10 along it: the advancement's steps are 10⁻⁷ long,
// so the step cap ends it early, at a time still safe.
TEST(ContactGeometry, ImpactTimeStopsAtTheStepCapWithASafeTime) {
  const std::array<Vector3d, 8> graze = {
      Vector3d(0.1, 0.1, 1e-6), Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0),
      Vector3d(10, 0, 0),       Vector3d::Zero(),  Vector3d::Zero(),  Vector3d::Zero()};
  const double t = pointTriangleTime(graze);
  EXPECT_GT(t, 0.0);
  EXPECT_LT(t, 0.01);
  EXPECT_GE(pointTriangleDistanceAt(graze, t), 1e-7);
}

TEST(ContactGeometry, ImpactTimeRefusesAGapFractionOutsideTheUnitInterval) {
  const Vector3d z = Vector3d::Zero(), x = Vector3d::UnitX(), y = Vector3d::UnitY(), p(0.2, 0.2, 1);
  EXPECT_THROW(optimize::pointTriangleImpactTime(p, z, x, y, -x, z, z, z, 0.0), InputError);
  EXPECT_THROW(optimize::edgeEdgeImpactTime(p, z, x, y, -x, z, z, z, 1.0), InputError);
  // A start distance of 0 admits no motion.
  EXPECT_EQ(optimize::pointTriangleImpactTime(z, z, x, y, y, z, z, z), 0.0);
}

// --- Broad phase ---

// A crumpled sheet: the 4-8 patch with random heights and in-plane jitter, so that its faces come
// close to one another in places.
modeling::Mesh crumpledSheet(std::mt19937& random) {
  modeling::GeneratorOptions options;
  options.n = 8;
  modeling::Mesh mesh = modeling::generateMesh(options);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    mesh.positions(v, 0) += 0.04 * unit(random);
    mesh.positions(v, 1) += 0.04 * unit(random);
    mesh.positions(v, 2) = 0.1 * unit(random);
  }
  return mesh;
}

// Random triangles (a soup), some overlapping, with their edges.
modeling::Mesh randomTriangles(std::mt19937& random, int count) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  modeling::Mesh mesh;
  mesh.positions.resize(3 * count, 3);
  mesh.triangles.resize(count, 3);
  for (int f = 0; f < count; ++f) {
    const Vector3d centre(0.5 * unit(random), 0.5 * unit(random), 0.5 * unit(random));
    for (int i = 0; i < 3; ++i) {
      mesh.positions.row(3 * f + i) =
          (centre + 0.2 * Vector3d(unit(random), unit(random), unit(random))).transpose();
      mesh.triangles(f, i) = 3 * f + i;
    }
  }
  return mesh;
}

modeling::IndexPairs meshEdges(const modeling::Mesh& mesh) {
  std::set<std::array<int, 2>> unique;
  for (int f = 0; f < mesh.faceCount(); ++f)
    for (int i = 0; i < 3; ++i) {
      const int a = mesh.triangles(f, i), b = mesh.triangles(f, (i + 1) % 3);
      unique.insert({std::min(a, b), std::max(a, b)});
    }
  modeling::IndexPairs edges(unique.size(), 2);
  int e = 0;
  for (const auto& pair : unique) edges.row(e++) << pair[0], pair[1];
  return edges;
}

bool shareVertex(const int* a, int aCount, const int* b, int bCount) {
  for (int i = 0; i < aCount; ++i)
    for (int j = 0; j < bCount; ++j)
      if (a[i] == b[j]) return true;
  return false;
}

// Every pair within `inflation` at one of the sampled times of the motion is a candidate; no
// candidate shares a vertex; the lists are sorted, without repeats, edge pairs with i < j.
void expectCandidatesCoverBruteForce(const modeling::Mesh& mesh, const modeling::Positions& dx,
                                     double inflation) {
  const modeling::IndexPairs edges = meshEdges(mesh);
  const optimize::CandidatePairs pairs =
      optimize::contactCandidates(mesh.positions, dx, mesh.triangles, edges, inflation);
  const std::set<std::array<int, 2>> vertexFace(pairs.vertexFace.begin(), pairs.vertexFace.end());
  const std::set<std::array<int, 2>> edgeEdgePairs(pairs.edgeEdge.begin(), pairs.edgeEdge.end());
  EXPECT_EQ(vertexFace.size(), pairs.vertexFace.size());
  EXPECT_EQ(edgeEdgePairs.size(), pairs.edgeEdge.size());
  EXPECT_TRUE(std::is_sorted(pairs.vertexFace.begin(), pairs.vertexFace.end()));
  EXPECT_TRUE(std::is_sorted(pairs.edgeEdge.begin(), pairs.edgeEdge.end()));
  for (const auto& [v, f] : pairs.vertexFace)
    EXPECT_FALSE(shareVertex(&v, 1, mesh.triangles.row(f).data(), 3));
  for (const auto& [e, g] : pairs.edgeEdge) {
    EXPECT_LT(e, g);
    EXPECT_FALSE(shareVertex(edges.row(e).data(), 2, edges.row(g).data(), 2));
  }
  int closeVertexFace = 0, closeEdgeEdge = 0;
  const int samples = dx.rows() == 0 ? 1 : 11;
  for (int k = 0; k < samples; ++k) {
    modeling::Positions x = mesh.positions;
    if (dx.rows() != 0) x += (k / 10.0) * dx;
    const auto point = [&](int v) -> Vector3d { return x.row(v).transpose(); };
    for (int v = 0; v < mesh.vertexCount(); ++v)
      for (int f = 0; f < mesh.faceCount(); ++f) {
        const auto face = mesh.triangles.row(f);
        if (shareVertex(&v, 1, face.data(), 3)) continue;
        if (optimize::pointTriangleDistanceSquared(point(v), point(face[0]), point(face[1]),
                                                   point(face[2])) > inflation * inflation)
          continue;
        ++closeVertexFace;
        EXPECT_TRUE(vertexFace.count({v, f})) << "vertex " << v << " face " << f;
      }
    for (int e = 0; e < edges.rows(); ++e)
      for (int g = e + 1; g < edges.rows(); ++g) {
        if (shareVertex(edges.row(e).data(), 2, edges.row(g).data(), 2)) continue;
        if (optimize::edgeEdgeDistanceSquared(point(edges(e, 0)), point(edges(e, 1)),
                                              point(edges(g, 0)),
                                              point(edges(g, 1))) > inflation * inflation)
          continue;
        ++closeEdgeEdge;
        EXPECT_TRUE(edgeEdgePairs.count({e, g})) << "edges " << e << ", " << g;
      }
  }
  EXPECT_GT(closeVertexFace, 0);  // the case does test something
  EXPECT_GT(closeEdgeEdge, 0);
}

TEST(ContactGeometry, BroadPhaseFindsEveryCloseStaticPair) {
  std::mt19937 random(3);
  expectCandidatesCoverBruteForce(crumpledSheet(random), modeling::Positions(), 0.05);
  expectCandidatesCoverBruteForce(randomTriangles(random, 40), modeling::Positions(), 0.02);
}

TEST(ContactGeometry, BroadPhaseFindsEveryPairThatComesCloseDuringTheMotion) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (modeling::Mesh mesh : {crumpledSheet(random), randomTriangles(random, 40)}) {
    modeling::Positions dx(mesh.vertexCount(), 3);
    for (int v = 0; v < mesh.vertexCount(); ++v)
      dx.row(v) << 0.1 * unit(random), 0.1 * unit(random), 0.2 * unit(random);
    expectCandidatesCoverBruteForce(mesh, dx, 0.02);
  }
}

// The candidates among some vertices are exactly the full broad phase's pairs with a primitive
// touching one of them, in the same sorted lists: for a few marked vertices, for all and for none.
TEST(ContactGeometry, BroadPhaseAmongVerticesIsTheFullPhaseRestricted) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (modeling::Mesh mesh : {crumpledSheet(random), randomTriangles(random, 40)}) {
    const modeling::IndexPairs edges = meshEdges(mesh);
    modeling::Positions dx(mesh.vertexCount(), 3);
    for (int v = 0; v < mesh.vertexCount(); ++v)
      dx.row(v) << 0.1 * unit(random), 0.1 * unit(random), 0.2 * unit(random);
    const optimize::CandidatePairs all =
        optimize::contactCandidates(mesh.positions, dx, mesh.triangles, edges, 0.02);
    for (const double share : {0.1, 1.0, 0.0}) {
      std::vector<bool> among(mesh.vertexCount());
      for (int v = 0; v < mesh.vertexCount(); ++v) among[v] = 0.5 * (unit(random) + 1.0) < share;
      const auto touches = [&](const auto& row) {
        return std::any_of(row.data(), row.data() + row.size(), [&](int v) { return among[v]; });
      };
      optimize::CandidatePairs expected;
      for (const auto& [v, f] : all.vertexFace)
        if (among[v] || touches(mesh.triangles.row(f))) expected.vertexFace.push_back({v, f});
      for (const auto& [e, g] : all.edgeEdge)
        if (touches(edges.row(e)) || touches(edges.row(g))) expected.edgeEdge.push_back({e, g});
      const optimize::CandidatePairs found =
          optimize::contactCandidatesAmong(mesh.positions, dx, mesh.triangles, edges, 0.02, among);
      EXPECT_EQ(found.vertexFace, expected.vertexFace) << "share " << share;
      EXPECT_EQ(found.edgeEdge, expected.edgeEdge) << "share " << share;
      if (share == 0.1) EXPECT_GT(found.vertexFace.size() + found.edgeEdge.size(), 0u);
      if (share == 1.0) EXPECT_EQ(found.vertexFace.size(), all.vertexFace.size());
    }
  }
}

TEST(ContactGeometry, BroadPhaseRefusesMismatchedInput) {
  std::mt19937 random(1);
  const modeling::Mesh mesh = randomTriangles(random, 3);
  const modeling::IndexPairs edges = meshEdges(mesh);
  EXPECT_THROW(optimize::contactCandidates(mesh.positions, modeling::Positions::Zero(2, 3),
                                           mesh.triangles, edges, 0.1),
               InputError);
  EXPECT_THROW(optimize::contactCandidates(mesh.positions, modeling::Positions(), mesh.triangles,
                                           edges, -1.0),
               InputError);
  modeling::Triangles bad = mesh.triangles;
  bad(0, 0) = 99;
  EXPECT_THROW(optimize::contactCandidates(mesh.positions, modeling::Positions(), bad, edges, 0.1),
               InputError);
  EXPECT_THROW(optimize::contactCandidatesAmong(mesh.positions, modeling::Positions(),
                                                mesh.triangles, edges, 0.1, std::vector<bool>(2)),
               InputError);
}

}  // namespace
}  // namespace flexure
