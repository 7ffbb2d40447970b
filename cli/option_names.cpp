#include "cli/option_names.h"

#include <utility>
#include <vector>

#include "modeling/field_names.h"

namespace flexure::cli {
namespace {

// Rows: one per option field that a library message may name, a table per subsystem.

// Minimize, energies, membranes, plasticity and forming.
std::vector<modeling::FieldName> solveFlags() {
  return {
      {"ProblemOptions.dof", "--dof"},
      {"ProblemOptions.membrane", "--membrane"},
      {"ProblemOptions.fixedRings", "--fix rings:K"},
      {"ProblemOptions.fixedVertex", "--fix"},
      {"ProblemOptions.boundarySurface", "--boundary"},
      {"ConfigurationEnergyOptions.boundarySurface", "--boundary-surface"},
      {"ProblemOptions.boundaryPositions", "--init"},
      {"ProblemOptions.boundaryNormals", "--boundary-normals"},
      {"ProblemOptions.linearizedClamp", "--linearized"},
      {"ProblemOptions.load.gravity", "--gravity"},
      {"ProblemOptions.load.density", "--density"},
      {"ProblemOptions.obstacles", "--obstacle"},
      {"ProblemOptions.meshObstacles", "--obstacle mesh:FILE"},
      {"ProblemOptions.selfContact", "--self-contact"},
      {"ProblemOptions.contactOffset", "--contact-offset"},
      {"LoadOptions.mass", "--mass"},
      {"ProblemOptions.fixedEdge", "--pin rings:K"},
      // no flag: fair sets it to the start's shape
      {"ProblemOptions.membraneRest", "the membrane's rest shape"},
      {"BendingOptions.discretization", "--energy"},
      {"BendingOptions.poisson", "--poisson"},
      {"BendingOptions.hingeAngle", "--hinge-angle"},
      {"BendingOptions.vertexArea", "--vertex-area"},
      {"BendingOptions.stiffness", "--stiffness"},
      {"MinimizeOptions.solver", "--solver"},
      {"MinimizeOptions.hessian", "--hessian"},
      {"MinimizeOptions.start", "--start"},
      {"MinimizeOptions.threads", "--threads"},
      {"MinimizeOptions.maxIterations", "--max-iterations"},
      {"MinimizeOptions.linearized", "--linearized"},
      {"PlasticityOptions.yieldCurvature", "--yield-curvature"},
      {"PlasticityOptions.yieldStrain", "--yield-strain"},
      {"PlasticityOptions.hardening", "--hardening"},
      {"FormingOptions.loadSteps", "--load-steps"},
      // no flags: the forming loop's limits
      {"FormingOptions.maxUpdatesPerStep", "the forming's update limit"},
      {"FormingOptions.tolerance", "the forming's tolerance"},
      {"BoundaryConditions.fixedVertex", "--fix"},
  };
}

// Time stepping: integrator, damping, pins and their motions, steps.
std::vector<modeling::FieldName> dynamicsFlags() {
  return {
      {"DynamicsOptions.integrator", "--integrator"},
      {"DynamicsOptions.beta", "--beta"},
      {"DynamicsOptions.gamma", "--gamma"},
      // the longer first: it starts with the next one
      {"DynamicsOptions.rayleighMass|rayleighStiffness|bendingDamping", "--damping"},
      {"DynamicsOptions.rayleighMass|rayleighStiffness", "--damping rayleigh:α,β"},
      {"DynamicsOptions.bendingDamping", "--damping bend:c"},
      {"DynamicsOptions.energyTolerance", "--energy-tolerance"},
      {"DynamicsOptions.stepTolerance", "--step-tolerance"},
      {"DynamicsOptions.quasiNewtonPairs", "--quasi-newton-pairs"},
      {"DynamicsOptions.friction", "--friction"},
      {"DynamicsOptions.pinGroups", "--pin SET@MOTION"},
      {"PinMotion.kind", "--pin-motion"},
      {"PinMotion.axis", "axis ax,ay,az"},
      {"PinMotion.point", "point px,py,pz"},
      {"PinMotion.omega", "omega"},
      {"PinMotion.velocity", "velocity vx,vy,vz"},
      {"PinGroup.releaseTime", "--pin SET@release:T"},
      {"TimeSteps.dt", "--dt"},
      {"TimeSteps.minDt", "--min-dt"},
      {"TimeSteps.duration", "--duration"},
      {"SimulationSpec.checkpointed", "--checkpoint / --resume"},
  };
}

// Studies, fairing, membranes, modes, spectra, meshes and fracture.
std::vector<modeling::FieldName> studyFlags() {
  return {
      {"StudyOptions.energies", "--energies"},
      {"StudyOptions.families", "--families"},
      {"StudyOptions.userMeshes", "--mesh"},
      {"StudyOptions.seeds", "--seeds"},
      {"StudyOptions.baseN", "--n"},
      {"StudyOptions.levels", "--levels"},
      {"StudyOptions.amplitudes", "--amplitudes"},
      {"StudyOptions.threads", "--threads"},
      {"StudyOptions.quadratics", "--quadratics"},
      {"StudyOptions.solution", "--solution"},
      {"FairingOptions.membraneWeight", "--membrane-weight"},
      {"FairingOptions.start", "--start"},
      {"FairingOptions.metric", "--metric"},
      {"FairingOptions.method", "--method"},
      {"FairingSpec.allowSlivers", "--allow-slivers"},
      {"FairingSpec.remesh", "--remesh"},
      {"RemeshOptions.targetEdgeLength", "--remesh-edge-length"},
      {"RemeshOptions.iterations", "--remesh-iterations"},
      {"MembraneOptions.young", "--young"},
      {"MembraneOptions.poisson", "--membrane-poisson"},
      {"MembraneOptions.lengthStiffness", "--length-stiffness"},
      {"MembraneOptions.areaStiffness", "--area-stiffness"},
      {"MembraneOptions.shapeStiffness", "--shape-stiffness"},
      {"ModesOptions.count", "--count"},
      {"ModesOptions.clamp", "--clamp"},
      {"ModesOptions.density", "--density"},
      {"ModesOptions.dof", "--dof"},
      {"ModesOptions.mass", "--mass"},
      {"ModesOptions.support", "--support"},
      {"SpectrumStudyOptions.energies", "--energies"},
      {"SpectrumStudyOptions.families", "--families"},
      {"SpectrumStudyOptions.baseN", "--n"},
      {"SpectrumStudyOptions.levels", "--levels"},
      {"SpectrumStudyOptions.count", "--count"},
      {"SpectrumStudyOptions.support", "--support"},
      {"GeneratorOptions.aspect", "--aspect"},
      {"FractureOptions.fractureStrain", "--fracture-strain"},
      {"FractureOptions.thickness", "--thickness"},
  };
}

// The comparison figure and renders.
std::vector<modeling::FieldName> figureFlags() {
  return {
      {"ComparisonOptions.rows", "--families/--mesh"},
      {"ComparisonOptions.energies", "--energies"},
      {"ComparisonOptions.size", "--size"},
      {"ComparisonOptions.solve", "--solve"},
      {"ComparisonOptions.cellsPerSide", "--n"},
      {"ComparisonOptions.style", "--style"},
      // renders
      {"RenderOptions.style", "--style"},
      {"RenderOptions.background", "--background"},
      {"RenderOptions.surface", "--surface"},
      {"RenderOptions.width", "--width"},
      {"RenderOptions.height", "--height"},
      {"RenderOptions.azimuthDegrees", "--azimuth"},
      {"RenderOptions.elevationDegrees", "--elevation"},
      {"RenderOptions.stripeCount", "--stripes"},
      {"RenderOptions.stripeWidth", "--stripe-width"},
      {"RenderOptions.stripeDirectionDegrees", "--stripe-direction"},
      {"RenderOptions.lightDirection", "--light"},
      {"RenderOptions.errorMax", "--error-max"},
      {"RenderOptions.curvatureMax", "--curvature-max"},
      {"RenderOptions.background", "--background"},
      {"RenderOptions.referencePositions", "--reference"},
      {"RenderOptions.exaggeration", "--exaggerate"},
      {"RenderOptions.markedFaces", "the faces marked at the mesh's problems"},
      {"RenderOptions.crackEdges", "the lips of the cracks drawn in the frames"},
      // the viewer page
      {"ViewerPageSpec.meshes", "the inputs"},
      {"ViewerPageSpec.style", "--style"},
      {"ViewerPageSpec.stripeCount", "--stripes"},
      {"ViewerPageSpec.stripeWidth", "--stripe-width"},
  };
}

const std::vector<modeling::FieldName>& fieldFlags() {
  static const std::vector<modeling::FieldName> rows = [] {
    std::vector<modeling::FieldName> all;
    for (auto table : {solveFlags, dynamicsFlags, studyFlags, figureFlags}) {
      std::vector<modeling::FieldName> part = table();
      all.insert(all.end(), part.begin(), part.end());
    }
    return all;
  }();
  return rows;
}

}  // namespace

std::string withFlagNames(std::string message) {
  return modeling::renameFields(std::move(message), fieldFlags());
}

}  // namespace flexure::cli
