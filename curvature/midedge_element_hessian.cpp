// The midedge element's energy, gradient and exact Hessian from the closed-form
// derivatives of its three hinge angles (element_hessian.h states the chain
// rule). γ_i = θ_i / 2 + σ_i ξ_i (θ_i = 0 on a boundary edge), so row i of Jγ =
// ∂γ/∂x is ½ ∇θ_i + σ_i e_{ξ_i} and ∇²γ_i = ½ ∇²θ_i, with ∇θ_i, ∇²θ_i
// hinge_angle_derivatives.h's over the hinge (x_{i+1}, x_{i+2}, x_i, flap_i).
//
// Rest metric: S_T = Σ_i γ_i T̄_i with constant tensors T̄_i (midedge_normals.h),
// so the residuals are affine in γ, r = r₀ + Σ_i C_i γ_i with C_i =
// koiterResiduals(T̄_i, 0) (koiter_density.h):
//
//   ∇r = C Jγ,   ∇E_e = (C Jγ)ᵀ r,   ∇²E_e = (C Jγ)ᵀ (C Jγ) + Σ_i (r · C_i) ½
//   ∇²θ_i.
//
// Current metric: r = g(y) = √A_T koiter(Σ_i γ_i T_i / A_T − S̄) with y = (γ,
// T_0, T_1, T_2, A_T), the current edge tensors T_i and area A_T
// (current_metric.h) functions of the face's 9 unknowns (second-order jets);
// with J = ∂y/∂x,
//
//   ∇²E_e = Jᵀ (Σ_k ∇g_k ∇g_kᵀ + r_k ∇²g_k) J + Σ_m (Σ_k r_k ∂g_k/∂y_m) ∇²y_m.
#include <array>
#include <cmath>

#include "curvature/element_hessian.h"
#include "curvature/hinge_angle_derivatives.h"

