// Offscreen renders of a triangle mesh (OSMesa, GLSL 4.50): reflection lines, isophotes,
// highlight lines, plain shading and per-vertex scalar fields with a colour map and legend (the
// `error` style: |z − p(x, y)| against a polynomial surface; the `curvature` style: a signed
// per-vertex field the caller computes, on a diverging map; the `displacement` style: the distance
// |x_v − x̄_v| from a reference mesh of the same connectivity). Obstacles (spheres, planes), the
// lips of cracks and a caption can be drawn with the mesh. PNG out, written atomically.
//
// Camera. The mesh is centred on its bounding-box centre c and scaled by its bounding radius
// R = max |x_v − c|. The camera looks at c from the direction
//   e = (cos E sin A, −cos E cos A, sin E)   (A = azimuth, E = elevation, in degrees),
// with image right = (cos A, sin A, 0) and image up = e × right: azimuth 0, elevation 90 (the
// default) looks straight down −z with x to the right and y up; azimuth 0, elevation 0 looks
// along +y from the −y side. Orthographic framing fits the projected extents of the mesh with a
// 6 % margin; perspective (30° vertical field of view, the eye on the line through c along e)
// puts the eye as close as it can with every vertex in view, with the same margin.
//
// Normals. Smooth: vertex normals are area-weighted, n_v ∝ Σ_f∋v (x_1 − x_0) × (x_2 − x_0) (the
// unnormalized face normal is twice the face area times the unit normal), interpolated across
// faces and renormalized per pixel. Flat: each face's unit normal. Faces are lit on both sides
// (the normal is flipped on back faces), since the meshes are open surfaces.
//
// All environments (stripes, lights) are fixed to the camera, so a render depends only on the
// mesh's shape relative to the view.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "modeling/mesh.h"
#include "modeling/polynomial_surface.h"
#include "render/image.h"

