// Self-contact of a shell: every vertex–face and edge–edge pair of the mesh repels through the
// log barrier of obstacles.h on its unsigned distance (incremental potential contact, Li et al.
// 2020, "Incremental Potential Contact", ACM TOG 39(4), §4; its codimensional form for shells,
// Li, Kaufman & Jiang 2021, "Codimensional Incremental Potential Contact", ACM TOG 40(4)), so
// that no two parts of the mesh — fragments after a cut included — pass through each other.
//
// Pairs: a vertex and a face not containing it, two edges sharing no vertex (contact/
// broad_phase.h finds the candidates in O(n)). A pair k at distance d_k < d̂ contributes
//   B_k = κ m_k b(d_k),   b(d) = −(d − d̂)² log(d / d̂)  (barrierPotential, obstacles.h),
// with m_k = 1 for a vertex–face pair and, for an edge–edge pair, IPC's mollifier m(c) of the
// edges' cross product c = |e_a × e_b|² (contact/primitive_distance.h), which makes B_k C¹ where
// nearly parallel edges switch between distance types and vanishes with the cross product.
// The derivatives of d = √s come from those of the squared distance s:
//   ∇d = ∇s / (2d),   ∇²d = ∇²s / (2d) − ∇s ∇sᵀ / (4 d³),
// and B_k's Hessian, κ [b m'' + b'(m' ∇dᵀ + ∇d m'ᵀ) + m (b'' ∇d ∇dᵀ + b' ∇²d)] over the pair's
// 12 coordinates, enters Newton's matrix projected to its nearest positive semidefinite matrix
// (as IPC does) or exact (`add`'s `semidefinite`). Time steps take it exact, as they take the
// elastic terms, and projected in the Gauss–Newton fallback when the step's matrix is not
// positive definite (newton_loop.h): a pressed pair's b' ∇²d is negative across the contact
// normal, and with it dropped Newton converged only linearly (by about 4 % an iteration at the
// smallest step of the 2 698-vertex light bulb, which stopped at t = 0.058). Its entries enter
// where the Hessian pattern couples the pair's vertices (couplings() says which the pattern
// needs); a pair whose vertices it does not couple enters by its diagonal 3 × 3 blocks only — a
// principal part, so semidefinite where the pair's matrix is, and still a descent model.
//
// Layer and stiffness (the stated rule, as the obstacles'): d̂ = ¼ of the rest mesh's mean edge
// length unless given, κ = m̄ max(|g|, 1) / d̂ with m̄ the mean lumped vertex mass: a vertex resting
// on a face holds about its weight at half the layer. That κ holds a vertex's weight but not its
// momentum: a light vertex of a fresh crack lip flung at 100–1000 m/s towards a pair 5e-4 apart
// (the 2 698-vertex light bulb) met a barrier ~600× weaker than its step's inertia, and Newton
// crawled towards d ≈ 5e-8 in steps the collision filter cut to 2–7 % of their length. So time
// steps adapt it per shell vertex by the obstacles' rule (obstacles.h, adaptedStiffness): `adapt`
// sets κ_v from μ_k w_k², twice the kinetic energy of approach of the vertex's pairs that the
// step's motion at the present velocities can bring within d̂ (w_k = −ḋ_k = −∇d_k · ẋ over the
// pair's four vertices, an obstacle's vertices moving by their motion; μ_k the pair's reduced
// mass, so a heavy vertex meeting a light fast one is not stiffened by the light one's speed
// alone), freely outside the layer and raised within the stiffening budget inside it, there by
// the pairs within 2 d̂ that would close at least half their distance in the step (w_k h ≥ d_k/2:
// a sheet sliding on another has pairs whose closest points lie on an edge of the face below,
// and their distances shrink while the sheet's does not; raising κ for them pumped energy into
// a sliding sheet and slowed it by 2.6 %); a pair's stiffness is the largest of κ (κ_o with an
// obstacle) and its shell vertices' κ_v. Raising κ_v by
// Δ raises each of its pairs' by at most Δ, so the budget counts Δ times Σ of its pairs' barriers
// per unit κ. Static solves keep κ.
//
// Pairs close at rest and at the start are inset (the seed's fracture-aware rule, Gingold et al.
// 2004 §5, which insets the repulsion along fresh crack lips): a cut's lips start coincident, and
// the neighbours of a sliver-rich rest mesh may lie within d̂ of each other; repelling them at d̂
// would push lips apart and strain an unloaded mesh. Such a pair (within d̂ both in the rest state
// and at the start, exemptClosePairs) repels on its own inset layer ℓ_k < d̂ instead: ℓ_k = 0 (no
// repulsion) while it is closer than d̂/1000 both at rest and in place — lips still together (a
// cut opens its fresh lips at rest and in place, fracture.h's openLips, so a pair apart at rest is
// inset at any distance above 0) —, then half the largest distance
// it has been found at (liftExemptions, before each time step: ℓ_k ← max(ℓ_k, d/2), which leaves
// B_k = 0 where it is), until it is found at d ≥ d̂ and repels on d̂ like any other pair. A cut
// keeps the state of every pair it leaves whole (carriedInsets): were the cut mesh's close pairs
// inset afresh at half their distance, a lip pressed shut to a tenth of its layer would lose its
// barrier at each cut and its layer would shrink tenfold per cut (the 2 698-vertex light bulb
// ended with a pair 1.9e-9 apart on a layer of 2.9e-6, Newton stalling). So
// abutting lips stay where they are, separate freely and may touch again, but once apart they
// never pass through each other (its inset pairs join the collision filter as well). An inset
// pair's stiffness is κ d̂/ℓ_k: the barrier's force at d = c ℓ_k, ∝ κ ℓ_k, is then an ordinary
// pair's at c d̂.
//
// Mesh obstacles (mesh_obstacles.h) join the collision mesh: its vertices are the shell's [0, V),
// then each obstacle's; its faces and edges the shell's, then each obstacle's with offset indices.
// A pair between an obstacle primitive and a shell primitive repels like any other (never exempt:
// an obstacle has no rest state relative to the shell); pairs of two obstacle primitives are left
// out, and pairs of two shell primitives count only with self-contact on. The obstacles'
// positions are set per time (setObstacleTime) and are never unknowns: every public function
// takes and returns the shell's rows (#V) alone.
//
// Feasibility: a step x + α δ is capped by stepBound, additive continuous collision detection
// (contact/continuous_collision.h) over the pairs whose boxes the motion sweeps, so that no pair
// that repels ever crosses during a step (IPC's guarantee: the line search never leaves the
// intersection-free set).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "modeling/stencils.h"
#include "optimize/assembly/friction.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/assembly/mesh_obstacles.h"
#include "optimize/assembly/obstacles.h"

