// Fracture (seed 002): the criterion's strains against known answers, and the cut along a crack:
// direction, manifoldness, conserved rest area, no sliver made, no energy made, two pieces.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "modeling/crack_cut.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/mesh_check.h"
#include "optimize/inelastic/fracture.h"
#include "optimize/inelastic/fracturing.h"
#include "optimize/problem.h"

namespace flexure {
namespace {

using modeling::CrackCut;
using modeling::Mesh;
using modeling::Positions;
using optimize::FractureOptions;
using optimize::TimeStepper;

constexpr double kPi = 3.14159265358979323846;

Mesh rotated(Mesh mesh, double degrees) {
  const double a = degrees * kPi / 180.0;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  mesh.positions = (mesh.positions * rotation.transpose()).eval();
  return mesh;
}

Mesh patch(int n) {
  modeling::GeneratorOptions options;
  options.n = n;
  return modeling::generateMesh(options);
}

// Pulled along x with the stretch 1 + ε cos(π x̄) (x = x̄ + ε sin(π x̄)/π): the Green strain
// E_xx = ((1 + ε cos π x̄)² − 1)/2 peaks on the line x̄ = 0.
Positions pulledApart(const Mesh& rest, double epsilon) {
  Positions current = rest.positions;
  for (int v = 0; v < rest.vertexCount(); ++v) {
    current(v, 0) += epsilon * std::sin(kPi * rest.positions(v, 0)) / kPi;
  }
  return current;
}

double greenStrain(double stretch) {
  return 0.5 * (stretch * stretch - 1.0);
}

double faceArea(const Positions& x, const Mesh& mesh, int f) {
  const Eigen::Vector3d a = x.row(mesh.triangles(f, 0)).transpose();
  const Eigen::Vector3d b = x.row(mesh.triangles(f, 1)).transpose();
  const Eigen::Vector3d c = x.row(mesh.triangles(f, 2)).transpose();
  return 0.5 * (b - a).cross(c - a).norm();
}

double totalArea(const Mesh& mesh) {
  double area = 0.0;
  for (int f = 0; f < mesh.faceCount(); ++f) area += faceArea(mesh.positions, mesh, f);
  return area;
}

double smallestAngle(const Mesh& mesh, int f) {
  double smallest = 180.0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, k)).transpose();
    const Eigen::Vector3d u = mesh.positions.row(mesh.triangles(f, (k + 1) % 3)).transpose() - a;
    const Eigen::Vector3d w = mesh.positions.row(mesh.triangles(f, (k + 2) % 3)).transpose() - a;
    smallest = std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)) * 180.0 / kPi);
  }
  return smallest;
}

int connectedComponents(const Mesh& mesh) {
  std::vector<int> parent(mesh.vertexCount());
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (int f = 0; f < mesh.faceCount(); ++f) {
    parent[root(mesh.triangles(f, 0))] = root(mesh.triangles(f, 1));
    parent[root(mesh.triangles(f, 1))] = root(mesh.triangles(f, 2));
  }
  std::set<int> roots;
  for (int v = 0; v < mesh.vertexCount(); ++v) roots.insert(root(v));
  return static_cast<int>(roots.size());
}

struct ElasticEnergy {
  double bending = 0.0;
  double membrane = 0.0;
  double total() const { return bending + membrane; }
};

// Hinge bending and StVK membrane of `current` on `rest`, nothing held.
ElasticEnergy elasticEnergies(const Mesh& rest, const Positions& current) {
  optimize::ProblemOptions options;
  options.membrane = curvature::MembraneOptions{};
  options.dof = optimize::DofMode::Xyz;
  options.fixedRings = 0;
  const optimize::Problem problem = optimize::buildProblem(rest, options);
  ElasticEnergy energy;
  energy.bending = problem.bending().energy(current, problem.restXi);
  for (const auto* term : problem.termPointers())
    energy.membrane += term->energy(current, problem.restXi);
  energy.membrane -= energy.bending;
  return energy;
}

double elasticEnergy(const Mesh& rest, const Positions& current) {
  return elasticEnergies(rest, current).total();
}

// ---- the criterion ---------------------------------------------------------------------------

TEST(FractureCriterion, OptionsValidateNameTheField) {
  FractureOptions options;
  options.thickness = 0.01;
  EXPECT_THROW(options.validate(), InputError);
  options.fractureStrain = 0.1;
  EXPECT_NO_THROW(options.validate());
  options.thickness = -1.0;
  try {
    options.validate();
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("FractureOptions.thickness"), std::string::npos);
  }
  options.thickness = 0.0;
  options.fractureStrain = std::nan("");
  EXPECT_THROW(options.validate(), InputError);
}