namespace flexure::render {

class OffscreenContext;

// Plastic: a non-negative value per vertex (vertexScalars, a plastic strain) on the sequential
// colour map over [0, plasticMax] (empty: the largest), with a legend; only the simulation's frames
// have one, so parseRenderStyle does not name it.
enum class RenderStyle {
  Reflection,
  Isophote,
  Highlight,
  Shaded,
  Error,
  Curvature,
  Displacement,
  Plastic
};

// "reflection" | "isophote" | "highlight" | "shaded" | "error" | "curvature" | "displacement";
// InputError listing them otherwise.
RenderStyle parseRenderStyle(std::string_view name);
std::string_view renderStyleName(RenderStyle style);

struct Rgb {
  double r = 1.0, g = 1.0, b = 1.0;  // each in [0, 1]
};

// RenderOptions.background from "#rrggbb" (or "rrggbb"); InputError naming the field and quoting
// the text otherwise.
Rgb parseBackground(std::string_view text);

enum class Projection { Orthographic, Perspective };

// Obstacles drawn with the mesh (the shapes of optimize/assembly/obstacles.h, which render/ does
// not depend on): the sphere |x − centre| = radius, and the plane normal·x = offset, drawn as a
// square of half side kPlaneHalfSide × the framed points' radius (about their bounding-box centre)
// centred on the foot of that centre.
struct SphereObstacle {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 1.0;
};
struct PlaneObstacle {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
};
inline constexpr double kPlaneHalfSide = 1.0;

struct RenderOptions {
  RenderStyle style = RenderStyle::Reflection;
  int width = 1024, height = 1024;  // pixels, each in [32, 8192]
  double azimuthDegrees = 0.0, elevationDegrees = 90.0;
  Projection projection = Projection::Orthographic;
  Rgb background{1.0, 1.0, 1.0};
  bool smoothNormals = true;  // false: flat (face) normals
  bool edges = false;         // draw every triangle edge, one pixel wide
  // Stripes (reflection, isophote, highlight): the count across the range of the stripe
  // coordinate, the dark fraction of each period in (0, 1), and the angle of the stripes in the
  // image, counter-clockwise from the image x axis (90 = vertical stripes).
  int stripeCount = 12;
  double stripeWidth = 0.5;
  double stripeDirectionDegrees = 90.0;
  // Towards the light, in camera coordinates (x right, y up, z toward the viewer); normalized.
  std::array<double, 3> lightDirection{-0.35, 0.45, 1.0};
  // The `error` style: the surface p and the colour-map range of |z − p(x, y)|; the range is
  // [0, max over the vertices] when empty (a mesh exactly on p is all the colour of 0).
  modeling::PolynomialSurface surface;
  std::optional<double> errorMax;
  // The `error` style on a log scale: log10 |z − p| over [log10 errorLogFloor, log10 max] (values
  // below the floor take the bottom colour), for fields spanning decades (sharedErrorScale).
  std::optional<double> errorLogFloor;
  // The `displacement` style and exaggeration: the reference positions x̄ (#V by 3, the mesh's
  // connectivity), the colour range [0, displacementMax] of |x_v − x̄_v| (empty: the largest), in
  // the mesh's length unit. Every style draws x̄ + exaggeration (x − x̄) when x̄ is given (the
  // colours keep the true distances).
  modeling::Positions referencePositions;
  std::optional<double> displacementMax;
  double exaggeration = 1.0;
  // Replaces the legend's words on how its range was chosen ("largest", "given") when not empty,
  // e.g. "shared by all panels".
  std::string rangeNote;
  // Points the camera frames in place of the mesh's vertices (#P by 3; empty: the mesh's), so
  // that renders of a mesh before and after a change share one framing.
  modeling::Positions framingPoints;
  // The `curvature` style: a signed value per vertex (#V; the renderer does not compute it, so
  // render/ stays independent of curvature/), interpolated across faces on a diverging colour map
  // (blue negative, white 0, red positive) over [−m, m], m = curvatureRange(values) or
  // `curvatureMax` (values beyond take the end colours), with a legend titled `scalarLabel` and
  // the range "|symbol| ≤ m (98th percentile)" (or "largest", "given").
  std::vector<double> vertexScalars;
  std::optional<double> curvatureMax;
  std::optional<double> plasticMax;  // the plastic style's top of the colour map
  std::string plasticLabel = "plastic strain (1 / length)";  // the plastic style's legend title
  std::string scalarLabel = "H", scalarSymbol = "H";
  // The `curvature` style: the zero level set of vertexScalars drawn as dark lines about two
  // pixels wide (a mode's nodal lines), hidden where the surface hides it.
  bool zeroContour = false;
  // Obstacles drawn shaded in obstacleColour, framed with the mesh (every style).
  std::vector<SphereObstacle> spheres;
  std::vector<PlaneObstacle> planes;
  std::vector<modeling::Mesh> obstacleMeshes;  // drawn where their positions are
  Rgb obstacleColour{0.86, 0.62, 0.36};
  // Faces drawn in markedColour, lit, over every style (e.g. the faces at a mesh's problems,
  // modeling/mesh_check.h); indices into the mesh's faces.
  std::vector<int> markedFaces;
  Rgb markedColour{0.9, 0.1, 0.1};
  // A line of text at the top left of the image (e.g. a frame's time), in black or white against
  // the background.
  std::string caption;
  // Line segments drawn over the render (#2S by 3: rows 2s and 2s + 1 are the ends of segment s,
  // in the mesh's coordinates), e.g. the outline of a region: projected with the render's camera
  // and stroked with Cairo on top of the surface (never hidden by it), `outlineWidth` pixels wide
  // (round caps), in `outlineColour` (a green, apart from the grey stripes and the diverging
  // map's blue–white–red, so that it reads on every style but `error`'s viridis).
  modeling::Positions outlineSegments;
  Rgb outlineColour{0.0, 0.8, 0.2};
  double outlineWidth = 2.5;
  // Cracks: edges of the mesh (pairs of vertex indices, e.g. crackLipEdges) drawn in crackColour
  // over every style as a band `crackWidth` pixels wide along the edge inside each face that has
  // it, so that the surface hides it where it hides the face; the two lips of a closed crack lie
  // on one line and show as one band twice as wide. Magenta: apart from the grey stripes, the
  // shaded grey-blue, both colour maps, the obstacles' orange, the marking red and the outline
  // green. An edge that is no face's is refused.
  std::vector<std::array<int, 2>> crackEdges;
  Rgb crackColour{1.0, 0.0, 0.8};
  double crackWidth = 2.0;

