#include "optimize/assembly/self_contact.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "modeling/errors.h"
#include "modeling/self_intersections.h"
#include "optimize/assembly/obstacles.h"
#include "optimize/contact/broad_phase.h"
#include "optimize/contact/continuous_collision.h"
#include "optimize/contact/primitive_distance.h"

namespace flexure::optimize {
namespace {

using Vector12 = Eigen::Matrix<double, 12, 1>;
using Matrix12 = Eigen::Matrix<double, 12, 12>;

Eigen::Vector3d row(const Positions& x, int v) {
  return x.row(v).transpose();
}

// The nearest positive semidefinite matrix V max(Λ, 0) Vᵀ (Higham 1988).
Matrix12 projected(const Matrix12& h) {
  const Eigen::SelfAdjointEigenSolver<Matrix12> eigen(h);
  if (eigen.eigenvalues().minCoeff() >= 0.0) return h;
  const Eigen::Matrix<double, 12, 1> clamped = eigen.eigenvalues().cwiseMax(0.0);
  return eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
}

// The midrange of each coordinate over the rows of u (#V by 3).
Eigen::RowVector3d midrange(const Positions& u) {
  return 0.5 * (u.colwise().maxCoeff() + u.colwise().minCoeff());
}

// The median of each coordinate over the rows of u (#V ≥ 1 by 3): a centre that a few far
// rows do not pull (SelfContact::fastVertices).
Eigen::RowVector3d median(const Positions& u) {
  Eigen::RowVector3d centre;
  std::vector<double> column(u.rows());
  for (int k = 0; k < 3; ++k) {
    for (Eigen::Index v = 0; v < u.rows(); ++v) column[v] = u(v, k);
    std::nth_element(column.begin(), column.begin() + column.size() / 2, column.end());
    centre[k] = column[column.size() / 2];
  }
  return centre;
}

// M of SelfContact::nearbyPairs: max_v |dx_v − c|, c the coordinates' midranges (also ρ, of the
// move from where the candidates were kept).
double relativeMotion(const Positions& dx) {
  if (dx.rows() == 0) return 0.0;
  const Eigen::RowVector3d centre = midrange(dx);
  return (dx.rowwise() - centre).rowwise().norm().maxCoeff();
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The pairs the broad phase proposes at x over the motion dx (empty: static) within `inflation`.
std::vector<ContactPair> candidates(const Positions& x, const Positions& dx,
                                    const modeling::Triangles& faces,
                                    const modeling::IndexPairs& edges, double inflation,
                                    const std::vector<bool>* among) {
  const CandidatePairs found = among == nullptr
                                   ? contactCandidates(x, dx, faces, edges, inflation)
                                   : contactCandidatesAmong(x, dx, faces, edges, inflation, *among);
  std::vector<ContactPair> pairs;
  pairs.reserve(found.vertexFace.size() + found.edgeEdge.size());
  for (const std::array<int, 2>& p : found.vertexFace)
    pairs.push_back({ContactPair::Kind::VertexFace, p[0], p[1]});
  for (const std::array<int, 2>& p : found.edgeEdge)
    pairs.push_back({ContactPair::Kind::EdgeEdge, p[0], p[1]});
  return pairs;
}

// Whether the pattern couples every two free vertices of `v` (`index`: each vertex coordinate's
// free index, −1 when fixed; a vertex is pinned whole).

}  // namespace

SelfContact::SelfContact(modeling::Triangles faces, modeling::IndexPairs edges, Positions rest,
                         double layer, double stiffness)
    : faces_(std::move(faces)),
      edges_(std::move(edges)),
      rest_(std::move(rest)),
      layer_(layer),
      stiffness_(stiffness),
      vertexStiffness_(Eigen::VectorXd::Constant(rest_.rows(), stiffness)),
      shellVertices_(static_cast<int>(rest_.rows())),
      shellFaces_(static_cast<int>(faces_.rows())),
      shellEdges_(static_cast<int>(edges_.rows())),
      vertexStart_{shellVertices_},
      faceStart_{shellFaces_},
      edgeStart_{shellEdges_} {
  if (!(layer_ > 0.0) || !std::isfinite(layer_))
    throw InputError("SelfContact: the contact layer d̂ must be > 0, got " + numberText(layer_));
  if (!(stiffness_ > 0.0) || !std::isfinite(stiffness_))
    throw InputError("SelfContact: the stiffness κ must be > 0, got " + numberText(stiffness_));
}

void SelfContact::addObstacles(std::vector<MeshObstacle> obstacles, bool shellPairs) {
  validateMeshObstacles(obstacles);
  shellPairs_ = shellPairs;
  obstacleStiffness_ = stiffness_;
  for (MeshObstacle& obstacle : obstacles) {
    const int v0 = vertexStart_.back(), f0 = faceStart_.back(), e0 = edgeStart_.back();
    const modeling::IndexPairs edges = triangleEdges(obstacle.mesh.triangles);
    const int w = obstacle.mesh.vertexCount(), f = obstacle.mesh.faceCount();
    const int e = static_cast<int>(edges.rows());
    rest_.conservativeResize(v0 + w, 3);
    rest_.bottomRows(w) = obstacle.mesh.positions;
    faces_.conservativeResize(f0 + f, 3);
    faces_.bottomRows(f) = obstacle.mesh.triangles.array() + v0;
    edges_.conservativeResize(e0 + e, 2);
    edges_.bottomRows(e) = edges.array() + v0;
    vertexStart_.push_back(v0 + w);
    faceStart_.push_back(f0 + f);
    edgeStart_.push_back(e0 + e);
    obstacles_.push_back(std::move(obstacle));
  }
  obstaclePositions_ = rest_.bottomRows(rest_.rows() - shellVertices_);
  keptAt_.resize(0, 3);
  activeAt_.resize(0, 3);
  movingAt_.resize(0, 3);
}

void SelfContact::setObstacleTime(double t) {
  obstacleTime_ = t;
  for (std::size_t k = 0; k < obstacles_.size(); ++k)
    if (obstacles_[k].moves())
      obstaclePositions_.middleRows(vertexStart_[k] - shellVertices_,
                                    obstacles_[k].mesh.vertexCount()) =
          obstacles_[k].positionsAt(t);
}

void SelfContact::setObstacleStiffness(double stiffness) {
  if (!(stiffness >= stiffness_) || !std::isfinite(stiffness))
    throw InputError("SelfContact: the mesh obstacles' stiffness must be at least κ = " +
                     numberText(stiffness_) + ", got " + numberText(stiffness));
  obstacleStiffness_ = stiffness;
}

void SelfContact::resetStiffness() {
  vertexStiffness_.setConstant(stiffness_);
}

void SelfContact::setVertexStiffness(const Eigen::VectorXd& stiffness) {
  if (stiffness.size() != shellVertices_ || !stiffness.allFinite() ||
      !(stiffness.size() == 0 || stiffness.minCoeff() >= stiffness_))
    throw InputError("SelfContact: expected " + std::to_string(shellVertices_) +
                     " finite vertex stiffnesses of at least κ = " + numberText(stiffness_) +
                     ", got " + std::to_string(stiffness.size()));
  vertexStiffness_ = stiffness;
}

double SelfContact::reducedMass(const ContactPair& pair, const std::array<int, 4>& v,
                                const Eigen::VectorXd& mass) const {
  const int split = pair.kind == ContactPair::Kind::VertexFace ? 1 : 2;
  double side[2] = {0.0, 0.0};
  for (int i = 0; i < 4; ++i) {
    const int s = i < split ? 0 : 1;
    const int count = s == 0 ? split : 4 - split;
    side[s] += v[i] < shellVertices_ ? mass[v[i]] / count : std::numeric_limits<double>::infinity();
  }
  if (!std::isfinite(side[0])) return side[1];
  if (!std::isfinite(side[1])) return side[0];
  return side[0] * side[1] / (side[0] + side[1]);
}

std::vector<VertexApproach> SelfContact::approaches(const std::vector<ContactPair>& pairs,
                                                    const Positions& x, const Positions& velocity,
                                                    const Eigen::VectorXd& mass,
                                                    double step) const {
  std::vector<VertexApproach> approach(static_cast<std::size_t>(shellVertices_));
  for (const ContactPair& pair : pairs) {
    const std::array<int, 4> v = vertices(pair);
    Vector12 sGradient;
    const double s = pair.kind == ContactPair::Kind::VertexFace
                         ? pointTriangleDistanceSquared(row(x, v[0]), row(x, v[1]), row(x, v[2]),
                                                        row(x, v[3]), &sGradient)
                         : edgeEdgeDistanceSquared(row(x, v[0]), row(x, v[1]), row(x, v[2]),
                                                   row(x, v[3]), &sGradient);
    const double d = std::sqrt(s);
    if (!(d > 0.0)) continue;
    // w = −ḋ = −∇s · ẋ / (2d) (0 when receding), with the pair's reduced mass μ = m₁m₂/(m₁ + m₂)
    // of its two primitives' mean vertex masses (an obstacle's is ∞: μ = m₁); an inset pair's
    // distance counts in units of its own layer.
    double w = 0.0;
    for (int i = 0; i < 4; ++i) w -= sGradient.segment<3>(3 * i).dot(velocity.row(v[i])) / (2 * d);
    const double impact = reducedMass(pair, v, mass) * std::max(0.0, w) * w;
    const double layer = pairLayer(pair), scaled = d * layer_ / layer;
    const double unitBarrier =
        d < layer ? layer_ / layer * mollifier(pair, x) * barrierPotential(d, layer) : 0.0;
    for (int i = 0; i < 4; ++i) {
      if (v[i] >= shellVertices_) continue;
      VertexApproach& a = approach[static_cast<std::size_t>(v[i])];
      a.closest = std::min(a.closest, scaled);
      a.impact = std::max(a.impact, impact);
      if (scaled < 2.0 * layer_ && w * step >= 0.5 * d)
        a.nearImpact = std::max(a.nearImpact, impact);
      a.unitBarrier += unitBarrier;
    }
  }
  return approach;
}

double SelfContact::adapt(const Positions& shell, const Positions& velocity,
                          const Eigen::VectorXd& mass, double step, double budget) {
  if (empty()) return 0.0;
  const auto start = std::chrono::steady_clock::now();
  const Positions x = stacked(shell);
  Positions obstacleVelocity(obstaclePositions_.rows(), 3);
  for (std::size_t k = 0; k < obstacles_.size(); ++k)
    obstacleVelocity.middleRows(vertexStart_[k] - shellVertices_,
                                obstacles_[k].mesh.vertexCount()) =
        obstacles_[k].velocitiesAt(obstacleTime_);
  const Positions speed = stackedMotion(velocity, obstacleVelocity);
  const Positions sweep = step > 0.0 ? Positions(step * speed) : Positions();
  const std::vector<VertexApproach> approach =
      approaches(approachingPairs(x, sweep), x, speed, mass, step);
  detectionSeconds_ += secondsSince(start);
  double added = 0.0;
  for (int v = 0; v < shellVertices_; ++v)
    vertexStiffness_[v] =
        adaptedStiffness(vertexStiffness_[v], stiffness_, approach[static_cast<std::size_t>(v)],
                         layer_, budget, added);
  return added;
}

bool SelfContact::obstaclesMove() const {
  return std::any_of(obstacles_.begin(), obstacles_.end(),
                     [](const MeshObstacle& o) { return o.moves(); });
}

Positions SelfContact::stacked(const Positions& x) const {
  if (obstacles_.empty()) return x;
  Positions all(x.rows() + obstaclePositions_.rows(), 3);
  all << x, obstaclePositions_;
  return all;
}

Positions SelfContact::stackedMotion(const Positions& dx, const Positions& obstacleMotion) const {
  if (obstacles_.empty() || dx.size() == 0) return dx;
  Positions all(dx.rows() + obstaclePositions_.rows(), 3);
  if (obstacleMotion.size() == 0)
    all << dx, Positions::Zero(obstaclePositions_.rows(), 3);
  else
    all << dx, obstacleMotion;
  return all;
}

std::array<bool, 2> SelfContact::onShell(const ContactPair& pair) const {
  if (pair.kind == ContactPair::Kind::VertexFace)
    return {pair.first < shellVertices_, pair.second < shellFaces_};
  return {pair.first < shellEdges_, pair.second < shellEdges_};
}

bool SelfContact::counts(const ContactPair& pair) const {
  const std::array<bool, 2> shell = onShell(pair);
  return shell[0] && shell[1] ? shellPairs_ : shell[0] || shell[1];
}

std::vector<ContactPair> SelfContact::countedCandidates(const Positions& x, const Positions& dx,
                                                        double inflation,
                                                        const std::vector<bool>* among) const {
  std::vector<ContactPair> pairs = candidates(x, dx, faces_, edges_, inflation, among);
  if (obstacles_.empty()) return pairs;
  pairs.erase(
      std::remove_if(pairs.begin(), pairs.end(), [&](const ContactPair& p) { return !counts(p); }),
      pairs.end());
  return pairs;
}

int SelfContact::ownerOf(const std::vector<int>& starts, int index) const {
  return static_cast<int>(std::upper_bound(starts.begin(), starts.end(), index) - starts.begin()) -
         1;
}

std::string SelfContact::vertexText(int v) const {
  const int k = ownerOf(vertexStart_, v);
  if (k < 0) return "shell vertex " + std::to_string(v);
  return "vertex " + std::to_string(v - vertexStart_[k]) + " of " + meshObstacleName(obstacles_, k);
}

std::vector<int> SelfContact::shellVerticesOf(const ContactPair& pair) const {
  std::vector<int> shell;
  for (int v : vertices(pair))
    if (v < shellVertices_) shell.push_back(v);
  return shell;
}

std::string SelfContact::describe(const ContactPair& pair) const {
  const std::array<int, 4> v = vertices(pair);
  if (pair.kind == ContactPair::Kind::VertexFace) {
    const int k = ownerOf(faceStart_, pair.second);
    const std::string face = k < 0 ? "shell face " + std::to_string(pair.second)
                                   : "face " + std::to_string(pair.second - faceStart_[k]) +
                                         " of " + meshObstacleName(obstacles_, k);
    return vertexText(v[0]) + " and " + face;
  }
  const auto edge = [&](int a, int b) {
    const int k = ownerOf(vertexStart_, a);
    const int offset = k < 0 ? 0 : vertexStart_[k];
    return (k < 0 ? std::string("shell edge (") : std::string("edge (")) +
           std::to_string(a - offset) + ", " + std::to_string(b - offset) + ")" +
           (k < 0 ? std::string() : " of " + meshObstacleName(obstacles_, k));
  };
  return edge(v[0], v[1]) + " and " + edge(v[2], v[3]);
}

std::uint64_t SelfContact::key(const ContactPair& pair) {
  return (std::uint64_t(pair.kind == ContactPair::Kind::EdgeEdge) << 62) |
         (std::uint64_t(pair.first) << 31) | std::uint64_t(pair.second);
}

ContactPair SelfContact::pairOf(std::uint64_t key) {
  const std::uint64_t mask = (std::uint64_t(1) << 31) - 1;
  return {(key >> 62) ? ContactPair::Kind::EdgeEdge : ContactPair::Kind::VertexFace,
          static_cast<int>((key >> 31) & mask), static_cast<int>(key & mask)};
}

std::array<int, 4> SelfContact::vertices(const ContactPair& pair) const {
  if (pair.kind == ContactPair::Kind::VertexFace)
    return {pair.first, faces_(pair.second, 0), faces_(pair.second, 1), faces_(pair.second, 2)};
  return {edges_(pair.first, 0), edges_(pair.first, 1), edges_(pair.second, 0),
          edges_(pair.second, 1)};
}

double SelfContact::boxGap(const ContactPair& pair, const Positions& x, const Positions* dx) const {
  const std::array<int, 4> v = vertices(pair);
  const int split = pair.kind == ContactPair::Kind::VertexFace ? 1 : 2;
  Eigen::Array3d low[2], high[2];  // the first primitive's box, the second's
  for (int i = 0; i < 4; ++i) {
    const int side = i < split ? 0 : 1;
    Eigen::Array3d p = x.row(v[i]).transpose(), q = p;
    if (dx != nullptr) q += dx->row(v[i]).transpose().array();
    const Eigen::Array3d lowest = p.min(q), highest = p.max(q);
    const bool first = i == 0 || i == split;
    low[side] = first ? lowest : Eigen::Array3d(low[side].min(lowest));
    high[side] = first ? highest : Eigen::Array3d(high[side].max(highest));
  }
  return (low[0] - high[1]).max(low[1] - high[0]).maxCoeff();
}

double SelfContact::squaredDistance(const ContactPair& pair, const Positions& x) const {
  const std::array<int, 4> v = vertices(pair);
  if (pair.kind == ContactPair::Kind::VertexFace)
    return pointTriangleDistanceSquared(row(x, v[0]), row(x, v[1]), row(x, v[2]), row(x, v[3]));
  return edgeEdgeDistanceSquared(row(x, v[0]), row(x, v[1]), row(x, v[2]), row(x, v[3]));
}

double SelfContact::pairLayer(const ContactPair& pair) const {
  if (exempt_.empty()) return layer_;
  const auto k = exempt_.find(key(pair));
  return k == exempt_.end() ? layer_ : k->second;
}

bool SelfContact::ignored(const ContactPair& pair) const {
  if (exempt_.empty()) return false;
  const auto k = exempt_.find(key(pair));
  return k != exempt_.end() && k->second == 0.0;
}

std::vector<InsetPair> SelfContact::insets() const {
  std::vector<std::pair<std::uint64_t, double>> sorted(exempt_.begin(), exempt_.end());
  std::sort(sorted.begin(), sorted.end());
  std::vector<InsetPair> out;
  for (const auto& [id, layer] : sorted) out.push_back({pairOf(id), layer});
  return out;
}

namespace {

// A pair named by its vertices, independently of the edge and face numbering: (kind, the vertex
// or the first edge's ends, then the face's corners or the second edge's ends), each primitive's
// vertices sorted and, for two edges, the edges in order.
using PairSignature = std::array<int, 5>;

PairSignature signature(ContactPair::Kind kind, std::array<int, 4> v) {
  if (kind == ContactPair::Kind::VertexFace) {
    std::sort(v.begin() + 1, v.end());
    return {0, v[0], v[1], v[2], v[3]};
  }
  std::array<int, 2> a = {std::min(v[0], v[1]), std::max(v[0], v[1])};
  std::array<int, 2> b = {std::min(v[2], v[3]), std::max(v[2], v[3])};
  if (b < a) std::swap(a, b);
  return {1, a[0], a[1], b[0], b[1]};
}

}  // namespace

std::vector<InsetPair> SelfContact::carriedInsets(const SelfContact& before,
                                                  const std::vector<int>& ancestor) const {
  if (ancestor.size() != static_cast<std::size_t>(shellVertices_))
    throw InputError("SelfContact: " + std::to_string(ancestor.size()) +
                     " vertex ancestors for a mesh of " + std::to_string(shellVertices_) +
                     " vertices");
  std::map<PairSignature, double> earlier;
  for (const auto& [id, layer] : before.exempt_) {
    const ContactPair pair = pairOf(id);
    earlier.emplace(signature(pair.kind, before.vertices(pair)), layer);
  }
  std::vector<InsetPair> out;
  for (const InsetPair& inset : insets()) {
    std::array<int, 4> v = vertices(inset.pair);
    bool whole = true;
    for (int& u : v) {
      u = ancestor[static_cast<std::size_t>(u)];
      whole = whole && u >= 0;
    }
    std::array<int, 4> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    if (!whole || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
      out.push_back(inset);  // a fresh lip's pair: as exemptClosePairs left it
      continue;
    }
    const auto found = earlier.find(signature(inset.pair.kind, v));
    if (found != earlier.end()) out.push_back({inset.pair, found->second});
  }
  return out;
}

void SelfContact::setInsets(const std::vector<InsetPair>& insets) {
  exempt_.clear();
  keptAt_.resize(0, 3);  // the kept candidates left other pairs out, the active pairs other layers
  activeAt_.resize(0, 3);
  movingAt_.resize(0, 3);
  for (const InsetPair& inset : insets) {
    const ContactPair& p = inset.pair;
    const bool vertexFace = p.kind == ContactPair::Kind::VertexFace;
    const bool fits = p.first >= 0 && p.second >= 0 &&
                      (vertexFace ? p.first < shellVertices_ && p.second < shellFaces_
                                  : p.first < shellEdges_ && p.second < shellEdges_) &&
                      inset.layer >= 0.0 && inset.layer < layer_;
    if (!fits)
      throw InputError("SelfContact: an inset pair (" + std::to_string(p.first) + ", " +
                       std::to_string(p.second) + ") with layer " + numberText(inset.layer) +
                       " that is not two primitives of the shell within the layer");
    exempt_.emplace(key(p), inset.layer);
  }
}

void SelfContact::exemptClosePairs(const Positions& x) {
  if (empty()) return;
  exempt_.clear();
  keptAt_.resize(0, 3);  // the kept candidates did not leave the new exemptions out
  activeAt_.resize(0, 3);
  movingAt_.resize(0, 3);
  const Positions at = stacked(x);
  for (const ContactPair& pair : countedCandidates(rest_, Positions(), 0.5 * layer_)) {
    const double squared = layer_ * layer_;
    const std::array<bool, 2> shell = onShell(pair);  // a shell–obstacle pair is never exempt
    if (shell[0] && shell[1] && squaredDistance(pair, rest_) < squared &&
        squaredDistance(pair, at) < squared)
      exempt_.emplace(key(pair), 0.0);
  }
}

// An exempt pair's inset layer starts once it is this many d̂ apart, in place or at rest: lips
// closer in both are still together (closer, CCD would hold their every motion to tiny steps). A
// pair apart at rest (a cut's lips opened, fracture.h's openLips, or a lip of an earlier cut that a
// new crack splits) is inset at any distance above 0 at which it is found.
constexpr double kSmallestInset = 1e-3;

void SelfContact::liftExemptions(const Positions& shell) {
  const Positions x = stacked(shell);
  bool changed = false;  // a pair lifted, or an inset layer raised
  for (auto k = exempt_.begin(); k != exempt_.end();) {
    const double d = std::sqrt(squaredDistance(pairOf(k->first), x));
    if (d >= layer_) {
      k = exempt_.erase(k);
      changed = true;
      continue;
    }
    const double together = kSmallestInset * layer_;
    const bool apart = d >= together ||
                       (d > 0.0 && squaredDistance(pairOf(k->first), rest_) >= together * together);
    if (apart && 0.5 * d > k->second) {
      k->second = 0.5 * d;
      changed = true;
    }
    ++k;
  }
  if (!changed) return;
  keptAt_.resize(0, 3);  // the kept candidates left the lifted pairs out
  activeAt_.resize(0, 3);
  movingAt_.resize(0, 3);
}

// A motion whose margin r (nearbyPairs) would exceed this many d̂ gets a broad phase of its own
// swept boxes: the kept pairs' count grows as (d̂ + 2r)², and the Newton loop's later, shorter
// steps are served by kept candidates of the smallest margin.
constexpr double kLongestKeptMotion = 0.5;
// ACCD's rate bound l ≤ 3 M (nearbyPairs' rule).
constexpr double kRateBound = 3.0;
// The kept distances' allowance for rounding, relative to d̂ plus the largest coordinate: far
// above the distance functions' rounding errors, far below any distance that matters.
constexpr double kDistanceRoundoff = 1e-9;
// ACCD's gap fraction s (contact/continuous_collision.h): no pair comes closer than s × its start
// distance during a step.
constexpr double kImpactGap = 0.1;
// A pair whose distance rate bound l is below this fraction of (1 − s) × a lower bound on its
// start distance has impact time 1 (its first step reaches t = 1 with room for rounding).
constexpr double kFirstStepMargin = 0.99;
// A wild motion: more than this share of the vertices fast (SelfContact::fastVertices). Measured
// on the 10 000-vertex hinge drape with self-contact (50 steps, one run each; detection seconds,
// run seconds): 1/2 8.2, 28.2; 1/8 3.8, 21.2 (without the cut 18.2, 40.6; self-contact off 13.8).
constexpr double kWildShare = 0.125;
// Its cut, below the largest at which no vertex is fast (room for rounding).
constexpr double kWildCut = 0.999;

double SelfContact::neededMargin(double motion) const {
  return 0.5 * (kRateBound * motion / (kFirstStepMargin * (1.0 - kImpactGap)) - layer_);
}

double SelfContact::rateAllowance(double rho) const {
  return kFirstStepMargin * (1.0 - kImpactGap) * (layer_ + 2.0 * (keptMargin_ - rho));
}

bool SelfContact::keptServe(const Positions& x, const Positions& dx) const {
  if (keptAt_.rows() != x.rows()) return false;
  const double rho = relativeMotion(x - keptAt_);
  if (!(rho <= keptMargin_)) return false;
  return dx.size() == 0 || kRateBound * relativeMotion(dx) <= rateAllowance(rho);
}

const std::vector<ContactPair>& SelfContact::nearbyPairs(const Positions& x,
                                                         const Positions& dx) const {
  if (keptServe(x, dx)) return kept_;
  const double motion = dx.size() == 0 ? 0.0 : relativeMotion(dx);
  const double needed = neededMargin(motion);
  if (needed <= kLongestKeptMotion * layer_) {
    keep(x, std::max({0.5 * layer_, motion, needed}));
    return kept_;
  }
  // A long motion: the kept pairs, kept anew at x unless they serve it, and the pairs whose swept
  // boxes overlap among those with a vertex fast enough to reach any other pair.
  if (movingAt_.rows() == x.rows() && movingAt_ == x && movingBy_.rows() == dx.rows() &&
      movingBy_ == dx)
    return moving_;
  const std::vector<bool> fast = fastVertices(x, dx);
  movingAt_ = x, movingBy_ = dx;
  moving_ = kept_;
  for (const ContactPair& pair : countedCandidates(x, dx, 0.0, &fast))
    if (!ignored(pair)) moving_.push_back(pair);
  std::sort(moving_.begin(), moving_.end(),
            [](const ContactPair& a, const ContactPair& b) { return key(a) < key(b); });
  moving_.erase(
      std::unique(moving_.begin(), moving_.end(),
                  [](const ContactPair& a, const ContactPair& b) { return key(a) == key(b); }),
      moving_.end());
  return moving_;
}

std::vector<ContactPair> SelfContact::approachingPairs(const Positions& x,
                                                       const Positions& sweep) const {
  const double motion = sweep.size() == 0 ? 0.0 : relativeMotion(sweep);
  if (motion > kLongestKeptMotion * layer_) {
    std::vector<ContactPair> pairs = countedCandidates(x, sweep, 0.5 * layer_);
    pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                               [&](const ContactPair& p) { return ignored(p); }),
                pairs.end());
    return pairs;
  }
  if (!(keptAt_.rows() == x.rows() && relativeMotion(x - keptAt_) + motion <= keptMargin_))
    keep(x, std::max(0.5 * layer_, motion));
  return kept_;
}

