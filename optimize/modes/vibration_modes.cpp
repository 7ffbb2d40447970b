#include "optimize/modes/vibration_modes.h"

#include <Spectra/SymEigsShiftSolver.h>
#include <Eigen/QR>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>

#include "curvature/energy_registry.h"
#include "curvature/midedge_boundary.h"
#include "modeling/errors.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/linear/cholesky_factor.h"
#include "optimize/linear/linear_algebra_threads.h"

namespace flexure::optimize {

namespace {

using Clock = std::chrono::steady_clock;
using Sparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The dimension of the infinitesimal rigid motions the unknowns can express and the fixed
// vertices leave free. xyz: translations t and rotations ω × x (6). Height mode (a flat plate,
// checkModesRest): w = a + b x + c y (a z translation and the two tilts).
int rigidMotionCount(const Positions& rest, const std::vector<bool>& fixed, DofMode dof) {
  const bool xyz = dof == DofMode::Xyz;
  const int dimension = xyz ? 6 : 3;
  std::vector<int> held;
  for (int v = 0; v < rest.rows(); ++v)
    if (fixed[v]) held.push_back(v);
  if (held.empty()) return dimension;
  const int rowsPerVertex = xyz ? 3 : 1;
  Eigen::MatrixXd constraints(rowsPerVertex * held.size(), dimension);
  for (size_t k = 0; k < held.size(); ++k) {
    const Eigen::Vector3d x = rest.row(held[k]).transpose();
    if (!xyz) {
      const double row[3] = {1.0, x.x(), x.y()};
      for (int j = 0; j < dimension; ++j) constraints(k, j) = row[j];
      continue;
    }
    // velocity = t + ω × x = [I | −[x]×] (t, ω)
    Eigen::Matrix3d cross;
    cross << 0.0, -x.z(), x.y(), x.z(), 0.0, -x.x(), -x.y(), x.x(), 0.0;
    constraints.block<3, 3>(3 * k, 0).setIdentity();
    constraints.block<3, 3>(3 * k, 3) = -cross;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(constraints);
  qr.setThreshold(1e-10);
  return dimension - static_cast<int>(qr.rank());
}

// (C − σ)⁻¹ x = M^{1/2} (S − σM)⁻¹ M^{1/2} x on the massive unknowns, through the factor of the
// whole K − σM with zero right-hand side on the massless rows (the header's derivation).
class ShiftInvertOperator {
 public:
  using Scalar = double;
  ShiftInvertOperator(const CholeskyFactor& factor, const std::vector<int>& massive,
                      const Eigen::VectorXd& rootMass, int size, double shift)
      : factor_(factor), massive_(massive), rootMass_(rootMass), size_(size), shift_(shift) {}
  Eigen::Index rows() const { return static_cast<Eigen::Index>(massive_.size()); }
  Eigen::Index cols() const { return rows(); }
  void set_shift(double sigma) {
    if (sigma != shift_) throw std::logic_error("ShiftInvertOperator: factored for another shift");
  }
  void perform_op(const double* in, double* out) const {
    Eigen::VectorXd b = Eigen::VectorXd::Zero(size_);
    for (size_t j = 0; j < massive_.size(); ++j) b[massive_[j]] = rootMass_[j] * in[j];
    const Eigen::VectorXd y = factor_.solve(b);
    for (size_t j = 0; j < massive_.size(); ++j) out[j] = rootMass_[j] * y[massive_[j]];
    ++operations_;
  }
  int operations() const { return operations_; }

 private:
  const CholeskyFactor& factor_;
  const std::vector<int>& massive_;
  const Eigen::VectorXd& rootMass_;
  int size_;
  double shift_;
  mutable int operations_ = 0;
};

// The held vertices' count, the rigid modes, L, D = 2 k_B and the shift σ.
void setSupportAndScales(ModesResult& result, const Positions& rest, const std::vector<bool>& fixed,
                         const ModesOptions& o) {
  result.fixedVertices = static_cast<int>(std::count(fixed.begin(), fixed.end(), true));
  result.rigidModes = rigidMotionCount(rest, fixed, o.dof);
  const Eigen::Vector3d extent = rest.colwise().maxCoeff() - rest.colwise().minCoeff();
  result.length = o.length > 0.0 ? o.length : extent.maxCoeff();
  result.flexuralRigidity = 2.0 * o.bendingStiffness;
  // λ² = 1: far below every flexible mode (the first of a free square plate has λ ≈ 13), above
  // the rigid ones' ω² = 0, so K − σM is positive definite.
  result.shift = -result.flexuralRigidity / (o.density * std::pow(result.length, 4));
}

// The unknowns: free vertex coordinates, then the ξ (all free but the clamped boundary ones
// of Clamp::Rings, which stay at rest with their faces).
std::vector<bool> freeUnknowns(const std::vector<bool>& fixed,
                               const std::vector<bool>& boundaryEdge, int xiCount,
                               const ModesOptions& o) {
  const bool clampRings = o.support == Support::Clamped && o.clamp == Clamp::Rings;
  std::vector<bool> heldEdge(xiCount, false);
  for (int e = 0; e < xiCount; ++e) heldEdge[e] = clampRings && boundaryEdge[e];
  return freeUnknownMask(fixed, heldEdge, o.dof);
}

// K = ∇²E at rest = JᵀJ (every residual vanishes there), both triangles.
Sparse stiffnessAtRest(const HessianAssembly& assembly, const Positions& rest,
                       const Eigen::VectorXd& restXi) {
  const int n = assembly.size();
  const HessianEvaluation at = assembly.evaluate(rest, restXi, HessianProjection::Exact, nullptr,
                                                 curvature::SecondDerivatives::GaussNewton);
  const Eigen::Map<const Sparse> upper(n, n, static_cast<int>(at.values.size()),
                                       assembly.columnStart().data(), assembly.rowIndex().data(),
                                       at.values.data());
  return Sparse(upper.selfadjointView<Eigen::Upper>());
}

// The reduced index of each assembly unknown, −1 for the boundary ξ a normals clamp constrains.
std::vector<int> reducedIndices(const std::vector<int>& freeUnknowns, bool clampNormals,
                                const std::vector<bool>& boundaryEdge, int vertexCount) {
  const int n = static_cast<int>(freeUnknowns.size());
  std::vector<int> reducedIndex(n, -1);
  int reduced = 0;
  for (int k = 0; k < n; ++k) {
    const int unknown = freeUnknowns[k];
    const bool constrained =
        clampNormals && unknown >= 3 * vertexCount && boundaryEdge[unknown - 3 * vertexCount];
    if (!constrained) reducedIndex[k] = reduced++;
  }
  return reducedIndex;
}

// Clamp::Normals: ξ_e of a boundary edge = Σ_c g_{e,c} δ_{o,c}, o the boundary face's vertex
// opposite e (its other two are held), g from the linearized clamp probed with a unit move of
// coordinate c at every free vertex — each boundary ξ sees one free vertex, so one probe per
// coordinate separates them. P maps the reduced unknowns to the assembly's.
Sparse normalsClampMap(const modeling::Stencils& stencils, const Positions& rest,
                       const std::vector<int>& freeUnknowns, const std::vector<bool>& free,
                       const std::vector<bool>& boundaryEdge, const std::vector<int>& reducedIndex,
                       int reduced) {
  const int vertexCount = stencils.vertexCount();
  const int n = static_cast<int>(freeUnknowns.size());
  std::vector<int> assemblyIndex(free.size(), -1);
  for (int k = 0; k < n; ++k) assemblyIndex[freeUnknowns[k]] = k;
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < n; ++k)
    if (reducedIndex[k] >= 0) entries.emplace_back(k, reducedIndex[k], 1.0);
  const modeling::PolynomialSurface flat = modeling::PolynomialSurface::quadratic(0, 0, 0);
  for (int c = 0; c < 3; ++c) {
    Positions probe = Positions::Zero(vertexCount, 3);
    bool any = false;
    for (int v = 0; v < vertexCount; ++v)
      if (free[3 * v + c]) probe(v, c) = 1.0, any = true;
    if (!any) continue;
    const Eigen::VectorXd g = curvature::linearizedClampedBoundaryXi(stencils, rest, probe, flat);
    for (int f = 0; f < stencils.faceCount(); ++f) {
      for (int i = 0; i < 3; ++i) {
        const int e = stencils.faceEdges(f, i), o3 = 3 * stencils.faces(f, i) + c;
        if (!boundaryEdge[e] || assemblyIndex[o3] < 0 || g[e] == 0.0) continue;
        entries.emplace_back(assemblyIndex[3 * vertexCount + e], reducedIndex[assemblyIndex[o3]],
                             g[e]);
      }
    }
  }
  Sparse p(n, reduced);
  p.setFromTriplets(entries.begin(), entries.end());
  return p;
}

struct ReducedMasses {
  Eigen::VectorXd mass;               // per reduced unknown: m_v on a vertex coordinate, 0 on ξ
  std::vector<int> massive;           // the reduced unknowns with mass, ascending
  std::vector<int> unknownOfReduced;  // the assembly's unknown of each reduced one
};

ReducedMasses reducedMasses(const Eigen::VectorXd& vertexMass, const std::vector<int>& freeUnknowns,
                            const std::vector<int>& reducedIndex, int reduced, int vertexCount) {
  ReducedMasses masses;
  masses.mass = Eigen::VectorXd::Zero(reduced);
  masses.unknownOfReduced.resize(reduced);
  for (size_t k = 0; k < reducedIndex.size(); ++k) {
    if (reducedIndex[k] < 0) continue;
    const int unknown = freeUnknowns[k];
    masses.unknownOfReduced[reducedIndex[k]] = unknown;
    if (unknown < 3 * vertexCount) {
      masses.mass[reducedIndex[k]] = vertexMass[unknown / 3];
      masses.massive.push_back(reducedIndex[k]);
    }
  }
  return masses;
}

void checkModeCount(int count, int wanted, const ModesResult& result) {
  if (wanted < result.massUnknowns) return;
  throw InputError("ModesOptions.count " + std::to_string(count) + ": the problem has only " +
                   std::to_string(result.massUnknowns) + " vertex unknowns (" +
                   std::to_string(result.rigidModes) +
                   (result.rigidModes == 1 ? " rigid mode" : " rigid modes") +
                   "); ask for fewer modes or refine the mesh");
}

// The factor of K − σM; called under SingleThreadedLinearAlgebra.
std::unique_ptr<CholeskyFactor> factorShifted(const Sparse& stiffness, const Eigen::VectorXd& mass,
                                              double shift) {
  const int reduced = static_cast<int>(stiffness.rows());
  Sparse shifted = stiffness;
  for (int k = 0; k < reduced; ++k) shifted.coeffRef(k, k) -= shift * mass[k];
  // The upper triangle of K − σM, supernodal, on AMD. Measured at n = 256 (one run each, a loaded
  // machine): midedge's factor 4.5 s on AMD against 7.3 on METIS, 7.8 on CHOLMOD's nested
  // dissection and 6.3 on CHOLMOD's default choice; hinge and cotan within 10 % of each other on
  // all four.
  shifted.makeCompressed();
  CholeskyOptions choleskyOptions;
  choleskyOptions.matrix = CholeskyMatrix::SymmetricUpper;
  choleskyOptions.cholmodWarnings = false;
  auto factor = std::make_unique<CholeskyFactor>(
      reduced, std::vector<int>(shifted.outerIndexPtr(), shifted.outerIndexPtr() + reduced + 1),
      std::vector<int>(shifted.innerIndexPtr(), shifted.innerIndexPtr() + shifted.nonZeros()),
      std::vector<int>{}, choleskyOptions);
  if (!factor->factor(shifted.valuePtr())) {
    throw NumericalError(
        "K - sigma M is not positive definite: the energy's Hessian at rest has an eigenvalue "
        "below the shift (a rest state that is not a minimum?)");
  }
  return factor;
}

struct Eigenpairs {
  Eigen::VectorXd values;   // ω², in Spectra's order
  Eigen::MatrixXd vectors;  // u = M^{1/2} v on the massive unknowns, one column each
};

// The smallest `pairs` eigenpairs of C among its m; the restarts are added to `restarts`.
Eigenpairs lanczos(ShiftInvertOperator& op, int pairs, int m, double shift, int& restarts) {
  const int ncv = std::min(m, std::max(2 * pairs + 1, pairs + 20));
  Spectra::SymEigsShiftSolver<ShiftInvertOperator> eigs(op, pairs, ncv, shift);
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-12, Spectra::SortRule::SmallestAlge);
  if (eigs.info() != Spectra::CompInfo::Successful) {
    throw NumericalError("the Lanczos iteration did not converge to " + std::to_string(pairs) +
                         " eigenpairs in 1000 restarts");
  }
  restarts += static_cast<int>(eigs.num_iterations());
  return {eigs.eigenvalues(), eigs.eigenvectors()};
}

// The eigenvalues of (S, M) below τ, by Sylvester's law of inertia: the negative pivots of an
// LDLᵀ of K − τM (the massless ξ block of K is positive definite and adds none); `fallback` when
// that factorization fails.
int eigenvaluesBelow(const Sparse& stiffness, const Eigen::VectorXd& mass, double tau,
                     int fallback) {
  Sparse below = stiffness;
  for (int k = 0; k < below.rows(); ++k) below.coeffRef(k, k) -= tau * mass[k];
  Eigen::SimplicialLDLT<Sparse, Eigen::Upper> ldlt(below);
  if (ldlt.info() != Eigen::Success) return fallback;
  return static_cast<int>((ldlt.vectorD().array() < 0.0).count());
}

// The smallest `wanted` eigenpairs, then as many more as there are zero modes beyond the rigid
// ones: they take the place of flexible modes, and Lanczos may return fewer copies of a repeated
// zero eigenvalue than there are, so they are counted exactly. Sets result.zeroModes and
// result.restarts.
Eigenpairs smallestEigenpairs(ShiftInvertOperator& op, const Sparse& stiffness,
                              const Eigen::VectorXd& mass, int count, int wanted,
                              double zeroOmegaSquared, ModesResult& result) {
  const int m = result.massUnknowns;
  Eigenpairs pairs = lanczos(op, wanted, m, result.shift, result.restarts);
  const int zerosFound = static_cast<int>((pairs.values.array() < zeroOmegaSquared).count());
  result.zeroModes =
      zerosFound > 0 ? eigenvaluesBelow(stiffness, mass, zeroOmegaSquared, zerosFound) : 0;
  if (count + result.zeroModes > wanted && wanted < m - 1) {
    try {
      pairs =
          lanczos(op, std::min(m - 1, count + result.zeroModes), m, result.shift, result.restarts);
    } catch (const NumericalError&) {  // a long run of equal eigenvalues: keep the first answer
    }
  }
  return pairs;
}

std::vector<int> ascendingOrder(const Eigen::VectorXd& values) {
  std::vector<int> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return values[a] < values[b]; });
  return order;
}