// A uniform stretch λ along a direction α: every face has E_m = (λ² − 1)/2 along it, whatever the
// mesh's orientation, and cracks perpendicular to it.
TEST(FractureCriterion, UniformStretchHasTheGreenStrainAlongTheLoad) {
  for (double degrees : {0.0, 15.0, 30.0, 45.0}) {
    SCOPED_TRACE(degrees);
    const Mesh rest = rotated(patch(6), degrees);
    const double a = 20.0 * kPi / 180.0;
    const Eigen::Vector3d load(std::cos(a), std::sin(a), 0.0);
    const double stretch = 1.1;
    const Eigen::Matrix3d deformation =
        Eigen::Matrix3d::Identity() + (stretch - 1.0) * load * load.transpose();
    const Positions current = rest.positions * deformation.transpose();
    for (const auto& face : optimize::facePrincipalStrains(rest, current, 0.01)) {
      EXPECT_NEAR(face.strain, greenStrain(stretch), 1e-12);
      EXPECT_NEAR(std::abs(face.strainDirection.dot(load)), 1.0, 1e-12);
      EXPECT_NEAR(face.crackDirection.dot(load), 0.0, 1e-12);
    }
  }
}

// Bending a flat plate isometrically onto a cylinder of curvature κ: E_m ≈ 0 and the fibres at
// ± h/2 carry ± (h/2) κ across the axis (the triangle-averaged shape operator's change).
TEST(FractureCriterion, PureBendingStrainsTheFibresByHalfTheThicknessTimesTheCurvature) {
  const Mesh rest = patch(16);
  const double kappa = 0.5;
  const double thickness = 0.02;
  Positions current = rest.positions;
  for (int v = 0; v < rest.vertexCount(); ++v) {
    const double x = rest.positions(v, 0);
    current(v, 0) = std::sin(kappa * x) / kappa;
    current(v, 2) = (1.0 - std::cos(kappa * x)) / kappa;
  }
  const std::vector<optimize::FaceStrains> strains = optimize::faceStrains(rest, current);
  const std::vector<optimize::FacePrincipalStrain> principal =
      optimize::facePrincipalStrains(rest, current, thickness);
  int interior = 0;
  for (int f = 0; f < rest.faceCount(); ++f) {
    const Eigen::Vector3d centroid =
        (rest.positions.row(rest.triangles(f, 0)) + rest.positions.row(rest.triangles(f, 1)) +
         rest.positions.row(rest.triangles(f, 2)))
            .transpose() /
        3.0;
    if (centroid.cwiseAbs().maxCoeff() > 0.4) continue;  // faces with every edge interior
    ++interior;
    EXPECT_LT(strains[f].membrane.norm(), 1e-3 * kappa * kappa);
    EXPECT_NEAR(std::abs(strains[f].bending.trace()), kappa, 0.03 * kappa);
    EXPECT_NEAR(principal[f].strain, 0.5 * thickness * kappa, 0.03 * 0.5 * thickness * kappa);
    EXPECT_NEAR(std::abs(principal[f].strainDirection.x()), 1.0, 1e-2);
  }
  EXPECT_GT(interior, 100);
}

TEST(FractureCriterion, NoCriticalFaceBelowTheFractureStrain) {
  const Mesh rest = patch(8);
  const Positions current = pulledApart(rest, 0.1);
  FractureOptions options;
  options.fractureStrain = greenStrain(1.1) * 1.0001;
  EXPECT_FALSE(optimize::criticalFace(rest, current, options).has_value());
  options.fractureStrain = greenStrain(1.1) * 0.9;
  const auto critical = optimize::criticalFace(rest, current, options);
  ASSERT_TRUE(critical.has_value());
  EXPECT_GT(critical->strain, options.fractureStrain);
  EXPECT_THROW(optimize::criticalFace(rest, Positions(current.topRows(3)), options), InputError);
}

// ---- the cut ---------------------------------------------------------------------------------

struct StripCrack {
  Mesh rest;
  Positions current;
  CrackCut cut;
};

// Pulls the strip apart (ε = 0.1) with ε_f the strain at |x̄| = 0.15 and cuts from the critical
// face through the faces over ε_f.
StripCrack crackStrip(const Mesh& rest) {
  StripCrack result{rest, pulledApart(rest, 0.1), {}};
  FractureOptions options;
  options.fractureStrain = greenStrain(1.0 + 0.1 * std::cos(0.15 * kPi));
  options.thickness = 0.01;
  const auto critical = optimize::criticalFace(rest, result.current, options);
  EXPECT_TRUE(critical.has_value());
  std::vector<bool> cracking(rest.faceCount(), false);
  const auto strains = optimize::facePrincipalStrains(rest, result.current, options.thickness);
  for (int f = 0; f < rest.faceCount(); ++f)
    cracking[f] = strains[f].strain > options.fractureStrain;
  result.cut = modeling::cutAlongCrack(rest, result.current,
                                       {critical->face, critical->crackDirection}, cracking);
  return result;
}

