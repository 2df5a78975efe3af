// What the lumped pass's vector traffic costs beside its matrix: the pass
// over one body's paired stiffness rows (PairedRows::packed_products) with
// the loads and stores of ElasticBody's fused step, in four variants timed
// in turn, round after round, in one process (and, under mpirun, on every
// rank at once, between barriers, each rank on the body of its number):
// - program: as the pass (the force read and zeroed, the inverse mass, the
//   mass, v^{n+1/2} read and written, the next displacement stored);
// - stream: the next displacement by non-temporal stores (no read of its
//   old cache lines);
// - shifted: the arrays at 8 bytes past a 64-byte boundary, where Open MPI's
//   shared-memory window placed the state (doc/parallel.md, session 44);
// - no force: without the force's read and zeroing (as if the pass knew
//   the rows without contact forces);
// - window: u, the next displacement and v^{n+1/2} in a window of MPI-3
//   shared memory, as `Load balancing = shared memory` places a body's
//   state (one window per body, rank 0 allocating it, every rank mapping
//   and touching it, the arrays at cache lines), the rest on the heap.
// Printed per rank: the median time of each variant and the median over
// the rounds of its ratio to `program` (the figure a drift of the machine
// moves least). The arrays hold synthetic values; the bits are not the
// program's.
//
// usage: [mpirun -np 2] build/benchmarks/benchmark_pass_traffic FILE.prm
//          [rounds, default 30]
#include <deal.II/base/mpi.h>

#include <isoimpact/scene/scene.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>
#include <tuple>
#include <vector>

#ifdef __SSE2__
#  include <emmintrin.h>

using namespace dealii;

namespace
{
  enum Variant
  {
    program,
    stream,
    shifted,
    no_force,
    window,
    n_variants
  };

  // The pass's loads and stores around each pair's products; returns the
  // energies' sum (printed: not optimised out).
  template <Variant variant>
  double
  pass(const isoimpact::PairedRows &rows,
       const double                *u,
       double                      *u_ahead,
       double                      *force,
       const double                *inverse_mass,
       const double                *mass,
       double                      *vh,
       const double                 dt)
  {
    double sum = 0.;
    for (std::size_t p = 0; p < rows.n_pairs(); ++p)
      {
        const std::size_t i    = 2 * p;
        const __m128d     ku   = rows.packed_products(p, u);
        const __m128d     zero = _mm_setzero_pd();
        const __m128d     w    = _mm_loadu_pd(inverse_mass + i);
        __m128d           f    = zero;
        if constexpr (variant != no_force)
          {
            f = _mm_loadu_pd(force + i);
            _mm_storeu_pd(force + i, zero);
          }
        const __m128d a        = _mm_andnot_pd(_mm_cmpeq_pd(w, zero),
                                        _mm_mul_pd(_mm_sub_pd(f, ku), w));
        const __m128d previous = _mm_loadu_pd(vh + i);
        const __m128d next =
          _mm_add_pd(previous, _mm_mul_pd(_mm_set1_pd(dt), a));
        _mm_storeu_pd(vh + i, next);
        const __m128d own = _mm_loadu_pd(u + i);
        const __m128d u_next =
          _mm_add_pd(own, _mm_mul_pd(_mm_set1_pd(dt), next));
        if constexpr (variant == stream)
          _mm_stream_pd(u_ahead + i, u_next);
        else
          _mm_storeu_pd(u_ahead + i, u_next);
        const __m128d terms =
          _mm_add_pd(_mm_mul_pd(_mm_mul_pd(previous, _mm_loadu_pd(mass + i)),
                                next),
                     _mm_mul_pd(own, ku));
        sum +=
          _mm_cvtsd_f64(terms) + _mm_cvtsd_f64(_mm_unpackhi_pd(terms, terms));
      }
    _mm_sfence();
    return sum;
  }
} // namespace

