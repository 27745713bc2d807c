// The checkpoint file format (ppohdem/dem/checkpoint.hpp): exact round trip, little-endian
// layout, and refusal of every damaged file: each single flipped byte, each truncation, a
// file of another format version (refused by name), a file that is not a checkpoint, and a
// record count that the file cannot hold (refused before allocating).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "ppohdem/dem/checkpoint.hpp"

namespace ppohdem::dem {
namespace {

/// A small checkpoint whose doubles include the awkward ones (-0, denormal, huge).
Checkpoint sample() {
  Checkpoint c;
  c.provenance = "test provenance";
  c.scene = "scene.toml";
  EngineState& e = c.engine;
  e.engine = "reference";
  e.step = 123456789012L;
  e.dt = 1.0e-5;
  for (int i = 0; i < 3; ++i) {
    Particle p;
    p.id = -5 + 1000000007LL * i;
    p.position = Vec3(-0.0, std::numeric_limits<double>::denorm_min(), 1e300 * (i + 1));
    p.velocity = Vec3(0.1 * i, -2.5, 3.0);
    p.angular_velocity = Vec3(1, 2, 3) * (i + 0.5);
    p.radius = 1e-3 * (i + 1);
    p.material = static_cast<std::uint16_t>(i == 2 ? 65535 : i);  // the largest index too
    p.force = Vec3(std::nextafter(1.0, 2.0), -1e-300, 7.0);
    p.torque = Vec3(4, 5, 6);
    e.particles.push_back(p);
  }
  ContactHistoryRecord pair;
  pair.id_a = -5;
  pair.id_b = 1000000002;
  pair.spring.displacement = Vec3(1e-7, -2e-7, 0.0);
  pair.spring.stiffness = 1234.5;
  pair.spring.branch_i = Vec3(0, 0, 1e-3);
  pair.spring.branch_j = Vec3(0, 0, -1e-3);
  ContactHistoryRecord wall = pair;
  wall.kind = ContactHistoryRecord::Kind::kParticleBoundary;
  wall.id_b = 3;
  wall.spring.branch_j = Vec3::Zero();
  wall.spring.surface_velocity = Vec3(0.25, -0.5, 1e-9);
  e.contacts = {pair, wall};
  e.accumulators = Energies{1, 2, -3, 4, 5, 6};
  e.escaped_ids = {7, 9};
  e.boundary_loads.resize(4);
  e.boundary_loads[3].force = Vec3(1, -1, 2);
  e.contact_counts = {11, 12};
  e.boundary_power = -3.5e-7;
  e.engine_private = {0, 255, 17};
  c.objects.push_back({"ball", Quat(0.5, 0.5, -0.5, 0.5), Vec3(1, 2, 3), 42});
  c.insertion.counters = {{3, 400, 30, 28, 2}, {0, 0, 0, 0, 0}};
  c.insertion.kinetic = 0.125;
  c.insertion.gravitational = -1e-300;
  c.insertion.rows = {"0,0,0,10,10,0,10,0"};
  c.run.energy_rows = {"0,0,1,2,3,4,5,6", "10,1e-4,1,2,3,4,5,6"};
  c.run.object_rows = {"0,0,0,..."};
  c.run.frames = 3;
  return c;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::string refusal(const std::vector<std::uint8_t>& bytes) {
  try {
    decode_checkpoint(bytes, "ck.bin");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::uint32_t read_u32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8 |
         static_cast<std::uint32_t>(b[at + 2]) << 16 | static_cast<std::uint32_t>(b[at + 3]) << 24;
}
void write_u32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) b[at + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(v >> (8 * k));
}

// Where the header ends: magic 8, version 4, build length 4 + build, payload length 8.
std::size_t header_length(const std::vector<std::uint8_t>& b) { return 16 + read_u32(b, 12) + 8; }

TEST(CheckpointFormat, Crc32IsTheStandardCrc32) {
  // The CRC-32 (ISO-HDLC) check value of "123456789" from the CRC catalogue
  // (reveng.sourceforge.io/crc-catalogue): 0xCBF43926.
  const char* text = "123456789";
  EXPECT_EQ(crc32_of(reinterpret_cast<const std::uint8_t*>(text), 9), 0xCBF43926u);
}

TEST(CheckpointFormat, RoundTripKeepsEveryBit) {
  const Checkpoint c = sample();
  const Checkpoint d = decode_checkpoint(encode_checkpoint(c), "memory");
  EXPECT_EQ(d.build, checkpoint_build_name());
  EXPECT_EQ(d.provenance, c.provenance);
  EXPECT_EQ(d.scene, c.scene);
  EXPECT_EQ(d.engine.engine, "reference");
  EXPECT_EQ(d.engine.step, c.engine.step);
  ASSERT_EQ(d.engine.particles.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const Particle& p = c.engine.particles[i];
    const Particle& q = d.engine.particles[i];
    EXPECT_EQ(p.id, q.id);
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(same_bits(p.position[k], q.position[k]) && same_bits(p.velocity[k], q.velocity[k]) &&
                  same_bits(p.angular_velocity[k], q.angular_velocity[k]) && same_bits(p.force[k], q.force[k]) &&
                  same_bits(p.torque[k], q.torque[k]));
    }
    EXPECT_TRUE(same_bits(p.radius, q.radius));
    EXPECT_EQ(p.material, q.material);
  }
  EXPECT_TRUE(std::signbit(d.engine.particles[0].position.x()));  // -0.0 stays -0.0
  ASSERT_EQ(d.engine.contacts.size(), 2u);
  EXPECT_EQ(d.engine.contacts[1].kind, ContactHistoryRecord::Kind::kParticleBoundary);
  EXPECT_EQ(d.engine.contacts[0].id_b, 1000000002);
  EXPECT_EQ(d.engine.contacts[0].spring.displacement, c.engine.contacts[0].spring.displacement);
  EXPECT_EQ(d.engine.contacts[0].spring.branch_j, c.engine.contacts[0].spring.branch_j);
  EXPECT_EQ(d.engine.accumulators.boundary_work, 6.0);
  EXPECT_EQ(d.engine.escaped_ids, c.engine.escaped_ids);
  EXPECT_EQ(d.engine.boundary_loads.at(3).force, Vec3(1, -1, 2));
  EXPECT_EQ(d.engine.contact_counts.particle_boundary, 12u);
  EXPECT_EQ(d.engine.contacts[1].spring.surface_velocity, c.engine.contacts[1].spring.surface_velocity);
  EXPECT_EQ(d.engine.boundary_power, -3.5e-7);
  EXPECT_EQ(d.engine.engine_private, c.engine.engine_private);
  ASSERT_EQ(d.objects.size(), 1u);
  EXPECT_EQ(d.objects[0].rotation.coeffs(), c.objects[0].rotation.coeffs());
  EXPECT_EQ(d.objects[0].outside_grid, 42u);
  EXPECT_EQ(d.run.energy_rows, c.run.energy_rows);
  EXPECT_EQ(d.run.object_rows, c.run.object_rows);
  EXPECT_EQ(d.run.frames, 3u);
  ASSERT_EQ(d.insertion.counters.size(), 2u);
  EXPECT_EQ(d.insertion.counters[0].draws, 400u);
  EXPECT_EQ(d.insertion.counters[0].failed, 2);
  EXPECT_EQ(d.insertion.kinetic, 0.125);
  EXPECT_EQ(d.insertion.gravitational, -1e-300);
  EXPECT_EQ(d.insertion.rows, c.insertion.rows);
}

// An older version's file: this build's encoding with the last `cut` payload bytes (fields the
// older version did not have, all empty) removed, then version, length and CRCs fixed.
std::vector<std::uint8_t> as_older_version(std::vector<std::uint8_t> b, std::uint32_t version, std::size_t cut) {
  const std::size_t header = header_length(b);
  b.erase(b.end() - 4 - static_cast<std::ptrdiff_t>(cut), b.end() - 4);
  write_u32(b, 8, version);
  std::uint64_t payload = b.size() - header - 8;
  for (int k = 0; k < 8; ++k) b[header - 8 + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(payload >> (8 * k));
  write_u32(b, header, crc32_of(b.data(), header));
  write_u32(b, b.size() - 4, crc32_of(b.data() + header + 4, static_cast<std::size_t>(payload)));
  return b;
}

TEST(CheckpointFormat, Version4WithoutPartsIsStillRead) {
  // A version-4 file is a single version-5 file without the part table (u64 0: 8 bytes).
  const Checkpoint c = sample();
  const Checkpoint d = decode_checkpoint(as_older_version(encode_checkpoint(c), 4, 8), "v4");
  EXPECT_EQ(d.run.frames, 3u);
  EXPECT_EQ(d.insertion.rows, c.insertion.rows);
  EXPECT_TRUE(d.parts.empty());
  EXPECT_EQ(d.engine.particles.size(), 3u);
}

TEST(CheckpointFormat, Version3WithoutInsertionsIsStillRead) {
  // A version-3 file is a version-4 file without the insertion record (which, empty, is
  // u64 0, 3 x f64 0, u64 0: 40 bytes), before the part table.
  Checkpoint c = sample();
  c.insertion = InsertionRecord{};
  const Checkpoint d = decode_checkpoint(as_older_version(encode_checkpoint(c), 3, 40 + 8), "v3");
  EXPECT_EQ(d.run.frames, 3u);
  EXPECT_TRUE(d.insertion.counters.empty());
  EXPECT_EQ(d.engine.particles.size(), 3u);
}

TEST(CheckpointFormat, LayoutIsLittleEndianWithMagicVersionAndBuild) {
  const std::vector<std::uint8_t> b = encode_checkpoint(sample());
  EXPECT_EQ(std::string(b.begin(), b.begin() + 8), "PPOHDEMC");
  EXPECT_EQ(std::vector<std::uint8_t>(b.begin() + 8, b.begin() + 12),
            (std::vector<std::uint8_t>{static_cast<std::uint8_t>(kCheckpointFormatVersion), 0, 0, 0}));
  const std::uint32_t n = read_u32(b, 12);
  EXPECT_EQ(std::string(b.begin() + 16, b.begin() + 16 + n), checkpoint_build_name());
  // Payload length (u64 LE) = file - header - header CRC - payload CRC.
  std::uint64_t payload = 0;
  for (int k = 0; k < 8; ++k) payload |= static_cast<std::uint64_t>(b[16 + n + static_cast<std::size_t>(k)]) << (8 * k);
  EXPECT_EQ(payload, b.size() - header_length(b) - 8);
  // The two CRCs, recomputed here over the documented ranges.
  EXPECT_EQ(read_u32(b, header_length(b)), crc32_of(b.data(), header_length(b)));
  EXPECT_EQ(read_u32(b, b.size() - 4), crc32_of(b.data() + header_length(b) + 4, payload));
  // The first payload field: u64 length of the provenance string, then its bytes.
  const std::size_t p = header_length(b) + 4;
  EXPECT_EQ(b[p], 15u);  // "test provenance"
  EXPECT_EQ(std::string(b.begin() + static_cast<std::ptrdiff_t>(p + 8), b.begin() + static_cast<std::ptrdiff_t>(p + 23)),
            "test provenance");
}

TEST(CheckpointFormat, EveryFlippedByteIsRefused) {
  const std::vector<std::uint8_t> good = encode_checkpoint(sample());
  const std::size_t header = header_length(good);
  for (std::size_t i = 0; i < good.size(); ++i) {
    std::vector<std::uint8_t> bad = good;
    bad[i] ^= 0x10;
    const std::string message = refusal(bad);
    ASSERT_FALSE(message.empty()) << "byte " << i << " flipped was accepted";
    if (i < 8) {
      EXPECT_NE(message.find("not a ppohdem checkpoint"), std::string::npos) << message;
    } else if (i < header + 4) {
      // The header CRC covers version, build and length; a flip in the CRC itself too.
      EXPECT_NE(message.find("header is corrupted"), std::string::npos) << "byte " << i << ": " << message;
    } else {
      EXPECT_NE(message.find("data is corrupted (CRC-32"), std::string::npos) << "byte " << i << ": " << message;
    }
  }
}

TEST(CheckpointFormat, EveryTruncationIsRefused) {
  const std::vector<std::uint8_t> good = encode_checkpoint(sample());
  const std::size_t header = header_length(good);
  for (std::size_t n = 0; n < good.size(); ++n) {
    const std::vector<std::uint8_t> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n));
    const std::string message = refusal(cut);
    ASSERT_FALSE(message.empty()) << "truncated to " << n << " bytes was accepted";
    if (n >= header + 4) {
      EXPECT_NE(message.find("checkpoint is truncated: the header announces " + std::to_string(good.size()) +
                             " bytes, the file has " + std::to_string(n)),
                std::string::npos)
          << message;
    }
  }
  std::vector<std::uint8_t> longer = good;
  longer.push_back(0);
  EXPECT_NE(refusal(longer).find("too long"), std::string::npos);
}

TEST(CheckpointFormat, AnotherFormatVersionIsRefusedByName) {
  // Older layouts (1: before the particles' material index, 2: before the rolling spring) and
  // a newer one (3, before the insertion record, is still read: test above).
  for (const std::uint32_t version : {1u, kOldestCheckpointFormatVersion - 1, kCheckpointFormatVersion + 1}) {
    std::vector<std::uint8_t> b = encode_checkpoint(sample());
    write_u32(b, 8, version);  // a consistent header (its CRC recomputed)
    write_u32(b, header_length(b), crc32_of(b.data(), header_length(b)));
    const std::string message = refusal(b);
    EXPECT_NE(message.find("checkpoint format version " + std::to_string(version) + ", written by " +
                           checkpoint_build_name()),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("reads format versions " + std::to_string(kOldestCheckpointFormatVersion) + " to " +
                           std::to_string(kCheckpointFormatVersion)),
              std::string::npos)
        << message;
  }
}

TEST(CheckpointFormat, OtherFilesAreNotCheckpoints) {
  const std::string text = "step,time,kinetic\n0,0,1\n";
  EXPECT_NE(refusal(std::vector<std::uint8_t>(text.begin(), text.end())).find("not a ppohdem checkpoint"),
            std::string::npos);
  EXPECT_NE(refusal({}).find("not a ppohdem checkpoint"), std::string::npos);
}

TEST(CheckpointFormat, ACountTheFileCannotHoldIsRefusedBeforeAllocating) {
  // A checksummed payload that announces 2^60 particles: encode a real one, patch the count
  // and recompute the payload CRC, as a writer with a bug (or a forger) would.
  Checkpoint c = sample();
  c.provenance.clear();
  c.scene.clear();
  std::vector<std::uint8_t> b = encode_checkpoint(c);
  const std::size_t p = header_length(b) + 4;            // payload start
  const std::size_t count_at = p + 8 + 8 + 8 + 9 + 8 + 8;  // 2 empty strings, "reference", step, dt
  ASSERT_EQ(b[count_at], 3u);                             // the particle count
  b[count_at + 7] = 0x10;                                 // 2^60 + 3
  write_u32(b, b.size() - 4, crc32_of(b.data() + p, b.size() - p - 4));
  const std::string message = refusal(b);
  EXPECT_NE(message.find("particles: a count of 1152921504606846979 records"), std::string::npos) << message;
}

TEST(CheckpointFormat, FileRoundTripLeavesNoTempFiles) {
  const auto dir = std::filesystem::temp_directory_path() / ("ppohdem_ckfmt_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_checkpoint(dir / "c.bin", sample());
  write_checkpoint(dir / "c.bin", sample());  // replaced atomically
  EXPECT_EQ(read_checkpoint(dir / "c.bin").engine.step, sample().engine.step);
  // The file (streamed in 1 MiB pieces) holds exactly encode_checkpoint's bytes, also for a
  // payload of several pieces (20,000 particles, 3 MB).
  Checkpoint large = sample();
  for (int i = 0; i < 20000; ++i) {
    large.engine.particles.push_back(large.engine.particles[static_cast<std::size_t>(i % 3)]);
    large.engine.particles.back().id = 10 + i;
  }
  for (const Checkpoint& c : {sample(), large}) {
    write_checkpoint(dir / "c.bin", c);
    std::ifstream in(dir / "c.bin", std::ios::binary);
    const std::vector<std::uint8_t> file{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_GT(file.size(), c.engine.particles.size() * 140);  // 140 bytes a particle
    EXPECT_TRUE(file == encode_checkpoint(c));
  }
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "c.bin");
  }
  EXPECT_EQ(files, 1u);
  EXPECT_THROW(read_checkpoint(dir / "missing.bin"), InputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ppohdem::dem
