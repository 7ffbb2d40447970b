// The cotan element's energy, gradient and exact Hessian through its sums over the ring's faces
// (element_hessian.h states the chain rule). With y = (K_v, N_v = Σ_j (x_j − x_v) × (x_{j+1} −
// x_v), A_v) and r = g(y) (cotan_mean_curvature.h: g = w (K·N/|N| − K̄·n̄) / √A, the √A on the
// current metric only):
//
//   ∇E_e = r ∇r = r Jᵀ∇g,
//   ∇²E_e = ∇r ∇rᵀ + r ∇²r = Jᵀ (∇g ∇gᵀ + r ∇²g) J + r Σ_j P_jᵀ (Σ_m ∂g/∂y_m ∇²y_m^(j)) P_j,
//
// where y^(j) is face j's term (cotanFaceTerms, currentFaceVertexArea), a function of the edge
// vectors (x_a − x_v, x_b − x_v) alone, and P_j maps the element's unknowns to those.
#include <algorithm>
#include <array>
#include <cmath>

#include "curvature/element_hessian.h"

namespace flexure::curvature {
namespace {

// y: K_v (3), N_v (3), A_v.
constexpr int kSums = 7;

// Face j's terms read a = x_a − x_v and b = x_b − x_v alone: their jets are over those F values
// (6; in height mode the 2 z's), and (a, b) = P (x_v, x_a, x_b) with P = [−I I 0; −I 0 I]
// (per coordinate), so the face's block over its vertices is Pᵀ ∇²y P.
template <int F>
using FaceVertices = Eigen::Matrix<double, F, F / 2 * 3>;
template <int F>
FaceVertices<F> edgeDifferences() {
  constexpr int perVertex = F / 2;
  FaceVertices<F> p = FaceVertices<F>::Zero();
  for (int e = 0; e < 2; ++e)
    for (int s = 0; s < perVertex; ++s) {
      p(perVertex * e + s, s) = -1.0;
      p(perVertex * e + s, perVertex * (1 + e) + s) = 1.0;
    }
  return p;
}

// Face j's terms of y as second-order jets of (a, b) (the x, y, z of each, or their z).
template <int F>
void faceTerms(const CotanMeanCurvatureResidual& residual, const std::array<const double*, 3>& x,
               Derivatives derivatives, std::array<SecondOrderJet<F>, kSums>& y) {
  using Jet = SecondOrderJet<F>;
  Jet edge[2][3];
  for (int e = 0; e < 2; ++e)
    for (int c = 0; c < 3; ++c) {
      const double difference = x[1 + e][c] - x[0][c];
      edge[e][c] = !isElementUnknown(derivatives, c, 3) ? Jet(difference)
                   : derivatives == Derivatives::All    ? Jet::variable(difference, 3 * e + c)
                                                        : Jet::variable(difference, e);
    }
  const Vec3<Jet> a{edge[0][0], edge[0][1], edge[0][2]}, b{edge[1][0], edge[1][1], edge[1][2]};
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
  constexpr int perVertex = F / 2, faceUnknowns = 3 * perVertex;
  static const FaceVertices<F> p = edgeDifferences<F>();
  const auto faceSlot = [&](int j, int a) {
    const int q = a / perVertex;
    return perVertex * (q == 0 ? 0 : 1 + (j + q - 1) % ring) + a % perVertex;
  };
  for (int j = 0; j < ring; ++j)
    for (int m = 0; m < kSums; ++m) {
      const Eigen::Matrix<double, faceUnknowns, 1> row = p.transpose() * faces[j][m].v;
      for (int a = 0; a < faceUnknowns; ++a) jacobian(m, faceSlot(j, a)) += row[a];
    }

  Eigen::Matrix<double, kSums, kSums> outer;  // ∇g ∇gᵀ + r ∇²g
  for (int m = 0; m < kSums; ++m)
    for (int n = 0; n < kSums; ++n) outer(m, n) = g.v[m] * g.v[n] + r * g.hessian(m, n);
  const Eigen::Matrix<double, kSums, 1> slopes = g.v;  // ∂g/∂y

  out.energy = 0.5 * r * r;
  out.gradient.noalias() = r * (jacobian.transpose() * slopes);
  out.hessian.resize(count, count);
  out.hessian.noalias() = jacobian.transpose() * (outer * jacobian);
  // r Σ_m ∂g/∂y_m ∇²y_m, face by face (Pᵀ (…) P), into the upper triangle.
  for (int j = 0; j < ring; ++j) {
    Eigen::Matrix<double, F, F> part = Eigen::Matrix<double, F, F>::Zero();
    for (int m = 0; m < kSums; ++m) {
      const double weight = r * slopes[m];
      if (weight == 0.0) continue;
      for (int a = 0, k = 0; a < F; ++a)
        for (int b = a; b < F; ++b, ++k) part(a, b) += weight * faces[j][m].h[k];
    }
    part.template triangularView<Eigen::StrictlyLower>() = part.transpose();
    const Eigen::Matrix<double, faceUnknowns, faceUnknowns> block = p.transpose() * part * p;
    for (int a = 0; a < faceUnknowns; ++a)
      for (int b = 0; b < faceUnknowns; ++b) {
        const int sa = faceSlot(j, a), sb = faceSlot(j, b);
        if (sa <= sb) out.hessian(sa, sb) += block(a, b);
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
  return derivatives == Derivatives::All ? separableHessian<6>(residual, blocks, derivatives, out)
                                         : separableHessian<2>(residual, blocks, derivatives, out);
}

}  // namespace flexure::curvature
