#pragma once
/// \file distance_dat.hpp
/// The original program's distance files (ppOpen-APPL/DEM-Util `distance_NNNN.dat`).
///
/// One text file per MPI rank, NNNN = rank with 4 digits, in the same directory:
///   rank 0 only, line 1, Fortran format (4I8):   gridX gridY gridZ nprocs
///   then one record per node, format (3I8,1E20.8): i j k d
/// with 1-based indices, loop order k outer, j, then i inner over the rank's own x-slab.
/// Slabs: every rank gets gridX / nprocs x-planes; the first gridX mod nprocs ranks get one
/// more (rank 0 holds the lowest i). Values have 8 significant digits (E20.8), e.g.
/// `      0.44173684E+03`. Node (i, j, k) sits at ((i-1) h, (j-1) h, (k-1) h) with h = L / n
/// (GridSpec::ppohdem_legacy); the file itself stores no spacing.
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ppohdem/grid/scalar_field.hpp"

namespace ppohdem {

/// `v` as gfortran writes it with edit descriptor E20.8: right-justified in 20 columns,
/// mantissa 0.dddddddd (the 8 digits correctly rounded, ties to even), exponent `E+dd`,
/// or `+ddd` without the letter when |exponent| > 99 (Fortran rule for Ew.d); zero is
/// `0.00000000E+00`, -0 keeps its sign; `Infinity`, `-Infinity`, `NaN` right-justified.
std::string format_fortran_e20_8(double v);

/// The x-planes [first_plane, first_plane + plane_count) (0-based) that `rank` holds.
struct DistanceDatSlab {
  int first_plane = 0;
  int plane_count = 0;
};
DistanceDatSlab distance_dat_slab(int grid_x, int nprocs, int rank);

/// `dir / "distance_NNNN.dat"`.
std::filesystem::path distance_dat_path(const std::filesystem::path& dir, int rank);

/// What the files hold: node counts, the rank count that wrote them, and every value in
/// GridSpec order (x fastest, index = i + nx (j + ny k), 0-based).
struct DistanceDat {
  Index3 nodes = {0, 0, 0};
  int nprocs = 0;
  std::vector<double> values;

  /// The values on `grid` (e.g. GridSpec::ppohdem_legacy(L, nodes)); throws InputError if the
  /// grid's node counts differ from the file's.
  ScalarField on_grid(const GridSpec& grid) const;
};

/// Write all `nprocs` rank files into `dir` (which must exist). `values` in GridSpec order.
/// Each file is written to a temporary name first; nothing is renamed into place until every
/// file has been written. Needs 1 <= nprocs <= nodes[0] and nodes < 10^8 (I8 fields).
void write_distance_dat(const std::filesystem::path& dir, std::span<const double> values, const Index3& nodes,
                        int nprocs);

/// Only rank `rank`'s file of an `nprocs`-rank set, byte for byte what write_distance_dat
/// writes for it, to `file` (any name; the original names it prefix + distance_NNNN.dat), written
/// atomically. For programs whose MPI ranks each write their own file.
void write_distance_dat_rank(const std::filesystem::path& file, std::span<const double> values,
                             const Index3& nodes, int nprocs, int rank);

/// Read rank 0's header, then every rank file it names, from the directory `dir_or_rank0_file`
/// or from the directory holding that rank-0 file. InputError (file:line, expected, found) on a
/// bad header, a missing rank file, a malformed record, indices out of the expected order, or
/// too few / too many records.
/// Before allocating the nodes' values the reader checks that the rank files together hold at
/// least 7 bytes per announced record (the shortest record, `1 1 1 0`), so a header claiming
/// 10^8 x 10^8 x 10^8 nodes is an InputError, not an allocation failure.
DistanceDat read_distance_dat(const std::filesystem::path& dir_or_rank0_file);

/// Same, from the files' bytes in memory (fuzzing entry point): `rank_files[r]` is rank r's
/// file; rank 0's header must announce nprocs = rank_files.size() or less (missing ranks are
/// reported as for files). Messages name `source_dir / distance_NNNN.dat`.
DistanceDat read_distance_dat_bytes(std::span<const std::string_view> rank_files,
                                    const std::filesystem::path& source_dir);

}  // namespace ppohdem
