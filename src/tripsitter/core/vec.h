// Small 3-vector value type, one arithmetic for every scalar type (float, double, integer raw fixed point).
#pragma once

#include <cmath>

namespace tripsitter::core {

template <class T>
struct Vec3 {
  T x{}, y{}, z{};

  constexpr Vec3() = default;
  constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}

  constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr const T& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }

  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator*(T s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(T s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3& operator+=(const Vec3& o) { return *this = *this + o; }
  constexpr Vec3& operator-=(const Vec3& o) { return *this = *this - o; }
  constexpr bool operator==(const Vec3&) const = default;
};

template <class T>
constexpr Vec3<T> operator*(T s, const Vec3<T>& v) { return v * s; }

template <class T>
constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

template <class T>
constexpr Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The component-wise product (a colour filtered by a tint).
template <class T>
constexpr Vec3<T> hadamard(const Vec3<T>& a, const Vec3<T>& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

template <class T>
T length(const Vec3<T>& v) { return std::sqrt(dot(v, v)); }

template <class T>
Vec3<T> normalize(const Vec3<T>& v) { return v / length(v); }

using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;

}  // namespace tripsitter::core
