#include "render/mesh_renderer.h"

#include <cairo.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <utility>

#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/vertex_quantities.h"
#include "render/cairo_image.h"
#include "render/colour_map.h"
#include "render/offscreen_context.h"

namespace flexure::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kRequestedSamples = 8;
constexpr double kFramingMargin = 1.06;           // orthographic: extents × 1.06
constexpr double kPerspectiveFieldOfView = 30.0;  // degrees, vertical
constexpr int kMaxColourStops = 16;               // the shader's array size
constexpr const char* kFont = "DejaVu Sans";

// The styles that colour a per-vertex scalar and draw a legend.
bool hasLegend(RenderStyle style) {
  return style == RenderStyle::Error || style == RenderStyle::Curvature ||
         style == RenderStyle::Displacement || style == RenderStyle::Plastic;
}

// What is drawn: the mesh at its drawn positions (x̄ + k (x − x̄) when exaggerated), the obstacles
// as one triangle mesh, and the points the camera frames.
struct Scene {
  modeling::Mesh mesh;
  modeling::Mesh obstacles;
  modeling::Positions framingPoints;
};

// A sphere of `radius` about `centre` as a latitude–longitude mesh, kSphereSlices around and
// kSphereStacks pole to pole, appended to `out`.
constexpr int kSphereSlices = 48, kSphereStacks = 24;
void appendSphere(const SphereObstacle& sphere, modeling::Mesh& out) {
  const int first = out.vertexCount();
  const int ringCount = kSphereStacks - 1;
  modeling::Positions points(2 + ringCount * kSphereSlices, 3);
  points.row(0) = (sphere.centre + sphere.radius * Eigen::Vector3d::UnitZ()).transpose();
  points.row(1) = (sphere.centre - sphere.radius * Eigen::Vector3d::UnitZ()).transpose();
  for (int i = 0; i < ringCount; ++i) {
    const double polar = kPi * (i + 1) / kSphereStacks;
    for (int j = 0; j < kSphereSlices; ++j) {
      const double around = 2.0 * kPi * j / kSphereSlices;
      const Eigen::Vector3d u(std::sin(polar) * std::cos(around),
                              std::sin(polar) * std::sin(around), std::cos(polar));
      points.row(2 + i * kSphereSlices + j) = (sphere.centre + sphere.radius * u).transpose();
    }
  }
  const auto ring = [&](int i, int j) { return first + 2 + i * kSphereSlices + j % kSphereSlices; };
  std::vector<Eigen::Vector3i> faces;
  for (int j = 0; j < kSphereSlices; ++j) {
    faces.emplace_back(first, ring(0, j), ring(0, j + 1));
    faces.emplace_back(first + 1, ring(ringCount - 1, j + 1), ring(ringCount - 1, j));
    for (int i = 0; i + 1 < ringCount; ++i) {
      faces.emplace_back(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      faces.emplace_back(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
  }
  out.positions.conservativeResize(first + points.rows(), 3);
  out.positions.bottomRows(points.rows()) = points;
  const Eigen::Index faceStart = out.triangles.rows();
  out.triangles.conservativeResize(faceStart + static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f)
    out.triangles.row(faceStart + static_cast<Eigen::Index>(f)) = faces[f].transpose();
}

// The plane as a square of half side `halfSide` centred on the foot of `centre` on the plane.
void appendPlane(const PlaneObstacle& plane, const Eigen::Vector3d& centre, double halfSide,
                 modeling::Mesh& out) {
  const Eigen::Vector3d n = plane.normal.normalized();
  const Eigen::Vector3d foot = centre - (n.dot(centre) - plane.offset / plane.normal.norm()) * n;
  const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
  const int first = out.vertexCount();
  out.positions.conservativeResize(first + 4, 3);
  const double signs[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int k = 0; k < 4; ++k)
    out.positions.row(first + k) =
        (foot + halfSide * (signs[k][0] * u + signs[k][1] * w)).transpose();
  const Eigen::Index faceStart = out.triangles.rows();
  out.triangles.conservativeResize(faceStart + 2, 3);
  out.triangles.row(faceStart) << first, first + 1, first + 2;
  out.triangles.row(faceStart + 1) << first, first + 2, first + 3;
}

// The drawn mesh, the obstacles and the framed points: the given framing points (or the drawn
// mesh's), every sphere, and every plane's square, sized and centred by those points' bounding box.
Scene buildScene(const modeling::Mesh& mesh, const RenderOptions& o) {
  Scene scene;
  scene.mesh = mesh;
  if (o.referencePositions.rows() > 0 && o.exaggeration != 1.0) {
    scene.mesh.positions =
        o.referencePositions + o.exaggeration * (mesh.positions - o.referencePositions);
  }
  const modeling::Positions& base =
      o.framingPoints.rows() > 0 ? o.framingPoints : scene.mesh.positions;
  scene.obstacles.positions.resize(0, 3);
  scene.obstacles.triangles.resize(0, 3);
  for (const SphereObstacle& sphere : o.spheres) appendSphere(sphere, scene.obstacles);
  if (!o.planes.empty()) {
    const Eigen::Vector3d lo = base.colwise().minCoeff().transpose();
    const Eigen::Vector3d hi = base.colwise().maxCoeff().transpose();
    const Eigen::Vector3d centre = 0.5 * (lo + hi);
    const double radius =
        std::max((base.rowwise() - centre.transpose()).rowwise().norm().maxCoeff(), 1e-9);
    for (const PlaneObstacle& plane : o.planes)
      appendPlane(plane, centre, kPlaneHalfSide * radius, scene.obstacles);
  }
  scene.framingPoints.resize(base.rows() + scene.obstacles.positions.rows(), 3);
  scene.framingPoints.topRows(base.rows()) = base;
  scene.framingPoints.bottomRows(scene.obstacles.positions.rows()) = scene.obstacles.positions;
  return scene;
}

// What the shaders see. The "frame" is the camera-aligned object frame: origin at the mesh's
// bounding-box centre, axes (image right, image up, toward the viewer), unit = bounding radius.
struct Camera {
  Eigen::Matrix3d rotation;      // rows: image right, image up, toward the viewer (e)
  Eigen::Matrix3d worldToFrame;  // rotation / R
  Eigen::Vector3d centre;
  Eigen::Matrix4d frameToClip;
  bool perspective = false;
  Eigen::Vector3d eye{0.0, 0.0, 0.0};  // perspective only, in the frame
};

Eigen::Matrix3d viewRotation(double azimuthDegrees, double elevationDegrees) {
  const double a = azimuthDegrees * kPi / 180.0, e = elevationDegrees * kPi / 180.0;
  const Eigen::Vector3d toViewer(std::cos(e) * std::sin(a), -std::cos(e) * std::cos(a),
                                 std::sin(e));
  const Eigen::Vector3d right(std::cos(a), std::sin(a), 0.0);
  const Eigen::Vector3d up = toViewer.cross(right);
  Eigen::Matrix3d rows;
  rows.row(0) = right;
  rows.row(1) = up;
  rows.row(2) = toViewer;
  return rows;
}

Camera frameCamera(const modeling::Positions& points, const RenderOptions& o, int width,
                   int height) {
  const Eigen::Vector3d lo = points.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = points.colwise().maxCoeff().transpose();
  Camera camera;
  camera.centre = 0.5 * (lo + hi);
  const double radius = (points.rowwise() - camera.centre.transpose()).rowwise().norm().maxCoeff();
  if (!(radius > 0.0) || !std::isfinite(radius)) {
    throw InputError("render: the mesh has no extent (all vertices coincide) or is not finite");
  }
  camera.rotation = viewRotation(o.azimuthDegrees, o.elevationDegrees);
  camera.worldToFrame = camera.rotation / radius;
  const double aspect = static_cast<double>(width) / height;
  Eigen::Matrix4d clip = Eigen::Matrix4d::Zero();
  const Eigen::MatrixXd frame =
      (points.rowwise() - camera.centre.transpose()) * camera.worldToFrame.transpose();
  if (o.projection == Projection::Orthographic) {
    // Fit the projected extents: x ↦ (x − cx) / halfWidth, y ↦ (y − cy) / halfHeight; depth
    // z ∈ [−1.5, 1.5] (the frame's unit ball with room) ↦ −z / 1.5, nearer = smaller.
    const double x0 = frame.col(0).minCoeff(), x1 = frame.col(0).maxCoeff();
    const double y0 = frame.col(1).minCoeff(), y1 = frame.col(1).maxCoeff();
    const double halfWidth =
        kFramingMargin * std::max({0.5 * (x1 - x0), 0.5 * (y1 - y0) * aspect, 1e-6});
    const double halfHeight = halfWidth / aspect;
    clip(0, 0) = 1.0 / halfWidth;
    clip(0, 3) = -0.5 * (x0 + x1) / halfWidth;
    clip(1, 1) = 1.0 / halfHeight;
    clip(1, 3) = -0.5 * (y0 + y1) / halfHeight;
    clip(2, 2) = -1.0 / 1.5;
    clip(3, 3) = 1.0;
  } else {
    // The eye at (0, 0, D) looking down −z, D the smallest distance at which every vertex lies
    // inside the field of view with the margin: |x| / (D − z) ≤ tan(fovX / 2) / margin, and the
    // same for y. Then the usual perspective matrix on eye coordinates (frame − eye), with the
    // near and far planes just outside the mesh's depth range.
    const double fovY = kPerspectiveFieldOfView * kPi / 180.0;
    const double tanY = std::tan(0.5 * fovY) / kFramingMargin, tanX = tanY * aspect;
    double distance = 0.0;
    for (Eigen::Index v = 0; v < frame.rows(); ++v) {
      distance = std::max({distance, frame(v, 2) + std::abs(frame(v, 0)) / tanX,
                           frame(v, 2) + std::abs(frame(v, 1)) / tanY});
    }
    distance = std::max(distance, frame.col(2).maxCoeff() + 0.05);
    camera.perspective = true;
    camera.eye = Eigen::Vector3d(0.0, 0.0, distance);
    const double nearPlane = 0.9 * (distance - frame.col(2).maxCoeff());
    const double farPlane = 1.1 * (distance - frame.col(2).minCoeff()) + 0.01;
    const double f = 1.0 / std::tan(0.5 * fovY);
    Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
    projection(0, 0) = f / aspect;
    projection(1, 1) = f;
    projection(2, 2) = (farPlane + nearPlane) / (nearPlane - farPlane);
    projection(2, 3) = 2.0 * farPlane * nearPlane / (nearPlane - farPlane);
    projection(3, 2) = -1.0;
    Eigen::Matrix4d translate = Eigen::Matrix4d::Identity();
    translate(2, 3) = -distance;
    clip = projection * translate;
  }
  camera.frameToClip = clip;
  return camera;
}

// One record per triangle corner (no index buffer, so flat normals and the edge overlay's
// barycentric coordinates come free): frame position (3), frame normal (3), scalar (1), and one
// float m + 4 b for the material m (0 the mesh, 1 an obstacle, 2 a marked face of the mesh) and
// the face's crack bits b (faceCrackBits; 0 to 63, so the float is exact).
constexpr int kFloatsPerCorner = 8;

// Per face (#F), where cracks touch it: bit k set when the edge (t_{k+1}, t_{k+2}) opposite corner
// k is a crack edge, bit 3 + k when corner k is an end of one (its faces around the vertex fill the
// band's joints and caps). InputError for an edge that is no face's.
std::vector<int> faceCrackBits(const modeling::Mesh& mesh,
                               const std::vector<std::array<int, 2>>& crackEdges) {
  std::map<std::pair<int, int>, bool> isCrack;
  std::set<int> crackVertices;
  for (const auto& [a, b] : crackEdges) {
    isCrack[{std::min(a, b), std::max(a, b)}] = false;
    crackVertices.insert({a, b});
  }
  std::vector<int> bits(crackEdges.empty() ? 0 : mesh.faceCount(), 0);
  for (int f = 0; f < static_cast<int>(bits.size()); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (crackVertices.count(mesh.triangles(f, k))) bits[f] |= 8 << k;
      const int a = mesh.triangles(f, (k + 1) % 3), b = mesh.triangles(f, (k + 2) % 3);
      const auto edge = isCrack.find({std::min(a, b), std::max(a, b)});
      if (edge == isCrack.end()) continue;
      edge->second = true;
      bits[f] |= 1 << k;
    }
  }
  for (const auto& [edge, found] : isCrack)
    if (!found)
      throw InputError("RenderOptions.crackEdges: (" + std::to_string(edge.first) + ", " +
                       std::to_string(edge.second) + ") is not an edge of the mesh");
  return bits;
}

// `marked`: per face (#F, or empty), whether it takes material 2 instead of `material`;
// `crackBits`: per face (#F, or empty), faceCrackBits.
void appendCornerSoup(const modeling::Mesh& mesh, const Camera& camera, bool smooth,
                      const std::vector<double>& scalars, float material,
                      const std::vector<char>& marked, const std::vector<int>& crackBits,
                      std::vector<float>& soup) {
  const Eigen::MatrixX3d normals =
      smooth ? modeling::vertexNormals(mesh.positions, mesh.triangles) : Eigen::MatrixX3d();
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const auto t = mesh.triangles.row(f);
    Eigen::Vector3d faceNormal = Eigen::Vector3d::Zero();
    if (!smooth) {
      const Eigen::Vector3d x0 = mesh.positions.row(t(0)), x1 = mesh.positions.row(t(1)),
                            x2 = mesh.positions.row(t(2));
      faceNormal = (x1 - x0).cross(x2 - x0).normalized();
    }
    for (int k = 0; k < 3; ++k) {
      const int v = t(k);
      const Eigen::Vector3d p =
          camera.worldToFrame * (mesh.positions.row(v).transpose() - camera.centre);
      const Eigen::Vector3d n =
          camera.rotation * (smooth ? Eigen::Vector3d(normals.row(v).transpose()) : faceNormal);
      for (int i = 0; i < 3; ++i) soup.push_back(static_cast<float>(p(i)));
      for (int i = 0; i < 3; ++i) soup.push_back(static_cast<float>(n(i)));
      soup.push_back(scalars.empty() ? 0.0f : static_cast<float>(scalars[v]));
      const float faceMaterial = !marked.empty() && marked[f] ? 2.0f : material;
      soup.push_back(faceMaterial + (crackBits.empty() ? 0.0f : 4.0f * crackBits[f]));
    }
  }
}

// Vertex stage: frame coordinates in, clip coordinates out; the corner's barycentric coordinate
// (1 at its own corner, 0 at the others) comes from gl_VertexID, three corners per triangle.
const char* const kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in float scalar;
layout(location = 3) in float material;  // the material + 4 × the face's crack bits
uniform mat4 frameToClip;
out vec3 framePosition;
out vec3 frameNormal;
out float vertexScalar;
out float vertexMaterial;
out vec3 barycentric;
flat out int faceCracks;
void main() {
  framePosition = position;
  faceCracks = int(material + 0.5) / 4;
  vertexMaterial = material - 4.0 * float(faceCracks);
  frameNormal = normal;
  vertexScalar = scalar;
  barycentric = vec3(0.0);
  barycentric[gl_VertexID % 3] = 1.0;
  gl_Position = frameToClip * vec4(position, 1.0);
}
)";

