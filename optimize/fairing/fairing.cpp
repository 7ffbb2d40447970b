#include "optimize/fairing/fairing.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <utility>

#include "curvature/bending_angle.h"
#include "curvature/dihedral_barrier.h"
#include "curvature/energy_registry.h"
#include "curvature/kernel_math.h"
#include "modeling/cgal_fair.h"
#include "modeling/errors.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/linear/biharmonic.h"
#include "optimize/linear/least_squares.h"
#include "optimize/problem.h"

namespace flexure::optimize {

FairingStart parseFairingStart(std::string_view name) {
  if (name == "best") return FairingStart::Best;
  if (name == "biharmonic") return FairingStart::Biharmonic;
  if (name == "input") return FairingStart::Input;
  throw InputError("FairingOptions.start " + std::string(name) +
                   ": expected best, biharmonic or input");
}

FairingMetric parseFairingMetric(std::string_view name) {
  if (name == "input") return FairingMetric::Input;
  if (name == "current") return FairingMetric::Current;
  if (name == "current-exact") return FairingMetric::CurrentExact;
  throw InputError("FairingOptions.metric " + std::string(name) +
                   ": expected input, current or current-exact");
}

FairingMethod parseFairingMethod(std::string_view name) {
  if (name == "flexure") return FairingMethod::Flexure;
  if (name == "cgal") return FairingMethod::Cgal;
  throw InputError("FairingOptions.method " + std::string(name) + ": expected flexure or cgal");
}
namespace {

constexpr double kPi = 3.14159265358979323846;

// The angle between m and n in degrees (curvature/kernel_math.h's formula, the angle barrier's).
double angleDegrees(const Eigen::Vector3d& m, const Eigen::Vector3d& n) {
  return curvature::angleBetween(curvature::Vec3<double>{m.x(), m.y(), m.z()},
                                 curvature::Vec3<double>{n.x(), n.y(), n.z()}) *
         180.0 / kPi;
}

// The faces touching a moving vertex.
std::vector<int> regionFaces(const modeling::FairingPatch& patch) {
  std::vector<int> faces;
  const modeling::Triangles& t = patch.mesh.triangles;
  for (int f = 0; f < t.rows(); ++f)
    if (patch.moves[t(f, 0)] || patch.moves[t(f, 1)] || patch.moves[t(f, 2)]) faces.push_back(f);
  return faces;
}

curvature::BendingOptions flatRest(curvature::BendingOptions b) {
  b.restCurvature = curvature::RestCurvature::Flat;
  return b;
}

// E_bend of one discretization at `x`, midedge ξ minimized for x.
double bendingEnergy(const modeling::Stencils& stencils, const modeling::RestState& rest,
                     const curvature::BendingOptions& b, const Positions& x) {
  const std::unique_ptr<curvature::EnergyTerm> term =
      curvature::makeBendingEnergy(stencils, rest, b);
  return relaxedEnergy({term.get()}, x, Eigen::VectorXd::Zero(stencils.edgeCount()),
                       std::vector<bool>(stencils.edgeCount(), true));
}

// The smallest angle and the shape measures of the region's faces at x.
TriangleQuality triangleQuality(const modeling::FairingPatch& patch, const std::vector<int>& region,
                                const Positions& x) {
  TriangleQuality q;
  q.minAngleDegrees = 180.0;
  q.minShape = 1.0;
  double shapeSum = 0.0;
  for (int f : region) {
    const auto t = patch.mesh.triangles.row(f);
    const Eigen::Vector3d p[3] = {x.row(t(0)), x.row(t(1)), x.row(t(2))};
    const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    double squares = 0.0;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d a = p[(i + 1) % 3] - p[i], b = p[(i + 2) % 3] - p[i];
      squares += a.squaredNorm();
      const double angle = angleDegrees(a, b);
      q.minAngleDegrees = std::min(q.minAngleDegrees, angle);
    }
    const double shape = squares > 0.0 ? 4.0 * std::sqrt(3.0) * area / squares : 0.0;
    q.minShape = std::min(q.minShape, shape);
    shapeSum += shape;
  }
  q.meanShape = region.empty() ? 0.0 : shapeSum / static_cast<double>(region.size());
  return q;
}

// The linear fair: each coordinate minimizes Σ_v (L x)_v² / Ā_v with the held vertices fixed.
Positions fairBiharmonic(const modeling::FairingPatch& patch, const modeling::Stencils& stencils,
                         const modeling::RestState& rest) {
  std::vector<bool> held(patch.moves.size());
  for (std::size_t v = 0; v < held.size(); ++v) held[v] = !patch.moves[v];
  Positions x = patch.mesh.positions;
  for (int k = 0; k < 3; ++k) x.col(k) = solveBiharmonic(stencils, rest, held, x.col(k));
  return x;
}

// The hinges with a moving vertex (indices into stencils.hinges).
std::vector<int> regionHinges(const modeling::FairingPatch& patch,
                              const modeling::Stencils& stencils) {
  std::vector<int> hinges;
  for (Eigen::Index h = 0; h < stencils.hinges.rows(); ++h) {
    bool moves = false;
    for (int i = 0; i < 4; ++i) moves = moves || patch.moves[stencils.hinges(h, i)];
    if (moves) hinges.push_back(static_cast<int>(h));
  }
  return hinges;
}

// Whether `x` folds a hinge with a moving vertex past the dihedral barrier's ceiling
// (kFoldCeilingDegrees) and sharper than the input does there.
bool foldsPastCeiling(const modeling::FairingPatch& patch, const modeling::Stencils& stencils,
                      const Positions& x) {
  const auto turn = [&](const Positions& y, Eigen::Index h) {
    const auto at = [&](int i) {
      const int v = stencils.hinges(h, i);
      return curvature::Vec3<double>{y(v, 0), y(v, 1), y(v, 2)};
    };
    return std::abs(curvature::bendingAngle(at(0), at(1), at(2), at(3))) * 180.0 / kPi;
  };
  for (int h : regionHinges(patch, stencils)) {
    const double folded = turn(x, h);
    if (folded > kFoldCeilingDegrees && folded > turn(patch.mesh.positions, h)) return true;
  }
  return false;
}

// The start of the nonlinear fair (options.start; Best: the linear fair unless the input has the
// lower energy or the linear fair fails the triangle checks), and which it is.
std::pair<Positions, FairingStart> fairingStart(const modeling::FairingPatch& patch,
                                                const modeling::Stencils& stencils,
                                                const modeling::RestState& rest,
                                                const curvature::BendingOptions& b,
                                                FairingStart start) {
  if (start == FairingStart::Input) return {patch.mesh.positions, start};
  const Positions linear = fairBiharmonic(patch, stencils, rest);
  if (start == FairingStart::Biharmonic) return {linear, start};
  // The membrane keeps the start's triangles, so a linear fair with inverted or degenerate
  // faces (three_peaks' all-interior: 13 faces turned over) is no start; nor, on the current
  // metric, one that folds a hinge past the dihedral barrier's ceiling (the barrier cannot undo
  // it: cylinder_locally_refined's hole, a hinge at 110°, ended with a face turned over).
  const bool foldedStart =
      b.metric == curvature::CurvatureMetric::Current && foldsPastCeiling(patch, stencils, linear);
  const bool inputLower = !checkFairing(patch, linear, nullptr).trianglesPassed() || foldedStart ||
                          bendingEnergy(stencils, rest, b, patch.mesh.positions) <
                              bendingEnergy(stencils, rest, b, linear);
  if (inputLower) return {patch.mesh.positions, FairingStart::Input};
  return {linear, FairingStart::Biharmonic};
}

// The angle barrier's floor (degrees): the smallest-angle rule's limit (kSliverToleranceDegrees
// below the smaller of the input's and the linear fair's smallest angle — the linear fair is
// CGAL's) raised by kAngleFloorMarginDegrees. Both starts are above it.
double angleFloorDegrees(const modeling::FairingPatch& patch, const std::vector<int>& region,
                         const Positions& linear) {
  return std::min(triangleQuality(patch, region, patch.mesh.positions).minAngleDegrees,
                  triangleQuality(patch, region, linear).minAngleDegrees) -
         kSliverToleranceDegrees + kAngleFloorMarginDegrees;
}

}  // namespace

