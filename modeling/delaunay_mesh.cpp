// The irregular test mesh: CGAL Delaunay triangulation of a seeded Poisson-disk point set.
//
// Points. The 4n boundary vertices sit exactly 1/n apart on the sides, corners included. The
// interior points form a Poisson-disk sample: no two points (boundary ones included) closer than
// r = 0.72/n, none closer than d = 0.6/n to a side. Darts are uniform in the inner square
// [−1/2 + d, 1/2 − d]² and tested against a background grid of cell size just under r/√2, which
// holds at most one point per cell and finds every point within r of a dart in 5 × 5 cells.
// After 2 random darts per cell, one more dart goes into each of the 3 × 3 sub-cells of every
// empty cell (until one is kept). Then every point of the inner square lies within a sub-cell
// diagonal r/3 of a dart that had a sample point within r, so no empty disk of radius 4r/3 is
// left there: an interior triangle has edges ≥ r and circumradius R < 4r/3, so its angles are
// ≥ asin(r / 2R) > 22° (a fully maximal sample would give R < r and 30°).
//
// Constants. Measured over seeds, the mean edge length of these meshes is (1.00 ± 0.01)/n for
// r = 0.72/n (about 1.39 r), matching the boundary spacing; the smallest angle stays above 25°.
// d = 0.6/n keeps interior points off the sides yet close enough for well-shaped triangles on
// the boundary segments: a point at height d over the middle of a segment of length 1/n sees it
// under 80°, one over the segment's end makes a right triangle with angles 31° and 59°.
//
// Randomness. Uniform doubles are the top 53 bits of std::mt19937_64 draws, a sequence the
// standard fixes, so the same (n, seed) gives the same mesh bit for bit with any standard
// library. Faces come in a canonical order (each rotated to start at its smallest index, then
// sorted), independent of CGAL's storage order; interior vertices are sorted by (y, x).
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "modeling/errors.h"
#include "modeling/generators.h"

namespace flexure::modeling {

namespace {

constexpr double kRadius = 0.72;       // Poisson-disk radius r, × 1/n
constexpr double kSideGap = 0.6;       // least distance d of an interior point from a side, × 1/n
constexpr double kDartsPerCell = 2.0;  // random darts per background grid cell
constexpr int kGapSubdivision = 3;     // gap filling: darts per grid cell side

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using DataStructure =
    CGAL::Triangulation_data_structure_2<VertexBase, CGAL::Triangulation_face_base_2<Kernel>>;
using Triangulation = CGAL::Delaunay_triangulation_2<Kernel, DataStructure>;

struct Point2 {
  double x;
  double y;
};

double squaredDistance(Point2 a, Point2 b) {
  const double dx = a.x - b.x;
  const double dy = a.y - b.y;
  return dx * dx + dy * dy;
}

// Uniform double in [0, 1) from the top 53 bits of one 64-bit draw.
double uniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Points in the square [−1/2, 1/2]², at least r apart, with a background grid answering "is any
// point closer than r to p?". A cell's diagonal is just under r, so it holds at most one point,
// stored in place (NaN when empty, which no distance test accepts); the points within r of p lie
// in the 5 × 5 cells around p's cell.
class DiskSample {
 public:
  explicit DiskSample(double radius)
      : radius_(radius),
        cellSize_(radius / std::sqrt(2.0) * (1.0 - 1e-9)),
        cellsPerSide_(static_cast<int>(std::ceil(1.0 / cellSize_))),
        cells_(static_cast<std::size_t>(cellsPerSide_) * cellsPerSide_,
               Point2{std::numeric_limits<double>::quiet_NaN(),
                      std::numeric_limits<double>::quiet_NaN()}) {}

  int cellsPerSide() const { return cellsPerSide_; }
  const std::vector<Point2>& points() const { return points_; }

  bool isFree(Point2 p) const { return nearPoint(p) == nullptr; }

  // A point closer than r to p, or nullptr.
  const Point2* nearPoint(Point2 p) const {
    const int ci = cellIndex(p.x);
    const int cj = cellIndex(p.y);
    const double r2 = radius_ * radius_;
    const int iBegin = std::max(ci - 2, 0);
    const int iEnd = std::min(ci + 2, cellsPerSide_ - 1);
    for (int j = std::max(cj - 2, 0); j <= std::min(cj + 2, cellsPerSide_ - 1); ++j) {
      const Point2* row = &cells_[static_cast<std::size_t>(j) * cellsPerSide_];
      for (int i = iBegin; i <= iEnd; ++i) {
        if (squaredDistance(row[i], p) < r2) return &row[i];
      }
    }
    return nullptr;
  }