void expectCleanCut(const StripCrack& strip) {
  const CrackCut& cut = strip.cut;
  // The crack runs across the strip, perpendicular to the load (x), within 5°.
  const Eigen::Vector3d span = (cut.crackRest.bottomRows(1) - cut.crackRest.topRows(1)).transpose();
  const double degrees = std::acos(std::abs(span.normalized().y())) * 180.0 / kPi;
  EXPECT_LT(degrees, 5.0) << "crack from " << cut.crackRest.topRows(1) << " to "
                          << cut.crackRest.bottomRows(1);
  EXPECT_GT(span.norm(), 0.9);
  // Manifold, rest area kept, the configuration unchanged where it was.
  const modeling::MeshCheck check = modeling::checkMesh(cut.rest);
  EXPECT_TRUE(check.valid()) << (check.valid() ? "" : check.problems.front().reason);
  EXPECT_NEAR(totalArea(cut.rest), totalArea(strip.rest), 1e-12 * totalArea(strip.rest));
  for (int v = 0; v < strip.rest.vertexCount(); ++v) {
    EXPECT_EQ(cut.current.row(v), strip.current.row(v));
  }
  // No face the cut made has an angle below 10°.
  std::map<int, int> piecesOf;
  for (int origin : cut.faceOrigin) ++piecesOf[origin];
  int made = 0;
  for (int f = 0; f < cut.rest.faceCount(); ++f) {
    if (piecesOf[cut.faceOrigin[f]] < 2) continue;
    ++made;
    EXPECT_GE(smallestAngle(cut.rest, f), 10.0) << "face " << f;
  }
  EXPECT_EQ(made > 0, cut.facesSplit > 0);
  // Two pieces; the split makes no energy.
  EXPECT_EQ(connectedComponents(cut.rest), 2);
  EXPECT_LE(elasticEnergy(cut.rest, cut.current),
            elasticEnergy(strip.rest, strip.current) * (1.0 + 1e-12));
}

TEST(CrackCut, StripPulledApartCracksAcrossTheLoadOnRotatedMeshes) {
  for (double degrees : {0.0, 15.0, 30.0, 45.0}) {
    SCOPED_TRACE("mesh rotated " + std::to_string(degrees) + "°");
    const StripCrack strip = crackStrip(rotated(patch(16), degrees));
    expectCleanCut(strip);
  }
}

TEST(CrackCut, StripPulledApartCracksAcrossTheLoadOnAnIrregularMesh) {
  for (std::uint64_t seed : {1, 2, 3}) {
    SCOPED_TRACE("delaunay seed " + std::to_string(seed));
    const StripCrack strip = crackStrip(modeling::delaunayMesh(16, seed));
    expectCleanCut(strip);
  }
}

// Curved and stretched: the cut keeps positions and drops the hinges across the crack, and the
// faces it splits are flat inside, so the hinge + StVK energy does not rise.
TEST(CrackCut, NoEnergyIsMadeOnACurvedStrip) {
  Mesh rest = modeling::delaunayMesh(12, 5);
  for (int v = 0; v < rest.vertexCount(); ++v) {
    rest.positions(v, 2) = 0.2 * rest.positions(v, 1) * rest.positions(v, 1);
  }
  Positions current = pulledApart(rest, 0.1);
  for (int v = 0; v < rest.vertexCount(); ++v) current(v, 2) *= 1.5;
  const Eigen::Vector3d x0 = rest.positions.row(rest.triangles(0, 0)).transpose();
  int seedFace = 0;
  double nearest = 1e9;
  for (int f = 0; f < rest.faceCount(); ++f) {
    const Eigen::Vector3d c =
        (rest.positions.row(rest.triangles(f, 0)) + rest.positions.row(rest.triangles(f, 1)) +
         rest.positions.row(rest.triangles(f, 2)))
            .transpose() /
        3.0;
    if (c.head<2>().norm() < nearest) nearest = c.head<2>().norm(), seedFace = f;
  }
  (void)x0;
  const Eigen::Vector3d a = rest.positions.row(rest.triangles(seedFace, 0)).transpose();
  const Eigen::Vector3d normal =
      (rest.positions.row(rest.triangles(seedFace, 1)).transpose() - a)
          .cross(rest.positions.row(rest.triangles(seedFace, 2)).transpose() - a)
          .normalized();
  const Eigen::Vector3d direction = normal.cross(Eigen::Vector3d::UnitX()).normalized();
  const CrackCut cut = modeling::cutAlongCrack(rest, current, {seedFace, direction},
                                               std::vector<bool>(rest.faceCount(), true));
  EXPECT_TRUE(modeling::checkMesh(cut.rest).valid());
  EXPECT_EQ(connectedComponents(cut.rest), 2);
  EXPECT_GT(cut.facesSplit, 0);
  const ElasticEnergy before = elasticEnergies(rest, current);
  const ElasticEnergy after = elasticEnergies(cut.rest, cut.current);
  EXPECT_GT(before.bending, 0.0);
  EXPECT_GT(before.membrane, 0.0);
  // The membrane (constant strain per face) is split exactly; the hinge energy's weights
  // 3 ℓ̄² / (Ā_f + Ā_g) grow on the hinges around the split faces (smaller faces): measured
  // +3.9 % here (docs/energies.md, "Fracture").
  EXPECT_LE(after.membrane, before.membrane * (1.0 + 1e-12));
  EXPECT_LT(after.bending, 1.05 * before.bending);
  EXPECT_NEAR(totalArea(cut.rest), totalArea(rest), 1e-12 * totalArea(rest));
}

