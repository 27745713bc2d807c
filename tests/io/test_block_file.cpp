// BlockFileWriter (ppohdem/io/block_file.hpp): the file holds exactly the bytes written, for
// sizes on both sides of the O_DIRECT alignment (4 KiB) and of the 4 MiB block, written in
// pieces of awkward sizes; in the build directory and in /dev/shm (tmpfs, which refuses O_DIRECT
// before Linux 6.6: the buffered path there); no temp file is left behind, and a
// writer destroyed without commit leaves no file and any earlier target untouched.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "ppohdem/io/block_file.hpp"

namespace fs = std::filesystem;

namespace {

std::string pattern(std::size_t n) {
  std::string s(n, '\0');
  std::uint32_t x = 12345;
  for (char& c : s) {
    x = x * 1664525u + 1013904223u;  // any bytes, NUL included
    c = static_cast<char>(x >> 24);
  }
  return s;
}

std::string contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<fs::path> directories() {
  std::vector<fs::path> dirs{fs::current_path() / ("block_file_test_" + std::to_string(::getpid()))};
  if (fs::is_directory("/dev/shm")) dirs.push_back(fs::path("/dev/shm") / ("ppohdem_block_file_test_" + std::to_string(::getpid())));
  return dirs;
}

}  // namespace

TEST(BlockFileWriter, WritesExactlyTheBytesGiven) {
  const std::size_t mib = std::size_t{1} << 20;
  for (const fs::path& dir : directories()) {
    for (const bool bypass : {true, false}) {  // O_DIRECT if the file system takes it; buffered
      fs::create_directories(dir);
      for (const std::size_t size : {std::size_t{0}, std::size_t{1}, std::size_t{4095}, std::size_t{4096},
                                     std::size_t{4097}, 4 * mib - 1, 4 * mib, 4 * mib + 1, 9 * mib + 3}) {
        SCOPED_TRACE(dir.string() + ", " + std::to_string(size) + " bytes, bypass " + std::to_string(bypass));
        const std::string data = pattern(size);
        const fs::path file = dir / "out.bin";
        {
          ppohdem::BlockFileWriter w(file, bypass);
          if (!bypass) EXPECT_FALSE(w.direct());
          std::size_t at = 0, piece = 1;
          while (at < size) {  // pieces of 1, 4, 16, ... bytes, up to 1 MiB + 7
            const std::size_t n = std::min(size - at, piece);
            w.write(data.data() + at, n);
            at += n;
            piece = std::min(piece * 4, mib + 7);
          }
          w.commit(/*sync_to_disk=*/size == 4097);
        }
        EXPECT_EQ(fs::file_size(file), size);
        EXPECT_TRUE(contents(file) == data);
        EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1) << "a temp file left";
      }
      fs::remove_all(dir);
    }
  }
}

TEST(BlockFileWriter, WithoutCommitNothingChanges) {
  for (const fs::path& dir : directories()) {
    fs::create_directories(dir);
    const fs::path file = dir / "out.csv";
    std::ofstream(file) << "earlier\n";
    {
      ppohdem::BlockFileWriter w(file);
      const std::string data = pattern(5 << 20);
      w.write(data.data(), data.size());
    }
    EXPECT_EQ(contents(file), "earlier\n");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1) << "a temp file left";
    fs::remove_all(dir);
  }
}

TEST(BlockFileWriter, AMissingDirectoryIsNamed) {
  try {
    ppohdem::BlockFileWriter w("/nonexistent_dir_ppohdem/x.csv");
    ADD_FAILURE() << "opened";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("directory '/nonexistent_dir_ppohdem' does not exist"), std::string::npos)
        << e.what();
  }
}
