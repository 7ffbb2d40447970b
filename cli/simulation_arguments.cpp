// flexure simulate's flags mapped to the library: the integrator, pins and damping, the body
// (energy, membrane, load, obstacles), the fracture and plasticity rules, the time steps, and the
// frame images' look with the video's checks.
#include "cli/simulation_arguments.h"

#include <filesystem>

#include "cli/dynamics_arguments.h"
#include "cli/simulation_video.h"
#include "curvature/midedge_boundary.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "modeling/rest_state.h"
#include "optimize/boundary_conditions.h"

namespace flexure::cli {
namespace {

// --damping rayleigh:α,β and/or bend:c, each at most once.
void parseDamping(const std::vector<std::string>& specs, optimize::DynamicsOptions& dynamics) {
  bool rayleigh = false, bend = false;
  for (const std::string& damping : specs) {
    if (damping.rfind("rayleigh:", 0) == 0 && !rayleigh) {
      const std::vector<double> ab = parseNumbers("--damping", damping.substr(9), 2);
      dynamics.rayleighMass = ab[0];
      dynamics.rayleighStiffness = ab[1];
      rayleigh = true;
    } else if (damping.rfind("bend:", 0) == 0 && !bend) {
      dynamics.bendingDamping = parseNumbers("--damping", damping.substr(5), 1)[0];
      bend = true;
    } else {
      throw InputError("--damping " + damping +
                       ": expected rayleigh:alpha,beta or bend:c (each at most once)");
    }
  }
}

// The integrator, the pins' motions and releases (their vertices come with the mesh,
// simulatedBody) and the damping, as the flags give them.
optimize::DynamicsOptions dynamicsOptions(const SimulateOptions& o) {
  optimize::DynamicsOptions dynamics;
  dynamics.integrator = optimize::parseIntegrator(o.integrator);
  dynamics.beta = o.beta;
  dynamics.gamma = o.gamma;
  checkPinSpecs(o.pin, o.pinMotion);
  if (!o.pinMotion.empty()) {
    if (o.pin == std::vector<std::string>{"none"})
      throw InputError("--pin-motion " + o.pinMotion +
                       ": moves the pinned vertices; give them with --pin");
    dynamics.pinMotion = parsePinMotion(o.pinMotion);
  }
  dynamics.pinGroups = pinGroupMotions(o.pin, dynamics.pinMotion);
  parseDamping(o.damping, dynamics);
  dynamics.energyTolerance = o.energyTolerance;
  dynamics.stepTolerance = o.stepTolerance;
  dynamics.quasiNewtonPairs = o.quasiNewtonPairs;
  dynamics.friction = o.friction;
  return dynamics;
}

modeling::Positions startPositions(const SimulateOptions& o, const modeling::Mesh& restMesh) {
  if (o.initFile.empty()) return restMesh.positions;
  const modeling::Mesh init = modeling::readMesh(o.initFile);
  if (init.vertexCount() != restMesh.vertexCount() || init.triangles != restMesh.triangles)
    throw InputError(o.initFile + ": does not share the connectivity of " + o.restFile +
                     ": --init must be the rest mesh in other positions");
  return init.positions;
}

// What is simulated, before the mesh is read: the bending energy and membrane, every coordinate
// free, the load and the obstacles.
optimize::ProblemOptions bodyOptions(const SimulateOptions& o) {
  optimize::ProblemOptions p;
  p.bending = bendingOptions(o.bending);
  if (!o.membrane.model.empty()) p.membrane = membraneOptions(o.membrane);
  p.dof = optimize::DofMode::Xyz;
  p.fixedRings = 0;
  p.boundaryNormals = optimize::BoundaryNormals::Free;
  p.load = loadOptions(o.load);
  p.obstacles = obstacleList(o.load);
  p.meshObstacles = meshObstacleList(o.load);
  p.selfContact = o.selfContact == "on";
  p.contactOffset = o.contactOffset;
  return p;
}

}  // namespace

std::optional<render::RenderOptions> frameLook(const SimulateOptions& o) {
  namespace fs = std::filesystem;
  std::optional<render::RenderOptions> look;
  if (o.renderStyle == "plastic") {
    if (!o.plasticity.enabled())
      throw InputError(
          "--render-style plastic: colours the plastic strain; give --yield-curvature or "
          "--yield-strain");
    look.emplace();
    look->style = render::RenderStyle::Plastic;
    look->plasticLabel = plasticityOptions(o.plasticity).measureName();
  } else if (o.renderStyle != "none") {
    look.emplace();
    look->style = render::parseRenderStyle(o.renderStyle);
    // Highlight lines alias into moiré at frame sizes on a gently curved sheet; error and
    // curvature need a surface or a field the frames do not have.
    if (look->style == render::RenderStyle::Error ||
        look->style == render::RenderStyle::Curvature ||
        look->style == render::RenderStyle::Highlight)
      throw InputError("--render-style " + o.renderStyle +
                       ": expected shaded, reflection, isophote, displacement, plastic or none");
  }
  if (look) {
    look->width = look->height = o.renderSize;
    if (look->style == render::RenderStyle::Displacement ||
        look->style == render::RenderStyle::Plastic)
      look->width += render::kLegendWidth;
    look->azimuthDegrees = 25.0;
    look->elevationDegrees = 30.0;
  }
  if (!o.video.empty()) {
    if (!look)
      throw InputError("--video " + o.video +
                       ": the video is made of the frame images; not with --render-style none");
    const fs::path ext = fs::path(o.video).extension();
    if (ext != ".mp4") throw InputError("--video " + o.video + ": expected a .mp4 file name");
    if (!ffmpegAvailable())
      throw InputError(
          "--video " + o.video +
          ": ffmpeg is not installed (Debian package ffmpeg, which scripts/install-deps "
          "installs); run without --video, or install it");
  }
  return look;
}

optimize::SimulationSpec simulationSpec(const SimulateOptions& o) {
  if (!(o.fps > 0.0)) throw InputError("--fps: expected a value > 0");
  optimize::SimulationSpec spec;
  spec.body = bodyOptions(o);
  spec.dynamics = dynamicsOptions(o);
  spec.plasticity.yieldCurvature = o.plasticity.yieldCurvature;
  spec.plasticity.yieldStrain = o.plasticity.yieldStrain;
  spec.plasticity.hardening = o.plasticity.hardening;
  if (o.fractureStrain != 0.0) {
    spec.fracture.emplace();
    spec.fracture->fractureStrain = o.fractureStrain;
    spec.fracture->thickness = o.thickness;
  } else if (o.thickness != 0.0) {
    throw InputError("--thickness: the fibres of the fracture criterion; give --fracture-strain");
  }
  spec.steps.dt = o.dt;
  spec.steps.minDt = o.minDt;
  spec.steps.duration = o.duration;
  spec.checkpointed = o.checkpointEvery > 0 || !o.resumeDir.empty();
  spec.validate();
  return spec;
}

optimize::Problem simulatedBody(const SimulateOptions& o, optimize::ProblemOptions& p,
                                optimize::DynamicsOptions& dynamics,
                                const modeling::Mesh& restMesh) {
  modeling::Stencils stencils = modeling::compileStencils(restMesh);
  modeling::RestState rest = modeling::precomputeRestState(stencils, restMesh.positions);
  PinnedGroups pinned = pinnedGroups(o.pin, stencils, rest.positions, dynamics.pinGroups);
  p.fixedVertex = std::move(pinned.held);
  p.boundaryPositions = startPositions(o, restMesh);
  if (curvature::energyEntry(p.bending.discretization).restEdgeUnknowns)
    p.fixedEdge = std::move(pinned.clampedEdges);
  return optimize::buildProblem(std::move(stencils), std::move(rest), p);
}

}  // namespace flexure::cli
