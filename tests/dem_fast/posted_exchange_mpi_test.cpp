// Run under mpirun at 2 and 3 ranks: Comm::post_exchange_with / progress_exchange /
// finish_exchange (the halo refresh's non-blocking exchange, docs/dem.md "The halo refresh
// behind the interior") deliver what each peer sent, the same as the blocking exchange_with
// with the sizes known, for empty blocks, small ones and 1 MB ones (above Open MPI's eager
// limit: a rendezvous that moves only inside MPI calls), with two exchanges in flight at once
// and an exchange_with in between; one message per nonempty block.
#include <cstdio>
#include <string>
#include <vector>

#include "mpi_case.hpp"
#include "ppohdem/comm/comm.hpp"

namespace {

/// The block `from` sends to `to` in round `round`: its size and bytes are fixed by the three.
ppohdem::Bytes block(int from, int to, int round) {
  const std::size_t sizes[] = {0, 48, 1 << 20};
  const std::size_t n = sizes[static_cast<std::size_t>(from + 2 * to + round) % 3];
  ppohdem::Bytes b(n);
  for (std::size_t k = 0; k < n; ++k) b[k] = static_cast<unsigned char>(from * 31 + to * 7 + round * 3 + k * 13);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ppohdem;
  test::MpiCase run(&argc, &argv);
  const Comm& comm = run.comm();
  const int me = comm.rank(), ranks = comm.size();
  std::vector<int> peers;  // every other rank, ascending (symmetric)
  for (int r = 0; r < ranks; ++r) {
    if (r != me) peers.push_back(r);
  }
  std::vector<std::vector<Bytes>> to(2, std::vector<Bytes>(peers.size()));
  std::vector<std::vector<std::size_t>> sizes(2, std::vector<std::size_t>(peers.size()));
  std::size_t nonempty[2] = {0, 0};  // blocks this rank sends in each round
  for (int round = 0; round < 2; ++round) {
    for (std::size_t i = 0; i < peers.size(); ++i) {
      to[round][i] = block(me, peers[i], round);
      sizes[round][i] = block(peers[i], me, round).size();
      nonempty[round] += to[round][i].empty() ? 0 : 1;
    }
  }
  const std::uint64_t sent_before = comm.messages_sent();
  auto first = comm.post_exchange_with(peers, to[0], sizes[0]);
  auto second = comm.post_exchange_with(peers, to[1], sizes[1]);
  for (int k = 0; k < 5; ++k) {
    comm.progress_exchange(*second);
    comm.progress_exchange(*first);
  }
  // A blocking exchange in between (the engine never does this).
  const std::vector<Bytes> blocking = comm.exchange_with(peers, to[0], &sizes[0]);
  comm.finish_exchange(*second);
  comm.finish_exchange(*first);
  comm.finish_exchange(*first);  // a second finish waits for nothing
  // Both posted rounds and the blocking one (round 0's blocks again).
  run.expect(comm.messages_sent() - sent_before == nonempty[0] + nonempty[1] + nonempty[0],
         "messages_sent counts one message per nonempty block");
  const Comm::PostedExchange* posted[2] = {first.get(), second.get()};
  for (int round = 0; round < 2; ++round) {
    run.expect(posted[round]->from.size() == peers.size(), "one block per peer");
    for (std::size_t i = 0; i < peers.size() && i < posted[round]->from.size(); ++i) {
      run.expect(posted[round]->from[i] == block(peers[i], me, round),
             "round " + std::to_string(round) + ": the block from rank " + std::to_string(peers[i]));
    }
  }
  run.expect(blocking == first->from, "the posted exchange's blocks are exchange_with's");
  const int exit_code = run.exit_code();
  if (me == 0) std::printf("%d ranks: posted exchanges %s\n", ranks, exit_code == 0 ? "deliver every block" : "FAILED");
  return exit_code;
}
