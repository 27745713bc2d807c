#include "checks_over_ranks.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace ppohdem::dem {
namespace {

template <class T>
void put(Bytes& out, const T& v) {
  const std::size_t at = out.size();
  out.resize(at + sizeof v);
  std::memcpy(out.data() + at, &v, sizeof v);
}
void put_text(Bytes& out, const std::string& text) {
  put(out, std::uint64_t{text.size()});
  out.insert(out.end(), text.begin(), text.end());
}
template <class T>
T take(const unsigned char*& at) {
  T v;
  std::memcpy(&v, at, sizeof v);
  at += sizeof v;
  return v;
}
std::string take_text(const unsigned char*& at) {
  const auto size = take<std::uint64_t>(at);
  std::string text(reinterpret_cast<const char*>(at), size);
  at += size;
  return text;
}

// SplitMix64's finaliser (Steele, Lea & Flood 2014): consecutive ids spread over the ranks.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

void throw_earliest_error(const Comm& comm, const std::optional<PlacedError>& mine) {
  if (comm.max_over_ranks(mine ? 1.0 : 0.0) == 0.0) return;
  Bytes record;
  put(record, static_cast<std::uint8_t>(mine ? 1 : 0));
  if (mine) {
    put(record, mine->place);
    put(record, std::uint64_t{mine->error.line()});
    put_text(record, mine->error.file());
    put_text(record, mine->error.message());
  }
  std::optional<PlacedError> earliest;
  for (const Bytes& b : comm.allgather(record)) {  // in rank order: a tie keeps the lower rank's
    const unsigned char* at = b.data();
    if (take<std::uint8_t>(at) == 0) continue;
    const auto place = take<std::uint64_t>(at);
    const auto line = take<std::uint64_t>(at);
    std::string file = take_text(at);
    const std::string message = take_text(at);
    if (!earliest || place < earliest->place) earliest = PlacedError{place, InputError(std::move(file), line, message)};
  }
  throw earliest->error;
}

std::size_t first_repeated_id(const Comm& comm, const Particles& mine, std::size_t first) {
  bool increasing = true;
  for (std::size_t i = 1; i < mine.size() && increasing; ++i) increasing = mine[i - 1].id < mine[i].id;
  Bytes summary;
  put(summary, static_cast<std::uint8_t>(increasing ? 1 : 0));
  put(summary, std::uint64_t{mine.size()});
  put(summary, mine.empty() ? std::int64_t{0} : mine.front().id);
  put(summary, mine.empty() ? std::int64_t{0} : mine.back().id);
  bool all_increasing = true;
  std::optional<std::int64_t> last;  // of the shares before
  for (const Bytes& b : comm.allgather(summary)) {
    const unsigned char* at = b.data();
    all_increasing = all_increasing && take<std::uint8_t>(at) == 1;
    if (take<std::uint64_t>(at) == 0) continue;
    const auto front = take<std::int64_t>(at), back = take<std::int64_t>(at);
    if (last && !(*last < front)) all_increasing = false;
    last = back;
  }
  if (all_increasing) return kNoRepeat;
  const auto ranks = static_cast<std::size_t>(comm.size());
  std::vector<Bytes> to(ranks);
  for (std::size_t k = 0; k < mine.size(); ++k) {
    Bytes& block = to[mix(static_cast<std::uint64_t>(mine[k].id)) % ranks];
    put(block, mine[k].id);
    put(block, std::uint64_t{first + k});
  }
  std::vector<std::pair<std::int64_t, std::uint64_t>> seen;  // (id, file index) of the ids hashed here
  for (const Bytes& b : comm.exchange(to)) {
    for (const unsigned char* at = b.data(); at < b.data() + b.size();) {
      const auto id = take<std::int64_t>(at);
      seen.emplace_back(id, take<std::uint64_t>(at));
    }
  }
  std::sort(seen.begin(), seen.end());
  std::uint64_t repeat = kNoRepeat;
  for (std::size_t i = 1; i < seen.size(); ++i) {
    if (seen[i].first == seen[i - 1].first) repeat = std::min(repeat, seen[i].second);  // seen at a smaller index
  }
  Bytes mine_repeat;
  put(mine_repeat, repeat);
  for (const Bytes& b : comm.allgather(mine_repeat)) {
    const unsigned char* at = b.data();
    repeat = std::min(repeat, take<std::uint64_t>(at));
  }
  return static_cast<std::size_t>(repeat);
}

std::optional<std::int64_t> first_unknown_id(const Comm& comm, const std::vector<std::int64_t>& known,
                                             const std::vector<std::int64_t>& asked) {
  const auto ranks = static_cast<std::size_t>(comm.size());
  std::vector<Bytes> to(ranks);
  for (const std::int64_t id : known) {
    Bytes& block = to[mix(static_cast<std::uint64_t>(id)) % ranks];
    put(block, std::uint8_t{0});
    put(block, id);
  }
  for (const std::int64_t id : asked) {
    Bytes& block = to[mix(static_cast<std::uint64_t>(id)) % ranks];
    put(block, std::uint8_t{1});
    put(block, id);
  }
  std::vector<std::int64_t> here, questions;
  for (const Bytes& b : comm.exchange(to)) {
    for (const unsigned char* at = b.data(); at < b.data() + b.size();) {
      const auto asking = take<std::uint8_t>(at);
      (asking ? questions : here).push_back(take<std::int64_t>(at));
    }
  }
  std::sort(here.begin(), here.end());
  std::int64_t unknown = std::numeric_limits<std::int64_t>::max();
  std::uint8_t found = 0;
  for (const std::int64_t id : questions) {
    if (!std::binary_search(here.begin(), here.end(), id) && (!found || id < unknown)) {
      unknown = id;
      found = 1;
    }
  }
  Bytes mine;
  put(mine, found);
  put(mine, unknown);
  std::optional<std::int64_t> first;
  for (const Bytes& b : comm.allgather(mine)) {
    const unsigned char* at = b.data();
    const bool has = take<std::uint8_t>(at) != 0;
    const auto id = take<std::int64_t>(at);
    if (has && (!first || id < *first)) first = id;
  }
  return first;
}

}  // namespace ppohdem::dem
