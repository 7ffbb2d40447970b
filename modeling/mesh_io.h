// Reading and writing meshes: OBJ, OFF, PLY (ASCII and binary) and STL (ASCII and binary) in;
// OBJ, OFF and PLY (ASCII) out.
//
// flexure parses the formats itself instead of through OpenMesh's readers: those pass every
// coordinate through float (0.1234567890123456789 reads back as 0.12345679104328156) and silently
// split non-manifold input, which hides exactly the problems flexure must report. Coordinates are
// written as the shortest decimal that reads back to the same double (at most 17 significant
// digits), so write → read round trips are exact and the same mesh gives byte-identical files.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

enum class MeshFormat { Obj, Off, Ply, Stl };

// The format named by the file's extension (case-insensitive). Throws InputError for an unknown
// extension, listing the known ones.
MeshFormat meshFormatOf(const std::string& path);
// The format of a mesh file to write: meshFormatOf's, refusing STL (read only) and listing the
// written formats in the message.
MeshFormat writableMeshFormatOf(const std::string& path);

// What a file holds before any check: vertices and polygons (0-based indices, each in range).
struct PolygonSoup {
  Positions positions;                     // #V by 3
  std::vector<std::vector<int>> polygons;  // #P polygons, each with >= 3 vertex indices
};

// Parses `path`. Throws InputError naming the file, the line (or byte offset, for binary data)
// and the problem for: a missing or unreadable file, an unknown format, a malformed header or
// number, a polygon with fewer than 3 vertices, an index out of range, truncated binary data.
PolygonSoup readPolygonSoup(const std::string& path);

// Splits every polygon with more than 3 vertices into a fan (v0, v_k, v_k+1). `splitPolygons`
// receives how many polygons were split.
Mesh triangulatePolygons(const PolygonSoup& soup, int* splitPolygons = nullptr);

// readPolygonSoup + triangulatePolygons + requireValidMesh. A notice is appended to `notices`
// (when given) for each repair made, e.g. "FILE: 6 quadrilateral faces split into triangles".
Mesh readMesh(const std::string& path, std::vector<std::string>* notices = nullptr);

// The file contents for `mesh` in `format` (Stl is rejected: flexure writes OBJ, OFF, PLY).
std::string formatMesh(const Mesh& mesh, MeshFormat format);

// Writes `mesh` to `path` in the format of its extension, atomically (atomic_write.h).
void writeMesh(const std::string& path, const Mesh& mesh);

}  // namespace flexure::modeling
