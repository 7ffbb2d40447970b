// Mesh reading and writing: exact round trips, reproducible output, each input format and its
// variants, and the errors (file and line or byte offset) for malformed files.
#include "modeling/mesh_io.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "modeling/errors.h"

namespace flexure::modeling {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

namespace fs = std::filesystem;

std::string tempPath(const std::string& name) {
  const fs::path dir = fs::path(FLEXURE_TEST_TMP) / "mesh_io";
  fs::create_directories(dir);
  return (dir / name).string();
}

// Writes `bytes` to a fresh temporary file called `name`; returns its path.
std::string writeTempFile(const std::string& name, const std::string& bytes) {
  const std::string path = tempPath(name);
  std::ofstream(path, std::ios::binary).write(bytes.data(), bytes.size());
  return path;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The message of the InputError `action` throws; fails the test when it throws nothing.
std::string inputErrorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

Mesh makeMesh(const std::vector<std::array<double, 3>>& points,
              const std::vector<std::array<int, 3>>& triangles) {
  Mesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t v = 0; v < points.size(); ++v) {
    for (int k = 0; k < 3; ++k) mesh.positions(v, k) = points[v][k];
  }
  mesh.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (size_t f = 0; f < triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) mesh.triangles(f, k) = triangles[f][k];
  }
  return mesh;
}

// A closed, consistently oriented tetrahedron.
Mesh tetrahedron(const std::vector<std::array<double, 3>>& corners) {
  return makeMesh(corners, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
}

// Coordinates that only survive a round trip when printed with up to 17 significant digits.
Mesh awkwardMesh() {
  return makeMesh({{0.1, 1.0 / 3.0, 1e-300},
                   {-2.5e17, 0.30000000000000004, -0.0},
                   {2.0 / 3.0, 5e-324, 1.7976931348623157e308},
                   {123456789.12345678, -1e-7, 6.02214076e23},
                   {std::nextafter(1.0, 2.0), -std::nextafter(0.1, 0.0), 9007199254740993.0}},
                  {{0, 1, 2}, {0, 2, 3}, {1, 3, 4}});
}

std::vector<std::vector<int>> trianglesOf(const Mesh& mesh) {
  std::vector<std::vector<int>> triangles;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    triangles.push_back({mesh.triangles(f, 0), mesh.triangles(f, 1), mesh.triangles(f, 2)});
  }
  return triangles;
}

std::vector<double> coordinatesOf(const Positions& positions) {
  return std::vector<double>(positions.data(), positions.data() + positions.size());
}

bool bitIdentical(const Positions& a, const Positions& b) {
  return a.rows() == b.rows() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0;
}

// Little- or big-endian binary encoding of a value, for hand-made PLY and STL files.
template <typename T>
void appendBytes(std::string& out, T value, bool bigEndian = false) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  const uint16_t probe = 1;
  const bool hostLittleEndian = *reinterpret_cast<const unsigned char*>(&probe) == 1;
  if (bigEndian == hostLittleEndian) std::reverse(bytes, bytes + sizeof(T));
  out.append(bytes, sizeof(T));
}

// ---------------------------------------------------------------------------------------------

TEST(MeshIoFormat, ExtensionsAreCaseInsensitive) {
  EXPECT_EQ(meshFormatOf("a/b.obj"), MeshFormat::Obj);
  EXPECT_EQ(meshFormatOf("b.OFF"), MeshFormat::Off);
  EXPECT_EQ(meshFormatOf("dir.x/b.Ply"), MeshFormat::Ply);
  EXPECT_EQ(meshFormatOf("b.stl"), MeshFormat::Stl);
}

TEST(MeshIoFormat, UnknownExtensionListsTheKnownOnes) {
  const std::string message = inputErrorOf([] { meshFormatOf("shape.3ds"); });
  EXPECT_THAT(message, HasSubstr("shape.3ds"));
  EXPECT_THAT(message, HasSubstr(".3ds"));
  EXPECT_THAT(message, HasSubstr(".obj .off .ply .stl"));
  EXPECT_THAT(inputErrorOf([] { meshFormatOf("noextension"); }), HasSubstr(".obj .off .ply"));
  EXPECT_THAT(inputErrorOf([] { readPolygonSoup("shape.3ds"); }), HasSubstr(".stl"));
}