curvature::MembraneOptions fairingMembrane(curvature::MembraneModel model, double weight,
                                           double bendingStiffness, double meanEdgeLength) {
  if (!(weight > 0.0) || !std::isfinite(weight))
    throw InputError("FairingOptions.membraneWeight must be positive (got " + numberText(weight) +
                     ")");
  const double l = meanEdgeLength;
  curvature::MembraneOptions m;
  m.model = model;
  m.shapeStiffness = weight * bendingStiffness;
  m.young = weight * bendingStiffness / (l * l);
  m.poisson = 0.3;
  m.lengthStiffness = weight * bendingStiffness / l;
  m.areaStiffness = weight * bendingStiffness / (l * l);
  return m;
}

Positions fairBiharmonic(const modeling::FairingPatch& patch) {
  const modeling::Stencils stencils = modeling::compileStencils(patch.mesh);
  return fairBiharmonic(patch, stencils,
                        modeling::precomputeRestState(stencils, patch.mesh.positions));
}

namespace {

// One stage of fairNonlinear: E_bend + w E_membrane (membrane rest `membraneRest`) + the barriers,
// minimized from `from` (ξ from `xiFrom`; empty: `from` is `start`, ξ their minimizer). The
// dihedral barrier is built at `start`, the first stage's start, so every stage has the same
// ceilings. ξ's minimizer at `start` does not depend on w (no membrane or barrier reads ξ): an
// earlier stage's `startXi` is passed on as `knownStartXi` (empty: computed). Every stage has the
// same unknowns and Hessian pattern, so `kept` carries CHOLMOD's analysis and the last factor from
// one stage to the next: a stage starts with chord steps on the factor its predecessor ended with.
struct FairingStage {
  MinimizeResult result;
  Eigen::VectorXd startXi;         // ξ minimized for `start` (midedge; else empty)
  double startGradientNorm = 0.0;  // |∇E| of this stage's E at (`start`, startXi)
  double finalGradientNorm = 0.0;  // and at the result
};

FairingStage solveFairingStage(const modeling::FairingPatch& patch,
                               const modeling::Stencils& stencils, const modeling::RestState& rest,
                               const FairingOptions& options, ProblemOptions p, double weight,
                               double meanEdge, const Positions& start, const Positions& from,
                               const Eigen::VectorXd& xiFrom, const Eigen::VectorXd& knownStartXi,
                               double angleFloorRadians, KeptFactorization& kept) {
  const std::vector<int> region = regionFaces(patch);
  p.membrane = fairingMembrane(options.membrane, weight, p.bending.stiffness, meanEdge);
  p.boundaryPositions = from;
  Problem problem = buildProblem(stencils, rest, p);
  if (options.angleBarrier)  // kept above the floor by the barrier
    problem.terms.push_back(curvature::makeAngleBarrier(problem.stencils, region, from,
                                                        p.bending.stiffness, angleFloorRadians,
                                                        kAngleBarrierBandDegrees * kPi / 180.0));
  // No hinge folds past the ceiling (or further than at the start): FairingOptions::foldBarrier.
  if (options.foldBarrier && options.metric != FairingMetric::Input)
    problem.terms.push_back(curvature::makeDihedralBarrier(
        problem.stencils, regionHinges(patch, problem.stencils), start, p.bending.stiffness,
        kFoldCeilingDegrees * kPi / 180.0, kFoldBarrierBandDegrees * kPi / 180.0,
        kAngleFloorMarginDegrees * kPi / 180.0));
  const std::vector<const curvature::EnergyTerm*> terms = problem.termPointers();
  const auto relaxedXi = [&](const Positions& x) {  // ξ at their minimizer for x
    return minimizeEdgeUnknowns(terms, x, problem.restXi,
                                std::vector<bool>(problem.restXi.size(), true));
  };
  FairingStage stage;
  if (problem.usesEdgeUnknowns()) {
    stage.startXi = knownStartXi.size() > 0 ? knownStartXi : relaxedXi(start);
    problem.boundary.xi = xiFrom.size() > 0 ? xiFrom : stage.startXi;
  }
  // |∇E| over the free unknowns: the moving vertices' coordinates, then every ξ (all free).
  const auto freeGradientNorm = [&](const Positions& x, const Eigen::VectorXd& xi) {
    const Eigen::VectorXd g = energyGradient(terms, x, xi).gradient;
    double squared = g.tail(g.size() - 3 * x.rows()).squaredNorm();
    for (Eigen::Index v = 0; v < x.rows(); ++v)
      if (patch.moves[static_cast<std::size_t>(v)]) squared += g.segment<3>(3 * v).squaredNorm();
    return std::sqrt(squared);
  };
  stage.startGradientNorm = freeGradientNorm(start, stage.startXi);
  MinimizeOptions solver = options.solver;
  solver.linearized = false;
  solver.start = Start::AsGiven;
  stage.result = minimize(problem, solver, &kept);
  stage.finalGradientNorm = freeGradientNorm(stage.result.positions, stage.result.xi);
  return stage;
}

// `later`'s counts and times include `earlier`'s, and its initial energy is `earlier`'s: a faded
// fairing reports its whole cost, from E at the first stage's start (with the start's membrane
// shape, the membrane costs nothing there, so that E is the same at every w).
void accumulateStageCost(MinimizeReport& later, const MinimizeReport& earlier) {
  later.iterations += earlier.iterations;
  later.factorizations += earlier.factorizations;
  later.totalSeconds += earlier.totalSeconds;
  later.evaluationSeconds += earlier.evaluationSeconds;
  later.linearSolverSeconds += earlier.linearSolverSeconds;
  later.orderingSeconds += earlier.orderingSeconds;
  later.initialEnergy = earlier.initialEnergy;
}

}  // namespace

