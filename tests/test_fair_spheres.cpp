// Fairing against known answers (issue #15): the sphere and the Clifford torus are Willmore
// surfaces, so a fair surface through a spoiled cap's held rings is the surface itself. The meshes
// of modeling/willmore_surfaces.h, and the distance of faired caps from the exact sphere for
// CGAL's fair and flexure's fairing on the input's and on the current metric.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "curvature/energy_registry.h"
#include "modeling/errors.h"
#include "modeling/fairing_region.h"
#include "modeling/mesh_check.h"
#include "modeling/stencils.h"
#include "modeling/vertex_sets.h"
#include "modeling/willmore_surfaces.h"
#include "optimize/fairing/fairing.h"

namespace flexure {
namespace {

using modeling::Mesh;
using modeling::WillmoreSurface;
constexpr double kPi = 3.14159265358979323846;

// Σ_T (x0 · (x1 × x2)) / 6: the enclosed volume, positive for outward-facing triangles.
double enclosedVolume(const Mesh& m) {
  double volume = 0.0;
  for (int f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d x0 = m.positions.row(m.triangles(f, 0)),
                          x1 = m.positions.row(m.triangles(f, 1)),
                          x2 = m.positions.row(m.triangles(f, 2));
    volume += x0.dot(x1.cross(x2)) / 6.0;
  }
  return volume;
}

double largestDistance(WillmoreSurface surface, const modeling::Positions& x,
                       const std::vector<bool>* only = nullptr) {
  double largest = 0.0;
  for (int v = 0; v < x.rows(); ++v)
    if (!only || (*only)[v])
      largest = std::max(largest, modeling::relativeDistance(surface, x.row(v).transpose()));
  return largest;
}

TEST(WillmoreSurfaces, MeshesLieOnTheirSurfacesFacingOut) {
  const Mesh sphere = modeling::irregularSphere(3, 0.3, 7);
  EXPECT_EQ(sphere.vertexCount(), 642);
  EXPECT_EQ(sphere.faceCount(), 1280);
  EXPECT_TRUE(modeling::checkMesh(sphere).valid());
  EXPECT_LT(largestDistance(WillmoreSurface::Sphere, sphere.positions), 1e-14);
  EXPECT_NEAR(enclosedVolume(sphere), 4.0 * kPi / 3.0, 0.02 * 4.0 * kPi / 3.0);
  // Irregular: not the icosphere (its vertices moved by up to 0.3 edges).
  EXPECT_NE(sphere.positions, modeling::irregularSphere(3, 0.0, 7).positions);

  const Mesh torus = modeling::cliffordTorus(20, 0.3, 7);
  EXPECT_EQ(torus.vertexCount(), 28 * 20);
  EXPECT_EQ(torus.faceCount(), 2 * 28 * 20);
  EXPECT_TRUE(modeling::checkMesh(torus).valid());
  EXPECT_LT(largestDistance(WillmoreSurface::CliffordTorus, torus.positions), 1e-14);
  const double volume = 2.0 * kPi * kPi * std::sqrt(2.0);  // 2π² R r², R = √2, r = 1
  EXPECT_NEAR(enclosedVolume(torus), volume, 0.03 * volume);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(2.0, 0.3, 0.1), Eigen::Vector3d(0.1, -1.5, 0.9)})
    EXPECT_NEAR((modeling::closestPoint(WillmoreSurface::CliffordTorus, p) - p).norm(),
                modeling::relativeDistance(WillmoreSurface::CliffordTorus, p), 1e-12);
  EXPECT_THROW(modeling::irregularSphere(-1, 0.3, 7), InputError);
  EXPECT_THROW(modeling::cliffordTorus(2, 0.3, 7), InputError);
}

// CGAL's isotropic remeshing: a valid closed mesh on the sphere with CGAL's own connectivity
// (valences other than the icosphere's 5 and 6) and edges near the target.
TEST(WillmoreSurfaces, RemeshedSphereHasCgalConnectivity) {
  const Mesh sphere = modeling::remeshedSphere(0.14);
  EXPECT_TRUE(modeling::checkMesh(sphere).valid());
  EXPECT_LT(largestDistance(WillmoreSurface::Sphere, sphere.positions), 1e-14);
  EXPECT_NEAR(enclosedVolume(sphere), 4.0 * kPi / 3.0, 0.02 * 4.0 * kPi / 3.0);
  std::vector<int> valence(sphere.vertexCount(), 0);
  double lengthSum = 0.0;
  for (int f = 0; f < sphere.faceCount(); ++f) {
    for (int i = 0; i < 3; ++i) {
      ++valence[sphere.triangles(f, i)];  // each edge counted once per side: valence = faces
      lengthSum += (sphere.positions.row(sphere.triangles(f, i)) -
                    sphere.positions.row(sphere.triangles(f, (i + 1) % 3)))
                       .norm();
    }
  }
  const auto [low, high] = std::minmax_element(valence.begin(), valence.end());
  EXPECT_LE(*low, 4);
  EXPECT_GE(*high, 8);
  EXPECT_NEAR(lengthSum / (3.0 * sphere.faceCount()), 0.14, 0.03);
  EXPECT_THROW(modeling::remeshedSphere(0.0), InputError);
}

