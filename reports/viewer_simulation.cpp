#include "reports/viewer_simulation.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "optimize/assembly/obstacles.h"

namespace flexure::reports {
namespace {

namespace fs = std::filesystem;

// The frame-NNNNN.obj files of a simulation folder, in order.
std::vector<fs::path> simulationFrames(const fs::path& dir) {
  std::vector<fs::path> frames;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("frame-", 0) == 0 && entry.path().extension() == ".obj")
      frames.push_back(entry.path());
  }
  std::sort(frames.begin(), frames.end());
  if (frames.empty())
    throw InputError(dir.string() +
                     ": a folder given to view must hold a simulation's frame-NNNNN.obj files; "
                     "it holds none");
  return frames;
}

// DIR/report.json parsed, or null when it is missing or not JSON.
nlohmann::json simulationReport(const fs::path& dir) {
  std::ifstream file(dir / "report.json");
  if (!file) return nullptr;
  nlohmann::json report = nlohmann::json::parse(file, nullptr, false);
  return report.is_discarded() || !report.is_object() ? nlohmann::json(nullptr) : report;
}

// The frame times of the report ("frame_times"), or none when it has not one for every frame.
std::vector<double> frameTimes(const nlohmann::json& report, std::size_t count) {
  if (report.is_null() || !report.contains("frame_times")) return {};
  std::vector<double> times;
  for (const auto& t : report["frame_times"])
    if (t.is_number()) times.push_back(t.get<double>());
  return times.size() == count ? times : std::vector<double>{};
}

// The lips of DIR/cracks.json, one list per frame of `m`, as segments along the lip edges.
void addCrackLips(render::ViewerMesh& m, const fs::path& dir) {
  const fs::path path = dir / "cracks.json";
  std::ifstream file(path);
  if (!file) return;
  const nlohmann::json cracks = nlohmann::json::parse(file, nullptr, false);
  const auto bad = [&](const std::string& what) {
    return InputError(path.string() + ": " + what + " (flexure simulate writes it)");
  };
  if (cracks.is_discarded() || !cracks.contains("lips") || !cracks["lips"].is_array())
    throw bad("no \"lips\" list");
  if (cracks["lips"].size() != m.frames.size())
    throw bad(std::to_string(cracks["lips"].size()) + " frames of lips for " +
              std::to_string(m.frames.size()) + " frames");
  for (std::size_t f = 0; f < m.frames.size(); ++f) {
    render::ViewerSegments lips;
    for (const nlohmann::json& edge : cracks["lips"][f]) {
      if (!edge.is_array() || edge.size() != 2 || !edge[0].is_number_integer() ||
          !edge[1].is_number_integer())
        throw bad("frame " + std::to_string(f) + ": a lip " + edge.dump() + " is no vertex pair");
      const int a = edge[0].get<int>(), b = edge[1].get<int>();
      if (a < 0 || b < 0 || a >= m.frames[f].rows() || b >= m.frames[f].rows())
        throw bad("frame " + std::to_string(f) + ": a lip " + edge.dump() + " names no vertex");
      lips.push_back({{a, a, 0.0}, {b, b, 0.0}});
    }
    m.frameCracks.push_back(std::move(lips));
  }
}

// The spheres and planes of DIR/report.json's "obstacles" added to `mesh`.
void addSimulationObstacles(render::ViewerMesh& mesh, const std::string& dir) {
  const std::string path = (fs::path(dir) / "report.json").string();
  const nlohmann::json report = simulationReport(dir);
  if (report.is_null() || !report.contains("obstacles") || !report["obstacles"].is_array()) return;
  for (const nlohmann::json& entry : report["obstacles"]) {
    if (!entry.is_string())
      throw InputError(path + ": an obstacle " + entry.dump() + " is no text");
    const optimize::Obstacle o = optimize::parseObstacle(path, entry.get<std::string>());
    if (o.kind == optimize::Obstacle::Kind::Sphere)
      mesh.spheres.push_back({o.vector, o.scalar});
    else
      mesh.planes.push_back({o.vector, o.scalar});
  }
}

}  // namespace

