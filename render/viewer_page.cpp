#include "render/viewer_page.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "render/colour_map.h"
#include "render/mesh_renderer.h"
#include "render/mesh_shaders.h"
#include "render/viewer_assets.h"

namespace flexure::render {
namespace {

[[noreturn]] void fail(const std::string& field, const std::string& what) {
  throw InputError("ViewerPageSpec." + field + " " + what);
}

// RFC 4648 base64 of `size` bytes.
std::string base64(const unsigned char* bytes, std::size_t size) {
  static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const std::uint32_t a = bytes[i], b = i + 1 < size ? bytes[i + 1] : 0,
                        c = i + 2 < size ? bytes[i + 2] : 0;
    const std::uint32_t word = (a << 16) | (b << 8) | c;
    out += digits[(word >> 18) & 63];
    out += digits[(word >> 12) & 63];
    out += i + 1 < size ? digits[(word >> 6) & 63] : '=';
    out += i + 2 < size ? digits[word & 63] : '=';
  }
  return out;
}

// Little-endian 32-bit words (the page reads them as Float32Array / Uint32Array on a
// little-endian machine, which every browser platform is).
template <typename T>
std::string base64Words(const std::vector<T>& words) {
  static_assert(sizeof(T) == 4);
  std::vector<unsigned char> bytes(4 * words.size());
  for (std::size_t i = 0; i < words.size(); ++i) {
    std::uint32_t w;
    std::memcpy(&w, &words[i], 4);
    for (int k = 0; k < 4; ++k) bytes[4 * i + k] = static_cast<unsigned char>(w >> (8 * k));
  }
  return base64(bytes.data(), bytes.size());
}

// A JSON string literal, with "</" written "<\/" so that it cannot close the page's <script>.
std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char code[8];
      std::snprintf(code, sizeof code, "\\u%04x", c);
      out += code;
    } else if (c == '/' && i > 0 && text[i - 1] == '<') {
      out += "\\/";
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string htmlText(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", x);
  return text;
}

std::string shortNumber(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

// The colour map's range over every field of every mesh: [min, max] for a sequential field;
// [-M, M] for a diverging one, M the 98th percentile of |value| (render/'s curvature default).
std::pair<double, double> fieldRange(const ViewerPageSpec& spec) {
  if (spec.fieldRange) return *spec.fieldRange;
  std::vector<double> values;
  for (const ViewerMesh& m : spec.meshes)
    for (const Eigen::VectorXd& f : m.fields) values.insert(values.end(), f.begin(), f.end());
  if (values.empty()) return {0.0, 1.0};
  if (spec.diverging) {
    for (double& v : values) v = std::abs(v);
    const std::size_t k = std::min(values.size() - 1, values.size() * 98 / 100);
    std::nth_element(values.begin(), values.begin() + k, values.end());
    const double m = values[k] > 0.0 ? values[k] : 1.0;
    return {-m, m};
  }
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  return {*lo, *hi > *lo ? *hi : *lo + 1.0};
}

// Segments as the vertex pairs of their points (4 words a segment) and the points' t (2 floats a
// segment): "\"lineEnds\":…,\"lineT\":…".
std::string segmentsData(const ViewerSegments& segments) {
  std::vector<float> t;
  std::vector<std::uint32_t> ends;
  for (const auto& [p, q] : segments)
    for (const ViewerLinePoint& point : {p, q}) {
      ends.push_back(static_cast<std::uint32_t>(point.a));
      ends.push_back(static_cast<std::uint32_t>(point.b));
      t.push_back(static_cast<float>(point.t));
    }
  return "\"lineEnds\":\"" + base64Words(ends) + "\",\"lineT\":\"" + base64Words(t) + "\"";
}

// A mesh's modes: each its label, φ (#V·3 floats) and its nodal lines (segmentsData).
std::string modesData(const ViewerMesh& m) {
  std::string out = "[";
  for (const ViewerMode& mode : m.modes) {
    std::vector<float> shape;
    for (Eigen::Index v = 0; v < mode.shape.rows(); ++v)
      for (int k = 0; k < 3; ++k) shape.push_back(static_cast<float>(mode.shape(v, k)));
    out += std::string(out.size() > 1 ? "," : "") + "{\"label\":" + jsonString(mode.label) +
           ",\"shape\":\"" + base64Words(shape) + "\"," + segmentsData(mode.nodalLines) + "}";
  }
  return out + "]";
}

// A mesh's obstacles: "[[x, y, z, r], …],\"planes\":[[nx, ny, nz, d], …]".
std::string obstaclesData(const ViewerMesh& m) {
  std::string spheres, planes;
  for (const SphereObstacle& s : m.spheres)
    spheres += std::string(spheres.empty() ? "" : ",") + "[" + number(s.centre.x()) + "," +
               number(s.centre.y()) + "," + number(s.centre.z()) + "," + number(s.radius) + "]";
  for (const PlaneObstacle& p : m.planes)
    planes += std::string(planes.empty() ? "" : ",") + "[" + number(p.normal.x()) + "," +
              number(p.normal.y()) + "," + number(p.normal.z()) + "," + number(p.offset) + "]";
  return "[" + spheres + "],\"planes\":[" + planes + "]";
}

std::vector<std::uint32_t> triangleWords(const modeling::Triangles& triangles) {
  std::vector<std::uint32_t> words;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) words.push_back(static_cast<std::uint32_t>(triangles(f, k)));
  return words;
}

Eigen::Index largestVertexCount(const ViewerMesh& m) {
  Eigen::Index count = 0;
  for (const modeling::Positions& x : m.frames) count = std::max(count, x.rows());
  return count;
}

// The frames (and fields), each padded to the largest vertex count with copies of its first
// vertex (no face of that frame names them), so that the page reads frame k at k·#V·3.
std::vector<float> paddedFrames(const ViewerMesh& m, Eigen::Index vertices) {
  std::vector<float> positions;
  for (const modeling::Positions& x : m.frames)
    for (Eigen::Index v = 0; v < vertices; ++v)
      for (int k = 0; k < 3; ++k)
        positions.push_back(static_cast<float>(x(v < x.rows() ? v : 0, k)));
  return positions;
}

// The fields, each padded to `count` values (vertices, or faces) with copies of its first.
std::vector<float> paddedFields(const ViewerMesh& m, Eigen::Index count) {
  std::vector<float> fields;
  for (const Eigen::VectorXd& f : m.fields)
    for (Eigen::Index v = 0; v < count; ++v)
      fields.push_back(static_cast<float>(v < f.size() ? f[v] : f[0]));
  return fields;
}

Eigen::Index largestFaceCount(const ViewerMesh& m) {
  Eigen::Index count = m.triangles.rows();
  for (const ViewerFaceChange& c : m.faceChanges) count = std::max(count, c.triangles.rows());
  return count;
}

// The face changes ("[{\"frame\":k,\"triangles\":…},…]") and each frame's cracks (segmentsData
// of them all and "crackStarts": the first segment of each frame, then the total).
std::string cutsData(const ViewerMesh& m) {
  std::string changes = "[";
  for (const ViewerFaceChange& c : m.faceChanges)
    changes += std::string(changes.size() > 1 ? "," : "") +
               "{\"frame\":" + std::to_string(c.frame) + ",\"triangles\":\"" +
               base64Words(triangleWords(c.triangles)) + "\"}";
  ViewerSegments cracks;
  std::string starts = "[";
  for (const ViewerSegments& frame : m.frameCracks) {
    starts += std::to_string(cracks.size()) + ",";
    cracks.insert(cracks.end(), frame.begin(), frame.end());
  }
  starts += std::to_string(cracks.size()) + "]";
  return changes + "],\"cracks\":{" + segmentsData(cracks) + ",\"starts\":" + starts + "}";
}

std::string meshData(const ViewerMesh& m, bool fieldOnFaces) {
  const Eigen::Index vertices = largestVertexCount(m), faces = largestFaceCount(m);
  const std::vector<float> positions = paddedFrames(m, vertices),
                           fields = paddedFields(m, fieldOnFaces ? faces : vertices);
  std::string times = "[";
  for (std::size_t i = 0; i < m.frameTimes.size(); ++i)
    times += (i ? "," : "") + number(m.frameTimes[i]);
  return "{\"name\":" + jsonString(m.name) + ",\"vertexCount\":" + std::to_string(vertices) +
         ",\"faceCount\":" + std::to_string(faces) +
         ",\"frameCount\":" + std::to_string(m.frames.size()) +
         ",\"fieldCount\":" + std::to_string(m.fields.size()) + ",\"times\":" + times + "]" +
         ",\"triangles\":\"" + base64Words(triangleWords(m.triangles)) + "\",\"positions\":\"" +
         base64Words(positions) + "\",\"fields\":" +
         (fields.empty() ? std::string("null") : "\"" + base64Words(fields) + "\"") +
         ",\"faceChanges\":" + cutsData(m) + ",\"modes\":" + modesData(m) + ",\"outline\":{" +
         segmentsData(m.outline) + "}" + ",\"spheres\":" + obstaclesData(m) + "}";
}

// "null", or {"points": #P·3 floats, "direction": [x, y, z] (zero: the default)}.
std::string framingData(const ViewerPageSpec& spec) {
  if (spec.framingPoints.rows() == 0) return "null";
  std::vector<float> points;
  for (Eigen::Index v = 0; v < spec.framingPoints.rows(); ++v)
    for (int k = 0; k < 3; ++k) points.push_back(static_cast<float>(spec.framingPoints(v, k)));
  const Eigen::Vector3d d =
      spec.viewDirection.norm() > 0.0 ? spec.viewDirection.normalized() : Eigen::Vector3d::Zero();
  return "{\"points\":\"" + base64Words(points) + "\",\"direction\":[" + number(d.x()) + "," +
         number(d.y()) + "," + number(d.z()) + "]}";
}

std::string pageData(const ViewerPageSpec& spec) {
  const ColourMap& map = spec.diverging ? divergingColourMap() : sequentialColourMap();
  const auto [lo, hi] = fieldRange(spec);
  std::string stops;
  for (const Rgb& c : map.stops)
    stops += std::string(stops.empty() ? "" : ",") + "[" + number(c.r) + "," + number(c.g) + "," +
             number(c.b) + "]";
  const int styleNumber = spec.style == ViewerStyle::Reflection ? 0
                          : spec.style == ViewerStyle::Isophote ? 1
                          : spec.style == ViewerStyle::Shaded   ? 3
                                                                : 4;
  const RenderOptions defaults;  // the offscreen renderer's light and stripe angle
  std::string meshes;
  for (const ViewerMesh& m : spec.meshes)
    meshes += (meshes.empty() ? "" : ",") + meshData(m, spec.fieldOnFaces);
  return "{\"style\":" + std::to_string(styleNumber) +
         ",\"stripeCount\":" + std::to_string(spec.stripeCount) +
         ",\"stripeWidth\":" + number(spec.stripeWidth) +
         ",\"stripeDirectionDegrees\":" + number(defaults.stripeDirectionDegrees) + ",\"light\":[" +
         number(defaults.lightDirection[0]) + "," + number(defaults.lightDirection[1]) + "," +
         number(defaults.lightDirection[2]) + "]" +
         ",\"azimuthDegrees\":" + number(defaults.azimuthDegrees) + ",\"obstacleColour\":[" +
         number(defaults.obstacleColour.r) + "," + number(defaults.obstacleColour.g) + "," +
         number(defaults.obstacleColour.b) + "]" + ",\"crackColour\":[" +
         number(defaults.crackColour.r) + "," + number(defaults.crackColour.g) + "," +
         number(defaults.crackColour.b) + "]" + ",\"elevationDegrees\":" + number(60.0) +
         ",\"overlay\":" + (spec.overlay ? "true" : "false") +
         ",\"multisample\":" + (spec.multisample ? "true" : "false") +
         ",\"framing\":" + framingData(spec) + ",\"fieldTitle\":" + jsonString(spec.fieldTitle) +
         ",\"fieldOnFaces\":" + (spec.fieldOnFaces ? "true" : "false") + ",\"range\":[" +
         number(lo) + "," + number(hi) + "],\"rangeText\":[" + jsonString(shortNumber(lo)) + "," +
         jsonString(shortNumber(hi)) + "],\"stops\":[" + stops + "],\"meshes\":[" + meshes + "]}";
}

// The template with each "@NAME@" of `parts` replaced, in one pass over the template only (a
// mesh name that spells a placeholder stays as written).
std::string filledTemplate(std::string_view page,
                           const std::vector<std::pair<std::string, std::string_view>>& parts) {
  std::string out;
  std::size_t from = 0;
  while (true) {
    std::size_t next = std::string_view::npos;
    const std::pair<std::string, std::string_view>* found = nullptr;
    for (const auto& part : parts) {
      const std::size_t at = page.find(part.first, from);
      if (at < next) next = at, found = &part;
    }
    if (!found) break;
    out.append(page.substr(from, next - from));
    out.append(found->second);
    from = next + found->first.size();
  }
  out.append(page.substr(from));
  return out;
}

void validateSegments(const ViewerSegments& segments, Eigen::Index vertices,
                      const std::string& at) {
  for (const auto& [p, q] : segments)
    for (const ViewerLinePoint& point : {p, q})
      if (point.a < 0 || point.b < 0 || point.a >= vertices || point.b >= vertices ||
          !(point.t >= 0.0 && point.t <= 1.0))
        fail(at, "has a point off the mesh (vertices 0.." + std::to_string(vertices - 1) +
                     ", t in [0, 1])");
}

void validateFaces(const ViewerMesh& m, const std::string& at) {
  if (m.triangles.rows() == 0) fail(at + ".triangles", "is empty (" + m.name + ")");
  for (std::size_t k = 0; k < m.faceChanges.size(); ++k) {
    const ViewerFaceChange& c = m.faceChanges[k];
    const std::size_t after = k == 0 ? 0 : m.faceChanges[k - 1].frame;
    if (c.frame <= after || c.frame >= m.frames.size() || c.triangles.rows() == 0)
      fail(at + ".faceChanges", "[" + std::to_string(k) + "] must name a later frame below " +
                                    std::to_string(m.frames.size()) + " and have faces");
  }
  for (std::size_t f = 0; f < m.frames.size(); ++f) {
    const modeling::Triangles& t = m.trianglesAt(f);
    const Eigen::Index vertices = m.frames[f].rows();
    if (t.minCoeff() < 0 || t.maxCoeff() >= vertices)
      fail(at + ".triangles", "of frame " + std::to_string(f) + " name a vertex outside 0.." +
                                  std::to_string(vertices - 1));
    if (f > 0 && &t == &m.trianglesAt(f - 1) && vertices != m.frames[f - 1].rows())
      fail(at + ".frames", "frame " + std::to_string(f) + " has " + std::to_string(vertices) +
                               " vertices, frame " + std::to_string(f - 1) + " has " +
                               std::to_string(m.frames[f - 1].rows()) + " and the same faces");
    if (!m.frames[f].allFinite())
      fail(at + ".frames", "frame " + std::to_string(f) + " has a coordinate that is not finite");
  }
}

// The fields: one, or one per frame; each a finite value per vertex (per face when `onFaces`) of
// its frame, a single one its first frame's.
void validateFields(const ViewerMesh& m, bool onFaces, const std::string& at) {
  if (m.fields.size() > 1 && m.fields.size() != m.frames.size())
    fail(at + ".fields", "has " + std::to_string(m.fields.size()) + " fields for " +
                             std::to_string(m.frames.size()) + " frames (give one or one each)");
  if (onFaces && m.fields.size() == 1 && !m.faceChanges.empty())
    fail(at + ".fields", "has one per-face field for frames whose faces change");
  if (onFaces && !m.fields.empty() && !m.modes.empty())
    fail(at + ".fields", "are per face on a mesh with modes (their fields are per vertex)");
  for (std::size_t k = 0; k < m.fields.size(); ++k) {
    const std::size_t frame = m.fields.size() == 1 ? 0 : k;
    const Eigen::Index count = onFaces ? m.trianglesAt(frame).rows() : m.frames[frame].rows();
    if (m.fields[k].size() != count)
      fail(at + ".fields", "has " + std::to_string(m.fields[k].size()) + " values for " +
                               std::to_string(count) + (onFaces ? " faces" : " vertices"));
    if (!m.fields[k].allFinite()) fail(at + ".fields", "has a value that is not finite");
  }
}

void validateMesh(const ViewerMesh& m, std::size_t i, bool fieldOnFaces) {
  const std::string at = "meshes[" + std::to_string(i) + "]";
  if (m.frames.empty()) fail(at + ".frames", "is empty: a mesh needs at least one frame");
  validateFaces(m, at);
  if (!m.frameTimes.empty() && m.frameTimes.size() != m.frames.size())
    fail(at + ".frameTimes", "has " + std::to_string(m.frameTimes.size()) + " times for " +
                                 std::to_string(m.frames.size()) + " frames");
  validateFields(m, fieldOnFaces, at);
  if (!m.frameCracks.empty() && m.frameCracks.size() != m.frames.size())
    fail(at + ".frameCracks", "has " + std::to_string(m.frameCracks.size()) + " lists for " +
                                  std::to_string(m.frames.size()) + " frames");
  for (std::size_t f = 0; f < m.frameCracks.size(); ++f)
    validateSegments(m.frameCracks[f], m.frames[f].rows(),
                     at + ".frameCracks[" + std::to_string(f) + "]");
}

void validateObstacles(const ViewerMesh& m, std::size_t i) {
  const std::string at = "meshes[" + std::to_string(i) + "]";
  for (const SphereObstacle& s : m.spheres)
    if (!s.centre.allFinite() || !(s.radius > 0.0 && std::isfinite(s.radius)))
      fail(at + ".spheres", "has a sphere whose centre is not finite or radius not > 0");
  for (const PlaneObstacle& p : m.planes)
    if (!p.normal.allFinite() || !(p.normal.norm() > 0.0) || !std::isfinite(p.offset))
      fail(at + ".planes", "has a plane whose normal is zero or not finite");
}

void validateModes(const ViewerMesh& m, std::size_t i) {
  validateObstacles(m, i);
  validateSegments(m.outline, m.frames.front().rows(), "meshes[" + std::to_string(i) + "].outline");
  if (m.modes.empty()) return;
  const std::string at = "meshes[" + std::to_string(i) + "].modes";
  if (m.frames.size() != 1)
    fail(at, "are animated about one rest frame, but the mesh has " +
                 std::to_string(m.frames.size()) + " frames");
  const Eigen::Index vertices = m.frames.front().rows();
  for (std::size_t k = 0; k < m.modes.size(); ++k) {
    const ViewerMode& mode = m.modes[k];
    const std::string here = at + "[" + std::to_string(k) + "]";
    if (mode.shape.rows() != vertices || !mode.shape.allFinite())
      fail(here + ".shape", "must be " + std::to_string(vertices) + " by 3 and finite");
    validateSegments(mode.nodalLines, vertices, here + ".nodalLines");
  }
}

}  // namespace

