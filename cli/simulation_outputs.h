// flexure simulate's output files (internal to cli/): the frame meshes and images, the fragments,
// energies.csv, energies.png, report.json and the video.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cli/simulation_arguments.h"
#include "cli/simulation_recording.h"
#include "optimize/inelastic/fracturing.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace flexure::cli {

// Whether `name` is a file a simulation writes in its output directory: energies.csv,
// energies.png, report.json, frame-*.obj, frame-*.png, fragment-*.obj, obstacle-*.obj.
bool isSimulationFile(const std::string& name);

// The frame meshes, their images (with `look`), energies.csv, energies.png and report.json in
// `dir`; the files of an earlier run there that this one did not write go at the commit.
void writeOutputs(const SimulateOptions& o, const std::optional<render::RenderOptions>& look,
                  render::OffscreenContext* context, const Recording& recording,
                  const std::string& title, const nlohmann::json& report,
                  const optimize::FracturingDynamics& dynamics, const std::filesystem::path& dir);

}  // namespace flexure::cli
