#include "optimize/contact/broad_phase.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "modeling/errors.h"

namespace flexure::optimize {
namespace {

// A closed axis-aligned box.
struct Box {
  std::array<double, 3> low, high;
};

// Whether two boxes overlap (true along an axis with an undefined coordinate).
bool overlap(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (a.low[k] > b.high[k] || b.low[k] > a.high[k]) return false;
  return true;
}

bool finite(const Box& box) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(box.low[k]) || !std::isfinite(box.high[k])) return false;
  return true;
}

void checkInput(const Eigen::Ref<const modeling::Positions>& x,
                const Eigen::Ref<const modeling::Positions>& dx, const modeling::Triangles& faces,
                const modeling::IndexPairs& edges, double inflation) {
  if (dx.rows() != 0 && dx.rows() != x.rows())
    throw InputError("contact candidates: the displacements have " + std::to_string(dx.rows()) +
                     " rows for " + std::to_string(x.rows()) + " vertices");
  if (!(inflation >= 0.0))
    throw InputError("contact candidates: the inflation must be ≥ 0, not " + numberText(inflation));
  const int n = static_cast<int>(x.rows());
  const bool inRange = (faces.size() == 0 || (faces.minCoeff() >= 0 && faces.maxCoeff() < n)) &&
                       (edges.size() == 0 || (edges.minCoeff() >= 0 && edges.maxCoeff() < n));
  if (!inRange)
    throw InputError("contact candidates: a face or edge names a vertex outside 0.." +
                     std::to_string(n - 1));
}

// The box of the vertices `vertices` at both ends of the motion, inflated on every side.
template <int N>
Box motionBox(const Eigen::Ref<const modeling::Positions>& x,
              const Eigen::Ref<const modeling::Positions>& dx, const int* vertices,
              double inflation) {
  Box box;
  box.low.fill(std::numeric_limits<double>::infinity());
  box.high.fill(-std::numeric_limits<double>::infinity());
  for (int i = 0; i < N; ++i)
    for (int k = 0; k < 3; ++k) {
      const double start = x(vertices[i], k);
      const double end = dx.rows() == 0 ? start : start + dx(vertices[i], k);
      box.low[k] = std::min({box.low[k], start, end});
      box.high[k] = std::max({box.high[k], start, end});
    }
  for (int k = 0; k < 3; ++k) box.low[k] -= inflation, box.high[k] += inflation;
  return box;
}

// The motion boxes of the rows of `primitives` (faces: N = 3, edges: N = 2; row-major indices).
template <int N, class Rows>
std::vector<Box> motionBoxes(const Eigen::Ref<const modeling::Positions>& x,
                             const Eigen::Ref<const modeling::Positions>& dx,
                             const Rows& primitives, double inflation) {
  std::vector<Box> boxes(primitives.rows());
  for (Eigen::Index k = 0; k < primitives.rows(); ++k)
    boxes[k] = motionBox<N>(x, dx, primitives.row(k).data(), inflation);
  return boxes;
}

bool shareVertex(const int* a, int aCount, const int* b, int bCount) {
  for (int i = 0; i < aCount; ++i)
    for (int j = 0; j < bCount; ++j)
      if (a[i] == b[j]) return true;
  return false;
}

// A uniform grid listing each finite box of a set in every cell it overlaps (spatial subdivision,
// Teschner et al. 2003, "Optimized spatial hashing for collision detection of deformable
// objects", here with a dense cell array over the boxes' extent). The cell edge is twice the
// boxes' mean largest side, enlarged until there are at most kCellsPerBox cells per box, so a box
// spans a few cells and a cell holds a few boxes: listing and querying are O(n) for boxes of
// similar size. Two overlapping boxes meet in exactly one reference cell, the cell of the largest
// corner of their lower corners (it lies in both boxes), which reports the pair once.
class BoxGrid {
 public:
  explicit BoxGrid(const std::vector<Box>& boxes) : boxes_(boxes) {
    chooseCells();
    std::vector<int> count(cellCount() + 1, 0);
    forEachListing([&](int, int c) { ++count[c + 1]; });
    for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
    cellStart_ = count;
    listed_.resize(count.back());
    listedBoxes_.resize(count.back());
    forEachListing([&](int b, int c) {
      listedBoxes_[count[c]] = boxes_[b];
      listed_[count[c]++] = b;
    });
    for (int b = 0; b < static_cast<int>(boxes_.size()); ++b)
      if (!finite(boxes_[b])) unlisted_.push_back(b);
  }

  // The boxes with an infinite or undefined coordinate, which no cell lists.
  const std::vector<int>& unlisted() const { return unlisted_; }