double infinityNorm(const Sparse& matrix) {  // the largest absolute row sum
  Eigen::VectorXd rows = Eigen::VectorXd::Zero(matrix.rows());
  for (int k = 0; k < matrix.outerSize(); ++k)
    for (Sparse::InnerIterator it(matrix, k); it; ++it) rows[it.row()] += std::abs(it.value());
  return rows.maxCoeff();
}

// ω², ω and λ = ω L² √(ρh / D) of an eigenvalue.
VibrationMode modeFrequency(double omegaSquared, double lambdaScale) {
  VibrationMode mode;
  mode.omegaSquared = omegaSquared;
  mode.omega = std::sqrt(std::max(mode.omegaSquared, 0.0));
  mode.lambda = mode.omega * lambdaScale;
  mode.zero = mode.lambda < kZeroModeLambda;
  return mode;
}

struct ModeRecovery {
  const CholeskyFactor& factor;  // of K − σM
  const Sparse& stiffness;
  const ReducedMasses& masses;
  const Eigen::VectorXd& rootMass;  // √m of each massive unknown
  double stiffnessNorm;             // ‖K‖∞
  double shift;
  int vertexCount;
};

// The whole eigenvector, ξ included, from u = M^{1/2} v on the massive unknowns:
// (ω² − σ) (K − σM)⁻¹ M v solves the ξ rows exactly and returns v where v is an eigenvector.
// Sets the M-normalized shape and the residual.
void recoverShape(VibrationMode& mode, const ModeRecovery& r, const Eigen::VectorXd& u) {
  const std::vector<int>& massive = r.masses.massive;
  const Eigen::VectorXd& mass = r.masses.mass;
  const Eigen::Index reduced = mass.size();
  Eigen::VectorXd b = Eigen::VectorXd::Zero(reduced);
  for (size_t j = 0; j < massive.size(); ++j)
    b[massive[j]] = r.rootMass[j] * u[j];  // M (M^{-1/2} u)
  Eigen::VectorXd y = (mode.omegaSquared - r.shift) * r.factor.solve(b);
  double norm = 0.0;
  for (int j : massive) norm += mass[j] * y[j] * y[j];
  y /= std::sqrt(norm);
  const Eigen::VectorXd ky = r.stiffness * y;
  const Eigen::VectorXd residual = ky - mode.omegaSquared * mass.cwiseProduct(y);
  mode.residual = mode.zero ? ky.norm() / (r.stiffnessNorm * y.norm())
                            : residual.norm() / std::max(ky.norm(), 1e-300);
  mode.shape = Positions::Zero(r.vertexCount, 3);
  for (Eigen::Index k = 0; k < reduced; ++k) {
    const int unknown = r.masses.unknownOfReduced[k];
    if (unknown < 3 * r.vertexCount) mode.shape(unknown / 3, unknown % 3) = y[k];
  }
}

