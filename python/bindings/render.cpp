// flexure._flexure.render: an offscreen OSMesa image of a mesh, as flexure render draws it, on one
// context made at the first call and reused (loading OSMesa and making a context is most of a
// small render's time).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "curvature/energy_registry.h"
#include "modeling/errors.h"
#include "modeling/polynomial_surface.h"
#include "python/bindings/bindings.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace py = pybind11;

namespace flexure::python {
namespace {

struct RenderArguments {
  std::string style = "reflection";
  int width = 1024, height = 1024;
  double azimuth = 0.0, elevation = 90.0;
  bool perspective = false, flat = false, edges = false;
  std::string background = "#ffffff";
  int stripes = 12;
  double stripeWidth = 0.5, stripeDirection = 90.0;
  std::optional<std::array<double, 3>> light;
  std::optional<std::string> surface;  // the error style's p
  std::optional<double> errorMax, curvatureMax;
  std::optional<Positions> framingPoints;
};

// render's runRenderCommand checks, the names the Python arguments'.
render::RenderOptions renderOptions(const RenderArguments& a) {
  render::RenderOptions r;
  r.style = render::parseRenderStyle(a.style);
  r.width = a.width;
  r.height = a.height;
  r.azimuthDegrees = a.azimuth;
  r.elevationDegrees = a.elevation;
  r.projection = a.perspective ? render::Projection::Perspective : render::Projection::Orthographic;
  r.smoothNormals = !a.flat;
  r.edges = a.edges;
  r.background = render::parseBackground(a.background);
  r.stripeCount = a.stripes;
  r.stripeWidth = a.stripeWidth;
  r.stripeDirectionDegrees = a.stripeDirection;
  if (a.light) r.lightDirection = *a.light;
  render::StyleOptions{a.surface, a.errorMax, a.curvatureMax}.applyTo(r);
  if (r.style == render::RenderStyle::Curvature) r.scalarLabel = "mean curvature H";
  if (a.framingPoints) r.framingPoints = *a.framingPoints;
  return r;
}

render::OffscreenContext& sharedContext() {
  static std::unique_ptr<render::OffscreenContext> context;
  if (!context) context = std::make_unique<render::OffscreenContext>();
  context->makeCurrent();
  return *context;
}

// H × W × 3 uint8, the image's rows top to bottom (as the PNG stores them).
py::array_t<std::uint8_t> renderImage(const PositionsRef& V, const TrianglesRef& F,
                                      const RenderArguments& a) {
  render::RenderOptions options = renderOptions(a);
  const modeling::Mesh mesh = checkedMesh(V, F, "V, F");
  if (options.style == render::RenderStyle::Curvature)
    options.vertexScalars = curvature::defaultMeanCurvatureEnergy().meanCurvatureField(mesh);
  // The GIL stays held: the context is one, used by one thread at a time.
  const render::Image image = render::renderMesh(sharedContext(), mesh, options);
  py::array_t<std::uint8_t> pixels(
      {py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(3)});
  auto w = pixels.mutable_unchecked<3>();
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::size_t i = 4 * (static_cast<std::size_t>(y) * image.width + x);
      for (int c = 0; c < 3; ++c) w(y, x, c) = image.rgba[i + c];
    }
  return pixels;
}

}  // namespace

void bindRender(py::module_& m) {
  py::class_<RenderArguments>(m, "RenderArguments")
      .def(py::init<>())
      .def_readwrite("style", &RenderArguments::style)
      .def_readwrite("width", &RenderArguments::width)
      .def_readwrite("height", &RenderArguments::height)
      .def_readwrite("azimuth", &RenderArguments::azimuth)
      .def_readwrite("elevation", &RenderArguments::elevation)
      .def_readwrite("perspective", &RenderArguments::perspective)
      .def_readwrite("flat", &RenderArguments::flat)
      .def_readwrite("edges", &RenderArguments::edges)
      .def_readwrite("background", &RenderArguments::background)
      .def_readwrite("stripes", &RenderArguments::stripes)
      .def_readwrite("stripe_width", &RenderArguments::stripeWidth)
      .def_readwrite("stripe_direction", &RenderArguments::stripeDirection)
      .def_readwrite("light", &RenderArguments::light)
      .def_readwrite("surface", &RenderArguments::surface)
      .def_readwrite("error_max", &RenderArguments::errorMax)
      .def_readwrite("curvature_max", &RenderArguments::curvatureMax)
      .def_readwrite("framing_points", &RenderArguments::framingPoints);
  m.def("render", &renderImage);
  m.def("encode_png", [](py::array_t<std::uint8_t, py::array::c_style> pixels) {
    if (pixels.ndim() != 3 || pixels.shape(2) != 3)
      throw py::value_error("image: expected an H x W x 3 uint8 array");  // the array's shape
    render::Image image;
    image.height = static_cast<int>(pixels.shape(0));
    image.width = static_cast<int>(pixels.shape(1));
    image.rgba.resize(4 * static_cast<std::size_t>(image.width) * image.height);
    const std::uint8_t* p = pixels.data();
    for (std::size_t k = 0; k < image.rgba.size() / 4; ++k) {
      for (int c = 0; c < 3; ++c) image.rgba[4 * k + c] = p[3 * k + c];
      image.rgba[4 * k + 3] = 255;
    }
    const std::string png = render::encodePng(image);
    return py::bytes(png);
  });
}

}  // namespace flexure::python
