#pragma once
/// \file vtu_writer.hpp
/// Particle frames as VTK XML (docs/formats.md "VTK XML frames"): an UnstructuredGrid piece
/// (`.vtu`) with the arrays in one appended block of raw little-endian binary (each array a
/// UInt64 byte count and its bytes), one vertex cell per particle; with several ranks one piece
/// per rank and a `.pvtu` index; and a `.pvd` collection of the frames with their times. Binary
/// doubles are the particles' bits: nothing is lost, and nothing is formatted.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem {

/// One particle array of a frame: its VTK name, type and number of components.
struct VtuArray {
  const char* name;
  const char* type;  ///< VTK type name: "Float64", "Int64", "UInt16"
  int components;
};

/// The point-data arrays of a frame, in file order: id, radius, velocity, angular_velocity,
/// material, force, torque (the particle CSV's columns, the material as its index, plus the
/// last evaluation's contact force and torque).
const std::vector<VtuArray>& vtu_point_arrays();

/// frame_NNNNNN.vtu (one rank) or frame_NNNNNN_RRRR.vtu (rank R's piece of several).
std::string vtu_piece_name(long step, int rank, int ranks);

/// Writes `particles` as one piece, atomically (temp file, then rename). `header` (the run
/// header) goes into an XML comment.
void write_vtu_frame(const std::filesystem::path& file, const Particles& particles, const std::string& header);

/// Writes the index of a frame's pieces (`piece_names`, relative to the index's directory).
void write_pvtu_index(const std::filesystem::path& file, const std::vector<std::string>& piece_names,
                      const std::string& header);

/// Writes the collection of frames: (time [s], file name relative to the collection).
void write_pvd_collection(const std::filesystem::path& file, const std::vector<std::pair<double, std::string>>& frames,
                          const std::string& header);

}  // namespace ppohdem::dem
