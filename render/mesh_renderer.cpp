#include "render/mesh_renderer.h"

#include <cairo.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

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
  return style == RenderStyle::Error || style == RenderStyle::Curvature;
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

Camera frameCamera(const modeling::Mesh& mesh, const RenderOptions& o, int width, int height) {
  const modeling::Positions& points = o.framingPoints.rows() > 0 ? o.framingPoints : mesh.positions;
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
// barycentric coordinates come free): frame position (3), frame normal (3), scalar (1).
constexpr int kFloatsPerCorner = 7;

std::vector<float> cornerSoup(const modeling::Mesh& mesh, const Camera& camera, bool smooth,
                              const std::vector<double>& scalars) {
  const Eigen::MatrixX3d normals =
      smooth ? modeling::vertexNormals(mesh.positions, mesh.triangles) : Eigen::MatrixX3d();
  std::vector<float> soup;
  soup.reserve(static_cast<std::size_t>(mesh.faceCount()) * 3 * kFloatsPerCorner);
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
    }
  }
  return soup;
}

// Vertex stage: frame coordinates in, clip coordinates out; the corner's barycentric coordinate
// (1 at its own corner, 0 at the others) comes from gl_VertexID, three corners per triangle.
const char* const kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in float scalar;
uniform mat4 frameToClip;
out vec3 framePosition;
out vec3 frameNormal;
out float vertexScalar;
out vec3 barycentric;
void main() {
  framePosition = position;
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
//  scalar      (error, curvature) the interpolated vertex scalar through the colour map on
//              [lo, hi], unlit so that the colour reads as a value.
//
// Stripes are dark where s is within w/2 of an integer (w = the dark fraction of a period); the
// edges are smoothed over one pixel, |∇s| ≈ fwidth(s), against aliasing. The edge overlay paints
// blue the pixels within about one pixel of a triangle edge (a barycentric coordinate near 0).
const char* const kFragmentShader = R"(#version 450 core
in vec3 framePosition;
in vec3 frameNormal;
in float vertexScalar;
in vec3 barycentric;
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

void main() {
  vec3 n = normalize(frameNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 v = perspective != 0 ? normalize(eye - framePosition) : vec3(0.0, 0.0, 1.0);
  vec3 d = vec3(stripeAcross, 0.0);
  vec3 c;
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
  }
  if (edges != 0) {
    vec3 nearEdge = smoothstep(vec3(0.0), 1.2 * fwidth(barycentric), barycentric);
    c = mix(edgeColour, c, min(nearEdge.x, min(nearEdge.y, nearEdge.z)));
  }
  colour = vec4(clamp(c, 0.0, 1.0), 1.0);
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

GLuint linkProgram(const GlFunctions& gl) {
  const GLuint vertex = compileShader(gl, GL_VERTEX_SHADER, kVertexShader, "vertex");
  const GLuint fragment = compileShader(gl, GL_FRAGMENT_SHADER, kFragmentShader, "fragment");
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

// The corner soup into a vertex buffer: position (3), normal (3) and scalar (1) per corner.
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
  for (GLuint attribute = 0; attribute < 3; ++attribute) gl.EnableVertexAttribArray(attribute);
  throwOnGlError(gl, "uploading the mesh");
}

void setUniforms(const GlFunctions& gl, GLuint program, const Camera& camera,
                 const RenderOptions& o, double scalarMin, double scalarMax, const ColourMap& map) {
  gl.UseProgram(program);
  const auto uniform = [&](const char* name) { return gl.GetUniformLocation(program, name); };
  Eigen::Matrix4f clip = camera.frameToClip.cast<float>();  // column-major, as GL expects
  gl.UniformMatrix4fv(uniform("frameToClip"), 1, GL_FALSE, clip.data());
  const int styleCode[] = {0, 1, 2, 3, 4, 4};
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
Image rasterize(OffscreenContext& context, const modeling::Mesh& mesh, const RenderOptions& o,
                int width, int height, const std::vector<double>& scalars, double scalarMin,
                double scalarMax, const ColourMap& map, RenderTimings* timings = nullptr) {
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

  const Camera camera = frameCamera(mesh, o, width, height);
  const std::vector<float> soup = cornerSoup(mesh, camera, o.smoothNormals, scalars);
  objects.program = linkProgram(gl);
  uploadCornerSoup(gl, objects, soup);
  setUniforms(gl, objects.program, camera, o, scalarMin, scalarMax, map);
  drawTriangles(gl, objects, o, width, height, static_cast<GLsizei>(mesh.faceCount()));
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

// The mesh image on the left, and on the right a vertical colour bar of `map` from `minimum`
// (bottom) to `maximum` (top) with ticks at legendTicks, and above it `title` and `range` (how
// the range was chosen), each fitted to the legend's width.
Image withLegend(const Image& meshImage, const RenderOptions& o, double minimum, double maximum,
                 const ColourMap& map, const std::string& title, const std::string& range) {
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
  const std::vector<double> ticks = legendTicks(minimum, maximum);
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : maximum - minimum;
  const double labelLeft = barLeft + barWidth + 8.0;
  const double labelWidth = o.width - kTextMargin - labelLeft;
  for (const double tick : ticks) {
    const double y = barBottom - (tick - minimum) / (maximum - minimum) * (barBottom - barTop);
    cairo_move_to(cr.get(), barLeft + barWidth, std::round(y) + 0.5);
    cairo_rel_line_to(cr.get(), 5.0, 0.0);
    cairo_stroke(cr.get());
    const std::string label = tickLabel(tick, step);
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
Image withOutline(const Image& meshImage, const modeling::Mesh& mesh, const RenderOptions& o) {
  if (o.outlineSegments.rows() == 0) return meshImage;
  const Camera camera = frameCamera(mesh, o, meshImage.width, meshImage.height);
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

cairo_status_t appendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

RenderStyle parseRenderStyle(std::string_view name) {
  for (RenderStyle style : {RenderStyle::Reflection, RenderStyle::Isophote, RenderStyle::Highlight,
                            RenderStyle::Shaded, RenderStyle::Error, RenderStyle::Curvature}) {
    if (renderStyleName(style) == name) return style;
  }
  throw InputError("unknown render style '" + std::string(name) +
                   "' (known: reflection, isophote, highlight, shaded, error, curvature)");
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
  if (outlineSegments.rows() % 2 != 0 || !outlineSegments.allFinite()) {
    fail("outlineSegments needs finite segment ends in pairs (" +
         std::to_string(outlineSegments.rows()) + " rows)");
  }
  if (!(outlineWidth > 0.0 && outlineWidth <= 100.0))
    fail("outlineWidth must lie in (0, 100] pixels");
  const auto inUnitCube = [](const Rgb& c) {
    return c.r >= 0 && c.r <= 1 && c.g >= 0 && c.g <= 1 && c.b >= 0 && c.b <= 1;
  };
  if (!inUnitCube(background)) fail("background: colour components must lie in [0, 1]");
  if (!inUnitCube(outlineColour)) fail("outlineColour: colour components must lie in [0, 1]");
}

Image renderMesh(OffscreenContext& context, const modeling::Mesh& mesh,
                 const RenderOptions& options) {
  return renderMesh(context, mesh, options, nullptr);
}

Image renderMesh(OffscreenContext& context, const modeling::Mesh& mesh,
                 const RenderOptions& options, RenderTimings* timings) {
  options.validate();
  if (mesh.faceCount() == 0) throw InputError("render: the mesh has no faces");
  if (!hasLegend(options.style)) {
    return withOutline(rasterize(context, mesh, options, options.width, options.height, {}, 0.0,
                                 1.0, sequentialColourMap(), timings),
                       mesh, options);
  }
  const int meshWidth = options.width - kLegendWidth;
  if (options.style == RenderStyle::Curvature) {
    const std::vector<double>& values = options.vertexScalars;
    if (static_cast<int>(values.size()) != mesh.vertexCount()) {
      throw InputError("render: " + std::to_string(values.size()) + " curvature values for " +
                       std::to_string(mesh.vertexCount()) + " vertices");
    }
    for (double value : values)
      if (!std::isfinite(value)) throw InputError("render: a curvature value is not finite");
    // Symmetric about 0, so that white is 0.
    const double bound = options.curvatureMax ? *options.curvatureMax : curvatureRange(values);
    char range[96];
    std::snprintf(range, sizeof range, "|%s| ≤ %.3g (%s)", options.scalarSymbol.c_str(), bound,
                  options.curvatureMax ? "given" : curvatureRangeRule(values).c_str());
    const Image meshImage =
        withOutline(rasterize(context, mesh, options, meshWidth, options.height, values, -bound,
                              bound, divergingColourMap(), timings),
                    mesh, options);
    return withLegend(meshImage, options, -bound, bound, divergingColourMap(), options.scalarLabel,
                      range);
  }
  const std::vector<double> errors = vertexSurfaceErrors(mesh, options.surface);
  const double largest = *std::max_element(errors.begin(), errors.end());
  // An all-zero field still needs a non-empty range: it then shows the colour of 0.
  const double maximum = options.errorMax ? *options.errorMax : std::max(largest, 1e-12);
  const Image meshImage =
      withOutline(rasterize(context, mesh, options, meshWidth, options.height, errors, 0.0, maximum,
                            sequentialColourMap(), timings),
                  mesh, options);
  char range[64];
  std::snprintf(range, sizeof range, "0 to %.3g (%s)", maximum,
                options.errorMax ? "given" : "largest");
  return withLegend(meshImage, options, 0.0, maximum, sequentialColourMap(), "|z − p(x, y)|",
                    range);
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