TEST(WillmoreSurfaces, CapsArePerturbedOnlyInside) {
  const Mesh sphere = modeling::irregularSphere(4, 0.3, 7);
  const Eigen::Vector3d pole(0.0, 0.0, 1.0);
  const std::vector<bool> cap =
      modeling::capRegion(WillmoreSurface::Sphere, sphere, pole, 60.0 * kPi / 180.0);
  // The cap's share of the vertices is its share of the area, (1 − cos 60°) / 2 = 1/4.
  EXPECT_NEAR(modeling::countVertices(cap) / double(sphere.vertexCount()), 0.25, 0.02);
  const modeling::Positions flat = modeling::perturbRegion(
      WillmoreSurface::Sphere, sphere, cap, pole, modeling::Perturbation::Flatten, 0.0, 11);
  const modeling::Positions noisy = modeling::perturbRegion(
      WillmoreSurface::Sphere, sphere, cap, pole, modeling::Perturbation::Noise, 0.05, 11);
  double lowest = 1.0;
  for (int v = 0; v < sphere.vertexCount(); ++v)
    if (cap[v]) lowest = std::min(lowest, sphere.positions(v, 2));
  for (int v = 0; v < sphere.vertexCount(); ++v) {
    if (!cap[v]) {
      EXPECT_EQ(flat.row(v), sphere.positions.row(v));
      EXPECT_EQ(noisy.row(v), sphere.positions.row(v));
      continue;
    }
    EXPECT_NEAR(flat(v, 2), lowest, 1e-14);  // pressed onto the plane of the lowest cap vertex
    EXPECT_LE(std::abs(noisy.row(v).norm() - 1.0), 0.05 + 1e-14);
    EXPECT_LT((noisy.row(v).normalized() - sphere.positions.row(v)).norm(), 1e-14);  // radial
  }
}

struct CapFairing {
  double input, cgal, inputMetric, currentMetric;
};

// A cap of `degrees` on `mesh` (of `surface`, centred at `centre`), spoiled, faired by CGAL and by
// flexure with `energy` (w = 0.1, cotan with the barycentric area: `flexure fair --metric
// current`'s defaults) on both metrics; each the largest relative distance from the
// exact surface over the cap.
CapFairing fairCap(WillmoreSurface surface, const Mesh& mesh, const Eigen::Vector3d& centre,
                   double degrees, modeling::Perturbation perturbation,
                   curvature::Discretization energy) {
  const std::vector<bool> cap = modeling::capRegion(surface, mesh, centre, degrees * kPi / 180.0);
  Mesh spoiled = mesh;
  spoiled.positions = modeling::perturbRegion(surface, mesh, cap, centre, perturbation, 0.05, 11);
  const modeling::Stencils stencils = modeling::compileStencils(spoiled);
  const modeling::FairingPatch patch = modeling::extractFairingPatch(spoiled, stencils, cap);
  const auto distance = [&](const modeling::Positions& x) {
    return largestDistance(surface, x, &patch.moves);
  };
  optimize::FairingOptions options;
  options.bending.discretization = energy;
  options.bending.vertexArea = curvature::VertexArea::Barycentric;
  options.membraneWeight = optimize::kCurrentMetricMembraneWeight;
  CapFairing r{distance(patch.mesh.positions), distance(optimize::fairCgal(patch)), 0.0, 0.0};
  for (auto metric : {optimize::FairingMetric::Input, optimize::FairingMetric::Current}) {
    options.metric = metric;
    const optimize::FairingResult faired = optimize::fairNonlinear(patch, options);
    EXPECT_TRUE(faired.report.converged) << faired.report.termination;
    EXPECT_TRUE(optimize::checkFairing(patch, faired.positions, &faired).passed());
    (metric == optimize::FairingMetric::Input ? r.inputMetric : r.currentMetric) =
        distance(faired.positions);
  }
  return r;
}