// A crack stopped by faces that are not cracking ends at a vertex inside the mesh: one piece,
// still manifold, the tip not duplicated.
TEST(CrackCut, ACrackTipInsideTheMeshLeavesOnePieceAndGrowsLater) {
  const Mesh rest = patch(16);
  std::vector<bool> cracking(rest.faceCount(), false);
  int seedFace = -1;
  for (int f = 0; f < rest.faceCount(); ++f) {
    double cx = 0.0, cy = 0.0;
    for (int k = 0; k < 3; ++k) {
      cx += rest.positions(rest.triangles(f, k), 0) / 3.0;
      cy += rest.positions(rest.triangles(f, k), 1) / 3.0;
    }
    cracking[f] = std::abs(cx) < 0.1 && cy < 0.1;
    if (seedFace < 0 && std::abs(cx - 0.03) < 0.03 && std::abs(cy) < 0.05) seedFace = f;
  }
  ASSERT_GE(seedFace, 0);
  const CrackCut cut = modeling::cutAlongCrack(
      rest, rest.positions, {seedFace, Eigen::Vector3d(0.1, 1.0, 0.0).normalized()}, cracking);
  EXPECT_TRUE(modeling::checkMesh(cut.rest).valid());
  EXPECT_EQ(connectedComponents(cut.rest), 1);
  EXPECT_GT(cut.verticesDuplicated, 0);
  EXPECT_NEAR(totalArea(cut.rest), totalArea(rest), 1e-12);

  // A later check grows the crack from its tip: the face past the tip, cracking now, starts a
  // crack that runs to the outer boundary one way and stops on the first crack the other way.
  const Eigen::Vector3d tip =
      cut.crackRest
          .row(cut.crackRest(0, 1) > cut.crackRest(cut.crackRest.rows() - 1, 1)
                   ? 0
                   : cut.crackRest.rows() - 1)
          .transpose();
  int pastTip = -1;
  double nearest = 1e9;
  for (int f = 0; f < cut.rest.faceCount(); ++f) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
      centroid += cut.rest.positions.row(cut.rest.triangles(f, k)).transpose() / 3.0;
    const double distance = (centroid - tip).norm();
    if (centroid.y() > tip.y() && distance < nearest) nearest = distance, pastTip = f;
  }
  ASSERT_GE(pastTip, 0);
  const CrackCut grown =
      modeling::cutAlongCrack(cut.rest, cut.current, {pastTip, Eigen::Vector3d::UnitY()},
                              std::vector<bool>(cut.rest.faceCount(), true));
  EXPECT_TRUE(modeling::checkMesh(grown.rest).valid());
  EXPECT_EQ(connectedComponents(grown.rest), 2) << "tip " << tip.transpose() << "\nfirst\n"
                                                << cut.crackRest << "\ngrown\n"
                                                << grown.crackRest;
  EXPECT_NEAR(totalArea(grown.rest), totalArea(rest), 1e-12);
}