void ViewerPageSpec::validate() const {
  if (meshes.empty()) fail("meshes", "is empty: give at least one mesh");
  if (stripeCount < 1 || stripeCount > 1000) fail("stripeCount", "must be in [1, 1000]");
  if (!(stripeWidth > 0.0 && stripeWidth < 1.0)) fail("stripeWidth", "must be in (0, 1)");
  if (!framingPoints.allFinite()) fail("framingPoints", "has a coordinate that is not finite");
  if (!viewDirection.allFinite()) fail("viewDirection", "is not finite");
  if (fieldRange && !(std::isfinite(fieldRange->first) && std::isfinite(fieldRange->second) &&
                      fieldRange->first < fieldRange->second))
    fail("fieldRange", "must be finite with its low end below its high end");
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    validateMesh(meshes[i], i, fieldOnFaces);
    validateModes(meshes[i], i);
  }
  const bool anyField = std::any_of(meshes.begin(), meshes.end(),
                                    [](const ViewerMesh& m) { return !m.fields.empty(); });
  const bool allFields = std::all_of(meshes.begin(), meshes.end(),
                                     [](const ViewerMesh& m) { return !m.fields.empty(); });
  if (style == ViewerStyle::Field && !allFields)
    fail("style", "is field, but a mesh has no field values");
  if (style != ViewerStyle::Field && anyField)
    fail("style", std::string("is ") + viewerStyleName(style) + ", which draws no field");
}

