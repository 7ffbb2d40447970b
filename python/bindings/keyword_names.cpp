#include "python/bindings/keyword_names.h"

#include <utility>
#include <vector>

#include "modeling/field_names.h"

namespace flexure::python {
namespace {

// One row per option field that a library message may name, as the package's functions take it
// (python/flexure); a longer field before one it starts with.
const std::vector<modeling::FieldName>& keywordNames() {
  static const std::vector<modeling::FieldName> rows = {
      // Problem, energy, minimize, form
      {"ProblemOptions.dof", "dof"},
      {"ProblemOptions.membraneRest", "the membrane's rest shape"},
      {"ProblemOptions.membrane", "membrane"},
      {"ProblemOptions.fixedRings", "fixed_rings"},
      {"ProblemOptions.fixedVertex", "fixed"},
      {"ProblemOptions.fixedEdge", "pinned rings:K"},
      {"ProblemOptions.boundarySurface", "boundary_surface"},
      {"ConfigurationEnergyOptions.boundarySurface", "boundary_surface"},
      // minimize's boundary_positions; a Simulation's start V_start
      {"ProblemOptions.boundaryPositions", "boundary_positions (V_start)"},
      {"ProblemOptions.boundaryNormals", "boundary_normals"},
      {"ProblemOptions.linearizedClamp", "linearized_clamp"},
      {"ProblemOptions.load.gravity", "gravity"},
      {"ProblemOptions.load.density", "density"},
      {"ProblemOptions.obstacles", "obstacles"},
      {"ProblemOptions.meshObstacles", "mesh_obstacles"},
      {"ProblemOptions.selfContact", "self_contact"},
      {"ProblemOptions.contactOffset", "contact_offset"},
      {"LoadOptions.mass", "mass"},
      {"BoundaryConditions.fixedVertex rings:2", "fixed_rings=2"},
      {"BoundaryConditions.fixedVertex rings:K", "fixed_rings=K"},
      {"BoundaryConditions.fixedVertex", "fixed"},
      {"BendingOptions.discretization", "energy"},
      {"BendingOptions.poisson", "poisson"},
      {"BendingOptions.hingeAngle", "hinge_angle"},
      {"BendingOptions.vertexArea", "vertex_area"},
      {"BendingOptions.stiffness", "stiffness"},
      {"MinimizeOptions.solver", "solver"},
      {"MinimizeOptions.hessian", "hessian"},
      {"MinimizeOptions.start", "start"},
      {"MinimizeOptions.threads", "threads"},
      {"MinimizeOptions.maxIterations", "max_iterations"},
      {"MinimizeOptions.linearized", "linearized"},
      {"PlasticityOptions.yieldCurvature", "yield_curvature"},
      {"PlasticityOptions.yieldStrain", "yield_strain"},
      {"PlasticityOptions.hardening", "hardening"},
      {"FormingOptions.loadSteps", "load_steps"},
      {"FormingOptions.maxUpdatesPerStep", "max_updates_per_step"},
      {"FormingOptions.tolerance", "update_tolerance"},
      {"MembraneOptions.young", "membrane young"},
      {"MembraneOptions.poisson", "membrane poisson"},
      {"MembraneOptions.lengthStiffness", "membrane length_stiffness"},
      {"MembraneOptions.areaStiffness", "membrane area_stiffness"},
      {"MembraneOptions.shapeStiffness", "membrane shape_stiffness"},
      // Simulation
      {"DynamicsOptions.integrator", "integrator"},
      {"DynamicsOptions.beta", "beta"},
      {"DynamicsOptions.gamma", "gamma"},
      {"DynamicsOptions.rayleighMass|rayleighStiffness|bendingDamping",
       "rayleigh / bending_damping"},
      {"DynamicsOptions.rayleighMass|rayleighStiffness", "rayleigh"},
      {"DynamicsOptions.rayleighMass", "rayleigh"},
      {"DynamicsOptions.bendingDamping", "bending_damping"},
      {"DynamicsOptions.energyTolerance", "energy_tolerance"},
      {"DynamicsOptions.stepTolerance", "step_tolerance"},
      {"DynamicsOptions.friction", "friction"},
      {"DynamicsOptions.pinGroups", "pin_groups"},
      {"PinMotion.kind", "pin_motion"},
      {"PinMotion.axis", "axis"},
      {"PinMotion.point", "point"},
      {"PinMotion.omega", "omega"},
      {"PinMotion.velocity", "velocity"},
      {"PinGroup.releaseTime", "pin_groups release time"},
      {"FractureOptions.fractureStrain", "fracture_strain"},
      {"FractureOptions.thickness", "thickness"},
      {"TimeSteps.dt", "dt"},
      {"TimeSteps.minDt", "min_dt"},
      {"TimeSteps.duration", "duration"},
      {"SimulationSpec.checkpointed", "checkpoints"},
      // fair, modes, studies, renders
      {"FairingOptions.membraneWeight", "membrane_weight"},
      {"FairingOptions.start", "start"},
      {"FairingOptions.metric", "metric"},
      {"FairingOptions.method", "method"},
      {"FairingSpec.allowSlivers", "allow_slivers"},
      {"ModesOptions.count", "count"},
      {"ModesOptions.clamp", "clamp"},
      {"ModesOptions.density", "density"},
      {"ModesOptions.dof", "dof"},
      {"ModesOptions.mass", "mass"},
      {"ModesOptions.support", "support"},
      {"SpectrumStudyOptions.energies", "energies"},
      {"SpectrumStudyOptions.families", "families"},
      {"SpectrumStudyOptions.baseN", "n"},
      {"SpectrumStudyOptions.levels", "levels"},
      {"SpectrumStudyOptions.count", "count"},
      {"SpectrumStudyOptions.support", "support"},
      {"StudyOptions.energies", "energies"},
      {"StudyOptions.families", "families"},
      {"StudyOptions.userMeshes", "the study's meshes"},
      {"StudyOptions.seeds", "seeds"},
      {"StudyOptions.baseN", "n"},
      {"StudyOptions.levels", "levels"},
      {"StudyOptions.amplitudes", "amplitudes"},
      {"StudyOptions.threads", "threads"},
      {"StudyOptions.quadratics", "quadratics"},
      {"StudyOptions.solution", "solution"},
      {"GeneratorOptions.aspect", "aspect"},
      {"ComparisonOptions.rows", "families"},
      {"ComparisonOptions.energies", "energies"},
      {"ComparisonOptions.size", "size"},
      {"ComparisonOptions.solve", "solve"},
      {"ComparisonOptions.cellsPerSide", "n"},
      {"ComparisonOptions.style", "style"},
      {"RenderOptions.style", "style"},
      {"RenderOptions.background", "background"},
      {"RenderOptions.surface", "surface"},
      {"RenderOptions.width", "size"},
      {"RenderOptions.height", "size"},
      {"RenderOptions.azimuthDegrees", "azimuth"},
      {"RenderOptions.elevationDegrees", "elevation"},
      {"RenderOptions.stripeCount", "stripes"},
      {"RenderOptions.stripeWidth", "stripe_width"},
      {"RenderOptions.stripeDirectionDegrees", "stripe_direction"},
      {"RenderOptions.lightDirection", "light"},
      {"RenderOptions.errorMax", "error_max"},
      {"RenderOptions.curvatureMax", "curvature_max"},
      {"RenderOptions.background", "background"},
      {"RenderOptions.referencePositions", "surface"},
      {"RenderOptions.markedFaces", "the faces marked at the mesh's problems"},
      {"RenderOptions.crackEdges", "the lips of the cracks"},
      // flexure.view
      {"ViewerPageSpec.meshes", "the meshes"},
      {"ViewerPageSpec.style", "style"},
      {"ViewerPageSpec.stripeCount", "stripes"},
      {"ViewerPageSpec.stripeWidth", "stripe_width"},
  };
  return rows;
}

}  // namespace

std::string withKeywordNames(std::string message) {
  return modeling::renameFields(std::move(message), keywordNames());
}

}  // namespace flexure::python
