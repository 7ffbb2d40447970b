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

curvature::BendingOptions bendingOptions(const BendingArguments& a) {
  curvature::BendingOptions b;
  b.discretization = curvature::parseDiscretization(a.energy);
  b.poisson = a.poisson;
  b.stiffness = a.stiffness;
  if (a.vertexArea == "voronoi")
    b.vertexArea = curvature::VertexArea::Voronoi;
  else if (a.vertexArea == "barycentric")
    b.vertexArea = curvature::VertexArea::Barycentric;
  else
    throw InputError("vertex_area " + a.vertexArea + ": expected voronoi or barycentric");
  if (a.hingeAngle == "theta")
    b.hingeAngle = curvature::HingeAngle::Theta;
  else if (a.hingeAngle == "tan")
    b.hingeAngle = curvature::HingeAngle::Tan;
  else
    throw InputError("hinge_angle " + a.hingeAngle + ": expected theta or tan");
  if (a.flatRest) b.restCurvature = curvature::RestCurvature::Flat;
  curvature::effectivePoisson(b);  // the entry's ν rule, before any mesh work
  return b;
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