  // Calls report(j) once for every listed box j > after overlapping `box` (finite) for which
  // wanted(j).
  template <class Wanted, class Report>
  void query(const Box& box, int after, const Wanted& wanted, const Report& report) const {
    const std::array<int, 3> low = cellOf(box.low), high = cellOf(box.high);
    for (int i = low[0]; i <= high[0]; ++i)
      for (int j = low[1]; j <= high[1]; ++j)
        for (int k = low[2]; k <= high[2]; ++k) {
          const int c = index({i, j, k});
          // A cell lists its boxes in increasing order: those > after are its last.
          for (int e = cellStart_[c + 1] - 1; e >= cellStart_[c] && listed_[e] > after; --e) {
            const int b = listed_[e];
            if (overlap(box, listedBoxes_[e]) && wanted(b) &&
                isReferenceCell(box, listedBoxes_[e], {i, j, k}))
              report(b);
          }
        }
  }

 private:
  static constexpr int kCellsPerBox = 4;
  // The cell edge over the boxes' mean largest side (measured: 1 to 3 cost within 25 %, 2 least).
  static constexpr double kCellPerSide = 2.0;

  void chooseCells() {
    low_.fill(std::numeric_limits<double>::infinity());
    std::array<double, 3> high;
    high.fill(-std::numeric_limits<double>::infinity());
    double side = 0.0;
    int finiteCount = 0;
    for (const Box& box : boxes_) {
      if (!finite(box)) continue;
      ++finiteCount;
      double largest = 0.0;
      for (int k = 0; k < 3; ++k) {
        low_[k] = std::min(low_[k], box.low[k]), high[k] = std::max(high[k], box.high[k]);
        largest = std::max(largest, box.high[k] - box.low[k]);
      }
      side += largest;
    }
    cell_ = finiteCount == 0 ? 1.0 : kCellPerSide * side / finiteCount;
    for (int k = 0; k < 3; ++k) cell_ = std::max(cell_, (high[k] - low_[k]) * 1e-6);
    if (!(cell_ > 0.0)) cell_ = 1.0;
    const double limit = kCellsPerBox * std::max(finiteCount, 1);
    for (;;) {
      double cells = 1.0;
      for (int k = 0; k < 3; ++k) {
        size_[k] = finiteCount == 0 ? 1 : static_cast<int>((high[k] - low_[k]) / cell_) + 1;
        cells *= size_[k];
      }
      if (cells <= limit) break;
      cell_ *= std::cbrt(cells / limit) * 1.01;
    }
    inverseCell_ = 1.0 / cell_;
  }

  int cellCount() const { return size_[0] * size_[1] * size_[2]; }
  int index(const std::array<int, 3>& c) const {
    return c[0] + size_[0] * (c[1] + size_[1] * c[2]);
  }

  std::array<int, 3> cellOf(const std::array<double, 3>& p) const {
    std::array<int, 3> c;
    for (int k = 0; k < 3; ++k) {
      const double t = std::floor((p[k] - low_[k]) * inverseCell_);
      c[k] = static_cast<int>(std::clamp(t, 0.0, double(size_[k] - 1)));
    }
    return c;
  }

  bool isReferenceCell(const Box& a, const Box& b, const std::array<int, 3>& cell) const {
    std::array<double, 3> corner;
    for (int k = 0; k < 3; ++k) corner[k] = std::max(a.low[k], b.low[k]);
    return cellOf(corner) == cell;
  }

  // Calls list(box, cell) for every finite box and every cell it overlaps.
  template <class List>
  void forEachListing(const List& list) const {
    for (int b = 0; b < static_cast<int>(boxes_.size()); ++b) {
      if (!finite(boxes_[b])) continue;
      const std::array<int, 3> low = cellOf(boxes_[b].low), high = cellOf(boxes_[b].high);
      for (int i = low[0]; i <= high[0]; ++i)
        for (int j = low[1]; j <= high[1]; ++j)
          for (int k = low[2]; k <= high[2]; ++k) list(b, index({i, j, k}));
    }
  }

  const std::vector<Box>& boxes_;
  std::array<double, 3> low_;
  std::array<int, 3> size_ = {1, 1, 1};
  double cell_ = 1.0, inverseCell_ = 1.0;
  std::vector<int> cellStart_, listed_, unlisted_;
  std::vector<Box>
      listedBoxes_;  // listed_'s boxes, in its order (a cell's scan reads them in a row)
};

// Calls report(b) once for every box b > after of `boxes` (listed in `grid`) overlapping `box` for
// which wanted(b): through the grid for a finite box; by testing them all for the boxes with an
// infinite or undefined coordinate, which the grid does not list (an undefined one overlaps every
// box: the broad phase errs on the side of more candidates).
template <class Wanted, class Report>
void overlapping(const BoxGrid& grid, const std::vector<Box>& boxes, const Box& box, int after,
                 const Wanted& wanted, const Report& report) {
  if (!finite(box)) {
    for (int b = after + 1; b < static_cast<int>(boxes.size()); ++b)
      if (overlap(box, boxes[b]) && wanted(b)) report(b);
    return;
  }
  grid.query(box, after, wanted, report);
  for (const int b : grid.unlisted())
    if (b > after && overlap(box, boxes[b]) && wanted(b)) report(b);
}

}  // namespace

