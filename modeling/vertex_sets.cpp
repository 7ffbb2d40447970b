#include "modeling/vertex_sets.h"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>

#include "modeling/errors.h"

namespace flexure::modeling {

std::vector<bool> readVertexSet(const std::string& path, int vertexCount, std::string_view what) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the " + std::string(what));
  std::vector<bool> set(vertexCount, false);
  std::string line;
  for (int lineNumber = 1; std::getline(in, line); ++lineNumber) {
    line = line.substr(0, line.find('#'));
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream words(line);
    std::string word;
    while (words >> word) {
      int v = -1;
      const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), v);
      if (error != std::errc() || end != word.data() + word.size()) {
        throw InputError(path + ": line " + std::to_string(lineNumber) + ": '" + word +
                         "' is not a vertex index");
      }
      if (v < 0 || v >= vertexCount) {
        throw InputError(path + ": line " + std::to_string(lineNumber) + ": vertex " + word +
                         " is out of range (the mesh has " + std::to_string(vertexCount) + ")");
      }
      set[v] = true;
    }
  }
  return set;
}

std::vector<bool> verticesInSphere(const Positions& positions, const Eigen::Vector3d& centre,
                                   double radius) {
  std::vector<bool> set(positions.rows(), false);
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    set[v] = (positions.row(v).transpose() - centre).norm() <= radius;
  return set;
}

int countVertices(const std::vector<bool>& set) {
  return static_cast<int>(std::count(set.begin(), set.end(), true));
}

}  // namespace flexure::modeling
