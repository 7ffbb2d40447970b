// The caption (a line of text at the top left, in black or white against the background) and
// the outline segments (projected with the render's camera) drawn over a render with Cairo.
#include "render/overlays.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "render/cairo_image.h"
#include "render/camera.h"

namespace flexure::render {
namespace {

constexpr const char* kFont = "DejaVu Sans";

}  // namespace

Image withCaption(const Image& image, const RenderOptions& o) {
  if (o.caption.empty()) return image;
  const CairoSurface surface = surfaceFromImage(image);
  CairoContext cr(cairo_create(surface.get()), &cairo_destroy);
  const double luminance =
      0.2126 * o.background.r + 0.7152 * o.background.g + 0.0722 * o.background.b;
  const double ink = luminance > 0.5 ? 0.0 : 1.0;
  cairo_set_source_rgb(cr.get(), ink, ink, ink);
  cairo_select_font_face(cr.get(), kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  const double size = std::clamp(0.04 * image.height, 10.0, 24.0);
  const double fitted = std::min(
      size, size * (image.width - 2.0 * kTextMargin) / textWidth(cr.get(), o.caption, size));
  cairo_set_font_size(cr.get(), fitted);
  cairo_move_to(cr.get(), 2.0 * kTextMargin, 2.0 * kTextMargin + fitted);
  cairo_show_text(cr.get(), o.caption.c_str());
  cairo_surface_flush(surface.get());
  return imageFromSurface(surface.get());
}

Image withOutline(const Image& meshImage, const Scene& scene, const RenderOptions& o) {
  if (o.outlineSegments.rows() == 0) return meshImage;
  const Camera camera = frameCamera(scene.framingPoints, o, meshImage.width, meshImage.height);
  const CairoSurface surface = surfaceFromImage(meshImage);
  CairoContext cr(cairo_create(surface.get()), &cairo_destroy);
  cairo_set_source_rgb(cr.get(), o.outlineColour.r, o.outlineColour.g, o.outlineColour.b);
  cairo_set_line_width(cr.get(), o.outlineWidth);
  cairo_set_line_cap(cr.get(), CAIRO_LINE_CAP_ROUND);
  const auto pixel = [&](Eigen::Index row) {
    const Eigen::Vector3d p =
        camera.worldToFrame * (o.outlineSegments.row(row).transpose() - camera.centre);
    const Eigen::Vector4d q = camera.frameToClip * p.homogeneous();
    return Eigen::Vector2d((q(0) / q(3) + 1.0) * 0.5 * meshImage.width,
                           (1.0 - q(1) / q(3)) * 0.5 * meshImage.height);
  };
  for (Eigen::Index s = 0; s + 1 < o.outlineSegments.rows(); s += 2) {
    const Eigen::Vector2d a = pixel(s), b = pixel(s + 1);
    cairo_move_to(cr.get(), a.x(), a.y());
    cairo_line_to(cr.get(), b.x(), b.y());
  }
  cairo_stroke(cr.get());
  cairo_surface_flush(surface.get());
  return imageFromSurface(surface.get());
}

}  // namespace flexure::render