std::vector<bool> SelfContact::fastVertices(const Positions& x, const Positions& dx) const {
  if (!keptServe(x, Positions())) keep(x, 0.5 * layer_);
  const double reach = rateAllowance(relativeMotion(x - keptAt_));
  const Eigen::RowVector3d centre = median(dx);
  std::vector<bool> fast(x.rows());
  for (Eigen::Index v = 0; v < x.rows(); ++v)
    fast[v] = !(kRateBound * (dx.row(v) - centre).norm() <= reach);
  return fast;
}

void SelfContact::keep(const Positions& x, double margin) const {
  keptMargin_ = margin;
  kept_.clear();
  keptDistance_.clear();
  keptSlack_ = kDistanceRoundoff * (layer_ + x.cwiseAbs().maxCoeff());
  const double reach = layer_ + 2.0 * keptMargin_ + keptSlack_;
  for (const ContactPair& pair : countedCandidates(x, Positions(), 0.5 * layer_ + keptMargin_)) {
    if (ignored(pair) || boxGap(pair, x) >= reach) continue;
    const double distance = std::sqrt(squaredDistance(pair, x));
    if (distance >= reach) continue;
    kept_.push_back(pair);
    keptDistance_.push_back(distance);
  }
  keptAt_ = x;
}

void SelfContact::measureMoves(const Positions& x) const {
  const Positions u = x - keptAt_;
  const Eigen::RowVector3d centre = midrange(u);
  moved_.resize(x.rows());
  for (Eigen::Index v = 0; v < x.rows(); ++v) moved_[v] = (u.row(v) - centre).norm();
}