// Multiplicities: runs of modes whose λ agree to kDegenerateTolerance; the zero modes are one.
void setMultiplicities(std::vector<VibrationMode>& modes) {
  for (size_t i = 0; i < modes.size();) {
    size_t j = i + 1;
    while (j < modes.size() && (modes[i].zero ? modes[j].zero
                                              : std::abs(modes[j].lambda - modes[j - 1].lambda) <=
                                                    kDegenerateTolerance * modes[j].lambda))
      ++j;
    for (size_t k = i; k < j; ++k) modes[k].multiplicity = static_cast<int>(j - i);
    i = j;
  }
}

// The energies whose edge unknowns give boundary normals a normals clamp can hold: "midedge".
std::string edgeUnknownEnergyNames() {
  return curvature::energyNamesWhere(&curvature::EnergyEntry::hasEdgeUnknowns);
}

}  // namespace

bool restIsFlatPlate(const Positions& rest) {
  const Eigen::Vector3d extent = rest.colwise().maxCoeff() - rest.colwise().minCoeff();
  return extent.z() <= kFlatRestTolerance * extent.maxCoeff();
}

void checkModesRest(const ModesOptions& o, const Positions& rest, bool edgeUnknowns) {
  const bool flat = restIsFlatPlate(rest);
  if (o.dof == DofMode::Height && !flat) {
    const Eigen::Vector3d extent = rest.colwise().maxCoeff() - rest.colwise().minCoeff();
    char range[96];
    std::snprintf(range, sizeof range, "z spans %.3g of a largest side %.3g", extent.z(),
                  extent.maxCoeff());
    throw InputError(
        "ModesOptions.dof height moves the vertices along z only, the transverse motion of a "
        "plate flat in the xy plane; this rest surface is not flat (" +
        std::string(range) +
        "), so its height modes would mean nothing: use ModesOptions.dof xyz with a membrane "
        "(the shell's modes)");
  }
  if (o.clamp != Clamp::Normals || o.support != Support::Clamped) return;
  if (!edgeUnknowns)
    throw InputError("ModesOptions.clamp normals holds the " + edgeUnknownEnergyNames() +
                     " normals: it applies to " + edgeUnknownEnergyNames() + " only");
  if (o.dof != DofMode::Height || !flat)
    throw InputError(
        "ModesOptions.clamp normals holds the boundary normals vertical, which needs a flat plate "
        "in height mode; for a shell (ModesOptions.dof xyz) clamp with ModesOptions.clamp rings "
        "or choose another ModesOptions.support");
}

