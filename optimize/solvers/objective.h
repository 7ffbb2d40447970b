// An objective for the Newton loop (newton_loop.h): a smooth function of the free unknowns of a
// configuration (x, ξ), with its Hessian pattern over them.
//
// The free unknowns are HessianAssembly's (hessian_assembly.h): coordinate c of vertex v is
// unknown 3v + c, ξ_e is 3 #V + e; the free ones renumbered k = 0 .. n − 1 in that order. A point
// of the loop is the vector y (n) of their values; the fixed unknowns are those of `fixedPart`.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "optimize/assembly/hessian_assembly.h"

namespace flexure::optimize {

// A configuration: positions (#V by 3) and midedge ξ (#E, or empty).
struct Configuration {
  Positions positions;
  Eigen::VectorXd xi;
};

class Objective {
 public:
  // `assembly` outlives the objective; `fixedPart` holds the values of the fixed unknowns.
  Objective(const HessianAssembly& assembly, Configuration fixedPart)
      : assembly_(assembly), fixedPart_(std::move(fixedPart)) {}
  virtual ~Objective() = default;

  const HessianAssembly& assembly() const { return assembly_; }
  int size() const { return assembly_.size(); }
  const Configuration& fixedPart() const { return fixedPart_; }

  // y (n) of a configuration, and the configuration of y (the fixed unknowns from fixedPart).
  Eigen::VectorXd freeValues(const Configuration& at) const;
  Configuration configuration(const Eigen::VectorXd& y) const;
  // Writes y's entries into `at` (its fixed unknowns untouched).
  void place(const Eigen::VectorXd& y, Configuration& at) const;
  // The vertex displacement (#V by 3) of a step δ over the free unknowns (ξ entries dropped).
  Positions displacement(const Eigen::VectorXd& delta) const;

  // The value and gradient at y, with the Hessian on the pattern: `kind` Exact (the objective's
  // own Hessian, e.g. element-projected), GaussNewton (JᵀJ for ∇²E), None (no `values`).
  virtual HessianEvaluation evaluate(const Eigen::VectorXd& y,
                                     curvature::SecondDerivatives kind) = 0;
  // The value the line search compares: +∞ where an element is degenerate or a vertex is inside
  // an obstacle.
  virtual double lineSearchValue(const Eigen::VectorXd& y) = 0;
  // Per vertex, the longest fraction α_v ≤ 1 of the step δ from y that keeps it feasible
  // (outside the obstacles); empty when nothing bounds a step.
  virtual Eigen::VectorXd vertexStepBounds(const Eigen::VectorXd& y,
                                           const Eigen::VectorXd& delta) = 0;
  // The longest feasible fraction of the whole step δ (min_v α_v, 1 when nothing bounds it, unless
  // an objective bounds δ by more than its vertices' bounds, e.g. pairs that must not cross).
  virtual double stepBound(const Eigen::VectorXd& y, const Eigen::VectorXd& delta);
  // The roundoff of a value near `value` at y, under which the line search cannot judge a
  // decrease.
  virtual double roundoff(const Eigen::VectorXd& y, double value) const = 0;
  // Where the objective's Hessian maps every rigid translation τ of the free vertices to W τ for
  // a known diagonal W (nothing held, nothing fixed in space), a step δ solved with such a matrix
  // has τᵀWδ = −τᵀ∇f: it cancels the momentum residual τᵀ∇f. Adds to δ the translations that
  // restore that for a δ that lost it (an L-BFGS step: its update does not keep H τ = W τ);
  // otherwise leaves δ as it is.
  virtual void keepTranslationResidual(const Eigen::VectorXd& /*gradient*/,
                                       Eigen::VectorXd& /*delta*/) const {}

 protected:
  const HessianAssembly& assembly_;
  Configuration fixedPart_;
};

}  // namespace flexure::optimize
