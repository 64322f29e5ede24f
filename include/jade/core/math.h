#pragma once
// Constants and angle conversions shared by every layer (one definition each).

namespace jade {

constexpr float kPi = 3.14159265358979323846f;

// Degrees → radians and back. Written as d·π/180 (not d·(π/180)) so every
// caller rounds the same way.
constexpr float radians(float degrees) { return degrees * kPi / 180.f; }
constexpr float degrees(float radians) { return radians * 180.f / kPi; }
// Double precision, for analysis (spectra, fits) rather than transport.
constexpr double kPiD = 3.14159265358979323846;
constexpr double radians(double degrees) { return degrees * kPiD / 180.0; }
constexpr double degrees(double radians) { return radians * 180.0 / kPiD; }

}  // namespace jade
