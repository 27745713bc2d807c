// libFuzzer target: particle CSV files (dem::read_particles_csv). The reader takes a path, so
// each input is written to a file in a per-process tmpfs directory first. The reader is given
// two material names, as a scene with [[material]] entries would, so inputs with the optional
// 12th column 'material' reach the name lookup too.
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "ppohdem/dem/particle_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  const auto file = fuzz::scratch().write("particles.csv", fuzz::as_text(data, size));
  fuzz::run_reader([&] {
    static const std::vector<std::string> kMaterials{"glass", "steel"};
    const dem::Particles particles = dem::read_particles_csv(file, kMaterials);
    // Promises of particle_csv.hpp for an accepted file: finite values, radius > 0, unique ids.
    std::set<std::int64_t> ids;
    for (const dem::Particle& p : particles) {
      PPOHDEM_FUZZ_CHECK(p.position.allFinite() && p.velocity.allFinite() && p.angular_velocity.allFinite());
      PPOHDEM_FUZZ_CHECK(std::isfinite(p.radius) && p.radius > 0.0);
      PPOHDEM_FUZZ_CHECK(ids.insert(p.id).second);
      PPOHDEM_FUZZ_CHECK(p.material < kMaterials.size());
    }
  });
  return 0;
}
