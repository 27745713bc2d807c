// Checkpoints written per rank (ppohdem/dem/checkpoint.hpp "Parts"): a part's exact round trip
// and refusal of every damaged part (each flipped byte, each truncation, a rank or
// construction index out of range), the merge of the parts into the whole state (placed by
// construction index, lists sorted) against the state they were cut from, the merge's
// refusals (another step, rank, count, a particle twice or missing), and the files on disk:
// write_checkpoint_parts on one rank, read back, old parts removed, a manifest naming a
// missing part or a path outside its directory refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <tuple>
#include <unistd.h>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/checkpoint.hpp"

namespace ppohdem::dem {
namespace {

namespace fs = std::filesystem;

/// The whole state: 7 particles (ids unrelated to order), pair and wall histories, escaped ids.
EngineState whole_state() {
  EngineState e;
  e.engine = "fast";
  e.step = 4200;
  e.dt = 1.0e-5;
  for (int i = 0; i < 7; ++i) {
    Particle p;
    p.id = 1000 - 37 * i;
    p.position = Vec3(-0.0, std::numeric_limits<double>::denorm_min() * i, 1e300 / (i + 1));
    p.velocity = Vec3(0.1 * i, -2.5, 3.0);
    p.radius = 1e-3 * (i + 1);
    p.material = static_cast<std::uint16_t>(i % 2);
    p.force = Vec3(std::nextafter(1.0, 2.0), -1e-300, 7.0 * i);
    e.particles.push_back(p);
  }
  for (int i = 0; i < 5; ++i) {
    ContactHistoryRecord c;
    c.kind = i % 2 ? ContactHistoryRecord::Kind::kParticleBoundary : ContactHistoryRecord::Kind::kParticlePair;
    c.id_a = 1000 - 37 * i;
    c.id_b = i % 2 ? i : 1000 - 37 * (i + 1);
    c.spring.displacement = Vec3(1e-7 * i, -2e-7, 0.0);
    c.spring.stiffness = 1234.5 + i;
    e.contacts.push_back(c);
  }
  std::sort(e.contacts.begin(), e.contacts.end(), [](const auto& a, const auto& b) {
    return std::tuple(a.kind, a.id_a, a.id_b) < std::tuple(b.kind, b.id_a, b.id_b);
  });
  e.escaped_ids = {1000 - 37 * 6, 1000 - 37 * 2};
  std::sort(e.escaped_ids.begin(), e.escaped_ids.end());
  e.accumulators = Energies{1, 2, -3, 4, 5, 6};
  e.boundary_loads.resize(2);
  e.contact_counts = {3, 2};
  e.boundary_power = -3.5e-7;
  return e;
}

/// The whole state cut into 3 parts by construction index (i % 3, in a scrambled order inside
/// each part), each contact and escaped id with the owner of its first particle.
std::vector<CheckpointPart> cut_into_parts(const EngineState& e) {
  std::vector<CheckpointPart> parts(3);
  auto owner = [&](std::int64_t id) {
    for (std::size_t i = 0; i < e.particles.size(); ++i) {
      if (e.particles[i].id == id) return i % 3;
    }
    return std::size_t{0};
  };
  for (std::size_t r = 0; r < 3; ++r) {
    parts[r].step = e.step;
    parts[r].rank = static_cast<std::uint32_t>(r);
    parts[r].ranks = 3;
    parts[r].total = e.particles.size();
  }
  for (std::size_t i = e.particles.size(); i-- > 0;) {  // reversed: the merge must place them
    parts[i % 3].order.push_back(i);
    parts[i % 3].particles.push_back(e.particles[i]);
  }
  for (const ContactHistoryRecord& c : e.contacts) parts[owner(c.id_a)].contacts.push_back(c);
  for (const std::int64_t id : e.escaped_ids) parts[owner(id)].escaped_ids.push_back(id);
  return parts;
}

/// A manifest for `parts` (entries with their counts and CRCs), lists empty.
Checkpoint manifest_for(const EngineState& e, const std::vector<CheckpointPart>& parts) {
  Checkpoint c;
  c.provenance = "test";
  c.engine = e;
  c.engine.particles.clear();
  c.engine.contacts.clear();
  c.engine.escaped_ids.clear();
  c.run.energy_rows = {"0,0,1,2,3,4,5,6"};
  for (const CheckpointPart& p : parts) {
    const std::vector<std::uint8_t> b = encode_checkpoint_part(p);
    CheckpointPartEntry entry;
    entry.file = "checkpoint.bin.parts/step_0000004200.rank_" + std::to_string(p.rank) + "_of_3.bin";
    entry.particles = p.particles.size();
    entry.contacts = p.contacts.size();
    entry.escaped = p.escaped_ids.size();
    entry.payload_crc = static_cast<std::uint32_t>(b[b.size() - 4]) | static_cast<std::uint32_t>(b[b.size() - 3]) << 8 |
                        static_cast<std::uint32_t>(b[b.size() - 2]) << 16 |
                        static_cast<std::uint32_t>(b[b.size() - 1]) << 24;
    c.parts.push_back(entry);
  }
  return c;
}

std::vector<std::string> sources(std::size_t n) {
  std::vector<std::string> s;
  for (std::size_t k = 0; k < n; ++k) s.push_back("part" + std::to_string(k));
  return s;
}

std::string merge_refusal(const EngineState& e, std::vector<CheckpointPart> parts) {
  Checkpoint c = manifest_for(e, parts);
  try {
    merge_checkpoint_parts(c, parts, sources(parts.size()));
  } catch (const InputError& ex) {
    return ex.what();
  }
  return "";
}

std::string part_refusal(const std::vector<std::uint8_t>& bytes) {
  try {
    decode_checkpoint_part(bytes, "p.bin");
  } catch (const InputError& ex) {
    return ex.what();
  }
  return "";
}

void expect_same_state(const EngineState& a, const EngineState& b) {
  // Re-encoded, the two states must give the same bytes (every field, bit for bit).
  Checkpoint x, y;
  x.engine = a;
  y.engine = b;
  EXPECT_EQ(encode_checkpoint(x), encode_checkpoint(y));
}

TEST(CheckpointParts, PartRoundTripKeepsEveryBit) {
  for (const CheckpointPart& p : cut_into_parts(whole_state())) {
    const std::vector<std::uint8_t> b = encode_checkpoint_part(p);
    EXPECT_EQ(std::string(b.begin(), b.begin() + 8), "PPOHDEMP");
    const CheckpointPart d = decode_checkpoint_part(b, "p.bin");
    EXPECT_EQ(d.step, p.step);
    EXPECT_EQ(d.rank, p.rank);
    EXPECT_EQ(d.ranks, p.ranks);
    EXPECT_EQ(d.total, p.total);
    EXPECT_EQ(d.order, p.order);
    EXPECT_EQ(d.escaped_ids, p.escaped_ids);
    EXPECT_EQ(encode_checkpoint_part(d), b);
  }
}

TEST(CheckpointParts, EveryFlippedByteAndTruncationIsRefused) {
  const std::vector<std::uint8_t> good = encode_checkpoint_part(cut_into_parts(whole_state())[1]);
  for (std::size_t i = 0; i < good.size(); ++i) {
    std::vector<std::uint8_t> bad = good;
    bad[i] ^= 0x10;
    const std::string message = part_refusal(bad);
    ASSERT_FALSE(message.empty()) << "byte " << i << " flipped was accepted";
    EXPECT_EQ(message.rfind("p.bin: ", 0), 0u) << message;
  }
  for (std::size_t n = 0; n < good.size(); ++n) {
    const std::string message = part_refusal(std::vector<std::uint8_t>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n)));
    ASSERT_FALSE(message.empty()) << "truncated to " << n << " bytes was accepted";
  }
  EXPECT_NE(part_refusal(std::vector<std::uint8_t>(good.begin(), good.end() - 1))
                .find("checkpoint part is truncated: the header announces " + std::to_string(good.size()) +
                      " bytes, the file has " + std::to_string(good.size() - 1)),
            std::string::npos);
  // A whole checkpoint is not a part (the magic bytes say which is which).
  Checkpoint c;
  EXPECT_NE(part_refusal(encode_checkpoint(c)).find("not a ppohdem checkpoint part (expected the magic bytes 'PPOHDEMP'"),
            std::string::npos);
}

