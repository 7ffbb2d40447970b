#include "optimize/contact/continuous_collision.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "modeling/errors.h"
#include "optimize/contact/primitive_distance.h"

namespace flexure::optimize {
namespace {

// The cap on the advancement's steps: each step but the last covers at least a tenth of
// (1 − s) d(0) / l, so the cap binds only when l > 1000 (1 − s) d(0).
constexpr int kMaxSteps = 10000;
// The advancement stops once the distance left above the gap is below this fraction of d(0) − g.
constexpr double kStopFraction = 0.1;

// The four points of a pair of primitives; the first `firstCount` belong to the first primitive.
struct MovingPair {
  std::array<Eigen::Vector3d, 4> x, dx;
  int firstCount;
};

template <class Distance>
double impactTime(const MovingPair& pair, double gapFraction, const Distance& distanceAt) {
  if (!(gapFraction > 0.0 && gapFraction < 1.0))
    throw InputError("continuous collision detection: the gap fraction must lie in (0, 1), not " +
                     numberText(gapFraction));
  const double rate = distanceRateBound(pair.dx, pair.firstCount);
  if (!std::isfinite(rate)) return 0.0;
  const double start = std::sqrt(distanceAt(0.0));
  if (!(start > 0.0)) return 0.0;
  if (rate == 0.0) return 1.0;
  const double gap = gapFraction * start, stop = kStopFraction * (start - gap);
  double t = 0.0, distance = start;
  for (int step = 0; step < kMaxSteps; ++step) {
    t += (distance - gap) / rate;
    if (t >= 1.0) return 1.0;
    distance = std::sqrt(distanceAt(t));
    if (distance - gap < stop) return t;
  }
  return t;
}

// The pair's positions at time t.
std::array<Eigen::Vector3d, 4> positionsAt(const MovingPair& pair, double t) {
  std::array<Eigen::Vector3d, 4> x;
  for (int i = 0; i < 4; ++i) x[i] = pair.x[i] + t * pair.dx[i];
  return x;
}

}  // namespace

double distanceRateBound(const std::array<Eigen::Vector3d, 4>& dx, int firstCount) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& d : dx) mean += 0.25 * d;
  double first = 0.0, second = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double speed = (dx[i] - mean).norm();
    double& largest = i < firstCount ? first : second;
    largest = std::max(largest, speed);
  }
  return first + second;
}

double pointTriangleImpactTime(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                               const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                               const Eigen::Vector3d& dp, const Eigen::Vector3d& dt0,
                               const Eigen::Vector3d& dt1, const Eigen::Vector3d& dt2,
                               double gapFraction) {
  const MovingPair pair{{p, t0, t1, t2}, {dp, dt0, dt1, dt2}, 1};
  return impactTime(pair, gapFraction, [&](double t) {
    const std::array<Eigen::Vector3d, 4> x = positionsAt(pair, t);
    return pointTriangleDistanceSquared(x[0], x[1], x[2], x[3]);
  });
}

double edgeEdgeImpactTime(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                          const Eigen::Vector3d& b0, const Eigen::Vector3d& b1,
                          const Eigen::Vector3d& da0, const Eigen::Vector3d& da1,
                          const Eigen::Vector3d& db0, const Eigen::Vector3d& db1,
                          double gapFraction) {
  const MovingPair pair{{a0, a1, b0, b1}, {da0, da1, db0, db1}, 2};
  return impactTime(pair, gapFraction, [&](double t) {
    const std::array<Eigen::Vector3d, 4> x = positionsAt(pair, t);
    return edgeEdgeDistanceSquared(x[0], x[1], x[2], x[3]);
  });
}

}  // namespace flexure::optimize