// STL is read, not written: the output check lists what is written.
TEST(MeshIoFormat, WritableFormatsAreThoseWritten) {
  EXPECT_EQ(writableMeshFormatOf("a/b.OBJ"), MeshFormat::Obj);
  EXPECT_EQ(writableMeshFormatOf("b.off"), MeshFormat::Off);
  EXPECT_EQ(writableMeshFormatOf("b.ply"), MeshFormat::Ply);
  EXPECT_EQ(inputErrorOf([] { writableMeshFormatOf("scan.stl"); }),
            "scan.stl: STL output is not supported (flexure writes .obj .off .ply)");
  EXPECT_EQ(inputErrorOf([] { writableMeshFormatOf("shape.3ds"); }),
            "shape.3ds: unknown extension '.3ds' (flexure writes .obj .off .ply)");
}

// ---------------------------------------------------------------------------------------------

class MeshIoRoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(MeshIoRoundTrip, CoordinatesAndTrianglesReadBackBitExact) {
  const Mesh mesh = awkwardMesh();
  const std::string path = tempPath(std::string("round_trip.") + GetParam());
  writeMesh(path, mesh);
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_TRUE(bitIdentical(soup.positions, mesh.positions))
      << ::testing::PrintToString(coordinatesOf(soup.positions));
  EXPECT_TRUE(std::signbit(soup.positions(1, 2)));  // -0 stays negative
  EXPECT_EQ(soup.polygons, trianglesOf(mesh));
}

TEST_P(MeshIoRoundTrip, ReadMeshReturnsTheWrittenValidMesh) {
  const Mesh mesh = tetrahedron({{0.1, 0.2, 0.3}, {1.0 / 3.0, 0, 0}, {0, 2.0 / 3.0, 0}, {0, 0, 1}});
  const std::string path = tempPath(std::string("valid.") + GetParam());
  writeMesh(path, mesh);
  std::vector<std::string> notices;
  const Mesh read = readMesh(path, &notices);
  EXPECT_TRUE(bitIdentical(read.positions, mesh.positions));
  EXPECT_EQ(trianglesOf(read), trianglesOf(mesh));
  EXPECT_TRUE(notices.empty());
}

TEST_P(MeshIoRoundTrip, FormattingIsReproducible) {
  const MeshFormat format = meshFormatOf(std::string("x.") + GetParam());
  const std::string first = formatMesh(awkwardMesh(), format);
  EXPECT_EQ(formatMesh(awkwardMesh(), format), first);
  const std::string path = tempPath(std::string("twice.") + GetParam());
  writeMesh(path, awkwardMesh());
  EXPECT_EQ(readFile(path), first);
}

INSTANTIATE_TEST_SUITE_P(MeshIoFormats, MeshIoRoundTrip, ::testing::Values("obj", "off", "ply"));

TEST(MeshIoWrite, TextLayoutOfEachFormat) {
  const Mesh mesh = makeMesh({{0.1, 0, -1}, {1, 2.5, 3}, {1e-300, -2.5e17, 0}}, {{0, 1, 2}});
  EXPECT_EQ(formatMesh(mesh, MeshFormat::Obj),
            "v 0.1 0 -1\nv 1 2.5 3\nv 1e-300 -2.5e+17 0\nf 1 2 3\n");
  EXPECT_EQ(formatMesh(mesh, MeshFormat::Off),
            "OFF\n3 1 0\n0.1 0 -1\n1 2.5 3\n1e-300 -2.5e+17 0\n3 0 1 2\n");
  EXPECT_EQ(formatMesh(mesh, MeshFormat::Ply),
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
            "property double z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0.1 0 -1\n1 2.5 3\n1e-300 -2.5e+17 0\n3 0 1 2\n");
}

TEST(MeshIoWrite, StlOutputIsRejected) {
  const Mesh mesh = awkwardMesh();
  EXPECT_THAT(inputErrorOf([&] { formatMesh(mesh, MeshFormat::Stl); }),
              HasSubstr("STL output is not supported"));
  const std::string path = tempPath("rejected.stl");
  fs::remove(path);
  EXPECT_THAT(inputErrorOf([&] { writeMesh(path, mesh); }), HasSubstr("rejected.stl"));
  EXPECT_FALSE(fs::exists(path));
}