FairingResult fairNonlinear(const modeling::FairingPatch& patch, const FairingOptions& options) {
  const modeling::Stencils stencils = modeling::compileStencils(patch.mesh);
  const modeling::RestState rest = modeling::precomputeRestState(stencils, patch.mesh.positions);
  const std::vector<int> region = regionFaces(patch);
  ProblemOptions p;
  // E_bend as minimized: flat rest, on the input's or the current metric.
  p.bending = flatRest(options.bending);
  p.bending.metric = options.metric == FairingMetric::Input ? curvature::CurvatureMetric::Rest
                                                            : curvature::CurvatureMetric::Current;
  p.bending.secureMetric = options.metric != FairingMetric::CurrentExact;
  const auto [start, startKind] = fairingStart(patch, stencils, rest, p.bending, options.start);
  double edgeLengthSum = 0.0;
  for (int f : region)
    for (int i = 0; i < 3; ++i) edgeLengthSum += rest.edgeLengths[stencils.faceEdges(f, i)];
  const double meanEdge = edgeLengthSum / (3.0 * static_cast<double>(region.size()));
  if (options.membraneShape == FairingShape::Start) p.membraneRest = start;
  p.dof = DofMode::Xyz;
  p.fixedVertex.resize(patch.moves.size());
  for (std::size_t v = 0; v < patch.moves.size(); ++v) p.fixedVertex[v] = !patch.moves[v];
  p.boundaryNormals = BoundaryNormals::Free;
  const Positions linear = options.angleBarrier && startKind != FairingStart::Biharmonic
                               ? fairBiharmonic(patch, stencils, rest)
                               : start;
  const double angleFloor = angleFloorDegrees(patch, region, linear) * kPi / 180.0;
  KeptFactorization kept;
  FairingStage stage =
      solveFairingStage(patch, stencils, rest, options, p, options.membraneWeight, meanEdge, start,
                        start, Eigen::VectorXd(), Eigen::VectorXd(), angleFloor, kept);
  // The fade (FairingOptions::membraneFadeStages): w_k = w / 10^k, each stage started at the last
  // converged result; a stage that does not converge or fails checkFairing's checks is dropped and
  // the fade stops there, so the result is the last stage that converged — unless the solver's
  // observer stopped the stage: a stopped fairing is reported as stopped, not converged.
  double weight = options.membraneWeight, keptWeight = weight;
  int keptStages = 0;
  for (int k = 0; k < options.membraneFadeStages && stage.result.report.converged; ++k) {
    weight *= kMembraneFadeFactor;
    try {
      FairingStage next = solveFairingStage(patch, stencils, rest, options, p, weight, meanEdge,
                                            start, stage.result.positions, stage.result.xi,
                                            stage.startXi, angleFloor, kept);
      if (next.result.report.stop == NewtonStop::Stopped) {
        stage.result.report.converged = false;
        stage.result.report.stop = NewtonStop::Stopped;
        stage.result.report.termination = next.result.report.termination;
        break;
      }
      FairingResult candidate{next.result.positions, next.result.report, startKind};
      candidate.startGradientNorm = next.startGradientNorm;
      candidate.finalGradientNorm = next.finalGradientNorm;
      const FairingChecks checks = checkFairing(patch, next.result.positions, &candidate);
      if (!next.result.report.converged || !checks.passed()) break;
      accumulateStageCost(next.result.report, stage.result.report);
      stage = std::move(next);
      keptWeight = weight;
      ++keptStages;
    } catch (const NumericalError&) {
      break;
    }
  }
  FairingResult fairing{std::move(stage.result.positions), stage.result.report, startKind};
  fairing.startGradientNorm = stage.startGradientNorm;
  fairing.finalGradientNorm = stage.finalGradientNorm;
  fairing.membraneWeight = keptWeight;
  fairing.membraneFadeStages = keptStages;
  return fairing;
}

