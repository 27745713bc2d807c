#pragma once
// One file from every rank's part, in rank order, without any rank holding every part: the
// particle CSV files, legacy VTK and POV-Ray frames under mpirun (docs/dem.md "Reading on
// every rank"). Private to core/src/dem.
#include <utility>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/io/block_file.hpp"

namespace ppohdem::dem {

/// Rank 0 writes its `text`, then every other rank's in rank order, taking one rank's text at
/// a time (it asks rank r for it when it gets there); the others send theirs. `writer` is used
/// on rank 0 only. Collective: every rank calls it at the same point.
inline void write_in_rank_order(BlockFileWriter* writer, Bytes text, const Comm& comm) {
  if (comm.rank() != 0) {
    (void)comm.exchange_with({0}, {std::move(text)});
    return;
  }
  writer->write(reinterpret_cast<const char*>(text.data()), text.size());
  Bytes().swap(text);
  for (int r = 1; r < comm.size(); ++r) {
    const std::vector<Bytes> from = comm.exchange_with({r}, {Bytes{}});
    writer->write(reinterpret_cast<const char*>(from[0].data()), from[0].size());
  }
}

}  // namespace ppohdem::dem
