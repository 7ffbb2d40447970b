// flexure._flexure: the library's problem, energies and solvers for Python (pybind11). The
// pure-Python package flexure/ on top validates arguments and documents every function; this
// layer converts types and releases the GIL during long work.
//
// Arrays: V is bound as Eigen::Ref<const Positions> (#V by 3, row-major), which maps a
// C-contiguous float64 numpy array without a copy (data_address shows it); F as
// Eigen::Ref<const Triangles> (#F by 3 int32).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <algorithm>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "curvature/energy_registry.h"
#include "curvature/membrane_energy.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/mesh_check.h"
#include "modeling/mesh_io.h"
#include "modeling/polynomial_surface.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/configuration_energy.h"
#include "optimize/inelastic/plasticity.h"
#include "optimize/linear/heap_reuse.h"
#include "optimize/linear/linearized_solver.h"
#include "optimize/problem.h"
#include "optimize/solvers/static_energy.h"
#include "python/bindings/bindings.h"
#include "python/bindings/keyword_names.h"

namespace py = pybind11;

namespace flexure::python {
namespace {

py::dict bendingReport(const curvature::BendingOptions& b) {
  py::dict d;
  d["energy_name"] = std::string(curvature::discretizationName(b.discretization));
  d["poisson"] = curvature::effectivePoisson(b);
  d["stiffness"] = b.stiffness;
  const curvature::EnergyEntry& entry = curvature::energyEntry(b.discretization);
  if (entry.readsVertexArea) d["vertex_area"] = curvature::vertexAreaName(b.vertexArea);
  if (entry.readsHingeAngle) d["hinge_angle"] = curvature::hingeAngleName(b.hingeAngle);
  return d;
}

// The bending energy of V against the rest mesh (V_rest, F), as `flexure energy` computes it:
// nothing held; midedge's ξ minimized over, the boundary ones clamped to `boundarySurface`'s
// normals when it is given.
py::dict energyOf(const PositionsRef& restV, const TrianglesRef& F, const PositionsRef& V,
                  const BendingArguments& arguments, const std::optional<std::string>& surfaceSpec,
                  bool linearized) {
  optimize::ConfigurationEnergyOptions options;
  options.bending = bendingOptions(arguments);
  if (surfaceSpec) options.boundarySurface = modeling::PolynomialSurface::parse(*surfaceSpec);
  options.linearized = linearized;
  options.validate();
  const modeling::Mesh restMesh = checkedMesh(restV, F, "V_rest, F");
  const Positions current = V;
  optimize::ConfigurationEnergy e;
  {
    py::gil_scoped_release release;
    e = optimize::configurationEnergy(restMesh, current, options);
  }
  py::dict d = bendingReport(options.bending);
  d["linearized"] = linearized;
  d["energy"] = e.energy;
  d["elements"] = e.elements;
  d["element_kind"] = e.elementKind;
  d["covered_area"] = e.coveredArea;
  d["energy_per_area"] = e.perArea();
  if (!e.boundaryXi.empty()) d["boundary_xi"] = e.boundaryXi;
  return d;
}

// Everything buildProblem takes, as the Python arguments name it.
struct ProblemArguments : MembraneFields {
  BendingArguments bending;
  std::string dof = "height";
  std::optional<std::vector<bool>> fixed;
  int fixedRings = 2;
  std::optional<Positions> boundaryPositions;
  std::optional<std::string> boundarySurface;
  std::optional<std::string> boundaryNormals;  // empty: clamped with a surface, else free
  bool linearizedClamp = false;
  std::optional<std::string> membrane;
  std::optional<Eigen::Vector3d> gravity;
  double density = 1.0;
};

optimize::ProblemOptions problemOptions(const ProblemArguments& a) {
  optimize::ProblemOptions p;
  p.bending = bendingOptions(a.bending);
  p.dof = optimize::parseDofMode(a.dof, "ProblemOptions.dof");
  if (a.fixed) p.fixedVertex = *a.fixed;
  p.fixedRings = a.fixedRings;
  if (a.boundaryPositions) p.boundaryPositions = *a.boundaryPositions;
  if (a.boundarySurface) p.boundarySurface = modeling::PolynomialSurface::parse(*a.boundarySurface);
  p.boundaryNormals = optimize::parseBoundaryNormals(
      a.boundaryNormals.value_or(a.boundarySurface ? "clamped" : "free"));
  p.linearizedClamp = a.linearizedClamp;
  if (a.membrane) p.membrane = a.membraneOptions(*a.membrane);
  p.load.gravity = a.gravity;
  p.load.density = a.density;
  return p;
}

// A Problem with its static objective E − fᵀx + B over the free unknowns (Newton's: the same
// free set, derivatives and Hessian pattern as minimize's). Not movable: the objective keeps
// references into the problem.
class BoundProblem {
 public:
  BoundProblem(optimize::Problem problem, curvature::BendingOptions bending)
      : problem_(std::move(problem)),
        bending_(bending),
        terms_(problem_.termPointers()),
        assembly_(terms_, problem_.freeUnknowns(), static_cast<int>(problem_.rest.positions.rows()),
                  problem_.dof == optimize::DofMode::Height ? curvature::Derivatives::HeightOnly
                                                            : curvature::Derivatives::All),
        objective_(assembly_, startConfiguration(), terms_, problem_.externalForce,
                   problem_.obstacles, optimize::HessianProjection::Exact) {}
  BoundProblem(const BoundProblem&) = delete;
  BoundProblem& operator=(const BoundProblem&) = delete;

