// The hinge's curvature tensor per face (docs/energies.md, "Plasticity"): the linear map between a
// uniform curvature tensor K on a face and the hinge angles it makes, so that per-edge angle
// measures read as per-face tensors (the plastic strain the face energies store) and back.
//
// For the vertex interpolant of the height field ½ uᵀ K u on the two flaps of an interior edge e
// (rest geometry, the flap g unfolded into f's plane), in the edge's frame — t along e, of length
// L, from its first vertex; m the in-plane normal from f towards g; g's apex at (a_g, h_g), f's at
// (a_f, −h_f) — the jump of the interpolant's normal slope is
//
//   θ_e(K) = ½ K_mm (h_f + h_g) + K_tm (a_g − a_f) + ½ K_tt [a_g (a_g − L)/h_g + a_f (a_f − L)/h_f]
//
// (along e both flaps' interpolants have the exact slope ½ K_tt L; the normal slope on each flap
// follows from its apex value ½ K(apex, apex)). Linear in K: a row c_e of three coefficients of
// (a, b, c), K = [[a, b], [b, c]] in a face's frame. It equals the hinge's angle measure of the
// interpolated surface to O(|K|² h) (tests/test_hinge_face_tensors.cpp).
#pragma once

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "modeling/rest_state.h"
#include "modeling/stencils.h"

namespace flexure::curvature {

// An interior edge's flaps, intrinsic: its length L and the apexes (a_f, h_f), (a_g, h_g).
struct HingeFlaps {
  double length, af, hf, ag, hg;
};

// c_e in a frame where t and m (unit, orthogonal; m from f towards g) have these components.
Eigen::RowVector3d hingeAngleRow(const Eigen::Vector2d& t, const Eigen::Vector2d& m,
                                 const HingeFlaps& flaps);

// What the tensors are built from, copied out of the stencils and the rest state: a term that
// builds them later keeps this, not references to a Problem's members (which move with it).
struct HingeRestGeometry {
  modeling::Positions positions;    // #V by 3: X̄
  modeling::Triangles faces;        // #F by 3
  modeling::IndexQuads hinges;      // #H by 4: (i, j, k, l)
  modeling::IndexPairs hingeFaces;  // #H by 2: the faces (f, g) of each hinge's edge

  static HingeRestGeometry of(const modeling::Stencils& s, const modeling::RestState& rest);
};

// The rows c_e of every hinge (the stencils' hinge order, which is the hinge term's element
// order) in the rest frames (face_frame.h) of its two faces, and per face the inverse map.
class HingeFaceTensors {
 public:
  explicit HingeFaceTensors(const HingeRestGeometry& geometry);
  HingeFaceTensors(const modeling::Stencils& s, const modeling::RestState& rest)
      : HingeFaceTensors(HingeRestGeometry::of(s, rest)) {}

  // The faces with at least one interior edge, in mesh order: element k is mesh face face(k).
  int faceCount() const { return static_cast<int>(faces_.size()); }
  int face(int k) const { return faces_[static_cast<size_t>(k)].id; }

  // #faces by 3, (a, b, c) in each face's rest frame: the tensor T_f with c_e · T_f = angles[e]
  // on f's interior edges — M_f⁻¹ with three (M_f the rows of f's edges), the minimum-norm one
  // (in a² + 2b² + c²) with fewer, which reproduces those one or two angles exactly.
  Eigen::MatrixXd tensors(const Eigen::VectorXd& angles) const;
  // #hinges: ½ (c_e^f · T_f + c_e^g · T_g), each face's tensor in its own frame. For the tensors
  // of one uniform K this is θ_e(K).
  Eigen::VectorXd angles(const Eigen::MatrixXd& tensors) const;

 private:
  struct Face {
    int id;
    std::vector<int> hinges;                       // its interior edges' hinges
    Eigen::Matrix<double, 3, Eigen::Dynamic> map;  // M_f⁻¹ (or the minimum-norm inverse)
  };
  std::vector<Face> faces_;
  std::vector<std::array<int, 2>> hingeFaces_;                // per hinge: the elements of f, g
  std::vector<std::array<Eigen::RowVector3d, 2>> hingeRows_;  // c_e in f's frame, in g's
};

// The hinge term's rest angles φ(θ̄⁰_e) and, built on first use, the face tensors and the rest
// tensors S̄⁰_f = T_f(φ(θ̄⁰)) they read. Only a plastic update reads the hinge's rest curvature,
// so a problem that never does (an elastic one) never pays the build, about 5× the rest of the
// term's, only the copy of the geometry (bench/energy_bench.cpp, BM_HingeRestTensors: counters
// term_ms and geometry_ms against the build's time). The build is the eager one, so the tensors
// are the same bit for bit. The accessors are const and may be called from several threads at once:
// the build runs once, under std::call_once, into members that are mutable for that reason only.
class HingeRestTensors {
 public:
  HingeRestTensors(HingeRestGeometry geometry, Eigen::VectorXd restAngles)
      : geometry_(std::move(geometry)), restAngles_(std::move(restAngles)) {}
  HingeRestTensors(const HingeRestTensors&) = delete;
  HingeRestTensors& operator=(const HingeRestTensors&) = delete;

  const Eigen::VectorXd& restAngles() const { return restAngles_; }  // φ(θ̄⁰_e), #hinges
  const HingeFaceTensors& faces() const { return built().faces; }
  const Eigen::MatrixXd& restTensors() const { return built().rest; }  // S̄⁰, #faces by 3
  // Whether the tensors have been built (a cheap query: a term's cost, and its test).
  bool isBuilt() const { return isBuilt_.load(std::memory_order_acquire); }

 private:
  struct Built {
    HingeFaceTensors faces;
    Eigen::MatrixXd rest;
  };
  const Built& built() const;

  HingeRestGeometry geometry_;
  Eigen::VectorXd restAngles_;
  mutable std::once_flag once_;
  mutable std::optional<Built> built_;
  mutable std::atomic<bool> isBuilt_{false};
};

}  // namespace flexure::curvature
