/* What one poll of the overlapped halo refresh costs (docs/performance.md "Projected scaling"):
   rank 0 posts 19 receives and 19 sends of 21,000 bytes (the busiest rank of the weak bed at
   4,096 ranks: 400 KB in 19 messages, above Open MPI's eager limit) to rank 1, which posts
   its side only afterwards, and times MPI_Testall over the 38 pending requests. Build and run:
     mpicc -O2 -o testall validation/benchmarks/mpi_testall_cost.c
     mpirun -n 2 --bind-to none ./testall */
#include <mpi.h>
#include <stdio.h>

enum { kMessages = 19, kBytes = 21000, kCalls = 20000 };
static char in[kMessages][kBytes], out[kMessages][kBytes];

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int me = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  const int peer = 1 - me;
  MPI_Request req[2 * kMessages];
  if (me == 0) {
    for (int i = 0; i < kMessages; ++i) MPI_Irecv(in[i], kBytes, MPI_BYTE, peer, i, MPI_COMM_WORLD, &req[i]);
    for (int i = 0; i < kMessages; ++i) MPI_Isend(out[i], kBytes, MPI_BYTE, peer, 100 + i, MPI_COMM_WORLD, &req[kMessages + i]);
    int done = 0;
    const double t0 = MPI_Wtime();
    for (int k = 0; k < kCalls; ++k) MPI_Testall(2 * kMessages, req, &done, MPI_STATUSES_IGNORE);
    const double t = MPI_Wtime() - t0;
    printf("MPI_Testall over %d pending requests: %.3f us a call\n", 2 * kMessages, t / kCalls * 1e6);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (me == 1) {
    for (int i = 0; i < kMessages; ++i) MPI_Irecv(in[i], kBytes, MPI_BYTE, peer, 100 + i, MPI_COMM_WORLD, &req[i]);
    for (int i = 0; i < kMessages; ++i) MPI_Isend(out[i], kBytes, MPI_BYTE, peer, i, MPI_COMM_WORLD, &req[kMessages + i]);
  }
  MPI_Waitall(2 * kMessages, req, MPI_STATUSES_IGNORE);
  MPI_Finalize();
  return 0;
}
