// Render speed of the offscreen renderer (render/mesh_renderer.h): a reflection-line render of
// the patch48 (4-8) mesh with n × n cells (2n² triangles; n = 500: 500 000) lifted onto the
// quadratic z = 0.3x² − 0.7xy + 0.5y², at size × size pixels. Wall-clock seconds per phase:
//   context      creating the OSMesa GL 4.5 core context (dlopen included)
//   upload_draw  framebuffers, framing, the vertex soup, shader link, upload and draw (finished)
//   readback     the multisample resolve and glReadPixels
//   encode       the PNG encode (Cairo), as writePng does before its atomic write
//   total        the four summed, of the fastest run
// The mesh is generated once and not timed. `--repeat R` runs the whole sequence R times (a fresh
// context each time) and keeps each phase's fastest time (the first context also pays the cold
// dlopen of libOSMesa: see the per-run lines). JSON on stdout, a line per run on
// stderr. Not a test: scripts/bench render.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>

#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace flexure;
  CLI::App app("Offscreen render speed: context, upload + draw, readback, PNG encode");
  int n = 500, size = 1024, repeat = 3;
  app.add_option("--n", n, "Cells per side of the patch48 mesh (2 n^2 triangles)")
      ->capture_default_str();
  app.add_option("--size", size, "Image width and height in pixels")->capture_default_str();
  app.add_option("--repeat", repeat, "Runs; each phase's fastest is kept")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  modeling::GeneratorOptions generator;
  generator.n = n;
  modeling::Mesh mesh = modeling::generateMesh(generator);
  modeling::applyHeightField(modeling::PolynomialSurface::parse("quadratic:0.3,-0.7,0.5"),
                             mesh.positions);
  render::RenderOptions options;
  options.width = options.height = size;

  constexpr double kInf = std::numeric_limits<double>::infinity();
  double context = kInf, uploadDraw = kInf, readback = kInf, encode = kInf, total = kInf;
  std::size_t pngBytes = 0;
  for (int run = 0; run < repeat; ++run) {
    Clock::time_point start = Clock::now();
    render::OffscreenContext gl;
    const double contextSeconds = since(start);
    render::RenderTimings timings;
    const render::Image image = render::renderMesh(gl, mesh, options, &timings);
    start = Clock::now();
    const std::string png = render::encodePng(image);
    const double encodeSeconds = since(start);
    pngBytes = png.size();
    const double runTotal = contextSeconds + timings.uploadDraw + timings.readback + encodeSeconds;
    context = std::min(context, contextSeconds);
    uploadDraw = std::min(uploadDraw, timings.uploadDraw);
    readback = std::min(readback, timings.readback);
    encode = std::min(encode, encodeSeconds);
    total = std::min(total, runTotal);
    std::fprintf(stderr,
                 "run %d: context %.3f s, upload+draw %.3f s, readback %.3f s, encode %.3f s, "
                 "total %.3f s\n",
                 run + 1, contextSeconds, timings.uploadDraw, timings.readback, encodeSeconds,
                 runTotal);
    if (run == 0) std::fprintf(stderr, "renderer: %s\n", gl.description().c_str());
  }
  const nlohmann::json result = {
      {"mesh",
       {{"family", "patch48"},
        {"n", n},
        {"vertices", mesh.vertexCount()},
        {"triangles", mesh.faceCount()}}},
      {"image", {{"width", size}, {"height", size}, {"style", "reflection"}}},
      {"repeat", repeat},
      {"png_bytes", pngBytes},
      {"seconds",
       {{"context", context},
        {"upload_draw", uploadDraw},
        {"readback", readback},
        {"encode", encode},
        {"total", total}}}};
  std::cout << result.dump(2) << '\n';
  return 0;
}