TEST(CheckpointParts, RankOrIndexOutOfRangeIsRefused) {
  CheckpointPart p = cut_into_parts(whole_state())[2];
  p.rank = 3;
  EXPECT_NE(part_refusal(encode_checkpoint_part(p)).find("rank 3 of 3, expected a rank below the count"),
            std::string::npos);
  p.rank = 2;
  p.order[0] = 7;
  EXPECT_NE(part_refusal(encode_checkpoint_part(p)).find("construction index 7, expected below the total of 7"),
            std::string::npos);
}

TEST(CheckpointParts, MergedPartsAreTheWholeState) {
  const EngineState whole = whole_state();
  const std::vector<CheckpointPart> parts = cut_into_parts(whole);
  Checkpoint c = manifest_for(whole, parts);
  merge_checkpoint_parts(c, parts, sources(3));
  EXPECT_TRUE(c.parts.empty());
  ASSERT_EQ(c.engine.particles.size(), whole.particles.size());
  for (std::size_t i = 0; i < whole.particles.size(); ++i) EXPECT_EQ(c.engine.particles[i].id, whole.particles[i].id);
  expect_same_state(c.engine, whole);
}

TEST(CheckpointParts, MismatchedPartsAreRefused) {
  const EngineState e = whole_state();
  {
    auto parts = cut_into_parts(e);
    parts[1].step = 4100;
    EXPECT_NE(merge_refusal(e, parts).find("part1: checkpoint part: step 4100; the manifest expects part 1 of 3 at step 4200"),
              std::string::npos);
  }
  {
    auto parts = cut_into_parts(e);
    std::swap(parts[0], parts[2]);
    EXPECT_NE(merge_refusal(e, parts).find("part0: checkpoint part: rank 2 of 3; the manifest expects part 0 of 3"),
              std::string::npos);
  }
  {  // the manifest's counts: a part with a contact more than it lists
    auto parts = cut_into_parts(e);
    Checkpoint c = manifest_for(e, parts);
    parts[0].contacts.push_back(parts[0].contacts.front());
    std::string message;
    try {
      merge_checkpoint_parts(c, parts, sources(3));
    } catch (const InputError& ex) {
      message = ex.what();
    }
    EXPECT_NE(message.find("part0: checkpoint part: " + std::to_string(parts[0].particles.size()) + " particles, " +
                           std::to_string(parts[0].contacts.size()) + " contacts"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("the manifest lists"), std::string::npos) << message;
  }
  {  // a particle in two parts (and so one missing)
    auto parts = cut_into_parts(e);
    parts[2].order[0] = parts[0].order[0];
    EXPECT_NE(merge_refusal(e, parts).find("part2: checkpoint part: construction index " + std::to_string(parts[0].order[0]) +
                                           " appears in two parts"),
              std::string::npos);
  }
  {  // a particle missing
    auto parts = cut_into_parts(e);
    parts[1].order.pop_back();
    parts[1].particles.pop_back();
    EXPECT_NE(merge_refusal(e, parts).find("the parts hold 6 particles, expected their total of 7"), std::string::npos);
  }
}

TEST(CheckpointParts, AManifestHoldsNoParticles) {
  const EngineState e = whole_state();
  Checkpoint c = manifest_for(e, cut_into_parts(e));
  c.engine.escaped_ids = {1};
  try {
    decode_checkpoint(encode_checkpoint(c), "m.bin");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& ex) {
    EXPECT_NE(std::string(ex.what()).find("a manifest of 3 parts must hold no particles, contacts or escaped ids"),
              std::string::npos)
        << ex.what();
  }
}

// On disk, one rank (SerialComm): the part and the manifest, read back as the whole state; a
// part of the next step without its manifest changes nothing; a later checkpoint replaces the
// earlier one's part; missing and outside parts refused.
TEST(CheckpointParts, FilesOnDiskReadBackAndReplaceTheirPredecessor) {
  const fs::path dir = fs::temp_directory_path() / ("ppohdem_parts_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const SerialComm comm;
  EngineState e = whole_state();
  auto share_of = [](const EngineState& state) {
    EngineStateShare share;
    share.state = state;
    share.total = state.particles.size();
    for (std::size_t i = 0; i < state.particles.size(); ++i) share.order.push_back(i);
    return share;
  };
  Checkpoint c;
  c.provenance = "test";
  c.run.energy_rows = {"0,0,1,2,3,4,5,6"};
  write_checkpoint_parts(dir / "checkpoint.bin", c, share_of(e), comm);
  EXPECT_TRUE(fs::exists(dir / "checkpoint.bin.parts" / "step_0000004200.rank_0_of_1.bin"));
  expect_same_state(read_checkpoint(dir / "checkpoint.bin").engine, e);
  // A run killed after writing the next checkpoint's part, before its manifest: the manifest
  // on disk still names the complete earlier checkpoint, which reads as before.
  const EngineState earlier = e;
  e.step = 4300;
  e.particles[3].velocity.x() = -1.0;
  {
    CheckpointPart next;
    next.step = e.step;
    next.total = e.particles.size();
    next.particles = e.particles;
    for (std::size_t i = 0; i < e.particles.size(); ++i) next.order.push_back(i);
    const std::vector<std::uint8_t> b = encode_checkpoint_part(next);
    std::ofstream(dir / "checkpoint.bin.parts" / "step_0000004300.rank_0_of_1.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  }
  expect_same_state(read_checkpoint(dir / "checkpoint.bin").engine, earlier);
  write_checkpoint_parts(dir / "checkpoint.bin", c, share_of(e), comm);
  EXPECT_FALSE(fs::exists(dir / "checkpoint.bin.parts" / "step_0000004200.rank_0_of_1.bin"));
  const Checkpoint back = read_checkpoint(dir / "checkpoint.bin");
  EXPECT_TRUE(back.parts.empty());
  expect_same_state(back.engine, e);
  // A manifest naming a path outside its directory, and one naming a part that is not there.
  std::ifstream in(dir / "checkpoint.bin", std::ios::binary);
  Checkpoint m = decode_checkpoint({std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()}, "m");
  for (const std::string& name : {std::string("../elsewhere.bin"), (dir / "x.bin").string()}) {
    m.parts[0].file = name;
    write_checkpoint(dir / "bad.bin", m);
    try {
      read_checkpoint(dir / "bad.bin");
      ADD_FAILURE() << name << " accepted";
    } catch (const InputError& ex) {
      EXPECT_NE(std::string(ex.what()).find("checkpoint: part 0 is named '" + name +
                                            "', expected a path relative to the manifest's directory"),
                std::string::npos)
          << ex.what();
    }
  }
  m.parts[0].file = "checkpoint.bin.parts/step_0000004200.rank_0_of_1.bin";
  write_checkpoint(dir / "bad.bin", m);
  try {
    read_checkpoint(dir / "bad.bin");
    ADD_FAILURE() << "a missing part accepted";
  } catch (const InputError& ex) {
    EXPECT_NE(std::string(ex.what()).find((dir / "bad.bin").string() + ": checkpoint: part 0 of 1, " +
                                          (dir / "checkpoint.bin.parts/step_0000004200.rank_0_of_1.bin").string() +
                                          ", does not exist"),
              std::string::npos)
        << ex.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ppohdem::dem