namespace flexure::optimize {

// A pair of primitives: a vertex and a face, or two edges (indices into the mesh's edge list).
struct ContactPair {
  enum class Kind { VertexFace, EdgeEdge };
  Kind kind = Kind::VertexFace;
  int first = -1, second = -1;  // (vertex, face) or (edge, edge)
};

// An inset pair and its layer ℓ_k (below: 0 while its lips are together).
struct InsetPair {
  ContactPair pair;
  double layer = 0.0;
};

// What a configuration's contact looks like (report.json's contact statistics).
struct ContactCensus {
  int pairs = 0;  // pairs within the layer, exempt ones left out
  double smallestDistance = std::numeric_limits<double>::infinity();  // over those pairs
  ContactPair closest;
};

class SelfContact {
 public:
  SelfContact() = default;  // off
  // `faces` (#F by 3) and `edges` (#E by 2) of the mesh, its rest positions (the mollifiers'
  // thresholds and the exemptions), the layer d̂ > 0 and the stiffness κ > 0.
  SelfContact(modeling::Triangles faces, modeling::IndexPairs edges, Positions rest, double layer,
              double stiffness);

  // Appends `obstacles` to the collision mesh, placed at time 0; shell–shell pairs count only when
  // `shellPairs` (self-contact on).
  void addObstacles(std::vector<MeshObstacle> obstacles, bool shellPairs);
  // Places the mesh obstacles where they are at time t.
  void setObstacleTime(double t);
  const std::vector<MeshObstacle>& meshObstacles() const { return obstacles_; }
  // The obstacles' vertices (#W by 3, in order) where setObstacleTime last put them.
  const Positions& obstaclePositions() const { return obstaclePositions_; }
  bool obstaclesMove() const;
  // κ_o, the stiffness of the pairs with a mesh obstacle (≥ κ; κ unless raised): a moving obstacle
  // must make the shell give way at its speed, which may take a stiffer barrier than the
  // weight-based κ (TimeStepper raises it, as IPC adapts κ, Li et al. 2020 §4.3).
  double obstacleStiffness() const { return obstacleStiffness_; }
  void setObstacleStiffness(double stiffness);
  // Whether pairs of two shell primitives repel (self-contact on).
  bool shellPairs() const { return shellPairs_; }

