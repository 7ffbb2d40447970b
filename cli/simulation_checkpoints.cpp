// flexure simulate's checkpoints as JSON: the state (positions, velocities, accelerations, the
// midedge unknowns, contact stiffnesses, the energy balance), the counts and the recording, with
// the options and an FNV-1a checksum of the rest mesh, so that a run resumes on the same only.
#include "cli/simulation_checkpoints.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"

namespace flexure::cli {
namespace {

nlohmann::json matrixJson(const Eigen::MatrixXd& m) {
  return std::vector<double>(m.data(), m.data() + m.size());
}

Eigen::MatrixXd matrixFrom(const nlohmann::json& j, Eigen::Index rows, Eigen::Index cols) {
  const std::vector<double> values = j.get<std::vector<double>>();
  if (static_cast<Eigen::Index>(values.size()) != rows * cols)
    throw InputError("expected " + std::to_string(rows * cols) + " numbers");
  return Eigen::Map<const Eigen::MatrixXd>(values.data(), rows, cols);
}

// The inset pairs as [kind (0: vertex–face, 1: edge–edge), first, second, ℓ] rows.
nlohmann::json insetsJson(const std::vector<optimize::InsetPair>& insets) {
  nlohmann::json rows = nlohmann::json::array();
  for (const optimize::InsetPair& p : insets)
    rows.push_back({p.pair.kind == optimize::ContactPair::Kind::EdgeEdge ? 1 : 0, p.pair.first,
                    p.pair.second, p.layer});
  return rows;
}

std::vector<optimize::InsetPair> insetsFrom(const nlohmann::json& rows) {
  std::vector<optimize::InsetPair> insets;
  for (const nlohmann::json& row : rows) {
    if (!row.is_array() || row.size() != 4 || (row.at(0) != 0 && row.at(0) != 1))
      throw InputError("an inset pair that is not [0 or 1, first, second, layer]");
    optimize::InsetPair p;
    p.pair.kind = row.at(0).get<int>() == 1 ? optimize::ContactPair::Kind::EdgeEdge
                                            : optimize::ContactPair::Kind::VertexFace;
    p.pair.first = row.at(1).get<int>();
    p.pair.second = row.at(2).get<int>();
    p.layer = row.at(3).get<double>();
    insets.push_back(p);
  }
  return insets;
}

}  // namespace

std::string meshChecksum(const modeling::Mesh& mesh) {
  std::uint64_t hash = 14695981039346656037ull;
  for (const unsigned char c : modeling::formatMesh(mesh, modeling::MeshFormat::Obj))
    hash = (hash ^ c) * 1099511628211ull;
  char text[20];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

void writeCheckpoint(const SimulateOptions& o, optimize::TimeStepper& stepper,
                     const Recording& recording, const Run& run, long k,
                     const std::string& checksum) {
  stepper.forgetFactor();
  const optimize::TimeStepper::State st = stepper.state();
  const optimize::EnergyBalance& b = st.balance;
  nlohmann::json frames = nlohmann::json::array();
  for (const auto& frame : recording.frames) frames.push_back(matrixJson(frame.second.positions));
  const nlohmann::json checkpoint = {
      {"flexure_checkpoint", 1},
      {"options", o.fingerprint},
      {"mesh", checksum},
      {"step", k},
      {"time", st.time},
      {"x", matrixJson(st.x)},
      {"v", matrixJson(st.v)},
      {"a", matrixJson(st.a)},
      {"xi", matrixJson(st.xi)},
      {"contact_stiffness", matrixJson(st.contactStiffness)},
      {"contact_couplings", st.contactCouplings},
      {"mesh_obstacle_stiffness", st.obstacleStiffness},
      {"contact_insets", insetsJson(*st.contactInsets)},
      {"self_contact_stiffness", matrixJson(st.selfContactStiffness)},
      {"balance",
       {b.initial, b.dissipated, b.stiffening, b.peakKinetic, b.peakElastic, b.last, b.largestDrift,
        b.driftTime, static_cast<double>(b.driftStep), static_cast<double>(b.steps)}},
      {"run",
       {run.steps, run.newtonIterations, run.maxNewtonIterations, run.halvings, run.smallestStep}},
      {"csv", recording.csv.str()},
      {"history", recording.history},
      {"frames", frames},
      {"frame_times", recording.frameTimes},
      {"smallest_distance", std::isfinite(recording.smallestDistance)
                                ? nlohmann::json(recording.smallestDistance)
                                : nlohmann::json(nullptr)}};
  std::filesystem::create_directories(o.outputDir);
  modeling::writeFileNow((std::filesystem::path(o.outputDir) / "checkpoint.json").string(),
                         checkpoint.dump());
}

long resumeCheckpoint(const SimulateOptions& o, const std::string& checksum,
                      optimize::TimeStepper& stepper, Recording& recording, Run& run,
                      const modeling::Mesh& restMesh) {
  const std::string path = (std::filesystem::path(o.resumeDir) / "checkpoint.json").string();
  const std::string where = "--resume " + o.resumeDir + ": " + path;
  std::ifstream in(path);
  if (!in) throw InputError(where + ": no checkpoint (write one with --checkpoint N)");
  try {
    const nlohmann::json c = nlohmann::json::parse(in);
    if (c.at("flexure_checkpoint") != 1) throw InputError("not a checkpoint of this version");
    if (c.at("mesh") != checksum)
      throw InputError("was made with another rest mesh than " + o.restFile);
    if (c.at("options") != o.fingerprint)
      throw InputError("was made with other options: " + c.at("options").get<std::string>());
    const Eigen::Index n = restMesh.vertexCount();
    optimize::TimeStepper::State st;
    st.time = c.at("time");
    st.x = matrixFrom(c.at("x"), n, 3);
    st.v = matrixFrom(c.at("v"), n, 3);
    st.a = matrixFrom(c.at("a"), n, 3);
    st.xi = matrixFrom(c.at("xi"), c.at("xi").size(), 1);
    st.contactStiffness =
        matrixFrom(c.at("contact_stiffness"), c.at("contact_stiffness").size(), 1);
    st.contactCouplings = c.at("contact_couplings").get<std::vector<std::array<int, 2>>>();
    st.obstacleStiffness = c.value("mesh_obstacle_stiffness", 0.0);
    if (c.contains("contact_insets")) st.contactInsets = insetsFrom(c.at("contact_insets"));
    if (c.contains("self_contact_stiffness"))
      st.selfContactStiffness =
          matrixFrom(c.at("self_contact_stiffness"), c.at("self_contact_stiffness").size(), 1);
    for (const std::array<int, 2>& pair : st.contactCouplings)
      if (pair[0] < 0 || pair[0] >= pair[1] || pair[1] >= n)
        throw InputError("a contact coupling (" + std::to_string(pair[0]) + ", " +
                         std::to_string(pair[1]) + ") that is not two vertices i < j");
    const std::vector<double> b = c.at("balance").get<std::vector<double>>();
    if (b.size() != 10) throw InputError("expected 10 balance numbers");
    st.balance = {
        b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7], std::lround(b[8]), std::lround(b[9])};
    stepper.restore(st);
    const nlohmann::json& r = c.at("run");
    run.steps = r.at(0);
    run.newtonIterations = r.at(1);
    run.maxNewtonIterations = r.at(2);
    run.halvings = r.at(3);
    run.smallestStep = r.at(4);
    recording.csv.str(c.at("csv").get<std::string>());
    recording.csv.seekp(0, std::ios::end);
    recording.history = c.at("history").get<std::vector<std::vector<double>>>();
    recording.frames.clear();
    recording.frameRest.clear();
    for (const auto& frame : c.at("frames")) {
      char name[32];
      std::snprintf(name, sizeof name, "frame-%05zu.obj", recording.frames.size());
      modeling::Mesh m = restMesh;
      m.positions = matrixFrom(frame, n, 3);
      recording.frames.emplace_back(name, std::move(m));
      recording.frameRest.push_back(restMesh.positions);
    }
    recording.frameTimes = c.at("frame_times").get<std::vector<double>>();
    if (!c.at("smallest_distance").is_null())
      recording.smallestDistance = c.at("smallest_distance");
    return c.at("step");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": not a readable checkpoint: " + e.what());
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
}

}  // namespace flexure::cli
