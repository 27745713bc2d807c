#pragma once
/// \file vtk_structured_points.hpp
/// Legacy VTK (version 3.0) STRUCTURED_POINTS with one point-data scalar array:
///
///   # vtk DataFile Version 3.0
///   <title line>
///   BINARY
///   DATASET STRUCTURED_POINTS
///   DIMENSIONS nx ny nz
///   ORIGIN ox oy oz
///   SPACING hx hy hz
///   POINT_DATA nx*ny*nz
///   SCALARS distance double 1
///   LOOKUP_TABLE default
///   <nx*ny*nz big-endian IEEE doubles, x fastest>
///
/// Big-endian binary is what the VTK file-format specification prescribes for legacy files
/// (ParaView reads it). The reader accepts BINARY or ASCII, `double` or `float` scalars.
#include <filesystem>
#include <string>
#include <string_view>

#include "ppohdem/grid/scalar_field.hpp"

namespace ppohdem {

enum class VtkScalarType { kDouble, kFloat };

/// Write atomically. `title` must be one line (newlines are replaced by spaces, max 255 chars).
void write_vtk_structured_points(const std::filesystem::path& path, const ScalarField& field,
                                 std::string_view array_name = "distance",
                                 std::string_view title = "ppohdem signed distance",
                                 VtkScalarType type = VtkScalarType::kDouble);

/// Read; throws InputError with file:line on malformed headers or short data.
ScalarField read_vtk_structured_points(const std::filesystem::path& path,
                                       std::string* array_name = nullptr);
ScalarField read_vtk_structured_points_bytes(std::string_view bytes, const std::string& source_name,
                                             std::string* array_name = nullptr);

}  // namespace ppohdem
