// flexure view: one self-contained HTML page (render/viewer_page.h) of meshes and simulation
// folders, with a linked orbit camera, reflection lines or isophotes, a field with its legend
// (mean curvature, displacement, plastic strain, each face's smallest angle, the error against a
// reference surface), a simulation's frames on a time slider, and a modes folder's
// vibration modes animated with their nodal lines; --open opens it.
// This file reads the inputs and maps the flags to a ViewerPageSpec; the page is the library's.
#include <spawn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/curvature_arguments.h"
#include "curvature/energy_registry.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "render/viewer_page.h"
#include "reports/viewer_fairing.h"
#include "reports/viewer_fields.h"
#include "reports/viewer_modes.h"
#include "reports/viewer_simulation.h"

extern char** environ;

namespace flexure::cli {
namespace {

struct ViewCommandOptions {
  std::vector<std::string> inputs;
  std::string output;
  std::string style = "reflection";
  std::string reference;
  std::string curvatureEnergy;
  bool open = false;
  render::ViewerPageSpec page;
};

bool endsWithHtml(const std::string& path) {
  std::string lower = path;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return (lower.size() > 5 && lower.substr(lower.size() - 5) == ".html") ||
         (lower.size() > 4 && lower.substr(lower.size() - 4) == ".htm");
}

// One input: a mesh file (one frame) or a simulation folder (reports::readSimulationFolder).
render::ViewerMesh readViewerMesh(const std::string& input) {
  if (reports::isSimulationFolder(input)) return reports::readSimulationFolder(input);
  render::ViewerMesh m;
  m.name = std::filesystem::path(input).filename().string();
  modeling::Mesh mesh = modeling::readMesh(input);
  m.triangles = std::move(mesh.triangles);
  m.frames.push_back(std::move(mesh.positions));
  return m;
}

// Opens `page` with $BROWSER, else xdg-open, without waiting; a notice when neither starts.
void openPage(const std::string& page) {
  const char* browser = std::getenv("BROWSER");
  const std::string program = browser && *browser ? browser : "xdg-open";
  std::vector<char*> argv{const_cast<char*>(program.c_str()), const_cast<char*>(page.c_str()),
                          nullptr};
  pid_t pid;
  if (posix_spawnp(&pid, program.c_str(), nullptr, nullptr, argv.data(), environ) != 0)
    std::cerr << "flexure view: could not start " << program << " to open " << page
              << " (set $BROWSER); the page is written\n";
}

void runViewCommand(ViewCommandOptions o, const GlobalOptions& global) {
  if (!endsWithHtml(o.output))
    throw InputError("--output '" + o.output + "': flexure view writes an HTML page (.html)");
  render::ViewerPageSpec& page = o.page;
  const reports::ViewStyle style = reports::parseViewStyle(o.style);
  page.style = style.drawing;
  if (style.field != reports::ViewerField::Curvature && !o.curvatureEnergy.empty())
    throw InputError("--curvature-energy applies to --style curvature only");
  if (style.field == reports::ViewerField::Curvature)
    curvatureEnergy(o.curvatureEnergy);  // refuses a name before any work
  const bool referenced = style.field == reports::ViewerField::Displacement ||
                          style.field == reports::ViewerField::Error;
  if (!referenced && !o.reference.empty())
    throw InputError("--reference applies to --style displacement and error only");
  if (style.field == reports::ViewerField::Error && o.reference.empty())
    throw InputError("--style error needs --reference SURFACE, the mesh to measure against");
  const modeling::Mesh reference =
      o.reference.empty() ? modeling::Mesh{} : modeling::readMesh(o.reference);

  for (const std::string& input : o.inputs) {
    if (reports::isFairingReport(input)) {  // input, CGAL's fair and the result, region outlined
      reports::addFairingReport(page, input);
      continue;
    }
    if (!reports::isModesFolder(input)) {
      page.meshes.push_back(readViewerMesh(input));
      continue;
    }
    // A `flexure modes` folder: each energy's modes, animated, with their nodal lines.
    if (!std::filesystem::exists(std::filesystem::path(input) / "rest.obj"))
      throw InputError(input +
                       ": a modes folder without its rest mesh and mode shapes; write "
                       "them with flexure modes --write-shapes");
    for (render::ViewerMesh& m : reports::readModesFolder(input, page.style))
      page.meshes.push_back(std::move(m));
  }
  if (style.field == reports::ViewerField::Displacement)
    for (const render::ViewerMesh& m : page.meshes)
      if (reference.vertexCount() == 0 && m.frames.size() == 1)
        throw InputError(m.name + ": --style displacement of a mesh needs --reference REST");
  reports::ViewerFieldSources sources;
  if (style.field == reports::ViewerField::Curvature)
    sources.curvatureEnergy = &curvatureEnergy(o.curvatureEnergy);
  sources.rest = reference.positions;
  sources.restName = "--reference " + o.reference;
  sources.reference = reference;
  sources.referenceName = std::filesystem::path(o.reference).filename().string();
  sources.folders = o.inputs;
  reports::addFields(page, style.field, sources);
  page.title = "flexure view: " + o.inputs.front() + (o.inputs.size() > 1 ? " ..." : "");
  // Its own batch, committed here, so that the page is in place before --open shows it.
  modeling::OutputBatch batch;
  const std::size_t bytes = render::writeViewerPage(o.output, page);
  batch.commit();
  if (!global.quiet) {
    std::size_t frames = 0;
    for (const render::ViewerMesh& m : page.meshes) frames += m.frames.size();
    std::cerr << "flexure view: wrote " << o.output << " (" << page.meshes.size() << " meshes, "
              << frames << " frames, " << bytes / 1024 << " KiB)\n";
  }
  if (o.open) openPage(o.output);
}

}  // namespace

void registerViewCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<ViewCommandOptions>();
  ViewCommandOptions& o = *options;
  CLI::App* sub = app.add_subcommand(
      "view", "An interactive HTML page (three.js, offline) of meshes and simulation folders");
  auto files = CommandFiles::of(*sub);
  files
      ->inputs(
          "inputs", o.inputs,
          "Meshes (.obj, .off, .ply, .stl), simulation folders (flexure simulate -o DIR) and "
          "modes folders (flexure modes --write-shapes -o DIR) and fairing reports (flexure fair "
          "--report R.json), each in its own view (or one with --overlay)")
      ->required();
  files->output("-o,--output", o.output, "Output page (.html)")->required();
  sub->add_option("--style", o.style,
                  reports::viewStyleNames() +
                      " (plastic: a simulation's plastic strain; angle: each face's smallest "
                      "angle; error: the distance to --reference; default reflection)");
  sub->add_option("--stripes", o.page.stripeCount,
                  "Number of reflection stripes / isophote bands (default 12)")
      ->check(inRange(1, 1000));
  sub->add_option("--stripe-width", o.page.stripeWidth,
                  "Dark fraction of each stripe period, in (0, 1) (default 0.5)");
  sub->add_option("--curvature-energy", o.curvatureEnergy, curvatureEnergyHelp());
  files->input("--reference", o.reference,
               "Displacement style: the rest mesh (default: a simulation's first frame); error "
               "style: the reference surface (any mesh)");
  sub->add_flag("--overlay", o.page.overlay, "Every input in one view instead of one view each");
  sub->add_flag("--multisample", o.page.multisample,
                "Draw 4x multisampled: smoother silhouettes, about half the frame rate on "
                "software rendering");
  sub->add_flag("--open", o.open, "Open the page with $BROWSER or xdg-open once written");
  sub->footer(
      "Example: flexure view bowl.obj faired.obj --style curvature -o bowl.html --open\n"
      "The page is self-contained (three.js embedded): it works offline from file://.");
  files->onRun(global, [options, &global] { runViewCommand(*options, global); });
}

}  // namespace flexure::cli
