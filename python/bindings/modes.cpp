// flexure._flexure.modes: the vibration modes of a plate or shell as flexure modes solves them for
// one energy (one problem with nothing held and no boundary values; the support and the clamp are
// ModesOptions').
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "curvature/membrane_energy.h"
#include "modeling/errors.h"
#include "optimize/modes/vibration_modes.h"
#include "optimize/problem.h"
#include "python/bindings/bindings.h"

namespace py = pybind11;

namespace flexure::python {
namespace {

struct ModesArguments : MembraneFields {
  BendingArguments bending;
  int count = 12;
  std::string support = "clamped";
  std::optional<std::string> clamp;  // empty: normals for midedge, else rings
  std::optional<std::vector<bool>> fixed;
  std::string dof = "height";
  std::optional<std::string> membrane;
  std::string mass = "barycentric";
  double density = 1.0;
  double length = 0.0;
  bool nodalLines = true;
};

// The arguments mapped to the library's spec of a modes run, validated, and the options for the
// one energy (optimize::ModesSpec holds the rules; withKeywordNames names the keywords).
optimize::ModesOptions modesOptions(const ModesArguments& a, const curvature::BendingOptions& b) {
  optimize::ModesWords words;
  words.count = a.count;
  words.support = a.support;
  words.mass = a.mass;
  words.density = a.density;
  words.bendingStiffness = b.stiffness;
  words.length = a.length;
  words.dof = a.dof;
  words.clamp = a.clamp.value_or("");
  words.membrane = a.membrane.has_value();
  optimize::ModesSpec spec = optimize::modesSpec(words);
  if (a.fixed) spec.modes.extraFixed = *a.fixed;
  return spec.forEnergy(b);
}

py::dict modeDict(const optimize::VibrationMode& mode, const optimize::Problem& problem,
                  bool nodalLines) {
  py::dict d;
  d["omega_squared"] = mode.omegaSquared;
  d["omega"] = mode.omega;
  d["lambda"] = mode.lambda;
  d["zero"] = mode.zero;
  d["multiplicity"] = mode.multiplicity;
  d["residual"] = mode.residual;
  d["nodal_length"] = mode.nodalLength;
  d["participation"] = mode.participation;  // participationRatio; localized below 0.1
  d["localized"] = mode.localized;
  d["shape"] = mode.shape;
  if (nodalLines) {
    const auto segments = optimize::nodalSegments(problem.stencils, problem.rest, mode.shape);
    py::array_t<double> lines(
        {static_cast<py::ssize_t>(segments.size()), py::ssize_t(2), py::ssize_t(3)});
    auto w = lines.mutable_unchecked<3>();
    for (size_t s = 0; s < segments.size(); ++s)
      for (int c = 0; c < 3; ++c) {
        w(s, 0, c) = segments[s].first[c];
        w(s, 1, c) = segments[s].second[c];
      }
    d["nodal_lines"] = lines;
  }
  return d;
}

py::dict modesOf(const PositionsRef& V, const TrianglesRef& F, const ModesArguments& a) {
  const curvature::BendingOptions b = bendingOptions(a.bending);
  const optimize::ModesOptions options = modesOptions(a, b);
  optimize::ProblemOptions p;
  p.bending = b;
  p.dof = options.dof;
  if (a.membrane) p.membrane = a.membraneOptions(*a.membrane);
  p.fixedRings = 0;
  p.boundaryNormals = optimize::BoundaryNormals::Free;
  const modeling::Mesh mesh = checkedMesh(V, F, "V, F");
  std::optional<optimize::Problem> problem;
  optimize::ModesResult r;
  {
    py::gil_scoped_release release;
    problem.emplace(optimize::buildProblem(mesh, p));
    r = optimize::vibrationModes(problem->termPointers(), problem->stencils, problem->rest,
                                 problem->restXi, options);
  }
  py::list modes;
  for (const optimize::VibrationMode& mode : r.modes)
    modes.append(modeDict(mode, *problem, a.nodalLines));
  py::dict d;
  d["energy"] = std::string(curvature::discretizationName(b.discretization));
  d["poisson"] = curvature::effectivePoisson(b);
  d["support"] = optimize::supportName(options.support);
  if (options.support == optimize::Support::Clamped)
    d["clamp"] = optimize::clampName(options.clamp);
  d["rigid_modes"] = r.rigidModes;
  d["zero_modes"] = r.zeroModes;
  d["spurious_zero_modes"] = r.spuriousZeroModes;
  d["flexible_modes"] = r.flexibleModes;
  d["length"] = r.length;
  d["flexural_rigidity"] = r.flexuralRigidity;
  d["shift"] = r.shift;
  d["unknowns"] = r.unknowns;
  d["vertex_unknowns"] = r.massUnknowns;
  d["fixed_vertices"] = r.fixedVertices;
  d["lanczos_solves"] = r.operations;
  d["lanczos_restarts"] = r.restarts;
  d["seconds"] = r.totalSeconds;
  d["modes"] = modes;
  return d;
}

}  // namespace

void bindModes(py::module_& m) {
  py::class_<ModesArguments> modesArguments(m, "ModesArguments");
  defMembraneFields(modesArguments)
      .def(py::init<>())
      .def_readwrite("bending", &ModesArguments::bending)
      .def_readwrite("count", &ModesArguments::count)
      .def_readwrite("support", &ModesArguments::support)
      .def_readwrite("clamp", &ModesArguments::clamp)
      .def_readwrite("fixed", &ModesArguments::fixed)
      .def_readwrite("dof", &ModesArguments::dof)
      .def_readwrite("membrane", &ModesArguments::membrane)
      .def_readwrite("mass", &ModesArguments::mass)
      .def_readwrite("density", &ModesArguments::density)
      .def_readwrite("length", &ModesArguments::length)
      .def_readwrite("nodal_lines", &ModesArguments::nodalLines);
  m.def("modes", &modesOf);
}

}  // namespace flexure::python
