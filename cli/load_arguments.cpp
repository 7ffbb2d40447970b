#include "cli/load_arguments.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "cli/command_files.h"
#include "modeling/errors.h"

namespace flexure::cli {

void addLoadArguments(CLI::App& sub, LoadArguments& a) {
  sub.add_option("--gravity", a.gravity, "Gravity gx,gy,gz (e.g. 0,0,-9.81; default none)");
  sub.add_option("--density", a.density, "ρ, mass per unit rest area")
      ->capture_default_str()
      ->check(positive());
  sub.add_option("--mass", a.mass, "Lumped mass: barycentric | voronoi")->capture_default_str();
  sub.add_option("--obstacle", a.obstacles,
                 "Obstacle (repeatable): plane:nx,ny,nz,d (n.x = d, free side n) | sphere:x,y,z,r");
}

std::vector<double> parseNumbers(const std::string& option, const std::string& text, size_t count) {
  std::vector<double> values;
  std::stringstream stream(text);
  bool ok = true;
  for (std::string item; std::getline(stream, item, ',');) {
    char* end = nullptr;
    const double value = std::strtod(item.c_str(), &end);
    ok = ok && !item.empty() && *end == '\0' && std::isfinite(value);
    values.push_back(value);
  }
  if (!ok || values.size() != count || text.empty() || text.back() == ',')
    throw InputError(option + " " + text + ": expected " + std::to_string(count) +
                     " comma-separated numbers");
  return values;
}

Eigen::Vector3d gravityVector(const LoadArguments& a) {
  if (a.gravity.empty()) return Eigen::Vector3d::Zero();
  const std::vector<double> g = parseNumbers("--gravity", a.gravity, 3);
  return {g[0], g[1], g[2]};
}

std::vector<optimize::Obstacle> obstacleList(const LoadArguments& a) {
  std::vector<optimize::Obstacle> list;
  for (const std::string& spec : a.obstacles)
    list.push_back(optimize::parseObstacle("--obstacle", spec));
  return list;
}

optimize::MassLumping massLumping(const LoadArguments& a) {
  return modeling::parseMassLumping(a.mass, "LoadOptions.mass");
}

optimize::LoadOptions loadOptions(const LoadArguments& a) {
  optimize::LoadOptions load;
  if (!a.gravity.empty()) load.gravity = gravityVector(a);
  load.density = a.density;
  load.mass = massLumping(a);
  return load;
}

}  // namespace flexure::cli