double participationRatio(const Positions& shape, const Eigen::VectorXd& vertexMass) {
  const Eigen::ArrayXd squared = shape.rowwise().squaredNorm().array();
  const double second = (vertexMass.array() * squared).sum();
  const double fourth = (vertexMass.array() * squared.square()).sum();
  if (!(fourth > 0.0)) return 0.0;
  return second * second / (vertexMass.sum() * fourth);
}

void ModesOptions::validate() const {
  if (count < 1)
    throw InputError("ModesOptions.count " + std::to_string(count) + ": expected at least 1");
  if (!(density > 0.0)) throw InputError("ModesOptions.density: expected a value > 0");
}

ModesSpec modesSpec(const ModesWords& words) {
  ModesSpec spec;
  spec.modes.count = words.count;
  spec.modes.support = parseSupport(words.support);
  spec.modes.mass = modeling::parseMassLumping(words.mass, "ModesOptions.mass");
  spec.modes.density = words.density;
  spec.modes.bendingStiffness = words.bendingStiffness;
  spec.modes.length = words.length;
  spec.modes.dof = parseDofMode(words.dof, "ModesOptions.dof");
  if (!words.clamp.empty()) spec.clamp = parseClamp(words.clamp);
  spec.membrane = words.membrane;
  spec.validate();
  return spec;
}

