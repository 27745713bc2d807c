#pragma once
/// \file particle_csv.hpp
/// Particle files: CSV with the header line
///   id,x,y,z,vx,vy,vz,wx,wy,wz,radius
/// in SI units (m, m/s, rad/s, m). Lines starting with '#' are comments (ppohdem writes its
/// run header there), blank lines are skipped. The writer uses the same columns with 17
/// significant digits, so final.csv can start a new run and round-trips exactly.
#include <filesystem>
#include <string>

#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem {

/// Throws InputError(file, line, ...) on a wrong header, a wrong number of fields, a value
/// that is not a number or not finite (NaN, inf), a radius <= 0, or a repeated id.
Particles read_particles_csv(const std::filesystem::path& file);

/// Writes atomically; `header_comment` (e.g. the provenance line) goes on a '#' line first.
void write_particles_csv(const std::filesystem::path& file, const Particles& particles,
                         const std::string& header_comment);

}  // namespace ppohdem::dem
