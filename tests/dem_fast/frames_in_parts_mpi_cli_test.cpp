// Legacy VTK and POV-Ray frames written in parts under mpirun (docs/dem.md "Reading on every
// rank"), through the command line as a user runs it: `mpirun -n P ppohdem simulate SCENE` with
// the fast engine at P = 2 and 3 must write the frames that one process writes with the
// one-rank writers (write_vtk_frame and write_pov_frame given every particle: the oracle), byte
// for byte except the run header line (it names the rank count and the date). Cases: a bed,
// a bed of two particles (at 3 ranks the last rank's part is empty), and a mesh object whose
// display mesh rank 0 draws after the spheres.
// Label mpi; built only with PPOHDEM_ENABLE_MPI.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "bed_scene.hpp"
#include "box_over_bed.hpp"
#include "mpi_runner.hpp"

namespace fs = std::filesystem;
using ppohdem::test::CommandResult;
using ppohdem::test::replace_in_scene;
using ppohdem::test::run_mpi;

namespace {

fs::path scratch(const std::string& name) { return ppohdem::test::scratch("dem_frames_in_parts_mpi", name); }

/// The whole file.
std::string bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  EXPECT_TRUE(in.good()) << file;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The file with its run header line (the 0-based line `header_line`) cut out; that line must
/// name ppohdem (so the cut line is the header, not data).
std::string without_header(const fs::path& file, std::size_t header_line) {
  const std::string text = bytes(file);
  std::size_t begin = 0;
  for (std::size_t k = 0; k < header_line && begin != std::string::npos; ++k) {
    begin = text.find('\n', begin);
    if (begin != std::string::npos) ++begin;
  }
  const std::size_t end = begin == std::string::npos ? std::string::npos : text.find('\n', begin);
  if (end == std::string::npos) {
    ADD_FAILURE() << file << " has no line " << header_line;
    return text;
  }
  EXPECT_NE(text.substr(begin, end - begin).find("ppohdem"), std::string::npos) << file << ": " << text.substr(begin, end - begin);
  return text.substr(0, begin) + text.substr(end + 1);
}

/// "" if a == b, else their first differing line (whole files would flood the log).
std::string first_difference(const std::string& a, const std::string& b) {
  if (a == b) return "";
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  for (std::size_t line = 1;; ++line) {
    const bool more_a = static_cast<bool>(std::getline(sa, la)), more_b = static_cast<bool>(std::getline(sb, lb));
    if (!more_a && !more_b) return "the same lines, different bytes";
    if (!more_a || !more_b || la != lb) {
      return "line " + std::to_string(line) + ": '" + (more_a ? la : "(end)") + "' against '" + (more_b ? lb : "(end)") + "'";
    }
  }
}

std::string frame(long step, const char* extension) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%06ld.%s", step, extension);
  return name;
}

/// The scene write(dir) makes, with `formats = ["vtk", "pov"]` and frames every `every` steps
/// up to `steps`, run by one process (the one-rank writers) and at 2 and 3 ranks: every .vtk
/// (header line 1) and .pov frame (header line 0) and every listed object file must be the
/// one-process run's. Returns the one-process run's output directory.
fs::path expect_frames_as_one_process(const std::string& name, const std::function<fs::path(const fs::path&)>& write,
                                      long steps, long every, const std::vector<std::string>& object_files = {}) {
  const fs::path one_dir = scratch(name + "_one");
  const CommandResult one = ppohdem::test::run_ppohdem("simulate '" + write(one_dir).string() + "' --engine fast --quiet");
  EXPECT_EQ(one.exit_code, 0) << one.output;
  for (const int ranks : {2, 3}) {
    SCOPED_TRACE(name + ", ranks " + std::to_string(ranks));
    const fs::path dir = scratch(name + "_np" + std::to_string(ranks));
    const CommandResult run = run_mpi(ranks, 1, write(dir), "--engine fast --quiet");
    EXPECT_EQ(run.exit_code, 0) << run.output;
    for (long step = 0; step <= steps; step += every) {
      for (const auto& [extension, header_line] : {std::pair{"vtk", 1}, std::pair{"pov", 0}}) {
        const std::string file = frame(step, extension);
        EXPECT_EQ(first_difference(without_header(dir / "out" / file, header_line),
                                   without_header(one_dir / "out" / file, header_line)), "") << file;
      }
    }
    for (const std::string& file : object_files) {
      EXPECT_EQ(first_difference(without_header(dir / "out" / file, 1), without_header(one_dir / "out" / file, 1)), "") << file;
    }
    // Written by rank 0 alone, temp file then rename: no temp file is left.
    for (const auto& entry : fs::recursive_directory_iterator(dir / "out")) {
      EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << entry.path();
    }
  }
  return one_dir / "out";
}

