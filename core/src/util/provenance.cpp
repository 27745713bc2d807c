#include "ppohdem/provenance.hpp"

#include <unistd.h>

#include <array>
#include <ctime>

#include "ppohdem/build_info.hpp"

#ifdef PPOHDEM_WITH_OPENMP
#include <omp.h>
#endif

namespace ppohdem {

std::string provenance_line(int ranks, int threads) {
  if (threads <= 0) {
#ifdef PPOHDEM_WITH_OPENMP
    threads = omp_get_max_threads();
#else
    threads = 1;
#endif
  }
  std::array<char, 256> host{};
  if (gethostname(host.data(), host.size() - 1) != 0) host[0] = '\0';
  std::array<char, 32> date{};
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  std::strftime(date.data(), date.size(), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return std::string("ppohdem ") + build_info::kVersion + " (git " + build_info::kGitHash + "); " +
         build_info::kCompiler + " [" + build_info::kCxxFlags + "] " + build_info::kBuildType +
         "; ranks " + std::to_string(ranks) + "; threads " + std::to_string(threads) +
         "; precision double; host " + host.data() + "; " + date.data();
}

}  // namespace ppohdem
