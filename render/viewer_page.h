// The interactive viewer page: one self-contained HTML file (three.js and the page's script
// embedded, the meshes as base64 Float32/Uint32 arrays) that draws meshes side by side or
// overlaid with one linked camera, reflection lines and isophotes computed in the fragment shader
// from the same camera-locked environment as the offscreen renderer (render/mesh_shaders.cpp), a
// per-vertex or per-face field with its legend, a simulation's frames with a time slider, and
// vibration modes animated about the rest shape with their nodal lines.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "modeling/mesh.h"
#include "render/mesh_renderer.h"

namespace flexure::render {

enum class ViewerStyle { Reflection, Isophote, Shaded, Field };

// One mesh of the page: its connectivity, its positions at each frame (one frame for a still
// mesh), and optionally a per-vertex field at each frame (or one for every frame).
// A point of a line drawn on a mesh: (1 − t) x_a + t x_b of the frame shown, so that the line
// follows the mesh as it moves (a = b for a vertex).
struct ViewerLinePoint {
  int a = 0, b = 0;
  double t = 0.0;  // in [0, 1]
};
using ViewerSegments = std::vector<std::pair<ViewerLinePoint, ViewerLinePoint>>;

// A vibration mode of a mesh, animated on its first frame x_rest as
// x(t) = x_rest + a sin(2π t / T) φ, a the page's amplitude slider (1 by default, so that φ is
// the displacement at full swing) and T a fixed display period; its nodal lines drawn black.
struct ViewerMode {
  std::string label;          // the mode selector's entry, e.g. "mode 2: λ = 49.3, ω = 12.3"
  modeling::Positions shape;  // φ, #V by 3
  ViewerSegments nodalLines;  // on the moving mesh
};

// A cut (fracture, modeling/crack_cut.h) changes a simulation's faces and appends vertices: from
// frame `frame` on, until the next change, the frames have these faces.
struct ViewerFaceChange {
  std::size_t frame = 0;
  modeling::Triangles triangles;
};

struct ViewerMesh {
  std::string name;                           // shown above its view
  modeling::Triangles triangles;              // #F by 3 (the first frame's)
  std::vector<modeling::Positions> frames;    // each #V by 3 (#V the same between face changes)
  std::vector<ViewerFaceChange> faceChanges;  // in frame order; empty: one set of faces
  // The cracks' lips at each frame (empty, or one list per frame), drawn in the crack colour.
  std::vector<ViewerSegments> frameCracks;
  std::vector<double> frameTimes;  // one per frame, or empty (frames are numbered)
  // Empty, one, or one per frame; each #V values, or #F of the frame's faces when the page's
  // fieldOnFaces (one field then belongs to the first frame's faces).
  std::vector<Eigen::VectorXd> fields;
  std::vector<ViewerMode> modes;  // empty, or modes of a one-frame mesh (a selector)
  ViewerSegments outline;         // drawn green on every frame, e.g. a faired region's boundary
  // A simulation's obstacles, drawn in its view in the renderer's obstacle colour: the spheres,
  // and each plane as a square of half side the framed radius about the foot of the frames' centre.
  std::vector<SphereObstacle> spheres;
  std::vector<PlaneObstacle> planes;

  // The faces frame `frame` has.
  const modeling::Triangles& trianglesAt(std::size_t frame) const;
};

// What the page shows. validate() names the field at fault: "ViewerPageSpec.stripeCount …".
struct ViewerPageSpec {
  std::vector<ViewerMesh> meshes;
  ViewerStyle style = ViewerStyle::Reflection;
  int stripeCount = 12;      // stripes (reflection) or bands (isophote) across [-1, 1]
  double stripeWidth = 0.5;  // dark fraction of a stripe period, in (0, 1)
  bool overlay = false;      // every mesh in one view, instead of one view each
  // Draw 4× multisampled (smoother silhouettes and lines). Off by default: the stripes are
  // smoothed in the shader either way, and on software rendering the samples cost about as much
  // as the rest of a frame (scripts/bench view).
  bool multisample = false;
  std::string fieldTitle;     // the legend's title (Field style)
  bool diverging = false;     // the field is signed: the diverging map on [-M, M]
  bool fieldOnFaces = false;  // the fields are per face, each face drawn in one colour
  // The legend's range; empty: from the values ([min, max], or [-M, M] when diverging).
  std::optional<std::pair<double, double>> fieldRange;
  std::string title = "flexure view";
  // The camera's framing. Empty: every frame of every mesh, seen from the renderer's azimuth at
  // 60° elevation. Else the bounding sphere of these points (#P by 3), seen along viewDirection
  // (toward the viewer; zero: the default direction) — a faired region along its mean normal, as
  // flexure fair's figure frames it.
  modeling::Positions framingPoints;
  Eigen::Vector3d viewDirection = Eigen::Vector3d::Zero();

  void validate() const;  // throws InputError
};

ViewerStyle parseViewerStyle(const std::string& name);  // InputError naming the choices
const char* viewerStyleName(ViewerStyle style);

// The page's HTML; the same spec gives the same bytes.
std::string viewerPageHtml(const ViewerPageSpec& spec);

// validate(), then the page written atomically (modeling/atomic_write.h); returns its size in
// bytes.
std::size_t writeViewerPage(const std::string& path, const ViewerPageSpec& spec);

}  // namespace flexure::render