double SelfContact::keptDistanceBound(std::size_t k, const std::array<int, 4>& v) const {
  const int split = kept_[k].kind == ContactPair::Kind::VertexFace ? 1 : 2;
  double first = 0.0, second = 0.0;
  for (int i = 0; i < 4; ++i) {
    double& farthest = i < split ? first : second;
    farthest = std::max(farthest, moved_[v[i]]);
  }
  return keptDistance_[k] - first - second - keptSlack_;
}

const std::vector<std::pair<ContactPair, double>>& SelfContact::activePairs(
    const Positions& x) const {
  if (empty() || (activeAt_.rows() == x.rows() && activeAt_ == x)) return active_;
  const auto start = std::chrono::steady_clock::now();
  active_.clear();
  const std::vector<ContactPair>& pairs = nearbyPairs(x, Positions());
  const bool kept = &pairs == &kept_;
  if (kept) measureMoves(x);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const ContactPair& pair = pairs[k];
    // Lower bounds on the distance: the kept one, the boxes' gap.
    if (kept && keptDistanceBound(k, vertices(pair)) >= layer_) continue;
    if (boxGap(pair, x) >= layer_) continue;
    const double s = squaredDistance(pair, x);
    const double layer = pairLayer(pair);
    if (s < layer * layer) active_.emplace_back(pair, s);
  }
  activeAt_ = x;
  detectionSeconds_ += secondsSince(start);
  return active_;
}

