#include "cli/membrane_arguments.h"

#include "cli/command_files.h"

namespace flexure::cli {

void addMembraneArguments(CLI::App& sub, MembraneArguments& a, const std::string& help) {
  sub.add_option("--membrane", a.model, help);
  sub.add_option("--young", a.young, "stvk: Young's modulus x thickness")
      ->capture_default_str()
      ->check(positive());
  sub.add_option("--membrane-poisson", a.poisson, "stvk: Poisson's ratio")->capture_default_str();
  sub.add_option("--length-stiffness", a.lengthStiffness, "springs: k_L")
      ->capture_default_str()
      ->check(positive());
  sub.add_option("--area-stiffness", a.areaStiffness, "springs: k_A")
      ->capture_default_str()
      ->check(positive());
  sub.add_option("--shape-stiffness", a.shapeStiffness, "conformal: k_S (triangle shape, not size)")
      ->capture_default_str()
      ->check(positive());
}

curvature::MembraneOptions membraneOptions(const MembraneArguments& a) {
  curvature::MembraneOptions m;
  m.model = curvature::parseMembraneModel(a.model);
  m.young = a.young;
  m.poisson = a.poisson;
  m.lengthStiffness = a.lengthStiffness;
  m.areaStiffness = a.areaStiffness;
  m.shapeStiffness = a.shapeStiffness;
  return m;
}

std::vector<std::unique_ptr<curvature::EnergyTerm>> makeMembrane(const MembraneArguments& a,
                                                                 const modeling::Stencils& stencils,
                                                                 const modeling::RestState& rest) {
  return curvature::makeMembraneEnergy(stencils, rest, membraneOptions(a));
}

}  // namespace flexure::cli
