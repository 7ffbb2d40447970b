// formatMesh: OBJ, OFF and ASCII PLY text. Every coordinate is the shortest decimal that reads
// back to the same double, and nothing depends on time or locale, so output is reproducible.
#include <charconv>
#include <string>

#include "modeling/errors.h"
#include "modeling/mesh_io.h"

namespace flexure::modeling {
namespace {

void appendNumber(std::string& out, double value) {
  char buffer[32];  // the shortest round-trip form of a double has at most 24 characters
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void appendNumber(std::string& out, int value) {
  char buffer[16];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

// "x y z\n" per vertex, after `prefix`.
void appendVertices(std::string& out, const Mesh& mesh, const char* prefix) {
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    out += prefix;
    for (int k = 0; k < 3; ++k) {
      if (k > 0) out += ' ';
      appendNumber(out, mesh.positions(v, k));
    }
    out += '\n';
  }
}

// "a b c\n" per triangle, after `prefix`, indices offset by `base`.
void appendTriangles(std::string& out, const Mesh& mesh, const char* prefix, int base) {
  for (int f = 0; f < mesh.faceCount(); ++f) {
    out += prefix;
    for (int k = 0; k < 3; ++k) {
      if (k > 0) out += ' ';
      appendNumber(out, mesh.triangles(f, k) + base);
    }
    out += '\n';
  }
}

std::string formatObj(const Mesh& mesh) {
  std::string out;
  appendVertices(out, mesh, "v ");
  appendTriangles(out, mesh, "f ", 1);  // OBJ indices are 1-based
  return out;
}

std::string formatOff(const Mesh& mesh) {
  std::string out = "OFF\n";
  appendNumber(out, mesh.vertexCount());
  out += ' ';
  appendNumber(out, mesh.faceCount());
  out += " 0\n";  // the edge count, which OFF readers ignore
  appendVertices(out, mesh, "");
  appendTriangles(out, mesh, "3 ", 0);
  return out;
}

std::string formatPly(const Mesh& mesh) {
  std::string out = "ply\nformat ascii 1.0\nelement vertex ";
  appendNumber(out, mesh.vertexCount());
  out += "\nproperty double x\nproperty double y\nproperty double z\nelement face ";
  appendNumber(out, mesh.faceCount());
  out += "\nproperty list uchar int vertex_indices\nend_header\n";
  appendVertices(out, mesh, "");
  appendTriangles(out, mesh, "3 ", 0);
  return out;
}

}  // namespace

std::string formatMesh(const Mesh& mesh, MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj:
      return formatObj(mesh);
    case MeshFormat::Off:
      return formatOff(mesh);
    case MeshFormat::Ply:
      return formatPly(mesh);
    case MeshFormat::Stl:
      break;
  }
  throw InputError("STL output is not supported: write .obj, .off or .ply");
}

}  // namespace flexure::modeling