bool FairingChecks::gradientPassed() const {
  return !gradientChecked || finalGradientNorm <= kFairingGradientReduction * startGradientNorm ||
         finalGradientNorm <= kFairingGradientFloor;
}

std::string FairingChecks::failure() const {
  std::ostringstream s;
  s.precision(3);
  const char* separator = "";
  if (!gradientPassed()) {
    s << "gradient check: |grad E| = " << finalGradientNorm << " at the result against "
      << startGradientNorm << " at the start (a converged fairing has at most "
      << kFairingGradientReduction << " times the start's)";
    separator = "; ";
  }
  const auto face = [](const int(&v)[3]) {
    return "(" + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) +
           ")";
  };
  if (!degenerateFaces.empty()) {
    const DegenerateFace& f = degenerateFaces.front();
    s << separator << "triangle check: " << degenerateFaces.size()
      << (degenerateFaces.size() == 1 ? " face is" : " faces are") << " degenerate (2 area at most "
      << kDegenerateFlatness << " times the longest edge squared), "
      << "face " << face(f.vertices) << " at " << f.flatness;
    separator = "; ";
  }
  if (!invertedFaces.empty()) {
    const InvertedFace& f = invertedFaces.front();
    s << separator << "triangle check: " << invertedFaces.size()
      << (invertedFaces.size() == 1 ? " face is" : " faces are")
      << " inverted (normal turned 90 degrees or more from the input's and from a neighbour's), "
      << "face " << face(f.vertices) << " by " << f.inputTurnDegrees << " degrees ("
      << f.neighbourTurnDegrees << " against a neighbour)";
  }
  return s.str();
}

