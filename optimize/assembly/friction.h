// Lagged smoothed Coulomb friction at the contacts of the shell (Li et al. 2020, "Incremental
// Potential Contact", ACM TOG 39(4), §5 "Friction"): with the analytic obstacles (obstacles.h), and
// between the pairs of the collision mesh — shell against shell, shell against mesh obstacle
// (self_contact.h).
//
// A contact is found at the time step's start x_n and lagged over the step (fixed at x_n):
//   λ ≥ 0, its barrier's normal force there (−κ b'(d), times the edge–edge mollifier m),
//   T = [t₁ t₂], an orthonormal basis of the plane perpendicular to the contact normal n (the
//     direction between the two closest points: the obstacle's ∇d, or the pair's),
//   r(x) = Σ_i w_i (x_{v_i} − x_{n,v_i}) + r₀, the motion over the step of one closest point
//     relative to the other: w_i the closest points' coordinates on the contact's (up to four)
//     shell vertices — +1 for a vertex against an obstacle; (1, −β₀, −β₁, −β₂) for a vertex and a
//     face's closest point β; (1 − γ_a, γ_a, −(1 − γ_b), −γ_b) for two edges — and r₀ the known
//     motion of its obstacle side (a moving mesh obstacle's), negated.
// The tangential displacement is u = Tᵀ r(x), y = |u|, and the friction potential (§5.1, eq. 15)
//   D(x) = μ λ f₀(y),
// with IPC's mollifier on the slip length ε = ε_v h (ε_v a slip speed: below it friction grows
// smoothly from 0 instead of jumping to μλ; §5.1, eq. 14)
//   f₀(y) = −y³/(3ε²) + y²/ε + ε/3,   f₁(y) = f₀′(y) = 2y/ε − y²/ε²   for y < ε,
//   f₀(y) = y,                         f₁(y) = 1                      for y ≥ ε
// (f₀ C² at ε, f₁(0) = 0). Its gradient and Hessian in u,
//   ∇_u D  = μ λ (f₁(y)/y) u,
//   ∇²_u D = μ λ [ (f₁(y)/y) I₂ + ((f₁′(y) y − f₁(y)) / y³) u uᵀ ],
// where f₁(y)/y = 2/ε − y/ε² and (f₁′ y − f₁)/y³ = −1/(ε² y) for y < ε (so the rank-one part is
// −(u uᵀ/y)/ε², → 0 as y → 0), and f₁(y)/y = 1/y, (f₁′ y − f₁)/y³ = −1/y³ for y ≥ ε; in the
// vertices by the chain rule, ∇_{x_{v_i}} D = w_i T ∇_u D and the blocks
// ∇²_{x_{v_i} x_{v_j}} D = w_i w_j T ∇²_u D Tᵀ. The 2 × 2 bracket's eigenvalues are f₁(y)/y across
// u and f₁′(y) along it, both ≥ 0 (f₁′ = 2/ε − 2y/ε² on y < ε, 0 beyond), so the Hessian, a
// congruence of it, is already positive semidefinite: IPC's projection changes nothing.
//
// The work against friction over a step ending at x is ∇D(x)·(x − x_n) = ∇_u D · Tᵀ(r − r₀), per
// contact μ λ f₁(y) y ≥ 0 when its obstacle side is static: the time stepper counts it as
// dissipation in the energy balance.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "optimize/assembly/hessian_assembly.h"
#include "optimize/assembly/obstacles.h"

namespace flexure::optimize {

// f₀(y) on the slip length ε (above), and f₁ = f₀′ when asked.
double frictionMollifier(double y, double slip, double* derivative = nullptr);

// An orthonormal basis (3 × 2) of the plane perpendicular to the unit vector n.
Eigen::Matrix<double, 3, 2> tangentBasis(const Eigen::Vector3d& n);

// One lagged contact (above): r(x) = Σ_i w_i (x_{v_i} − x_{n,v_i}) + r₀ over its shell vertices.
struct FrictionContact {
  std::array<int, 4> vertices{-1, -1, -1, -1};        // v_i (−1: unused)
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();  // w_i
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();   // r₀
  double normalForce = 0.0;                           // λ
  Eigen::Matrix<double, 3, 2> basis;                  // T
};

// The contacts of the free vertices (`held` #V: the pinned ones, left out) with the analytic
// obstacles of `barrier` at the step's start `start` (#V by 3): each vertex within the layer, its
// weight 1, its normal the obstacle's ∇d.
std::vector<FrictionContact> obstacleFrictionContacts(const ObstacleBarrier& barrier,
                                                      const Positions& start,
                                                      const std::vector<bool>& held);

class Friction {
 public:
  Friction() = default;
  // The friction of `contacts` found at the step's start `start` (#V by 3), with coefficient μ =
  // `coefficient` ≥ 0 and slip length ε = `slip` > 0; none when μ = 0.
  Friction(std::vector<FrictionContact> contacts, const Positions& start, double coefficient,
           double slip);

  bool empty() const { return contacts_.empty(); }
  int contactCount() const { return static_cast<int>(contacts_.size()); }

  // D(x) (#V by 3 positions).
  double energy(const Positions& x) const;
  // Adds D at x to `e`, an evaluation over `assembly`'s free unknowns: its value, its gradient
  // and, when e.values is filled, its Hessian (a contact's blocks between two of its vertices
  // where the pattern couples them, else its diagonal blocks: a principal part, still
  // semidefinite).
  void add(const HessianAssembly& assembly, const Positions& x, HessianEvaluation& e) const;
  // Adds ∇D(x) to `gradient` (#V by 3).
  void addGradient(const Positions& x, Positions& gradient) const;
  // The work against friction of the motion from the step's start to x: ∇D(x)·(x − x_n).
  double work(const Positions& x) const;

 private:
  // u = Tᵀ r(x) of a contact.
  Eigen::Vector2d tangential(const FrictionContact& c, const Positions& x) const;
  // μ λ f₀(y) of one contact at x, its gradient in u and (when asked) its Hessian in u.
  double contactFriction(const FrictionContact& c, const Eigen::Vector2d& u,
                         Eigen::Vector2d& gradient, Eigen::Matrix2d* hessian) const;

  std::vector<FrictionContact> contacts_;
  Positions start_;  // x_n
  double coefficient_ = 0.0, slip_ = 1.0;
};

}  // namespace flexure::optimize
