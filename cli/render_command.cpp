// flexure render: an offscreen image of a mesh (reflection lines, isophotes, highlight lines,
// shading, the error against a polynomial surface, a mean-curvature map, or the displacement from a
// reference mesh, optionally exaggerated), written as PNG. The
// curvature map's values come from curvature/ here, so that render/ does not depend on it.
#include <cctype>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/curvature_arguments.h"
#include "curvature/energy_registry.h"
#include "modeling/errors.h"
#include "modeling/mesh_check.h"
#include "modeling/mesh_io.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace flexure::cli {
namespace {

struct RenderCommandOptions {
  std::string input;
  std::string output;
  std::string style = "reflection";
  std::string background = "#ffffff";
  std::string surface;
  std::vector<double> light;
  bool perspective = false;
  bool flat = false;
  std::optional<double> errorMax;
  std::string curvatureEnergy;
  std::optional<double> curvatureMax;
  std::string reference;
  std::optional<double> exaggerate;
  render::RenderOptions render;
};

bool endsWithPng(const std::string& path) {
  if (path.size() < 4) return false;
  std::string extension = path.substr(path.size() - 4);
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".png";
}

// The indices an element of a mesh problem names (mesh_check.cpp's words): "face F (vertices …)"
// and "faces F and G" name faces, "vertex V" a vertex, "edge (A, B)" its two end vertices.
void namedElements(const std::string& element, std::vector<int>& faces,
                   std::vector<int>& vertices) {
  std::vector<int> numbers;
  for (const char* c = element.c_str(); *c != '\0';) {
    if (std::isdigit(static_cast<unsigned char>(*c))) {
      char* end = nullptr;
      numbers.push_back(static_cast<int>(std::strtol(c, &end, 10)));
      c = end;
    } else {
      ++c;
    }
  }
  if (element.rfind("faces ", 0) == 0) {
    faces.insert(faces.end(), numbers.begin(), numbers.end());
  } else if (element.rfind("face ", 0) == 0 && !numbers.empty()) {
    faces.push_back(numbers.front());
    if (numbers.size() > 1) vertices.insert(vertices.end(), numbers.begin() + 1, numbers.end());
  } else if (element.rfind("vertex ", 0) == 0 || element.rfind("edge ", 0) == 0) {
    vertices.insert(vertices.end(), numbers.begin(), numbers.end());
  }
}

// A mesh that `info` refuses but that can be drawn: its problems' faces, and every face at a vertex
// they name (a zero-area face covers no pixel; its neighbours show where it is), are marked.
// Problems that leave nothing to draw (no faces, coordinates that are not finite or overflow)
// are not drawable: nullopt.
std::optional<std::vector<int>> markedFaces(const modeling::Mesh& mesh,
                                            const modeling::MeshCheck& check) {
  using Kind = modeling::MeshProblemKind;
  for (Kind fatal :
       {Kind::Empty, Kind::VertexIndexOutOfRange, Kind::NonFiniteCoordinate, Kind::AreaOverflow})
    if (check.problemCounts[static_cast<int>(fatal)] > 0) return std::nullopt;
  std::vector<int> faces, vertices;
  for (const modeling::MeshProblem& p : check.problems) namedElements(p.element, faces, vertices);
  std::vector<char> atVertex(mesh.vertexCount(), 0), marked(mesh.faceCount(), 0);
  for (int v : vertices)
    if (v >= 0 && v < mesh.vertexCount()) atVertex[v] = 1;
  for (int f : faces)
    if (f >= 0 && f < mesh.faceCount()) marked[f] = 1;
  for (int f = 0; f < mesh.faceCount(); ++f)
    for (int k = 0; k < 3; ++k)
      if (atVertex[mesh.triangles(f, k)]) marked[f] = 1;
  std::vector<int> result;
  for (int f = 0; f < mesh.faceCount(); ++f)
    if (marked[f]) result.push_back(f);
  return result;
}

// "3 non_manifold_vertex, 1 zero_area_face": each kind found and how often.
std::string problemSummary(const modeling::MeshCheck& check) {
  std::string text;
  for (size_t k = 0; k < check.problemCounts.size(); ++k) {
    if (check.problemCounts[k] == 0) continue;
    if (!text.empty()) text += ", ";
    text += std::to_string(check.problemCounts[k]) + " " +
            std::string(modeling::meshProblemName(static_cast<modeling::MeshProblemKind>(k)));
  }
  return text;
}

// The mesh to draw: a valid one as every command reads it; one that only the mesh checks refuse,
// as read, with its problems' faces in r.markedFaces, a caption saying what is marked and a
// warning on stderr (always: the picture is not of a usable mesh). Anything else rethrows.
modeling::Mesh readDrawableMesh(const std::string& path, render::RenderOptions& r,
                                std::vector<std::string>& notices) {
  try {
    return modeling::readMesh(path, &notices);
  } catch (const InputError& refused) {
    const modeling::Mesh mesh = modeling::triangulatePolygons(modeling::readPolygonSoup(path));
    const modeling::MeshCheck check = modeling::checkMesh(mesh, INT_MAX);
    const std::optional<std::vector<int>> marked = markedFaces(mesh, check);
    if (check.valid() || !marked) throw;
    r.markedFaces = *marked;
    const std::string summary = problemSummary(check);
    r.caption = "invalid: " + summary + " (red: " + std::to_string(marked->size()) + " faces)";
    std::cerr << "flexure render: warning: " << path << " is not a valid mesh (" << summary
              << "); drawn with the " << marked->size() << " faces at its problems in red:\n"
              << refused.what() << '\n';
    return mesh;
  }
}

void runRenderCommand(RenderCommandOptions o, const GlobalOptions& global) {
  // Every option is checked before the mesh is read or OSMesa loaded.
  if (!endsWithPng(o.output)) {
    throw InputError("--output '" + o.output + "': flexure render writes PNG images (.png)");
  }
  render::RenderOptions& r = o.render;
  r.style = render::parseRenderStyle(o.style);
  r.background = render::parseBackground(o.background);
  r.projection = o.perspective ? render::Projection::Perspective : render::Projection::Orthographic;
  r.smoothNormals = !o.flat;
  if (!o.light.empty()) r.lightDirection = {o.light[0], o.light[1], o.light[2]};
  render::StyleOptions styleOptions;
  if (!o.surface.empty()) styleOptions.surface = o.surface;
  styleOptions.errorMax = o.errorMax;
  styleOptions.curvatureMax = o.curvatureMax;
  styleOptions.applyTo(r);
  const bool curvatureStyle = r.style == render::RenderStyle::Curvature;
  if (curvatureStyle) {
    curvatureEnergy(o.curvatureEnergy);  // refuses a name before any work
    r.scalarLabel = "mean curvature H";
  } else if (!o.curvatureEnergy.empty()) {
    throw InputError("--curvature-energy applies to --style curvature only");
  }

  if (r.style == render::RenderStyle::Displacement && o.reference.empty())
    throw InputError("--style displacement needs --reference REST (a mesh with the same vertices)");
  if (o.exaggerate && o.reference.empty())
    throw InputError("--exaggerate scales the displacement from --reference: give it");
  if (o.exaggerate) r.exaggeration = *o.exaggerate;

  std::vector<std::string> notices;
  const modeling::Mesh mesh = readDrawableMesh(o.input, r, notices);
  if (!o.reference.empty()) {
    const modeling::Mesh reference = modeling::readMesh(o.reference, &notices);
    if (reference.vertexCount() != mesh.vertexCount() ||
        reference.faceCount() != mesh.faceCount() || reference.triangles != mesh.triangles) {
      throw InputError(
          "--reference " + o.reference + ": " + std::to_string(reference.vertexCount()) +
          " vertices and " + std::to_string(reference.faceCount()) + " faces, but " + o.input +
          " has " + std::to_string(mesh.vertexCount()) + " and " +
          std::to_string(mesh.faceCount()) + ", or other faces (the same connectivity is needed)");
    }
    r.referencePositions = reference.positions;
  }
  if (!global.quiet)
    for (const std::string& notice : notices) std::cerr << "flexure render: " << notice << '\n';
  const auto start = std::chrono::steady_clock::now();
  if (curvatureStyle) r.vertexScalars = curvatureEnergy(o.curvatureEnergy).meanCurvatureField(mesh);
  const render::Image image = render::renderMesh(mesh, r);
  render::writePng(o.output, image);
  if (!global.quiet) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cerr << "flexure render: wrote " << o.output << " (" << image.width << " x "
              << image.height << ", " << render::renderStyleName(r.style) << ", "
              << mesh.faceCount() << " faces, " << seconds << " s)\n";
  }
}

}  // namespace

void registerRenderCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<RenderCommandOptions>();
  RenderCommandOptions& o = *options;
  CLI::App* sub = app.add_subcommand(
      "render", "Render a mesh offscreen (OSMesa) to PNG: reflection lines, isophotes, ...");
  auto files = CommandFiles::of(*sub);
  files->input("input", o.input, "Mesh file (.obj, .off, .ply, .stl)")->required();
  files->output("-o,--output", o.output, "Output image (.png)")->required();
  sub->add_option("--style", o.style,
                  "reflection | isophote | highlight | shaded | error | curvature | displacement "
                  "(default reflection)");
  sub->add_option("--width", o.render.width, "Image width in pixels (default 1024)")
      ->check(inRange(16, 8192));
  sub->add_option("--height", o.render.height, "Image height in pixels (default 1024)")
      ->check(inRange(16, 8192));
  sub->add_option("--azimuth", o.render.azimuthDegrees,
                  "Camera azimuth in degrees about +z; 0 = seen from the -y side (default 0)");
  sub->add_option("--elevation", o.render.elevationDegrees,
                  "Camera elevation in degrees above the xy plane; 90 = from above (default 90)");
  sub->add_flag("--perspective", o.perspective, "Perspective projection (default orthographic)");
  sub->add_option("--background", o.background, "Background colour #rrggbb (default #ffffff)");
  sub->add_flag("--flat", o.flat, "Flat (face) normals instead of area-weighted vertex normals");
  sub->add_flag("--edges", o.render.edges, "Draw the triangle edges");
  sub->add_option("--stripes", o.render.stripeCount,
                  "Number of stripes / bands / highlight lines (default 12)")
      ->check(inRange(1, 1000));
  sub->add_option("--stripe-width", o.render.stripeWidth,
                  "Dark fraction of each stripe period, in (0, 1) (default 0.5)");
  sub->add_option("--stripe-direction", o.render.stripeDirectionDegrees,
                  "Stripe angle in the image, degrees from the x axis (default 90: vertical)");
  sub->add_option("--light", o.light, "Direction toward the light in camera coordinates X,Y,Z")
      ->expected(3)
      ->delimiter(',');
  sub->add_option("--surface", o.surface,
                  "Error style: the surface p, quadratic:a,b,c or polynomial:EXPR");
  sub->add_option("--error-max", o.errorMax,
                  "Error style: top of the colour map (default: the largest |z - p|)");
  sub->add_option("--curvature-energy", o.curvatureEnergy, curvatureEnergyHelp());
  sub->add_option("--curvature-max", o.curvatureMax,
                  "Curvature style: the colour map spans [-M, M] (default: the 98th percentile of "
                  "|H| over the vertices)");
  files->input("--reference", o.reference,
               "A mesh with the same vertices and faces (e.g. the rest state): displacement "
               "style colours |x - x_ref|; with --exaggerate the shape is drawn about it");
  sub->add_option("--exaggerate", o.exaggerate,
                  "Draw x_ref + K (x - x_ref): small displacements made visible (needs "
                  "--reference; colours keep the true distances)")
      ->check(positive());
  sub->footer(
      "Example: flexure render bowl.obj -o bowl.png --style reflection --elevation 60\n"
      "The renderer loads libOSMesa.so.8 (Debian: libosmesa6) at run time, or the library named "
      "by $FLEXURE_OSMESA_LIBRARY.");
  files->onRun(global, [options, &global] { runRenderCommand(*options, global); });
}

}  // namespace flexure::cli
