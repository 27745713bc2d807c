#pragma once
/// \file vector.hpp
/// Small fixed-size vocabulary types, all Eigen (double precision unless named otherwise).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

namespace ppohdem {
using Vec3 = Eigen::Vector3d;     ///< a point or vector in world units
using Quat = Eigen::Quaterniond;  ///< a rotation (kept unit-norm)
using Index3 = std::array<int, 3>;  ///< per-axis integer counts or indices (x, y, z)
}  // namespace ppohdem
