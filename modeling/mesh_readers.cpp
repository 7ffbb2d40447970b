// readPolygonSoup: one parser per format (OBJ, OFF, PLY, STL), all reporting errors as
// "PATH: line N: PROBLEM" (text) or "PATH: byte N: PROBLEM" (binary data).
#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "modeling/errors.h"
#include "modeling/mesh_io.h"

namespace flexure::modeling {
namespace {

using Point = std::array<double, 3>;

// ---------------------------------------------------------------------------------------------
// Shared helpers: file access, lines, words, numbers, error locations.

std::string readFileBytes(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    throw InputError(path + ": cannot open file (" + std::strerror(errno) + ")");
  }
  std::string bytes;
  char buffer[1 << 16];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, file)) > 0) bytes.append(buffer, n);
  const bool failed = std::ferror(file) != 0;
  const int error = errno;
  std::fclose(file);
  if (failed) throw InputError(path + ": cannot read file (" + std::strerror(error) + ")");
  return bytes;
}

// Where a problem is: a line of a text file or a byte offset of binary data.
struct Location {
  const std::string& path;
  long long position;
  bool isByteOffset = false;
};

[[noreturn]] void fail(const Location& at, const std::string& problem) {
  const char* unit = at.isByteOffset ? ": byte " : ": line ";
  throw InputError(at.path + unit + std::to_string(at.position) + ": " + problem);
}

// A token as shown in a message: quoted, cut short when long, bytes that are not printable ASCII
// shown as \xNN (binary data read as text must not reach the terminal raw).
std::string quoted(std::string_view token) {
  constexpr size_t kMaxShown = 40;
  std::string shown = "'";
  for (const char c : token.substr(0, kMaxShown)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f) {
      shown += c;
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      shown += escaped;
    }
  }
  return shown + (token.size() > kMaxShown ? "...'" : "'");
}

// Iterates over the lines of a text; a line excludes its '\n' and a trailing '\r'.
class LineCursor {
 public:
  LineCursor(std::string_view text, size_t offset = 0, int firstLineNumber = 1)
      : text_(text), next_(offset), number_(firstLineNumber - 1) {}

  bool next() {
    if (next_ >= text_.size()) return false;
    size_t end = text_.find('\n', next_);
    if (end == std::string_view::npos) end = text_.size();
    line_ = text_.substr(next_, end - next_);
    if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
    next_ = end + 1;
    ++number_;
    return true;
  }
  std::string_view line() const { return line_; }
  int number() const { return number_; }
  // Offset of the first byte after the current line.
  size_t offsetAfterLine() const { return std::min(next_, text_.size()); }

 private:
  std::string_view text_;
  std::string_view line_;
  size_t next_;
  int number_;
};

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !isSpace(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

// The words of `line` before any '#' comment.
std::vector<std::string_view> wordsBeforeComment(std::string_view line) {
  return splitWords(line.substr(0, line.find('#')));
}

// from_chars rejects a leading '+'; text formats allow one (but not "+-1").
std::string_view withoutPlus(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  return token;
}

// A decimal number (also "nan", "inf": the mesh check rejects those, naming the vertex).
double parseNumber(std::string_view token, const Location& at) {
  const std::string_view digits = withoutPlus(token);
  double value = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error == std::errc::result_out_of_range) fail(at, "number out of range: " + quoted(token));
  if (error != std::errc() || end != digits.data() + digits.size()) {
    fail(at, "malformed number " + quoted(token));
  }
  return value;
}

long long parseInteger(std::string_view token, const Location& at) {
  const std::string_view digits = withoutPlus(token);
  long long value = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error != std::errc() || end != digits.data() + digits.size()) {
    fail(at, "malformed integer " + quoted(token));
  }
  return value;
}

// A count from a header: a non-negative integer that fits an int.
int parseCount(std::string_view token, const Location& at) {
  const long long count = parseInteger(token, at);
  if (count < 0 || count > INT32_MAX) fail(at, "invalid count " + quoted(token));
  return static_cast<int>(count);
}

Positions toPositions(const std::vector<Point>& points) {
  Positions positions(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t v = 0; v < points.size(); ++v) {
    for (int k = 0; k < 3; ++k) positions(static_cast<Eigen::Index>(v), k) = points[v][k];
  }
  return positions;
}

// ---------------------------------------------------------------------------------------------
// OBJ: "v x y z [w]" and "f v1 v2 v3 ..." with v, v/t, v//n or v/t/n corners; indices are
// 1-based, negative ones count back from the last vertex defined so far.

