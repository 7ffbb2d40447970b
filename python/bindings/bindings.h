// What the binding files of flexure._flexure share: the array types, the checked mesh, the bending
// options as Python names them, and one function per file that adds its part to the module.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <utility>

#include "curvature/bending_spec.h"
#include "curvature/energy_registry.h"
#include "curvature/membrane_energy.h"
#include "modeling/mesh.h"
#include "optimize/modes/vibration_modes.h"
#include "optimize/solvers/newton_stop.h"

namespace flexure::python {

using modeling::Positions;
using modeling::Triangles;
using PositionsRef = Eigen::Ref<const Positions>;  // #V by 3 float64, row-major
using TrianglesRef = Eigen::Ref<const Triangles>;  // #F by 3 int32

// A checked mesh from V (#V by 3) and F (#F by 3); InputError names `source` and the element.
modeling::Mesh checkedMesh(const PositionsRef& V, const TrianglesRef& F, const std::string& source);

// The bending options as Python names them (the strings are the registry's and the CLI's values).
// The keyword arguments of a bending energy map one to one onto the library's spec (its options()
// holds the rules and names the fields, which withKeywordNames turns into the keywords).
using BendingArguments = curvature::BendingSpec;
inline curvature::BendingOptions bendingOptions(const BendingArguments& a) {
  return a.options();
}

// A membrane's parameters as Python names them: the library's defaults
// (curvature::MembraneOptions) until Python sets one. The argument structs that take a membrane
// derive from it.
struct MembraneFields {
  double young = curvature::MembraneOptions{}.young;
  double membranePoisson = curvature::MembraneOptions{}.poisson;
  double lengthStiffness = curvature::MembraneOptions{}.lengthStiffness;
  double areaStiffness = curvature::MembraneOptions{}.areaStiffness;
  double shapeStiffness = curvature::MembraneOptions{}.shapeStiffness;

  // The membrane `model` ("stvk" | "springs" | "conformal" | "mips") with these parameters.
  curvature::MembraneOptions membraneOptions(const std::string& model) const;
};

// Adds MembraneFields' parameters, as Python names them, to the class of an argument struct that
// derives from it.
template <typename Class>
Class& defMembraneFields(Class& c) {
  return c.def_readwrite("young", &MembraneFields::young)
      .def_readwrite("membrane_poisson", &MembraneFields::membranePoisson)
      .def_readwrite("length_stiffness", &MembraneFields::lengthStiffness)
      .def_readwrite("area_stiffness", &MembraneFields::areaStiffness)
      .def_readwrite("shape_stiffness", &MembraneFields::shapeStiffness);
}

// A long solve's observer for Python (optimize::IterationObserver), for a solve run with the GIL
// released: at every iteration it takes the GIL, calls `progress` (unless None) with a dict
// {"iteration", "energy", "gradient_norm"}, and checks for signals (Ctrl-C: KeyboardInterrupt).
// Whatever Python raised stops the solve, and raiseIfStopped() raises it once the solve has
// returned, so that the call returns nothing. Built and destroyed with the GIL held.
class SolveObserver {
 public:
  explicit SolveObserver(pybind11::object progress) : progress_(std::move(progress)) {}
  optimize::IterationObserver observer();
  // With the GIL held, after the solve: the exception that stopped it, if any.
  void raiseIfStopped();

 private:
  pybind11::object progress_;
  std::optional<pybind11::error_already_set> raised_;
};

void bindSimulation(pybind11::module_& m);
void bindFairing(pybind11::module_& m);
void bindModes(pybind11::module_& m);
void bindRender(pybind11::module_& m);
void bindViewer(pybind11::module_& m);
void bindMeshes(pybind11::module_& m);
void bindStudy(pybind11::module_& m);

}  // namespace flexure::python
