// Pi and degree <-> radian conversions: the one copy for the physics server
// and its tests.
//
// Two spellings of the same conversion round differently in the last bit:
// deg * pi / 180 (deg_to_rad) and deg * (pi / 180) (kRadPerDeg). Each place
// keeps the one it has always used, because traces are compared byte for
// byte across versions; new code may use either.
#pragma once

namespace chainsim {

inline constexpr double kPi = 3.14159265358979323846;

// the factors: degrees * kRadPerDeg = radians, radians * kDegPerRad = degrees
inline constexpr double kRadPerDeg = kPi / 180.0;
inline constexpr double kDegPerRad = 180.0 / kPi;

// deg * pi / 180, multiplied then divided
constexpr double deg_to_rad(double deg) { return deg * kPi / 180.0; }
// rad * 180 / pi, multiplied then divided
constexpr double rad_to_deg(double rad) { return rad * 180.0 / kPi; }

}  // namespace chainsim