/// write_bed's scene with legacy VTK and POV-Ray frames.
fs::path write_framed_bed(const fs::path& dir, int nx, int ny, int nz, long steps, long every) {
  const fs::path scene = ppohdem::test::write_bed(dir, nx, ny, nz, steps, every);
  replace_in_scene(scene, "formats = [\"csv\"]", "formats = [\"vtk\", \"pov\"]");
  return scene;
}

}  // namespace

// 7 x 7 x 7 colliding spheres in a walled box, 4 frames: the frames at 2 and 3 ranks (parts of
// 172 + 171 and 115 + 114 + 114 particles) are the one-process frames.
TEST(FramesInPartsMpi, VtkAndPovFramesAreTheOneProcessFrames) {
  const fs::path one = expect_frames_as_one_process(
      "bed", [](const fs::path& dir) { return write_framed_bed(dir, 7, 7, 7, 60, 20); }, 60, 20);
  // Not vacuous: every particle is in the frame, and the last one's vertex is numbered 342.
  const std::string vtk = bytes(one / frame(60, "vtk"));
  EXPECT_NE(vtk.find("POINTS 343 double\n"), std::string::npos);
  EXPECT_NE(vtk.find("\n1 342\nPOINT_DATA 343\n"), std::string::npos);
  const std::string pov = bytes(one / frame(60, "pov"));
  std::size_t spheres = 0;
  for (std::size_t at = 0; (at = pov.find("sphere {", at)) != std::string::npos; ++at) ++spheres;
  EXPECT_EQ(spheres, 343u);
}

// Two particles: at 3 ranks the parts are 1, 1 and 0 particles (an empty part sends empty
// sections and no box).
TEST(FramesInPartsMpi, ARankWithoutParticlesWritesNothingOfItsOwn) {
  const fs::path one = expect_frames_as_one_process(
      "two", [](const fs::path& dir) { return write_framed_bed(dir, 2, 1, 1, 20, 10); }, 20, 10);
  EXPECT_NE(bytes(one / frame(20, "vtk")).find("POINTS 2 double\n"), std::string::npos);
}

// A 6 mm box mesh (mesh_object_mpi_cli_test.cpp's, its display mesh drawn in the POV-Ray frames
// after the spheres and written to objects/) pushed into a 9 x 9 x 9 bed.
TEST(FramesInPartsMpi, AMeshObjectIsDrawnAfterTheSpheres) {
  auto write = [](const fs::path& dir) {
    const fs::path scene = write_framed_bed(dir, 9, 9, 9, 40, 20);
    ppohdem::test::append_box_over_bed(dir, scene,
                                       "[[object.motion]]\nstart = 0.0\ntype = \"rotate\"\naxis = [1.0, 0.0, 0.0]\nomega = 20.0\n");
    return scene;
  };
  const fs::path one = expect_frames_as_one_process("mesh_object", write, 40, 20,
                                                    {"objects/object_0_000000.vtk", "objects/object_0_000040.vtk"});
  const std::string pov = bytes(one / frame(40, "pov"));
  const std::size_t mesh = pov.find("mesh {\n");
  ASSERT_NE(mesh, std::string::npos);
  EXPECT_EQ(pov.find("sphere {", mesh), std::string::npos) << "the mesh comes after the spheres";
}
