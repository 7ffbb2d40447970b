#include "render/field_map.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "modeling/errors.h"
#include "render/cairo_image.h"
#include "render/colour_map.h"

namespace flexure::render {

Image renderFieldMap(const FieldMap& map) {
  if (map.mesh == nullptr) throw InputError("field map: no mesh");
  const modeling::Mesh& mesh = *map.mesh;
  if (static_cast<int>(map.values.size()) != mesh.vertexCount()) {
    throw InputError("field map: " + std::to_string(map.values.size()) + " values for " +
                     std::to_string(mesh.vertexCount()) + " vertices");
  }
  if (map.size < 32 || map.size > 8192)
    throw InputError("field map: size " + std::to_string(map.size) + ": expected 32 .. 8192");

  // Frame the x, y bounding box with a margin of 4 % on every side, y up.
  const Eigen::Vector2d lo = mesh.positions.leftCols(2).colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = mesh.positions.leftCols(2).colwise().maxCoeff().transpose();
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  const double scale = 0.92 * map.size / extent;
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  auto pixel = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector2d(0.5 * map.size + scale * (p.x() - centre.x()),
                           0.5 * map.size - scale * (p.y() - centre.y()));
  };

  CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, map.size, map.size),
                       cairo_surface_destroy);
  CairoContext cr(cairo_create(surface.get()), cairo_destroy);
  cairo_set_source_rgb(cr.get(), 1.0, 1.0, 1.0);
  cairo_paint(cr.get());

  double bound = 0.0;
  for (double v : map.values) bound = std::max(bound, std::abs(v));
  if (!(bound > 0.0)) bound = 1.0;
  // One mesh-gradient patch per triangle, its fourth corner back at the first (a closed
  // three-sided Coons patch), colours at the corners.
  cairo_pattern_t* pattern = cairo_pattern_create_mesh();
  for (int f = 0; f < mesh.faceCount(); ++f) {
    cairo_mesh_pattern_begin_patch(pattern);
    for (int corner = 0; corner < 4; ++corner) {
      const int v = mesh.triangles(f, corner % 3);
      const Eigen::Vector2d q = pixel(mesh.positions.row(v).transpose());
      if (corner == 0) cairo_mesh_pattern_move_to(pattern, q.x(), q.y());
      if (corner == 1 || corner == 2) cairo_mesh_pattern_line_to(pattern, q.x(), q.y());
      const Rgb c = divergingColourMap().at(0.5 + 0.5 * map.values[v] / bound);
      cairo_mesh_pattern_set_corner_color_rgb(pattern, corner, c.r, c.g, c.b);
    }
    cairo_mesh_pattern_end_patch(pattern);
  }
  cairo_set_source(cr.get(), pattern);
  cairo_paint(cr.get());
  cairo_pattern_destroy(pattern);

  // The boundary: edges that belong to one face.
  std::map<std::pair<int, int>, int> edgeFaces;
  for (int f = 0; f < mesh.faceCount(); ++f)
    for (int i = 0; i < 3; ++i) {
      const int a = mesh.triangles(f, i), b = mesh.triangles(f, (i + 1) % 3);
      ++edgeFaces[{std::min(a, b), std::max(a, b)}];
    }
  const double width = std::max(1.0, map.size / 160.0);
  cairo_set_line_cap(cr.get(), CAIRO_LINE_CAP_ROUND);
  cairo_set_line_width(cr.get(), width);
  cairo_set_source_rgb(cr.get(), 0.45, 0.45, 0.45);
  for (const auto& [edge, faces] : edgeFaces) {
    if (faces != 1) continue;
    const Eigen::Vector2d a = pixel(mesh.positions.row(edge.first).transpose());
    const Eigen::Vector2d b = pixel(mesh.positions.row(edge.second).transpose());
    cairo_move_to(cr.get(), a.x(), a.y());
    cairo_line_to(cr.get(), b.x(), b.y());
  }
  cairo_stroke(cr.get());

  cairo_set_line_width(cr.get(), 1.5 * width);
  cairo_set_source_rgb(cr.get(), 0.0, 0.0, 0.0);
  for (const auto& [first, second] : map.lines) {
    const Eigen::Vector2d a = pixel(first), b = pixel(second);
    cairo_move_to(cr.get(), a.x(), a.y());
    cairo_line_to(cr.get(), b.x(), b.y());
  }
  cairo_stroke(cr.get());
  cairo_surface_flush(surface.get());
  return imageFromSurface(surface.get());
}

}  // namespace flexure::render
