#pragma once
// Checks of particles spread over the ranks (each rank holding a share of a file) that every
// rank must answer alike, and as one rank holding them all would (docs/dem.md "Reading on
// every rank"). Private to core/src/dem.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/particle.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::dem {

/// A rank's first error and its place in file order (a line or a particle's index: smaller is
/// earlier).
struct PlacedError {
  std::uint64_t place = 0;
  InputError error;
};

/// Collective: if any rank has an error, every rank throws the earliest one (a tie: the lower
/// rank's). One allreduce when none has; an allgather of the messages when one has.
void throw_earliest_error(const Comm& comm, const std::optional<PlacedError>& mine);

inline constexpr std::size_t kNoRepeat = std::numeric_limits<std::size_t>::max();

/// Collective: the file index of the earliest particle whose id an earlier particle has (the
/// second of a pair), over all the ranks' shares, or kNoRepeat. `mine` are the particles
/// [first, first + mine.size()) of the file. Ids that increase across the shares (most files)
/// need one allgather of each share's first and last id; otherwise each (id, index) goes to the
/// rank its id hashes to, which finds the repeats among its ids.
std::size_t first_repeated_id(const Comm& comm, const Particles& mine, std::size_t first);

/// Collective: the smallest of the ids `asked` on any rank that no rank lists in `known`, or
/// none. Each id goes to the rank it hashes to, which compares the two sets there.
std::optional<std::int64_t> first_unknown_id(const Comm& comm, const std::vector<std::int64_t>& known,
                                             const std::vector<std::int64_t>& asked);

}  // namespace ppohdem::dem
