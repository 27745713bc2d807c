#pragma once
/// \file particle_csv.hpp
/// Particle files: CSV with the header line
///   id,x,y,z,vx,vy,vz,wx,wy,wz,radius
/// in SI units (m, m/s, rad/s, m), or, in a scene with named materials, the same header with a
/// 12th column `material` holding a material's name (pair_laws.hpp):
///   id,x,y,z,vx,vy,vz,wx,wy,wz,radius,material
/// Lines starting with '#' are comments (ppohdem writes its run header there), blank lines are
/// skipped. The writer uses the same columns with 17 significant digits, so final.csv can
/// start a new run and round-trips exactly; it writes the material column only for a scene of
/// several materials (one-material outputs are unchanged).
#include <filesystem>
#include <string>
#include <vector>

#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem {

/// Throws InputError(file, line, ...) on a wrong header, a wrong number of fields, a value
/// that is not a number or not finite (NaN, inf), a radius <= 0, or a repeated id; with a
/// material column, a name not in `material_names` (Particle::material = its index there), or
/// no names at all (a scene without named materials).
Particles read_particles_csv(const std::filesystem::path& file,
                             const std::vector<std::string>& material_names = {});

/// Writes atomically; `header_comment` (e.g. the provenance line) goes on a '#' line first.
/// With two or more `material_names`, adds the material column (each particle's name).
void write_particles_csv(const std::filesystem::path& file, const Particles& particles,
                         const std::string& header_comment,
                         const std::vector<std::string>& material_names = {});

}  // namespace ppohdem::dem
