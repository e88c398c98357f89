#pragma once
// Mathematical constants and angle conversions shared by every module: one pi for the whole
// project instead of a local copy per file.

namespace skelgrasp {

// The double nearest to pi (the same value as M_PI and C++20's std::numbers::pi).
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2 * kPi;  // exact: doubling only changes the exponent

// Length units: metres per millimetre (readers scale millimetre files to SI metres).
inline constexpr double kMetresPerMillimetre = 1e-3;

// Degrees to radians. Multiplies before dividing (deg * pi / 180), the order every caller used
// before, so results are bit-identical to the former inline conversions.
constexpr double radiansFromDegrees(double degrees) {
  return degrees * kPi / 180.0;
}

}  // namespace skelgrasp