void ModesSpec::validate() const {
  modes.validate();
  if (clamp && modes.support != Support::Clamped)
    throw InputError("ModesOptions.clamp applies to ModesOptions.support clamped");
  if (modes.dof == DofMode::Height && membrane)
    throw InputError("ProblemOptions.membrane applies to ModesOptions.dof xyz");
  if (modes.dof == DofMode::Xyz && !membrane)
    throw InputError(
        "ModesOptions.dof xyz needs a membrane (ProblemOptions.membrane stvk|springs|conformal)");
}

ModesOptions ModesSpec::forEnergy(const curvature::BendingOptions& bending) const {
  ModesOptions o = modes;
  const curvature::EnergyEntry& entry = curvature::energyEntry(bending.discretization);
  const bool edgeUnknowns = static_cast<bool>(entry.restEdgeUnknowns);
  o.clamp = clamp.value_or(edgeUnknowns ? Clamp::Normals : Clamp::Rings);
  if (o.clamp == Clamp::Normals && !edgeUnknowns && o.support == Support::Clamped)
    throw InputError("ModesOptions.clamp normals holds the " + edgeUnknownEnergyNames() +
                     " normals: " + entry.name +
                     " has none; use ModesOptions.clamp rings or BendingOptions.discretization " +
                     edgeUnknownEnergyNames());
  return o;
}
const char* supportName(Support support) {
  switch (support) {
    case Support::Clamped:
      return "clamped";
    case Support::SimplySupported:
      return "simply-supported";
    case Support::Free:
      return "free";
  }
  return "";
}
const char* clampName(Clamp clamp) {
  return clamp == Clamp::Rings ? "rings" : "normals";
}