FairingChecks checkFairing(const modeling::FairingPatch& patch, const Positions& positions,
                           const FairingResult* solve) {
  const modeling::Triangles& faces = patch.mesh.triangles;
  const std::vector<int> region = regionFaces(patch);
  FairingChecks checks;
  if (solve) {
    checks.gradientChecked = true;
    checks.startGradientNorm = solve->startGradientNorm;
    checks.finalGradientNorm = solve->finalGradientNorm;
  }
  // (x1 − x0) × (x2 − x0) of the triangle (i, j, k) at positions x.
  const auto areaNormal = [](const Positions& x, int i, int j, int k) {
    const Eigen::Vector3d x0 = x.row(i), x1 = x.row(j), x2 = x.row(k);
    return Eigen::Vector3d((x1 - x0).cross(x2 - x0));
  };
  const Positions& input = patch.mesh.positions;
  // The faces at each face's edges: for face f, edge i (from corner i to i + 1) the face across.
  std::vector<std::array<int, 3>> across(static_cast<int>(faces.rows()), {-1, -1, -1});
  {
    std::map<std::pair<int, int>, std::pair<int, int>> halfedge;  // (from, to) → (face, edge)
    for (int f = 0; f < static_cast<int>(faces.rows()); ++f)
      for (int i = 0; i < 3; ++i) halfedge[{faces(f, i), faces(f, (i + 1) % 3)}] = {f, i};
    for (const auto& [edge, at] : halfedge) {
      const auto twin = halfedge.find({edge.second, edge.first});
      if (twin != halfedge.end()) across[at.first][at.second] = twin->second.first;
    }
  }
  for (int f : region) {
    const auto t = faces.row(f);
    const int named[3] = {patch.inputVertex[t(0)], patch.inputVertex[t(1)],
                          patch.inputVertex[t(2)]};
    const Eigen::Vector3d before = areaNormal(input, t(0), t(1), t(2));
    const Eigen::Vector3d after = areaNormal(positions, t(0), t(1), t(2));
    double longest = 0.0;
    for (int i = 0; i < 3; ++i)
      longest =
          std::max(longest, (positions.row(t((i + 1) % 3)) - positions.row(t(i))).squaredNorm());
    const double flatness = longest > 0.0 ? after.norm() / longest : 0.0;
    if (!(flatness > kDegenerateFlatness)) {
      checks.degenerateFaces.push_back({{named[0], named[1], named[2]}, flatness});
      continue;  // its normal is meaningless
    }
    if (before.dot(after) > 0.0) continue;
    double neighbourTurn = 0.0;
    for (int i = 0; i < 3; ++i) {
      const int g = across[f][i];
      if (g < 0) continue;
      const auto u = faces.row(g);
      neighbourTurn =
          std::max(neighbourTurn, angleDegrees(after, areaNormal(positions, u(0), u(1), u(2))));
    }
    if (neighbourTurn >= 90.0) {
      checks.invertedFaces.push_back(
          {{named[0], named[1], named[2]}, angleDegrees(before, after), neighbourTurn});
    }
  }
  checks.inputMinAngleDegrees =
      triangleQuality(patch, region, patch.mesh.positions).minAngleDegrees;
  checks.resultMinAngleDegrees = triangleQuality(patch, region, positions).minAngleDegrees;
  return checks;
}

