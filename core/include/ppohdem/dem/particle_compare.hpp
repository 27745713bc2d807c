#pragma once
/// \file particle_compare.hpp
/// How far two runs' particles are apart, field by field: the check behind "both engines give
/// the same bits" (docs/dem.md "Optimized engine"), for the Python module's pd.compare.
///   max_<field> = max over particles and components of |a - b|  [field units]
///   bitwise     = every double of every field has the same bit pattern in a and b
/// Particles are matched by position in the vectors (construction order), which must hold the
/// same ids in the same order.
#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem {

struct ParticleDifference {
  double max_position = 0.0;          ///< [m]
  double max_velocity = 0.0;          ///< [m/s]
  double max_angular_velocity = 0.0;  ///< [rad/s]
  double max_force = 0.0;             ///< [N]
  double max_torque = 0.0;            ///< [N m]
  double max_radius = 0.0;            ///< [m]
  bool bitwise = true;
};

/// Throws InputError if the counts or the ids (in order) differ. A NaN in either side makes
/// that field's maximum NaN and bitwise true only if both bit patterns agree.
ParticleDifference compare_particles(const Particles& a, const Particles& b);

}  // namespace ppohdem::dem
