// Obstacles a shell cannot pass: planes and spheres, felt by the vertices through a smooth log
// barrier (incremental potential contact, Li et al. 2020, "Incremental Potential Contact",
// ACM TOG 39(4)), used by the static solve (newton_solver.cpp) and the time steps
// (time_stepping.cpp) alike.
//
// Signed distance of a point x to an obstacle (positive outside, the free side):
//   plane:nx,ny,nz,d   the plane n·x = d, n normalized (d scaled with it); d(x) = n̂·x − d/|n|,
//                      the free side the one n points to (plane:0,0,1,0 is a floor at z = 0);
//   sphere:x,y,z,r     d(x) = |x − c| − r, the free side outside.
//
// Barrier on the distance d of vertex v inside a layer of thickness d̂:
//   b_v(d) = −κ_v (d − d̂)² log(d / d̂)   for 0 < d < d̂,   0 for d ≥ d̂,   +∞ for d ≤ 0,
// C² at d̂, convex and decreasing on (0, d̂), with
//   b'(d)  = −κ_v [2 (d − d̂) log(d/d̂) + (d − d̂)² / d],
//   b''(d) = −κ_v [2 log(d/d̂) + 4 (d − d̂) / d − (d − d̂)² / d²].
// The vertex energy is Σ_v Σ_o b_v(d_o(x_v)); its gradient b' ∇d and Hessian b'' ∇d ∇dᵀ + b' ∇²d
// (∇d = n̂ and ∇²d = 0 for a plane; ∇d = u = (x − c)/|x − c|, ∇²d = (I − u uᵀ)/|x − c| for a
// sphere, where b' ∇²d is negative semidefinite: the positive semidefinite variant drops it).
//
// Layer and stiffness (the stated rule): d̂ = ¼ of the rest mesh's mean edge length, and
// κ_v = m_v a / d̂ with m_v the vertex's lumped mass and a = max(|g|, 1) (g the gravity, in the
// mesh's units per s²): the barrier's force −b'(d̂/2) = 1.19 m_v a holds a vertex's weight at
// about half the layer, so a sheet at rest on an obstacle lies within d̂ of it.
//
// Adaptive stiffness (time steps only; after Li et al. 2020, §4.3, which raise κ where distances
// get small): the rule's κ_v holds a vertex's weight but not its momentum — a sheet falling at
// 1 m/s onto a sphere drove vertices to d ≈ 2e-5 d̂, where b'' ∝ 1/d², and contact steps took
// 4–11 factorizations. Before each step, `adapt` sets per vertex v
//   outside the layer (d ≥ d̂ for every obstacle, where b_v = 0 and κ_v can change freely):
//     κ_v = max(κ̄_v, 2 m_v w_v² / (d̂² log 2)),
//   inside it: κ_v = max(κ_v, 2 m_v w_v² / (d̂² log 2)) · min(2, d̂ / (10 d_v)) when d_v < d̂/10,
// with κ̄_v the rule's stiffness above and w_v the vertex's approach speed, the largest −v·∇d (0
// when receding) — outside the layer over every obstacle (κ_v costs nothing there, and a fast
// vertex can cross more than a layer in one step), inside it over the obstacles within 2 d̂ (a far
// obstacle's approach would stiffen the near one's barrier). The first term lets the barrier absorb
// the normal kinetic energy ½ m_v w² by d = d̂/2 (b(d̂/2) = κ d̂² log 2 / 4); the second grows κ_v, at
// most twofold per step, while a vertex is pressed deeper than d̂/10 (its equilibrium distance under
// a given load grows about in proportion to κ_v there). κ never falls inside the layer; raising it
// there adds (κ_new − κ_v) b_v(d)/κ_v to the motion — energy the pressed barrier gives back as
// kinetic energy on rebound, and which the twofold-per-step rule makes grow as the step shrinks
// (a sphere dropped on a plane: 13 %, 13 %, 16 % of its peak kinetic energy at h = 0.01, 0.005,
// 0.0025). So the raises inside the layer spend at most a budget of energy, vertex by vertex (the
// time stepper's: S, their energy over the run, at most the work done against damping plus half
// its energy tolerance of the peak kinetic energy, so that they never lift the total above E(0)).
//
// Feasibility: a step x + α δ of the solvers is capped by stepBound (continuous collision
// detection in closed form: the first α at which a vertex moving on a straight line reaches the
// plane or the sphere), so that no iterate ever has a vertex at d ≤ 0.
#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "modeling/rest_state.h"
#include "optimize/assembly/hessian_assembly.h"