namespace flexure::curvature {
namespace {

// y on the current metric: γ (3), the tensors T_i (3 each), A_T.
constexpr int kFaceQuantities = 10;
constexpr int kSums = 3 + kFaceQuantities;
using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kSums,
                           kMaxElementUnknowns<MidedgeResidual>>;

// The element slot of coordinate c of block b (blocks: ξ0, ξ1, ξ2, then
// vertices), or −1 where it is not an unknown (a vertex's x and y in height
// mode).
int midedgeSlot(Derivatives derivatives, int block, int c) {
  if (block < 3) return block;
  if (derivatives == Derivatives::All) return 3 + 3 * (block - 3) + c;
  return c == 2 ? block : -1;
}

// The three γ: their values, rows 0..2 of `jacobian` (zero before), and each
// interior edge's hinge blocks (x_{i+1}, x_{i+2}, x_i, flap, as
// MidedgeResidual::shapeOperator reads them) and angle derivatives.
struct EdgeAngles {
  std::array<double, 3> gamma;
  std::array<std::array<int, 4>, 3> hinge;
  std::array<HingeAngleDerivatives, 3> theta;
};
void edgeAngles(const MidedgeResidual& residual, const std::vector<const double*>& blocks,
                Derivatives derivatives, Rows& jacobian, EdgeAngles& out) {
  for (int i = 0, flap = 6; i < 3; ++i) {
    jacobian(i, midedgeSlot(derivatives, i, 0)) = residual.signs[i];
    double theta = 0.0;
    if (residual.hasFlap[i]) {
      out.hinge[i] = {3 + (i + 1) % 3, 3 + (i + 2) % 3, 3 + i, flap++};
      const double* x[4] = {blocks[out.hinge[i][0]], blocks[out.hinge[i][1]],
                            blocks[out.hinge[i][2]], blocks[out.hinge[i][3]]};
      hingeAngleDerivatives(x, true, out.theta[i]);
      theta = out.theta[i].angle;
      for (int a = 0; a < 12; ++a) {
        const int sa = midedgeSlot(derivatives, out.hinge[i][a / 3], a % 3);
        if (sa >= 0) jacobian(i, sa) += 0.5 * out.theta[i].gradient[a];
      }
    }
    out.gamma[i] = theta / 2.0 + residual.signs[i] * blocks[i][0];
  }
}

// hessian's upper triangle += Σ_i weight_i ½ ∇²θ_i over the interior edges.
void addAngleHessians(const MidedgeResidual& residual, const EdgeAngles& angles,
                      const std::array<double, 3>& weight, Derivatives derivatives,
                      Eigen::MatrixXd& hessian) {
  for (int i = 0; i < 3; ++i) {
    if (!residual.hasFlap[i]) continue;
    for (int a = 0; a < 12; ++a) {
      const int sa = midedgeSlot(derivatives, angles.hinge[i][a / 3], a % 3);
      if (sa < 0) continue;
      for (int b = 0; b < 12; ++b) {
        const int sb = midedgeSlot(derivatives, angles.hinge[i][b / 3], b % 3);
        if (sb >= sa) hessian(sa, sb) += 0.5 * weight[i] * angles.theta[i].hessian(a, b);
      }
    }
  }
}

bool restMetricHessian(const MidedgeResidual& residual, const std::vector<const double*>& blocks,
                       Derivatives derivatives, ElementHessian& out) {
  const int count = static_cast<int>(out.unknowns.size());
  Eigen::Vector3d r;
  if (!residual(blocks.data(), r.data())) return false;
  Eigen::Matrix3d c;  // column i: ∂r/∂γ_i
  for (int i = 0; i < 3; ++i)
    koiterResiduals(residual.edgeTensors[i], Sym2<double>{0.0, 0.0, 0.0}, residual.weights,
                    c.col(i).data());
  Rows gammaJacobian = Rows::Zero(3, count);  // Jγ
  thread_local EdgeAngles angles;
  edgeAngles(residual, blocks, derivatives, gammaJacobian, angles);
  const Rows jacobian = c * gammaJacobian;  // ∂r/∂x
  out.energy = 0.5 * r.squaredNorm();
  out.gradient.noalias() = jacobian.transpose() * r;
  out.hessian.resize(count, count);
  out.hessian.noalias() = jacobian.transpose() * jacobian;
  addAngleHessians(residual, angles, {r.dot(c.col(0)), r.dot(c.col(1)), r.dot(c.col(2))},
                   derivatives, out.hessian);
  out.hessian.triangularView<Eigen::StrictlyLower>() = out.hessian.transpose();
  return out.gradient.allFinite() && out.hessian.allFinite();
}

// The face's T_0, T_1, T_2 (a, b, c each; secure or exact) and A_T as jets of its F unknowns (9,
// or 3 z's).
template <int F>
void currentFaceQuantities(const std::vector<const double*>& blocks, Derivatives derivatives,
                           bool secure, std::array<SecondOrderJet<F>, kFaceQuantities>& q) {
  using Jet = SecondOrderJet<F>;
  Jet seeded[3][3];
  for (int v = 0; v < 3; ++v)
    for (int c = 0; c < 3; ++c)
      seeded[v][c] = isElementUnknown(derivatives, c, 3)
                         ? Jet::variable(blocks[3 + v][c], F == 9 ? 3 * v + c : v)
                         : Jet(blocks[3 + v][c]);
  const Vec3<Jet> face[3] = {{seeded[0][0], seeded[0][1], seeded[0][2]},
                             {seeded[1][0], seeded[1][1], seeded[1][2]},
                             {seeded[2][0], seeded[2][1], seeded[2][2]}};
  const CurrentFrame<Jet> frame = currentFrame(face[0], face[1], face[2]);
  const std::array<Sym2<Jet>, 3> tensors = currentEdgeTensors(face, frame, secure);
  for (int i = 0; i < 3; ++i) {
    q[3 * i] = tensors[i].a;
    q[3 * i + 1] = tensors[i].b;
    q[3 * i + 2] = tensors[i].c;
  }
  q[9] = frame.area;
}

// g(y) = √A_T koiter(Σ_i γ_i T_i / A_T − S̄): MidedgeResidual::shapeOperator on
// the current metric, koiterResiduals, scaleByCurrentArea; with its gradients
// and Hessians in y.
std::array<SecondOrderJet<kSums>, 3> currentResiduals(const MidedgeResidual& residual,
                                                      const Eigen::Matrix<double, kSums, 1>& y) {
  using Jet = SecondOrderJet<kSums>;
  std::array<Jet, kSums> v;
  for (int m = 0; m < kSums; ++m) v[m] = Jet::variable(y[m], m);
  const Jet& area = v[12];
  Sym2<Jet> s{Jet(0.0), Jet(0.0), Jet(0.0)};
  for (int i = 0; i < 3; ++i)
    addScaled(s, v[i] / area, Sym2<Jet>{v[3 + 3 * i], v[4 + 3 * i], v[5 + 3 * i]});
  std::array<Jet, 3> r;
  koiterResiduals(s, residual.restShapeOperator, residual.weights, r.data());
  const Jet root = sqrt(area);
  for (Jet& rk : r) rk = root * rk;
  return r;
}

template <int F>
bool currentMetricHessian(const MidedgeResidual& residual, const std::vector<const double*>& blocks,
                          Derivatives derivatives, ElementHessian& out) {
  using FaceJet = SecondOrderJet<F>;
  const int count = static_cast<int>(out.unknowns.size());
  std::array<double, 3> value;
  if (!residual(blocks.data(), value.data())) return false;
  Rows jacobian = Rows::Zero(kSums, count);  // J = ∂y/∂x
  thread_local EdgeAngles angles;
  edgeAngles(residual, blocks, derivatives, jacobian, angles);
  std::array<FaceJet, kFaceQuantities> face;
  currentFaceQuantities<F>(blocks, derivatives, residual.secureMetric, face);
  Eigen::Matrix<double, kSums, 1> y;
  for (int i = 0; i < 3; ++i) y[i] = angles.gamma[i];
  for (int m = 0; m < kFaceQuantities; ++m) {
    y[3 + m] = face[m].a;
    // The face's unknowns are slots 3 .. 3 + F − 1 (x0, x1, x2 follow the ξ).
    for (int a = 0; a < F; ++a) jacobian(3 + m, 3 + a) = face[m].v[a];
  }
  const std::array<SecondOrderJet<kSums>, 3> g = currentResiduals(residual, y);
  Eigen::Matrix<double, kSums, kSums> outer = Eigen::Matrix<double, kSums, kSums>::Zero();
  Eigen::Matrix<double, kSums, 1> slopes = Eigen::Matrix<double, kSums, 1>::Zero();  // Σ r_k ∇g_k
  out.energy = 0.0;
  for (const SecondOrderJet<kSums>& gk : g) {
    out.energy += 0.5 * gk.a * gk.a;
    slopes += gk.a * gk.v;
    for (int m = 0; m < kSums; ++m)
      for (int n = 0; n < kSums; ++n) outer(m, n) += gk.v[m] * gk.v[n] + gk.a * gk.hessian(m, n);
  }
  out.gradient.noalias() = jacobian.transpose() * slopes;
  out.hessian.resize(count, count);
  out.hessian.noalias() = jacobian.transpose() * (outer * jacobian);
  addAngleHessians(residual, angles, {slopes[0], slopes[1], slopes[2]}, derivatives, out.hessian);
  std::array<double, FaceJet::kPacked> part{};
  for (int m = 0; m < kFaceQuantities; ++m)
    for (int p = 0; p < FaceJet::kPacked; ++p) part[p] += slopes[3 + m] * face[m].h[p];
  for (int a = 0, p = 0; a < F; ++a)
    for (int b = a; b < F; ++b, ++p) out.hessian(3 + a, 3 + b) += part[p];
  out.hessian.triangularView<Eigen::StrictlyLower>() = out.hessian.transpose();
  return out.gradient.allFinite() && out.hessian.allFinite();
}

}  // namespace

bool elementHessian(const MidedgeResidual& residual, const std::vector<const double*>& blocks,
                    const std::vector<int>& sizes, const std::vector<long>& firstUnknown,
                    Derivatives derivatives, ElementHessian& out) {
  elementUnknowns(sizes, firstUnknown, derivatives, out.unknowns);
  if (!residual.currentMetric) return restMetricHessian(residual, blocks, derivatives, out);
  return derivatives == Derivatives::All
             ? currentMetricHessian<9>(residual, blocks, derivatives, out)
             : currentMetricHessian<3>(residual, blocks, derivatives, out);
}

}  // namespace flexure::curvature
