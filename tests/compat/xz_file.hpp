#pragma once
// Decompress an .xz fixture (liblzma) into memory.
#include <filesystem>
#include <string>

namespace ppohdem::test {

/// The decompressed bytes of `path`; throws std::runtime_error naming the file on any error.
std::string read_xz_file(const std::filesystem::path& path);

}  // namespace ppohdem::test
