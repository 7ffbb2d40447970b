// Format dispatch, triangulation and the checked readMesh / writeMesh entry points. The parsers
// are in mesh_readers.cpp, the formatters in mesh_writers.cpp.
#include "modeling/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/mesh_check.h"

namespace flexure::modeling {
namespace {

constexpr const char* kKnownExtensions = ".obj .off .ply .stl";
constexpr const char* kWritableExtensions = ".obj .off .ply";

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// "FILE: 6 quadrilateral faces split into triangles" or, when larger polygons were split too,
// "FILE: 7 polygons with more than 3 vertices split into triangles".
std::string splitNotice(const std::string& path, const PolygonSoup& soup, int split) {
  const bool allQuads = std::all_of(soup.polygons.begin(), soup.polygons.end(),
                                    [](const std::vector<int>& p) { return p.size() <= 4; });
  const std::string what = allQuads ? (split == 1 ? " quadrilateral face" : " quadrilateral faces")
                                    : (split == 1 ? " polygon" : " polygons");
  const std::string detail = allQuads ? "" : " with more than 3 vertices";
  return path + ": " + std::to_string(split) + what + detail + " split into triangles";
}

}  // namespace

MeshFormat meshFormatOf(const std::string& path) {
  const std::string extension = lowercase(std::filesystem::path(path).extension().string());
  if (extension == ".obj") return MeshFormat::Obj;
  if (extension == ".off") return MeshFormat::Off;
  if (extension == ".ply") return MeshFormat::Ply;
  if (extension == ".stl") return MeshFormat::Stl;
  const std::string found =
      extension.empty() ? "no file extension" : "unknown extension '" + extension + "'";
  throw InputError(path + ": " + found + " (known mesh formats: " + kKnownExtensions + ")");
}

Mesh triangulatePolygons(const PolygonSoup& soup, int* splitPolygons) {
  Eigen::Index triangleCount = 0;
  int split = 0;
  for (const std::vector<int>& polygon : soup.polygons) {
    triangleCount += static_cast<Eigen::Index>(polygon.size()) - 2;
    if (polygon.size() > 3) ++split;
  }
  Mesh mesh;
  mesh.positions = soup.positions;
  mesh.triangles.resize(triangleCount, 3);
  Eigen::Index t = 0;
  for (const std::vector<int>& polygon : soup.polygons) {
    for (size_t k = 1; k + 1 < polygon.size(); ++k, ++t) {
      mesh.triangles.row(t) << polygon[0], polygon[k], polygon[k + 1];
    }
  }
  if (splitPolygons != nullptr) *splitPolygons = split;
  return mesh;
}

Mesh readMesh(const std::string& path, std::vector<std::string>* notices) {
  const PolygonSoup soup = readPolygonSoup(path);
  int split = 0;
  Mesh mesh = triangulatePolygons(soup, &split);
  requireValidMesh(mesh, path);
  if (split > 0 && notices != nullptr) notices->push_back(splitNotice(path, soup, split));
  return mesh;
}

MeshFormat writableMeshFormatOf(const std::string& path) {
  const std::string extension = lowercase(std::filesystem::path(path).extension().string());
  if (extension == ".stl")
    throw InputError(path + ": STL output is not supported (flexure writes " + kWritableExtensions +
                     ")");
  if (extension == ".obj" || extension == ".off" || extension == ".ply") return meshFormatOf(path);
  const std::string found =
      extension.empty() ? "no file extension" : "unknown extension '" + extension + "'";
  throw InputError(path + ": " + found + " (flexure writes " + kWritableExtensions + ")");
}

void writeMesh(const std::string& path, const Mesh& mesh) {
  writeFileAtomically(path, formatMesh(mesh, writableMeshFormatOf(path)));
}

}  // namespace flexure::modeling
