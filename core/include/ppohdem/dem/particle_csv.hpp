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
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "ppohdem/dem/particle.hpp"
#include "ppohdem/dem/simulation_setup.hpp"

namespace ppohdem {
class Comm;
}

namespace ppohdem::dem {

/// Reads the whole file, then parses its lines on the OpenMP threads.
/// Throws InputError(file, line, ...) at the first bad line in file order, on a wrong header, a wrong number of fields, a value
/// that is not a number or not finite (NaN, inf), a radius <= 0, or a repeated id; with a
/// material column, a name not in `material_names` (Particle::material = its index there), or
/// no names at all (a scene without named materials).
Particles read_particles_csv(const std::filesystem::path& file,
                             const std::vector<std::string>& material_names = {});

/// A rank's share of a particle file, and where it sits in the file.
struct SharedParticles {
  Particles particles;  ///< in file order
  ParticleShare share;  ///< comm, the file index of the first, and the file's count
};

/// The same file read by every rank of `comm`, each keeping a share (docs/dem.md "Reading on
/// every rank"): a rank reads and parses, on its threads, the data lines that start in its 1/P
/// of the bytes, and keeps those particles. Every rank throws the same InputError at the same
/// first bad line in file order, a repeated id in another share included. Collective. A file
/// that is not a regular file (a pipe) is read whole by every rank, which keeps a 1/P of it.
SharedParticles read_particles_csv(const std::filesystem::path& file, const std::vector<std::string>& material_names,
                                   const Comm& comm);

namespace detail {
/// read_particles_csv's parse of a file's text `text` (named `name` in errors), its data lines
/// cut into `pieces` pieces parsed at the same time (OpenMP): the same particles and the same
/// first error, in file order, for any number of pieces (tests/dem/particle_io_test.cpp).
Particles parse_particles_csv(std::string_view text, const std::string& name,
                              const std::vector<std::string>& material_names, std::size_t pieces);
}  // namespace detail

/// Writes atomically; `header_comment` (e.g. the provenance line) goes on a '#' line first.
/// With two or more `material_names`, adds the material column (each particle's name).
void write_particles_csv(const std::filesystem::path& file, const Particles& particles,
                         const std::string& header_comment,
                         const std::vector<std::string>& material_names = {});

/// The same file written by every rank of `comm`, each giving its consecutive part of the
/// particles (`mine`; rank order is file order: DemEngine::ordered_part). Each rank formats its
/// lines on its threads; rank 0 writes the file, taking the other ranks' text one rank at a
/// time, so no rank holds every particle. The bytes are the one-rank writer's. Collective.
void write_particles_csv(const std::filesystem::path& file, const Particles& mine, const std::string& header_comment,
                         const std::vector<std::string>& material_names, const Comm& comm);

}  // namespace ppohdem::dem