bool isIgnoredObjStatement(std::string_view keyword) {
  // Everything else the OBJ specification defines: normals, texture coordinates, grouping,
  // materials, lines, points and free-form geometry.
  static const std::unordered_set<std::string_view> kIgnored = {
      "vn",       "vt",       "vp",        "g",          "o",     "s",      "usemtl",
      "mtllib",   "l",        "p",         "cstype",     "deg",   "bmat",   "step",
      "curv",     "curv2",    "surf",      "parm",       "trim",  "hole",   "scrv",
      "sp",       "end",      "con",       "mg",         "lod",   "maplib", "usemap",
      "c_interp", "d_interp", "trace_obj", "shadow_obj", "bevel", "ctech",  "stech"};
  return kIgnored.count(keyword) > 0;
}

// "v x y z [w]", or "v x y z r g b" as MeshLab writes vertex colours; only x y z are kept.
Point parseObjVertex(const std::vector<std::string_view>& words, const Location& at) {
  if (words.size() < 4 || words.size() > 7) fail(at, "expected 'v x y z [w]'");
  for (size_t i = 4; i < words.size(); ++i) parseNumber(words[i], at);
  return {parseNumber(words[1], at), parseNumber(words[2], at), parseNumber(words[3], at)};
}

// The 0-based vertex index of a face corner "v", "v/t", "v//n" or "v/t/n". Positive indices are
// range-checked after the whole file is read (a face may precede the vertices it uses).
int parseObjCorner(std::string_view corner, int verticesSoFar, const Location& at) {
  std::vector<std::string_view> parts;
  for (size_t start = 0;;) {
    const size_t slash = corner.find('/', start);
    parts.push_back(corner.substr(start, slash - start));
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  if (parts.size() > 3) fail(at, "malformed face corner " + quoted(corner));
  // Texture and normal indices are not used, but must be well-formed.
  for (size_t i = 1; i < parts.size(); ++i) {
    if (!parts[i].empty()) parseInteger(parts[i], at);
  }
  const std::string_view vertex = parts[0];
  const long long index = parseInteger(vertex, at);
  if (index == 0) fail(at, "vertex index 0 (OBJ indices start at 1)");
  if (index > 0) {
    if (index > INT32_MAX) fail(at, "vertex index " + quoted(vertex) + " out of range");
    return static_cast<int>(index - 1);
  }
  if (-index > verticesSoFar) {
    fail(at, "relative vertex index " + quoted(vertex) + " out of range (" +
                 std::to_string(verticesSoFar) + " vertices defined so far)");
  }
  return static_cast<int>(verticesSoFar + index);
}

PolygonSoup parseObj(const std::string& path, std::string_view text) {
  std::vector<Point> points;
  std::vector<std::vector<int>> polygons;
  std::vector<int> polygonLines;
  LineCursor lines(text);
  while (lines.next()) {
    const Location at{path, lines.number()};
    const auto words = wordsBeforeComment(lines.line());
    if (words.empty()) continue;
    if (words[0] == "v") {
      points.push_back(parseObjVertex(words, at));
    } else if (words[0] == "f") {
      if (words.size() < 4) fail(at, "a face needs at least 3 vertices");
      std::vector<int> polygon;
      for (size_t i = 1; i < words.size(); ++i) {
        polygon.push_back(parseObjCorner(words[i], static_cast<int>(points.size()), at));
      }
      polygons.push_back(std::move(polygon));
      polygonLines.push_back(lines.number());
    } else if (!isIgnoredObjStatement(words[0])) {
      fail(at, "unknown statement " + quoted(words[0]));
    }
  }
  for (size_t p = 0; p < polygons.size(); ++p) {
    for (int index : polygons[p]) {
      if (index >= static_cast<int>(points.size())) {
        fail({path, polygonLines[p]}, "vertex index " + std::to_string(index + 1) +
                                          " out of range (the file has " +
                                          std::to_string(points.size()) + " vertices)");
      }
    }
  }
  return {toPositions(points), std::move(polygons)};
}

// ---------------------------------------------------------------------------------------------
// OFF: header "[ST][C][N]OFF", counts "nv nf [ne]" (on the header line or the next one), then
// nv vertex lines "x y z [extra columns]" and nf face lines "k i1 ... ik [colour]", 0-based,
// and nothing else but comments and blank lines. '#' starts a comment.

// Advances to the next line holding words; false at end of text.
bool nextWordsLine(LineCursor& lines, std::vector<std::string_view>& words) {
  while (lines.next()) {
    words = wordsBeforeComment(lines.line());
    if (!words.empty()) return true;
  }
  return false;
}

void checkOffKeyword(std::string_view keyword, const Location& at) {
  constexpr std::string_view kSuffix = "OFF";
  if (keyword.size() < kSuffix.size() || keyword.substr(keyword.size() - 3) != kSuffix) {
    fail(at, "not an OFF file (expected the header 'OFF', found " + quoted(keyword) + ")");
  }
  for (char c : keyword.substr(0, keyword.size() - 3)) {
    if (c == '4' || c == 'n') fail(at, quoted(keyword) + ": only 3-dimensional OFF is supported");
    // ST: texture coordinates, C: colour, N: normal; all extra vertex columns.
    if (c != 'S' && c != 'T' && c != 'C' && c != 'N') {
      fail(at, "unknown OFF header " + quoted(keyword));
    }
  }
}

struct OffCounts {
  int vertices = 0;
  int faces = 0;
};

OffCounts parseOffHeader(const std::string& path, LineCursor& lines) {
  std::vector<std::string_view> words;
  if (!nextWordsLine(lines, words)) fail({path, lines.number()}, "empty file (no OFF header)");
  checkOffKeyword(words[0], {path, lines.number()});
  words.erase(words.begin());
  if (!words.empty() && words[0] == "BINARY") {
    fail({path, lines.number()}, "binary OFF is not supported");
  }
  if (words.empty() && !nextWordsLine(lines, words)) {
    fail({path, lines.number()}, "file ends before the vertex and face counts");
  }
  const Location at{path, lines.number()};
  if (words.size() < 2 || words.size() > 3) {
    fail(at, "expected counts 'vertices faces edges'");
  }
  return {parseCount(words[0], at), parseCount(words[1], at)};
}

// "k i1 ... ik [colour]": face `f` of a file with `vertexCount` vertices.
std::vector<int> parseOffFace(const std::vector<std::string_view>& words, int f, int vertexCount,
                              const Location& at) {
  const long long size = parseInteger(words[0], at);
  const std::string name = "face " + std::to_string(f);
  if (size < 3) fail(at, name + " has fewer than 3 vertices");
  if (static_cast<long long>(words.size()) - 1 < size) {
    fail(at, name + " lists fewer than " + std::to_string(size) + " vertex indices");
  }
  std::vector<int> polygon;
  for (size_t i = 1; i <= static_cast<size_t>(size); ++i) {
    const long long index = parseInteger(words[i], at);
    if (index < 0 || index >= vertexCount) {
      fail(at, name + ": vertex index " + std::to_string(index) + " out of range (" +
                   std::to_string(vertexCount) + " vertices)");
    }
    polygon.push_back(static_cast<int>(index));
  }
  return polygon;
}

// Advances to the next line holding words; fails naming how many `items` were read.
void nextOffRecord(const std::string& path, LineCursor& lines, std::vector<std::string_view>& words,
                   int index, int count, const char* items) {
  if (!nextWordsLine(lines, words)) {
    fail({path, lines.number()},
         "file ends after " + std::to_string(index) + " of " + std::to_string(count) + " " + items);
  }
}

PolygonSoup parseOff(const std::string& path, std::string_view text) {
  LineCursor lines(text);
  const OffCounts counts = parseOffHeader(path, lines);
  std::vector<std::string_view> words;
  std::vector<Point> points;
  for (int v = 0; v < counts.vertices; ++v) {
    nextOffRecord(path, lines, words, v, counts.vertices, "vertices");
    const Location at{path, lines.number()};
    // Only x y z: the columns after them (normal, colour, texture) are not used.
    if (words.size() < 3) fail(at, "vertex " + std::to_string(v) + " needs 3 coordinates");
    points.push_back(
        {parseNumber(words[0], at), parseNumber(words[1], at), parseNumber(words[2], at)});
  }
  std::vector<std::vector<int>> polygons;
  for (int f = 0; f < counts.faces; ++f) {
    nextOffRecord(path, lines, words, f, counts.faces, "faces");
    polygons.push_back(parseOffFace(words, f, counts.vertices, {path, lines.number()}));
  }
  // Lines past the counted faces: faces the header's count leaves out, which would be dropped.
  if (nextWordsLine(lines, words)) {
    fail({path, lines.number()}, "data after the " + std::to_string(counts.faces) +
                                     (counts.faces == 1 ? " face" : " faces") +
                                     " the header counts (is the header's face count too small?)");
  }
  return {toPositions(points), std::move(polygons)};
}

// ---------------------------------------------------------------------------------------------
// PLY: a text header ("ply", "format ...", "element NAME COUNT", "property TYPE NAME",
// "property list COUNT_TYPE ITEM_TYPE NAME", "end_header") followed by ascii lines (one element
// instance per line) or packed binary records of either byte order.

enum class PlyScalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyProperty {
  std::string name;
  bool isList = false;
  PlyScalar countType = PlyScalar::UInt8;  // lists only
  PlyScalar valueType = PlyScalar::Float32;
};

struct PlyElement {
  std::string name;
  int count = 0;
  std::vector<PlyProperty> properties;
  int line = 0;  // of its "element" header line
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
  size_t bodyOffset = 0;
  int bodyFirstLine = 0;
};

PlyScalar parsePlyScalar(std::string_view name, const Location& at) {
  static const std::unordered_map<std::string_view, PlyScalar> kNames = {
      {"char", PlyScalar::Int8},      {"int8", PlyScalar::Int8},
      {"uchar", PlyScalar::UInt8},    {"uint8", PlyScalar::UInt8},
      {"short", PlyScalar::Int16},    {"int16", PlyScalar::Int16},
      {"ushort", PlyScalar::UInt16},  {"uint16", PlyScalar::UInt16},
      {"int", PlyScalar::Int32},      {"int32", PlyScalar::Int32},
      {"uint", PlyScalar::UInt32},    {"uint32", PlyScalar::UInt32},
      {"float", PlyScalar::Float32},  {"float32", PlyScalar::Float32},
      {"double", PlyScalar::Float64}, {"float64", PlyScalar::Float64}};
  const auto found = kNames.find(name);
  if (found == kNames.end()) fail(at, "unknown property type " + quoted(name));
  return found->second;
}

bool isFloatingPoint(PlyScalar type) {
  return type == PlyScalar::Float32 || type == PlyScalar::Float64;
}

size_t byteSize(PlyScalar type) {
  switch (type) {
    case PlyScalar::Int8:
    case PlyScalar::UInt8:
      return 1;
    case PlyScalar::Int16:
    case PlyScalar::UInt16:
      return 2;
    case PlyScalar::Int32:
    case PlyScalar::UInt32:
    case PlyScalar::Float32:
      return 4;
    case PlyScalar::Float64:
      return 8;
  }
  return 0;
}

PlyEncoding parsePlyFormat(const std::vector<std::string_view>& words, const Location& at) {
  if (words.size() != 3) fail(at, "expected 'format ENCODING 1.0'");
  if (words[1] == "ascii") return PlyEncoding::Ascii;
  if (words[1] == "binary_little_endian") return PlyEncoding::BinaryLittleEndian;
  if (words[1] == "binary_big_endian") return PlyEncoding::BinaryBigEndian;
  fail(at, "unknown PLY format " + quoted(words[1]));
}

PlyProperty parsePlyProperty(const std::vector<std::string_view>& words, const Location& at) {
  PlyProperty property;
  if (words.size() == 5 && words[1] == "list") {
    property.isList = true;
    property.countType = parsePlyScalar(words[2], at);
    property.valueType = parsePlyScalar(words[3], at);
    property.name = words[4];
    if (isFloatingPoint(property.countType)) fail(at, "a list count must have an integer type");
  } else if (words.size() == 3 && words[1] != "list") {
    property.valueType = parsePlyScalar(words[1], at);
    property.name = words[2];
  } else {
    fail(at, "expected 'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'");
  }
  return property;
}

PlyHeader parsePlyHeader(const std::string& path, std::string_view text) {
  LineCursor lines(text);
  if (!lines.next() || splitWords(lines.line()) != std::vector<std::string_view>{"ply"}) {
    fail({path, 1}, "not a PLY file (the first line must be 'ply')");
  }
  PlyHeader header;
  bool hasFormat = false;
  while (lines.next()) {
    const Location at{path, lines.number()};
    const auto words = splitWords(lines.line());
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    if (words[0] == "end_header") {
      if (!hasFormat) fail(at, "the header has no 'format' line");
      header.bodyOffset = lines.offsetAfterLine();
      header.bodyFirstLine = lines.number() + 1;
      return header;
    }
    if (words[0] == "format") {
      header.encoding = parsePlyFormat(words, at);
      hasFormat = true;
    } else if (words[0] == "element") {
      if (words.size() != 3) fail(at, "expected 'element NAME COUNT'");
      header.elements.push_back(
          {std::string(words[1]), parseCount(words[2], at), {}, lines.number()});
    } else if (words[0] == "property") {
      if (header.elements.empty()) fail(at, "a property before any element");
      header.elements.back().properties.push_back(parsePlyProperty(words, at));
    } else {
      fail(at, "unknown header line " + quoted(words[0]));
    }
  }
  fail({path, lines.number()}, "the header has no 'end_header' line");
}

// What flexure takes from the elements: vertex x, y, z and the face index lists.
struct PlyFields {
  int vertexElement = -1;
  std::array<int, 3> coordinates = {-1, -1, -1};  // property indices of x, y, z
  int faceElement = -1;
  int faceIndices = -1;  // property index of vertex_indices / vertex_index
};

int findProperty(const PlyElement& element, std::string_view name) {
  for (size_t i = 0; i < element.properties.size(); ++i) {
    if (element.properties[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

PlyFields findPlyFields(const std::string& path, const PlyHeader& header) {
  PlyFields fields;
  for (size_t e = 0; e < header.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    if (element.name == "vertex") fields.vertexElement = static_cast<int>(e);
    if (element.name == "face") fields.faceElement = static_cast<int>(e);
  }
  if (fields.vertexElement < 0) {
    fail({path, header.bodyFirstLine - 1}, "the header declares no 'vertex' element");
  }
  const PlyElement& vertex = header.elements[fields.vertexElement];
  for (int k = 0; k < 3; ++k) {
    const std::string name(1, "xyz"[k]);
    fields.coordinates[k] = findProperty(vertex, name);
    if (fields.coordinates[k] < 0 || vertex.properties[fields.coordinates[k]].isList) {
      fail({path, vertex.line}, "the 'vertex' element has no scalar property '" + name + "'");
    }
  }
  if (fields.faceElement < 0) return fields;
  const PlyElement& face = header.elements[fields.faceElement];
  fields.faceIndices = findProperty(face, "vertex_indices");
  if (fields.faceIndices < 0) fields.faceIndices = findProperty(face, "vertex_index");
  if (fields.faceIndices < 0 || !face.properties[fields.faceIndices].isList ||
      isFloatingPoint(face.properties[fields.faceIndices].valueType)) {
    fail({path, face.line}, "the 'face' element has no integer list property 'vertex_indices'");
  }
  return fields;
}

// Values of ascii PLY data: one element instance per line, whitespace-separated.
class PlyAsciiSource {
 public:
  PlyAsciiSource(const std::string& path, std::string_view text, const PlyHeader& header)
      : path_(path), lines_(text, header.bodyOffset, header.bodyFirstLine) {}

  void beginRecord(const PlyElement& element, int index) {
    do {
      if (!lines_.next()) {
        fail("data ends before " + element.name + " " + std::to_string(index) + " of " +
             std::to_string(element.count));
      }
      words_ = splitWords(lines_.line());
    } while (words_.empty());
    nextWord_ = 0;
  }
  double read(PlyScalar type) {
    if (nextWord_ >= words_.size()) fail("too few values on the line");
    const std::string_view word = words_[nextWord_++];
    const Location at{path_, lines_.number()};
    if (isFloatingPoint(type)) return parseNumber(word, at);
    return static_cast<double>(parseInteger(word, at));
  }
  void endRecord() {
    if (nextWord_ != words_.size()) fail("more values on the line than the header declares");
  }
  [[noreturn]] void fail(const std::string& problem) const {
    modeling::fail({path_, lines_.number()}, problem);
  }

 private:
  const std::string& path_;
  LineCursor lines_;
  std::vector<std::string_view> words_;
  size_t nextWord_ = 0;
};

// Values of binary PLY data: packed records, every value in the file's byte order.
class PlyBinarySource {
 public:
  PlyBinarySource(const std::string& path, std::string_view bytes, const PlyHeader& header)
      : path_(path),
        bytes_(bytes),
        offset_(header.bodyOffset),
        bigEndian_(header.encoding == PlyEncoding::BinaryBigEndian) {}

  void beginRecord(const PlyElement& element, int index) {
    element_ = &element;
    index_ = index;
    recordOffset_ = offset_;
  }
  double read(PlyScalar type) {
    const size_t size = byteSize(type);
    if (bytes_.size() - offset_ < size) {
      modeling::fail({path_, static_cast<long long>(offset_), true},
                     "data ends inside " + element_->name + " " + std::to_string(index_) + " of " +
                         std::to_string(element_->count));
    }
    const uint64_t bits = readBits(size);
    offset_ += size;
    return decode(type, bits);
  }
  void endRecord() {}
  [[noreturn]] void fail(const std::string& problem) const {
    modeling::fail({path_, static_cast<long long>(recordOffset_), true}, problem);
  }

 private:
  // The `size` bytes at the offset as an unsigned integer, whatever the host's byte order.
  uint64_t readBits(size_t size) const {
    uint64_t bits = 0;
    for (size_t i = 0; i < size; ++i) {
      const size_t byte = bigEndian_ ? i : size - 1 - i;
      bits = bits << 8 | static_cast<unsigned char>(bytes_[offset_ + byte]);
    }
    return bits;
  }
  template <typename T, typename Bits>
  static double as(uint64_t bits) {
    const auto narrow = static_cast<Bits>(bits);
    T value;
    std::memcpy(&value, &narrow, sizeof value);
    return static_cast<double>(value);
  }
  static double decode(PlyScalar type, uint64_t bits) {
    switch (type) {
      case PlyScalar::Int8:
        return as<int8_t, uint8_t>(bits);
      case PlyScalar::UInt8:
        return as<uint8_t, uint8_t>(bits);
      case PlyScalar::Int16:
        return as<int16_t, uint16_t>(bits);
      case PlyScalar::UInt16:
        return as<uint16_t, uint16_t>(bits);
      case PlyScalar::Int32:
        return as<int32_t, uint32_t>(bits);
      case PlyScalar::UInt32:
        return as<uint32_t, uint32_t>(bits);
      case PlyScalar::Float32:
        return as<float, uint32_t>(bits);
      case PlyScalar::Float64:
        return as<double, uint64_t>(bits);
    }
    return 0;
  }

  const std::string& path_;
  std::string_view bytes_;
  size_t offset_;
  bool bigEndian_;
  const PlyElement* element_ = nullptr;
  int index_ = 0;
  size_t recordOffset_ = 0;
};

// Reads one list property; returns its items when `keep`, otherwise skips them.
template <typename Source>
std::vector<double> readPlyList(Source& source, const PlyProperty& property, bool keep) {
  const double count = source.read(property.countType);
  if (count < 0) source.fail("negative list length in '" + property.name + "'");
  std::vector<double> items;
  for (long long i = 0; i < static_cast<long long>(count); ++i) {
    const double item = source.read(property.valueType);
    if (keep) items.push_back(item);
  }
  return items;
}

template <typename Source>
void readPlyFace(Source& source, const PlyElement& face, int faceIndex, int indicesProperty,
                 int vertexCount, std::vector<std::vector<int>>& polygons) {
  std::vector<double> indices;
  for (int p = 0; p < static_cast<int>(face.properties.size()); ++p) {
    const PlyProperty& property = face.properties[p];
    if (property.isList) {
      std::vector<double> items = readPlyList(source, property, p == indicesProperty);
      if (p == indicesProperty) indices = std::move(items);
    } else {
      source.read(property.valueType);
    }
  }
  const std::string name = "face " + std::to_string(faceIndex);
  if (indices.size() < 3) source.fail(name + " has fewer than 3 vertices");
  std::vector<int> polygon;
  for (double index : indices) {
    if (index < 0 || index >= vertexCount) {
      source.fail(name + ": vertex index " + std::to_string(static_cast<long long>(index)) +
                  " out of range (" + std::to_string(vertexCount) + " vertices)");
    }
    polygon.push_back(static_cast<int>(index));
  }
  polygons.push_back(std::move(polygon));
}

template <typename Source>
Point readPlyVertex(Source& source, const PlyElement& vertex, const std::array<int, 3>& xyz) {
  Point point = {0, 0, 0};
  for (int p = 0; p < static_cast<int>(vertex.properties.size()); ++p) {
    const PlyProperty& property = vertex.properties[p];
    if (property.isList) {
      readPlyList(source, property, false);
      continue;
    }
    const double value = source.read(property.valueType);
    for (int k = 0; k < 3; ++k) {
      if (p == xyz[k]) point[k] = value;
    }
  }
  return point;
}

template <typename Source>
void skipPlyRecord(Source& source, const PlyElement& element) {
  for (const PlyProperty& property : element.properties) {
    if (property.isList) {
      readPlyList(source, property, false);
    } else {
      source.read(property.valueType);
    }
  }
}

template <typename Source>
PolygonSoup readPlyBody(Source& source, const PlyHeader& header, const PlyFields& fields) {
  const int vertexCount = header.elements[fields.vertexElement].count;
  std::vector<Point> points;
  std::vector<std::vector<int>> polygons;
  for (int e = 0; e < static_cast<int>(header.elements.size()); ++e) {
    const PlyElement& element = header.elements[e];
    for (int i = 0; i < element.count; ++i) {
      source.beginRecord(element, i);
      if (e == fields.vertexElement) {
        points.push_back(readPlyVertex(source, element, fields.coordinates));
      } else if (e == fields.faceElement) {
        readPlyFace(source, element, i, fields.faceIndices, vertexCount, polygons);
      } else {
        skipPlyRecord(source, element);
      }
      source.endRecord();
    }
  }
  return {toPositions(points), std::move(polygons)};
}

PolygonSoup parsePly(const std::string& path, std::string_view bytes) {
  const PlyHeader header = parsePlyHeader(path, bytes);
  const PlyFields fields = findPlyFields(path, header);
  if (header.encoding == PlyEncoding::Ascii) {
    PlyAsciiSource source(path, bytes, header);
    return readPlyBody(source, header, fields);
  }
  PlyBinarySource source(path, bytes, header);
  return readPlyBody(source, header, fields);
}

// ---------------------------------------------------------------------------------------------
// STL: binary (80-byte header, uint32 triangle count, then per triangle 12 float32: normal and
// 3 vertices, and a uint16 attribute, all little-endian) or ascii ("solid NAME", facets of
// "facet normal nx ny nz / outer loop / vertex x y z (x3) / endloop / endfacet", "endsolid").
// STL repeats each vertex in every triangle; vertices with bit-identical coordinates are merged.

constexpr size_t kStlHeaderBytes = 84;
constexpr size_t kStlTriangleBytes = 50;

// Indexes points by their exact bit patterns, in first-occurrence order.
class VertexMerger {
 public:
  int indexOf(const Point& point) {
    Key key;
    std::memcpy(key.data(), point.data(), sizeof key);
    const auto [found, inserted] = indices_.try_emplace(key, static_cast<int>(points_.size()));
    if (inserted) points_.push_back(point);
    return found->second;
  }
  const std::vector<Point>& points() const { return points_; }

 private:
  using Key = std::array<uint64_t, 3>;
  struct KeyHash {
    size_t operator()(const Key& key) const {
      size_t hash = 0;
      for (uint64_t bits : key) hash = hash * 0x9E3779B97F4A7C15ull + std::hash<uint64_t>()(bits);
      return hash;
    }
  };
  std::unordered_map<Key, int, KeyHash> indices_;
  std::vector<Point> points_;
};

uint32_t littleEndianUint32(const char* data) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(data);
  return uint32_t{bytes[0]} | uint32_t{bytes[1]} << 8 | uint32_t{bytes[2]} << 16 |
         uint32_t{bytes[3]} << 24;
}

float littleEndianFloat(const char* data) {
  const uint32_t bits = littleEndianUint32(data);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

bool isBinaryStl(std::string_view bytes) {
  if (bytes.size() < kStlHeaderBytes) return false;
  const uint64_t triangles = littleEndianUint32(bytes.data() + 80);
  return bytes.size() == kStlHeaderBytes + kStlTriangleBytes * triangles;
}

PolygonSoup parseBinaryStl(std::string_view bytes) {
  const uint32_t triangles = littleEndianUint32(bytes.data() + 80);
  VertexMerger merger;
  std::vector<std::vector<int>> polygons;
  for (uint32_t t = 0; t < triangles; ++t) {
    // Skip the 12-byte facet normal: orientation comes from the vertex order.
    const char* vertexData = bytes.data() + kStlHeaderBytes + kStlTriangleBytes * t + 12;
    std::vector<int> triangle;
    for (int corner = 0; corner < 3; ++corner) {
      Point point;
      for (int k = 0; k < 3; ++k) point[k] = littleEndianFloat(vertexData + 4 * (3 * corner + k));
      triangle.push_back(merger.indexOf(point));
    }
    polygons.push_back(std::move(triangle));
  }
  return {toPositions(merger.points()), std::move(polygons)};
}

// A file that is neither: its size does not match a binary triangle count, and it does not
// start like ascii STL. Reports the binary reading, the likelier intent for such bytes.
[[noreturn]] void failUnrecognisedStl(const std::string& path, std::string_view bytes) {
  if (bytes.size() < kStlHeaderBytes) {
    fail({path, 1}, "not an STL file (no 'solid' line, and too short for binary STL)");
  }
  const uint64_t triangles = littleEndianUint32(bytes.data() + 80);
  fail({path, 80, true}, "binary STL announces " + std::to_string(triangles) + " triangles (" +
                             std::to_string(kStlHeaderBytes + kStlTriangleBytes * triangles) +
                             " bytes), but the file has " + std::to_string(bytes.size()) +
                             " bytes");
}

// Ascii STL, line by line; the state is where in the facet grammar the last line left off.
class AsciiStlParser {
 public:
  AsciiStlParser(const std::string& path, std::string_view text) : path_(path), lines_(text) {}

  PolygonSoup parse() {
    while (lines_.next()) {
      const auto words = splitWords(lines_.line());
      if (!words.empty()) parseLine(words);
    }
    if (state_ != State::OutsideSolid) fail("file ends inside a solid (missing 'endsolid')");
    return {toPositions(merger_.points()), std::move(polygons_)};
  }

 private:
  enum class State { OutsideSolid, InSolid, InFacet, InLoop, LoopClosed };

  void parseLine(const std::vector<std::string_view>& words) {
    const std::string_view keyword = words[0];
    if (keyword == "solid") {
      expect(State::OutsideSolid, keyword);
      state_ = State::InSolid;
    } else if (keyword == "facet") {
      expect(State::InSolid, keyword);
      if (words.size() != 5 || words[1] != "normal") fail("expected 'facet normal nx ny nz'");
      state_ = State::InFacet;
    } else if (keyword == "outer") {
      expect(State::InFacet, keyword);
      if (words.size() != 2 || words[1] != "loop") fail("expected 'outer loop'");
      state_ = State::InLoop;
      polygon_.clear();
    } else if (keyword == "vertex") {
      expect(State::InLoop, keyword);
      polygon_.push_back(merger_.indexOf(parseVertex(words)));
    } else if (keyword == "endloop") {
      expect(State::InLoop, keyword);
      if (polygon_.size() < 3) fail("a facet needs at least 3 vertices");
      state_ = State::LoopClosed;
    } else if (keyword == "endfacet") {
      expect(State::LoopClosed, keyword);
      polygons_.push_back(std::move(polygon_));
      polygon_.clear();
      state_ = State::InSolid;
    } else if (keyword == "endsolid") {
      expect(State::InSolid, keyword);
      state_ = State::OutsideSolid;
    } else {
      fail("unknown keyword " + quoted(keyword));
    }
  }

  Point parseVertex(const std::vector<std::string_view>& words) const {
    const Location at{path_, lines_.number()};
    if (words.size() != 4) fail("expected 'vertex x y z'");
    return {parseNumber(words[1], at), parseNumber(words[2], at), parseNumber(words[3], at)};
  }

  void expect(State state, std::string_view keyword) const {
    if (state_ != state) fail("unexpected " + quoted(keyword));
  }

  [[noreturn]] void fail(const std::string& problem) const {
    modeling::fail({path_, lines_.number()}, problem);
  }

  const std::string& path_;
  LineCursor lines_;
  State state_ = State::OutsideSolid;
  VertexMerger merger_;
  std::vector<int> polygon_;
  std::vector<std::vector<int>> polygons_;
};

bool startsWithSolid(std::string_view bytes) {
  const auto words = splitWords(bytes.substr(0, bytes.find('\n')));
  return !words.empty() && words[0] == "solid";
}

PolygonSoup parseStl(const std::string& path, std::string_view bytes) {
  if (isBinaryStl(bytes)) return parseBinaryStl(bytes);
  if (!startsWithSolid(bytes)) failUnrecognisedStl(path, bytes);
  return AsciiStlParser(path, bytes).parse();
}

}  // namespace

PolygonSoup readPolygonSoup(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path + ": is a directory, not a mesh file");
  const MeshFormat format = meshFormatOf(path);
  const std::string bytes = readFileBytes(path);
  if (bytes.empty()) throw InputError(path + ": the file is empty (0 bytes)");
  switch (format) {
    case MeshFormat::Obj:
      return parseObj(path, bytes);
    case MeshFormat::Off:
      return parseOff(path, bytes);
    case MeshFormat::Ply:
      return parsePly(path, bytes);
    case MeshFormat::Stl:
      return parseStl(path, bytes);
  }
  throw InputError(path + ": unknown mesh format");
}

}  // namespace flexure::modeling