// Fragment stage, in the camera-aligned frame (x right, y up, z toward the viewer). n is the unit
// normal flipped toward the front on back faces; v the unit vector toward the viewer: (0, 0, 1)
// for orthographic views, (eye − x)/|eye − x| for perspective. d = (−sin θ, cos θ, 0) is the unit
// vector across the stripes, θ the stripe angle in the image.
//
//  reflection  the view ray reflected about the normal, r = reflect(−v, n) = −v + 2 (n·v) n,
//              looks up a camera-locked environment of parallel stripes at infinity: stripe
//              coordinate s = N/2 · (r·d + 1), so the N stripes span r·d ∈ [−1, 1]. A plane seen
//              head-on reflects the single direction r = v ⟂ d: one colour.
//  isophote    bands of the diffuse term: s = N/2 · (n·L + 1), L the unit light direction.
//  highlight   highlight lines (Beier & Chen 1994): a family of parallel linear lights in the
//              plane z = h (h = 2, in front of the unit ball), running along the stripe angle and
//              spaced 2/N apart. The normal line x + λ n meets that plane at q = x + (h − x_z)/n_z
//              n; s = N/2 · (q·d). Dark lines where the normal line passes a light (s near an
//              integer); grey where n_z <= 0 (the normal line misses the plane).
//  shaded      Lambert plus a Blinn-Phong highlight: c (0.15 + 0.85 max(n·L, 0)) + 0.25 (n·H)^40.
//  scalar      (error, curvature, displacement) the interpolated vertex scalar through the
//              colour map on [lo, hi], unlit so that the colour reads as a value; with the zero
//              contour, black where |s| < 0.75 fwidth(s), fading out by 1.25 fwidth(s) (a line
//              about two pixels wide along the level set s = 0).
//  obstacle    (material 1, every style) Lambert in the obstacle colour: c (0.3 + 0.7 max(n·L, 0)).
//  marked      (material 2, a face RenderOptions.markedFaces names, every style) Lambert in the
//              marking colour, brighter: c (0.55 + 0.45 max(n·L, 0)), so that it reads as that
//              colour.
//  cracks      (the mesh's faces, every style) the crack colour, unlit, where the distance in
//              pixels to one of the face's crack edges or crack vertices is below the crack width,
//              blended over one pixel. With b the barycentric coordinates (affine across the face
//              on the screen, ∇ their pixel derivatives): to the edge opposite corner k, b_k /
//              |∇b_k|; to corner k, |G⁻¹ (b_i, b_j)| with G the rows ∇b_i, ∇b_j of the other two
//              corners (both vanish at corner k).
//
// Stripes are dark where s is within w/2 of an integer (w = the dark fraction of a period); the
// edges are smoothed over one pixel, |∇s| ≈ fwidth(s), against aliasing. The edge overlay paints
// blue the pixels within about one pixel of a triangle edge (a barycentric coordinate near 0).
const char* const kFragmentShader = R"(#version 450 core
in vec3 framePosition;
in vec3 frameNormal;
in float vertexScalar;
in float vertexMaterial;
in vec3 barycentric;
flat in int faceCracks;
uniform int style;  // 0 reflection, 1 isophote, 2 highlight, 3 shaded, 4 scalar
uniform int perspective;
uniform vec3 eye;
uniform vec3 lightDirection;
uniform vec2 stripeAcross;
uniform float stripeCount;
uniform float stripeWidth;
uniform int edges;
uniform vec2 scalarRange;
uniform int stopCount;
uniform vec3 stops[16];
uniform int zeroContour;
uniform vec3 obstacleColour;
uniform vec3 markedColour;
uniform vec3 crackColour;
uniform float crackWidth;
out vec4 colour;

