// Write throughput of the particle frame formats (docs/performance.md "I/O: VTU frames"): the CSV frame
// (write_particles_csv, %.17g text) against the VTK XML frame (write_vtu_frame, appended raw
// binary), on N particles of a bed-like state, interleaved rounds, best of each. Never run in
// ctest (a benchmark, not a test).
//   ppohdem-bench-frames [N = 1000000] [DIR = /tmp] [ROUNDS = 3]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/dem/vtu_writer.hpp"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  const std::size_t n = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1000000;
  const fs::path dir = argc > 2 ? fs::path(argv[2]) : fs::temp_directory_path();
  const int rounds = argc > 3 ? std::atoi(argv[3]) : 3;
  // A settling bed's state: positions in a 0.1 m box, velocities and spins of order 0.1 m/s
  // and 100 rad/s, forces of order 1e-4 N (full 17-digit values, as a run writes them).
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ppohdem::dem::Particles p(n);
  for (std::size_t i = 0; i < n; ++i) {
    p[i].id = static_cast<std::int64_t>(i + 1);
    p[i].position = {0.05 + 0.05 * u(rng), 0.05 + 0.05 * u(rng), 0.05 + 0.05 * u(rng)};
    p[i].velocity = {0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng)};
    p[i].angular_velocity = {100 * u(rng), 100 * u(rng), 100 * u(rng)};
    p[i].radius = 5e-4;
    p[i].force = {1e-4 * u(rng), 1e-4 * u(rng), 1e-4 * u(rng)};
    p[i].torque = {1e-8 * u(rng), 1e-8 * u(rng), 1e-8 * u(rng)};
  }
  const fs::path csv = dir / "bench_frame.csv";
  const fs::path vtu = dir / "bench_frame.vtu";
  double best_csv = 1e300, best_vtu = 1e300;
  auto timed = [](auto write) {
    const auto start = std::chrono::steady_clock::now();
    write();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  for (int r = 0; r < rounds; ++r) {
    best_csv = std::min(best_csv, timed([&] { ppohdem::dem::write_particles_csv(csv, p, "bench"); }));
    best_vtu = std::min(best_vtu, timed([&] { ppohdem::dem::write_vtu_frame(vtu, p, "bench"); }));
  }
  const double mb_csv = static_cast<double>(fs::file_size(csv)) / 1e6;
  const double mb_vtu = static_cast<double>(fs::file_size(vtu)) / 1e6;
  std::printf("particles %zu, best of %d rounds\n", n, rounds);
  std::printf("csv: %.1f MB in %.3f s = %.0f MB/s, %.2f M particles/s\n", mb_csv, best_csv, mb_csv / best_csv,
              static_cast<double>(n) / best_csv / 1e6);
  std::printf("vtu: %.1f MB in %.3f s = %.0f MB/s, %.2f M particles/s\n", mb_vtu, best_vtu, mb_vtu / best_vtu,
              static_cast<double>(n) / best_vtu / 1e6);
  fs::remove(csv);
  fs::remove(vtu);
  return 0;
}