Positions fairCgal(const modeling::FairingPatch& patch) {
  return modeling::cgalFair(patch.mesh, patch.moves, 1);
}

FairingMeasures measureFairing(const modeling::FairingPatch& patch, const Positions& positions,
                               const curvature::BendingOptions& material) {
  const modeling::Stencils stencils = modeling::compileStencils(patch.mesh);
  const modeling::RestState rest = modeling::precomputeRestState(stencils, patch.mesh.positions);
  FairingMeasures m;
  // Every registered energy, with the ν its rule takes (a mean-curvature model takes none).
  const int energies = static_cast<int>(curvature::registeredEnergies().size());
  for (int index = 0; index < energies; ++index) {
    const curvature::Discretization d(index);
    curvature::BendingOptions b = flatRest(material);
    b.discretization = d;
    b.vertexArea = material.vertexArea;
    b.hingeAngle = material.hingeAngle;
    if (curvature::energyEntry(d).poissonRule == curvature::PoissonRule::MeanCurvatureOnly)
      b.poisson.reset();
    for (auto metric : {curvature::CurvatureMetric::Rest, curvature::CurvatureMetric::Current}) {
      b.metric = metric;
      EnergyMeasure e{std::string(curvature::discretizationName(d)), 0.0, ""};
      try {
        e.value = bendingEnergy(stencils, rest, b, positions);
      } catch (const std::exception& error) {
        e.value = std::numeric_limits<double>::quiet_NaN();
        e.error = error.what();
      }
      (metric == curvature::CurvatureMetric::Rest ? m.bending : m.bendingCurrent).push_back(e);
    }
  }
  m.quality = triangleQuality(patch, regionFaces(patch), positions);
  m.maxDisplacement = (positions - patch.mesh.positions).rowwise().norm().maxCoeff();
  return m;
}

