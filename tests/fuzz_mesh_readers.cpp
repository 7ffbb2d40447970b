// A seeded mutation fuzz loop over every mesh reader (OBJ, OFF, PLY ASCII and binary, STL ASCII and
// binary): each valid seed file is mutated (bytes flipped, inserted, deleted, duplicated, numbers
// replaced by extreme ones, the file cut short) and read. Every input must either read or be
// rejected with InputError (the exit-2 path): any other exception fails the test, a crash or a
// hang fails the CTest run (its timeout). Fixed seeds keep the inputs the same on every run.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "modeling/errors.h"
#include "modeling/mesh_io.h"

namespace flexure::modeling {
namespace {

namespace fs = std::filesystem;

constexpr int kInputsPerFormat = 2000;

// The unit square as two triangles; a third triangle and vertex so that faces share an edge.
const float kPoints[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 1.5f, 0.2f}};
const int kTriangles[3][3] = {{0, 1, 2}, {0, 2, 3}, {3, 2, 4}};

std::string asciiSeed(const std::string& format) {
  std::string text;
  if (format == "obj") {
    text = "# seed\n";
    for (const auto& p : kPoints)
      text += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " +
              std::to_string(p[2]) + "\n";
    for (const auto& t : kTriangles)
      text += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + "/1 " +
              std::to_string(t[2] + 1) + "//2\n";
  } else if (format == "off") {
    text = "OFF\n5 3 0\n";
    for (const auto& p : kPoints)
      text += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
    for (const auto& t : kTriangles)
      text += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " +
              std::to_string(t[2]) + "\n";
  } else if (format == "ply") {
    text =
        "ply\nformat ascii 1.0\ncomment seed\nelement vertex 5\nproperty float x\nproperty float "
        "y\nproperty float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& p : kPoints)
      text += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
    for (const auto& t : kTriangles)
      text += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " +
              std::to_string(t[2]) + "\n";
  } else {  // stl
    text = "solid seed\n";
    for (const auto& t : kTriangles) {
      text += "facet normal 0 0 1\nouter loop\n";
      for (int k = 0; k < 3; ++k) {
        const float* p = kPoints[t[k]];
        text += "vertex " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " +
                std::to_string(p[2]) + "\n";
      }
      text += "endloop\nendfacet\n";
    }
    text += "endsolid seed\n";
  }
  return text;
}

template <typename T>
void append(std::string& bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  bytes.append(raw, sizeof(T));
}

std::string binaryPlySeed() {
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\nproperty float "
      "y\nproperty float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : kPoints)
    for (float c : p) append(bytes, c);
  for (const auto& t : kTriangles) {
    append(bytes, static_cast<std::uint8_t>(3));
    for (int v : t) append(bytes, static_cast<std::int32_t>(v));
  }
  return bytes;
}

std::string binaryStlSeed() {
  std::string bytes(80, ' ');
  bytes.replace(0, 11, "binary seed");
  append(bytes, static_cast<std::uint32_t>(3));
  for (const auto& t : kTriangles) {
    for (int k = 0; k < 3; ++k) append(bytes, k == 2 ? 1.0f : 0.0f);  // normal
    for (int v : t)
      for (float c : kPoints[v]) append(bytes, c);
    append(bytes, static_cast<std::uint16_t>(0));
  }
  return bytes;
}

// One random edit of `bytes`.
void mutate(std::string& bytes, std::mt19937_64& random) {
  static const char* const kTokens[] = {"-1",
                                        "0",
                                        "4294967296",
                                        "99999999999",
                                        "nan",
                                        "inf",
                                        "1e308",
                                        "-0",
                                        "\n",
                                        " ",
                                        "#",
                                        "3 0 0 0",
                                        "f",
                                        "v",
                                        "element",
                                        "end_header\n",
                                        "property list uchar int x\n"};
  const auto pick = [&](std::size_t n) {
    return n == 0 ? std::size_t{0} : std::uniform_int_distribution<std::size_t>(0, n - 1)(random);
  };
  const std::size_t at = pick(bytes.size() + 1);
  switch (pick(7)) {
    case 0:  // flip a byte
      if (!bytes.empty()) bytes[pick(bytes.size())] = static_cast<char>(pick(256));
      break;
    case 1:  // insert random bytes
      bytes.insert(at, std::string(1 + pick(4), static_cast<char>(pick(256))));
      break;
    case 2:  // delete a range
      bytes.erase(at, 1 + pick(16));
      break;
    case 3:  // duplicate a range
      bytes.insert(at, bytes.substr(pick(bytes.size() + 1), 1 + pick(32)));
      break;
    case 4:  // cut the file short
      bytes.resize(at);
      break;
    case 5: {  // replace a digit by an extreme number or a keyword
      const std::size_t digit = bytes.find_first_of("0123456789", at);
      const std::string token = kTokens[pick(std::size(kTokens))];
      if (digit != std::string::npos) {
        bytes.replace(digit, 1, token);
      } else {
        bytes.insert(at, token);
      }
      break;
    }
    default:  // overwrite four bytes with an extreme 32-bit value (binary counts and indices)
      if (bytes.size() >= 4) {
        const std::uint32_t values[] = {0u, 0xffffffffu, 0x7fffffffu, 0x80000000u, 1000000000u};
        const std::uint32_t v = values[pick(std::size(values))];
        std::memcpy(&bytes[pick(bytes.size() - 3)], &v, 4);
      }
  }
}

void fuzz(const std::string& name, const std::string& extension, const std::string& seed,
          std::uint64_t randomSeed) {
  const fs::path dir = fs::path(FLEXURE_TEST_TMP) / "fuzz_mesh_readers";
  fs::create_directories(dir);
  const std::string path = (dir / (name + "." + extension)).string();
  std::mt19937_64 random(randomSeed);
  int read = 0, rejected = 0;
  for (int k = 0; k < kInputsPerFormat; ++k) {
    std::string bytes = seed;
    const int edits = 1 + static_cast<int>(random() % 4);
    for (int e = 0; e < edits; ++e) mutate(bytes, random);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    try {
      readMesh(path);
      ++read;
    } catch (const InputError&) {
      ++rejected;
    } catch (const std::exception& e) {
      // Keep the input for a reproduction.
      std::ofstream(path + ".failing", std::ios::binary) << bytes;
      FAIL() << name << " input " << k << " (kept as " << path << ".failing) threw "
             << typeid(e).name() << ": " << e.what();
    }
  }
  std::printf("%s: %d inputs read, %d rejected\n", name.c_str(), read, rejected);
  // The loop must exercise both outcomes, or the mutations are too weak or too strong.
  EXPECT_GT(read, 0) << name;
  EXPECT_GT(rejected, kInputsPerFormat / 10) << name;
}

TEST(FuzzMeshReaders, Obj) {
  fuzz("obj", "obj", asciiSeed("obj"), 1);
}
TEST(FuzzMeshReaders, Off) {
  fuzz("off", "off", asciiSeed("off"), 2);
}
TEST(FuzzMeshReaders, PlyAscii) {
  fuzz("ply-ascii", "ply", asciiSeed("ply"), 3);
}
TEST(FuzzMeshReaders, PlyBinary) {
  fuzz("ply-binary", "ply", binaryPlySeed(), 4);
}
TEST(FuzzMeshReaders, StlAscii) {
  fuzz("stl-ascii", "stl", asciiSeed("stl"), 5);
}
TEST(FuzzMeshReaders, StlBinary) {
  fuzz("stl-binary", "stl", binaryStlSeed(), 6);
}

}  // namespace
}  // namespace flexure::modeling