namespace flexure::optimize {

struct Obstacle {
  enum class Kind { Plane, Sphere };
  Kind kind = Kind::Plane;
  Eigen::Vector3d vector = Eigen::Vector3d::UnitZ();  // plane: unit normal n̂; sphere: centre c
  double scalar = 0.0;                                // plane: offset d/|n|; sphere: radius r
  std::string label;  // for messages: parseObstacle's `option` and text ("obstacle plane:0,0,1,0")

  // d(x), and when asked ∇d and ∇²d.
  double signedDistance(const Eigen::Vector3d& x, Eigen::Vector3d* gradient = nullptr,
                        Eigen::Matrix3d* hessian = nullptr) const;
  // The first t in [0, ∞) at which x + t δ reaches d = 0 (∞ when it never does); x outside.
  double contactTime(const Eigen::Vector3d& x, const Eigen::Vector3d& delta) const;
};

// plane:nx,ny,nz,d or sphere:x,y,z,r; InputError quoting `option` (what gave the text, e.g. the
// command line's option) and the text otherwise (a zero normal, a radius ≤ 0, a number that is
// not finite).
Obstacle parseObstacle(const std::string& option, const std::string& spec);

// b(d) / κ and its first two derivatives (d1, d2 may be null); +∞ for d ≤ 0, 0 for d ≥ d̂.
double barrierPotential(double d, double layer, double* d1 = nullptr, double* d2 = nullptr);

class ObstacleBarrier {
 public:
  ObstacleBarrier() = default;
  // stiffness: κ_v per vertex (#V).
  ObstacleBarrier(std::vector<Obstacle> obstacles, double layer, Eigen::VectorXd stiffness);

  bool empty() const { return obstacles_.empty(); }
  double layer() const { return layer_; }
  const std::vector<Obstacle>& obstacles() const { return obstacles_; }

  // Σ_v Σ_o b_v(d_o(x_v)) (#V by 3 positions); +∞ when a vertex is inside or on an obstacle.
  double energy(const Positions& x) const;
  // Adds the barrier at x to `e`, an evaluation over `assembly`'s free unknowns: its value, its
  // gradient and, when e.values is filled, its Hessian (each vertex's 3 × 3 block, on the entries
  // of the pattern's free coordinates; `semidefinite` drops the sphere's b' ∇²d).
  void add(const HessianAssembly& assembly, const Positions& x, HessianEvaluation& e,
           bool semidefinite) const;
  // The largest α ≤ 1 such that x + α' dx stays outside every obstacle for α' ≤ α, with margin:
  // min(1, 0.9 × the first contact time over the vertices).
  double stepBound(const Positions& x, const Positions& dx) const;
  // Per vertex v (#V): the largest α_v ≤ 1 such that x_v + α' dx_v stays outside every obstacle
  // for α' ≤ α_v, with the same margin (stepBound is their minimum).
  Eigen::VectorXd vertexStepBounds(const Positions& x, const Positions& dx) const;
  // Adds the barrier's gradient at x to `gradient` (#V by 3), every vertex.
  void addGradient(const Positions& x, Positions& gradient) const;
  // Before a time step at positions x with vertex velocities `velocity` (#V by 3): the adaptive
  // stiffness above, with the lumped masses `mass` (#V), the raises inside the layer adding at
  // most `budget` to the barrier energy (in vertex order; the last one raised partly). Returns
  // the energy they added, B(x; κ_new) − B(x; κ_old).
  double adapt(const Positions& x, const Positions& velocity, const Eigen::VectorXd& mass,
               double budget = std::numeric_limits<double>::infinity());
  // Back to the rule's stiffness κ̄ (the start of a run).
  void resetStiffness() { stiffness_ = ruleStiffness_; }
  double stiffness(Eigen::Index v) const { return stiffness_[v]; }
  const Eigen::VectorXd& stiffness() const { return stiffness_; }
  // κ_v per vertex as a checkpoint kept them (#V; InputError otherwise).
  void setStiffness(const Eigen::VectorXd& stiffness);
  // InputError naming the first vertex of `what` (e.g. "the start") inside or on an obstacle.
  void requireOutside(const Positions& x, const std::string& what) const;
  // The smallest signed distance over vertices and obstacles, and where.
  double smallestDistance(const Positions& x, int* vertex = nullptr) const;

