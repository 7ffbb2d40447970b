// An energy term: one discretization (or membrane model) bound to a rest state. Terms are what
// the optimizer assembles; each is a sum over elements of ½ |r_e|², r_e an element's residuals,
// so that Ceres' cost equals the energy of docs/energies.md.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "curvature/element_hessian.h"
#include "curvature/height_only_cost.h"
#include "modeling/mesh.h"

namespace ceres {
class Problem;
}

namespace flexure::curvature {

using modeling::Positions;

// Residuals and their Jacobian in compressed-row form, built by appending element rows. Columns:
// 3v + c for coordinate c of vertex v, then 3 #V + e for the midedge unknown ξ_e.
struct JacobianRows {
  std::vector<int> rowStart{0};  // row k's entries are [rowStart[k], rowStart[k + 1])
  std::vector<int> columns;      // ascending within a row
  std::vector<double> values;
  std::vector<double> residuals;
};

// The rest curvature of a bending term's elements, which a plastic update moves
// (optimize/inelastic/plasticity.h; Gingold et al. 2004, seed 002: the plastic strain is stored
// like the elastic one). Per element — a mesh face — in element order, its shape operator
// S_T = [[a, b], [b, c]] in the face's rest frame (a, b, c): the face energies' own, the hinge's
// the tensor its angles read as on the face (curvature/hinge_face_tensors.h).
class RestCurvatureState {
 public:
  virtual ~RestCurvatureState() = default;
  virtual int elementId(int e) const = 0;  // the mesh face of element e
  // #elements by 3: S_T at positions `x` and edge unknowns `xi`.
  virtual Eigen::MatrixXd elementCurvatures(const Positions& x,
                                            const Eigen::VectorXd& xi) const = 0;
  // #elements by 3: S̄_T, and its replacement.
  virtual Eigen::MatrixXd restCurvatures() const = 0;
  virtual void setRestCurvatures(const Eigen::MatrixXd& rest) = 0;
};

// The rest metric of a membrane's faces, which a membrane plastic update moves (seed 002: the
// membrane's plastic strain is a change of the squared rest edge lengths). Per face, in element
// order, the rest strain P_T = [[a, b], [b, c]] (a, b, c) in the face's rest frame, zero when
// built: the membrane reads the strain ε_T − P_T, ε_T = ½(FᵀF − I) the Green strain, i.e. the
// rest metric Ā_T = I + 2 P_T (ℓ̄² ← ℓ̄² + 2 ūᵀ P_T ū for a rest edge ū).
class RestMetricState {
 public:
  virtual ~RestMetricState() = default;
  virtual int elementId(int e) const = 0;  // the mesh face of element e
  // #elements by 3: ε_T at positions `x` (#V by 3).
  virtual Eigen::MatrixXd elementStrains(const Positions& x) const = 0;
  // #elements by 3: P_T, and its replacement.
  virtual Eigen::MatrixXd restStrains() const = 0;
  virtual void setRestStrains(const Eigen::MatrixXd& rest) = 0;
  // D̄_T = [ū1 − ū0, ū2 − ū0], element e's rest edges in its rest frame (2 × 2), the frame of
  // ε_T and P_T.
  virtual Eigen::Matrix2d restEdgeMatrix(int e) const = 0;
};

class EnergyTerm {
 public:
  virtual ~EnergyTerm() = default;

  virtual std::string name() const = 0;
  // The mesh element each residual block belongs to ("edge", "face", "vertex"), and how many
  // contribute.
  virtual std::string elementKind() const = 0;
  virtual int elementCount() const = 0;
  // A_cov: the rest area the elements cover (docs/energies.md, C1).
  virtual double coveredArea() const = 0;
  // Whether the term reads one midedge unknown ξ per edge (midedge only).
  virtual bool usesEdgeUnknowns() const { return false; }

  // The faces' rest curvature, when the term has one a plastic update can move (the face
  // shape-operator energies and the hinge); null otherwise.
  virtual RestCurvatureState* restCurvatureState() { return nullptr; }
  // The faces' rest metric, when the term has one a membrane plastic update can move (stvk);
  // null otherwise.
  virtual RestMetricState* restMetricState() { return nullptr; }

  // Sets touched[v] for every vertex an element of this term reads (touched has #V entries).
  virtual void markTouchedVertices(std::vector<bool>& touched) const = 0;

  // E at positions `x` (#V by 3) and edge unknowns `xi` (#E; read only when usesEdgeUnknowns()).
  // Throws NumericalError naming the element when one is degenerate (e.g. a collapsed face).
  virtual double energy(const Positions& x, const Eigen::VectorXd& xi) const = 0;
  // Per element: its energy ½ |r_e|², in element order.
  virtual Eigen::VectorXd elementEnergies(const Positions& x, const Eigen::VectorXd& xi) const = 0;

  // Adds one residual block per element; with Derivatives::HeightOnly (height mode, x and y
  // held by the problem) their Jacobians hold only ∂/∂z and ∂/∂ξ (height_only_cost.h). `positions`
  // is a row-major #V × 3 array whose rows are the vertex parameter blocks; `xi` the #E edge
  // unknowns (one block each; midedge only). Every block the term reads must already be in
  // `problem`.
  virtual void addResidualBlocks(ceres::Problem& problem, double* positions, double* xi,
                                 Derivatives derivatives) const = 0;

  // Appends the residuals and Jacobian rows at (x, ξ) of elements [begin, end), in element order
  // (the order of the residual blocks above); the same autodiff cost functions, evaluated
  // directly. HeightOnly: only the z and ξ columns. Reads only `this` and the arguments, so
  // disjoint ranges may run concurrently. Throws NumericalError naming a degenerate element.
  virtual void appendJacobianRows(const Positions& x, const Eigen::VectorXd& xi, int begin, int end,
                                  Derivatives derivatives, JacobianRows& out) const = 0;

  // Element e's unknowns (element_hessian.h), in the order its Hessian uses.
  virtual void elementUnknowns(int e, Derivatives derivatives, int vertexCount,
                               std::vector<long>& out) const = 0;
  // Hands `sink` the energy, gradient and Hessian (element_hessian.h: exact, or its Gauss–Newton
  // part) at (x, ξ) of each element in [begin, end), in order. Reads only `this` and the
  // arguments, so disjoint ranges may run concurrently. Throws NumericalError naming a
  // degenerate element, InputError naming an element with more than kMaxHessianUnknowns
  // unknowns (exact only).
  virtual void elementHessians(const Positions& x, const Eigen::VectorXd& xi, int begin, int end,
                               Derivatives derivatives, SecondDerivatives kind,
                               ElementHessianSink& sink) const = 0;
};

}  // namespace flexure::curvature
