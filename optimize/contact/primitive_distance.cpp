#include "optimize/contact/primitive_distance.h"

#include <array>

#include "curvature/second_order_jet.h"

namespace flexure::optimize {
namespace {

using curvature::SecondOrderJet;

template <class T>
using Point = std::array<T, 3>;

template <class T>
Point<T> minus(const Point<T>& a, const Point<T>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <class T>
T dot(const Point<T>& a, const Point<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class T>
Point<T> cross(const Point<T>& a, const Point<T>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double valueOf(double x) {
  return x;
}
template <int N>
double valueOf(const SecondOrderJet<N>& x) {
  return x.a;
}

// The closed forms, each over the points it reads (the distance types of the header).
struct PointPoint {  // (p, q)
  static constexpr int kPoints = 2;
  template <class T>
  T operator()(const std::array<Point<T>, 2>& x) const {
    const Point<T> d = minus(x[0], x[1]);
    return dot(d, d);
  }
};
struct PointEdge {  // (p, e0, e1)
  static constexpr int kPoints = 3;
  template <class T>
  T operator()(const std::array<Point<T>, 3>& x) const {
    const Point<T> n = cross(minus(x[1], x[0]), minus(x[2], x[0]));
    const Point<T> e = minus(x[2], x[1]);
    return dot(n, n) / dot(e, e);
  }
};
struct PointPlane {  // (p, t0, t1, t2)
  static constexpr int kPoints = 4;
  template <class T>
  T operator()(const std::array<Point<T>, 4>& x) const {
    const Point<T> n = cross(minus(x[2], x[1]), minus(x[3], x[1]));
    const T h = dot(minus(x[0], x[1]), n);
    return h * h / dot(n, n);
  }
};
struct LineLine {  // (a0, a1, b0, b1)
  static constexpr int kPoints = 4;
  template <class T>
  T operator()(const std::array<Point<T>, 4>& x) const {
    const Point<T> n = cross(minus(x[1], x[0]), minus(x[3], x[2]));
    const T h = dot(minus(x[2], x[0]), n);
    return h * h / dot(n, n);
  }
};
// m(c) with c = |(a1 − a0) × (b1 − b0)|² over (a0, a1, b0, b1).
struct Mollifier {
  static constexpr int kPoints = 4;
  double threshold;
  template <class T>
  T operator()(const std::array<Point<T>, 4>& x) const {
    const Point<T> n = cross(minus(x[1], x[0]), minus(x[3], x[2]));
    const T c = dot(n, n);
    if (valueOf(c) >= threshold) return T(1.0);
    const T r = c / threshold;
    return (2.0 - r) * r;
  }
};

// A formula over the arguments `slots` (indices into the four arguments, in the formula's
// order); its derivatives, by second-order jets, scattered into the 12 unknowns.
template <class Formula>
double evaluate(const Formula& formula, const std::array<const Eigen::Vector3d*, 4>& arguments,
                const std::array<int, Formula::kPoints>& slots, Vector12* gradient,
                Matrix12* hessian) {
  constexpr int K = Formula::kPoints;
  if (gradient == nullptr && hessian == nullptr) {
    std::array<Point<double>, K> x;
    for (int k = 0; k < K; ++k)
      for (int c = 0; c < 3; ++c) x[k][c] = (*arguments[slots[k]])[c];
    return formula(x);
  }
  using Jet = SecondOrderJet<3 * K>;
  std::array<Point<Jet>, K> x;
  for (int k = 0; k < K; ++k)
    for (int c = 0; c < 3; ++c) x[k][c] = Jet::variable((*arguments[slots[k]])[c], 3 * k + c);
  const Jet f = formula(x);
  const auto unknown = [&](int i) { return 3 * slots[i / 3] + i % 3; };
  if (gradient != nullptr) {
    gradient->setZero();
    for (int i = 0; i < 3 * K; ++i) (*gradient)[unknown(i)] = f.v[i];
  }
  if (hessian != nullptr) {
    hessian->setZero();
    for (int i = 0; i < 3 * K; ++i)
      for (int j = 0; j < 3 * K; ++j) (*hessian)(unknown(i), unknown(j)) = f.hessian(i, j);
  }
  return f.a;
}

// Which closed form is active, and on which arguments.
enum class DistanceType { PointPoint, PointEdge, PointPlane, LineLine };
struct ActiveType {
  DistanceType type;
  std::array<int, 4> slots;  // the first 2, 3 or 4 are read
};

double evaluateType(const ActiveType& active,
                    const std::array<const Eigen::Vector3d*, 4>& arguments, Vector12* gradient,
                    Matrix12* hessian) {
  const std::array<int, 4>& s = active.slots;
  switch (active.type) {
    case DistanceType::PointPoint:
      return evaluate(PointPoint{}, arguments, {s[0], s[1]}, gradient, hessian);
    case DistanceType::PointEdge:
      return evaluate(PointEdge{}, arguments, {s[0], s[1], s[2]}, gradient, hessian);
    case DistanceType::PointPlane:
      return evaluate(PointPlane{}, arguments, s, gradient, hessian);
    case DistanceType::LineLine:
      break;
  }
  return evaluate(LineLine{}, arguments, s, gradient, hessian);
}

// The closest feature of the triangle (t0, t1, t2) to p, by the Voronoi regions of its vertices
// and edges (Ericson, "Real-Time Collision Detection", 2005, §5.1.5); p is argument 0, t_i
// argument i + 1.
ActiveType pointTriangleType(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a;
  const double d1 = ab.dot(p - a), d2 = ac.dot(p - a);
  if (d1 <= 0.0 && d2 <= 0.0) return {DistanceType::PointPoint, {0, 1}};
  const double d3 = ab.dot(p - b), d4 = ac.dot(p - b);
  if (d3 >= 0.0 && d4 <= d3) return {DistanceType::PointPoint, {0, 2}};
  if (d1 * d4 - d3 * d2 <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
    return {DistanceType::PointEdge, {0, 1, 2}};
  const double d5 = ab.dot(p - c), d6 = ac.dot(p - c);
  if (d6 >= 0.0 && d5 <= d6) return {DistanceType::PointPoint, {0, 3}};
  if (d5 * d2 - d1 * d6 <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
    return {DistanceType::PointEdge, {0, 1, 3}};
  if (d3 * d6 - d5 * d4 <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return {DistanceType::PointEdge, {0, 2, 3}};
  return {DistanceType::PointPlane, {0, 1, 2, 3}};
}

// Point `p` (argument index p) against the segment of arguments (e0, e1): point–point with the
// nearer endpoint when p projects outside the segment, point–edge otherwise.
ActiveType pointSegmentType(const std::array<const Eigen::Vector3d*, 4>& x, int p, int e0, int e1) {
  const Eigen::Vector3d e = *x[e1] - *x[e0];
  const double along = (*x[p] - *x[e0]).dot(e);
  if (along <= 0.0) return {DistanceType::PointPoint, {p, e0}};
  if (along >= e.squaredNorm()) return {DistanceType::PointPoint, {p, e1}};
  return {DistanceType::PointEdge, {p, e0, e1}};
}

// Below this sin² of the angle between the segments they are parallel: the lines' closest points
// are then ill-determined (their error grows as ε_machine / sin²), and the endpoint distances,
// which differ from the line–line distance by at most about (sin θ · length)², are used.
constexpr double kParallelSinSquared = 1e-12;

// Segments (a0, a1) = arguments 0, 1 and (b0, b1) = arguments 2, 3.
ActiveType edgeEdgeType(const std::array<const Eigen::Vector3d*, 4>& x) {
  const Eigen::Vector3d u = *x[1] - *x[0], v = *x[3] - *x[2], w = *x[0] - *x[2];
  const double uu = u.squaredNorm(), uv = u.dot(v), vv = v.squaredNorm();
  const double determinant = uu * vv - uv * uv;  // |u × v|²
  if (determinant > kParallelSinSquared * uu * vv) {
    // The lines' closest points a0 + s u and b0 + t v (normal equations of |w + s u − t v|²).
    const double uw = u.dot(w), vw = v.dot(w);
    const double s = (uv * vw - vv * uw) / determinant, t = (uu * vw - uv * uw) / determinant;
    if (s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0) return {DistanceType::LineLine, {0, 1, 2, 3}};
  }
  const std::array<ActiveType, 4> candidates = {
      pointSegmentType(x, 0, 2, 3), pointSegmentType(x, 1, 2, 3), pointSegmentType(x, 2, 0, 1),
      pointSegmentType(x, 3, 0, 1)};
  ActiveType nearest = candidates[0];
  double nearestDistance = evaluateType(nearest, x, nullptr, nullptr);
  for (int k = 1; k < 4; ++k) {
    const double distance = evaluateType(candidates[k], x, nullptr, nullptr);
    if (distance < nearestDistance) nearest = candidates[k], nearestDistance = distance;
  }
  return nearest;
}

}  // namespace

double pointTriangleDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                    const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                    Vector12* gradient, Matrix12* hessian) {
  return evaluateType(pointTriangleType(p, t0, t1, t2), {&p, &t0, &t1, &t2}, gradient, hessian);
}

double edgeEdgeDistanceSquared(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                               const Eigen::Vector3d& b0, const Eigen::Vector3d& b1,
                               Vector12* gradient, Matrix12* hessian) {
  const std::array<const Eigen::Vector3d*, 4> x = {&a0, &a1, &b0, &b1};
  return evaluateType(edgeEdgeType(x), x, gradient, hessian);
}

double edgeEdgeMollifier(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                         const Eigen::Vector3d& b0, const Eigen::Vector3d& b1, double threshold,
                         Vector12* gradient, Matrix12* hessian) {
  return evaluate(Mollifier{threshold}, {&a0, &a1, &b0, &b1}, {0, 1, 2, 3}, gradient, hessian);
}

double edgeEdgeMollifierThreshold(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                  const Eigen::Vector3d& b0, const Eigen::Vector3d& b1) {
  return 1e-3 * (a1 - a0).squaredNorm() * (b1 - b0).squaredNorm();
}

}  // namespace flexure::optimize