  bool empty() const { return faces_.rows() == 0; }
  double layer() const { return layer_; }
  double stiffness() const { return stiffness_; }

  // Before a time step of length `step` at x with vertex velocities `velocity` (#V by 3), the
  // obstacles where setObstacleTime put them: the adaptive stiffness above with the lumped masses
  // `mass` (#V) over the pairs the motion x + step · velocity can bring within d̂ (step 0: those
  // within d̂ now), the raises inside the layer adding at most `budget` to the barrier energy.
  // Returns that bound on the energy they added.
  double adapt(const Positions& x, const Positions& velocity, const Eigen::VectorXd& mass,
               double step, double budget = std::numeric_limits<double>::infinity());
  // Back to κ at every vertex (the start of a run).
  void resetStiffness();
  // κ_v per shell vertex (#V), and a replacement as a checkpoint or a cut kept it (InputError
  // for a wrong size or a value below κ or not finite).
  const Eigen::VectorXd& vertexStiffness() const { return vertexStiffness_; }
  void setVertexStiffness(const Eigen::VectorXd& stiffness);

  // Insets the pairs within d̂ both in the rest state and at x (the start of a run, a cut), and
  // only those, with ℓ_k = 0.
  void exemptClosePairs(const Positions& x);
  // Raises each inset pair's ℓ_k to half its distance d at x when d ≥ d̂/1000, or d > 0 and the
  // pair is d̂/1000 apart at rest, and lifts the inset of every pair at d ≥ d̂.
  void liftExemptions(const Positions& x);
  int exemptCount() const { return static_cast<int>(exempt_.size()); }
  // The inset pairs, in a fixed order, and a replacement for them (a state a run reached: its
  // insets carry their history). InputError for a pair whose primitives are not the shell's.
  std::vector<InsetPair> insets() const;
  void setInsets(const std::vector<InsetPair>& insets);
  // This mesh's insets (a cut mesh's, as exemptClosePairs left them) with the history of
  // `before`, the mesh the cut was made in: this mesh's vertex i is a copy of before's vertex
  // ancestor[i] (−1 for a vertex the cut added on an edge). A pair whose four vertices are copies
  // of four distinct vertices forming a pair of `before` keeps what that pair was: its inset layer,
  // or no inset for an ordinary pair. So a cut changes no barrier between primitives it leaves
  // whole (a lip pressed shut stays on its layer, an ordinary pair stays on d̂); pairs across the
  // fresh lips, with a vertex the cut added or whose ancestors share a vertex, start as inset.
  std::vector<InsetPair> carriedInsets(const SelfContact& before,
                                       const std::vector<int>& ancestor) const;