Support parseSupport(std::string_view name) {
  for (Support s : {Support::Clamped, Support::SimplySupported, Support::Free})
    if (name == supportName(s)) return s;
  throw InputError("ModesOptions.support " + std::string(name) +
                   ": expected clamped, simply-supported or free");
}

Clamp parseClamp(std::string_view name) {
  for (Clamp c : {Clamp::Rings, Clamp::Normals})
    if (name == clampName(c)) return c;
  throw InputError("ModesOptions.clamp " + std::string(name) + ": expected rings or normals");
}
std::vector<bool> supportFixedVertices(const modeling::Stencils& stencils, Support support,
                                       Clamp clamp, const std::vector<bool>& extra) {
  int rings = 0;
  if (support == Support::SimplySupported) rings = 1;
  if (support == Support::Clamped) rings = clamp == Clamp::Rings ? 2 : 1;
  std::vector<bool> fixed = fixedRings(stencils, rings);
  for (size_t v = 0; v < extra.size(); ++v)
    if (extra[v]) fixed[v] = true;
  return fixed;
}

std::vector<std::pair<NodalPoint, NodalPoint>> nodalEdgeSegments(const modeling::Stencils& stencils,
                                                                 const modeling::RestState& rest,
                                                                 const Positions& shape) {
  const Eigen::MatrixX3d normals = modeling::vertexNormals(rest.positions, stencils.faces);
  Eigen::VectorXd s = (shape.array() * normals.array()).rowwise().sum();
  const double floor = kNodalFloor * s.cwiseAbs().maxCoeff();
  for (double& value : s)
    if (std::abs(value) <= floor) value = 0.0;
  std::vector<std::pair<NodalPoint, NodalPoint>> segments;
  for (int f = 0; f < stencils.faceCount(); ++f) {
    // Points of the zero set on the face's edges: a crossing inside each edge whose ends have
    // opposite signs, and a vertex where s = 0 (a held one) when it is the face's only such vertex.
    std::vector<NodalPoint> points;
    int zeros = 0;
    for (int i = 0; i < 3; ++i) zeros += s[stencils.faces(f, i)] == 0.0;
    if (zeros > 1) continue;
    for (int i = 0; i < 3; ++i) {
      const int v = stencils.faces(f, i);
      const int a = stencils.faces(f, (i + 1) % 3), b = stencils.faces(f, (i + 2) % 3);
      if (s[v] == 0.0) points.push_back({v, v, 0.0});
      if (s[a] * s[b] < 0.0) points.push_back({a, b, s[a] / (s[a] - s[b])});
    }
    if (points.size() == 2) segments.emplace_back(points[0], points[1]);
  }
  // A line along an edge between two zeros: where s changes sign across it (the two opposite
  // vertices differ in sign), which the held boundary, zero on both sides, never does.
  for (int h = 0; h < stencils.hingeCount(); ++h) {
    const int i = stencils.hinges(h, 0), j = stencils.hinges(h, 1);
    const int k = stencils.hinges(h, 2), l = stencils.hinges(h, 3);
    if (s[i] == 0.0 && s[j] == 0.0 && s[k] * s[l] < 0.0)
      segments.emplace_back(NodalPoint{i, i, 0.0}, NodalPoint{j, j, 0.0});
  }
  return segments;
}

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> nodalSegments(
    const modeling::Stencils& stencils, const modeling::RestState& rest, const Positions& shape) {
  auto point = [&](const NodalPoint& p) -> Eigen::Vector3d {
    return ((1.0 - p.t) * rest.positions.row(p.a) + p.t * rest.positions.row(p.b)).transpose();
  };
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
  for (const auto& [p, q] : nodalEdgeSegments(stencils, rest, shape))
    segments.emplace_back(point(p), point(q));
  return segments;
}

