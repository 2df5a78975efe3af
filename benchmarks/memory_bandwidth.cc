// Memory bandwidth of this machine, per MPI rank and summed over the ranks
// that stream at the same time. Their ratio (2 ranks against 1) is the
// speed-up of a step bound by memory traffic alone
// (benchmarks/mpi_step_cost.py runs it with 1 and 2 ranks); a step that one
// core runs below the bandwidth it can draw scales beyond it. Two kernels
// over arrays far larger than the caches:
// - read:  s += x_i (four partial sums), 8 bytes per entry;
// - triad: a_i = b_i + 3 c_i, 24 bytes per entry counted (STREAM's rule).
// Each kernel runs `repeats` times between barriers; the fastest run of
// each rank is reported.
//
// usage: mpirun -np N build/benchmarks/benchmark_memory_bandwidth
//          [entries per array, default 2e7] [repeats, default 10]
#include <deal.II/base/mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

using namespace dealii;

namespace
{
  double
  seconds_since(const std::chrono::steady_clock::time_point start)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start)
      .count();
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                   comm = MPI_COMM_WORLD;
  const std::size_t                n    = argc > 1 ? std::stod(argv[1]) : 2e7;
  const int                        repeats = argc > 2 ? std::stoi(argv[2]) : 10;

  std::vector<double> a(n, 1.), b(n, 2.), c(n, 3.);
  double              best_read  = std::numeric_limits<double>::max();
  double              best_triad = std::numeric_limits<double>::max();
  double              checksum   = 0.;
  for (int r = 0; r < repeats; ++r)
    {
      MPI_Barrier(comm);
      auto   start = std::chrono::steady_clock::now();
      double s0 = 0., s1 = 0., s2 = 0., s3 = 0.;
      for (std::size_t i = 0; i + 3 < n; i += 4)
        {
          s0 += b[i];
          s1 += b[i + 1];
          s2 += b[i + 2];
          s3 += b[i + 3];
        }
      best_read = std::min(best_read, seconds_since(start));
      checksum += s0 + s1 + s2 + s3;

      MPI_Barrier(comm);
      start = std::chrono::steady_clock::now();
      for (std::size_t i = 0; i < n; ++i)
        a[i] = b[i] + 3. * c[i];
      best_triad = std::min(best_triad, seconds_since(start));
      checksum += a[n / 2];
    }

  const double read_rate  = 8. * n / best_read / 1e9;
  const double triad_rate = 24. * n / best_triad / 1e9;
  const auto   reads      = Utilities::MPI::all_gather(comm, read_rate);
  const auto   triads     = Utilities::MPI::all_gather(comm, triad_rate);
  const auto   checksums  = Utilities::MPI::all_gather(comm, checksum);
  if (Utilities::MPI::this_mpi_process(comm) == 0)
    {
      double read_sum = 0., triad_sum = 0.;
      for (unsigned int p = 0; p < reads.size(); ++p)
        {
          read_sum += reads[p];
          triad_sum += triads[p];
        }
      std::cout << std::fixed << std::setprecision(2) << "ranks "
                << reads.size() << " entries_per_array " << n
                << " read_GB_per_s_total " << read_sum
                << " triad_GB_per_s_total " << triad_sum << " (checksum "
                << checksums[0] << ")" << std::endl;
    }
  return 0;
}