  const optimize::Problem& problem() const { return problem_; }
  const curvature::BendingOptions& bending() const { return bending_; }
  const optimize::HessianAssembly& assembly() const { return assembly_; }
  optimize::StaticEnergy& objective() { return objective_; }

  optimize::Configuration startConfiguration() const {
    return {problem_.boundary.start,
            problem_.usesEdgeUnknowns() ? problem_.boundary.xi : Eigen::VectorXd()};
  }

 private:
  optimize::Problem problem_;
  curvature::BendingOptions bending_;
  std::vector<const curvature::EnergyTerm*> terms_;
  optimize::HessianAssembly assembly_;
  optimize::StaticEnergy objective_;
};

std::unique_ptr<BoundProblem> makeProblem(const PositionsRef& restV, const TrianglesRef& F,
                                          const ProblemArguments& arguments) {
  const optimize::ProblemOptions options = problemOptions(arguments);
  const modeling::Mesh rest = checkedMesh(restV, F, "V_rest, F");
  py::gil_scoped_release release;
  return std::make_unique<BoundProblem>(optimize::buildProblem(rest, options), options.bending);
}

// (E, ∇E (n), the Hessian's upper-triangle values on the pattern, empty for kind "none").
py::tuple evaluateProblem(BoundProblem& p, const Eigen::VectorXd& y, const std::string& kind) {
  const curvature::SecondDerivatives second = curvature::parseSecondDerivatives(kind);
  optimize::HessianEvaluation e;
  {
    py::gil_scoped_release release;
    e = p.objective().evaluate(y, second);
  }
  py::array_t<double> values(static_cast<py::ssize_t>(e.values.size()));
  std::copy(e.values.begin(), e.values.end(), values.mutable_data());
  return py::make_tuple(e.energy, e.gradient, values);
}

py::dict reportDict(const optimize::MinimizeReport& r) {
  py::dict d;
  d["converged"] = r.converged;
  d["solver"] = r.solver;
  d["termination"] = r.termination;
  d["iterations"] = r.iterations;
  d["factorizations"] = r.factorizations;
  d["initial_energy"] = r.initialEnergy;
  d["final_energy"] = r.finalEnergy;
  d["final_gradient_norm"] = r.gradientNorm;
  py::dict seconds;
  seconds["total"] = r.totalSeconds;
  seconds["evaluation"] = r.evaluationSeconds;
  seconds["linear_solver"] = r.linearSolverSeconds;
  seconds["ordering"] = r.orderingSeconds;
  d["seconds"] = seconds;
  py::dict problem;
  problem["vertices"] = r.vertices;
  problem["fixed_vertices"] = r.fixedVertices;
  problem["free_edge_unknowns"] = r.freeEdgeUnknowns;
  problem["unknowns"] = r.unknowns;
  problem["residuals"] = r.residuals;
  d["problem"] = problem;
  return d;
}

struct SolverArguments {
  std::string solver = "newton";
  std::string hessian = "exact";
  bool linearized = false;
  std::string start = "linearized";
  int maxIterations = 200;
  double functionTolerance = 1e-12, gradientTolerance = 1e-10, parameterTolerance = 1e-12;
  int threads = 2;
};

optimize::MinimizeOptions minimizeOptions(const SolverArguments& a) {
  optimize::MinimizeOptions o;
  o.solver = optimize::parseSolver(a.solver);
  o.hessian = optimize::parseHessianMode(a.hessian);
  o.start = optimize::parseStart(a.start);
  o.linearized = a.linearized;
  o.maxIterations = a.maxIterations;
  o.functionTolerance = a.functionTolerance;
  o.gradientTolerance = a.gradientTolerance;
  o.parameterTolerance = a.parameterTolerance;
  o.threads = a.threads;
  o.validate();
  return o;
}

// (V, ξ, report); the report also says "energy_name", "poisson", "dof" and "linearized".
// `progress`: None or a callable (SolveObserver); Ctrl-C stops the solve either way.
py::tuple minimizeProblem(const BoundProblem& p, const SolverArguments& a, py::object progress) {
  optimize::MinimizeOptions o = minimizeOptions(a);
  SolveObserver observer(std::move(progress));
  o.observer = observer.observer();
  optimize::MinimizeResult result;
  {
    py::gil_scoped_release release;
    result = optimize::minimize(p.problem(), o);
  }
  observer.raiseIfStopped();
  py::dict report = reportDict(result.report);
  const py::dict bending = bendingReport(p.bending());
  report["energy_name"] = bending["energy_name"];
  report["poisson"] = bending["poisson"];
  report["dof"] = p.problem().dof == optimize::DofMode::Height ? "height" : "xyz";
  report["linearized"] = a.linearized;
  return py::make_tuple(result.positions, result.xi, report);
}

// Quasi-static forming (plasticity.h formPlastically) of the problem `arguments` build on (V_rest,
// F): (V, ξ, report). The report is FormingReport's, with the last solve's report and the plastic
// state (per bending element P_b and its equivalent curvature, per face P_m).
py::tuple formProblem(const PositionsRef& restV, const TrianglesRef& F,
                      const ProblemArguments& arguments, const SolverArguments& solver,
                      const optimize::PlasticityOptions& plasticity,
                      const optimize::FormingOptions& forming, py::object progress) {
  const optimize::ProblemOptions options = problemOptions(arguments);
  optimize::MinimizeOptions o = minimizeOptions(solver);
  SolveObserver observer(std::move(progress));  // every solve of the forming reports to it
  o.observer = observer.observer();
  plasticity.validate();
  forming.validate();
  const modeling::Mesh rest = checkedMesh(restV, F, "V_rest, F");
  optimize::FormingResult formed;
  {
    py::gil_scoped_release release;
    optimize::Problem problem = optimize::buildProblem(rest, options);
    formed = optimize::formPlastically(problem, plasticity, forming, o);
  }
  observer.raiseIfStopped();
  const optimize::FormingReport& r = formed.report;
  py::dict report;
  report["converged"] = r.converged;
  report["solves"] = r.solves;
  report["yielded_elements"] = r.yieldedElements;
  report["yielded_faces"] = r.yieldedFaces;
  report["dissipation"] = r.dissipation;
  report["release_pins"] = r.releasePins;
  report["last_solve"] = reportDict(r.lastSolve);
  report["plastic_strain"] = formed.state.plasticStrain;
  report["plastic_curvature"] = optimize::equivalentPlasticCurvatures(formed.state);
  report["yielded"] = formed.state.yielded;
  report["membrane_plastic_strain"] = formed.state.membranePlasticStrain;
  report["membrane_yielded"] = formed.state.membraneYielded;
  return py::make_tuple(formed.positions, formed.xi, report);
}

// A LinearizedSolver on a problem's terms, rest state and held unknowns: J at rest and
// J_freeᵀ J_free factored once; every solve takes new boundary values.
class BoundLinearizedSolver {
 public:
  BoundLinearizedSolver(const BoundProblem& p, bool inPlane) : problem_(p.problem()) {
    optimize::LinearizedUnknowns unknowns;
    unknowns.fixedVertex = problem_.boundary.fixedVertex;
    unknowns.fixedEdge = problem_.boundary.fixedEdge;
    unknowns.heightOnly = problem_.dof == optimize::DofMode::Height;
    unknowns.fixedMoveInPlane = inPlane || !unknowns.heightOnly;
    py::gil_scoped_release release;
    solver_ = std::make_unique<optimize::LinearizedSolver>(
        problem_.termPointers(), problem_.rest.positions, problem_.restXi, unknowns);
  }

