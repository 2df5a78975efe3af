// What one claim of the band's chunks costs (Load balancing = claimed or
// shared memory, doc/parallel.md, sessions 38 and 46): an atomic increment
// of a counter in a window of MPI-3 shared memory that the node's ranks map,
// timed two ways, one after the other, between barriers, every rank at once:
// - MPI_Fetch_and_op with MPI_Win_flush (in a passive epoch, lock_all), as
//   the claims were made up to session 50 (but for session 46);
// - the processor's atomic add on the mapped counter (__atomic_fetch_add),
//   as they are made since session 51.
// With one rank the counter stays in its core's cache; with two both ranks
// claim all the time, the worst case (in a pass they claim side by side
// only where they meet in a band). Printed per rank: ns per claim, the
// fastest of `repeats` runs.
//
// usage: mpirun -np N build/benchmarks/benchmark_claim_cost
//          [claims per run, default 200000] [repeats, default 5]
#include <deal.II/base/mpi.h>

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <limits>
#include <string>

using namespace dealii;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const long         n_claims = argc > 1 ? std::stol(argv[1]) : 200000;
  const unsigned int repeats  = argc > 2 ? std::stoi(argv[2]) : 5;
  if (n_claims <= 0 || repeats == 0)
    {
      std::cerr << "usage: benchmark_claim_cost [claims > 0] [repeats > 0]\n";
      return 2;
    }
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD,
                      MPI_COMM_TYPE_SHARED,
                      0,
                      MPI_INFO_NULL,
                      &node);
  const unsigned int rank    = Utilities::MPI::this_mpi_process(node);
  long long         *counter = nullptr;
  MPI_Win            window;
  MPI_Win_allocate_shared(rank == 0 ? sizeof(long long) : 0,
                          sizeof(long long),
                          MPI_INFO_NULL,
                          node,
                          &counter,
                          &window);
  MPI_Aint size = 0;
  int      unit = 0;
  MPI_Win_shared_query(window, 0, &size, &unit, &counter);
  MPI_Win_lock_all(MPI_MODE_NOCHECK, window);
  if (rank == 0)
    *counter = 0;
  MPI_Win_sync(window);
  MPI_Barrier(node);

  const char *names[2] = {"MPI_Fetch_and_op + MPI_Win_flush",
                          "__atomic_fetch_add"};
  double      best[2]  = {std::numeric_limits<double>::max(),
                          std::numeric_limits<double>::max()};
  long long   last     = 0;
  for (unsigned int r = 0; r < repeats; ++r)
    for (unsigned int way = 0; way < 2; ++way)
      {
        MPI_Barrier(node);
        const auto      start = std::chrono::steady_clock::now();
        const long long one   = 1;
        for (long k = 0; k < n_claims; ++k)
          if (way == 0)
            {
              MPI_Fetch_and_op(&one,
                               &last,
                               MPI_LONG_LONG,
                               0,
                               0,
                               MPI_SUM,
                               window);
              MPI_Win_flush(0, window);
            }
          else
            last = __atomic_fetch_add(counter, 1, __ATOMIC_ACQ_REL);
        best[way] = std::min(best[way],
                             std::chrono::duration<double>(
                               std::chrono::steady_clock::now() - start)
                               .count());
      }
  MPI_Barrier(node);
  // Every claim counted once (both ways add one to the same counter).
  const long long expected =
    2LL * repeats * n_claims * Utilities::MPI::n_mpi_processes(node);
  MPI_Win_sync(window);
  const bool counted = (*counter == expected);
  for (unsigned int p = 0; p < Utilities::MPI::n_mpi_processes(node); ++p)
    {
      MPI_Barrier(node);
      if (p != rank)
        continue;
      std::cout << "rank " << rank << " of "
                << Utilities::MPI::n_mpi_processes(node) << ":";
      for (unsigned int way = 0; way < 2; ++way)
        std::cout << " " << names[way] << " " << std::fixed
                  << std::setprecision(1) << 1e9 * best[way] / n_claims
                  << " ns per claim" << (way == 0 ? ";" : "");
      std::cout << (counted ? "" : " (COUNTER WRONG)") << std::endl;
    }
  MPI_Win_unlock_all(window);
  MPI_Win_free(&window);
  MPI_Comm_free(&node);
  return counted ? 0 : 1;
}
