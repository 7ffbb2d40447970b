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

}  // namespace flexure::python