// One fracture check on a strip pulled apart and moving: the pieces get the velocities of the
// points they were cut from, pins stay with their vertices, and the fragments are the two halves.
TEST(FractureShell, CarriesVelocitiesAndPinsAndGivesTwoFragments) {
  const Mesh rest = rotated(patch(16), 15.0);
  const Positions current = pulledApart(rest, 0.1);
  Positions velocities = Positions::Zero(rest.vertexCount(), 3);
  std::vector<bool> held(rest.vertexCount(), false);
  for (int v = 0; v < rest.vertexCount(); ++v) {
    velocities.row(v) << 2.0 * rest.positions(v, 0), 0.0, 1.0;  // stretching, and rising
    held[v] = std::abs(rest.positions(v, 0)) > 0.45;
  }
  FractureOptions options;
  options.fractureStrain = greenStrain(1.1) * 2.0;
  options.thickness = 0.01;
  EXPECT_FALSE(optimize::fractureShell(rest, current, velocities, held, options).has_value());
  options.fractureStrain = greenStrain(1.0 + 0.1 * std::cos(0.15 * kPi));
  const auto shell = optimize::fractureShell(rest, current, velocities, held, options);
  ASSERT_TRUE(shell.has_value());
  ASSERT_EQ(shell->velocities.rows(), shell->rest.vertexCount());
  for (int v = 0; v < shell->rest.vertexCount(); ++v) {
    // The velocity field is affine in the rest position: interpolation reproduces it exactly.
    EXPECT_NEAR(shell->velocities(v, 0), 2.0 * shell->rest.positions(v, 0), 1e-14);
    EXPECT_EQ(shell->velocities(v, 2), 1.0);
    if (v < rest.vertexCount()) {
      EXPECT_EQ(shell->heldVertex[v], held[v]);
    } else {
      EXPECT_FALSE(shell->heldVertex[v]);  // the crack runs through the middle
    }
  }
  const std::vector<Mesh> fragments = optimize::meshFragments(shell->rest);
  ASSERT_EQ(fragments.size(), 2u);
  double area = 0.0;
  for (const Mesh& fragment : fragments) {
    EXPECT_TRUE(modeling::checkMesh(fragment).valid());
    EXPECT_EQ(connectedComponents(fragment), 1);
    area += totalArea(fragment);
  }
  EXPECT_NEAR(area, totalArea(rest), 1e-12);
  EXPECT_EQ(fragments[0].faceCount() + fragments[1].faceCount(), shell->rest.faceCount());
}

TEST(CrackCut, BadSeedsNameTheProblem) {
  const Mesh rest = patch(4);
  const std::vector<bool> cracking(rest.faceCount(), true);
  EXPECT_THROW(modeling::cutAlongCrack(rest, rest.positions,
                                       {rest.faceCount(), Eigen::Vector3d::UnitX()}, cracking),
               InputError);
  EXPECT_THROW(
      modeling::cutAlongCrack(rest, rest.positions, {0, Eigen::Vector3d::UnitZ()}, cracking),
      InputError);
  EXPECT_THROW(modeling::cutAlongCrack(rest, rest.positions, {0, Eigen::Vector3d::UnitX()},
                                       std::vector<bool>(3, true)),
               InputError);
}

}  // namespace
}  // namespace flexure

namespace flexure {
namespace {

// Cuts from many faces in many directions on curved, closed and open meshes, through every face
// or a third of them: always manifold, the rest area kept, no angle below 10° made.
TEST(CrackCut, AnyCutOnShellsAndIrregularMeshesIsClean) {
  std::vector<std::pair<std::string, Mesh>> meshes;
  for (const auto family : {modeling::MeshFamily::Sphere, modeling::MeshFamily::Cylinder,
                            modeling::MeshFamily::Hemisphere}) {
    modeling::GeneratorOptions options;
    options.family = family;
    options.n = 16;
    meshes.emplace_back(std::string(modeling::meshFamilyName(family)),
                        modeling::generateMesh(options));
  }
  meshes.emplace_back("delaunay", modeling::delaunayMesh(10, 4));
  for (const auto& [name, rest] : meshes) {
    for (int f = 0; f < rest.faceCount(); f += 7) {
      SCOPED_TRACE(name + " face " + std::to_string(f));
      const Eigen::Vector3d a = rest.positions.row(rest.triangles(f, 0)).transpose();
      const Eigen::Vector3d edge = rest.positions.row(rest.triangles(f, 1)).transpose() - a;
      const Eigen::Vector3d normal =
          edge.cross(rest.positions.row(rest.triangles(f, 2)).transpose() - a).normalized();
      const double turn = 0.7 * f;
      const Eigen::Vector3d direction = Eigen::AngleAxisd(turn, normal) * edge.normalized();
      std::vector<bool> cracking(rest.faceCount());
      for (int g = 0; g < rest.faceCount(); ++g) cracking[g] = f % 2 == 0 || g % 3 != 0;
      const CrackCut cut = modeling::cutAlongCrack(rest, rest.positions, {f, direction}, cracking);
      const modeling::MeshCheck check = modeling::checkMesh(cut.rest);
      ASSERT_TRUE(check.valid()) << check.problems.front().element << ": "
                                 << check.problems.front().reason;
      EXPECT_NEAR(totalArea(cut.rest), totalArea(rest), 1e-12 * totalArea(rest));
      std::map<int, int> piecesOf;
      for (int origin : cut.faceOrigin) ++piecesOf[origin];
      for (int g = 0; g < cut.rest.faceCount(); ++g) {
        if (piecesOf[cut.faceOrigin[g]] > 1) {
          EXPECT_GE(smallestAngle(cut.rest, g), 10.0);
        }
      }
      EXPECT_GE(cut.crackVertices.size(), 2u);
    }
  }
}

}  // namespace
}  // namespace flexure