  // Σ_k B_k at x (#V by 3); +∞ when a repelling pair touches (d = 0).
  double energy(const Positions& x) const;
  // Adds Σ_k B_k, its gradient and (when e.values is filled) its Hessian at x to `e`, an
  // evaluation over `assembly`'s free unknowns: each pair's projected to its nearest positive
  // semidefinite matrix (`semidefinite`, what Newton takes), or exact.
  void add(const HessianAssembly& assembly, const Positions& x, HessianEvaluation& e,
           bool semidefinite = true) const;
  // Adds the gradient of Σ_k B_k at x to `gradient` (#V by 3), every vertex.
  void addGradient(const Positions& x, Positions& gradient) const;
  // The largest α ≤ 1 such that no repelling pair crosses while x moves to x + α' dx, α' ≤ α
  // (conservative: each pair keeps at least a tenth of its distance at x).
  double stepBound(const Positions& x, const Positions& dx) const;
  // The same bound while x moves to x + dx and the obstacles from where they are to where they
  // are at time t, and the pair that sets it (when < 1).
  double stepBound(const Positions& x, const Positions& dx, double t, ContactPair* limiting) const;
  // The shell's vertices among a pair's four (none for a pair of two obstacle primitives).
  std::vector<int> shellVerticesOf(const ContactPair& pair) const;
  // A pair in words: "shell vertex 3 and face 7 of box.obj", "shell edge (1, 2) and …".
  std::string describe(const ContactPair& pair) const;
  // The vertex pairs (i < j) of the repelling pairs that may come within d̂ while x moves to
  // x + dx (every pair of the two primitives' vertices): what the Hessian pattern should couple.
  std::vector<std::array<int, 2>> couplings(const Positions& x, const Positions& dx) const;
  // The repelling pairs within d̂ at x, and the closest of them.
  ContactCensus census(const Positions& x) const;
  // The lagged friction contacts (friction.h) of the repelling pairs within d̂ at x (#V by 3), the
  // obstacles where setObstacleTime put them and moving to where they are at time `end`: per pair
  // its normal force λ = −κ m b'(d), the closest points' direction n = ∇_{first primitive} s /
  // (2d) (∇s of a primitive's vertex is 2 w (c_a − c_b), w its closest point's coordinate, by the
  // envelope theorem) and the weights w_i = ∇_i s · n / (2d), negative on the second primitive;
  // the obstacle vertices' motion enters r₀.
  std::vector<FrictionContact> frictionContacts(const Positions& x, double end) const;
  // InputError naming a pair of faces of `what` (e.g. "the start") that intersect (exact,
  // modeling/self_intersections.h), or the first repelling pair that touches (d = 0).
  void requireApart(const Positions& x, const std::string& what) const;
  // The wall-clock seconds spent in the broad phase and the collision filter since the last take.
  double takeDetectionSeconds() { return std::exchange(detectionSeconds_, 0.0); }

