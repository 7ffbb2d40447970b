// The mesh drawn with OpenGL (OSMesa): one record per triangle corner uploaded to a vertex
// buffer, the shader program linked, the uniforms set from the camera and the options, the
// triangles drawn into an 8× multisampled framebuffer, resolved and read back as an image.
#include "render/mesh_rasterizer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "modeling/errors.h"
#include "modeling/vertex_quantities.h"
#include "render/camera.h"
#include "render/cracks.h"
#include "render/mesh_shaders.h"
#include "render/offscreen_context.h"

namespace flexure::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kRequestedSamples = 8;
constexpr int kMaxColourStops = 16;  // the shader's array size

// One record per triangle corner (no index buffer, so flat normals and the edge overlay's
// barycentric coordinates come free): frame position (3), frame normal (3), scalar (1), and one
// float m + 4 b for the material m (0 the mesh, 1 an obstacle, 2 a marked face of the mesh) and
// the face's crack bits b (faceCrackBits; 0 to 63, so the float is exact).
constexpr int kFloatsPerCorner = 8;

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
  const std::string stripes = "@STRIPE_FUNCTIONS@";
  fragmentSource.replace(fragmentSource.find(stripes), stripes.size(), kStripeFunctions);
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

}  // namespace

Image rasterize(OffscreenContext& context, const Scene& scene, const RenderOptions& o, int width,
                int height, const std::vector<double>& scalars, double scalarMin, double scalarMax,
                const ColourMap& map, RenderTimings* timings) {
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

}  // namespace flexure::render