double SelfContact::unmollifiedStiffness(const ContactPair& pair) const {
  const std::array<bool, 2> shell = onShell(pair);
  double kappa = shell[0] && shell[1] ? stiffness_ : obstacleStiffness_;
  for (int v : vertices(pair))
    if (v < shellVertices_) kappa = std::max(kappa, vertexStiffness_[v]);
  return kappa * layer_ / pairLayer(pair);
}

double SelfContact::mollifier(const ContactPair& pair, const Positions& x) const {
  if (pair.kind == ContactPair::Kind::VertexFace) return 1.0;
  const std::array<int, 4> v = vertices(pair);
  const double threshold = edgeEdgeMollifierThreshold(row(rest_, v[0]), row(rest_, v[1]),
                                                      row(rest_, v[2]), row(rest_, v[3]));
  return edgeEdgeMollifier(row(x, v[0]), row(x, v[1]), row(x, v[2]), row(x, v[3]), threshold);
}

double SelfContact::pairStiffness(const ContactPair& pair, const Positions& x) const {
  return unmollifiedStiffness(pair) * mollifier(pair, x);
}

double SelfContact::pairBarrier(const ContactPair& pair, double squaredDistance, const Positions& x,
                                Vector12* gradient, Matrix12* hessian) const {
  const std::array<int, 4> v = vertices(pair);
  const bool wantGradient = gradient != nullptr || hessian != nullptr;
  const double d = std::sqrt(squaredDistance);
  double b1 = 0.0, b2 = 0.0;
  const double b = barrierPotential(d, pairLayer(pair), &b1, &b2);
  if (!std::isfinite(b)) return b;
  // The mollifier m (1 for a vertex–face pair) and its derivatives.
  double m = 1.0;
  Vector12 mGradient = Vector12::Zero();
  Matrix12 mHessian = Matrix12::Zero();
  Vector12 sGradient;
  Matrix12 sHessian;
  if (pair.kind == ContactPair::Kind::VertexFace) {
    pointTriangleDistanceSquared(row(x, v[0]), row(x, v[1]), row(x, v[2]), row(x, v[3]),
                                 wantGradient ? &sGradient : nullptr,
                                 hessian != nullptr ? &sHessian : nullptr);
  } else {
    edgeEdgeDistanceSquared(row(x, v[0]), row(x, v[1]), row(x, v[2]), row(x, v[3]),
                            wantGradient ? &sGradient : nullptr,
                            hessian != nullptr ? &sHessian : nullptr);
    const double threshold = edgeEdgeMollifierThreshold(row(rest_, v[0]), row(rest_, v[1]),
                                                        row(rest_, v[2]), row(rest_, v[3]));
    m = edgeEdgeMollifier(row(x, v[0]), row(x, v[1]), row(x, v[2]), row(x, v[3]), threshold,
                          wantGradient ? &mGradient : nullptr,
                          hessian != nullptr ? &mHessian : nullptr);
  }
  const double kappa = unmollifiedStiffness(pair);
  if (!wantGradient) return kappa * m * b;
  const Vector12 dGradient = sGradient / (2.0 * d);
  if (gradient != nullptr) *gradient = kappa * (b * mGradient + m * b1 * dGradient);
  if (hessian != nullptr) {
    const Matrix12 dHessian =
        sHessian / (2.0 * d) - sGradient * sGradient.transpose() / (4.0 * d * d * d);
    const Matrix12 bm = b1 * mGradient * dGradient.transpose();
    *hessian = kappa * (b * mHessian + bm + bm.transpose() +
                        m * (b2 * dGradient * dGradient.transpose() + b1 * dHessian));
  }
  return kappa * m * b;
}