int
main(int argc, char **argv)
{
  using namespace isoimpact;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (argc < 2)
    {
      std::cerr << "usage: benchmark_pass_traffic FILE.prm [rounds]\n";
      return 2;
    }
  const unsigned int rounds = argc > 2 ? std::stoi(argv[2]) : 30;
  const unsigned int rank   = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
  try
    {
      const Parameters   parameters = read_parameters(argv[1]);
      Scene              scene      = build_scene(parameters);
      const unsigned int body       = rank % scene.bodies.size();
      const PairedRows  &rows = scene.bodies[body]->paired_stiffness_rows();
      const std::size_t  n    = scene.bodies[body]->n_dofs();
      AssertThrow(!rows.empty() && 2 * rows.n_pairs() == n,
                  ExcMessage("the body's rows are not paired"));
      // Six arrays at a 64-byte boundary, six 8 bytes past one.
      const std::size_t stride = (n + 16) / 8 * 8;
      double           *memory =
        static_cast<double *>(std::aligned_alloc(64, 12 * stride * 8));
      for (std::size_t i = 0; i < 12 * stride; ++i)
        memory[i] = 1e-3 * double((i * 7919) % 1000);
      const auto array = [&](const unsigned int k, const bool shift) {
        return memory + (shift ? 6 + k : k) * stride + (shift ? 1 : 0);
      };
      // One window per body on the node's ranks, rank 0 allocating.
      MPI_Comm node;
      MPI_Comm_split_type(MPI_COMM_WORLD,
                          MPI_COMM_TYPE_SHARED,
                          0,
                          MPI_INFO_NULL,
                          &node);
      const unsigned int   node_rank = Utilities::MPI::this_mpi_process(node);
      std::vector<MPI_Win> windows(scene.bodies.size());
      double              *window_arrays = nullptr;
      for (unsigned int b = 0; b < scene.bodies.size(); ++b)
        {
          const std::size_t bytes =
            node_rank == 0 ? (3 * stride + 8) * sizeof(double) : 0;
          double *base = nullptr;
          MPI_Win_allocate_shared(bytes,
                                  sizeof(double),
                                  MPI_INFO_NULL,
                                  node,
                                  &base,
                                  &windows[b]);
          MPI_Aint size;
          int      unit;
          MPI_Win_shared_query(windows[b], 0, &size, &unit, &base);
          double *aligned = reinterpret_cast<double *>(
            (reinterpret_cast<std::uintptr_t>(base) + 63) / 64 * 64);
          // Every rank touches every page of every body's window.
          for (std::size_t i = 0; i < 3 * stride; i += 512)
            aligned[i] = aligned[i] + 0.;
          MPI_Barrier(node);
          if (b == body)
            window_arrays = aligned;
        }
      // u, the next displacement, v^{n+1/2}: the heap's values.
      for (const unsigned int k : {0u, 1u, 5u})
        std::copy(array(k, false),
                  array(k, false) + n,
                  window_arrays + (k == 5 ? 2 : k) * stride);
      std::vector<std::vector<double>> times(n_variants), ratios(n_variants);
      double                           check = 0.;
      for (unsigned int round = 0; round < rounds; ++round)
        {
          double round_times[n_variants];
          for (unsigned int v = 0; v < n_variants; ++v)
            {
              const bool shift = (v == shifted);
              double    *u = array(0, shift), *u_ahead = array(1, shift);
              double    *vh = array(5, shift);
              if (v == window)
                {
                  u       = window_arrays;
                  u_ahead = window_arrays + stride;
                  vh      = window_arrays + 2 * stride;
                }
              MPI_Barrier(MPI_COMM_WORLD);
              const auto   start = std::chrono::steady_clock::now();
              const auto   args  = std::make_tuple(std::cref(rows),
                                                u,
                                                u_ahead,
                                                array(2, shift),
                                                array(3, shift),
                                                array(4, shift),
                                                vh,
                                                1e-6);
              const double sum =
                (v == program) ? std::apply(pass<program>, args) :
                (v == stream)  ? std::apply(pass<stream>, args) :
                (v == shifted) ? std::apply(pass<shifted>, args) :
                (v == window)  ? std::apply(pass<window>, args) :
                                 std::apply(pass<no_force>, args);
              round_times[v] = std::chrono::duration<double>(
                                 std::chrono::steady_clock::now() - start)
                                 .count();
              check += sum;
            }
          for (unsigned int v = 0; v < n_variants; ++v)
            {
              times[v].push_back(round_times[v]);
              ratios[v].push_back(round_times[v] / round_times[program]);
            }
        }
      const auto median = [](std::vector<double> values) {
        std::sort(values.begin(), values.end());
        return values[values.size() / 2];
      };
      const char *names[n_variants] = {"program",
                                       "stream",
                                       "shifted",
                                       "no force",
                                       "window"};
      for (unsigned int r = 0;
           r < Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
           ++r)
        {
          MPI_Barrier(MPI_COMM_WORLD);
          if (r != rank)
            continue;
          std::cout << "rank " << rank << ", body " << body + 1 << ", "
                    << rows.n_pairs() << " row pairs, " << rounds
                    << " rounds (check " << check << "):";
          for (unsigned int v = 0; v < n_variants; ++v)
            std::cout << " " << names[v] << " " << 1e3 * median(times[v])
                      << " ms" << (v == program ? "" : " (ratio ")
                      << (v == program ? "" : std::to_string(median(ratios[v])))
                      << (v == program ? "" : ")")
                      << (v + 1 < n_variants ? ";" : "");
          std::cout << std::endl;
        }
      std::free(memory);
      for (auto &w : windows)
        MPI_Win_free(&w);
      MPI_Comm_free(&node);
    }
  catch (const std::exception &error)
    {
      std::cerr << "benchmark_pass_traffic: " << error.what() << std::endl;
      return 1;
    }
  return 0;
}
#else
int
main()
{
  std::cerr << "benchmark_pass_traffic needs SSE2\n";
  return 1;
}
#endif
