#include "cli/load_arguments.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "cli/command_files.h"
#include "cli/dynamics_arguments.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"

namespace flexure::cli {

void addLoadArguments(CLI::App& sub, LoadArguments& a) {
  sub.add_option("--gravity", a.gravity, "Gravity gx,gy,gz (e.g. 0,0,-9.81; default none)");
  sub.add_option("--density", a.density, "ρ, mass per unit rest area")
      ->capture_default_str()
      ->check(positive());
  sub.add_option("--mass", a.mass, "Lumped mass: barycentric | voronoi")->capture_default_str();
  sub.add_option("--obstacle", a.obstacles,
                 "Obstacle (repeatable): plane:nx,ny,nz,d (n.x = d, free side n) | sphere:x,y,z,r "
                 "| mesh:FILE[@MOTION] (a triangle mesh, OBJ/OFF/PLY/STL; MOTION as --pin's: "
                 "translate:vx,vy,vz | rotate:ax,ay,az,px,py,pz,omega | none; simulate only)");
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

namespace {

bool isMeshObstacle(const std::string& spec) {
  return spec.rfind("mesh:", 0) == 0;
}

// The triangles of FILE: every polygon a triangle, at least one.
modeling::Mesh obstacleMesh(const std::string& spec, const std::string& file) {
  const modeling::PolygonSoup soup = modeling::readPolygonSoup(file);
  if (soup.polygons.empty()) throw InputError("--obstacle " + spec + ": " + file + " has no faces");
  for (std::size_t p = 0; p < soup.polygons.size(); ++p)
    if (soup.polygons[p].size() != 3)
      throw InputError("--obstacle " + spec + ": " + file + " is not a triangle mesh: face " +
                       std::to_string(p) + " has " + std::to_string(soup.polygons[p].size()) +
                       " vertices");
  return modeling::triangulatePolygons(soup);
}

}  // namespace

std::vector<optimize::Obstacle> obstacleList(const LoadArguments& a) {
  std::vector<optimize::Obstacle> list;
  for (const std::string& spec : a.obstacles)
    if (!isMeshObstacle(spec)) list.push_back(optimize::parseObstacle("--obstacle", spec));
  return list;
}

std::vector<optimize::MeshObstacle> meshObstacleList(const LoadArguments& a) {
  std::vector<optimize::MeshObstacle> list;
  for (const std::string& spec : a.obstacles) {
    if (!isMeshObstacle(spec)) continue;
    std::string file = spec.substr(5), motion;
    const std::size_t at = file.rfind('@');
    if (at != std::string::npos) {
      motion = file.substr(at + 1);
      file.resize(at);
    }
    optimize::MeshObstacle obstacle;
    obstacle.label = "--obstacle " + spec;
    obstacle.mesh = obstacleMesh(spec, file);
    if (!motion.empty() && motion != "none")
      obstacle.motion = parsePinMotion(motion, "--obstacle " + spec + ":");
    list.push_back(std::move(obstacle));
  }
  return list;
}

std::vector<std::string> meshObstacleSpecs(const LoadArguments& a) {
  std::vector<std::string> specs;
  for (const std::string& spec : a.obstacles)
    if (isMeshObstacle(spec)) specs.push_back(spec);
  return specs;
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