TEST(MeshIoWrite, MissingDirectoryThrowsAndCreatesNothing) {
  const fs::path dir = fs::path(tempPath("no_such_dir"));
  fs::remove_all(dir);
  const std::string path = (dir / "out.obj").string();
  EXPECT_THAT(inputErrorOf([&] { writeMesh(path, awkwardMesh()); }), HasSubstr("out.obj"));
  EXPECT_FALSE(fs::exists(dir));
}

TEST(MeshIoWrite, UnknownExtensionThrows) {
  const std::string path = tempPath("mesh.xyz");
  fs::remove(path);
  EXPECT_THAT(inputErrorOf([&] { writeMesh(path, awkwardMesh()); }), HasSubstr(".obj .off"));
  EXPECT_FALSE(fs::exists(path));
}

// ---------------------------------------------------------------------------------------------

TEST(MeshIoObj, ParsesCornerFormsNegativeIndicesAndIgnoredStatements) {
  const std::string path = writeTempFile("forms.obj",
                                         "# made by hand\n"
                                         "mtllib shape.mtl\n"
                                         "o shape\n"
                                         "v 0 0 0\n"
                                         "v +1.5 0 0 1.0\n"
                                         "v 0 1e-3 0\n"
                                         "vt 0 0\n"
                                         "vt 1 0\n"
                                         "vn 0 0 1\n"
                                         "v 1 1 0.25 0.5 0.5 0.5\n"
                                         "\n"
                                         "g group\n"
                                         "usemtl red\n"
                                         "s off\n"
                                         "f 1/1/1 2/2/1 3/1/1\n"
                                         "f 2//1 4//1 3//1   # trailing comment\r\n"
                                         "f -3/1 -1/2 -2/1\n"
                                         "f -4 -3 -2\n"
                                         "l 1 2\n");
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_THAT(coordinatesOf(soup.positions),
              ElementsAre(0, 0, 0, 1.5, 0, 0, 0, 1e-3, 0, 1, 1, 0.25));
  EXPECT_THAT(soup.polygons, ElementsAre(ElementsAre(0, 1, 2), ElementsAre(1, 3, 2),
                                         ElementsAre(1, 3, 2), ElementsAre(0, 1, 2)));
}

