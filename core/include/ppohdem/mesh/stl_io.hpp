#pragma once
/// \file stl_io.hpp
/// STL reader and writer, ASCII and binary, auto-detected.
///
/// Detection (docs/formats.md): a file whose first non-blank word is `solid` is parsed as
/// ASCII; if that fails and the file size equals 84 + 50 n (n = the binary triangle count at
/// offset 80) it is read as binary (some binary exporters start the header with "solid").
/// Anything else must be binary with a matching size; a size mismatch is an error
/// ("truncated or padded binary STL").
/// ASCII is read token by token, so keywords and numbers may be split across lines as in the
/// seed's List 1.1. NaN/Inf coordinates are errors; zero-area triangles are counted, not fatal.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem {

enum class StlEncoding { kAscii, kBinary };

struct StlReadReport {
  StlEncoding encoding = StlEncoding::kAscii;
  std::size_t degenerate_triangles = 0;  ///< triangles of exactly zero area (kept)
  /// ASCII facets whose `vertex` keywords are not exactly one before each coordinate triple
  /// (List 1.1 layout: keyword after its numbers, or missing); accepted, counted here.
  std::size_t irregular_vertex_keywords = 0;
  /// facet normals that were NaN/Inf in the file; stored as zero (normals are informational).
  std::size_t non_finite_normals = 0;
};

/// Read an STL file. Throws InputError naming the file and the line (ASCII) or the triangle
/// index (binary) and what was expected.
TriangleMesh read_stl(const std::filesystem::path& path, StlReadReport* report = nullptr);

/// Same, from bytes in memory; `source_name` is used in error messages (fuzzing entry point).
TriangleMesh read_stl_bytes(std::string_view bytes, const std::string& source_name,
                            StlReadReport* report = nullptr);

/// Write atomically (temp file + rename). ASCII uses `ascii_significant_digits` (17 by
/// default: every double round-trips exactly); binary stores float32, little-endian.
/// Normals written are the file normals if `use_file_normals`, else recomputed unit normals.
void write_stl(const std::filesystem::path& path, const TriangleMesh& mesh, StlEncoding encoding,
               bool use_file_normals = false, int ascii_significant_digits = 17);

}  // namespace ppohdem