const vec3 darkStripeColour = vec3(0.06);
const vec3 lightStripeColour = vec3(0.96);
const vec3 surfaceColour = vec3(0.72, 0.77, 0.86);
const vec3 edgeColour = vec3(0.15, 0.35, 0.85);  // visible on black and on white stripes

float darkStripe(float s) {
  float distanceToLine = abs(s - round(s));
  float halfPixel = 0.5 * max(fwidth(s), 1e-6);
  return 1.0 - smoothstep(0.5 * stripeWidth - halfPixel, 0.5 * stripeWidth + halfPixel,
                          distanceToLine);
}

vec3 colourMap(float value) {
  float t = clamp((value - scalarRange.x) / (scalarRange.y - scalarRange.x), 0.0, 1.0);
  float x = t * float(stopCount - 1);
  int i = min(int(floor(x)), stopCount - 2);
  return mix(stops[i], stops[i + 1], x - float(i));
}

// c with the face's cracks drawn over it (compiled in with CRACKS only); bx, by the pixel
// derivatives of the barycentric coordinates, taken on a face with cracks (faceCracks and the
// material are one value over a face, so the branches are the same across each 2 × 2 pixel quad
// the derivatives difference).
vec3 withCracks(vec3 c) {
#ifdef CRACKS
  if (faceCracks == 0) return c;
  vec3 bx = dFdx(barycentric), by = dFdy(barycentric);
  float nearest = 1e30;
  for (int k = 0; k < 3; ++k) {
    if ((faceCracks & (1 << k)) != 0)
      nearest = min(nearest, barycentric[k] / max(length(vec2(bx[k], by[k])), 1e-9));
    if ((faceCracks & (8 << k)) == 0) continue;
    int i = (k + 1) % 3, j = (k + 2) % 3;
    mat2 g = mat2(bx[i], bx[j], by[i], by[j]);  // columns: rows ∇b_i, ∇b_j
    if (abs(determinant(g)) > 1e-12)
      nearest = min(nearest, length(inverse(g) * vec2(barycentric[i], barycentric[j])));
  }
  c = mix(crackColour, c, smoothstep(crackWidth - 0.5, crackWidth + 0.5, nearest));
#endif
  return c;
}

