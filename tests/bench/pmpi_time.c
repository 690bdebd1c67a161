/* Time spent in MPI per rank, by call, for any MPI program (PMPI interposer; no rebuild of
 * LIGGGHTS). Used for docs/PERFORMANCE.md ("Twenty-first session"): run a case twice with
 * different step counts and divide the differences by the extra steps.
 *
 *   mpicc -shared -fPIC -O2 -o /tmp/pmpi_time.so tests/bench/pmpi_time.c
 *   LD_PRELOAD=/tmp/pmpi_time.so PMPI_TIME_OUT=/tmp/pmpi.txt mpirun -np 2 build/bin/liggghts -in ...
 *
 * One line per rank is appended to $PMPI_TIME_OUT (default pmpi_time.txt) at MPI_Finalize. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

static double t_start, t_send, t_wait, t_allreduce;
static long n_send, n_wait, n_allreduce;

int MPI_Init(int *argc, char ***argv)
{
  int rc = PMPI_Init(argc, argv);
  t_start = PMPI_Wtime();
  return rc;
}

int MPI_Send(const void *buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm)
{
  double t = PMPI_Wtime();
  int rc = PMPI_Send(buf, count, type, dest, tag, comm);
  t_send += PMPI_Wtime() - t;
  n_send++;
  return rc;
}

int MPI_Wait(MPI_Request *request, MPI_Status *status)
{
  double t = PMPI_Wtime();
  int rc = PMPI_Wait(request, status);
  t_wait += PMPI_Wtime() - t;
  n_wait++;
  return rc;
}

int MPI_Allreduce(const void *in, void *out, int count, MPI_Datatype type, MPI_Op op, MPI_Comm comm)
{
  double t = PMPI_Wtime();
  int rc = PMPI_Allreduce(in, out, count, type, op, comm);
  t_allreduce += PMPI_Wtime() - t;
  n_allreduce++;
  return rc;
}

int MPI_Finalize(void)
{
  int rank;
  PMPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const char *name = getenv("PMPI_TIME_OUT");
  FILE *out = fopen(name ? name : "pmpi_time.txt", "a");
  if (out) {
    fprintf(out, "rank %d: %.4f s from MPI_Init; MPI_Send %ld calls %.4f s, MPI_Wait %ld calls "
            "%.4f s, MPI_Allreduce %ld calls %.4f s\n", rank, PMPI_Wtime() - t_start, n_send,
            t_send, n_wait, t_wait, n_allreduce, t_allreduce);
    fclose(out);
  }
  return PMPI_Finalize();
}