std::vector<FrictionContact> SelfContact::frictionContacts(const Positions& shell,
                                                           double end) const {
  std::vector<FrictionContact> contacts;
  if (empty()) return contacts;
  const Positions x = stacked(shell);
  Positions obstacleMotion = -obstaclePositions_;
  for (std::size_t k = 0; k < obstacles_.size(); ++k)
    obstacleMotion.middleRows(vertexStart_[k] - shellVertices_, obstacles_[k].mesh.vertexCount()) +=
        obstacles_[k].positionsAt(end);
  for (const auto& [pair, s] : activePairs(x)) {
    const std::array<int, 4> v = vertices(pair);
    Vector12 sGradient;
    if (pair.kind == ContactPair::Kind::VertexFace)
      pointTriangleDistanceSquared(row(x, v[0]), row(x, v[1]), row(x, v[2]), row(x, v[3]),
                                   &sGradient);
    else
      edgeEdgeDistanceSquared(row(x, v[0]), row(x, v[1]), row(x, v[2]), row(x, v[3]), &sGradient);
    const double d = std::sqrt(s);
    const int firstVertices = pair.kind == ContactPair::Kind::VertexFace ? 1 : 2;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (int i = 0; i < firstVertices; ++i) n += sGradient.segment<3>(3 * i) / (2.0 * d);
    if (!(d > 0.0)) continue;
    // λ = −κ m b'(d): the barrier's force along the distance, the mollifier held fixed.
    double b1 = 0.0;
    barrierPotential(d, pairLayer(pair), &b1);
    FrictionContact c;
    c.normalForce = -pairStiffness(pair, x) * b1;
    if (!(c.normalForce > 0.0)) continue;
    c.basis = tangentBasis(n.normalized());
    for (int i = 0; i < 4; ++i) {
      const double w = sGradient.segment<3>(3 * i).dot(n) / (2.0 * d);
      if (v[i] < shellVertices_) {
        c.vertices[i] = v[i];
        c.weights[i] = w;
      } else {
        c.offset += w * obstacleMotion.row(v[i] - shellVertices_).transpose();
      }
    }
    contacts.push_back(c);
  }
  return contacts;
}