TEST(MeshIoObj, FaceMayPrecedeItsVertices) {
  const std::string path = writeTempFile("forward.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_THAT(readPolygonSoup(path).polygons, ElementsAre(ElementsAre(0, 1, 2)));
}

TEST(MeshIoObj, FileWithoutFacesIsNotAParseError) {
  const std::string path = writeTempFile("points.obj", "v 0 0 0\nv 1 0 0\n");
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_EQ(soup.positions.rows(), 2);
  EXPECT_TRUE(soup.polygons.empty());
  EXPECT_THROW(readMesh(path), InputError);  // the mesh check reports it
}

TEST(MeshIoObj, NanAndInfinityParseAndAreRejectedByTheMeshCheck) {
  const std::string path =
      writeTempFile("nonfinite.obj", "v nan 0 0\nv 1 inf 0\nv 0 1 -inf\nf 1 2 3\n");
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_TRUE(std::isnan(soup.positions(0, 0)));
  EXPECT_EQ(soup.positions(1, 1), std::numeric_limits<double>::infinity());
  EXPECT_EQ(soup.positions(2, 2), -std::numeric_limits<double>::infinity());
  EXPECT_THAT(inputErrorOf([&] { readMesh(path); }), HasSubstr("nonfinite.obj"));
}

// ---------------------------------------------------------------------------------------------

TEST(MeshIoOff, CountsOnTheHeaderLineAndComments) {
  const std::string path = writeTempFile("header_counts.off",
                                         "OFF 4 2 0  # counts here\n"
                                         "# a comment line\n"
                                         "0 0 0\n"
                                         "\n"
                                         "1 0 0 # vertex comment\n"
                                         "0 1 0\n"
                                         "1 1 0\n"
                                         "3 0 1 2\n"
                                         "# between faces\n"
                                         "3 1 3 2 255 0 0\n");
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_THAT(coordinatesOf(soup.positions), ElementsAre(0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0));
  EXPECT_THAT(soup.polygons, ElementsAre(ElementsAre(0, 1, 2), ElementsAre(1, 3, 2)));
}

TEST(MeshIoOff, VariantsWithExtraVertexColumns) {
  const std::string path = writeTempFile("colour.off",
                                         "CNOFF\n"
                                         "\n"
                                         "4 1 0\n"
                                         "0 0 0 0 0 1 255 0 0 255\n"
                                         "1 0 0 0 0 1 255 0 0 255\n"
                                         "1 1 0 0 0 1 255 0 0 255\n"
                                         "0 1 0 0 0 1 255 0 0 255\n"
                                         "4 0 1 2 3\n");
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_THAT(coordinatesOf(soup.positions), ElementsAre(0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0));
  EXPECT_THAT(soup.polygons, ElementsAre(ElementsAre(0, 1, 2, 3)));
}

// ---------------------------------------------------------------------------------------------

TEST(MeshIoPly, AsciiWithExtraPropertiesAndElements) {
  const std::string path = writeTempFile("ascii.ply",
                                         "ply\n"
                                         "format ascii 1.0\n"
                                         "comment made by hand\n"
                                         "element vertex 3\n"
                                         "property float nx\n"
                                         "property double x\n"
                                         "property double y\n"
                                         "property double z\n"
                                         "property uchar red\n"
                                         "element face 1\n"
                                         "property uchar flags\n"
                                         "property list uchar int vertex_index\n"
                                         "element edge 1\n"
                                         "property int vertex1\n"
                                         "property int vertex2\n"
                                         "end_header\n"
                                         "9 0.1 0.2 0.3 255\n"
                                         "9 1 0 0 0\n"
                                         "\n"
                                         "9 0 1 -2.5e17 7\n"
                                         "1 3 0 1 2\n"
                                         "0 1\n");
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_THAT(coordinatesOf(soup.positions), ElementsAre(0.1, 0.2, 0.3, 1, 0, 0, 0, 1, -2.5e17));
  EXPECT_THAT(soup.polygons, ElementsAre(ElementsAre(0, 1, 2)));
}

// A binary PLY: an element to skip before the vertices, float or double coordinates among other
// properties, and faces with a flag before the index list.
std::string binaryPly(bool bigEndian, bool doubleCoordinates) {
  std::string header = std::string("ply\nformat ") +
                       (bigEndian ? "binary_big_endian" : "binary_little_endian") +
                       " 1.0\n"
                       "element material 2\n"
                       "property uchar red\n"
                       "property list ushort int16 tags\n"
                       "element vertex 4\n"
                       "property int16 id\n" +
                       (doubleCoordinates ? "property float64 x\nproperty float64 y\n"
                                            "property float64 z\n"
                                          : "property float x\nproperty float y\n"
                                            "property float z\n") +
                       "property list uchar float normal\n"
                       "element face 2\n"
                       "property char flag\n"
                       "property list uint8 uint32 vertex_indices\n"
                       "end_header\n";
  std::string body;
  for (int m = 0; m < 2; ++m) {
    appendBytes<uint8_t>(body, 200, bigEndian);
    appendBytes<uint16_t>(body, 2, bigEndian);
    appendBytes<int16_t>(body, -1, bigEndian);
    appendBytes<int16_t>(body, 7, bigEndian);
  }
  const double coordinates[4][3] = {{0.1, 0, 0}, {1, 0, 0}, {0, -2.5, 0}, {1, 1, 1.0 / 3.0}};
  for (int v = 0; v < 4; ++v) {
    appendBytes<int16_t>(body, static_cast<int16_t>(v), bigEndian);
    for (double c : coordinates[v]) {
      if (doubleCoordinates) {
        appendBytes<double>(body, c, bigEndian);
      } else {
        appendBytes<float>(body, static_cast<float>(c), bigEndian);
      }
    }
    appendBytes<uint8_t>(body, 1, bigEndian);
    appendBytes<float>(body, 0.5f, bigEndian);
  }
  const uint32_t faces[2][3] = {{0, 1, 2}, {1, 3, 2}};
  for (const auto& face : faces) {
    appendBytes<int8_t>(body, -3, bigEndian);
    appendBytes<uint8_t>(body, 3, bigEndian);
    for (uint32_t index : face) appendBytes<uint32_t>(body, index, bigEndian);
  }
  return header + body;
}

TEST(MeshIoPly, BinaryLittleEndianFloatCoordinates) {
  const std::string path = writeTempFile("little.ply", binaryPly(false, false));
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_THAT(coordinatesOf(soup.positions),
              ElementsAre(double(0.1f), 0, 0, 1, 0, 0, 0, -2.5, 0, 1, 1, double(1.0f / 3.0f)));
  EXPECT_THAT(soup.polygons, ElementsAre(ElementsAre(0, 1, 2), ElementsAre(1, 3, 2)));
}

TEST(MeshIoPly, BinaryBigEndianDoubleCoordinates) {
  const std::string path = writeTempFile("big.ply", binaryPly(true, true));
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_THAT(coordinatesOf(soup.positions),
              ElementsAre(0.1, 0, 0, 1, 0, 0, 0, -2.5, 0, 1, 1, 1.0 / 3.0));
  EXPECT_THAT(soup.polygons, ElementsAre(ElementsAre(0, 1, 2), ElementsAre(1, 3, 2)));
}

TEST(MeshIoPly, TruncatedBinaryDataNamesTheByteOffset) {
  const std::string whole = binaryPly(false, true);
  const std::string path = writeTempFile("truncated.ply", whole.substr(0, whole.size() - 5));
  // Cutting 5 bytes leaves 3 of the 4 bytes of the last face's second index.
  const std::string offset = std::to_string(whole.size() - 8);
  const std::string message = inputErrorOf([&] { readPolygonSoup(path); });
  EXPECT_THAT(message, HasSubstr("truncated.ply: byte " + offset + ": "));
  EXPECT_THAT(message, HasSubstr("face 1"));
}

// ---------------------------------------------------------------------------------------------

// Two triangles sharing the edge (1,0,0)-(0,1,0), each listing its own copies of the vertices.
const float kStlTriangles[2][3][3] = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                      {{1, 0, 0}, {1, 1, 0.1f}, {0, 1, 0}}};

