#pragma once
/// \file stl_ascii.hpp
/// Internal: the ASCII STL parser used by read_stl_bytes (stl_io.cpp).
#include <string>
#include <string_view>

#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::detail {

/// Parse ASCII STL text (grammar in stl_ascii.cpp and docs/formats.md). Throws InputError
/// naming `source_name`, the line and what was expected. Adds to `report`'s counters.
TriangleMesh parse_ascii_stl(std::string_view text, const std::string& source_name,
                             StlReadReport& report);

/// True if the first whitespace-separated word of `bytes` is `solid` (any case).
bool starts_with_solid_keyword(std::string_view bytes);

}  // namespace ppohdem::detail