void main() {
  vec3 n = normalize(frameNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 v = perspective != 0 ? normalize(eye - framePosition) : vec3(0.0, 0.0, 1.0);
  vec3 d = vec3(stripeAcross, 0.0);
  vec3 c;
  if (vertexMaterial > 1.5) {
    c = markedColour * (0.55 + 0.45 * max(dot(n, lightDirection), 0.0));
    colour = vec4(withCracks(c), 1.0);
    return;
  }
  if (vertexMaterial > 0.5) {
    colour = vec4(obstacleColour * (0.3 + 0.7 * max(dot(n, lightDirection), 0.0)), 1.0);
    return;
  }
  if (style == 0) {
    vec3 r = reflect(-v, n);
    c = mix(lightStripeColour, darkStripeColour, darkStripe(0.5 * stripeCount * (dot(r, d) + 1.0)));
  } else if (style == 1) {
    float s = 0.5 * stripeCount * (dot(n, lightDirection) + 1.0);
    c = mix(lightStripeColour, darkStripeColour, darkStripe(s));
  } else if (style == 2) {
    const float h = 2.0;
    if (n.z > 1e-3) {
      vec3 q = framePosition + (h - framePosition.z) / n.z * n;
      c = mix(lightStripeColour, darkStripeColour, darkStripe(0.5 * stripeCount * dot(q, d)));
    } else {
      c = vec3(0.5);
    }
  } else if (style == 3) {
    vec3 halfway = normalize(lightDirection + v);
    c = surfaceColour * (0.15 + 0.85 * max(dot(n, lightDirection), 0.0)) +
        vec3(0.25 * pow(max(dot(n, halfway), 0.0), 40.0));
  } else {
    c = colourMap(vertexScalar);
    if (zeroContour != 0) {
      float pixel = max(fwidth(vertexScalar), 1e-30);
      c = mix(vec3(0.0), c, smoothstep(0.75 * pixel, 1.25 * pixel, abs(vertexScalar)));
    }
  }
  if (edges != 0) {
    vec3 nearEdge = smoothstep(vec3(0.0), 1.2 * fwidth(barycentric), barycentric);
    c = mix(edgeColour, c, min(nearEdge.x, min(nearEdge.y, nearEdge.z)));
  }
  colour = vec4(withCracks(clamp(c, 0.0, 1.0)), 1.0);
}
)";

// Deletes what it holds when the render ends, thrown or not.
struct GlObjects {
  const GlFunctions& gl;
  GLuint program = 0, vertexArray = 0, buffer = 0;
  GLuint framebuffers[2] = {0, 0};      // multisampled, resolved
  GLuint renderbuffers[3] = {0, 0, 0};  // multisampled colour, multisampled depth, resolved colour

  explicit GlObjects(const GlFunctions& functions) : gl(functions) {}
  ~GlObjects() {
    if (program) gl.DeleteProgram(program);
    if (buffer) gl.DeleteBuffers(1, &buffer);
    if (vertexArray) gl.DeleteVertexArrays(1, &vertexArray);
    gl.DeleteFramebuffers(2, framebuffers);
    gl.DeleteRenderbuffers(3, renderbuffers);
  }
};

GLuint compileShader(const GlFunctions& gl, GLenum kind, const char* source, const char* name) {
  const GLuint shader = gl.CreateShader(kind);
  gl.ShaderSource(shader, 1, &source, nullptr);
  gl.CompileShader(shader);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {0};
    gl.GetShaderInfoLog(shader, sizeof log, nullptr, log);
    gl.DeleteShader(shader);
    throw RenderError(std::string("OSMesa: the ") + name + " shader did not compile: " + log);
  }
  return shader;
}

// `cracks`: the fragment shader with its crack test (CRACKS defined); without it that test is
// compiled out, since llvmpipe runs a branch's body for every pixel whatever its condition (a 1.3×
// slower draw of a large mesh at 1024² measured with the test kept).
GLuint linkProgram(const GlFunctions& gl, bool cracks) {
  const GLuint vertex = compileShader(gl, GL_VERTEX_SHADER, kVertexShader, "vertex");
  std::string fragmentSource = kFragmentShader;
  if (cracks) fragmentSource.insert(fragmentSource.find('\n') + 1, "#define CRACKS\n");
  const GLuint fragment = compileShader(gl, GL_FRAGMENT_SHADER, fragmentSource.c_str(), "fragment");
  const GLuint program = gl.CreateProgram();
  gl.AttachShader(program, vertex);
  gl.AttachShader(program, fragment);
  gl.LinkProgram(program);
  gl.DeleteShader(vertex);
  gl.DeleteShader(fragment);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {0};
    gl.GetProgramInfoLog(program, sizeof log, nullptr, log);
    gl.DeleteProgram(program);
    throw RenderError(std::string("OSMesa: the shader program did not link: ") + log);
  }
  return program;
}