TEST(MeshIoStl, BinaryWithSolidHeaderMergesSharedVertices) {
  std::string bytes = "solid this header looks like ascii";
  bytes.resize(80, ' ');
  appendBytes<uint32_t>(bytes, 2);
  for (const auto& triangle : kStlTriangles) {
    for (int k = 0; k < 3; ++k) appendBytes<float>(bytes, k == 2 ? 1.0f : 0.0f);
    for (const auto& corner : triangle) {
      for (float c : corner) appendBytes<float>(bytes, c);
    }
    appendBytes<uint16_t>(bytes, 0);
  }
  const std::string path = writeTempFile("binary.stl", bytes);
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_EQ(soup.positions.rows(), 4);
  EXPECT_THAT(coordinatesOf(soup.positions),
              ElementsAre(0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, double(0.1f)));
  EXPECT_THAT(soup.polygons, ElementsAre(ElementsAre(0, 1, 2), ElementsAre(1, 3, 2)));
}

TEST(MeshIoStl, AsciiMergesSharedVertices) {
  const std::string path = writeTempFile("ascii.stl",
                                         "solid square\n"
                                         "  facet normal 0 0 1\n"
                                         "    outer loop\n"
                                         "      vertex 0 0 0\n"
                                         "      vertex 1 0 0\n"
                                         "      vertex 0 1 0\n"
                                         "    endloop\n"
                                         "  endfacet\n"
                                         "  facet normal 0 0 1\n"
                                         "    outer loop\n"
                                         "      vertex 1.0 0 0\n"
                                         "      vertex 1 1 0.1\n"
                                         "      vertex 0 1e0 0\n"
                                         "    endloop\n"
                                         "  endfacet\n"
                                         "endsolid square\n");
  const PolygonSoup soup = readPolygonSoup(path);
  EXPECT_EQ(soup.positions.rows(), 4);
  EXPECT_THAT(coordinatesOf(soup.positions), ElementsAre(0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0.1));
  EXPECT_THAT(soup.polygons, ElementsAre(ElementsAre(0, 1, 2), ElementsAre(1, 3, 2)));
}

