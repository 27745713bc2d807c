#pragma once
/// \file provenance.hpp
/// Who made an output: version, git hash, compiler, flags, ranks, threads, host, date
/// (CoMD's yamlAppInfo). Written at the top of every output file and printed at start.
#include <string>

namespace ppohdem {

/// One line, e.g. "ppohdem 0.1.0 (git abc123) GNU 12.2.0 -O3 ...; ranks 1; threads 2; host h".
/// threads <= 0 means "the OpenMP default of this process" (1 in a build without OpenMP).
std::string provenance_line(int ranks = 1, int threads = 0);

}  // namespace ppohdem
