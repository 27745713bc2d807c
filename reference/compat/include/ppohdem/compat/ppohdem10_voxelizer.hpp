#pragma once
/// \file ppohdem10_voxelizer.hpp
/// `--compat ppohdem-1.0`: the original ppOpen-APPL/DEM-Util 1.0 `distance_calculate` as it
/// really computes, number for number (docs/compat.md lists every place where it is wrong and
/// what ppohdem's default mode does instead).
///
/// The original's pipeline (ppohDEM, Fortran 90, Copyright (c) 2014 JAMSTEC, MIT licence; read
/// from Post-Peta-Crest/ppOpenHPC branch APPL/DEM and /work/shared/ppohdem-original/README.md):
///  1. z-ray voxelisation per (i, j) column: facets whose xy bounding box *strictly* contains the
///     column and whose three edge tests pass are crossed; the sorted crossing heights are taken
///     in pairs and nodes *strictly* between a pair are "inside" (ppohDEM_v_makecrosslist_MPI,
///     ppohDEM_v_makegridout_MPI);
///  2. pass 1: gridZ Jacobi sweeps of the first-order eikonal update |grad d| = 1 on the nodes
///     2..n-1 (Sethian's upwind quadratic with 1, 2 or 3 upwind axes), inside nodes fixed at 0,
///     every other node starting from the sentinel 10 Lx; then the boundary faces, edges and
///     corners are extrapolated as a neighbour + W, 2W, 3W (ppohDEM_v_distancecalculate_MPI);
///  3. exact band: every node with pass-1 value < 2 sqrt(hx^2+hy^2+hz^2) or voxel-inside gets
///     the brute-force point-to-triangle distance, negative if voxel-inside or if 2 of 3 axis
///     ray-parity tests say inside; these nodes are frozen, every other node is reset to the
///     sentinel (ppohDEM_v_distanceprecise);
///  4. pass 2: the same Jacobi sweeps and boundary extrapolation, from the frozen band.
/// With nprocs > 1 the x axis is cut into slabs (the first gridX mod nprocs ranks get one more
/// plane) that exchange one ghost plane per side at the start of every sweep; the boundary
/// extrapolation then reads the ghost plane that was exchanged *before* the last sweep, so the
/// values on the faces j = 1 and j = gridY at a rank's last plane depend on nprocs. This module
/// simulates the ranks in one process, so it reproduces that too.
///
/// Arithmetic is mirrored expression by expression (same operand order, no fused multiply-add;
/// the sources are compiled with -ffp-contract=off), so on IEEE-754 doubles the values are the
/// original's bit for bit where its behaviour is defined. Where it is not (see Ppohdem10Trace:
/// a column with an odd number of crossings reads one element past its array; more than 200
/// candidate facets in a column overflow a fixed array) this module takes the choice documented
/// there and counts the occurrences.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ppohdem/geometry/vector.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::compat {

/// The original's fixed sizes and constants.
inline constexpr int kPpohdem10MaxFacetCrossList = 200;  ///< MAX_FACET_CROSSLIST
inline constexpr double kPpohdem10SentinelFactor = 10.0; ///< unreached nodes hold 10 Lx

/// Every intermediate field, for study and for docs/compat.md. All per-node arrays are in
/// GridSpec order over the full grid (x fastest, index = i + nx (j + ny k), 0-based).
struct Ppohdem10Trace {
  Index3 nodes = {0, 0, 0};
  double spacing_w = 0.0;   ///< W = Lx / gridX [m], the step of the eikonal update
  double sentinel = 0.0;    ///< 10 Lx [m]
  double band_width = 0.0;  ///< check_gap = 2 sqrt(hx^2 + hy^2 + hz^2) [m]
  std::vector<std::uint8_t> voxel_inside;  ///< step 1 (value_3D)
  std::vector<double> pass1;               ///< after step 2, each rank's own planes
  std::vector<std::uint8_t> in_band;       ///< step 3 (calculated_3D): exact and frozen
  std::vector<std::uint8_t> vote_inside;   ///< step 3: the 2-of-3 axis vote said inside (band nodes only)
  std::vector<double> distance;            ///< the output: step 4, each rank's own planes
  /// Columns whose crossing count was odd. The original then compares with the element after
  /// the end of its crossing array (heap memory); this module marks nothing for that last
  /// unpaired crossing (glibc puts the next chunk's small size field there, a tiny positive
  /// double, so `z > c_last .and. z < tiny` is false for every z >= 0, which holds for the
  /// original's grid starting at 0).
  int odd_crossing_columns = 0;
  /// Columns whose candidate list held more than kPpohdem10MaxFacetCrossList facets (the
  /// original writes past its array there; this module keeps them all).
  int overflowing_columns = 0;
  /// Columns with a non-finite crossing height (a facet parallel to z passing the edge tests).
  int nonfinite_crossing_columns = 0;
};

/// The original's distance values for `placed_mesh` (already placed with
/// PlacementMode::kPpohdem10) on the grid of `input` (x = (Lx/gridX)(i-1), ...), as `nprocs`
/// ranks would have written them; GridSpec order over the full grid (write them with
/// write_distance_dat(dir, values, input.voxels, nprocs)). Throws InputError if nprocs < 1 or
/// nprocs > gridX, a count is < 3, or gridX > gridY (the original's face j = gridY loop uses
/// gridX as its j index and would run out of its array).
std::vector<double> ppohdem10_distance(const TriangleMesh& placed_mesh, const VoxelizerInput& input,
                                       int nprocs);

/// The same pipeline one stage at a time, as the original library's subroutines run it
/// (ppohDEM_v_makevoxel, ppohDEM_v_distancecalculate_MPI1, ppohDEM_v_distanceprecise,
/// ppohDEM_v_distancecalculate_MPI2; bindings/fortran/util). Each stage throws
/// std::logic_error naming its prerequisite if called out of order; distance() is the field
/// after the last stage run (each rank's own planes, GridSpec order).
class Ppohdem10VoxelizerStages {
 public:
  Ppohdem10VoxelizerStages(const TriangleMesh& placed_mesh, const VoxelizerInput& input, int nprocs);
  ~Ppohdem10VoxelizerStages();
  Ppohdem10VoxelizerStages(const Ppohdem10VoxelizerStages&) = delete;
  Ppohdem10VoxelizerStages& operator=(const Ppohdem10VoxelizerStages&) = delete;

  void voxelize();    ///< 1. z-ray voxelisation
  void pass1();       ///< 2. Jacobi pass from the voxel-inside nodes
  void exact_band();  ///< 3. exact signed distances in the band, frozen
  void pass2();       ///< 4. Jacobi pass from the band
  int stages_done() const;  ///< 0..4
  std::vector<double> distance() const;
  const Ppohdem10Trace& trace() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// object_mesh.stl as the original's output_object_mesh writes it: the placed mesh with the
/// input's facet normals, every line list-directed (one leading blank, reals with 17 significant
/// digits), e.g. "        vertex 24.999997000001500 24.999999700000149 13.000000000000000".
std::string ppohdem10_object_mesh_stl(const TriangleMesh& placed_mesh);

/// The same computation, keeping every intermediate field.
Ppohdem10Trace ppohdem10_distance_trace(const TriangleMesh& placed_mesh, const VoxelizerInput& input,
                                        int nprocs);

}  // namespace ppohdem::compat
