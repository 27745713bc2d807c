// Run under mpirun at 2 and 3 ranks: write_vtk_frame and write_pov_frame in parts (each rank a
// consecutive part of the particles, rank 0 writing) give byte for byte the file that the
// one-rank writers (the oracle) write from all the particles with the same header. The parts
// are cut as DemEngine::ordered_part cuts them, and also unevenly: everything on rank 0,
// everything on the last rank (rank 0's part empty), an empty middle part; no particles at
// all; one particle. The particles include what the POV-Ray box must treat as the one-rank
// loop does: a NaN coordinate (first particle and later ones), -0 and +0 with radius 0 (the
// first of equal values is kept), a header longer than VTK's 256-character title.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "mpi_case.hpp"
#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/output_writers.hpp"
#include "ppohdem/dem/simulation_setup.hpp"

namespace {

using ppohdem::Vec3;
using ppohdem::dem::Particle;
using ppohdem::dem::Particles;

std::string bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// n particles with positions and velocities of varied magnitudes and signs (so that %.10g
/// takes its several forms) and ids unrelated to their order.
Particles particles(std::size_t n) {
  Particles ps;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 0.37 * static_cast<double>(i) + 0.1;
    Particle p;
    p.id = static_cast<std::int64_t>(7919 * i % 1000003) - 500;
    p.radius = 1e-3 * (1.0 + 0.5 * std::sin(3.0 * a));
    p.position = Vec3(std::sin(a) * std::pow(10.0, static_cast<double>(i % 7) - 4.0), std::cos(1.3 * a), -0.01 * a);
    p.velocity = Vec3(std::sin(2.0 * a), 1e-12 * std::cos(a), 1e5 * a);
    p.angular_velocity = Vec3(-a, 0.0, 1.0 / (1.0 + a));
    ps.push_back(p);
  }
  return ps;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ppohdem;
  test::MpiCase run(&argc, &argv);
  const Comm& comm = run.comm();
  const int me = comm.rank();
  const std::size_t ranks = static_cast<std::size_t>(comm.size());
  const std::filesystem::path dir = run.scratch("dem_frame_parts");
  int cases = 0;
  const double nan = std::numeric_limits<double>::quiet_NaN();

  // One case: `all` cut into parts of the given sizes (summing to all.size()).
  auto check = [&](const std::string& name, const Particles& all, const std::vector<std::size_t>& sizes,
                   const std::string& header) {
    ++cases;
    std::size_t first = 0;
    for (std::size_t r = 0; r < static_cast<std::size_t>(me); ++r) first += sizes[r];
    const Particles mine(all.begin() + static_cast<std::ptrdiff_t>(first),
                         all.begin() + static_cast<std::ptrdiff_t>(first + sizes[static_cast<std::size_t>(me)]));
    const std::filesystem::path stem = dir / name;
    dem::write_vtk_frame(std::filesystem::path(stem).concat(".parts.vtk"), mine, first, all.size(), header, comm);
    dem::write_pov_frame(std::filesystem::path(stem).concat(".parts.pov"), mine, first, all.size(), header, comm);
    if (me != 0) return;
    dem::write_vtk_frame(std::filesystem::path(stem).concat(".vtk"), all, header);
    dem::write_pov_frame(std::filesystem::path(stem).concat(".pov"), all, header);
    for (const char* extension : {".vtk", ".pov"}) {
      const std::string oracle = bytes(std::filesystem::path(stem).concat(extension));
      const std::string parts = bytes(std::filesystem::path(stem).concat(std::string(".parts") + extension));
      run.expect(!oracle.empty() && parts == oracle,
                 name + extension + ": the file in parts (" + std::to_string(parts.size()) +
                     " bytes) is not the one-rank file (" + std::to_string(oracle.size()) + " bytes)");
    }
  };
  // The cuts of n particles: ordered_part's, all on rank 0, all on the last rank, the middle
  // rank empty (3 ranks).
  auto cuts = [&](std::size_t n) {
    std::vector<std::vector<std::size_t>> out;
    std::vector<std::size_t> even(ranks), first_only(ranks, 0), last_only(ranks, 0);
    for (std::size_t r = 0; r < ranks; ++r) {
      even[r] = dem::even_part_first(n, ranks, r + 1) - dem::even_part_first(n, ranks, r);
    }
    first_only[0] = n;
    last_only[ranks - 1] = n;
    out = {even, first_only, last_only};
    if (ranks >= 3) {
      std::vector<std::size_t> middle_empty(ranks, 0);
      middle_empty[0] = n / 2;
      middle_empty[ranks - 1] = n - n / 2;
      out.push_back(middle_empty);
    }
    return out;
  };
  const std::string header = "ppohdem frame parts test";
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{25}, std::size_t{1000}}) {
    int k = 0;
    for (const auto& sizes : cuts(n)) {
      std::string name = "n";  // (not "n" + ...: GCC 12 warns of a memcpy overlap there, -Wrestrict)
      name += std::to_string(n) + "_cut" + std::to_string(k++);
      check(name, particles(n), sizes, header);
    }
  }
  // A title longer than legacy VTK's 256 characters (cut at 255 by both writers).
  check("long_header", particles(10), cuts(10)[0], std::string(300, 'h'));
  // NaN: as the first particle's coordinate (the box stays NaN there) and as later ones (the
  // one-rank loop skips them), in each rank's part.
  Particles with_nan = particles(12);
  with_nan[0].position.x() = nan;
  for (std::size_t i = 3; i < with_nan.size(); i += 4) with_nan[i].position.y() = nan;
  for (const auto& sizes : cuts(with_nan.size())) check("nan_first_" + std::to_string(cases), with_nan, sizes, header);
  with_nan[0].position.x() = 0.5;
  with_nan[1].radius = nan;
  for (const auto& sizes : cuts(with_nan.size())) check("nan_later_" + std::to_string(cases), with_nan, sizes, header);
  // Signed zeros with radius 0: the first particle at (-0, +0, -0), the others at zero of the
  // other sign or further in: the box's lo and hi keep the first of equal values.
  Particles zeros = particles(9);
  for (std::size_t i = 0; i < zeros.size(); ++i) {
    const double z = i % 2 == 0 ? -0.0 : 0.0;
    zeros[i].position = Vec3(z, -z, z);
    zeros[i].radius = 0.0;
  }
  for (const auto& sizes : cuts(zeros.size())) check("zeros_" + std::to_string(cases), zeros, sizes, header);
  const int failures = run.failures_over_ranks();
  if (me == 0) std::printf("%d cases at %zu ranks, %d failures\n", cases, ranks, failures);
  return failures == 0 ? 0 : 1;
}