double SelfContact::energy(const Positions& shell) const {
  const Positions x = stacked(shell);
  double total = 0.0;
  for (const auto& [pair, s] : activePairs(x)) {
    if (s <= 0.0) return std::numeric_limits<double>::infinity();
    total += pairBarrier(pair, s, x, nullptr, nullptr);
  }
  return total;
}

void SelfContact::addGradient(const Positions& shell, Positions& gradient) const {
  const Positions x = stacked(shell);
  for (const auto& [pair, s] : activePairs(x)) {
    Vector12 g;
    pairBarrier(pair, s, x, &g, nullptr);
    const std::array<int, 4> v = vertices(pair);
    for (int i = 0; i < 4; ++i)
      if (v[i] < shellVertices_) gradient.row(v[i]) += g.segment<3>(3 * i).transpose();
  }
}

void SelfContact::add(const HessianAssembly& assembly, const Positions& shell, HessianEvaluation& e,
                      bool semidefinite) const {
  if (empty()) return;
  const Positions x = stacked(shell);
  // The free index of each vertex coordinate (−1: pinned, or an obstacle's).
  const std::vector<int> index = vertexUnknownIndex(assembly, shellVertices_);
  const bool withHessian = !e.values.empty();
  for (const auto& [pair, s] : activePairs(x)) {
    if (s <= 0.0) {
      e.energy = std::numeric_limits<double>::infinity();
      continue;
    }
    Vector12 g;
    Matrix12 h;
    e.energy += pairBarrier(pair, s, x, &g, withHessian ? &h : nullptr);
    if (withHessian && semidefinite) h = projected(h);
    addFourVertexBlock(assembly, index, vertices(pair), g, h, e);
  }
}

