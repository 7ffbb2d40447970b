// Small vector algebra on raw T* triples for the element kernels: T is double or ceres::Jet, so
// the same formula serves energy values, residuals (autodiff) and curvature fields.
#pragma once

#include <cmath>

#include "modeling/mixed_area.h"

namespace flexure::curvature {

template <class T>
struct Vec3 {
  T x, y, z;
};

template <class T>
inline Vec3<T> load(const T* p) {
  return {p[0], p[1], p[2]};
}
template <class T>
inline Vec3<T> operator-(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
inline Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T, class S>
inline Vec3<T> operator*(const S& s, const Vec3<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
inline T dot(const Vec3<T>& a, const Vec3<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
inline Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
inline T norm(const Vec3<T>& a) {
  using std::sqrt;
  return sqrt(dot(a, a));
}

// The angle in [0, π] between a and b: atan2(|a × b|, a · b), accurate near 0 and π (acos is not).
template <class T>
inline T angleBetween(const Vec3<T>& a, const Vec3<T>& b) {
  using std::atan2;
  return atan2(norm(cross(a, b)), dot(a, b));
}

// A symmetric 2×2 tensor [[a, b], [b, c]] in a face's rest frame (u, v).
template <class T>
struct Sym2 {
  T a, b, c;
};

// s += c t.
template <class T, class U>
inline void addScaled(Sym2<T>& s, const T& c, const Sym2<U>& t) {
  s.a += c * t.a;
  s.b += c * t.b;
  s.c += c * t.c;
}

}  // namespace flexure::curvature

namespace flexure::curvature {

using modeling::scalarPart;  // the value part of a double or a jet (modeling/mixed_area.h)
template <class T>
inline bool isFiniteScalar(const T& v) {
  return std::isfinite(scalarPart(v));
}

}  // namespace flexure::curvature
