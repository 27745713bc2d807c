#pragma once
/// \file units.hpp
/// The one unit system of ppohdem (CoMD's constants.h habit): **SI everywhere inside**.
///   length [m], time [s], mass [kg], force [N], stress/modulus [Pa], energy [J],
///   angle [rad], angular velocity [rad/s].
/// Input files may use other units only through the named conversions below.
/// Mesh coordinates and legacy ppohDEM inputs are dimensionless "model units" unless a scene
/// says otherwise; SDF values are always in the same length unit as the grid (world units),
/// and any length given "in h" says so in its name (e.g. `error_in_h`).
namespace ppohdem::units {
inline constexpr double kMetre = 1.0;
inline constexpr double kMillimetre = 1.0e-3;
inline constexpr double kMicrometre = 1.0e-6;
inline constexpr double kSecond = 1.0;
inline constexpr double kKilogram = 1.0;
inline constexpr double kPascal = 1.0;
inline constexpr double kMegapascal = 1.0e6;
inline constexpr double kGigapascal = 1.0e9;
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegree = kPi / 180.0;  ///< [rad]
}  // namespace ppohdem::units
