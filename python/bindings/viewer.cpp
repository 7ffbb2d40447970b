// flexure._flexure.viewer_page: flexure view's HTML page (render/viewer_page.h) of meshes and
// frame sequences given as arrays, modes folders and fairing reports; the styles as the command
// names them.
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
#include "reports/viewer_fairing.h"
#include "reports/viewer_fields.h"
#include "reports/viewer_modes.h"
#include "reports/viewer_simulation.h"

namespace py = pybind11;

namespace flexure::python {
namespace {

struct ViewerArguments {
  std::string style = "reflection";  // reports::parseViewStyle's names
  int stripes = 12;
  double stripeWidth = 0.5;
  bool overlay = false;
  bool multisample = false;
  std::optional<Positions> rest;  // displacement: the rest positions (else each first frame)
  // error: the reference surface (V, F) and its name in the legend.
  std::optional<std::pair<Positions, Triangles>> reference;
  std::string referenceName = "the reference";
};

// One mesh: its name, F, its frames (each #V by 3) and their times (empty: numbered); or a
// `flexure modes` folder or a `flexure fair` report (the last element; the others empty): its
// meshes, with their modes or the region outlined; or a simulation folder
// (reports::readSimulationFolder).
using ViewerItem =
    std::tuple<std::string, Triangles, std::vector<Positions>, std::vector<double>, std::string>;

// The page's HTML, as `flexure view` writes it for the same meshes and style.
py::bytes viewerPage(const std::vector<ViewerItem>& items, const ViewerArguments& a) {
  render::ViewerPageSpec page;
  const reports::ViewStyle style = reports::parseViewStyle(a.style);
  page.style = style.drawing;
  std::vector<std::string> folders;  // the plastic style's: each item's folder, or its name
  for (const auto& item : items)
    folders.push_back(std::get<4>(item).empty() ? std::get<0>(item) : std::get<4>(item));
  page.stripeCount = a.stripes;
  page.stripeWidth = a.stripeWidth;
  page.overlay = a.overlay;
  page.multisample = a.multisample;
  for (const auto& [name, F, frames, times, source] : items) {
    if (!source.empty() && reports::isFairingReport(source)) {
      reports::addFairingReport(page, source);
      continue;
    }
    if (reports::isModesFolder(source)) {
      for (render::ViewerMesh& m : reports::readModesFolder(source, page.style))
        page.meshes.push_back(std::move(m));
      continue;
    }
    if (!source.empty() && reports::isSimulationFolder(source)) {
      render::ViewerMesh m = reports::readSimulationFolder(source);
      m.name = name;
      if (!times.empty()) m.frameTimes = times;
      page.meshes.push_back(std::move(m));
      continue;
    }
    for (const Positions& V : frames) checkedMesh(V, F, name);
    render::ViewerMesh m;
    m.name = name;
    m.triangles = F;
    m.frames = frames;
    m.frameTimes = times;
    page.meshes.push_back(std::move(m));
  }
  reports::ViewerFieldSources sources;
  sources.rest = a.rest.value_or(Positions());
  sources.restName = "rest";
  if (a.reference)
    sources.reference = checkedMesh(a.reference->first, a.reference->second, "reference");
  sources.referenceName = a.referenceName;
  sources.folders = std::move(folders);
  reports::addFields(page, style.field, sources);
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
      .def_readwrite("multisample", &ViewerArguments::multisample)
      .def_readwrite("rest", &ViewerArguments::rest)
      .def_readwrite("reference", &ViewerArguments::reference)
      .def_readwrite("reference_name", &ViewerArguments::referenceName);
  m.def("viewer_page", &viewerPage);
  m.def("view_style_names", [] { return reports::viewStyleNames(); });
}

}  // namespace flexure::python
