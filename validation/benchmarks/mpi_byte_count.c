/* Payload bytes each rank receives per kind of collective, and sends point to point (MPI_Isend,
   MPI_Send), printed at MPI_Finalize: a PMPI wrapper for measurements (docs/performance.md
   "Energy sums without a gather", "Projection to many nodes"). Build and use:
     mpicc -shared -fPIC -O2 -o libmpicount.so validation/benchmarks/mpi_byte_count.c
     mpirun -n 2 -x LD_PRELOAD=$PWD/libmpicount.so ppohdem simulate scene.toml --engine fast --quiet */
#include <mpi.h>
#include <stdio.h>
static double bytes[5]; static long calls[5];
/* "record": allreduces of a derived datatype (the fast engine's one allreduce a step,
   Comm::combine_over_ranks); "allreduce": those of named types. */
static const char* names[5] = {"allgather", "allreduce", "alltoall(v)", "send", "record"};
static int tsize(MPI_Datatype t) { int s = 0; PMPI_Type_size(t, &s); return s; }
int MPI_Allgather(const void* sb, int sc, MPI_Datatype st, void* rb, int rc, MPI_Datatype rt, MPI_Comm c) {
  int n; PMPI_Comm_size(c, &n); bytes[0] += (double)rc * tsize(rt) * n; calls[0]++;
  return PMPI_Allgather(sb, sc, st, rb, rc, rt, c);
}
int MPI_Allgatherv(const void* sb, int sc, MPI_Datatype st, void* rb, const int* rc, const int* d, MPI_Datatype rt, MPI_Comm c) {
  int n; PMPI_Comm_size(c, &n); for (int i = 0; i < n; ++i) bytes[0] += (double)rc[i] * tsize(rt); calls[0]++;
  return PMPI_Allgatherv(sb, sc, st, rb, rc, d, rt, c);
}
int MPI_Allreduce(const void* sb, void* rb, int n, MPI_Datatype t, MPI_Op op, MPI_Comm c) {
  int ni, na, nd, combiner; PMPI_Type_get_envelope(t, &ni, &na, &nd, &combiner);
  const int k = combiner == MPI_COMBINER_NAMED ? 1 : 4;
  bytes[k] += (double)n * tsize(t); calls[k]++;
  return PMPI_Allreduce(sb, rb, n, t, op, c);
}
int MPI_Alltoallv(const void* sb, const int* sc, const int* sd, MPI_Datatype st, void* rb, const int* rc, const int* rd, MPI_Datatype rt, MPI_Comm c) {
  int n; PMPI_Comm_size(c, &n); for (int i = 0; i < n; ++i) bytes[2] += (double)rc[i] * tsize(rt); calls[2]++;
  return PMPI_Alltoallv(sb, sc, sd, st, rb, rc, rd, rt, c);
}
int MPI_Alltoall(const void* sb, int sc, MPI_Datatype st, void* rb, int rc, MPI_Datatype rt, MPI_Comm c) {
  int n; PMPI_Comm_size(c, &n); bytes[2] += (double)rc * tsize(rt) * n; calls[2]++;
  return PMPI_Alltoall(sb, sc, st, rb, rc, rt, c);
}
int MPI_Isend(const void* b, int n, MPI_Datatype t, int dest, int tag, MPI_Comm c, MPI_Request* req) {
  bytes[3] += (double)n * tsize(t); calls[3]++;
  return PMPI_Isend(b, n, t, dest, tag, c, req);
}
int MPI_Send(const void* b, int n, MPI_Datatype t, int dest, int tag, MPI_Comm c) {
  bytes[3] += (double)n * tsize(t); calls[3]++;
  return PMPI_Send(b, n, t, dest, tag, c);
}
int MPI_Finalize(void) {
  int r; PMPI_Comm_rank(MPI_COMM_WORLD, &r);
  for (int k = 0; k < 5; ++k) fprintf(stderr, "mpicount rank %d %s calls %ld bytes %.0f\n", r, names[k], calls[k], bytes[k]);
  return PMPI_Finalize();
}
