// Lagged smoothed Coulomb friction between the vertices and the obstacles (obstacles.h), after Li
// et al. 2020, "Incremental Potential Contact", ACM TOG 39(4), §5 "Friction".
//
// For each vertex v and obstacle o with d = d_o(x_v) < d̂ at the time step's start x_n (the
// contacts), lagged over the step (fixed at x_n):
//   λ = −κ_v b'(d) ≥ 0, the barrier's normal force (obstacles.h's b, its stiffness κ_v at x_n),
//   T = [t₁ t₂], an orthonormal basis of the plane tangent to the obstacle at the vertex's closest
//   point (normal n = ∇d at x_n: the plane's n̂, or the sphere's (x_n − c)/|x_n − c|).
// The relative tangential displacement over the step is u = Tᵀ (x − x_n) (the obstacles are
// static), y = |u|, and the friction potential (§5.1, eq. 15)
//   D(x) = μ λ f₀(y),
// with IPC's mollifier on the slip length ε = ε_v h (ε_v a slip speed: below it friction grows
// smoothly from 0 instead of jumping to μλ; §5.1, eq. 14)
//   f₀(y) = −y³/(3ε²) + y²/ε + ε/3,   f₁(y) = f₀′(y) = 2y/ε − y²/ε²   for y < ε,
//   f₀(y) = y,                         f₁(y) = 1                      for y ≥ ε
// (f₀ C² at ε, f₁(0) = 0). Its gradient and Hessian in x_v:
//   ∇D  = μ λ T (f₁(y)/y) u,
//   ∇²D = μ λ T [ (f₁(y)/y) I₂ + ((f₁′(y) y − f₁(y)) / y³) u uᵀ ] Tᵀ,
// where f₁(y)/y = 2/ε − y/ε² and (f₁′ y − f₁)/y³ = −1/(ε² y) for y < ε (so the rank-one part is
// −(u uᵀ/y)/ε², → 0 as y → 0), and f₁(y)/y = 1/y, (f₁′ y − f₁)/y³ = −1/y³ for y ≥ ε. The 2 × 2
// bracket's eigenvalues are f₁(y)/y across u and f₁′(y) along it, both ≥ 0 (f₁′ = 2/ε − 2y/ε² on
// y < ε, 0 beyond): the exact Hessian is already positive semidefinite, IPC's projection changes
// nothing.
//
// The work against friction over a step ending at x is ∇D(x)·(x − x_n) = μ λ f₁(y) y ≥ 0 per
// contact: the time stepper counts it as dissipation in the energy balance.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "optimize/assembly/hessian_assembly.h"
#include "optimize/assembly/obstacles.h"

namespace flexure::optimize {

// f₀(y) on the slip length ε (above), and f₁ = f₀′ when asked.
double frictionMollifier(double y, double slip, double* derivative = nullptr);

// An orthonormal basis (3 × 2) of the plane perpendicular to the unit vector n.
Eigen::Matrix<double, 3, 2> tangentBasis(const Eigen::Vector3d& n);

class ObstacleFriction {
 public:
  ObstacleFriction() = default;
  // The contacts of the free vertices (`held` #V: the pinned ones, left out) at the step's start
  // `start` (#V by 3), with friction coefficient μ = `coefficient` ≥ 0 and slip length ε =
  // `slip` > 0; none when μ = 0.
  ObstacleFriction(const ObstacleBarrier& barrier, const Positions& start,
                   const std::vector<bool>& held, double coefficient, double slip);

  bool empty() const { return contacts_.empty(); }
  int contactCount() const { return static_cast<int>(contacts_.size()); }

  // D(x) (#V by 3 positions).
  double energy(const Positions& x) const;
  // Adds D at x to `e`, an evaluation over `assembly`'s free unknowns: its value, its gradient
  // and, when e.values is filled, its Hessian (each contact's 3 × 3 block on its vertex).
  void add(const HessianAssembly& assembly, const Positions& x, HessianEvaluation& e) const;
  // Adds ∇D(x) to `gradient` (#V by 3).
  void addGradient(const Positions& x, Positions& gradient) const;
  // The work against friction of the motion from the step's start to x: ∇D(x)·(x − x_n) ≥ 0.
  double work(const Positions& x) const;

 private:
  struct Contact {
    Eigen::Index vertex = 0;
    double normalForce = 0.0;           // λ
    Eigen::Matrix<double, 3, 2> basis;  // T
  };
  // μ λ f₀(y) of one contact at x, its gradient and (when asked) its Hessian in x_v.
  double contactFriction(const Contact& c, const Positions& x, Eigen::Vector3d& gradient,
                         Eigen::Matrix3d* hessian) const;

  std::vector<Contact> contacts_;
  Positions start_;  // x_n
  double coefficient_ = 0.0, slip_ = 1.0;
};

}  // namespace flexure::optimize