bool isSimulationFolder(const std::string& dir) {
  return fs::is_directory(dir);
}

render::ViewerMesh readSimulationFolder(const std::string& dir) {
  render::ViewerMesh m;
  m.name = fs::path(dir).filename().string();
  if (m.name.empty()) m.name = fs::path(dir).parent_path().filename().string();
  const std::vector<fs::path> frames = simulationFrames(dir);
  for (const fs::path& path : frames) {
    modeling::Mesh mesh = modeling::readMesh(path.string());
    const modeling::Triangles& last =
        m.frames.empty() ? mesh.triangles : m.trianglesAt(m.frames.size() - 1);
    if (m.frames.empty()) {
      m.triangles = mesh.triangles;
    } else if (mesh.triangles != last) {
      m.faceChanges.push_back({m.frames.size(), mesh.triangles});
    } else if (mesh.vertexCount() != m.frames.back().rows()) {
      throw InputError(path.string() + ": " + std::to_string(mesh.vertexCount()) +
                       " vertices with the faces of the frame before, which has " +
                       std::to_string(m.frames.back().rows()));
    }
    m.frames.push_back(std::move(mesh.positions));
  }
  if (!m.faceChanges.empty() && !fs::exists(fs::path(dir) / "cracks.json"))
    throw InputError(frames[m.faceChanges.front().frame].string() +
                     ": other faces than the frame before, and " + dir +
                     " has no cracks.json (only a run that fractured changes its faces)");
  m.frameTimes = frameTimes(simulationReport(dir), m.frames.size());
  addCrackLips(m, dir);
  addSimulationObstacles(m, dir);
  return m;
}

void addPlasticFields(render::ViewerPageSpec& page, const std::vector<std::string>& folders,
                      std::size_t first) {
  page.style = render::ViewerStyle::Field;
  page.diverging = false;
  page.fieldOnFaces = true;
  for (std::size_t k = 0; k < folders.size(); ++k) {
    if (!isSimulationFolder(folders[k]))
      throw InputError(folders[k] +
                       ": the plastic style colours a simulation folder's plastic strain, and "
                       "this is no folder");
    const fs::path path = fs::path(folders[k]) / "plastic.json";
    std::ifstream file(path);
    if (!file)
      throw InputError(folders[k] +
                       ": no plastic.json (a simulation with a yield value writes it)");
    const nlohmann::json plastic = nlohmann::json::parse(file, nullptr, false);
    render::ViewerMesh& m = page.meshes.at(first + k);
    if (plastic.is_discarded() || !plastic.contains("faces") || !plastic["faces"].is_array() ||
        !plastic.contains("measure") || !plastic["measure"].is_string() ||
        plastic["faces"].size() != m.frames.size())
      throw InputError(path.string() +
                       ": not a measure name and one list of face values per "
                       "frame (\"faces\", " +
                       std::to_string(m.frames.size()) + " frames)");
    const std::string measure = plastic["measure"].get<std::string>();
    if (k > 0 && measure != page.fieldTitle)
      throw InputError(path.string() + ": measures " + measure + ", another folder " +
                       page.fieldTitle);
    page.fieldTitle = measure;
    m.fields.clear();
    for (std::size_t f = 0; f < m.frames.size(); ++f) {
      const nlohmann::json& values = plastic["faces"][f];
      const Eigen::Index faces = m.trianglesAt(f).rows();
      if (!values.is_array() || values.size() != static_cast<std::size_t>(faces))
        throw InputError(path.string() + ": frame " + std::to_string(f) +
                         " has not one value per face");
      Eigen::VectorXd field(faces);
      for (Eigen::Index j = 0; j < faces; ++j) {
        if (!values[j].is_number())
          throw InputError(path.string() + ": frame " + std::to_string(f) + ": a value " +
                           values[j].dump() + " is no number");
        field[j] = values[j].get<double>();
      }
      m.fields.push_back(std::move(field));
    }
  }
}

}  // namespace flexure::reports