TEST(MeshIoStl, BinaryWithWrongSizeNamesTheCountAtByte80) {
  std::string bytes(80, 'x');
  appendBytes<uint32_t>(bytes, 3);
  bytes.append(50 * 2, '\0');
  const std::string path = writeTempFile("short.stl", bytes);
  const std::string message = inputErrorOf([&] { readPolygonSoup(path); });
  EXPECT_THAT(message, HasSubstr("short.stl: byte 80: "));
  EXPECT_THAT(message, HasSubstr("3 triangles"));
}

// ---------------------------------------------------------------------------------------------

TEST(MeshIoTriangulate, FansSplitPolygonsAndCountsThem) {
  PolygonSoup soup;
  soup.positions = Positions::Zero(7, 3);
  soup.polygons = {{0, 1, 2}, {0, 2, 3, 4}, {6, 5, 4, 3, 2}};
  int split = -1;
  const Mesh mesh = triangulatePolygons(soup, &split);
  EXPECT_EQ(split, 2);
  EXPECT_EQ(mesh.vertexCount(), 7);
  EXPECT_THAT(trianglesOf(mesh),
              ElementsAre(ElementsAre(0, 1, 2), ElementsAre(0, 2, 3), ElementsAre(0, 3, 4),
                          ElementsAre(6, 5, 4), ElementsAre(6, 4, 3), ElementsAre(6, 3, 2)));
}

