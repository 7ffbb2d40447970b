// Offscreen renders of a triangle mesh: the render styles and colours by name, the options'
// ranges, and a render's flow (the scene, the GL rasterization, the legend, the outline and the
// caption).
#include "render/mesh_renderer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "modeling/errors.h"
#include "render/colour_map.h"
#include "render/legend.h"
#include "render/mesh_rasterizer.h"
#include "render/offscreen_context.h"
#include "render/overlays.h"
#include "render/scalar_fields.h"
#include "render/scene.h"

namespace flexure::render {
namespace {

// The styles that colour a per-vertex scalar and draw a legend.
bool hasLegend(RenderStyle style) {
  return style == RenderStyle::Error || style == RenderStyle::Curvature ||
         style == RenderStyle::Displacement || style == RenderStyle::Plastic;
}

}  // namespace

RenderStyle parseRenderStyle(std::string_view name) {
  for (RenderStyle style :
       {RenderStyle::Reflection, RenderStyle::Isophote, RenderStyle::Highlight, RenderStyle::Shaded,
        RenderStyle::Error, RenderStyle::Curvature, RenderStyle::Displacement}) {
    if (renderStyleName(style) == name) return style;
  }
  throw InputError(
      "unknown render style '" + std::string(name) +
      "' (known: reflection, isophote, highlight, shaded, error, curvature, displacement)");
}

std::string_view renderStyleName(RenderStyle style) {
  switch (style) {
    case RenderStyle::Reflection:
      return "reflection";
    case RenderStyle::Isophote:
      return "isophote";
    case RenderStyle::Highlight:
      return "highlight";
    case RenderStyle::Shaded:
      return "shaded";
    case RenderStyle::Error:
      return "error";
    case RenderStyle::Curvature:
      return "curvature";
    case RenderStyle::Displacement:
      return "displacement";
    case RenderStyle::Plastic:
      return "plastic";
  }
  return "?";
}

Rgb parseBackground(std::string_view text) {
  std::string_view hex = text;
  if (!hex.empty() && hex.front() == '#') hex.remove_prefix(1);
  const auto isHex = [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; };
  if (hex.size() != 6 || !std::all_of(hex.begin(), hex.end(), isHex)) {
    throw InputError("RenderOptions.background: colour '" + std::string(text) +
                     "' is not of the form #rrggbb");
  }
  const auto channel = [&](int k) {
    return std::stoi(std::string(hex.substr(2 * k, 2)), nullptr, 16) / 255.0;
  };
  return {channel(0), channel(1), channel(2)};
}

void StyleOptions::applyTo(RenderOptions& options) const {
  if (options.style == RenderStyle::Error) {
    if (!surface)
      throw InputError(
          "RenderOptions.style error needs RenderOptions.surface (e.g. quadratic:1,0,1)");
    options.surface = modeling::PolynomialSurface::parse(*surface);
    options.errorMax = errorMax;
  } else if (surface || errorMax) {
    throw InputError(
        "RenderOptions.surface and RenderOptions.errorMax apply to RenderOptions.style error only");
  }
  if (options.style == RenderStyle::Curvature)
    options.curvatureMax = curvatureMax;
  else if (curvatureMax)
    throw InputError("RenderOptions.curvatureMax applies to RenderOptions.style curvature only");
}

void RenderOptions::validate() const {
  const auto fail = [](const std::string& what) { throw InputError("RenderOptions." + what); };
  const int minWidth = hasLegend(style) ? kLegendWidth + 64 : 32;
  if (width < minWidth || width > 8192 || height < 32 || height > 8192) {
    fail("width x RenderOptions.height = " + std::to_string(width) + " x " +
         std::to_string(height) + " is outside [" + std::to_string(minWidth) +
         ", 8192] x [32, 8192] pixels");
  }
  if (!std::isfinite(azimuthDegrees)) fail("azimuthDegrees must be finite");
  if (!(std::abs(elevationDegrees) <= 90.0)) fail("elevationDegrees must lie in [-90, 90] degrees");
  if (stripeCount < 1 || stripeCount > 1000) fail("stripeCount must lie in [1, 1000]");
  if (!(stripeWidth > 0.0 && stripeWidth < 1.0))
    fail("stripeWidth (the dark fraction of a stripe period) must lie in (0, 1)");
  if (!std::isfinite(stripeDirectionDegrees)) fail("stripeDirectionDegrees must be finite");
  const double lightLength = std::hypot(lightDirection[0], lightDirection[1], lightDirection[2]);
  if (!(lightLength > 0.0) || !std::isfinite(lightLength))
    fail("lightDirection must be a finite non-zero vector");
  if (errorMax && !(*errorMax > 0.0 && std::isfinite(*errorMax)))
    fail("errorMax (the error colour-map maximum) must be positive");
  if (curvatureMax && !(*curvatureMax > 0.0 && std::isfinite(*curvatureMax)))
    fail("curvatureMax (the curvature colour-map bound) must be positive");
  if (style == RenderStyle::Curvature && vertexScalars.empty())
    fail("vertexScalars: the curvature style needs a value per vertex");
  if (errorLogFloor && !(*errorLogFloor > 0.0 && std::isfinite(*errorLogFloor)))
    fail("errorLogFloor (the bottom of the log error scale) must be positive");
  if (displacementMax && !(*displacementMax > 0.0 && std::isfinite(*displacementMax)))
    fail("displacementMax (the displacement colour-map maximum) must be positive");
  if (style == RenderStyle::Plastic && vertexScalars.empty())
    fail("vertexScalars: the plastic style needs a value per vertex");
  if (plasticMax && !(*plasticMax > 0.0 && std::isfinite(*plasticMax)))
    fail("plasticMax (the plastic colour-map maximum) must be positive");
  if (style == RenderStyle::Displacement && referencePositions.rows() == 0)
    fail("referencePositions: the displacement style needs the reference mesh's positions");
  if (!(exaggeration > 0.0 && std::isfinite(exaggeration)))
    fail("exaggeration must be a positive finite factor");
  if (exaggeration != 1.0 && referencePositions.rows() == 0)
    fail("exaggeration scales the displacement from referencePositions: give them");
  if (!referencePositions.allFinite()) fail("referencePositions must be finite");
  for (const SphereObstacle& sphere : spheres)
    if (!(sphere.radius > 0.0 && std::isfinite(sphere.radius)) || !sphere.centre.allFinite())
      fail("spheres: a sphere needs a finite centre and a positive radius");
  for (const PlaneObstacle& plane : planes)
    if (!(plane.normal.norm() > 0.0) || !plane.normal.allFinite() || !std::isfinite(plane.offset))
      fail("planes: a plane needs a finite non-zero normal and a finite offset");
  if (outlineSegments.rows() % 2 != 0 || !outlineSegments.allFinite()) {
    fail("outlineSegments needs finite segment ends in pairs (" +
         std::to_string(outlineSegments.rows()) + " rows)");
  }
  if (!(outlineWidth > 0.0 && outlineWidth <= 100.0))
    fail("outlineWidth must lie in (0, 100] pixels");
  if (!(crackWidth > 0.0 && crackWidth <= 100.0)) fail("crackWidth must lie in (0, 100] pixels");
  const auto inUnitCube = [](const Rgb& c) {
    return c.r >= 0 && c.r <= 1 && c.g >= 0 && c.g <= 1 && c.b >= 0 && c.b <= 1;
  };
  if (!inUnitCube(background)) fail("background: colour components must lie in [0, 1]");
  if (!inUnitCube(outlineColour)) fail("outlineColour: colour components must lie in [0, 1]");
  if (!inUnitCube(crackColour)) fail("crackColour: colour components must lie in [0, 1]");
}

Image renderMesh(OffscreenContext& context, const modeling::Mesh& mesh,
                 const RenderOptions& options) {
  return renderMesh(context, mesh, options, nullptr);
}

Image renderMesh(OffscreenContext& context, const modeling::Mesh& mesh,
                 const RenderOptions& options, RenderTimings* timings) {
  options.validate();
  if (mesh.faceCount() == 0) throw InputError("render: the mesh has no faces");
  if (options.referencePositions.rows() > 0 &&
      options.referencePositions.rows() != mesh.vertexCount()) {
    throw InputError("render: the reference has " +
                     std::to_string(options.referencePositions.rows()) + " vertices, the mesh " +
                     std::to_string(mesh.vertexCount()));
  }
  for (int f : options.markedFaces)
    if (f < 0 || f >= mesh.faceCount())
      throw InputError("RenderOptions.markedFaces: face " + std::to_string(f) +
                       " is not a face of the mesh (" + std::to_string(mesh.faceCount()) +
                       " faces)");
  const Scene scene = buildScene(mesh, options);
  if (!hasLegend(options.style)) {
    return withCaption(withOutline(rasterize(context, scene, options, options.width, options.height,
                                             {}, 0.0, 1.0, sequentialColourMap(), timings),
                                   scene, options),
                       options);
  }
  const ScalarField field = legendField(mesh, options);
  const int meshWidth = options.width - kLegendWidth;
  const Image meshImage =
      withOutline(rasterize(context, scene, options, meshWidth, options.height, field.values,
                            field.minimum, field.maximum, *field.map, timings),
                  scene, options);
  return withCaption(withLegend(meshImage, options, field.minimum, field.maximum, *field.map,
                                field.title, field.range, field.logarithmic),
                     options);
}

Image renderMesh(const modeling::Mesh& mesh, const RenderOptions& options) {
  options.validate();
  OffscreenContext context;
  return renderMesh(context, mesh, options);
}

}  // namespace flexure::render
