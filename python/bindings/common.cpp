// The helpers the binding files share (bindings.h).
#include "curvature/energy_registry.h"
#include "modeling/errors.h"
#include "modeling/mesh_check.h"
#include "python/bindings/bindings.h"

namespace flexure::python {

modeling::Mesh checkedMesh(const PositionsRef& V, const TrianglesRef& F,
                           const std::string& source) {
  modeling::Mesh mesh;
  mesh.positions = V;
  mesh.triangles = F;
  modeling::requireValidMesh(mesh, source);
  return mesh;
}

curvature::MembraneOptions MembraneFields::membraneOptions(const std::string& model) const {
  curvature::MembraneOptions m;
  m.model = curvature::parseMembraneModel(model);
  m.young = young;
  m.poisson = membranePoisson;
  m.lengthStiffness = lengthStiffness;
  m.areaStiffness = areaStiffness;
  m.shapeStiffness = shapeStiffness;
  return m;
}

optimize::IterationObserver SolveObserver::observer() {
  return [this](const optimize::IterationProgress& at) {
    if (raised_) return true;  // stopped: a later solve of the same call stops at once
    pybind11::gil_scoped_acquire gil;
    try {
      if (!progress_.is_none()) {
        pybind11::dict d;
        d["iteration"] = at.iteration;
        d["energy"] = at.energy;
        d["gradient_norm"] = at.gradientNorm;
        progress_(d);
      }
      if (PyErr_CheckSignals() != 0) throw pybind11::error_already_set();
    } catch (pybind11::error_already_set& e) {
      raised_.emplace(e);
      return true;
    }
    return false;
  };
}

void SolveObserver::raiseIfStopped() {
  if (raised_) {
    pybind11::error_already_set e = *raised_;
    raised_.reset();
    throw e;
  }
}

}  // namespace flexure::python
