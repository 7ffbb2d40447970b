#include "optimize/modes/vibration_modes.h"

#include <Spectra/SymEigsShiftSolver.h>
#include <Eigen/CholmodSupport>
#include <Eigen/QR>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "curvature/midedge_boundary.h"
#include "modeling/errors.h"
#include "optimize/linear/linear_algebra_threads.h"
#include "optimize/solvers/hessian_assembly.h"

namespace flexure::optimize {

namespace {

using Clock = std::chrono::steady_clock;
using Sparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

bool restIsFlat(const Positions& rest) {
  return rest.col(2).maxCoeff() == rest.col(2).minCoeff();
}

// The dimension of the infinitesimal rigid motions the unknowns can express and the fixed
// vertices leave free. xyz: translations t and rotations ω × x (6). Height mode on a flat plate:
// w = a + b x + c y (a z translation and the two tilts); on a curved rest only a z translation,
// since a tilt moves a curved surface sideways too.
int rigidMotionCount(const Positions& rest, const std::vector<bool>& fixed, DofMode dof) {
  const bool xyz = dof == DofMode::Xyz;
  const int dimension = xyz ? 6 : (restIsFlat(rest) ? 3 : 1);
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
  ShiftInvertOperator(const Eigen::CholmodSupernodalLLT<Sparse, Eigen::Upper>& factor,
                      const std::vector<int>& massive, const Eigen::VectorXd& rootMass, int size,
                      double shift)
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
  const Eigen::CholmodSupernodalLLT<Sparse, Eigen::Upper>& factor_;
  const std::vector<int>& massive_;
  const Eigen::VectorXd& rootMass_;
  int size_;
  double shift_;
  mutable int operations_ = 0;
};

}  // namespace

Support parseSupport(const std::string& name) {
  if (name == "clamped") return Support::Clamped;
  if (name == "simply-supported") return Support::SimplySupported;
  if (name == "free") return Support::Free;
  throw InputError("--support " + name + ": expected clamped, simply-supported or free");
}
Clamp parseClamp(const std::string& name) {
  if (name == "rings") return Clamp::Rings;
  if (name == "normals") return Clamp::Normals;
  throw InputError("--clamp " + name + ": expected rings or normals");
}
MassLumping parseMassLumping(const std::string& name) {
  if (name == "barycentric") return MassLumping::Barycentric;
  if (name == "voronoi") return MassLumping::Voronoi;
  throw InputError("--mass " + name + ": expected barycentric or voronoi");
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
const char* massLumpingName(MassLumping mass) {
  return mass == MassLumping::Barycentric ? "barycentric" : "voronoi";
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

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> nodalSegments(
    const modeling::Stencils& stencils, const modeling::RestState& rest, const Positions& shape) {
  const Eigen::MatrixX3d normals = modeling::vertexNormals(rest.positions, stencils.faces);
  Eigen::VectorXd s = (shape.array() * normals.array()).rowwise().sum();
  const double floor = kNodalFloor * s.cwiseAbs().maxCoeff();
  for (double& value : s)
    if (std::abs(value) <= floor) value = 0.0;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
  auto point = [&](int v) -> Eigen::Vector3d { return rest.positions.row(v).transpose(); };
  for (int f = 0; f < stencils.faceCount(); ++f) {
    // Points of the zero set on the face's edges: a crossing inside each edge whose ends have
    // opposite signs, and a vertex where s = 0 (a held one) when it is the face's only such vertex.
    std::vector<Eigen::Vector3d> points;
    int zeros = 0;
    for (int i = 0; i < 3; ++i) zeros += s[stencils.faces(f, i)] == 0.0;
    if (zeros > 1) continue;
    for (int i = 0; i < 3; ++i) {
      const int v = stencils.faces(f, i);
      const int a = stencils.faces(f, (i + 1) % 3), b = stencils.faces(f, (i + 2) % 3);
      if (s[v] == 0.0) points.push_back(point(v));
      if (s[a] * s[b] < 0.0) {
        const double t = s[a] / (s[a] - s[b]);
        points.push_back((1.0 - t) * point(a) + t * point(b));
      }
    }
    if (points.size() == 2) segments.emplace_back(points[0], points[1]);
  }
  // A line along an edge between two zeros: where s changes sign across it (the two opposite
  // vertices differ in sign), which the held boundary, zero on both sides, never does.
  for (int h = 0; h < stencils.hingeCount(); ++h) {
    const int i = stencils.hinges(h, 0), j = stencils.hinges(h, 1);
    const int k = stencils.hinges(h, 2), l = stencils.hinges(h, 3);
    if (s[i] == 0.0 && s[j] == 0.0 && s[k] * s[l] < 0.0) segments.emplace_back(point(i), point(j));
  }
  return segments;
}

ModesResult vibrationModes(const std::vector<const curvature::EnergyTerm*>& terms,
                           const modeling::Stencils& stencils, const modeling::RestState& rest,
                           const Eigen::VectorXd& restXi, const ModesOptions& o) {
  const auto start = Clock::now();
  const int vertexCount = stencils.vertexCount();
  const bool withXi = restXi.size() > 0;
  if (o.count < 1) throw InputError("--count " + std::to_string(o.count) + ": expected at least 1");
  if (o.clamp == Clamp::Normals && o.support == Support::Clamped) {
    if (!withXi)
      throw InputError("--clamp normals holds the midedge normals: it applies to midedge only");
    if (o.dof != DofMode::Height || !restIsFlat(rest.positions))
      throw InputError("--clamp normals: needs a flat plate in height mode (use --clamp rings)");
  }
  if (!(o.density > 0.0)) throw InputError("--density: expected a value > 0");

  ModesResult result;
  const std::vector<bool> fixed = supportFixedVertices(stencils, o.support, o.clamp, o.extraFixed);
  result.fixedVertices = static_cast<int>(std::count(fixed.begin(), fixed.end(), true));
  result.rigidModes = rigidMotionCount(rest.positions, fixed, o.dof);
  const Eigen::Vector3d extent =
      rest.positions.colwise().maxCoeff() - rest.positions.colwise().minCoeff();
  result.length = o.length > 0.0 ? o.length : extent.maxCoeff();
  result.flexuralRigidity = 2.0 * o.bendingStiffness;
  // λ² = 1: far below every flexible mode (the first of a free square plate has λ ≈ 13), above
  // the rigid ones' ω² = 0, so K − σM is positive definite.
  result.shift = -result.flexuralRigidity / (o.density * std::pow(result.length, 4));

  // The unknowns: free vertex coordinates, then the ξ (all free but the clamped boundary ones
  // of Clamp::Rings, which stay at rest with their faces).
  const std::vector<bool> boundaryEdge =
      withXi ? curvature::boundaryEdges(stencils) : std::vector<bool>();
  const bool clampRings = o.support == Support::Clamped && o.clamp == Clamp::Rings;
  const bool clampNormals = o.support == Support::Clamped && o.clamp == Clamp::Normals;
  std::vector<bool> free(3 * vertexCount + restXi.size(), false);
  for (int v = 0; v < vertexCount; ++v)
    for (int c = o.dof == DofMode::Height ? 2 : 0; c < 3 && !fixed[v]; ++c) free[3 * v + c] = true;
  for (int e = 0; e < restXi.size(); ++e)
    free[3 * vertexCount + e] = !(clampRings && boundaryEdge[e]);

  const HessianAssembly assembly(
      terms, free, vertexCount,
      o.dof == DofMode::Height ? curvature::Derivatives::HeightOnly : curvature::Derivatives::All);
  const int n = assembly.size();
  const HessianEvaluation at =
      assembly.evaluate(rest.positions, restXi, HessianProjection::Exact, nullptr,
                        curvature::SecondDerivatives::GaussNewton);
  const Eigen::Map<const Sparse> upper(n, n, static_cast<int>(at.values.size()),
                                       assembly.columnStart().data(), assembly.rowIndex().data(),
                                       at.values.data());
  Sparse stiffness = upper.selfadjointView<Eigen::Upper>();

  // Clamp::Normals: ξ_e of a boundary edge = Σ_c g_{e,c} δ_{o,c}, o the boundary face's vertex
  // opposite e (its other two are held), g from the linearized clamp probed with a unit move of
  // coordinate c at every free vertex — each boundary ξ sees one free vertex, so one probe per
  // coordinate separates them. P maps the reduced unknowns to the assembly's.
  std::vector<int> assemblyIndex(free.size(), -1);
  for (int k = 0; k < n; ++k) assemblyIndex[assembly.freeUnknowns()[k]] = k;
  std::vector<int> reducedIndex(n, -1);
  int reduced = 0;
  for (int k = 0; k < n; ++k) {
    const int unknown = assembly.freeUnknowns()[k];
    const bool constrained =
        clampNormals && unknown >= 3 * vertexCount && boundaryEdge[unknown - 3 * vertexCount];
    if (!constrained) reducedIndex[k] = reduced++;
  }
  if (reduced < n) {
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
      const Eigen::VectorXd g =
          curvature::linearizedClampedBoundaryXi(stencils, rest.positions, probe, flat);
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
    stiffness = Sparse(p.transpose() * stiffness * p);
  }

  // Masses on the reduced unknowns: m_v on each free vertex coordinate, 0 on ξ.
  const Eigen::VectorXd vertexMass = lumpedVertexMasses(rest, o.mass, o.density);
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(reduced);
  std::vector<int> massive;
  std::vector<int> unknownOfReduced(reduced);
  for (int k = 0; k < n; ++k) {
    if (reducedIndex[k] < 0) continue;
    const int unknown = assembly.freeUnknowns()[k];
    unknownOfReduced[reducedIndex[k]] = unknown;
    if (unknown < 3 * vertexCount) {
      mass[reducedIndex[k]] = vertexMass[unknown / 3];
      massive.push_back(reducedIndex[k]);
    }
  }
  result.unknowns = reduced;
  result.massUnknowns = static_cast<int>(massive.size());
  const int wanted = o.count + result.rigidModes;
  if (wanted >= result.massUnknowns) {
    throw InputError("--count " + std::to_string(o.count) + ": the problem has only " +
                     std::to_string(result.massUnknowns) + " vertex unknowns (" +
                     std::to_string(result.rigidModes) +
                     " rigid modes); ask for fewer modes or refine the mesh");
  }
  result.assemblySeconds = secondsSince(start);

  const auto factorStart = Clock::now();
  Sparse shifted = stiffness;
  for (int k = 0; k < reduced; ++k) shifted.coeffRef(k, k) -= result.shift * mass[k];
  const SingleThreadedLinearAlgebra oneThread;  // the factor and every shift-invert solve
  Eigen::CholmodSupernodalLLT<Sparse, Eigen::Upper> factor;
  factor.cholmod().print = 0;
  // AMD. Measured at n = 256 (one run each, a loaded machine): midedge's factor 4.5 s on AMD
  // against 7.3 on METIS, 7.8 on CHOLMOD's nested dissection and 6.3 on CHOLMOD's default
  // choice; hinge and cotan within 10 % of each other on all four.
  factor.cholmod().nmethods = 1;
  factor.cholmod().method[0].ordering = CHOLMOD_AMD;
  factor.compute(shifted);
  if (factor.info() != Eigen::Success) {
    throw NumericalError(
        "K - sigma M is not positive definite: the energy's Hessian at rest has an eigenvalue "
        "below the shift (a rest state that is not a minimum?)");
  }
  result.factorSeconds = secondsSince(factorStart);

  const auto eigenStart = Clock::now();
  Eigen::VectorXd rootMass(massive.size());
  for (size_t j = 0; j < massive.size(); ++j) rootMass[j] = std::sqrt(mass[massive[j]]);
  ShiftInvertOperator op(factor, massive, rootMass, reduced, result.shift);
  const double lambdaScale =
      std::pow(result.length, 2) * std::sqrt(o.density / result.flexuralRigidity);
  const double zeroOmegaSquared = std::pow(kZeroModeLambda / lambdaScale, 2);
  const int m = result.massUnknowns;
  // The smallest `pairs` eigenpairs.
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
  auto lanczos = [&](int pairs) {
    const int ncv = std::min(m, std::max(2 * pairs + 1, pairs + 20));
    Spectra::SymEigsShiftSolver<ShiftInvertOperator> eigs(op, pairs, ncv, result.shift);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-12, Spectra::SortRule::SmallestAlge);
    if (eigs.info() != Spectra::CompInfo::Successful) {
      throw NumericalError("the Lanczos iteration did not converge to " + std::to_string(pairs) +
                           " eigenpairs in 1000 restarts");
    }
    result.restarts += static_cast<int>(eigs.num_iterations());
    values = eigs.eigenvalues();
    vectors = eigs.eigenvectors();
  };
  lanczos(wanted);
  // Zero modes beyond the rigid ones take the place of flexible modes, and Lanczos may return
  // fewer copies of a repeated zero eigenvalue than there are. Count them exactly, by Sylvester's
  // law of inertia: the eigenvalues of (S, M) below τ are the negative pivots of an LDLᵀ of
  // K − τM (the massless ξ block of K is positive definite and adds none); then ask for that
  // many more.
  const int zerosFound = static_cast<int>((values.array() < zeroOmegaSquared).count());
  result.zeroModes = zerosFound;
  if (zerosFound > 0) {
    Sparse below = stiffness;
    for (int k = 0; k < reduced; ++k) below.coeffRef(k, k) -= zeroOmegaSquared * mass[k];
    Eigen::SimplicialLDLT<Sparse, Eigen::Upper> ldlt(below);
    if (ldlt.info() == Eigen::Success)
      result.zeroModes = static_cast<int>((ldlt.vectorD().array() < 0.0).count());
  }
  if (o.count + result.zeroModes > wanted && wanted < m - 1) {
    const Eigen::VectorXd firstValues = values;
    const Eigen::MatrixXd firstVectors = vectors;
    try {
      lanczos(std::min(m - 1, o.count + result.zeroModes));
    } catch (const NumericalError&) {  // a long run of equal eigenvalues: keep the first answer
      values = firstValues;
      vectors = firstVectors;
    }
  }
  std::vector<int> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return values[a] < values[b]; });