  // (V, ξ, energies) for the held vertices at `boundary`'s rows (#V by 3; the free rows are
  // ignored) and the held ξ at `xi` (#E; the problem's when empty).
  py::tuple solve(const PositionsRef& boundary, const std::optional<Eigen::VectorXd>& xi) const {
    const optimize::BoundaryConditions bc =
        optimize::withHeldValues(problem_.boundary, boundary, xi);
    optimize::LinearizedSolution s;
    {
      py::gil_scoped_release release;
      s = solver_->solve(bc);
    }
    py::dict d;
    d["initial_energy"] = s.initialEnergy;
    d["energy"] = s.energy;
    d["gradient_norm"] = s.gradientNorm;
    d["initial_gradient_norm"] = s.initialGradientNorm;
    return py::make_tuple(s.positions, s.xi, d);
  }

  int freeCount() const { return solver_->freeCount(); }
  int factorizations() const { return solver_->factorizations(); }
  double factorSeconds() const { return solver_->factorSeconds(); }
  double jacobianSeconds() const { return solver_->jacobianSeconds(); }

 private:
  const optimize::Problem& problem_;
  std::unique_ptr<optimize::LinearizedSolver> solver_;
};

py::tuple readMesh(const std::string& path) {
  std::vector<std::string> notices;
  modeling::Mesh mesh;
  {
    py::gil_scoped_release release;
    mesh = modeling::readMesh(path, &notices);
  }
  return py::make_tuple(mesh.positions, mesh.triangles, notices);
}

void writeMesh(const std::string& path, const PositionsRef& V, const TrianglesRef& F) {
  const modeling::Mesh mesh = checkedMesh(V, F, path);
  py::gil_scoped_release release;
  modeling::writeMesh(path, mesh);
}

py::tuple generate(const std::string& family, int n, std::uint64_t seed,
                   std::optional<double> aspect) {
  modeling::GeneratorOptions o;
  o.family = modeling::parseMeshFamily(family);
  o.n = n;
  o.seed = seed;
  o.aspect = aspect;
  modeling::Mesh mesh;
  {
    py::gil_scoped_release release;
    mesh = modeling::generateMesh(o);
  }
  return py::make_tuple(mesh.positions, mesh.triangles);
}

// The bending and problem arguments, the energy, Problem, minimize and the LinearizedSolver.
void bindProblem(py::module_& m) {
  namespace fo = flexure::optimize;
  py::class_<BendingArguments>(m, "BendingArguments")
      .def(py::init<>())
      .def_readwrite("energy", &BendingArguments::energy)
      .def_readwrite("poisson", &BendingArguments::poisson)
      .def_readwrite("stiffness", &BendingArguments::stiffness)
      .def_readwrite("vertex_area", &BendingArguments::vertexArea)
      .def_readwrite("hinge_angle", &BendingArguments::hingeAngle)
      .def_readwrite("flat_rest", &BendingArguments::flatRest);
  m.def("energy", &energyOf);

  py::class_<ProblemArguments> problemArguments(m, "ProblemArguments");
  defMembraneFields(problemArguments)
      .def(py::init<>())
      .def_readwrite("bending", &ProblemArguments::bending)
      .def_readwrite("dof", &ProblemArguments::dof)
      .def_readwrite("fixed", &ProblemArguments::fixed)
      .def_readwrite("fixed_rings", &ProblemArguments::fixedRings)
      .def_readwrite("boundary_positions", &ProblemArguments::boundaryPositions)
      .def_readwrite("boundary_surface", &ProblemArguments::boundarySurface)
      .def_readwrite("boundary_normals", &ProblemArguments::boundaryNormals)
      .def_readwrite("linearized_clamp", &ProblemArguments::linearizedClamp)
      .def_readwrite("membrane", &ProblemArguments::membrane)
      .def_readwrite("gravity", &ProblemArguments::gravity)
      .def_readwrite("density", &ProblemArguments::density);

  py::class_<SolverArguments>(m, "SolverArguments")
      .def(py::init<>())
      .def_readwrite("solver", &SolverArguments::solver)
      .def_readwrite("hessian", &SolverArguments::hessian)
      .def_readwrite("linearized", &SolverArguments::linearized)
      .def_readwrite("start", &SolverArguments::start)
      .def_readwrite("max_iterations", &SolverArguments::maxIterations)
      .def_readwrite("function_tolerance", &SolverArguments::functionTolerance)
      .def_readwrite("gradient_tolerance", &SolverArguments::gradientTolerance)
      .def_readwrite("parameter_tolerance", &SolverArguments::parameterTolerance)
      .def_readwrite("threads", &SolverArguments::threads);

  py::class_<BoundProblem>(m, "Problem")
      .def(py::init(&makeProblem))
      .def_property_readonly("size", [](const BoundProblem& p) { return p.assembly().size(); })
      .def_property_readonly("free_unknowns",
                             [](const BoundProblem& p) { return p.assembly().freeUnknowns(); })
      .def_property_readonly("column_start",
                             [](const BoundProblem& p) { return p.assembly().columnStart(); })
      .def_property_readonly("row_index",
                             [](const BoundProblem& p) { return p.assembly().rowIndex(); })
      .def_property_readonly("rest_positions",
                             [](const BoundProblem& p) { return p.problem().rest.positions; })
      .def_property_readonly("rest_xi", [](const BoundProblem& p) { return p.problem().restXi; })
      .def_property_readonly("start_positions",
                             [](const BoundProblem& p) { return p.problem().boundary.start; })
      .def_property_readonly("start_xi",
                             [](const BoundProblem& p) { return p.startConfiguration().xi; })
      .def_property_readonly("fixed_vertex",
                             [](const BoundProblem& p) { return p.problem().boundary.fixedVertex; })
      .def_property_readonly("fixed_edge",
                             [](const BoundProblem& p) { return p.problem().boundary.fixedEdge; })
      .def_property_readonly("uses_edge_unknowns",
                             [](const BoundProblem& p) { return p.problem().usesEdgeUnknowns(); })
      .def("free_values",
           [](BoundProblem& p, const Positions& V, const Eigen::VectorXd& xi) {
             return p.objective().freeValues(fo::Configuration{V, xi});
           })
      .def("configuration",
           [](BoundProblem& p, const Eigen::VectorXd& y) {
             const fo::Configuration c = p.objective().configuration(y);
             return py::make_tuple(c.positions, c.xi);
           })
      .def("evaluate", &evaluateProblem)
      .def("minimize", &minimizeProblem);
  m.def("form", &formProblem);

  py::class_<BoundLinearizedSolver>(m, "LinearizedSolver")
      .def(py::init<const BoundProblem&, bool>(), py::keep_alive<1, 2>())
      .def("solve", &BoundLinearizedSolver::solve)
      .def_property_readonly("free_count", &BoundLinearizedSolver::freeCount)
      .def_property_readonly("factorizations", &BoundLinearizedSolver::factorizations)
      .def_property_readonly("factor_seconds", &BoundLinearizedSolver::factorSeconds)
      .def_property_readonly("jacobian_seconds", &BoundLinearizedSolver::jacobianSeconds);
}

}  // namespace

}  // namespace flexure::python

PYBIND11_MODULE(_flexure, m) {
  using namespace flexure::python;
  m.doc() = "flexure's C++ library (use the flexure package, which checks arguments)";
  m.attr("__version__") = FLEXURE_VERSION;

  static py::exception<flexure::NumericalError> numericalError(m, "NumericalError",
                                                               PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const flexure::InputError& e) {
      PyErr_SetString(PyExc_ValueError, withKeywordNames(e.what()).c_str());
    } catch (const flexure::NumericalError& e) {
      numericalError(withKeywordNames(e.what()).c_str());
    }
  });

  m.def(
      "data_address",
      [](const PositionsRef& V) { return reinterpret_cast<std::uintptr_t>(V.data()); },
      "The address the binding reads V (#V by 3) at: V's own when it is not copied.");
  m.def("energies", &flexure::curvature::energyNameList);
  m.def("reuse_freed_memory", &flexure::optimize::reuseFreedMemory);
  m.def("read_mesh", &readMesh);
  m.def("write_mesh", &writeMesh);
  m.def("mesh", &generate);

  bindProblem(m);
  bindSimulation(m);
  bindFairing(m);
  bindModes(m);
  bindRender(m);
  bindViewer(m);
  bindMeshes(m);
  bindStudy(m);
}