// The samples per pixel (kRequestedSamples, or fewer if the renderer has fewer); throws for an
// image larger than the renderer's largest renderbuffer.
GLsizei multisampleCount(const GlFunctions& gl, int width, int height) {
  GLint maxSamples = 1, maxRenderbuffer = 0;
  gl.GetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  gl.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxRenderbuffer);
  if (width > maxRenderbuffer || height > maxRenderbuffer) {
    throw InputError("render: " + std::to_string(width) + " x " + std::to_string(height) +
                     " pixels exceed the renderer's limit of " + std::to_string(maxRenderbuffer));
  }
  return std::max(1, std::min<GLint>(kRequestedSamples, maxSamples));
}

// The multisampled framebuffer (colour and depth) and the single-sampled one its samples resolve
// into, width × height pixels.
void createFramebuffers(const GlFunctions& gl, GlObjects& objects, int width, int height,
                        GLsizei samples) {
  gl.GenFramebuffers(2, objects.framebuffers);
  gl.GenRenderbuffers(3, objects.renderbuffers);
  gl.BindRenderbuffer(GL_RENDERBUFFER, objects.renderbuffers[0]);
  gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
  gl.BindRenderbuffer(GL_RENDERBUFFER, objects.renderbuffers[1]);
  gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
  gl.BindRenderbuffer(GL_RENDERBUFFER, objects.renderbuffers[2]);
  gl.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  gl.BindFramebuffer(GL_FRAMEBUFFER, objects.framebuffers[0]);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                             objects.renderbuffers[0]);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                             objects.renderbuffers[1]);
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw RenderError("OSMesa: the multisampled framebuffer is incomplete");
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, objects.framebuffers[1]);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                             objects.renderbuffers[2]);
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw RenderError("OSMesa: the resolve framebuffer is incomplete");
  }
  throwOnGlError(gl, "creating the framebuffers");
}

// The corner soup into a vertex buffer: position (3), normal (3), scalar (1), material and crack
// bits (1).
void uploadCornerSoup(const GlFunctions& gl, GlObjects& objects, const std::vector<float>& soup) {
  gl.GenVertexArrays(1, &objects.vertexArray);
  gl.BindVertexArray(objects.vertexArray);
  gl.GenBuffers(1, &objects.buffer);
  gl.BindBuffer(GL_ARRAY_BUFFER, objects.buffer);
  gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(soup.size() * sizeof(float)), soup.data(),
                GL_STATIC_DRAW);
  const GLsizei stride = kFloatsPerCorner * sizeof(float);
  gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                         reinterpret_cast<const void*>(3 * sizeof(float)));
  gl.VertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride,
                         reinterpret_cast<const void*>(6 * sizeof(float)));
  gl.VertexAttribPointer(3, 1, GL_FLOAT, GL_FALSE, stride,
                         reinterpret_cast<const void*>(7 * sizeof(float)));
  for (GLuint attribute = 0; attribute < 4; ++attribute) gl.EnableVertexAttribArray(attribute);
  throwOnGlError(gl, "uploading the mesh");
}

void setUniforms(const GlFunctions& gl, GLuint program, const Camera& camera,
                 const RenderOptions& o, double scalarMin, double scalarMax, const ColourMap& map) {
  gl.UseProgram(program);
  const auto uniform = [&](const char* name) { return gl.GetUniformLocation(program, name); };
  Eigen::Matrix4f clip = camera.frameToClip.cast<float>();  // column-major, as GL expects
  gl.UniformMatrix4fv(uniform("frameToClip"), 1, GL_FALSE, clip.data());
  const int styleCode[] = {0, 1, 2, 3, 4, 4, 4, 4};  // in RenderStyle's order
  gl.Uniform1i(uniform("style"), styleCode[static_cast<int>(o.style)]);
  gl.Uniform1i(uniform("perspective"), camera.perspective ? 1 : 0);
  gl.Uniform3f(uniform("eye"), static_cast<float>(camera.eye(0)), static_cast<float>(camera.eye(1)),
               static_cast<float>(camera.eye(2)));
  const Eigen::Vector3d light =
      Eigen::Vector3d(o.lightDirection[0], o.lightDirection[1], o.lightDirection[2]).normalized();
  gl.Uniform3f(uniform("lightDirection"), static_cast<float>(light(0)),
               static_cast<float>(light(1)), static_cast<float>(light(2)));
  const double theta = o.stripeDirectionDegrees * kPi / 180.0;
  gl.Uniform2f(uniform("stripeAcross"), static_cast<float>(-std::sin(theta)),
               static_cast<float>(std::cos(theta)));
  gl.Uniform1f(uniform("stripeCount"), static_cast<float>(o.stripeCount));
  gl.Uniform1f(uniform("stripeWidth"), static_cast<float>(o.stripeWidth));
  gl.Uniform1i(uniform("edges"), o.edges ? 1 : 0);
  gl.Uniform1i(uniform("zeroContour"), o.zeroContour ? 1 : 0);
  gl.Uniform3f(uniform("obstacleColour"), static_cast<float>(o.obstacleColour.r),
               static_cast<float>(o.obstacleColour.g), static_cast<float>(o.obstacleColour.b));
  gl.Uniform3f(uniform("markedColour"), static_cast<float>(o.markedColour.r),
               static_cast<float>(o.markedColour.g), static_cast<float>(o.markedColour.b));
  gl.Uniform3f(uniform("crackColour"), static_cast<float>(o.crackColour.r),
               static_cast<float>(o.crackColour.g), static_cast<float>(o.crackColour.b));
  gl.Uniform1f(uniform("crackWidth"), static_cast<float>(o.crackWidth));
  gl.Uniform2f(uniform("scalarRange"), static_cast<float>(scalarMin),
               static_cast<float>(scalarMax));
  std::vector<float> stops;
  for (const Rgb& c : map.stops) {
    stops.insert(stops.end(),
                 {static_cast<float>(c.r), static_cast<float>(c.g), static_cast<float>(c.b)});
  }
  static_assert(kMaxColourStops >= 7);
  gl.Uniform1i(uniform("stopCount"), static_cast<GLint>(map.stops.size()));
  gl.Uniform3fv(uniform("stops"), static_cast<GLsizei>(map.stops.size()), stops.data());
  throwOnGlError(gl, "setting the shader uniforms");
}

void drawTriangles(const GlFunctions& gl, const GlObjects& objects, const RenderOptions& o,
                   int width, int height, GLsizei faceCount) {
  gl.BindFramebuffer(GL_FRAMEBUFFER, objects.framebuffers[0]);
  gl.Viewport(0, 0, width, height);
  gl.Enable(GL_DEPTH_TEST);
  gl.Enable(GL_MULTISAMPLE);
  gl.Disable(GL_CULL_FACE);
  gl.ClearColor(static_cast<float>(o.background.r), static_cast<float>(o.background.g),
                static_cast<float>(o.background.b), 1.0f);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl.DrawArrays(GL_TRIANGLES, 0, 3 * faceCount);
  throwOnGlError(gl, "drawing the mesh");
}