CapFairing fairRemeshedCap(double edge, double degrees, modeling::Perturbation perturbation,
                           curvature::Discretization energy) {
  return fairCap(WillmoreSurface::Sphere, modeling::remeshedSphere(edge),
                 Eigen::Vector3d(0.0, 0.0, 1.0), degrees, perturbation, energy);
}

CapFairing fairSphereCap(int levels, double degrees, modeling::Perturbation perturbation,
                         curvature::Discretization energy) {
  return fairCap(WillmoreSurface::Sphere, modeling::irregularSphere(levels, 0.3, 7),
                 Eigen::Vector3d(0.0, 0.0, 1.0), degrees, perturbation, energy);
}

// A 60° cap pressed flat (distance 0.5 at its centre) and faired back, at two resolutions.
// Measured (scripts/bench fair-sphere, levels 3 and 4): CGAL 0.171, 0.150; on the input's metric
// midedge 0.036, 0.029 (not approaching the sphere: the flat cap's metric is remembered); on the
// current metric midedge 0.0119, 0.0070, cotan 0.0041, 0.00088, triavg 0.0048, 0.0073 — below a
// tenth of CGAL's — and hinge 0.059, 0.072, which does not approach the sphere either (its
// weight 3ℓ²/(A_f + A_g) is not consistent on irregular meshes).
TEST(FairingSpheres, FlattenedCapComesBackOnTheCurrentMetric) {
  for (auto energy : {curvature::Discretization::Midedge, curvature::Discretization::Cotan,
                      curvature::Discretization::TriangleAveraged}) {
    SCOPED_TRACE(std::string(curvature::discretizationName(energy)));
    const CapFairing coarse = fairSphereCap(3, 60.0, modeling::Perturbation::Flatten, energy);
    const CapFairing fine = fairSphereCap(4, 60.0, modeling::Perturbation::Flatten, energy);
    for (const CapFairing& r : {coarse, fine}) {
      EXPECT_GT(r.input, 0.45);
      EXPECT_LT(r.currentMetric, 0.1 * r.cgal);
      EXPECT_LT(r.currentMetric, 0.6 * r.inputMetric);
    }
    if (energy == curvature::Discretization::Midedge) {
      EXPECT_LT(fine.currentMetric, 0.7 * coarse.currentMetric);  // measured ratio 0.59
    }
    if (energy == curvature::Discretization::Cotan) {
      EXPECT_LT(fine.currentMetric, 0.4 * coarse.currentMetric);  // measured ratio 0.21
    }
  }
  const CapFairing hinge =
      fairSphereCap(4, 60.0, modeling::Perturbation::Flatten, curvature::Discretization::Hinge);
  EXPECT_GT(hinge.currentMetric, 0.3 * hinge.cgal);
}

// 5 % radial noise on a 40° cap: every energy's error on the current metric below a quarter of
// CGAL's. Measured at level 4: CGAL 0.0244; hinge 0.0035, triavg 0.0013, cotan 0.00047, midedge
// 0.0042, quadfit 0.0013.
TEST(FairingSpheres, NoisyCapIsSmoothedCloserThanCgalFair) {
  for (auto energy : curvature::builtinDiscretizations()) {
    SCOPED_TRACE(std::string(curvature::discretizationName(energy)));
    const CapFairing r = fairSphereCap(4, 40.0, modeling::Perturbation::Noise, energy);
    EXPECT_NEAR(r.input, 0.05, 0.001);
    EXPECT_LT(r.currentMetric, 0.25 * r.cgal);
    if (energy == curvature::Discretization::Cotan) {
      EXPECT_LT(r.currentMetric, 0.05 * r.cgal);
    }
  }
}

// A small cap, 20° pressed flat (0.059 deep) at level 4: the linear fair is close already
// (CGAL 0.0029), every energy closer on the current metric. Measured: hinge 0.0022, triavg
// 0.00076, cotan 0.00045, midedge 0.0014, quadfit 0.00093.
TEST(FairingSpheres, SmallFlattenedCapEveryEnergyBelowCgal) {
  for (auto energy : curvature::builtinDiscretizations()) {
    SCOPED_TRACE(std::string(curvature::discretizationName(energy)));
    const CapFairing r = fairSphereCap(4, 20.0, modeling::Perturbation::Flatten, energy);
    EXPECT_GT(r.input, 0.05);
    EXPECT_LT(r.currentMetric, 0.85 * r.cgal);
    if (energy == curvature::Discretization::Cotan) {
      EXPECT_LT(r.currentMetric, 0.25 * r.cgal);
    }
  }
}

