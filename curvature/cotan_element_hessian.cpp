// The cotan element's energy, gradient and exact Hessian through its sums over the ring's faces
// (element_hessian.h states the chain rule). With y = (K_v, N_v = Σ_j (x_j − x_v) × (x_{j+1} −
// x_v), A_v) and r = g(y) (cotan_mean_curvature.h: g = w (K·N/|N| − K̄·n̄) / √A, the √A on the
// current metric only):
//
//   ∇E_e = r ∇r = r Jᵀ∇g,
//   ∇²E_e = ∇r ∇rᵀ + r ∇²r = Jᵀ (∇g ∇gᵀ + r ∇²g) J + r Σ_j P_jᵀ (Σ_m ∂g/∂y_m ∇²y_m^(j)) P_j,
//
// where y^(j) is face j's term (cotanFaceTerms, currentFaceVertexArea) over its three vertices'
// unknowns and P_j places them among the element's.
#include <algorithm>
#include <array>
#include <cmath>

#include "curvature/element_hessian.h"

namespace flexure::curvature {
namespace {

// y: K_v (3), N_v (3), A_v.
constexpr int kSums = 7;

// The element slot of coordinate c of block b (a vertex): all three, or the z alone.
int vertexSlot(Derivatives derivatives, int block, int c) {
  return derivatives == Derivatives::All ? 3 * block + c : block;
}

// Face j's terms of y as second-order jets of its F unknowns (9: x_v, x_a, x_b; 3: their z).
template <int F>
void faceTerms(const CotanMeanCurvatureResidual& residual, const std::array<const double*, 3>& x,
               Derivatives derivatives, std::array<SecondOrderJet<F>, kSums>& y) {
  using Jet = SecondOrderJet<F>;
  Jet seeded[3][3];
  for (int q = 0; q < 3; ++q)
    for (int c = 0; c < 3; ++c)
      seeded[q][c] = isElementUnknown(derivatives, c, 3)
                         ? Jet::variable(x[q][c], vertexSlot(derivatives, q, c))
                         : Jet(x[q][c]);
  const Vec3<Jet> center{seeded[0][0], seeded[0][1], seeded[0][2]};
  const Vec3<Jet> a = Vec3<Jet>{seeded[1][0], seeded[1][1], seeded[1][2]} - center;
  const Vec3<Jet> b = Vec3<Jet>{seeded[2][0], seeded[2][1], seeded[2][2]} - center;
  const CotanFaceTerms<Jet> face = cotanFaceTerms(a, b);
  y = {face.laplacian.x, face.laplacian.y, face.laplacian.z, face.normal.x,
       face.normal.y,    face.normal.z,    Jet(0.0)};
  if (residual.currentMetric) y[6] = currentFaceVertexArea(a, b, residual.voronoiArea);
}

// r = g(y) with its gradient and Hessian in y.
SecondOrderJet<kSums> residualOfSums(const CotanMeanCurvatureResidual& residual,
                                     const Eigen::Matrix<double, kSums, 1>& y) {
  using Jet = SecondOrderJet<kSums>;
  const Vec3<Jet> laplacian{Jet::variable(y[0], 0), Jet::variable(y[1], 1), Jet::variable(y[2], 2)};
  const Vec3<Jet> normal{Jet::variable(y[3], 3), Jet::variable(y[4], 4), Jet::variable(y[5], 5)};
  const Jet area = residual.currentMetric ? Jet::variable(y[6], 6) : Jet(1.0);
  return residual.residualOf(curvatureNormalOfSums(laplacian, normal), area);
}

template <int F>
bool separableHessian(const CotanMeanCurvatureResidual& residual,
                      const std::vector<const double*>& blocks, Derivatives derivatives,
                      ElementHessian& out) {
  using FaceJet = SecondOrderJet<F>;
  const int ring = static_cast<int>(blocks.size()) - 1;
  const int count = static_cast<int>(out.unknowns.size());
  thread_local std::vector<std::array<FaceJet, kSums>> faces;
  faces.resize(ring);
  Eigen::Matrix<double, kSums, 1> y = Eigen::Matrix<double, kSums, 1>::Zero();
  for (int j = 0; j < ring; ++j) {
    faceTerms<F>(residual, {blocks[0], blocks[1 + j], blocks[1 + (j + 1) % ring]}, derivatives,
                 faces[j]);
    for (int m = 0; m < kSums; ++m) y[m] += faces[j][m].a;
  }
  const SecondOrderJet<kSums> g = residualOfSums(residual, y);
  const double r = g.a;
  if (!std::isfinite(r)) return false;

  // J = ∂y/∂x over the element's slots; face j's vertex q is block 0, 1 + j or 1 + (j + 1) % k.
  using Jacobian = Eigen::Matrix<double, kSums, Eigen::Dynamic, 0, kSums, kMaxHessianUnknowns>;
  Jacobian jacobian = Jacobian::Zero(kSums, count);
  const int perVertex = F / 3;
  const auto faceBlock = [&](int j, int q) { return q == 0 ? 0 : 1 + (j + q - 1) % ring; };
  for (int j = 0; j < ring; ++j)
    for (int q = 0; q < 3; ++q)
      for (int s = 0; s < perVertex; ++s)
        for (int m = 0; m < kSums; ++m)
          jacobian(m, perVertex * faceBlock(j, q) + s) += faces[j][m].v[perVertex * q + s];

  Eigen::Matrix<double, kSums, kSums> outer;  // ∇g ∇gᵀ + r ∇²g
  for (int m = 0; m < kSums; ++m)
    for (int n = 0; n < kSums; ++n) outer(m, n) = g.v[m] * g.v[n] + r * g.hessian(m, n);
  const Eigen::Matrix<double, kSums, 1> slopes = g.v;  // ∂g/∂y

  out.energy = 0.5 * r * r;
  out.gradient.noalias() = r * (jacobian.transpose() * slopes);
  out.hessian.resize(count, count);
  out.hessian.noalias() = jacobian.transpose() * (outer * jacobian);
  // r Σ_m ∂g/∂y_m ∇²y_m, face by face, into the upper triangle.
  for (int j = 0; j < ring; ++j) {
    std::array<double, FaceJet::kPacked> part{};
    for (int m = 0; m < kSums; ++m) {
      const double weight = r * slopes[m];
      if (weight == 0.0) continue;
      for (int p = 0; p < FaceJet::kPacked; ++p) part[p] += weight * faces[j][m].h[p];
    }
    for (int a = 0, p = 0; a < F; ++a) {
      const int sa = perVertex * faceBlock(j, a / perVertex) + a % perVertex;
      for (int b = a; b < F; ++b, ++p) {
        const int sb = perVertex * faceBlock(j, b / perVertex) + b % perVertex;
        out.hessian(std::min(sa, sb), std::max(sa, sb)) += part[p];
      }
    }
  }
  out.hessian.triangularView<Eigen::StrictlyLower>() = out.hessian.transpose();
  return out.gradient.allFinite() && out.hessian.allFinite();
}

}  // namespace

bool elementHessian(const CotanMeanCurvatureResidual& residual,
                    const std::vector<const double*>& blocks, const std::vector<int>& sizes,
                    const std::vector<long>& firstUnknown, Derivatives derivatives,
                    ElementHessian& out) {
  elementUnknowns(sizes, firstUnknown, derivatives, out.unknowns);
  if (out.unknowns.size() > static_cast<size_t>(kMaxHessianUnknowns)) return false;
  return derivatives == Derivatives::All ? separableHessian<9>(residual, blocks, derivatives, out)
                                         : separableHessian<3>(residual, blocks, derivatives, out);
}

}  // namespace flexure::curvature
