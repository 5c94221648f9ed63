#pragma once
#include <cmath>
#include <numbers>

namespace cogmap {

constexpr double kPi = std::numbers::pi;

constexpr double DegToRad(double deg) { return deg * kPi / 180.0; }
constexpr double RadToDeg(double rad) { return rad * 180.0 / kPi; }

// Wraps an angle into (-pi, pi].
inline double NormalizeAngle(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a <= 0.0) a += 2.0 * kPi;
  return a - kPi;
}

// Smallest signed difference a - b, wrapped into (-pi, pi].
inline double AngleDiff(double a, double b) { return NormalizeAngle(a - b); }

}  // namespace cogmap