const modeling::Triangles& ViewerMesh::trianglesAt(std::size_t frame) const {
  const modeling::Triangles* faces = &triangles;
  for (const ViewerFaceChange& c : faceChanges)
    if (c.frame <= frame) faces = &c.triangles;
  return *faces;
}

ViewerStyle parseViewerStyle(const std::string& name) {
  for (ViewerStyle s :
       {ViewerStyle::Reflection, ViewerStyle::Isophote, ViewerStyle::Shaded, ViewerStyle::Field})
    if (name == viewerStyleName(s)) return s;
  fail("style", "'" + name + "': expected reflection, isophote, shaded or field");
}

const char* viewerStyleName(ViewerStyle style) {
  switch (style) {
    case ViewerStyle::Reflection:
      return "reflection";
    case ViewerStyle::Isophote:
      return "isophote";
    case ViewerStyle::Shaded:
      return "shaded";
    case ViewerStyle::Field:
      return "field";
  }
  return "?";
}

std::string viewerPageHtml(const ViewerPageSpec& spec) {
  const std::string title = htmlText(spec.title), data = pageData(spec);
  return filledTemplate(viewerTemplate(), {{"@FLEXURE_TITLE@", title},
                                           {"@FLEXURE_DATA@", data},
                                           {"@FLEXURE_ORBIT_CONTROLS@", orbitControlsScript()},
                                           {"@FLEXURE_THREE@", threeScript()},
                                           {"@STRIPE_FUNCTIONS@", kStripeFunctions}});
}

std::size_t writeViewerPage(const std::string& path, const ViewerPageSpec& spec) {
  spec.validate();
  const std::string page = viewerPageHtml(spec);
  modeling::writeFileAtomically(path, page);
  return page.size();
}

}  // namespace flexure::render