 private:
  // The repelling pairs within d̂ at x, each with its squared distance (kept until the next x).
  const std::vector<std::pair<ContactPair, double>>& activePairs(const Positions& x) const;
  // The candidate pairs (exempt ones left out) that can come within d̂ at x, or whose impact
  // time (stepBound) can be < 1 while x moves to x + dx (dx empty: static). Distances do not change
  // under a common translation, so the rule measures motion after removing one: M(u) is
  // max_v |u_v − c| with c the coordinates' midranges of u; ρ(x) = M(x − x_k) (x_k: where the
  // candidates were kept), so x is x_k moved by one translation and each vertex by at most ρ
  // besides, and every point of a primitive too (a convex combination of its vertices); M(dx)
  // bounds ACCD's rate l ≤ 3 M (continuous_collision.h: each |dx_i − p̄| ≤ ¾ max_j |dx_i − dx_j|
  // ≤ 1.5 M). The kept candidates are the pairs within distance d̂ + 2r of x_k (the broad phase's
  // boxes inflated by (d̂ + 2r)/2, then each pair's distance; on a smooth sheet with d̂ a quarter
  // edge that leaves out the ring neighbours a box test keeps); any other pair is at x more than
  // d̂ + 2r − 2ρ apart. They serve x when ρ(x) ≤ r (no other pair within d̂), and a motion dx
  // besides when 3 M(dx) ≤ 0.99 (1 − s) (d̂ + 2r − 2ρ(x)), so that every other pair's ACCD reaches
  // t = 1 in its first step (s: ACCD's gap fraction).
  // Otherwise a new broad phase at x keeps the pairs with r = max(d̂/2, M, the r the motion needs),
  // or, when that r exceeds d̂/2 (a long motion), returns, not kept, the kept pairs (kept anew at
  // x with r = d̂/2 unless they serve it) and the pairs whose swept boxes overlap among those with
  // a fast vertex (fastVertices): every other pair's vertices are slow, so its ACCD rate is
  // within that bound and its impact time 1, as above (on the 10 000-vertex drape a long motion's
  // swept boxes paired about 170 000 primitives, most of them ring neighbours no step brings near;
  // a wild motion is cut before, boundOver).
  const std::vector<ContactPair>& nearbyPairs(const Positions& x, const Positions& dx) const;
  // A pair's stiffness: the largest of κ (κ_o with an obstacle) and its shell vertices' κ_v, times
  // d̂/ℓ_k when inset (the force of a pair at a given fraction of its layer is then the same as an
  // ordinary pair's).
  double unmollifiedStiffness(const ContactPair& pair) const;
  // m_k of a pair at x (1 for a vertex–face pair), and κ m_k: its stiffness times its mollifier.
  double mollifier(const ContactPair& pair, const Positions& x) const;
  double pairStiffness(const ContactPair& pair, const Positions& x) const;
  // What adapt knows of each shell vertex's pairs at x moving with `velocity` (the collision
  // mesh's rows) over the candidates `pairs`, with the shell's lumped masses `mass` (#V), before
  // a step of length `step` (the near impacts: the pairs within 2 d̂ closing at least half their
  // distance in the step).
  std::vector<VertexApproach> approaches(const std::vector<ContactPair>& pairs, const Positions& x,
                                         const Positions& velocity, const Eigen::VectorXd& mass,
                                         double step) const;
  // The reduced mass m₁m₂/(m₁ + m₂) of a pair with vertices v: m_i the mean mass of primitive i's
  // vertices, ∞ for an obstacle's (then the other's).
  double reducedMass(const ContactPair& pair, const std::array<int, 4>& v,
                     const Eigen::VectorXd& mass) const;
  // A pair's layer: ℓ_k when inset, else d̂; and whether it is ignored (inset with ℓ_k = 0).
  double pairLayer(const ContactPair& pair) const;
  bool ignored(const ContactPair& pair) const;
  // The pairs (exempt ones left out) that may come within d̂ while x moves to x + sweep (a
  // superset). A pair the kept candidates leave out is more than d̂ + 2r − 2ρ(x) apart at x
  // (nearbyPairs' rule), and each of its points moves by at most M(sweep) besides a common
  // translation: the kept ones serve when ρ(x) + M ≤ r, and are kept anew at x with
  // r = max(d̂/2, M) otherwise; a motion longer than nearbyPairs' longest kept one takes the
  // broad phase's pairs whose swept boxes come within d̂.
  std::vector<ContactPair> approachingPairs(const Positions& x, const Positions& sweep) const;
  // Whether the kept candidates serve x and the motion dx (nearbyPairs' rule).
  bool keptServe(const Positions& x, const Positions& dx) const;
  // The ACCD rate under which a pair the kept candidates leave out has impact time 1 at x with
  // ρ(x) = rho: 0.99 (1 − s) (d̂ + 2r − 2ρ); and the r that makes a motion M's 3 M equal it at
  // x_k = x (nearbyPairs' rule).
  double rateAllowance(double rho) const;
  double neededMargin(double motion) const;
  // The vertices too fast for the kept candidates, 3 |dx_v − c| > 0.99 (1 − s) (d̂ + 2r − 2ρ(x))
  // (nearbyPairs' rule; ACCD's l ≤ 3 max |dx_v − c| over a pair's vertices holds for any centre
  // c, here the coordinates' medians, which a few far vertices do not pull), the candidates kept
  // anew at x with r = d̂/2 unless they serve it.
  std::vector<bool> fastVertices(const Positions& x, const Positions& dx) const;
  // Keeps the candidates within d̂ + 2 margin of x (nearbyPairs' rule, r = margin).
  void keep(const Positions& x, double margin) const;
  // Sets moved_ to each vertex's distance at x from where the candidates were kept, after
  // removing the translation of the coordinates' midranges.
  void measureMoves(const Positions& x) const;
  // A lower bound on the distance at x of kept pair k with vertices v, given measureMoves(x): its
  // distance where it was kept less the farthest move of each primitive's vertices (every point of
  // a primitive moves at most as far as its farthest vertex; the translation changes no distance)
  // and a rounding allowance.
  double keptDistanceBound(std::size_t k, const std::array<int, 4>& v) const;
  // B_k, and when asked its gradient (12) and Hessian (12 by 12) over `vertices`.
  double pairBarrier(const ContactPair& pair, double squaredDistance, const Positions& x,
                     Eigen::Matrix<double, 12, 1>* gradient,
                     Eigen::Matrix<double, 12, 12>* hessian) const;
  // The four vertices a pair's coordinates belong to (a vertex–face pair: the vertex, then the
  // face's corners; an edge–edge pair: the first edge's ends, then the second's).
  std::array<int, 4> vertices(const ContactPair& pair) const;
  double squaredDistance(const ContactPair& pair, const Positions& x) const;
  // The largest gap along a coordinate axis between the two primitives' bounding boxes at x, or
  // over the motion from x to x + *dx (≤ 0 when they overlap): a lower bound on their distance
  // (during the motion).
  double boxGap(const ContactPair& pair, const Positions& x, const Positions* dx = nullptr) const;
  static std::uint64_t key(const ContactPair& pair);
  static ContactPair pairOf(std::uint64_t key);  // key's inverse
  // The collision mesh's positions: x (#V) and the obstacles' rows; a motion dx and the obstacles'
  // (zero when empty).
  Positions stacked(const Positions& x) const;
  Positions stackedMotion(const Positions& dx, const Positions& obstacleMotion) const;
  // Whether a pair's primitives are the shell's (each of the two), and whether the pair counts.
  std::array<bool, 2> onShell(const ContactPair& pair) const;
  bool counts(const ContactPair& pair) const;
  // The broad phase's counted pairs (contact/broad_phase.h), those with a vertex in *among only
  // when given.
  std::vector<ContactPair> countedCandidates(const Positions& x, const Positions& dx,
                                             double inflation,
                                             const std::vector<bool>* among = nullptr) const;
  // stepBound over the collision mesh's x and dx: a wild motion (many vertices fast) cut first;
  // pairsBound, the smallest impact time over nearbyPairs.
  double boundOver(const Positions& x, const Positions& dx, ContactPair* limiting) const;
  double pairsBound(const Positions& x, const Positions& dx, ContactPair* limiting) const;
  // Which obstacle the collision mesh's vertex / face / edge belongs to (−1: the shell's).
  int ownerOf(const std::vector<int>& starts, int index) const;
  std::string vertexText(int v) const;