double SelfContact::stepBound(const Positions& x, const Positions& dx) const {
  if (empty()) return 1.0;
  return boundOver(stacked(x), stackedMotion(dx, Positions()), nullptr);
}

double SelfContact::stepBound(const Positions& x, const Positions& dx, double t,
                              ContactPair* limiting) const {
  if (empty()) return 1.0;
  Positions obstacleMotion = -obstaclePositions_;
  for (std::size_t k = 0; k < obstacles_.size(); ++k)
    obstacleMotion.middleRows(vertexStart_[k] - shellVertices_, obstacles_[k].mesh.vertexCount()) +=
        obstacles_[k].positionsAt(t);
  return boundOver(stacked(x), stackedMotion(dx, obstacleMotion), limiting);
}

double SelfContact::boundOver(const Positions& x, const Positions& dx,
                              ContactPair* limiting) const {
  const auto start = std::chrono::steady_clock::now();
  // A wild motion (nearbyPairs' long motion with many vertices fast, kWildShare: a chord step on
  // a stale factor can move the sheet's parts apart by its own size): its swept boxes would pair
  // up much of the mesh. It is cut first to the α₀ at which no vertex is fast, where the kept
  // pairs alone bound it: a smaller bound than the exact one, still feasible (and the line search
  // then starts there).
  const double motion = dx.size() == 0 ? 0.0 : relativeMotion(dx);
  double cut = 1.0;
  if (!keptServe(x, dx) && neededMargin(motion) > kLongestKeptMotion * layer_) {
    const std::vector<bool> fast = fastVertices(x, dx);  // the kept pairs serve x from here on
    if (kWildShare * x.rows() < std::count(fast.begin(), fast.end(), true))
      cut = kWildCut * rateAllowance(relativeMotion(x - keptAt_)) / (kRateBound * motion);
  }
  const double bound =
      cut < 1.0 ? cut * pairsBound(x, cut * dx, limiting) : pairsBound(x, dx, limiting);
  detectionSeconds_ += secondsSince(start);
  return bound;
}