TEST(MeshIoTriangulate, ReadMeshSplitsQuadsAndSaysSo) {
  const std::string path = writeTempFile("cube.obj",
                                         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                         "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                         "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\n"
                                         "f 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
  std::vector<std::string> notices;
  const Mesh mesh = readMesh(path, &notices);
  EXPECT_EQ(mesh.vertexCount(), 8);
  EXPECT_EQ(mesh.faceCount(), 12);
  EXPECT_THAT(notices, ElementsAre(path + ": 6 quadrilateral faces split into triangles"));
}

// ---------------------------------------------------------------------------------------------

struct MalformedFile {
  const char* name;
  const char* contents;
  const char* where;    // "line N" or "byte N"
  const char* problem;  // a part of the message
};

void PrintTo(const MalformedFile& file, std::ostream* out) {
  *out << file.name;
}

// "index0.obj" -> "index0_obj": test names allow only letters, digits and '_'.
std::string caseName(const ::testing::TestParamInfo<MalformedFile>& test) {
  std::string name = test.param.name;
  std::replace(name.begin(), name.end(), '.', '_');
  return name;
}

class MeshIoErrors : public ::testing::TestWithParam<MalformedFile> {};

TEST_P(MeshIoErrors, MessageNamesFileLocationAndProblem) {
  const MalformedFile& file = GetParam();
  const std::string path = writeTempFile(file.name, file.contents);
  const std::string message = inputErrorOf([&] { readPolygonSoup(path); });
  EXPECT_THAT(message, HasSubstr(path + ": " + file.where + ": "));
  EXPECT_THAT(message, HasSubstr(file.problem));
}

constexpr char kTriangleObj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

INSTANTIATE_TEST_SUITE_P(
    MeshIoObjFiles, MeshIoErrors,
    ::testing::Values(
        MalformedFile{"index0.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4", "index 0"},
        MalformedFile{"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n", "line 5",
                      "out of range"},
        MalformedFile{"relative.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n", "line 3", "out of range"},
        MalformedFile{"dots.obj", "v 0 0 0\nv 1.2.3 0 0\n", "line 2", "'1.2.3'"},
        MalformedFile{"letters.obj", "v 0 abc 0\n", "line 1", "'abc'"},
        MalformedFile{"plusminus.obj", "v 0 +-1 0\n", "line 1", "'+-1'"},
        MalformedFile{"huge.obj", "v 0 1e400 0\n", "line 1", "out of range"},
        MalformedFile{"short_v.obj", "v 0 0\n", "line 1", "v x y z"},
        MalformedFile{"two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3", "at least 3"},
        MalformedFile{"badcorner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n", "line 4", "'x'"},
        MalformedFile{"keyword.obj", "v 0 0 0\nbogus 1 2\n", "line 2", "'bogus'"}),
    caseName);

INSTANTIATE_TEST_SUITE_P(
    MeshIoOffFiles, MeshIoErrors,
    ::testing::Values(
        MalformedFile{"header.off", "# c\nPLY\n3 1 0\n", "line 2", "'PLY'"},
        MalformedFile{"four.off", "4OFF\n", "line 1", "3-dimensional"},
        MalformedFile{"counts.off", "OFF\n3 x 0\n", "line 2", "'x'"},
        MalformedFile{"fewv.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n", "line 4", "2 of 3 vertices"},
        MalformedFile{"shortv.off", "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n", "line 4", "vertex 1"},
        MalformedFile{"number.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0..5\n3 0 1 2\n", "line 5",
                      "'0..5'"},
        MalformedFile{"twov.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "line 6",
                      "fewer than 3"},
        MalformedFile{"range.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n\n3 0 1 3\n", "line 6",
                      "out of range"},
        MalformedFile{"missing.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "line 6",
                      "fewer than 3"},
        MalformedFile{"extra.off",
                      "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n# c\n\n3 1 3 2\n",
                      "line 10", "data after the 1 face the header counts"}),
    caseName);

INSTANTIATE_TEST_SUITE_P(
    MeshIoPlyFiles, MeshIoErrors,
    ::testing::Values(
        MalformedFile{"magic.ply", "PLY\n", "line 1", "not a PLY file"},
        MalformedFile{"type.ply",
                      "ply\nformat ascii 1.0\nelement vertex 0\nproperty real x\nend_header\n",
                      "line 4", "'real'"},
        MalformedFile{"noend.ply", "ply\nformat ascii 1.0\nelement vertex 0\n", "line 3",
                      "end_header"},
        MalformedFile{"noz.ply",
                      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                      "property float y\nend_header\n",
                      "line 3", "'z'"},
        MalformedFile{"few.ply",
                      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                      "property float y\nproperty float z\nend_header\n0 0 0\n1 0\n",
                      "line 9", "too few values"},
        MalformedFile{"float_index.ply",
                      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.0\n",
                      "line 13", "'2.0'"},
        MalformedFile{"range.ply",
                      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
                      "line 13", "out of range"},
        MalformedFile{"two.ply",
                      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
                      "line 13", "fewer than 3"},
        MalformedFile{"ends.ply",
                      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n",
                      "line 9", "vertex 2 of 3"}),
    caseName);

INSTANTIATE_TEST_SUITE_P(
    MeshIoStlFiles, MeshIoErrors,
    ::testing::Values(
        MalformedFile{"outside.stl", "solid a\nvertex 0 0 0\nendsolid a\n", "line 2",
                      "unexpected 'vertex'"},
        MalformedFile{"number.stl",
                      "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                      "vertex 0 1 zero\nendloop\nendfacet\nendsolid a\n",
                      "line 6", "'zero'"},
        MalformedFile{"two.stl",
                      "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                      "endloop\nendfacet\nendsolid a\n",
                      "line 6", "at least 3"},
        MalformedFile{"unended.stl",
                      "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n",
                      "line 5", "endsolid"},
        MalformedFile{"neither.stl", "hello", "line 1", "not an STL file"}),
    caseName);

TEST(MeshIoErrorsMisc, MissingFile) {
  const std::string path = tempPath("does_not_exist.obj");
  fs::remove(path);
  EXPECT_EQ(inputErrorOf([&] { readPolygonSoup(path); }),
            path + ": cannot open file (No such file or directory)");
  EXPECT_THAT(inputErrorOf([&] { readMesh(path); }), HasSubstr("cannot open file"));
}

TEST(MeshIoErrorsMisc, ReadMeshReportsAnInvalidMeshWithItsPath) {
  // Two faces over the same three vertices: a duplicate face.
  const std::string path =
      writeTempFile("duplicate.obj", std::string(kTriangleObj) + "f 1 2 3\nf 1 2 3\n");
  EXPECT_EQ(readPolygonSoup(path).polygons.size(), 2u);
  EXPECT_THAT(inputErrorOf([&] { readMesh(path); }), HasSubstr("duplicate.obj"));
}

}  // namespace
}  // namespace flexure::modeling