ModesResult vibrationModes(const std::vector<const curvature::EnergyTerm*>& terms,
                           const modeling::Stencils& stencils, const modeling::RestState& rest,
                           const Eigen::VectorXd& restXi, const ModesOptions& o) {
  const auto start = Clock::now();
  const int vertexCount = stencils.vertexCount();
  const bool withXi = restXi.size() > 0;
  o.validate();
  checkModesRest(o, rest.positions, withXi);

  ModesResult result;
  const std::vector<bool> fixed = supportFixedVertices(stencils, o.support, o.clamp, o.extraFixed);
  setSupportAndScales(result, rest.positions, fixed, o);

  const std::vector<bool> boundaryEdge =
      withXi ? curvature::boundaryEdges(stencils) : std::vector<bool>();
  const std::vector<bool> free =
      freeUnknowns(fixed, boundaryEdge, static_cast<int>(restXi.size()), o);
  const HessianAssembly assembly(
      terms, free, vertexCount,
      o.dof == DofMode::Height ? curvature::Derivatives::HeightOnly : curvature::Derivatives::All);
  const int n = assembly.size();
  Sparse stiffness = stiffnessAtRest(assembly, rest.positions, restXi);
  const bool clampNormals = o.support == Support::Clamped && o.clamp == Clamp::Normals;
  const std::vector<int> reducedIndex =
      reducedIndices(assembly.freeUnknowns(), clampNormals, boundaryEdge, vertexCount);
  const int reduced =
      n - static_cast<int>(std::count(reducedIndex.begin(), reducedIndex.end(), -1));
  if (reduced < n) {
    const Sparse p = normalsClampMap(stencils, rest.positions, assembly.freeUnknowns(), free,
                                     boundaryEdge, reducedIndex, reduced);
    stiffness = Sparse(p.transpose() * stiffness * p);
  }
  const Eigen::VectorXd vertexMass = modeling::lumpedVertexMasses(rest, o.mass, o.density);
  const ReducedMasses masses =
      reducedMasses(vertexMass, assembly.freeUnknowns(), reducedIndex, reduced, vertexCount);
  result.unknowns = reduced;
  result.massUnknowns = static_cast<int>(masses.massive.size());
  const int wanted = o.count + result.rigidModes;
  checkModeCount(o.count, wanted, result);
  result.assemblySeconds = secondsSince(start);

  const auto factorStart = Clock::now();
  const SingleThreadedLinearAlgebra oneThread;  // the factor and every shift-invert solve
  const std::unique_ptr<CholeskyFactor> factor =
      factorShifted(stiffness, masses.mass, result.shift);
  result.factorSeconds = secondsSince(factorStart);

  const auto eigenStart = Clock::now();
  Eigen::VectorXd rootMass(masses.massive.size());
  for (size_t j = 0; j < masses.massive.size(); ++j)
    rootMass[j] = std::sqrt(masses.mass[masses.massive[j]]);
  ShiftInvertOperator op(*factor, masses.massive, rootMass, reduced, result.shift);
  const double lambdaScale =
      std::pow(result.length, 2) * std::sqrt(o.density / result.flexuralRigidity);
  const double zeroOmegaSquared = std::pow(kZeroModeLambda / lambdaScale, 2);
  const Eigenpairs pairs =
      smallestEigenpairs(op, stiffness, masses.mass, o.count, wanted, zeroOmegaSquared, result);

  const ModeRecovery recovery{*factor,      stiffness,  masses, rootMass, infinityNorm(stiffness),
                              result.shift, vertexCount};
  int flexibleReturned = 0;
  for (int index : ascendingOrder(pairs.values)) {
    VibrationMode mode = modeFrequency(pairs.values[index], lambdaScale);
    if (!mode.zero && flexibleReturned == o.count) break;
    flexibleReturned += !mode.zero;
    recoverShape(mode, recovery, pairs.vectors.col(index));
    mode.participation = participationRatio(mode.shape, vertexMass);
    mode.localized = mode.participation < kLocalizedParticipation;
    for (const auto& [a, b] : nodalSegments(stencils, rest, mode.shape))
      mode.nodalLength += (b - a).norm();
    result.modes.push_back(std::move(mode));
  }
  result.spuriousZeroModes = std::max(0, result.zeroModes - result.rigidModes);
  result.flexibleModes = flexibleReturned;
  setMultiplicities(result.modes);
  result.operations = op.operations();
  result.eigenSeconds = secondsSince(eigenStart);
  result.totalSeconds = secondsSince(start);
  return result;
}

}  // namespace flexure::optimize