  modeling::Triangles faces_;
  modeling::IndexPairs edges_;
  Positions rest_;
  double layer_ = 0.0, stiffness_ = 0.0;
  Eigen::VectorXd vertexStiffness_;                   // κ_v per shell vertex (adapt)
  double obstacleTime_ = 0.0;                         // where setObstacleTime put the obstacles
  std::unordered_map<std::uint64_t, double> exempt_;  // inset pairs (key) and their ℓ_k
  int shellVertices_ = 0, shellFaces_ = 0, shellEdges_ = 0;
  bool shellPairs_ = true;
  double obstacleStiffness_ = 0.0;
  std::vector<MeshObstacle> obstacles_;
  // Where obstacle k's vertices, faces and edges start in the collision mesh (K + 1 entries each).
  std::vector<int> vertexStart_, faceStart_, edgeStart_;
  Positions obstaclePositions_ = Positions(0, 3);
  mutable double detectionSeconds_ = 0.0;
  // The kept candidates and where they were found (nearbyPairs); a motion's candidates, and the
  // motion (movingAt_ → movingAt_ + movingBy_).
  mutable Positions keptAt_;
  mutable double keptMargin_ = 0.0;
  mutable std::vector<ContactPair> kept_, moving_;
  mutable Positions movingAt_, movingBy_;
  // The kept pairs' distances at keptAt_ (in kept_'s order), their rounding allowance, and each
  // vertex's distance from keptAt_ (measureMoves).
  mutable std::vector<double> keptDistance_, moved_;
  mutable double keptSlack_ = 0.0;
  // The last active pairs and where they were found (activePairs).
  mutable Positions activeAt_;
  mutable std::vector<std::pair<ContactPair, double>> active_;
};

// The rule's self-contact for a mesh (its faces and edges from `stencils`): d̂ = `layer`, or ¼ the
// mean rest edge length when 0; κ = m̄ max(|g|, 1) / d̂ with the lumped masses `mass` (#V); the
// mesh obstacles `obstacles` appended, shell–shell pairs counted when `shellPairs`.
SelfContact makeSelfContact(const modeling::Stencils& stencils, const Positions& rest,
                            const Eigen::VectorXd& mass, const Eigen::Vector3d& gravity,
                            double layer = 0.0, const std::vector<MeshObstacle>& obstacles = {},
                            bool shellPairs = true);

}  // namespace flexure::optimize
