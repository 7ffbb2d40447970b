// flexure._flexure.fair: a region of a mesh faired by flexure's nonlinear fair
// (optimize/fairing/fairing.h) as flexure fair --method flexure fairs it, with the checks and the
// measures before and after. The region is a vertex mask or a spec of modeling::parseRegion.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "modeling/errors.h"
#include "modeling/fairing_region.h"
#include "modeling/region_remeshing.h"
#include "modeling/stencils.h"
#include "optimize/fairing/fairing.h"
#include "optimize/fairing/fairing_spec.h"
#include "python/bindings/bindings.h"

namespace py = pybind11;

namespace flexure::python {
namespace {

// The run's options are the library's spec (it holds the rules); the region is Python's.
struct FairArguments {
  optimize::FairingSpec spec;
  std::optional<std::vector<bool>> regionMask;
  std::string regionSpec;  // parseRegion's text when no mask is given
};

py::list energyList(const std::vector<optimize::EnergyMeasure>& measures) {
  py::list list;
  for (const optimize::EnergyMeasure& m : measures) {
    py::dict d;
    d["energy"] = m.energy;
    d["value"] = m.value;
    if (!m.error.empty()) d["error"] = m.error;
    list.append(d);
  }
  return list;
}

py::dict measureDict(const optimize::FairingMeasures& m) {
  py::dict d;
  d["bending"] = energyList(m.bending);
  d["bending_current"] = energyList(m.bendingCurrent);
  d["min_angle_degrees"] = m.quality.minAngleDegrees;
  d["mean_shape"] = m.quality.meanShape;
  d["min_shape"] = m.quality.minShape;
  d["max_displacement"] = m.maxDisplacement;
  return d;
}

// fair's smallest-angle rule (optimize::SliverCheck).
py::dict sliverDict(const optimize::SliverCheck& c) {
  py::dict d;
  d["input_degrees"] = c.inputDegrees;
  d["cgal_degrees"] = c.cgalDegrees;
  d["result_degrees"] = c.resultDegrees;
  d["limit_degrees"] = c.limitDegrees();
  d["passed"] = c.passed();
  return d;
}

py::dict checkDict(const optimize::FairingChecks& c) {
  py::dict d;
  d["passed"] = c.passed();
  d["failure"] = c.failure();
  d["gradient_checked"] = c.gradientChecked;
  d["gradient_passed"] = c.gradientPassed();
  d["start_gradient_norm"] = c.startGradientNorm;
  d["final_gradient_norm"] = c.finalGradientNorm;
  d["triangles_passed"] = c.trianglesPassed();
  d["degenerate_faces"] = c.degenerateFaces.size();
  d["inverted_faces"] = c.invertedFaces.size();
  d["input_min_angle_degrees"] = c.inputMinAngleDegrees;
  d["result_min_angle_degrees"] = c.resultMinAngleDegrees;
  return d;
}

// The remeshing's part of the report (modeling::RemeshedRegion), with the new faces.
py::dict remeshDict(const modeling::RemeshedRegion& r) {
  py::dict d;
  d["F"] = Triangles(r.mesh.triangles);
  d["target_edge_length"] = r.targetEdgeLength;
  d["iterations"] = r.iterations;
  d["faces_before"] = r.facesBefore;
  d["faces_after"] = r.facesAfter;
  d["hausdorff_distance"] = r.hausdorffDistance;
  d["hausdorff_input_to_remeshed"] = r.hausdorffInputToRemeshed;
  d["hausdorff_remeshed_to_input"] = r.hausdorffRemeshedToInput;
  d["min_angle_degrees_before"] = r.minAngleDegreesBefore;
  d["min_angle_degrees_after"] = r.minAngleDegreesAfter;
  return d;
}

// (V' #V by 3, report); with spec.remesh V' is of the remeshed mesh (#V' by 3), its faces in
// report["remesh"]["F"].
py::tuple fairMesh(const PositionsRef& V, const TrianglesRef& F, const FairArguments& a,
                   py::object progress) {
  optimize::FairingOptions options = a.spec.options();  // every rule, before any work
  options.solver.progress = false;
  SolveObserver observer(std::move(progress));  // every stage of the solve reports to it
  options.solver.observer = observer.observer();
  modeling::Mesh mesh = checkedMesh(V, F, "V, F");
  modeling::Stencils stencils = modeling::compileStencils(mesh);
  std::vector<bool> region;
  if (a.regionMask) {
    region = *a.regionMask;
  } else {
    region = modeling::parseRegion(a.regionSpec, mesh, stencils);
  }
  modeling::requireFairableRegion(stencils, region, "region");
  std::optional<modeling::RemeshedRegion> remeshed;
  if (a.spec.remesh) {
    {
      py::gil_scoped_release release;
      remeshed.emplace(modeling::remeshRegion(mesh, region, a.spec.remeshing));
    }
    mesh = remeshed->mesh;
    region = remeshed->region;
    stencils = modeling::compileStencils(mesh);
    modeling::requireFairableRegion(stencils, region, "region remeshed");
  }
  const optimize::FairingMethod method = a.spec.fairingMethod();
  const curvature::BendingOptions material = a.spec.material();
  std::optional<modeling::FairingPatch> patch;
  std::optional<optimize::FairingOutcome> r;
  Positions faired;
  {
    py::gil_scoped_release release;
    patch.emplace(modeling::extractFairingPatch(mesh, stencils, region));
    r.emplace(optimize::fairAndCheck(*patch, options, method, material));
    faired = modeling::scatterPatchPositions(mesh.positions, *patch, r->patchAfter);
  }
  observer.raiseIfStopped();
  const std::optional<optimize::FairingResult>& result = r->fairing;
  py::dict report;
  report["converged"] = r->converged(a.spec.allowSlivers);
  report["method"] = a.spec.method;
  report["solver_converged"] = r->solverConverged;
  if (result) {
    report["termination"] = result->report.termination;
    report["iterations"] = result->report.iterations;
    report["initial_energy"] = result->report.initialEnergy;
    report["final_energy"] = result->report.finalEnergy;
    report["seconds"] = result->report.totalSeconds;
    report["start"] = result->start == optimize::FairingStart::Input ? "input" : "biharmonic";
    report["membrane_final_weight"] = result->membraneWeight;  // after the fade's kept stages
    report["membrane_fade_stages"] = result->membraneFadeStages;
  }
  report["energy_name"] = std::string(curvature::discretizationName(material.discretization));
  report["membrane_weight"] = options.membraneWeight;
  int regionVertices = 0;
  for (bool moves : region) regionVertices += moves;
  report["region_vertices"] = regionVertices;
  report["patch_vertices"] = patch->mesh.vertexCount();
  report["patch_faces"] = patch->mesh.faceCount();
  report["before"] = measureDict(r->before);
  report["after"] = measureDict(r->after);
  report["cgal"] = measureDict(r->cgalMeasures);
  report["checks"] = checkDict(r->checks);
  report["slivers"] = sliverDict(r->slivers);
  std::string failure = r->failure(a.spec.allowSlivers);
  if (!r->solverConverged)
    failure = "the solve did not converge (" + result->report.termination + ")" +
              (failure.empty() ? "" : "; " + failure);
  report["failure"] = failure;
  if (remeshed) report["remesh"] = remeshDict(*remeshed);
  return py::make_tuple(faired, report);
}

}  // namespace

void bindFairing(py::module_& m) {
  py::class_<optimize::FairingSpec>(m, "FairingSpec")
      .def(py::init<>())
      .def_readwrite("bending", &optimize::FairingSpec::bending)
      .def_readwrite("membrane", &optimize::FairingSpec::membrane)
      .def_readwrite("membrane_weight", &optimize::FairingSpec::membraneWeight)
      .def_readwrite("start", &optimize::FairingSpec::start)
      .def_readwrite("metric", &optimize::FairingSpec::metric)
      .def_readwrite("method", &optimize::FairingSpec::method)
      .def_readwrite("allow_slivers", &optimize::FairingSpec::allowSlivers)
      .def_readwrite("remesh", &optimize::FairingSpec::remesh)
      .def_property(
          "remesh_edge_length",
          [](const optimize::FairingSpec& s) { return s.remeshing.targetEdgeLength; },
          [](optimize::FairingSpec& s, std::optional<double> l) {
            s.remeshing.targetEdgeLength = l;
          })
      .def_property(
          "remesh_iterations",
          [](const optimize::FairingSpec& s) { return s.remeshing.iterations; },
          [](optimize::FairingSpec& s, int n) { s.remeshing.iterations = n; })
      .def_property(
          "max_iterations", [](const optimize::FairingSpec& s) { return s.solver.maxIterations; },
          [](optimize::FairingSpec& s, int n) { s.solver.maxIterations = n; });
  py::class_<FairArguments>(m, "FairArguments")
      .def(py::init<>())
      .def_readwrite("spec", &FairArguments::spec)
      .def_readwrite("region_mask", &FairArguments::regionMask)
      .def_readwrite("region_spec", &FairArguments::regionSpec);
  m.def("fair", &fairMesh);
}

}  // namespace flexure::python
