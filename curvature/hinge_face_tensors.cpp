// The hinge's per-face curvature tensor: rows c_e and their per-face inverses
// (hinge_face_tensors.h).
#include "curvature/hinge_face_tensors.h"

#include <Eigen/LU>
#include <Eigen/QR>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "curvature/face_frame.h"

namespace flexure::curvature {
namespace {

Eigen::Vector3d restVertex(const HingeRestGeometry& rest, int v) {
  return rest.positions.row(v).transpose();
}

// The rest frame of mesh face f (the frame the face energies' tensors are in).
FaceFrame restFrame(const HingeRestGeometry& rest, int f) {
  return FaceFrame::of(restVertex(rest, rest.faces(f, 0)), restVertex(rest, rest.faces(f, 1)),
                       restVertex(rest, rest.faces(f, 2)));
}

// The apex p's coordinates (a, h) along and off the edge x_i → x_i + L t̂ (h ≥ 0).
std::array<double, 2> apex(const Eigen::Vector3d& xi, const Eigen::Vector3d& unit,
                           const Eigen::Vector3d& p) {
  const double a = (p - xi).dot(unit);
  return {a, (p - xi - a * unit).norm()};
}

// c_e in face `frame`: t the edge's unit direction in it, m the in-plane normal from f towards g,
// found from the face's apex at `apexOffset` from x_i: m · (x_l − x_i) > 0 when `apexIsG`, else
// m · (x_k − x_i) < 0.
Eigen::RowVector3d rowInFrame(const FaceFrame& frame, const Eigen::Vector3d& edge,
                              const Eigen::Vector3d& apexOffset, bool apexIsG,
                              const HingeFlaps& flaps) {
  const Eigen::Vector2d t = frame.components(edge).normalized();
  Eigen::Vector2d m(-t.y(), t.x());
  const double side = m.dot(frame.components(apexOffset));
  if ((side > 0.0) != apexIsG) m = -m;
  return hingeAngleRow(t, m, flaps);
}

}  // namespace

Eigen::RowVector3d hingeAngleRow(const Eigen::Vector2d& t, const Eigen::Vector2d& m,
                                 const HingeFlaps& f) {
  // K_tt = tᵀ K t, K_tm = tᵀ K m, K_mm = mᵀ K m as rows of coefficients of (a, b, c).
  const Eigen::RowVector3d tt(t.x() * t.x(), 2 * t.x() * t.y(), t.y() * t.y());
  const Eigen::RowVector3d tm(t.x() * m.x(), t.x() * m.y() + t.y() * m.x(), t.y() * m.y());
  const Eigen::RowVector3d mm(m.x() * m.x(), 2 * m.x() * m.y(), m.y() * m.y());
  const double along = 0.5 * (f.ag * (f.ag - f.length) / f.hg + f.af * (f.af - f.length) / f.hf);
  return along * tt + (f.ag - f.af) * tm + 0.5 * (f.hf + f.hg) * mm;
}

HingeRestGeometry HingeRestGeometry::of(const modeling::Stencils& s,
                                        const modeling::RestState& rest) {
  HingeRestGeometry g{rest.positions, s.faces, s.hinges, modeling::IndexPairs(s.hingeCount(), 2)};
  for (int h = 0; h < s.hingeCount(); ++h) g.hingeFaces.row(h) = s.edgeFaces.row(s.hingeEdges[h]);
  return g;
}

HingeFaceTensors::HingeFaceTensors(const HingeRestGeometry& rest) {
  const auto faceCount = static_cast<int>(rest.faces.rows());
  const auto hingeCount = static_cast<int>(rest.hinges.rows());
  std::vector<int> elementOf(static_cast<size_t>(faceCount), -1);
  const auto elementFor = [&](int f) {
    if (elementOf[static_cast<size_t>(f)] < 0) {
      elementOf[static_cast<size_t>(f)] = static_cast<int>(faces_.size());
      faces_.push_back({f, {}, {}});
    }
    return elementOf[static_cast<size_t>(f)];
  };
  // Elements in mesh face order.
  std::vector<bool> hasInterior(static_cast<size_t>(faceCount), false);
  for (int h = 0; h < hingeCount; ++h)
    for (int side = 0; side < 2; ++side)
      hasInterior[static_cast<size_t>(rest.hingeFaces(h, side))] = true;
  for (int f = 0; f < faceCount; ++f)
    if (hasInterior[static_cast<size_t>(f)]) elementFor(f);
  std::vector<FaceFrame> frames;
  frames.reserve(static_cast<size_t>(faceCount));
  for (int f = 0; f < faceCount; ++f) frames.push_back(restFrame(rest, f));
  hingeFaces_.resize(static_cast<size_t>(hingeCount));
  hingeRows_.resize(static_cast<size_t>(hingeCount));
  for (int h = 0; h < hingeCount; ++h) {
    const Eigen::Vector3d xi = restVertex(rest, rest.hinges(h, 0)),
                          xj = restVertex(rest, rest.hinges(h, 1));
    const Eigen::Vector3d xk = restVertex(rest, rest.hinges(h, 2)),
                          xl = restVertex(rest, rest.hinges(h, 3));
    // f = (i, j, k) is the edge face that holds k.
    int f = rest.hingeFaces(h, 0), g = rest.hingeFaces(h, 1);
    bool fHoldsK = false;
    for (int c = 0; c < 3; ++c) fHoldsK = fHoldsK || rest.faces(f, c) == rest.hinges(h, 2);
    if (!fHoldsK) std::swap(f, g);
    const double length = (xj - xi).norm();
    const Eigen::Vector3d unit = (xj - xi) / length;
    const auto [af, hf] = apex(xi, unit, xk);
    const auto [ag, hg] = apex(xi, unit, xl);
    const HingeFlaps flaps{length, af, hf, ag, hg};
    hingeFaces_[static_cast<size_t>(h)] = {elementFor(f), elementFor(g)};
    hingeRows_[static_cast<size_t>(h)] = {rowInFrame(frames[f], xj - xi, xk - xi, false, flaps),
                                          rowInFrame(frames[g], xj - xi, xl - xi, true, flaps)};
    faces_[static_cast<size_t>(elementFor(f))].hinges.push_back(h);
    faces_[static_cast<size_t>(elementFor(g))].hinges.push_back(h);
  }
  // M_f⁻¹, or the minimum-norm inverse in a² + 2b² + c² (the Frobenius norm of [[a, b], [b, c]],
  // frame-independent): with D = diag(1, 1/√2, 1), T = D (M D)⁺ φ.
  const Eigen::Vector3d d(1.0, 1.0 / std::sqrt(2.0), 1.0);
  for (Face& face : faces_) {
    Eigen::MatrixXd rows(face.hinges.size(), 3);
    for (size_t r = 0; r < face.hinges.size(); ++r) {
      const auto h = static_cast<size_t>(face.hinges[r]);
      const int side = faces_[static_cast<size_t>(hingeFaces_[h][0])].id == face.id ? 0 : 1;
      rows.row(static_cast<Eigen::Index>(r)) = hingeRows_[h][static_cast<size_t>(side)];
    }
    if (rows.rows() == 3)
      face.map = Eigen::Matrix3d(rows).inverse();
    else
      face.map = d.asDiagonal() *
                 (rows * d.asDiagonal()).completeOrthogonalDecomposition().pseudoInverse();
  }
}

Eigen::MatrixXd HingeFaceTensors::tensors(const Eigen::VectorXd& angles) const {
  Eigen::MatrixXd out(faces_.size(), 3);
  for (size_t k = 0; k < faces_.size(); ++k) {
    Eigen::VectorXd local(faces_[k].hinges.size());
    for (size_t r = 0; r < faces_[k].hinges.size(); ++r)
      local[static_cast<Eigen::Index>(r)] = angles[faces_[k].hinges[r]];
    out.row(static_cast<Eigen::Index>(k)) = (faces_[k].map * local).transpose();
  }
  return out;
}

Eigen::VectorXd HingeFaceTensors::angles(const Eigen::MatrixXd& tensors) const {
  Eigen::VectorXd out(hingeFaces_.size());
  for (size_t h = 0; h < hingeFaces_.size(); ++h)
    out[static_cast<Eigen::Index>(h)] =
        0.5 * (hingeRows_[h][0].dot(tensors.row(hingeFaces_[h][0])) +
               hingeRows_[h][1].dot(tensors.row(hingeFaces_[h][1])));
  return out;
}

const HingeRestTensors::Built& HingeRestTensors::built() const {
  std::call_once(once_, [this] {
    HingeFaceTensors faces(geometry_);
    Eigen::MatrixXd rest = faces.tensors(restAngles_);
    built_.emplace(Built{std::move(faces), std::move(rest)});
    isBuilt_.store(true, std::memory_order_release);
  });
  return *built_;
}

}  // namespace flexure::curvature