  // Throws InputError starting with the field ("RenderOptions.stripeWidth …") for a value out of
  // the ranges above (the width leaves room for the legend of `error` and `curvature`).
  void validate() const;
};

// The options that belong to one style, as a person gives them (the command's flags, Python's
// keywords): the error style's surface p (PolynomialSurface::parse's text) and colour-map maximum,
// the curvature style's colour-map bound.
struct StyleOptions {
  std::optional<std::string> surface;
  std::optional<double> errorMax, curvatureMax;

  // Sets them on `options`, whose style is chosen. InputError naming the fields: the error style
  // without a surface, an option given to a style that does not draw it.
  void applyTo(RenderOptions& options) const;
};

// Legend ticks over [minimum, maximum]: the multiples in the range of the largest step 1, 2 or
// 5 × 10^k that gives at least four ([-0.75, 0.75] → -0.6, -0.4, …, 0.6).
std::vector<double> legendTicks(double minimum, double maximum);

// The default colour range m of a curvature map: the kCurvatureRangePercentile-th percentile of
// |value| (nearest rank), so that a few extreme vertices (a scan's spikes, the tip of a cone) do
// not wash the map out; the largest |value| when that percentile is 0; 1e-12 for an all-zero
// field. curvatureRangeRule says which in words: "98th percentile", or "largest" when no value
// exceeds m.
inline constexpr double kCurvatureRangePercentile = 98.0;
double curvatureRange(const std::vector<double>& values);
std::string curvatureRangeRule(const std::vector<double>& values);

// One colour scale for several `error` renders (a figure's panels), from every panel's vertex
// errors: errorMax the largest error over all panels (1e-12 when all are 0); when the largest
// panel maximum exceeds kLogScaleDecades decades times the smallest positive one, a log scale with
// errorLogFloor one decade under that smallest maximum (and at least 1e-16 × errorMax).
inline constexpr double kLogScaleDecades = 2.0;
struct ErrorScale {
  double errorMax = 1e-12;
  std::optional<double> errorLogFloor;
};
ErrorScale sharedErrorScale(const std::vector<std::vector<double>>& panelErrors);

// Width in pixels of the legend strip on the right of `error`, `curvature` and `displacement`
// renders (the mesh is framed in the remaining width).
inline constexpr int kLegendWidth = 130;

// Renders `mesh` (a valid mesh: see mesh.h) with an 8× multisampled framebuffer (fewer when the GL
// allows fewer), resolved to one sample per pixel. Throws InputError for options out of range,
// RenderError (offscreen_context.h) when OSMesa or GL fails.
Image renderMesh(OffscreenContext& context, const modeling::Mesh& mesh,
                 const RenderOptions& options);
// Wall-clock seconds of one render's phases (bench/render_bench.cpp): framing, the vertex soup,
// upload and draw (finished with glFinish: llvmpipe draws lazily), then the multisample resolve
// and glReadPixels. A null `timings` skips the extra glFinish.
struct RenderTimings {
  double uploadDraw = 0.0, readback = 0.0;
};
Image renderMesh(OffscreenContext& context, const modeling::Mesh& mesh,
                 const RenderOptions& options, RenderTimings* timings);
// The same with a context of its own on the default OSMesa library.
Image renderMesh(const modeling::Mesh& mesh, const RenderOptions& options);

// The per-vertex values the `error` style colours: |z_v − p(x_v, y_v)|, #V.
std::vector<double> vertexSurfaceErrors(const modeling::Mesh& mesh,
                                        const modeling::PolynomialSurface& surface);

// The per-vertex values the `displacement` style colours: |x_v − x̄_v|, #V; InputError when the
// vertex counts differ.
std::vector<double> vertexDisplacements(const modeling::Positions& positions,
                                        const modeling::Positions& reference);

// The lips of the cracks a cut opened (modeling/crack_cut.h): the boundary edges of the mesh
// (`triangles`, #F by 3) that have a twin, another boundary edge whose ends lie at the same rest
// positions (`rest`, #V by 3), exactly: a cut duplicates the crack's vertices at their rest
// positions and keeps a tip vertex whole, so each lip of a crack, tip edges included, is the twin
// of the one across it. A mesh with no coincident vertices has none.
std::vector<std::array<int, 2>> crackLipEdges(const modeling::Positions& rest,
                                              const modeling::Triangles& triangles);

// The image as PNG bytes (8-bit RGB, opaque; deterministic), and written to `path` atomically.
std::string encodePng(const Image& image);
void writePng(const std::string& path, const Image& image);

}  // namespace flexure::render