  // Throws one dart into each of the m × m sub-cells of every empty cell, restricted to the
  // square [low, high]², and stops at a cell's first hit. Afterwards every point of the square
  // lies within a sub-cell diagonal of a dart that was either kept or had a point within r.
  void fillGaps(double low, double high, int m, std::mt19937_64& rng) {
    const double sub = cellSize_ / m;
    for (int cj = 0; cj < cellsPerSide_; ++cj) {
      for (int ci = 0; ci < cellsPerSide_; ++ci) {
        if (!std::isnan(cells_[static_cast<std::size_t>(cj) * cellsPerSide_ + ci].x)) continue;
        const double x0 = -0.5 + ci * cellSize_;
        const double y0 = -0.5 + cj * cellSize_;
        bool filled = false;
        // The point that rejected the last dart usually rejects the next one too.
        Point2 blocker = cells_[static_cast<std::size_t>(cj) * cellsPerSide_ + ci];
        for (int b = 0; b < m && !filled; ++b) {
          const double yLow = std::max(y0 + b * sub, low);
          const double yHigh = std::min(y0 + (b + 1) * sub, high);
          if (yLow >= yHigh) continue;
          for (int a = 0; a < m && !filled; ++a) {
            const double xLow = std::max(x0 + a * sub, low);
            const double xHigh = std::min(x0 + (a + 1) * sub, high);
            if (xLow >= xHigh) continue;
            const Point2 p{xLow + (xHigh - xLow) * uniform(rng),
                           yLow + (yHigh - yLow) * uniform(rng)};
            if (squaredDistance(blocker, p) < radius_ * radius_) continue;
            if (const Point2* near = nearPoint(p)) {
              blocker = *near;
            } else {
              add(p);
              filled = true;
            }
          }
        }
      }
    }
  }

  // p must be free or at least r from every point already added.
  void add(Point2 p) {
    cells_[static_cast<std::size_t>(cellIndex(p.y)) * cellsPerSide_ + cellIndex(p.x)] = p;
    points_.push_back(p);
  }

 private:
  int cellIndex(double coordinate) const {
    const int c = static_cast<int>(std::floor((coordinate + 0.5) / cellSize_));
    return std::clamp(c, 0, cellsPerSide_ - 1);
  }

  double radius_;
  double cellSize_;
  int cellsPerSide_;
  std::vector<Point2> cells_;
  std::vector<Point2> points_;
};

// The 4n boundary points, counter-clockwise from the corner (−1/2, −1/2).
std::vector<Point2> boundaryPoints(int n) {
  std::vector<Point2> points;
  points.reserve(4 * static_cast<std::size_t>(n));
  const auto at = [n](int i) { return static_cast<double>(i) / n; };
  for (int i = 0; i < n; ++i) points.push_back({-0.5 + at(i), -0.5});
  for (int i = 0; i < n; ++i) points.push_back({0.5, -0.5 + at(i)});
  for (int i = 0; i < n; ++i) points.push_back({0.5 - at(i), 0.5});
  for (int i = 0; i < n; ++i) points.push_back({-0.5, 0.5 - at(i)});
  return points;
}

// Interior Poisson-disk points (see the file comment), sorted by (y, x).
std::vector<Point2> interiorPoints(int n, std::uint64_t seed, const std::vector<Point2>& boundary) {
  const double radius = kRadius / n;
  const double low = -0.5 + kSideGap / n;
  const double width = 1.0 - 2.0 * kSideGap / n;
  if (width <= 0.0) return {};

  DiskSample sample(radius);
  for (const Point2& p : boundary) sample.add(p);

  std::mt19937_64 rng(seed);
  const double darts = kDartsPerCell * static_cast<double>(sample.cellsPerSide()) *
                       sample.cellsPerSide() * width * width;
  for (std::int64_t k = 0; k < static_cast<std::int64_t>(darts); ++k) {
    const double x = low + width * uniform(rng);
    const Point2 p{x, low + width * uniform(rng)};
    if (sample.isFree(p)) sample.add(p);
  }
  sample.fillGaps(low, low + width, kGapSubdivision, rng);
  std::vector<Point2> interior(
      sample.points().begin() + static_cast<std::ptrdiff_t>(boundary.size()),
      sample.points().end());
  std::sort(interior.begin(), interior.end(),
            [](const Point2& a, const Point2& b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
  return interior;
}

}  // namespace

Mesh delaunayMesh(int n, std::uint64_t seed) {
  if (n < 1) throw InputError("delaunay: n must be at least 1, got " + std::to_string(n));
  std::vector<Point2> points = boundaryPoints(n);
  const std::vector<Point2> interior = interiorPoints(n, seed, points);
  points.insert(points.end(), interior.begin(), interior.end());

  std::vector<std::pair<Kernel::Point_2, int>> input;
  input.reserve(points.size());
  for (std::size_t v = 0; v < points.size(); ++v) {
    input.emplace_back(Kernel::Point_2(points[v].x, points[v].y), static_cast<int>(v));
  }
  Triangulation triangulation;
  triangulation.insert(input.begin(), input.end());

  // CGAL stores finite faces counter-clockwise.
  std::vector<std::array<int, 3>> faces;
  faces.reserve(triangulation.number_of_faces());
  for (auto face = triangulation.finite_faces_begin(); face != triangulation.finite_faces_end();
       ++face) {
    std::array<int, 3> f = {face->vertex(0)->info(), face->vertex(1)->info(),
                            face->vertex(2)->info()};
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    faces.push_back(f);
  }
  std::sort(faces.begin(), faces.end());

  Mesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t v = 0; v < points.size(); ++v) {
    mesh.positions.row(static_cast<Eigen::Index>(v)) << points[v].x, points[v].y, 0.0;
  }
  mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    mesh.triangles.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  }
  return mesh;
}

}  // namespace flexure::modeling