namespace flexure {
namespace {

// Pulled along x with ε(ȳ) = ε₁ + ε₀ (0.5 − ȳ): the Green strain peaks on x̄ = 0 (where the
// shear is zero, so the load is along x there) and grows towards ȳ = −0.5.
Positions pulledMoreBelow(const Mesh& rest, double epsilon0, double epsilon1) {
  Positions current = rest.positions;
  for (int v = 0; v < rest.vertexCount(); ++v) {
    const double epsilon = epsilon1 + epsilon0 * (0.5 - rest.positions(v, 1));
    current(v, 0) += epsilon * std::sin(kPi * rest.positions(v, 0)) / kPi;
  }
  return current;
}

// The faces a cut made (their old face split in two or more): none has an angle below 10°.
void expectNoSliverMade(const CrackCut& cut) {
  std::map<int, int> piecesOf;
  for (int origin : cut.faceOrigin) ++piecesOf[origin];
  for (int f = 0; f < cut.rest.faceCount(); ++f) {
    if (piecesOf[cut.faceOrigin[f]] > 1) {
      EXPECT_GE(smallestAngle(cut.rest, f), 10.0) << "face " << f;
    }
  }
}

// Seed 002: the crack grows from its tip in later steps. The load is along x on `rest` (a mesh of
// the unit square, rotated, or irregular): a first check cracks the lower part (the faces over
// ε_f) and stops inside; with the load raised (over ε_f across), the next check starts at that tip
// (not at the strongest face, which is next to the first crack's lips) and runs on to the far
// boundary. The finished crack, from the first crack's boundary end to the grown one's, and the
// grown part each run across the load (along y) within 5°, and the finished crack spans the mesh's
// width `width` along x = 0: two pieces, manifold, the rest area kept, no angle below 10° made by
// either cut.
void expectCrackGrowsFromItsTipAcrossTheLoad(const Mesh& rest, double width) {
  const auto degreesOffAcross = [](const Eigen::Vector3d& span) {
    return std::acos(std::min(1.0, std::abs(span.normalized().y()))) * 180.0 / kPi;
  };
  FractureOptions options;
  options.fractureStrain = greenStrain(1.0 + 0.1 * 0.5);  // ε(ȳ) = 0.05 at ȳ = 0 in the first
  const Positions first = pulledMoreBelow(rest, 0.1, 0.0);
  const auto cracked =
      optimize::fractureShell(rest, first, Positions::Zero(rest.vertexCount(), 3), {}, options);
  ASSERT_TRUE(cracked.has_value());
  EXPECT_EQ(connectedComponents(cracked->rest), 1);
  expectNoSliverMade(cracked->cut);
  ASSERT_EQ(cracked->openTips.size(), 1u);
  const Eigen::Vector3d tip = cracked->openTips.front();
  const Positions& firstCrack = cracked->cut.crackRest;
  const Eigen::Vector3d firstEnd =
      (firstCrack.row(0).transpose() == tip ? firstCrack.bottomRows(1) : firstCrack.topRows(1))
          .transpose();

  // The load raised on the cut mesh.
  const Positions second = pulledMoreBelow(cracked->rest, 0.1, 0.08);
  const auto grown = optimize::fractureShell(
      cracked->rest, second, Positions::Zero(second.rows(), 3), {}, options, cracked->openTips);
  ASSERT_TRUE(grown.has_value());
  const Positions& crack = grown->cut.crackRest;
  const bool startsAtTip = crack.row(0).transpose() == tip;
  EXPECT_TRUE(startsAtTip || crack.bottomRows(1).transpose() == tip)
      << "tip " << tip.transpose() << "\ncrack\n"
      << crack;
  const Eigen::Vector3d grownEnd =
      (startsAtTip ? crack.bottomRows(1) : crack.topRows(1)).transpose();
  EXPECT_LT(degreesOffAcross(grownEnd - tip), 5.0) << "grown crack\n" << crack;
  const Eigen::Vector3d finished = grownEnd - firstEnd;
  EXPECT_LT(degreesOffAcross(finished), 5.0) << "first crack\n"
                                             << firstCrack << "\ngrown crack\n"
                                             << crack;
  EXPECT_GT(std::abs(finished.y()), width - 2.0 / 16.0);  // each end within an edge of the boundary
  const modeling::MeshCheck check = modeling::checkMesh(grown->rest);
  EXPECT_TRUE(check.valid()) << (check.valid() ? "" : check.problems.front().reason);
  EXPECT_EQ(connectedComponents(grown->rest), 2);
  EXPECT_TRUE(grown->openTips.empty());
  EXPECT_NEAR(totalArea(grown->rest), totalArea(rest), 1e-12 * totalArea(rest));
  expectNoSliverMade(grown->cut);
}

TEST(FractureShell, ACrackGrowsFromItsTipAcrossTheLoadOnRotatedMeshes) {
  for (double degrees : {0.0, 15.0, 30.0, 45.0}) {
    SCOPED_TRACE("mesh rotated " + std::to_string(degrees) + "°");
    // The unit square turned by θ ≤ 45° is 1 / cos θ wide along x = 0.
    expectCrackGrowsFromItsTipAcrossTheLoad(rotated(patch(16), degrees),
                                            1.0 / std::cos(degrees * kPi / 180.0));
  }
}

TEST(FractureShell, ACrackGrowsFromItsTipAcrossTheLoadOnAnIrregularMesh) {
  for (std::uint64_t seed : {1, 2, 3}) {
    SCOPED_TRACE("delaunay seed " + std::to_string(seed));
    expectCrackGrowsFromItsTipAcrossTheLoad(modeling::delaunayMesh(16, seed), 1.0);
  }
}

}  // namespace
}  // namespace flexure