CandidatePairs contactCandidates(const Eigen::Ref<const modeling::Positions>& x,
                                 const Eigen::Ref<const modeling::Positions>& dx,
                                 const modeling::Triangles& faces,
                                 const modeling::IndexPairs& edges, double inflation) {
  checkInput(x, dx, faces, edges, inflation);
  const std::vector<Box> faceBoxes = motionBoxes<3>(x, dx, faces, inflation);
  const std::vector<Box> edgeBoxes = motionBoxes<2>(x, dx, edges, inflation);

  // Each vertex's and each edge's pairs are found together and sorted among themselves: the
  // lists come out sorted.
  CandidatePairs pairs;
  const BoxGrid faceGrid(faceBoxes);
  for (int v = 0; v < x.rows(); ++v) {
    const std::size_t first = pairs.vertexFace.size();
    overlapping(
        faceGrid, faceBoxes, motionBox<1>(x, dx, &v, inflation), -1,
        [&](int f) { return !shareVertex(&v, 1, faces.row(f).data(), 3); },
        [&](int f) {
          pairs.vertexFace.push_back({v, f});
        });
    std::sort(pairs.vertexFace.begin() + first, pairs.vertexFace.end());
  }
  const BoxGrid edgeGrid(edgeBoxes);
  for (int e = 0; e < edges.rows(); ++e) {
    const std::size_t first = pairs.edgeEdge.size();
    overlapping(
        edgeGrid, edgeBoxes, edgeBoxes[e], e,
        [&](int g) { return !shareVertex(edges.row(e).data(), 2, edges.row(g).data(), 2); },
        [&](int g) {
          pairs.edgeEdge.push_back({e, g});
        });
    std::sort(pairs.edgeEdge.begin() + first, pairs.edgeEdge.end());
  }
  return pairs;
}

CandidatePairs contactCandidatesAmong(const Eigen::Ref<const modeling::Positions>& x,
                                      const Eigen::Ref<const modeling::Positions>& dx,
                                      const modeling::Triangles& faces,
                                      const modeling::IndexPairs& edges, double inflation,
                                      const std::vector<bool>& among) {
  checkInput(x, dx, faces, edges, inflation);
  if (among.size() != static_cast<std::size_t>(x.rows()))
    throw InputError("contact candidates: " + std::to_string(among.size()) + " vertex flags for " +
                     std::to_string(x.rows()) + " vertices");
  const auto touches = [&](const auto& row) {
    for (Eigen::Index i = 0; i < row.size(); ++i)
      if (among[row[i]]) return true;
    return false;
  };
  const std::vector<Box> faceBoxes = motionBoxes<3>(x, dx, faces, inflation);
  const std::vector<Box> edgeBoxes = motionBoxes<2>(x, dx, edges, inflation);
  std::vector<Box> vertexBoxes(x.rows());
  for (int v = 0; v < x.rows(); ++v) vertexBoxes[v] = motionBox<1>(x, dx, &v, inflation);

  // Vertex–face: a vertex of `among` against every face, then every other vertex against the
  // faces that touch `among` (found from those faces' side).
  CandidatePairs pairs;
  const BoxGrid faceGrid(faceBoxes), vertexGrid(vertexBoxes);
  for (int v = 0; v < x.rows(); ++v)
    if (among[v])
      overlapping(
          faceGrid, faceBoxes, vertexBoxes[v], -1,
          [&](int f) { return !shareVertex(&v, 1, faces.row(f).data(), 3); },
          [&](int f) {
            pairs.vertexFace.push_back({v, f});
          });
  for (int f = 0; f < faces.rows(); ++f)
    if (touches(faces.row(f)))
      overlapping(
          vertexGrid, vertexBoxes, faceBoxes[f], -1,
          [&](int v) { return !among[v] && !shareVertex(&v, 1, faces.row(f).data(), 3); },
          [&](int v) {
            pairs.vertexFace.push_back({v, f});
          });
  // Edge–edge: each edge touching `among` against every edge, a pair of two such edges once.
  const BoxGrid edgeGrid(edgeBoxes);
  for (int e = 0; e < edges.rows(); ++e)
    if (touches(edges.row(e)))
      overlapping(
          edgeGrid, edgeBoxes, edgeBoxes[e], -1,
          [&](int g) {
            return (g > e || !touches(edges.row(g))) &&
                   !shareVertex(edges.row(e).data(), 2, edges.row(g).data(), 2);
          },
          [&](int g) {
            pairs.edgeEdge.push_back({std::min(e, g), std::max(e, g)});
          });
  std::sort(pairs.vertexFace.begin(), pairs.vertexFace.end());
  std::sort(pairs.edgeEdge.begin(), pairs.edgeEdge.end());
  return pairs;
}

}  // namespace flexure::optimize