double SelfContact::pairsBound(const Positions& x, const Positions& dx,
                               ContactPair* limiting) const {
  double bound = 1.0;
  const std::vector<ContactPair>& pairs = nearbyPairs(x, dx);
  const bool kept = &pairs == &kept_;
  if (kept) measureMoves(x);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const ContactPair& pair = pairs[k];
    if (boxGap(pair, x, &dx) > 0.0) continue;  // the swept boxes are apart: no contact
    const std::array<int, 4> v = vertices(pair);
    const std::array<Eigen::Vector3d, 4> p{row(x, v[0]), row(x, v[1]), row(x, v[2]), row(x, v[3])};
    const std::array<Eigen::Vector3d, 4> d{row(dx, v[0]), row(dx, v[1]), row(dx, v[2]),
                                           row(dx, v[3])};
    const int split = pair.kind == ContactPair::Kind::VertexFace ? 1 : 2;
    if (kept && distanceRateBound(d, split) <=
                    kFirstStepMargin * (1.0 - kImpactGap) * keptDistanceBound(k, v))
      continue;  // its impact time is 1
    const double t =
        pair.kind == ContactPair::Kind::VertexFace
            ? pointTriangleImpactTime(p[0], p[1], p[2], p[3], d[0], d[1], d[2], d[3], kImpactGap)
            : edgeEdgeImpactTime(p[0], p[1], p[2], p[3], d[0], d[1], d[2], d[3], kImpactGap);
    if (t < bound && limiting != nullptr) *limiting = pair;
    bound = std::min(bound, t);
  }
  return bound;
}

std::vector<std::array<int, 2>> SelfContact::couplings(const Positions& shell,
                                                       const Positions& dx) const {
  if (empty()) return {};
  const auto start = std::chrono::steady_clock::now();
  // Each coupling (i, j) is listed under i (counting sort), and each vertex's list sorted and
  // cleared of repeats: the result comes out sorted in O(n) for a bounded number per vertex.
  // Distances do not change under a common translation: the swept boxes of dx less its
  // coordinates' midranges hold the pairs' relative motion.
  Positions motion = stackedMotion(dx, Positions());
  if (motion.rows() != 0) motion.rowwise() -= midrange(motion);
  std::vector<std::array<int, 2>> listed;
  for (const ContactPair& pair : countedCandidates(stacked(shell), motion, 0.5 * layer_)) {
    if (ignored(pair)) continue;
    const std::array<int, 4> v = vertices(pair);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (v[i] != v[j] && v[i] < shellVertices_ && v[j] < shellVertices_)
          listed.push_back({std::min(v[i], v[j]), std::max(v[i], v[j])});
  }
  std::vector<int> first(shellVertices_ + 1, 0), second(listed.size());
  for (const std::array<int, 2>& c : listed) ++first[c[0] + 1];
  for (int v = 0; v < shellVertices_; ++v) first[v + 1] += first[v];
  std::vector<int> next(first.begin(), first.end() - 1);
  for (const std::array<int, 2>& c : listed) second[next[c[0]]++] = c[1];
  std::vector<std::array<int, 2>> pairs;
  for (int v = 0; v < shellVertices_; ++v) {
    const auto begin = second.begin() + first[v], end = second.begin() + first[v + 1];
    std::sort(begin, end);
    for (auto j = begin; j != end; ++j)
      if (j == begin || *j != *(j - 1)) pairs.push_back({v, *j});
  }
  detectionSeconds_ += secondsSince(start);
  return pairs;
}

ContactCensus SelfContact::census(const Positions& shell) const {
  ContactCensus c;
  for (const auto& [pair, s] : activePairs(stacked(shell))) {
    ++c.pairs;
    if (std::sqrt(s) < c.smallestDistance) {
      c.smallestDistance = std::sqrt(s);
      c.closest = pair;
    }
  }
  return c;
}

void SelfContact::requireApart(const Positions& shell, const std::string& what) const {
  if (empty()) return;
  const modeling::Mesh shellMesh{shell, faces_.topRows(shellFaces_)};
  if (shellPairs_) {
    const std::vector<std::array<int, 2>> crossing = modeling::intersectingFacePairs(shellMesh);
    if (!crossing.empty())
      throw InputError(what + ": the shell passes through itself: faces " +
                       std::to_string(crossing[0][0]) + " and " + std::to_string(crossing[0][1]) +
                       " intersect (" + std::to_string(crossing.size()) + " pairs in all)");
  }
  for (std::size_t k = 0; k < obstacles_.size(); ++k) {
    const int first = vertexStart_[k] - shellVertices_;
    const modeling::Mesh obstacle{
        obstaclePositions_.middleRows(first, obstacles_[k].mesh.vertexCount()),
        obstacles_[k].mesh.triangles};
    const std::vector<std::array<int, 2>> crossing =
        modeling::intersectingFacePairs(shellMesh, obstacle);
    if (!crossing.empty())
      throw InputError(what + ": " + meshObstacleName(obstacles_, static_cast<int>(k)) +
                       " intersects the shell: shell face " + std::to_string(crossing[0][0]) +
                       " and its face " + std::to_string(crossing[0][1]) + " (" +
                       std::to_string(crossing.size()) + " pairs in all)");
  }
  for (const auto& [pair, s] : activePairs(stacked(shell)))
    if (s <= 0.0) throw InputError(what + ": " + describe(pair) + " touch");
}

SelfContact makeSelfContact(const modeling::Stencils& stencils, const Positions& rest,
                            const Eigen::VectorXd& mass, const Eigen::Vector3d& gravity,
                            double layer, const std::vector<MeshObstacle>& obstacles,
                            bool shellPairs) {
  if (layer == 0.0) {
    double total = 0.0;
    for (int e = 0; e < stencils.edgeCount(); ++e)
      total += (rest.row(stencils.edges(e, 0)) - rest.row(stencils.edges(e, 1))).norm();
    layer = 0.25 * total / std::max(1, stencils.edgeCount());
  }
  const double stiffness = mass.mean() * std::max(gravity.norm(), 1.0) / layer;
  SelfContact contact(stencils.faces, stencils.edges, rest, layer, stiffness);
  if (!obstacles.empty() || !shellPairs) contact.addObstacles(obstacles, shellPairs);
  return contact;
}

}  // namespace flexure::optimize
