// The command-line options of a gravity load and of obstacles, shared by minimize (static) and
// simulate (dynamic): --gravity gx,gy,gz, --density ρ (mass per unit rest area), --mass (the
// lumping) and --obstacle plane:nx,ny,nz,d | sphere:x,y,z,r | mesh:FILE[@MOTION] (repeatable;
// optimize/assembly/obstacles.h, optimize/assembly/mesh_obstacles.h).
#pragma once

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <string>
#include <vector>

#include "optimize/assembly/obstacles.h"
#include "optimize/modes/vibration_modes.h"
#include "optimize/problem.h"

namespace flexure::cli {

struct LoadArguments {
  std::string gravity;  // empty: none
  double density = 1.0;
  std::string mass = "barycentric";
  std::vector<std::string> obstacles;
};

void addLoadArguments(CLI::App& sub, LoadArguments& arguments);

// `count` comma-separated finite numbers; InputError quoting `option` and the text otherwise.
std::vector<double> parseNumbers(const std::string& option, const std::string& text, size_t count);

// g (zero when --gravity is not given).
Eigen::Vector3d gravityVector(const LoadArguments& arguments);
optimize::MassLumping massLumping(const LoadArguments& arguments);
// The parsed plane and sphere --obstacle specs (InputError on a malformed one).
std::vector<optimize::Obstacle> obstacleList(const LoadArguments& arguments);
// The mesh:FILE[@MOTION] --obstacle specs, read (InputError naming the spec for an unreadable
// file, a face that is not a triangle, no faces, or a malformed motion), and their texts.
std::vector<optimize::MeshObstacle> meshObstacleList(const LoadArguments& arguments);
std::vector<std::string> meshObstacleSpecs(const LoadArguments& arguments);

// The load of a problem: g (none when --gravity is not given), ρ and the lumping.
optimize::LoadOptions loadOptions(const LoadArguments& arguments);

}  // namespace flexure::cli