// Resolve the samples (their average per pixel) and read back, bottom row first in GL.
std::vector<std::uint8_t> readResolvedPixels(const GlFunctions& gl, const GlObjects& objects,
                                             int width, int height) {
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, objects.framebuffers[0]);
  gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, objects.framebuffers[1]);
  gl.BlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, objects.framebuffers[1]);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  std::vector<std::uint8_t> bottomUp(static_cast<std::size_t>(4) * width * height);
  gl.ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottomUp.data());
  gl.Finish();
  throwOnGlError(gl, "reading the image back");
  return bottomUp;
}

// GL's rows (bottom first) as an image (top row first).
Image imageFromBottomUp(const std::vector<std::uint8_t>& bottomUp, int width, int height) {
  Image image;
  image.width = width;
  image.height = height;
  image.rgba.resize(bottomUp.size());
  const std::size_t rowBytes = static_cast<std::size_t>(4) * width;
  for (int y = 0; y < height; ++y) {
    std::copy_n(bottomUp.begin() + static_cast<std::ptrdiff_t>((height - 1 - y) * rowBytes),
                rowBytes, image.rgba.begin() + static_cast<std::ptrdiff_t>(y * rowBytes));
  }
  return image;
}

// Draws the mesh with GL into an image of `width` × `height` (the whole image, or the part left
// of the legend).
Image rasterize(OffscreenContext& context, const Scene& scene, const RenderOptions& o, int width,
                int height, const std::vector<double>& scalars, double scalarMin, double scalarMax,
                const ColourMap& map, RenderTimings* timings = nullptr) {
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point from) {
    return std::chrono::duration<double>(Clock::now() - from).count();
  };
  const Clock::time_point start = Clock::now();
  context.makeCurrent();
  const GlFunctions& gl = context.gl();
  gl.GetError();  // start clean
  const GLsizei samples = multisampleCount(gl, width, height);
  GlObjects objects(gl);
  createFramebuffers(gl, objects, width, height, samples);

  const Camera camera = frameCamera(scene.framingPoints, o, width, height);
  std::vector<float> soup;
  soup.reserve(static_cast<std::size_t>(scene.mesh.faceCount() + scene.obstacles.faceCount()) * 3 *
               kFloatsPerCorner);
  std::vector<char> marked;
  if (!o.markedFaces.empty()) marked.assign(scene.mesh.faceCount(), 0);
  for (int f : o.markedFaces) marked[f] = 1;
  appendCornerSoup(scene.mesh, camera, o.smoothNormals, scalars, 0.0f, marked,
                   faceCrackBits(scene.mesh, o.crackEdges), soup);
  appendCornerSoup(scene.obstacles, camera, true, {}, 1.0f, {}, {}, soup);
  objects.program = linkProgram(gl, !o.crackEdges.empty());
  uploadCornerSoup(gl, objects, soup);
  setUniforms(gl, objects.program, camera, o, scalarMin, scalarMax, map);
  drawTriangles(gl, objects, o, width, height,
                static_cast<GLsizei>(scene.mesh.faceCount() + scene.obstacles.faceCount()));
  Clock::time_point readStart = Clock::now();
  if (timings) {
    gl.Finish();  // llvmpipe draws lazily: without this the draw would be timed as the readback
    readStart = Clock::now();
    timings->uploadDraw = std::chrono::duration<double>(readStart - start).count();
  }
  const std::vector<std::uint8_t> bottomUp = readResolvedPixels(gl, objects, width, height);
  if (timings) timings->readback = seconds(readStart);
  return imageFromBottomUp(bottomUp, width, height);
}

// A tick's label: fixed-point with as many decimals as the tick step needs (0.2 → "0.4"), or
// %g for very small or large steps; a round-off zero prints as "0".
std::string tickLabel(double value, double step) {
  char label[32];
  if (std::abs(value) < 1e-9 * step) value = 0.0;
  if (step >= 1e-4 && step < 1e5) {
    const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
    std::snprintf(label, sizeof label, "%.*f", decimals, value);
  } else {
    std::snprintf(label, sizeof label, "%.3g", value);
  }
  return label;
}

// Whole decades in [minimum, maximum] (decimal logarithms), every one or every k-th so that there
// are at most eight.
std::vector<double> decadeTicks(double minimum, double maximum) {
  const double first = std::ceil(minimum - 1e-9), last = std::floor(maximum + 1e-9);
  const double stride = std::max(1.0, std::ceil((last - first + 1.0) / 8.0));
  std::vector<double> ticks;
  for (double k = first; k <= last; k += stride) ticks.push_back(k);
  return ticks;
}

std::string decadeLabel(double exponent) {
  char label[16];
  std::snprintf(label, sizeof label, "1e%d", static_cast<int>(std::lround(exponent)));
  return label;
}

// `text` at the top left of `image`, in black or white against the background.
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

