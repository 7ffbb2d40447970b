// flexure simulate's outputs: the energy plot, the frame images rendered with one camera and one
// colour scale for the whole run (and their video), and every file of the output directory, the
// files of an earlier run there that this one did not write removed at the commit.
#include "cli/simulation_outputs.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "cli/command_files.h"
#include "cli/mesh_json.h"
#include "cli/simulation_video.h"
#include "modeling/atomic_write.h"
#include "modeling/mesh_io.h"
#include "render/plot.h"

namespace flexure::cli {
namespace {

// Schedules the removal (at the commit) of the frame images in `frameDir` this run did not write.
void removeStaleFrames(const std::filesystem::path& frameDir,
                       const std::vector<std::string>& kept) {
  std::error_code ec;
  if (!std::filesystem::is_directory(frameDir, ec)) return;
  for (const auto& entry : std::filesystem::directory_iterator(frameDir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file(ec) || !isSimulationFile(name) ||
        std::find(kept.begin(), kept.end(), name) != kept.end())
      continue;
    modeling::removeWhenCommitted(entry.path().string());
  }
}

// The energy history as a plot: each energy against time.
render::LinePlot energyPlot(const Recording& recording, const std::string& title) {
  render::LinePlot plot;
  plot.title = title;
  plot.xLabel = "time";
  plot.yLabel = "energy";
  std::vector<std::string> labels = {"kinetic"};
  labels.insert(labels.end(), recording.termNames.begin(), recording.termNames.end());
  labels.push_back("gravity");
  if (recording.contact) labels.push_back("contact");
  if (recording.plastic) labels.push_back("plastic dissipation");
  labels.push_back("total");
  for (size_t c = 0; c < labels.size(); ++c) {
    render::PlotSeries series{labels[c], {}, {}};
    for (const auto& row : recording.history) {
      series.x.push_back(row[0]);
      series.y.push_back(row[c + 1]);
    }
    plot.series.push_back(std::move(series));
  }
  return plot;
}

// The obstacles as the renderer draws them.
void addObstacles(const std::vector<optimize::Obstacle>& obstacles, render::RenderOptions& look) {
  for (const optimize::Obstacle& obstacle : obstacles) {
    if (obstacle.kind == optimize::Obstacle::Kind::Sphere)
      look.spheres.push_back({obstacle.vector, obstacle.scalar});
    else if (obstacle.kind == optimize::Obstacle::Kind::Plane)
      look.planes.push_back({obstacle.vector, obstacle.scalar});
  }
}

// The frames rendered with one camera for the whole run, framed on every frame's drawn vertices
// (rest + exaggerate (x − rest)) and the obstacles, with the frame's time and, for the
// displacement style, one colour scale (the largest displacement of the run), with `cracks` the
// lips each frame's cuts opened drawn over it, in DIR/frames/ (the earlier runs' images there that
// this one did not write go), and the video.
void writeFrameImages(const SimulateOptions& o, render::RenderOptions look,
                      render::OffscreenContext& context, const Recording& recording,
                      const std::vector<optimize::Obstacle>& obstacles,
                      const std::vector<optimize::MeshObstacle>& meshObstacles, bool cracks,
                      const std::filesystem::path& dir) {
  const auto& frames = recording.frames;
  look.exaggeration = o.exaggerate;
  addObstacles(obstacles, look);
  Eigen::Index pointCount = 0, obstaclePoints = 0;
  for (const modeling::Positions& rest : recording.frameRest) pointCount += rest.rows();
  for (const optimize::MeshObstacle& obstacle : meshObstacles)
    obstaclePoints += obstacle.mesh.vertexCount();
  look.framingPoints.resize(pointCount + obstaclePoints * Eigen::Index(frames.size()), 3);
  double largestDisplacement = 0.0;
  Eigen::Index first = 0;
  for (size_t f = 0; f < frames.size(); ++f) {
    const modeling::Positions& x = frames[f].second.positions;
    const modeling::Positions& rest = recording.frameRest[f];
    look.framingPoints.middleRows(first, rest.rows()) = rest + o.exaggerate * (x - rest);
    first += rest.rows();
    for (const optimize::MeshObstacle& obstacle : meshObstacles) {
      look.framingPoints.middleRows(first, obstacle.mesh.vertexCount()) =
          obstacle.positionsAt(recording.frameTimes[f]);
      first += obstacle.mesh.vertexCount();
    }
    largestDisplacement = std::max(largestDisplacement, (x - rest).rowwise().norm().maxCoeff());
  }
  if (look.style == render::RenderStyle::Plastic) {
    double largest = 0.0;
    for (const Eigen::VectorXd& strain : recording.framePlastic)
      largest = std::max(largest, strain.maxCoeff());
    look.plasticMax = std::max(largest, 1e-12);
    look.rangeNote = "largest of the run";
  }
  if (look.style == render::RenderStyle::Displacement) {
    look.displacementMax = std::max(largestDisplacement, 1e-12);
    look.rangeNote = "largest of the run";
  }
  const std::filesystem::path frameDir = dir / "frames";
  modeling::createOutputDirectory(frameDir.string());
  std::vector<std::string> pngs, names;
  for (size_t f = 0; f < frames.size(); ++f) {
    const auto& [name, mesh] = frames[f];
    char caption[80];
    if (o.exaggerate != 1.0)
      std::snprintf(caption, sizeof caption, "t = %.3f s, displacement ×%g",
                    recording.frameTimes[f], o.exaggerate);
    else
      std::snprintf(caption, sizeof caption, "t = %.3f s", recording.frameTimes[f]);
    look.caption = caption;
    look.obstacleMeshes.clear();
    for (const optimize::MeshObstacle& obstacle : meshObstacles)
      look.obstacleMeshes.push_back(
          {obstacle.positionsAt(recording.frameTimes[f]), obstacle.mesh.triangles});
    look.referencePositions = recording.frameRest[f];
    if (cracks) look.crackEdges = render::crackLipEdges(recording.frameRest[f], mesh.triangles);
    if (look.style == render::RenderStyle::Plastic) {
      const Eigen::VectorXd& strain = recording.framePlastic[f];
      look.vertexScalars.assign(strain.data(), strain.data() + strain.size());
    }
    names.push_back(name.substr(0, name.size() - 4) + ".png");
    pngs.push_back(render::encodePng(render::renderMesh(context, mesh, look)));
    modeling::writeFileAtomically((frameDir / names.back()).string(), pngs.back());
  }
  removeStaleFrames(frameDir, names);
  if (!o.video.empty()) writeVideo(o.video, pngs, o.fps);
}

// DIR/cracks.json: {"lips": [frame 0's lips, frame 1's, …]}, each the vertex pairs of the
// frame's mesh that are crack lips (render::crackLipEdges of the frame's rest positions), for
// `flexure view`.
void writeCrackLips(const Recording& recording, const std::string& path) {
  nlohmann::json lips = nlohmann::json::array();
  for (size_t f = 0; f < recording.frames.size(); ++f) {
    nlohmann::json frame = nlohmann::json::array();
    for (const auto& [a, b] :
         render::crackLipEdges(recording.frameRest[f], recording.frames[f].second.triangles))
      frame.push_back({a, b});
    lips.push_back(std::move(frame));
  }
  modeling::writeFileAtomically(path, nlohmann::json{{"lips", lips}}.dump() + "\n");
}

// DIR/plastic.json: {"measure": its name, "frames": [frame 0's values, …], "faces": [frame 0's
// values, …]}, the plastic measure at each frame of every vertex (PlasticDynamics::
// vertexPlasticMeasure, what the plastic render style colours) and of every face
// (facePlasticMeasure, what `flexure view --style plastic` colours).
void writePlasticMeasure(const SimulateOptions& o, const Recording& recording,
                         const std::string& path) {
  const auto lists = [](const std::vector<Eigen::VectorXd>& frames) {
    nlohmann::json out = nlohmann::json::array();
    for (const Eigen::VectorXd& values : frames)
      out.push_back(std::vector<double>(values.begin(), values.end()));
    return out;
  };
  modeling::writeFileAtomically(
      path, nlohmann::json{{"measure", plasticityOptions(o.plasticity).measureName()},
                           {"frames", lists(recording.framePlastic)},
                           {"faces", lists(recording.frameFacePlastic)}}
                    .dump() +
                "\n");
}

}  // namespace

bool isSimulationFile(const std::string& name) {
  if (name == "energies.csv" || name == "energies.png" || name == "report.json" ||
      name == "cracks.json" || name == "plastic.json")
    return true;
  const bool obj = name.size() > 4 && name.compare(name.size() - 4, 4, ".obj") == 0;
  const bool png = name.size() > 4 && name.compare(name.size() - 4, 4, ".png") == 0;
  return (name.rfind("frame-", 0) == 0 && (obj || png)) ||
         ((name.rfind("fragment-", 0) == 0 || name.rfind("obstacle-", 0) == 0) && obj);
}

void writeOutputs(const SimulateOptions& o, const std::optional<render::RenderOptions>& look,
                  render::OffscreenContext* context, const Recording& recording,
                  const std::string& title, const nlohmann::json& report,
                  const optimize::FracturingDynamics& dynamics, const std::filesystem::path& dir) {
  const render::LinePlot plot = energyPlot(recording, title);
  modeling::createOutputDirectory(dir.string());
  std::vector<std::string> written = {"energies.csv", "energies.png", "report.json"};
  for (const auto& [name, mesh] : recording.frames) {
    modeling::writeMesh((dir / name).string(), mesh);
    written.push_back(name);
  }
  if (!recording.framePlastic.empty()) {
    writePlasticMeasure(o, recording, (dir / "plastic.json").string());
    written.push_back("plastic.json");
  }
  if (dynamics.fractures()) {
    writeCrackLips(recording, (dir / "cracks.json").string());
    written.push_back("cracks.json");
    const std::vector<modeling::Mesh> fragments = dynamics.fragments();
    for (size_t k = 0; k < fragments.size(); ++k) {
      const std::string name = "fragment-" + std::to_string(k) + ".obj";
      modeling::writeMesh((dir / name).string(), fragments[k]);
      written.push_back(name);
    }
  }
  const std::vector<optimize::MeshObstacle>& meshObstacles =
      dynamics.problem().selfContact.meshObstacles();
  for (size_t k = 0; k < meshObstacles.size(); ++k) {  // each at rest (time 0)
    const std::string name = "obstacle-" + std::to_string(k) + ".obj";
    modeling::writeMesh((dir / name).string(), meshObstacles[k].mesh);
    written.push_back(name);
  }
  removeStaleFrames(dir, written);
  if (look)
    writeFrameImages(o, *look, *context, recording, dynamics.problem().obstacles.obstacles(),
                     meshObstacles, dynamics.fractures(), dir);
  else
    removeStaleFrames(dir / "frames", {});
  modeling::writeFileAtomically((dir / "energies.csv").string(), recording.csv.str());
  render::writeLinePlot(plot, (dir / "energies.png").string());
  writeJsonFile((dir / "report.json").string(), report);
}

}  // namespace flexure::cli