 private:
  // b_v(d_o(x_v)), its gradient and (when asked) its Hessian in x_v.
  double vertexBarrier(const Obstacle& o, Eigen::Index v, const Positions& x,
                       Eigen::Vector3d& gradient, Eigen::Matrix3d* hessian,
                       bool semidefinite) const;

  std::vector<Obstacle> obstacles_;
  double layer_ = 0.0;
  Eigen::VectorXd stiffness_;      // κ_v now
  Eigen::VectorXd ruleStiffness_;  // κ̄_v, as constructed
};

// What the adaptive stiffness rule above knows of one vertex's barriers at the start of a step:
// its smallest distance (∞ without any); m w², twice the kinetic energy of its largest approach,
// over all of them and over those within 2 d̂ (m_v w² against an obstacle; a pair's reduced mass
// in self-contact, self_contact.h); and Σ b/κ over them, its barrier energy per unit of κ_v.
struct VertexApproach {
  double closest = std::numeric_limits<double>::infinity();
  double impact = 0.0, nearImpact = 0.0, unitBarrier = 0.0;
};
// κ_v's next value by the adaptive stiffness rule above, from its `stiffness` now, the rule's
// `ruleStiffness` κ̄_v and its `approach`, in a layer d̂ = `layer`; a raise inside the layer adds its
// energy to `spent`, and stops where `spent` would pass `budget`.
double adaptedStiffness(double stiffness, double ruleStiffness, const VertexApproach& approach,
                        double layer, double budget, double& spent);

// The free index of each vertex coordinate 3v + c of `assembly` (3 #V entries; −1 when fixed).
std::vector<int> vertexUnknownIndex(const HessianAssembly& assembly, Eigen::Index vertexCount);
// Adds vertex v's gradient (3) and, when e.values is filled, its 3 × 3 Hessian block to `e`, on
// the entries of its free coordinates (`index`: vertexUnknownIndex).
void addVertexBlock(const HessianAssembly& assembly, const std::vector<int>& index, Eigen::Index v,
                    const Eigen::Vector3d& gradient, const Eigen::Matrix3d& hessian,
                    HessianEvaluation& e);
// Adds the gradient (12) and, when e.values is filled, the Hessian (12 × 12) of a term on four
// vertices `v` (coordinates 3i .. 3i + 2 are v[i]'s; −1, or a vertex whose coordinates `index`
// holds as −1, is no unknown and skipped) to `e`: the blocks between two of its vertices where
// the pattern couples them all, else only each vertex's diagonal block (a principal part: a
// semidefinite Hessian stays semidefinite, still a descent model).
void addFourVertexBlock(const HessianAssembly& assembly, const std::vector<int>& index,
                        const std::array<int, 4>& v, const Eigen::Matrix<double, 12, 1>& gradient,
                        const Eigen::Matrix<double, 12, 12>& hessian, HessianEvaluation& e);

// The barrier of the stated rule for `obstacles` on a mesh with rest state `rest`: d̂ = ¼ the mean
// rest edge length, κ_v = m_v max(|g|, 1) / d̂ with the lumped masses `mass` (#V).
ObstacleBarrier makeObstacleBarrier(std::vector<Obstacle> obstacles,
                                    const modeling::RestState& rest, const Eigen::VectorXd& mass,
                                    const Eigen::Vector3d& gravity);

}  // namespace flexure::optimize