// The mesh image on the left, and on the right a vertical colour bar of `map` from `minimum`
// (bottom) to `maximum` (top) with ticks at legendTicks, and above it `title` and `range` (how
// the range was chosen), each fitted to the legend's width.
// On a log scale `minimum` and `maximum` are decimal logarithms, the ticks whole decades labelled
// "1e-5".
Image withLegend(const Image& meshImage, const RenderOptions& o, double minimum, double maximum,
                 const ColourMap& map, const std::string& title, const std::string& range,
                 bool logarithmic = false) {
  CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, o.width, o.height),
                       &cairo_surface_destroy);
  CairoContext cr(cairo_create(surface.get()), &cairo_destroy);
  cairo_set_source_rgb(cr.get(), o.background.r, o.background.g, o.background.b);
  cairo_paint(cr.get());
  const CairoSurface meshSurface = surfaceFromImage(meshImage);
  cairo_set_source_surface(cr.get(), meshSurface.get(), 0.0, 0.0);
  cairo_paint(cr.get());

  const double luminance =
      0.2126 * o.background.r + 0.7152 * o.background.g + 0.0722 * o.background.b;
  const double ink = luminance > 0.5 ? 0.0 : 1.0;
  const double barLeft = meshImage.width + 14.0, barWidth = 18.0;
  const double barTop = std::round(0.18 * o.height), barBottom = std::round(0.82 * o.height);
  for (double y = barTop; y < barBottom; y += 1.0) {
    const Rgb c = map.at((barBottom - (y + 0.5)) / (barBottom - barTop));
    cairo_set_source_rgb(cr.get(), c.r, c.g, c.b);
    cairo_rectangle(cr.get(), barLeft, y, barWidth, 1.0);
    cairo_fill(cr.get());
  }
  cairo_set_source_rgb(cr.get(), ink, ink, ink);
  cairo_set_line_width(cr.get(), 1.0);
  cairo_rectangle(cr.get(), barLeft + 0.5, barTop + 0.5, barWidth - 1.0, barBottom - barTop - 1.0);
  cairo_stroke(cr.get());
  cairo_select_font_face(cr.get(), kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  const double textSize = std::clamp(0.022 * o.height, 10.0, 15.0);
  const std::vector<double> ticks =
      logarithmic ? decadeTicks(minimum, maximum) : legendTicks(minimum, maximum);
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : maximum - minimum;
  const double labelLeft = barLeft + barWidth + 8.0;
  const double labelWidth = o.width - kTextMargin - labelLeft;
  for (const double tick : ticks) {
    const double y = barBottom - (tick - minimum) / (maximum - minimum) * (barBottom - barTop);
    cairo_move_to(cr.get(), barLeft + barWidth, std::round(y) + 0.5);
    cairo_rel_line_to(cr.get(), 5.0, 0.0);
    cairo_stroke(cr.get());
    const std::string label = logarithmic ? decadeLabel(tick) : tickLabel(tick, step);
    const double size =
        std::min(textSize, textSize * labelWidth / textWidth(cr.get(), label, textSize));
    cairo_set_font_size(cr.get(), size);
    cairo_move_to(cr.get(), labelLeft, y + 0.35 * size);
    cairo_show_text(cr.get(), label.c_str());
  }
  // The title and the range line in the band above the bar, centred on the legend strip.
  const double legendLeft = meshImage.width, legendWidth = o.width - meshImage.width;
  const double bandHeight = (barTop - 0.5 * textSize) / 2.0;
  const TextLayout titleText =
      layOutText(cr.get(), title, textSize, legendWidth - 2.0 * kTextMargin, bandHeight);
  const TextLayout rangeText =
      layOutText(cr.get(), range, textSize, legendWidth - 2.0 * kTextMargin, bandHeight);
  showCentred(cr.get(), titleText, legendLeft + legendWidth / 2.0, bandHeight / 2.0);
  showCentred(cr.get(), rangeText, legendLeft + legendWidth / 2.0, 1.5 * bandHeight);
  return imageFromSurface(surface.get());
}

// The outline segments of `o` drawn over `meshImage` (the part of the render the mesh is framed
// in): each end x maps to the frame, p = (x − c) · worldToFrame, to clip coordinates
// q = frameToClip (p, 1), and to the pixel ((q_x / q_w + 1) w / 2, (1 − q_y / q_w) h / 2), image
// rows top to bottom as GL's viewport maps them, flipped.
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

// What a legend style colours: the per-vertex values, the colour map's range (decimal logarithms
// on a log scale), the map, and the legend's title and range words.
struct ScalarField {
  std::vector<double> values;
  double minimum = 0.0, maximum = 1.0;
  const ColourMap* map = nullptr;
  std::string title, range;
  bool logarithmic = false;
};

std::string rangeWords(const RenderOptions& o, const std::string& rule) {
  return o.rangeNote.empty() ? rule : o.rangeNote;
}

// The curvature style: a signed field on [−m, m], symmetric so that white is 0.
ScalarField curvatureField(const modeling::Mesh& mesh, const RenderOptions& o) {
  ScalarField field;
  field.values = o.vertexScalars;
  if (static_cast<int>(field.values.size()) != mesh.vertexCount()) {
    throw InputError("render: " + std::to_string(field.values.size()) + " curvature values for " +
                     std::to_string(mesh.vertexCount()) + " vertices");
  }
  for (double value : field.values)
    if (!std::isfinite(value)) throw InputError("render: a curvature value is not finite");
  const double bound = o.curvatureMax ? *o.curvatureMax : curvatureRange(field.values);
  char range[128];
  std::snprintf(range, sizeof range, "|%s| ≤ %.3g (%s)", o.scalarSymbol.c_str(), bound,
                rangeWords(o, o.curvatureMax ? "given" : curvatureRangeRule(field.values)).c_str());
  field.minimum = -bound;
  field.maximum = bound;
  field.map = &divergingColourMap();
  field.title = o.scalarLabel;
  field.range = range;
  return field;
}

// A magnitude on [0, max] (given or the largest; an all-zero field still needs a non-empty range:
// it then shows the colour of 0), or on a log scale [log10 floor, log10 max].
ScalarField magnitudeField(std::vector<double> values, std::optional<double> givenMaximum,
                           std::optional<double> logFloor, const RenderOptions& o) {
  ScalarField field;
  const double largest = *std::max_element(values.begin(), values.end());
  const double maximum = givenMaximum ? *givenMaximum : std::max(largest, 1e-12);
  char range[128];
  field.map = &sequentialColourMap();
  if (logFloor && *logFloor < maximum) {
    for (double& v : values) v = std::log10(std::max(v, *logFloor));
    field.minimum = std::log10(*logFloor);
    field.maximum = std::log10(maximum);
    field.logarithmic = true;
    std::snprintf(range, sizeof range, "%.2g to %.3g, log scale (%s)", *logFloor, maximum,
                  rangeWords(o, givenMaximum ? "given" : "largest").c_str());
  } else {
    field.maximum = maximum;
    std::snprintf(range, sizeof range, "0 to %.3g (%s)", maximum,
                  rangeWords(o, givenMaximum ? "given" : "largest").c_str());
  }
  field.values = std::move(values);
  field.range = range;
  return field;
}

ScalarField legendField(const modeling::Mesh& mesh, const RenderOptions& o) {
  if (o.style == RenderStyle::Curvature) return curvatureField(mesh, o);
  if (o.style == RenderStyle::Displacement) {
    ScalarField field = magnitudeField(vertexDisplacements(mesh.positions, o.referencePositions),
                                       o.displacementMax, std::nullopt, o);
    field.title = "|x − x̄| (mesh length unit)";
    return field;
  }
  if (o.style == RenderStyle::Plastic) {
    if (static_cast<int>(o.vertexScalars.size()) != mesh.vertexCount())
      throw InputError("render: " + std::to_string(o.vertexScalars.size()) +
                       " plastic strains for " + std::to_string(mesh.vertexCount()) + " vertices");
    ScalarField field = magnitudeField(o.vertexScalars, o.plasticMax, std::nullopt, o);
    field.title = o.plasticLabel;
    return field;
  }
  ScalarField field =
      magnitudeField(vertexSurfaceErrors(mesh, o.surface), o.errorMax, o.errorLogFloor, o);
  field.title = "|z − p(x, y)|";
  return field;
}

