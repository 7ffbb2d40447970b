// flexure._flexure.viewer_page: flexure view's HTML page (render/viewer_page.h) of meshes and
// frame sequences given as arrays; the styles as the command names them.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "curvature/energy_registry.h"
#include "modeling/errors.h"
#include "python/bindings/bindings.h"
#include "render/viewer_page.h"

namespace py = pybind11;

namespace flexure::python {
namespace {

struct ViewerArguments {
  std::string style = "reflection";  // reflection | isophote | shaded | curvature | displacement
  int stripes = 12;
  double stripeWidth = 0.5;
  bool overlay = false;
  std::optional<Positions> rest;  // displacement: the rest positions (else each first frame)
};

// One mesh: its name, F, its frames (each #V by 3) and their times (empty: numbered).
using ViewerItem = std::tuple<std::string, Triangles, std::vector<Positions>, std::vector<double>>;

// The page's HTML, as `flexure view` writes it for the same meshes and style.
py::bytes viewerPage(const std::vector<ViewerItem>& items, const ViewerArguments& a) {
  render::ViewerPageSpec page;
  const bool curvatureStyle = a.style == "curvature", displacementStyle = a.style == "displacement";
  page.style = curvatureStyle || displacementStyle ? render::ViewerStyle::Field
                                                   : render::parseViewerStyle(a.style);
  page.stripeCount = a.stripes;
  page.stripeWidth = a.stripeWidth;
  page.overlay = a.overlay;
  const curvature::EnergyEntry& energy = curvature::defaultMeanCurvatureEnergy();
  if (curvatureStyle) {
    page.fieldTitle = "mean curvature H (" + energy.name + ")";
    page.diverging = true;
  } else if (displacementStyle) {
    page.fieldTitle = "displacement |x - x_rest|";
  }
  for (const auto& [name, F, frames, times] : items) {
    render::ViewerMesh m{name, F, frames, times, {}};
    if (frames.empty()) throw InputError(name + ": no frames");
    for (const Positions& V : frames) {
      const modeling::Mesh mesh = checkedMesh(V, F, name);
      if (curvatureStyle) {
        const std::vector<double> h = energy.meanCurvatureField(mesh);
        m.fields.push_back(Eigen::Map<const Eigen::VectorXd>(h.data(), Eigen::Index(h.size())));
      } else if (displacementStyle) {
        const Positions& rest = a.rest ? *a.rest : frames.front();
        if (rest.rows() != V.rows())
          throw InputError("rest: " + std::to_string(rest.rows()) + " vertices, but " + name +
                           " has " + std::to_string(V.rows()));
        m.fields.push_back((V - rest).rowwise().norm());
      }
    }
    page.meshes.push_back(std::move(m));
  }
  page.validate();
  return py::bytes(render::viewerPageHtml(page));
}

}  // namespace

void bindViewer(py::module_& m) {
  py::class_<ViewerArguments>(m, "ViewerArguments")
      .def(py::init<>())
      .def_readwrite("style", &ViewerArguments::style)
      .def_readwrite("stripes", &ViewerArguments::stripes)
      .def_readwrite("stripe_width", &ViewerArguments::stripeWidth)
      .def_readwrite("overlay", &ViewerArguments::overlay)
      .def_readwrite("rest", &ViewerArguments::rest);
  m.def("viewer_page", &viewerPage);
}

}  // namespace flexure::python