  const double stiffnessNorm = [&] {  // ‖K‖∞, the largest absolute row sum
    Eigen::VectorXd rows = Eigen::VectorXd::Zero(reduced);
    for (int k = 0; k < stiffness.outerSize(); ++k)
      for (Sparse::InnerIterator it(stiffness, k); it; ++it) rows[it.row()] += std::abs(it.value());
    return rows.maxCoeff();
  }();
  int zerosReturned = 0, flexibleReturned = 0;
  for (int index : order) {
    VibrationMode mode;
    mode.omegaSquared = values[index];
    mode.omega = std::sqrt(std::max(mode.omegaSquared, 0.0));
    mode.lambda = mode.omega * lambdaScale;
    mode.zero = mode.lambda < kZeroModeLambda;
    if (!mode.zero && flexibleReturned == o.count) break;
    zerosReturned += mode.zero;
    flexibleReturned += !mode.zero;
    // The whole eigenvector, ξ included: (ω² − σ) (K − σM)⁻¹ M v solves the ξ rows exactly and
    // returns v where v is an eigenvector.
    Eigen::VectorXd b = Eigen::VectorXd::Zero(reduced);
    for (size_t j = 0; j < massive.size(); ++j)
      b[massive[j]] = rootMass[j] * vectors(j, index);  // M (M^{-1/2} u)
    Eigen::VectorXd y = (mode.omegaSquared - result.shift) * factor.solve(b);
    double norm = 0.0;
    for (int j : massive) norm += mass[j] * y[j] * y[j];
    y /= std::sqrt(norm);
    const Eigen::VectorXd ky = stiffness * y;
    const Eigen::VectorXd r = ky - mode.omegaSquared * mass.cwiseProduct(y);
    mode.residual =
        mode.zero ? ky.norm() / (stiffnessNorm * y.norm()) : r.norm() / std::max(ky.norm(), 1e-300);
    mode.shape = Positions::Zero(vertexCount, 3);
    for (int k = 0; k < reduced; ++k) {
      const int unknown = unknownOfReduced[k];
      if (unknown < 3 * vertexCount) mode.shape(unknown / 3, unknown % 3) = y[k];
    }
    for (const auto& [a, b2] : nodalSegments(stencils, rest, mode.shape))
      mode.nodalLength += (b2 - a).norm();
    result.modes.push_back(std::move(mode));
  }
  result.spuriousZeroModes = std::max(0, result.zeroModes - result.rigidModes);
  result.flexibleModes = flexibleReturned;
  // Multiplicities: runs of modes whose λ agree to kDegenerateTolerance; the zero modes are one.
  for (size_t i = 0; i < result.modes.size();) {
    size_t j = i + 1;
    while (j < result.modes.size() &&
           (result.modes[i].zero ? result.modes[j].zero
                                 : std::abs(result.modes[j].lambda - result.modes[j - 1].lambda) <=
                                       kDegenerateTolerance * result.modes[j].lambda))
      ++j;
    for (size_t k = i; k < j; ++k) result.modes[k].multiplicity = static_cast<int>(j - i);
    i = j;
  }
  result.operations = op.operations();
  result.eigenSeconds = secondsSince(eigenStart);
  result.totalSeconds = secondsSince(start);
  return result;
}

}  // namespace flexure::optimize
