#pragma once
/// \file output_writers.hpp
/// Run outputs, all written atomically and each starting with the run header line:
///   frame_NNNNNN.csv   particle CSV (particle_csv.hpp)
///   frame_NNNNNN.vtk   legacy VTK POLYDATA (ParaView): POINTS = centres, one VERTEX each,
///                      POINT_DATA: radius (scalar), velocity, angular_velocity (vectors), id
///   frame_NNNNNN.pov   POV-Ray scene: camera, light and `sphere { <x, z, y>, r }` per
///                      particle (POV-Ray is y-up, as the seed writes <x, z, y>)
///   energy.csv         step,time,kinetic,rotational,gravitational,elastic,dissipated,
///                      boundary_work  [-, s, J...]
#include <filesystem>
#include <string>
#include <vector>

#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem {

void write_vtk_frame(const std::filesystem::path& file, const Particles& particles,
                     const std::string& header);
void write_pov_frame(const std::filesystem::path& file, const Particles& particles,
                     const std::string& header);

/// Accumulates energy rows and rewrites energy.csv atomically on flush().
class EnergyLog {
 public:
  EnergyLog(std::filesystem::path file, std::string header);
  void add(long step, double time, const Energies& energies);
  void flush() const;

 private:
  std::filesystem::path file_;
  std::string header_;
  std::vector<std::string> rows_;
};

/// "frame_000123" for step 123 (six digits or more).
std::string frame_stem(long step);

}  // namespace ppohdem::dem