cairo_status_t appendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
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

Rgb parseColour(std::string_view text) {
  std::string_view hex = text;
  if (!hex.empty() && hex.front() == '#') hex.remove_prefix(1);
  const auto isHex = [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; };
  if (hex.size() != 6 || !std::all_of(hex.begin(), hex.end(), isHex)) {
    throw InputError("colour '" + std::string(text) + "' is not of the form #rrggbb");
  }
  const auto channel = [&](int k) {
    return std::stoi(std::string(hex.substr(2 * k, 2)), nullptr, 16) / 255.0;
  };
  return {channel(0), channel(1), channel(2)};
}

std::vector<double> vertexSurfaceErrors(const modeling::Mesh& mesh,
                                        const modeling::PolynomialSurface& surface) {
  std::vector<double> errors(mesh.vertexCount());
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    const auto x = mesh.positions.row(v);
    errors[v] = std::abs(x(2) - surface.height(x(0), x(1)));
  }
  return errors;
}

ErrorScale sharedErrorScale(const std::vector<std::vector<double>>& panelErrors) {
  ErrorScale scale;
  double largest = 0.0, smallestPositiveMaximum = std::numeric_limits<double>::infinity();
  for (const std::vector<double>& errors : panelErrors) {
    if (errors.empty()) continue;
    const double panelMaximum = *std::max_element(errors.begin(), errors.end());
    largest = std::max(largest, panelMaximum);
    if (panelMaximum > 0.0)
      smallestPositiveMaximum = std::min(smallestPositiveMaximum, panelMaximum);
  }
  scale.errorMax = std::max(largest, 1e-12);
  if (largest > 0.0 && largest > std::pow(10.0, kLogScaleDecades) * smallestPositiveMaximum)
    scale.errorLogFloor = std::max(0.1 * smallestPositiveMaximum, 1e-16 * largest);
  return scale;
}

std::vector<std::array<int, 2>> crackLipEdges(const modeling::Positions& rest,
                                              const modeling::Triangles& triangles) {
  // Each undirected edge with the faces that have it; then the boundary edges (one face) keyed by
  // their ends' rest positions, in order.
  std::map<std::pair<int, int>, int> faceCount;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles(f, k), b = triangles(f, (k + 1) % 3);
      ++faceCount[{std::min(a, b), std::max(a, b)}];
    }
  using Point = std::array<double, 3>;
  const auto point = [&](int v) { return Point{rest(v, 0), rest(v, 1), rest(v, 2)}; };
  std::map<std::pair<Point, Point>, std::vector<std::array<int, 2>>> boundaryAt;
  for (const auto& [edge, faces] : faceCount) {
    if (faces != 1) continue;
    const Point p = point(edge.first), q = point(edge.second);
    boundaryAt[{std::min(p, q), std::max(p, q)}].push_back({edge.first, edge.second});
  }
  std::vector<std::array<int, 2>> lips;
  for (const auto& [ends, edges] : boundaryAt)
    if (edges.size() > 1) lips.insert(lips.end(), edges.begin(), edges.end());
  return lips;
}

std::vector<double> vertexDisplacements(const modeling::Positions& positions,
                                        const modeling::Positions& reference) {
  if (positions.rows() != reference.rows()) {
    throw InputError("render: the reference has " + std::to_string(reference.rows()) +
                     " vertices, the mesh " + std::to_string(positions.rows()));
  }
  const Eigen::VectorXd distances = (positions - reference).rowwise().norm();
  return std::vector<double>(distances.data(), distances.data() + distances.size());
}

std::vector<double> legendTicks(double minimum, double maximum) {
  const double span = maximum - minimum;
  if (!(span > 0.0) || !std::isfinite(span)) return {minimum};
  // The largest step 1, 2 or 5 × 10^k with at least kMinimumTicks multiples in the range.
  constexpr int kMinimumTicks = 4;
  double decade = std::pow(10.0, std::ceil(std::log10(span)));
  for (;; decade /= 10.0) {
    for (const double mantissa : {5.0, 2.0, 1.0}) {
      const double step = mantissa * decade;
      const double first = std::ceil(minimum / step - 1e-9),
                   last = std::floor(maximum / step + 1e-9);
      if (last - first + 1.0 >= kMinimumTicks) {
        std::vector<double> ticks;
        for (double k = first; k <= last; k += 1.0) ticks.push_back(k * step);
        return ticks;
      }
    }
  }
}

double curvatureRange(const std::vector<double>& values) {
  if (values.empty()) return 1e-12;
  std::vector<double> magnitudes(values.size());
  std::transform(values.begin(), values.end(), magnitudes.begin(),
                 [](double v) { return std::abs(v); });
  // Nearest rank: the smallest |H| with at least kCurvatureRangePercentile % of the values at or
  // below it.
  const auto rank = static_cast<std::size_t>(
      std::ceil(kCurvatureRangePercentile / 100.0 * static_cast<double>(magnitudes.size())));
  const std::size_t index = std::clamp<std::size_t>(rank, 1, magnitudes.size()) - 1;
  std::nth_element(magnitudes.begin(), magnitudes.begin() + static_cast<std::ptrdiff_t>(index),
                   magnitudes.end());
  const double percentile = magnitudes[index];
  if (percentile > 0.0) return percentile;
  return std::max(*std::max_element(magnitudes.begin(), magnitudes.end()), 1e-12);
}

std::string curvatureRangeRule(const std::vector<double>& values) {
  const double range = curvatureRange(values);
  bool anyAbove = false;
  for (const double v : values) anyAbove = anyAbove || std::abs(v) > range;
  if (!anyAbove) return "largest";
  char rule[32];
  std::snprintf(rule, sizeof rule, "%gth percentile", kCurvatureRangePercentile);
  return rule;
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

std::string encodePng(const Image& image) {
  const CairoSurface surface = surfaceFromImage(image);
  std::string png;
  if (cairo_surface_write_to_png_stream(surface.get(), appendToString, &png) !=
      CAIRO_STATUS_SUCCESS) {
    throw InputError("render: Cairo could not encode the PNG");
  }
  return png;
}

void writePng(const std::string& path, const Image& image) {
  modeling::writeFileAtomically(path, encodePng(image));
}

}  // namespace flexure::render