namespace flexure {
namespace {

// A free strip (hinge + StVK, nothing held) started at `x` with the velocities v = rate (x̄, 0, 0),
// stretching along x, fracturing at ε_f.
optimize::FracturingDynamics stretchingStrip(const Mesh& rest, const Positions& x, double rate,
                                             double fractureStrain) {
  optimize::ProblemOptions options;
  options.membrane = curvature::MembraneOptions{};
  options.dof = optimize::DofMode::Xyz;
  options.fixedRings = 0;
  options.boundaryPositions = x;
  optimize::Problem problem = optimize::buildProblem(rest, options);
  FractureOptions fracture;
  fracture.fractureStrain = fractureStrain;
  fracture.thickness = 0.01;
  optimize::FracturingDynamics dynamics(rest, std::move(problem), options, {}, fracture);
  Positions v = Positions::Zero(rest.vertexCount(), 3);
  v.col(0) = rate * rest.positions.col(0);
  dynamics.start(x, v);
  return dynamics;
}

// Seed 002's search in time: a step in which the strain crosses ε_f is halved until the face that
// cracks exceeds ε_f by at most the overshoot band (2 %), so the crack is cut at the event.
TEST(FracturingDynamics, TheSearchInTimeCutsWhenTheStrainReachesTheFractureStrain) {
  const Mesh rest = patch(8);
  Positions x = rest.positions;
  x.col(0) *= 1.02;  // Green strain 0.0202, rising at first at 1.02 · 5 = 5.1 per second
  const double fractureStrain = 0.03;
  optimize::FracturingDynamics dynamics = stretchingStrip(rest, x, 5.0, fractureStrain);
  const double h = 0.004;  // the first step would end far over ε_f
  long step = 0;
  TimeStepper::Advance total;
  for (int k = 0; k < 3 && dynamics.cracks().empty(); ++k) {
    total = dynamics.advance(h, h / 1024.0, step);
    ASSERT_TRUE(total.completed);
    step += total.steps;
  }
  ASSERT_FALSE(dynamics.cracks().empty());
  EXPECT_GT(total.halvings, 0);
  const double first = dynamics.cracks().front().critical.strain;
  EXPECT_GT(first, fractureStrain);
  EXPECT_LE(first, fractureStrain * (1.0 + optimize::FracturingDynamics::kFractureOvershoot));
}

// A step that starts over the band (ε_f (1 + 2 %)) would be discarded at every length down to the
// shortest: it is split at once and none is tried and discarded. A free strip started at a Green
// strain of 0.05 everywhere, stretching on, with ε_f = 0.01: cracks, and no step discarded (10
// were before).
TEST(FracturingDynamics, AStepThatStartsOverTheBandIsNotTried) {
  const Mesh rest = patch(8);
  Positions x = rest.positions;
  x.col(0) *= std::sqrt(1.1);
  optimize::FracturingDynamics dynamics = stretchingStrip(rest, x, 1.0, 0.01);
  const double h = 0.005;
  const TimeStepper::Advance advance = dynamics.advance(h, h / 64.0, 0);
  ASSERT_TRUE(advance.completed);
  EXPECT_EQ(advance.halvings, 0);
  EXPECT_GE(advance.steps, 1);
  EXPECT_FALSE(dynamics.cracks().empty());
}

// Midedge's ξ across a cut: a free strip curved along its length (z = 0.3 x̄², bending energy in
// its ξ) stretching past ε_f is cut; right after the cut the stepper's ξ has one entry per
// edge of the cut mesh and minimizes E at the carried positions (re-solving from them changes
// nothing; before, they were the start's), and the motion goes on through more cuts with the
// energy balance held.
TEST(FracturingDynamics, MidedgeUnknownsAreResolvedOnTheCutMesh) {
  const Mesh rest = patch(8);
  Positions x = rest.positions;
  x.col(0) *= std::sqrt(1.08);  // Green strain 0.04 along x, more along the curve
  x.col(2) = 0.3 * rest.positions.col(0).array().square().matrix();
  optimize::ProblemOptions options;
  options.bending.discretization = curvature::Discretization::Midedge;
  options.boundaryNormals = optimize::BoundaryNormals::Free;  // nothing is held
  options.membrane = curvature::MembraneOptions{};
  options.dof = optimize::DofMode::Xyz;
  options.fixedRings = 0;
  options.boundaryPositions = x;
  optimize::Problem problem = optimize::buildProblem(rest, options);
  ASSERT_TRUE(problem.usesEdgeUnknowns());
  FractureOptions fracture;
  fracture.thickness = 0.01;
  const optimize::FractureCriterion criterion(rest);
  double largest = 0.0;  // the start's largest principal fibre strain; ε_f just above it
  for (const auto& face : criterion.principalStrains(criterion.strains(x), fracture.thickness))
    largest = std::max(largest, face.strain);
  fracture.fractureStrain = largest + 1e-4;
  optimize::FracturingDynamics dynamics(rest, std::move(problem), options, {}, fracture);
  Positions v = Positions::Zero(rest.vertexCount(), 3);
  v.col(0) = 2.0 * rest.positions.col(0);
  dynamics.start(x, v);
  // One step of 1e-4 s stretches past ε_f within the search band: the cut ends the advance.
  const TimeStepper::Advance first = dynamics.advance(1e-4, 1e-4 / 1024.0, 0);
  ASSERT_TRUE(first.completed);
  ASSERT_EQ(first.steps, 1);
  ASSERT_EQ(dynamics.cracks().size(), 1u);
  const TimeStepper& cut = dynamics.stepper();
  ASSERT_EQ(cut.xi().size(), Eigen::Index(dynamics.problem().stencils.edgeCount()));
  const Eigen::VectorXd again = cut.edgeUnknownsAt(cut.positions(), cut.xi());
  EXPECT_LE((again - cut.xi()).cwiseAbs().maxCoeff(), 1e-9);
  long step = 0;
  for (int k = 0; k < 10; ++k) {
    const TimeStepper::Advance advance = dynamics.advance(0.002, 0.002 / 1024.0, step);
    ASSERT_TRUE(advance.completed) << "at step " << step;
    step += advance.steps;
  }
  EXPECT_GE(dynamics.cracks().size(), 2u);
  EXPECT_TRUE(dynamics.stepper().balance().balancedWithin(0.05))
      << dynamics.stepper().balance().relativeDrift();
}

// The event faces after a first crack that stops inside: every face around its open tip, none
// with a vertex on its lips elsewhere, and every face off the lips.
TEST(FracturingDynamics, FacesOnACracksLipsAwayFromItsTipAreNoEvent) {
  const Mesh rest = patch(16);
  FractureOptions options;
  options.fractureStrain = greenStrain(1.0 + 0.1 * 0.5);
  const auto cracked = optimize::fractureShell(rest, pulledMoreBelow(rest, 0.1, 0.0),
                                               Positions::Zero(rest.vertexCount(), 3), {}, options);
  ASSERT_TRUE(cracked.has_value());
  ASSERT_EQ(cracked->openTips.size(), 1u);
  const Mesh& cut = cracked->rest;
  const std::vector<bool> event = optimize::fractureEventFaces(cut, cracked->openTips);
  ASSERT_EQ(event.size(), static_cast<std::size_t>(cut.faceCount()));
  std::map<std::array<double, 3>, int> copies;
  for (int v = 0; v < cut.vertexCount(); ++v)
    ++copies[{cut.positions(v, 0), cut.positions(v, 1), cut.positions(v, 2)}];
  int aroundTip = 0, onLips = 0;
  for (int f = 0; f < cut.faceCount(); ++f) {
    bool atTip = false, onLip = false;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = cut.positions.row(cut.triangles(f, k)).transpose();
      atTip = atTip || p == cracked->openTips.front();
      onLip = onLip || copies[{p.x(), p.y(), p.z()}] > 1;
    }
    aroundTip += atTip;
    onLips += onLip && !atTip;
    EXPECT_EQ(event[f], atTip || !onLip) << "face " << f;
  }
  EXPECT_GE(aroundTip, 3);
  EXPECT_GE(onLips, 4);
  EXPECT_EQ(optimize::fractureEventFaces(rest, {}), std::vector<bool>(rest.faceCount(), true));
}

}  // namespace
}  // namespace flexure
