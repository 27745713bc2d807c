#pragma once
/// \file output_writers.hpp
/// Run outputs, all written atomically and each starting with the run header line:
///   frame_NNNNNN.csv   particle CSV (particle_csv.hpp)
///   frame_NNNNNN.vtk   legacy VTK POLYDATA (ParaView): POINTS = centres, one VERTEX each,
///                      POINT_DATA: radius (scalar), velocity, angular_velocity (vectors), id
///   frame_NNNNNN.pov   POV-Ray scene: camera, light and `sphere { <x, z, y>, r }` per
///                      particle (POV-Ray is y-up, as the seed writes <x, z, y>), then one
///                      `mesh { triangle { <..>, <..>, <..> } ... }` per object with a display
///                      mesh, moved by the object's pose_at(t)
///   objects/object_K_NNNNNN.vtk  (with vtk or pov frames, objects with a display mesh) the
///                      display mesh of Scene::objects[K] moved by pose_at(t): legacy VTK
///                      POLYDATA, POINTS (3 per triangle, world frame, m) and POLYGONS
///   energy.csv         step,time,kinetic,rotational,gravitational,elastic,dissipated,
///                      boundary_work  [-, s, J...]
///   objects.csv        (scenes with [[object]]) one row per object per energy row:
///                      step,time,object,centroid_x,centroid_y,centroid_z,qw,qx,qy,qz,
///                      translation_x,translation_y,translation_z,force_x,force_y,force_z,
///                      torque_x,torque_y,torque_z,outside_grid
///                      [-, s, -, m x3, pose quaternion (object frame -> world), m x3, N x3,
///                      N m x3 about the current centroid, count outside the grid in reach]
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/particle.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem {
class Comm;
}

namespace ppohdem::dem {

void write_vtk_frame(const std::filesystem::path& file, const Particles& particles,
                     const std::string& header);
/// `objects`: the scene's objects; each one's display mesh (if any) is drawn at pose_at(time).
void write_pov_frame(const std::filesystem::path& file, const Particles& particles,
                     const std::string& header,
                     const std::vector<std::shared_ptr<const DistanceFieldObject>>& objects = {},
                     double time = 0.0);

/// Parts (several ranks, docs/dem.md "Reading on every rank"): the same bytes as the writers
/// above given all the particles, written from each rank's consecutive part of them. `mine`
/// holds the particles [first, first + mine.size()) of `total` (DemEngine::ordered_part:
/// rank r's part follows rank r - 1's); no rank holds every particle. Each rank formats its
/// own lines; rank 0 writes the file (BlockFileWriter: temp file, then rename), taking the
/// other ranks' text one rank at a time. Collective.
///
/// VTK: rank 0 writes each section's header (POINTS, VERTICES, radius, id, velocity,
/// angular_velocity), then every rank's lines of that section in rank order; a rank formats
/// one section at a time. VERTICES "1 i" numbers the particles by their global index first + k.
void write_vtk_frame(const std::filesystem::path& file, const Particles& mine, std::size_t first,
                     std::size_t total, const std::string& header, const Comm& comm);
/// POV-Ray: the camera frames the box of all the particles, which rank 0 merges in rank order
/// from each rank's box (one gather of 18 doubles a rank; minima and maxima, so exactly the one
/// loop's box); then the spheres in rank order, and rank 0 adds the objects' display meshes.
void write_pov_frame(const std::filesystem::path& file, const Particles& mine, std::size_t first,
                     std::size_t total, const std::string& header, const Comm& comm,
                     const std::vector<std::shared_ptr<const DistanceFieldObject>>& objects = {},
                     double time = 0.0);

/// `mesh` with every vertex mapped by `pose` (x -> R x + t); file normals are rotated.
TriangleMesh transformed(const TriangleMesh& mesh, const RigidTransform& pose);
/// Legacy VTK POLYDATA of a triangle mesh: 3 POINTS per triangle (%.17g, so a reader gets the
/// doubles back exactly) and one POLYGONS entry "3 a b c" per triangle.
void write_mesh_vtk(const std::filesystem::path& file, const TriangleMesh& mesh, const std::string& header);
/// "object_2_000123.vtk" for object 2 at step 123.
std::string object_mesh_file_name(std::size_t object_index, long step);

/// Accumulates energy rows and rewrites energy.csv atomically on flush().
class EnergyLog {
 public:
  EnergyLog(std::filesystem::path file, std::string header);
  void add(long step, double time, const Energies& energies);
  void flush() const;
  /// The data rows so far (checkpoints carry them, so a restarted run rewrites the same file).
  const std::vector<std::string>& rows() const { return rows_; }
  void set_rows(std::vector<std::string> rows) { rows_ = std::move(rows); }

 private:
  std::filesystem::path file_;
  std::string header_;
  std::vector<std::string> rows_;
};

/// Accumulates objects.csv rows (see above) and rewrites the file atomically on flush().
class ObjectLog {
 public:
  ObjectLog(std::filesystem::path file, std::string header);
  /// `object_index` is the position in Scene::objects (0-based), `load` its reaction;
  /// `outside_grid_offset` is added to the object's count (a restarted run continues it).
  void add(long step, double time, std::size_t object_index, const DistanceFieldObject& object,
           const BoundaryLoad& load, std::int64_t outside_grid_offset = 0);
  void flush() const;
  const std::vector<std::string>& rows() const { return rows_; }
  void set_rows(std::vector<std::string> rows) { rows_ = std::move(rows); }

 private:
  std::filesystem::path file_;
  std::string header_;
  std::vector<std::string> rows_;
};

/// "frame_000123" for step 123 (six digits or more).
std::string frame_stem(long step);

}  // namespace ppohdem::dem