double SliverCheck::limitDegrees() const {
  return std::min(inputDegrees, cgalDegrees) - kSliverToleranceDegrees;
}

std::string SliverCheck::failure() const {
  char text[320];
  std::snprintf(text, sizeof text,
                "smallest-angle check: the faired region's smallest angle %.3g deg is more than "
                "%g deg below min(input %.3g deg, CGAL's fair %.3g deg) (limit %.3g deg)",
                resultDegrees, kSliverToleranceDegrees, inputDegrees, cgalDegrees, limitDegrees());
  return text;
}

bool FairingOutcome::converged(bool allowSlivers) const {
  return solverConverged && checks.passed() && (sliversPassed || allowSlivers);
}

std::string FairingOutcome::failure(bool allowSlivers) const {
  std::string text = checks.failure();
  if (!sliversPassed && !allowSlivers) text += (text.empty() ? "" : "; ") + slivers.failure();
  return text;
}

FairingOutcome fairAndCheck(const modeling::FairingPatch& patch, const FairingOptions& options,
                            FairingMethod method, const curvature::BendingOptions& material) {
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
  };
  const bool cgal = method == FairingMethod::Cgal;
  FairingOutcome r;
  r.before = measureFairing(patch, patch.mesh.positions, material);
  const auto solveStart = Clock::now();
  if (!cgal) {
    r.fairing = fairNonlinear(patch, options);
    r.patchAfter = r.fairing->positions;
  }
  const double flexureSeconds = since(solveStart);
  const auto cgalStart = Clock::now();
  r.cgalPatch = fairCgal(patch);
  r.cgalSeconds = since(cgalStart);
  r.solveSeconds = cgal ? r.cgalSeconds : flexureSeconds;
  if (cgal) r.patchAfter = r.cgalPatch;
  r.cgalMeasures = measureFairing(patch, r.cgalPatch, material);
  r.after = cgal ? r.cgalMeasures : measureFairing(patch, r.patchAfter, material);
  r.checks = checkFairing(patch, r.patchAfter, r.fairing ? &*r.fairing : nullptr);
  r.slivers = {r.checks.inputMinAngleDegrees, r.cgalMeasures.quality.minAngleDegrees,
               r.checks.resultMinAngleDegrees};
  r.sliversPassed = cgal || r.slivers.passed();
  r.solverConverged = !r.fairing || r.fairing->report.converged;
  return r;
}

}  // namespace flexure::optimize