// The membrane's fade (FairingOptions::membraneFadeStages, on by default on the current metric):
// the flattened 60° cap's max error with the fade against one solve at w = 0.1 (today's before the
// fade). Measured (midedge, levels 3 and 4): 0.0119 → 0.0105 and 0.0070 → 0.0059; the smallest
// angle 18.77° → 19.22° and 18.00° → 18.43°. Fails without the fade.
TEST(FairingSpheres, MembraneFadeBringsTheFlattenedCapCloser) {
  const Eigen::Vector3d pole(0.0, 0.0, 1.0);
  for (int level : {3, 4}) {
    SCOPED_TRACE(level);
    const Mesh sphere = modeling::irregularSphere(level, 0.3, 7);
    const std::vector<bool> cap =
        modeling::capRegion(WillmoreSurface::Sphere, sphere, pole, 60.0 * kPi / 180.0);
    Mesh spoiled = sphere;
    spoiled.positions = modeling::perturbRegion(WillmoreSurface::Sphere, sphere, cap, pole,
                                                modeling::Perturbation::Flatten, 0.0, 11);
    const modeling::Stencils stencils = modeling::compileStencils(spoiled);
    const modeling::FairingPatch patch = modeling::extractFairingPatch(spoiled, stencils, cap);
    optimize::FairingOptions options =
        optimize::defaultFairingOptions(optimize::FairingMetric::Current);
    options.bending.discretization = curvature::Discretization::Midedge;
    ASSERT_EQ(options.membraneFadeStages, optimize::kCurrentMetricMembraneFadeStages);
    const optimize::FairingResult faded = optimize::fairNonlinear(patch, options);
    options.membraneFadeStages = 0;
    const optimize::FairingResult single = optimize::fairNonlinear(patch, options);
    for (const optimize::FairingResult* r : {&faded, &single}) {
      EXPECT_TRUE(r->report.converged) << r->report.termination;
      EXPECT_TRUE(optimize::checkFairing(patch, r->positions, r).passed());
    }
    const double fadedError =
        largestDistance(WillmoreSurface::Sphere, faded.positions, &patch.moves);
    const double singleError =
        largestDistance(WillmoreSurface::Sphere, single.positions, &patch.moves);
    EXPECT_LT(fadedError, 0.9 * singleError);
    EXPECT_LT(fadedError, level == 3 ? 0.011 : 0.0062);
    EXPECT_GT(faded.report.iterations, single.report.iterations);  // the stages' sum
    EXPECT_GE(optimize::checkFairing(patch, faded.positions, &faded).resultMinAngleDegrees,
              optimize::checkFairing(patch, single.positions, &single).resultMinAngleDegrees - 0.1);
  }
}

// The same on CGAL's remeshed sphere (target edge 0.138 and 0.069, the icosphere's at levels 3
// and 4). Measured: CGAL 0.161, 0.143; midedge 0.0076, 0.0039; cotan 0.0037, 0.00078.
TEST(FairingSpheres, FlattenedCapOfARemeshedSphereComesBack) {
  for (auto energy : {curvature::Discretization::Midedge, curvature::Discretization::Cotan}) {
    SCOPED_TRACE(std::string(curvature::discretizationName(energy)));
    for (double edge : {0.138, 0.069}) {
      const CapFairing r = fairRemeshedCap(edge, 60.0, modeling::Perturbation::Flatten, energy);
      EXPECT_GT(r.input, 0.45);
      EXPECT_LT(r.currentMetric, 0.1 * r.cgal);
      EXPECT_LT(r.currentMetric, r.inputMetric);
    }
  }
}

// The Clifford torus (n = 20, 40: 560 and 2 240 vertices), a 60° cap pressed flat. Measured:
// CGAL 0.137, 0.098; midedge 0.0175, 0.0132; cotan 0.028, 0.0094.
TEST(FairingSpheres, FlattenedTorusCapComesBack) {
  const Eigen::Vector3d centre(std::sqrt(2.0) + 1.0, 0.0, 0.0);
  for (auto energy : {curvature::Discretization::Midedge, curvature::Discretization::Cotan}) {
    SCOPED_TRACE(std::string(curvature::discretizationName(energy)));
    for (int n : {20, 40}) {
      const CapFairing r =
          fairCap(WillmoreSurface::CliffordTorus, modeling::cliffordTorus(n, 0.3, 7), centre, 60.0,
                  modeling::Perturbation::Flatten, energy);
      EXPECT_GT(r.input, 0.4);
      EXPECT_LT(r.currentMetric, 0.25 * r.cgal);
      EXPECT_LT(r.currentMetric, r.inputMetric);
    }
  }
}

}  // namespace
}  // namespace flexure
