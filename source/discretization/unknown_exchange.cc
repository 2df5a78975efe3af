// Layer 3: the ghost exchange of a step on several MPI ranks.
#include <deal.II/base/exceptions.h>

#include <isoimpact/discretization/unknown_exchange.h>

#include <sys/statvfs.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <thread>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    // This process's time in waits for the steps' messages
    // (UnknownExchange::seconds_waiting()), and a clock that adds the time
    // of its scope to it.
    double seconds_waiting_for_messages = 0.;

    struct WaitClock
    {
      const std::chrono::steady_clock::time_point start =
        std::chrono::steady_clock::now();
      ~WaitClock()
      {
        seconds_waiting_for_messages +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                        start)
            .count();
      }
    };

    // Spins until done() (counts in memory another rank of the node writes),
    // timed as a wait if it was not so at once.
    template <typename Done>
    void
    wait_until(const Done &done)
    {
      if (done())
        return;
      const WaitClock clock;
      for (unsigned int spins = 0; !done(); ++spins)
        if (spins > 1000)
          std::this_thread::yield(); // (more ranks than cores)
    }
  } // namespace

  namespace
  {
    // Whether MPI may still be called (messages under way at the end).
    bool
    mpi_is_running()
    {
      int initialized = 0, finalized = 0;
      MPI_Initialized(&initialized);
      MPI_Finalized(&finalized);
      return initialized != 0 && finalized == 0;
    }

    // The ranks of `communicator` that share this rank's node (memory both
    // map), ordered by rank.
    MPI_Comm
    node_communicator(const MPI_Comm communicator, const unsigned int rank)
    {
      MPI_Comm  node = MPI_COMM_NULL;
      const int ierr = MPI_Comm_split_type(communicator,
                                           MPI_COMM_TYPE_SHARED,
                                           rank,
                                           MPI_INFO_NULL,
                                           &node);
      AssertThrowMPI(ierr);
      return node;
    }

    // The bytes free in /dev/shm, where Open MPI places the files of its
    // shared-memory windows on Linux (MCA osc_sm_backing_directory), as
    // the node's first rank sees them (the same on every rank); infinite
    // where there is no /dev/shm to ask.
    double
    free_shared_memory_bytes(const MPI_Comm node)
    {
      double free_bytes = std::numeric_limits<double>::infinity();
      int    node_rank  = 0;
      MPI_Comm_rank(node, &node_rank);
      struct statvfs status;
      if (node_rank == 0 && statvfs("/dev/shm", &status) == 0)
        free_bytes = double(status.f_bavail) * double(status.f_frsize);
      MPI_Bcast(&free_bytes, 1, MPI_DOUBLE, 0, node);
      return free_bytes;
    }
  } // namespace

  // The claims' counter: one integer in rank 0's memory, which both ranks
  // of a node map (MPI_Win_allocate_shared), in a passive epoch for the
  // whole run; atomic increments where it is mapped (a compiler atomic:
  // MPI_Fetch_and_op with its flush took 0.16-0.63 us per claim in a
  // pass, this 0.09-0.16: doc/parallel.md, session 51). On the next cache
  // line each rank's count of passes, and with Load balancing = shared
  // memory the body's state (a second window), read and written in place.
  struct UnknownExchange::ClaimWindow
  {
    MPI_Comm   node         = MPI_COMM_NULL;
    MPI_Win    window       = MPI_WIN_NULL;
    MPI_Win    state_window = MPI_WIN_NULL;
    long long *counter      = nullptr; // the claims'
    long long *passes       = nullptr; // one per rank
    double    *state        = nullptr;
    // Sums over the ranks of at most sum_capacity values (start_sum()):
    // each rank's values of sum k in its slot k % sum_slots, and its counts
    // of sums started and completed (read), a cache line past the claims'
    // counter. This process's counts in the last two.
    static constexpr unsigned int sum_slots = 4, sum_capacity = 16;
    long long                    *sums_started_by   = nullptr; // one per rank
    long long                    *sums_completed_by = nullptr; // one per rank
    double                       *sum_values        = nullptr;
    long long                     sums_started = 0, sums_completed = 0;

    double *
    sum_slot(const unsigned int p, const long long k) const
    {
      return sum_values +
             (std::size_t(p) * sum_slots + k % sum_slots) * sum_capacity;
    }

    ClaimWindow(const MPI_Comm     communicator,
                const unsigned int rank,
                const std::size_t  n_state_values)
    {
      node          = node_communicator(communicator, rank);
      int node_size = 0;
      MPI_Comm_size(node, &node_size);
      AssertThrow(node_size == 2,
                  ExcMessage("Load balancing = claimed or shared memory "
                             "needs both MPI ranks on one node (memory both "
                             "map); use measured"));
      const double needed     = n_state_values * sizeof(double);
      const double free_bytes = free_shared_memory_bytes(node);
      const auto   megabytes  = [](const double bytes) {
        char text[32];
        std::snprintf(text, sizeof(text), "%.1f", bytes / 1e6);
        return std::string(text);
      };
      AssertThrow(needed <= free_bytes,
                  ExcMessage("Load balancing = shared memory: a body's state "
                             "needs " +
                             megabytes(needed) +
                             " MB in /dev/shm (where Open MPI maps its "
                             "shared memory), " +
                             megabytes(free_bytes) +
                             " MB are free; use Parallel/Load balancing = "
                             "measured, or a larger /dev/shm (docker run "
                             "--shm-size)"));
      // The claims' counter at displacement 0, the passes' counts on the
      // second cache line, the sums' counts and values from the third (the
      // claims' counter changes all through a pass).
      constexpr std::size_t n_counters = 16 + 4 + 2 * sum_slots * sum_capacity;
      long long            *counters   = nullptr;
      int ierr = MPI_Win_allocate_shared(rank == 0 ? n_counters * 8 : 0,
                                         sizeof(long long),
                                         MPI_INFO_NULL,
                                         node,
                                         &counters,
                                         &window);
      AssertThrowMPI(ierr);
      MPI_Aint size = 0;
      int      unit = 0;
      ierr          = MPI_Win_shared_query(window, 0, &size, &unit, &counters);
      AssertThrowMPI(ierr);
      counter           = counters;
      passes            = counters + 8;
      sums_started_by   = counters + 16;
      sums_completed_by = counters + 18;
      sum_values        = reinterpret_cast<double *>(counters + 20);
      static_assert(sizeof(double) == sizeof(long long));
      if (n_state_values > 0)
        {
          // 64 bytes more: the state starts at a cache line's boundary
          // (Open MPI's segment may start 8 bytes past one; the pass's
          // 16-byte loads then split cache lines, about 1 % of a rank's
          // pass: benchmark_pass_traffic, doc/parallel.md, session 44).
          ierr =
            MPI_Win_allocate_shared(rank == 0 ?
                                      n_state_values * sizeof(double) + 64 :
                                      0,
                                    sizeof(double),
                                    MPI_INFO_NULL,
                                    node,
                                    &state,
                                    &state_window);
          AssertThrowMPI(ierr);
          ierr = MPI_Win_shared_query(state_window, 0, &size, &unit, &state);
          AssertThrowMPI(ierr);
          AssertThrow(static_cast<std::size_t>(size) ==
                        n_state_values * sizeof(double) + 64,
                      ExcInternalError());
          state = reinterpret_cast<double *>(
            (reinterpret_cast<std::uintptr_t>(state) + 63) / 64 * 64);
          ierr = MPI_Win_lock_all(MPI_MODE_NOCHECK, state_window);
          AssertThrowMPI(ierr);
        }
      ierr = MPI_Win_lock_all(MPI_MODE_NOCHECK, window);
      AssertThrowMPI(ierr);
      if (rank == 0)
        std::fill(counters, counters + 20, 0LL);
      if (state != nullptr)
        {
          // Each rank zeroes half of the state, and after the barrier
          // reads a value of every page: the pages are mapped into both
          // processes here, in the set-up, not in the first step.
          const std::size_t half = n_state_values / 2;
          std::fill(state + (rank == 0 ? 0 : half),
                    state + (rank == 0 ? half : n_state_values),
                    0.);
          MPI_Win_sync(state_window);
        }
      MPI_Win_sync(window);
      MPI_Barrier(node);
      MPI_Win_sync(window);
      double sum_of_page_values = 0;
      for (std::size_t i = 0; i < n_state_values; i += 512)
        sum_of_page_values += static_cast<volatile double *>(state)[i];
      AssertThrow(sum_of_page_values == 0., ExcInternalError());
    }

    ~ClaimWindow()
    {
      if (!mpi_is_running())
        return;
      if (state_window != MPI_WIN_NULL)
        {
          MPI_Win_unlock_all(state_window);
          MPI_Win_free(&state_window);
        }
      MPI_Win_unlock_all(window);
      MPI_Win_free(&window);
      MPI_Comm_free(&node);
    }

    // The counter's value before adding one.
    long long
    fetch_and_increment() const
    {
      return __atomic_fetch_add(counter, 1LL, __ATOMIC_ACQ_REL);
    }
  };

  double
  UnknownExchange::seconds_waiting()
  {
    return seconds_waiting_for_messages;
  }

  unsigned int
  n_world_ranks()
  {
    return Utilities::MPI::job_supports_mpi() ?
             Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) :
             1;
  }

  unsigned int
  world_rank()
  {
    return Utilities::MPI::job_supports_mpi() ?
             Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) :
             0;
  }

  template <int dim>
  UnknownExchange::UnknownExchange(
    const UnknownPartition<dim>                &partition,
    const MPI_Comm                              communicator,
    const std::vector<types::global_dof_index> &shared,
    const LoadBalancing                         load_balancing,
    const double                                band_fraction)
    : comm(communicator)
    , n_procs(Utilities::MPI::n_mpi_processes(communicator))
    , rank(Utilities::MPI::this_mpi_process(communicator))
  {
    AssertThrow(partition.n_parts() == n_procs,
                ExcMessage("the partition has " +
                           std::to_string(partition.n_parts()) + " parts for " +
                           std::to_string(n_procs) + " MPI ranks"));
    const types::global_dof_index n =
      partition.owned_unknowns(0).size(); // the index space
    cells_here.resize(partition.n_cells());
    for (unsigned int c = 0; c < cells_here.size(); ++c)
      cells_here[c] = partition.cell_owner(c) == rank;
    owned_here.assign(n, 0);
    owned_by_rank.resize(n_procs);

    if (n_procs == 2 && load_balancing != LoadBalancing::off)
      {
        // The band: the interface layers of each part, nearest first, up
        // to band_fraction of the part's unknowns.
        balancing         = load_balancing;
        const auto &layer = partition.interface_layers();
        AssertThrow(layer.size() == n,
                    ExcMessage("load balancing needs the partition's layers "
                               "(a body whole on a rank: its anchors)"));
        whole_body = partition.owned_unknowns(0).n_elements() == 0 ||
                     partition.owned_unknowns(1).n_elements() == 0;
        if (balancing == LoadBalancing::automatic)
          {
            // Shared memory for a body whole on a rank, where both ranks
            // map the node's memory and /dev/shm has room for this body's
            // state and another's as large; measured else (a split body's
            // band is its interface layers, whose rows lie scattered:
            // measured was the faster there, doc/parallel.md, session 41).
            MPI_Comm node      = node_communicator(communicator, rank);
            int      node_size = 0;
            MPI_Comm_size(node, &node_size);
            const double needed =
              2. * shared_state_values_per_unknown * n * sizeof(double);
            const bool room = free_shared_memory_bytes(node) >= needed;
            MPI_Comm_free(&node);
            balancing = whole_body && node_size == 2 && room ?
                          LoadBalancing::shared_memory :
                          LoadBalancing::measured;
          }
        const auto layer_counts = [&](const unsigned int part) {
          std::vector<std::size_t> counts;
          for (types::global_dof_index i = 0; i < n; ++i)
            {
              const int s = layer[i];
              if ((part == 0) != (s <= 0) ||
                  std::abs(s) ==
                    UnknownPartition<dim>::interface_layer_unreached)
                continue;
              const std::size_t d = part == 0 ? -s : s - 1;
              if (d >= counts.size())
                counts.resize(d + 1, 0);
              ++counts[d];
            }
          return counts;
        };
        const auto band_depth = [&](const unsigned int part) {
          const auto  counts = layer_counts(part);
          const auto  size   = partition.owned_unknowns(part).n_elements();
          std::size_t sum = 0, depth = 0;
          // At least one layer; the deepest stays, so that a rank never
          // owns nothing.
          while (depth + 1 < counts.size() &&
                 (depth == 0 || sum + counts[depth] <= band_fraction * size))
            sum += counts[depth++];
          return int(depth);
        };
        min_split = -band_depth(0);
        max_split = band_depth(1);
        layer_lists.resize(max_split - min_split + 2);
        std::vector<std::vector<types::global_dof_index>> fixed(2);
        for (types::global_dof_index i = 0; i < n; ++i)
          {
            const int s = layer[i];
            if (s >= min_split && s <= max_split + 1)
              layer_lists[s - min_split].push_back(i);
            if (s <= min_split)
              fixed[0].push_back(i);
            else if (s > max_split)
              fixed[1].push_back(i);
          }
        // The rows this rank may own: its fixed ones and the band's
        // layers min_split + 1 ... max_split, which either rank may take.
        potential_rows = fixed[rank];
        for (int s = min_split + 1; s <= max_split; ++s)
          potential_rows.insert(potential_rows.end(),
                                layer_lists[s - min_split].begin(),
                                layer_lists[s - min_split].end());
        std::sort(potential_rows.begin(), potential_rows.end());
        owner_of.assign(n, 0);
        for (const auto i : fixed[1])
          owner_of[i] = 1;
        for (int s = 1; s <= max_split; ++s)
          for (const auto i : layer_lists[s - min_split])
            owner_of[i] = 1;
        shared_unknowns = shared;
        for (const auto i : shared)
          layer_of_shared.push_back(layer[i]);
        cost_per_row.assign(2, 0.);
        set_up_split();
        if (claims_band())
          {
            // The band's rows less the shared unknowns: the contact forces
            // land on these, and only their owner has them (it computes
            // them with its fixed rows, and sends them to the other rank
            // as ghosts); but see the state shared below.
            std::vector<types::global_dof_index> sorted_shared = shared;
            std::sort(sorted_shared.begin(), sorted_shared.end());
            std::vector<types::global_dof_index> band_rows;
            for (int s = min_split + 1; s <= max_split; ++s)
              for (const auto i : layer_lists[s - min_split])
                if (!std::binary_search(sorted_shared.begin(),
                                        sorted_shared.end(),
                                        i))
                  band_rows.push_back(i);
            std::sort(band_rows.begin(), band_rows.end());
            // A body whole on a rank with the state shared: no ghosts to
            // send, so the band need not be layers: as many rows,
            // consecutive, the contact surfaces' among them, at the end of
            // the index range where the surfaces' unknowns are fewer (the
            // last rows if as many), the owner's fixed rows the others.
            // Both ranks form the contact forces of the surfaces whose rows
            // they may step (ElasticBody: steps_contact_surface()), and the
            // pass leaves every surface row's force zero. Sessions 54-59
            // left the surfaces' rows out of the band (only their owner had
            // their forces): each run of them cut the band and left a few
            // fixed rows among the band's, which the owner's pass stepped
            // after its fixed rows, a jump for each; FEA's surfaces cut its
            // band of 10 % 160 times (doc/parallel.md, session 60).
            if (shares_state() && whole_body)
              {
                const auto is_shared = [&](const types::global_dof_index i) {
                  return std::binary_search(sorted_shared.begin(),
                                            sorted_shared.end(),
                                            i);
                };
                const std::size_t n_band       = band_rows.size();
                std::size_t       shared_first = 0, shared_last = 0;
                for (types::global_dof_index i = 0; i < n_band && i < n; ++i)
                  {
                    shared_first += is_shared(i);
                    shared_last += is_shared(n - 1 - i);
                  }
                band_rows.resize(std::min<std::size_t>(n_band, n));
                const types::global_dof_index first =
                  shared_first < shared_last ? 0 : n - band_rows.size();
                std::iota(band_rows.begin(), band_rows.end(), first);
                const unsigned int owner =
                  partition.owned_unknowns(0).n_elements() == 0 ? 1 : 0;
                if (rank != owner)
                  potential_rows = band_rows;
              }
            // The claims take the band in chunks of consecutive rows (a
            // layer's rows lie scattered over the index range, a few in a
            // row, and a pass over them was slower): about 2000 rows each
            // (some 50 us of a pass), in ascending order. (Chunks of 256
            // rows, a rank alone in the band claiming eight at once, ended
            // the two ranks' passes closer together, but made IGA's step 7 %
            // longer: each chunk starts a range of the pass, and a range
            // costs IGA 1-3 us, doc/parallel.md, sessions 54 and 56.)
            constexpr std::size_t chunk_rows = 2048;
            const std::size_t     n_chunks =
              std::max<std::size_t>(1,
                                    (band_rows.size() + chunk_rows / 2) /
                                      chunk_rows);
            band_chunk_ranges.resize(n_chunks);
            chunk_prefix.assign(1, 0);
            for (std::size_t c = 0; c < n_chunks; ++c)
              {
                const std::size_t first = band_rows.size() * c / n_chunks,
                                  end   = band_rows.size() * (c + 1) / n_chunks;
                auto &pieces            = band_chunk_ranges[c];
                for (std::size_t k = first; k < end; ++k)
                  {
                    const auto i = band_rows[k];
                    if (!pieces.empty() && pieces.back().second == i)
                      ++pieces.back().second;
                    else
                      pieces.emplace_back(i, i + 1);
                    owned_here[i] = 0; // outside the fixed rows
                  }
                chunk_prefix.push_back(end);
              }
            set_up_ranges();
            // (owned_here back to the partition's split; rank 0's rows of
            // the band there.)
            std::size_t band_rows_of_0 = 0;
            for (const auto i : band_rows)
              {
                owned_here[i] = owner_of[i] == rank;
                band_rows_of_0 += owner_of[i] == 0;
              }
            meeting_chunk  = 0;
            fixed_count[0] = owned_count[0] - band_rows_of_0;
            fixed_count[1] =
              owned_count[1] - (band_rows.size() - band_rows_of_0);
            AssertThrow(fixed_count[rank] == range_offsets.back(),
                        ExcInternalError());
          }
        return;
      }

    // The ghosts of every rank (each rank computes all of them alike).
    std::vector<std::vector<types::global_dof_index>> ghosts_of(n_procs);
    for (unsigned int p = 0; p < n_procs; ++p)
      {
        IndexSet needed = partition.relevant_unknowns(p);
        IndexSet shared_set(n);
        shared_set.add_indices(shared.begin(), shared.end());
        needed.add_indices(shared_set);
        needed.subtract_set(partition.owned_unknowns(p));
        needed.fill_index_vector(ghosts_of[p]);
        partition.owned_unknowns(p).fill_index_vector(owned_by_rank[p]);
      }
    ghosts = ghosts_of[rank];
    for (const auto i : owned_by_rank[rank])
      owned_here[i] = 1;
    set_up_ranges();
    for (unsigned int p = 0; p < n_procs; ++p)
      {
        if (p == rank)
          continue;
        std::vector<types::global_dof_index> to_send, to_receive;
        for (const auto i : ghosts_of[p])
          if (partition.owner(i) == rank)
            to_send.push_back(i);
        for (const auto i : ghosts)
          if (partition.owner(i) == p)
            to_receive.push_back(i);
        if (to_send.empty() && to_receive.empty())
          continue;
        peers.push_back(p);
        send_lists.push_back(std::move(to_send));
        receive_lists.push_back(std::move(to_receive));
      }
    for (const auto &list : send_lists)
      all_sent.insert(all_sent.end(), list.begin(), list.end());
  }

  void
  UnknownExchange::set_up_split()
  {
    // Rank 0 owns the layers <= present_split, rank 1 the others.
    for (types::global_dof_index i = 0; i < owner_of.size(); ++i)
      owned_here[i] = owner_of[i] == rank;
    owned_lists_stale = true;
    for (unsigned int p = 0; p < 2; ++p)
      owned_count[p] = std::count(owner_of.begin(), owner_of.end(), p);
    set_up_ranges();
    set_up_ghosts();
  }

  void
  UnknownExchange::switch_split(
    const int                                   target,
    const std::vector<types::global_dof_index> &moved)
  {
    // Only the rows that change hands are touched (a move costs no pass
    // over all unknowns): their owner, the counts and this rank's ranges
    // (with them added or taken out). The lists of owned unknowns follow
    // when they are read (refresh_owned_lists()).
    const unsigned int from = target > present_split ? 1 : 0;
    for (const auto i : moved)
      {
        owner_of[i]   = 1 - from;
        owned_here[i] = (1 - from) == rank;
      }
    owned_count[from] -= moved.size();
    owned_count[1 - from] += moved.size();
    owned_lists_stale = true;
    // The moved rows as ranges, then this rank's ranges with or without
    // them (both lists ascending and disjoint).
    std::vector<std::pair<types::global_dof_index, types::global_dof_index>>
      moved_ranges, joined;
    for (const auto i : moved)
      if (!moved_ranges.empty() && moved_ranges.back().second == i)
        ++moved_ranges.back().second;
      else
        moved_ranges.emplace_back(i, i + 1);
    if (rank != from)
      {
        std::vector<std::pair<types::global_dof_index, types::global_dof_index>>
          all;
        all.reserve(ranges.size() + moved_ranges.size());
        std::merge(ranges.begin(),
                   ranges.end(),
                   moved_ranges.begin(),
                   moved_ranges.end(),
                   std::back_inserter(all));
        for (const auto &range : all)
          if (!joined.empty() && joined.back().second == range.first)
            joined.back().second = range.second;
          else
            joined.push_back(range);
      }
    else
      {
        std::size_t m = 0;
        for (auto [first, end] : ranges)
          {
            while (m < moved_ranges.size() && moved_ranges[m].second <= first)
              ++m;
            for (; m < moved_ranges.size() && moved_ranges[m].first < end; ++m)
              {
                if (moved_ranges[m].first > first)
                  joined.emplace_back(first, moved_ranges[m].first);
                first = std::max(first, moved_ranges[m].second);
                if (moved_ranges[m].second > end)
                  break;
              }
            if (first < end)
              joined.emplace_back(first, end);
          }
      }
    ranges.swap(joined);
    set_up_range_offsets();
    AssertThrow(range_offsets.back() == owned_count[rank], ExcInternalError());
    present_split = target;
    set_up_ghosts();
  }

  void
  UnknownExchange::refresh_owned_lists() const
  {
    if (!owned_lists_stale)
      return;
    // In ascending order (the serial pass's order of the rows), sized
    // exactly: these lists are as long as the rank's rows.
    for (unsigned int p = 0; p < 2; ++p)
      {
        owned_by_rank[p].clear();
        owned_by_rank[p].shrink_to_fit();
        owned_by_rank[p].reserve(owned_count[p]);
      }
    for (types::global_dof_index i = 0; i < owner_of.size(); ++i)
      owned_by_rank[owner_of[i]].push_back(i);
    owned_lists_stale = false;
  }

  void
  UnknownExchange::set_up_ghosts()
  {
    // (Claimed balancing: the band itself comes with the band's updates.)
    ghosts        = needs_at(rank, present_split);
    peers         = {1 - rank};
    send_lists    = {needs_at(1 - rank, present_split)};
    receive_lists = {ghosts};
    all_sent      = send_lists[0];
  }

  std::vector<types::global_dof_index>
  UnknownExchange::needs_at(const unsigned int p, const int split) const
  {
    // Rank 0 reads layer split + 1 of rank 1, rank 1 layer split of rank 0,
    // both the shared unknowns the other owns (claimed balancing: the
    // other's layer next to the band, and the shared unknowns it owns at
    // the present split).
    const int layer = !claims_band() ? split : (p == 0 ? max_split : min_split);
    std::vector<types::global_dof_index> needs =
      layer_lists[layer + (p == 0 ? 1 : 0) - min_split];
    for (std::size_t k = 0; k < shared_unknowns.size(); ++k)
      if ((layer_of_shared[k] <= split) != (p == 0))
        needs.push_back(shared_unknowns[k]);
    std::sort(needs.begin(), needs.end());
    needs.erase(std::unique(needs.begin(), needs.end()), needs.end());
    return needs;
  }

  std::vector<types::global_dof_index>
  UnknownExchange::rows_between(const int target) const
  {
    std::vector<types::global_dof_index> rows;
    for (int s = std::min(present_split, target) + 1;
         s <= std::max(present_split, target);
         ++s)
      rows.insert(rows.end(),
                  layer_lists[s - min_split].begin(),
                  layer_lists[s - min_split].end());
    std::sort(rows.begin(), rows.end());
    return rows;
  }

  bool
  UnknownExchange::is_distributed() const
  {
    return n_procs > 1;
  }

  unsigned int
  UnknownExchange::n_ranks() const
  {
    return n_procs;
  }

  unsigned int
  UnknownExchange::this_rank() const
  {
    return rank;
  }

  MPI_Comm
  UnknownExchange::communicator() const
  {
    return comm;
  }

  ArrayView<const types::global_dof_index>
  UnknownExchange::owned_unknowns() const
  {
    if (owned_by_rank.empty())
      return {};
    refresh_owned_lists();
    return make_array_view(owned_by_rank[rank]);
  }

  types::global_dof_index
  UnknownExchange::n_owned_unknowns() const
  {
    return range_offsets.empty() ? 0 : range_offsets.back();
  }

  std::vector<types::global_dof_index>
  UnknownExchange::rows_to_store() const
  {
    if (balancing != LoadBalancing::off)
      return potential_rows;
    return std::vector<types::global_dof_index>(owned_unknowns().begin(),
                                                owned_unknowns().end());
  }

  bool
  UnknownExchange::balances_load() const
  {
    return balancing != LoadBalancing::off;
  }

  LoadBalancing
  UnknownExchange::load_balancing() const
  {
    return balancing;
  }

  bool
  UnknownExchange::claims_band() const
  {
    return balancing == LoadBalancing::claimed ||
           balancing == LoadBalancing::shared_memory;
  }

  bool
  UnknownExchange::shares_state() const
  {
    return balancing == LoadBalancing::shared_memory;
  }

  void
  UnknownExchange::open_claims(const std::size_t n_shared_values)
  {
    if (claims_band() && !claim_window)
      claim_window =
        std::make_shared<ClaimWindow>(comm,
                                      rank,
                                      shares_state() ? n_shared_values : 0);
  }

  double *
  UnknownExchange::shared_values() const
  {
    AssertThrow(claim_window && claim_window->state != nullptr,
                ExcMessage("open_claims() with shared values first"));
    return claim_window->state;
  }

  void
  UnknownExchange::end_shared_pass()
  {
    // The release orders the pass's writes before the count: the other
    // rank that reads the count (acquire) sees them.
    long long *own = claim_window->passes + rank;
    __atomic_store_n(own, *own + 1, __ATOMIC_RELEASE);
  }

  void
  UnknownExchange::wait_for_other_pass() const
  {
    const long long  own   = claim_window->passes[rank];
    const long long *other = claim_window->passes + (1 - rank);
    wait_until([&]() {
      return __atomic_load_n(other, __ATOMIC_ACQUIRE) >= own;
    });
  }

  bool
  UnknownExchange::claim_chunk(int &chunk)
  {
    AssertThrow(claim_window, ExcMessage("open_claims() first"));
    // Each claim adds one to the counter; the band's n chunks go to the
    // first n claims of the pass, rank 0 taking them from the first, rank 1
    // from the last. Each rank claims until its first claim beyond them: a
    // pass adds n + 2. (A rank starts the next pass's claims only after it
    // received the other's band values of this one: sent after its last
    // claim.)
    const int       n        = band_chunk_ranges.size();
    const long long previous = claim_window->fetch_and_increment();
    if (previous - claims_base < n)
      {
        chunk = rank == 0 ? own_claims : n - 1 - own_claims;
        ++own_claims;
        return true;
      }
    meeting_chunk = rank == 0 ? own_claims : n - own_claims;
    claims_base += n + 2;
    own_claims = 0;
    return false;
  }

  const std::vector<std::pair<types::global_dof_index, types::global_dof_index>>
    &
    UnknownExchange::chunk_ranges(const int chunk) const
  {
    AssertIndexRange(chunk, band_chunk_ranges.size());
    return band_chunk_ranges[chunk];
  }

  int
  UnknownExchange::n_band_chunks() const
  {
    return band_chunk_ranges.size();
  }

  int
  UnknownExchange::n_chunks_of_rank_0() const
  {
    return meeting_chunk;
  }

  std::pair<int, int>
  UnknownExchange::claimed_chunks(const unsigned int p) const
  {
    return p == 0 ? std::make_pair(0, meeting_chunk - 1) :
                    std::make_pair(meeting_chunk, n_band_chunks() - 1);
  }

  std::size_t
  UnknownExchange::n_claimed_rows(const unsigned int p) const
  {
    const std::size_t below = chunk_prefix[meeting_chunk];
    return p == 0 ? below : chunk_prefix.back() - below;
  }

  void
  UnknownExchange::post_to_other_rank(const std::vector<double> &values,
                                      const std::size_t          n_received,
                                      const int                  tag,
                                      UpdateUnderWay            &update) const
  {
    post_update(
      values,
      [&](const unsigned int) {
        return values.size();
      },
      [&](const unsigned int) {
        return n_received;
      },
      tag,
      update);
  }

  void
  UnknownExchange::wait_for_receives(UpdateUnderWay &update)
  {
    WaitClock clock;
    const int ierr = MPI_Waitall(update.receive_requests.size(),
                                 update.receive_requests.data(),
                                 MPI_STATUSES_IGNORE);
    AssertThrowMPI(ierr);
  }

  void
  UnknownExchange::start_band_update(const std::vector<double> &values,
                                     const unsigned int         per_row,
                                     const int                  tag,
                                     UpdateUnderWay            &update) const
  {
    AssertDimension(values.size(), per_row * n_claimed_rows(rank));
    const std::size_t n_received = per_row * n_claimed_rows(1 - rank);
    post_to_other_rank(values, n_received, tag, update);
  }

  const std::vector<double> *
  UnknownExchange::complete_band_update(UpdateUnderWay &update) const
  {
    if (!update.started)
      return nullptr;
    wait_for_receives(update);
    update.started = false;
    return &update.receives[0];
  }

  int
  UnknownExchange::split() const
  {
    return present_split;
  }

  std::pair<int, int>
  UnknownExchange::split_bounds() const
  {
    return {min_split, max_split};
  }

  unsigned int
  UnknownExchange::n_moves() const
  {
    return moves;
  }

  std::vector<types::global_dof_index>
  UnknownExchange::owned_counts() const
  {
    if (balancing != LoadBalancing::off)
      return {owned_count[0], owned_count[1]};
    std::vector<types::global_dof_index> counts;
    for (const auto &rows : owned_by_rank)
      counts.push_back(rows.size());
    return counts;
  }

  const std::vector<double> &
  UnknownExchange::pass_time_per_row() const
  {
    return cost_per_row;
  }

  const std::vector<UnknownExchange::PassRecord> &
  UnknownExchange::pass_time_history() const
  {
    return pass_history;
  }

  void
  UnknownExchange::observe_pass_times(const std::vector<double> &seconds,
                                      const std::vector<double> &ends)
  {
    if (balancing == LoadBalancing::off)
      return;
    AssertDimension(seconds.size(), 2);
    if (balancing == LoadBalancing::sweep)
      {
        // From the split a move under way goes to.
        const int from = move_in_flight ? move_target : present_split;
        if (from + sweep_direction > max_split ||
            from + sweep_direction < min_split)
          sweep_direction = -sweep_direction;
        next_split = std::clamp(from + sweep_direction, min_split, max_split);
        return;
      }
    // Measured: the joint rule with this body alone.
    observe_pass_times(std::vector<UnknownExchange *>{this}, seconds, ends);
  }

  bool
  UnknownExchange::balances_whole_body() const
  {
    return balancing != LoadBalancing::off && whole_body;
  }

  void
  UnknownExchange::observe_pass_times(
    const std::vector<UnknownExchange *> &exchanges,
    const std::vector<double>            &seconds,
    const std::vector<double>            &ends)
  {
    if (exchanges.empty())
      return;
    AssertDimension(seconds.size(), 2);
    auto &first = *exchanges[0];
    if (first.balancing == LoadBalancing::sweep)
      {
        for (auto *exchange : exchanges)
          exchange->observe_pass_times(seconds);
        return;
      }
    // Each rank's rows over all bodies (the state kept in the first
    // exchange), and the pass recorded (pass_time_history()); claimed:
    // the rows each computed, and nothing more to choose.
    std::array<double, 2> rows = {{0., 0.}};
    for (const auto *exchange : exchanges)
      for (unsigned int p = 0; p < 2; ++p)
        rows[p] += exchange->claims_band() ?
                     exchange->fixed_count[p] + exchange->n_claimed_rows(p) :
                     exchange->owned_count[p];
    first.pass_history.push_back({{{seconds[0], seconds[1]}},
                                  rows,
                                  ends.size() == 2 ?
                                    std::array<double, 2>{{ends[0], ends[1]}} :
                                    std::array<double, 2>{{0., 0.}}});
    // None while a move is under way: the pass timed the rows of a split
    // about to change.
    for (const auto *exchange : exchanges)
      if (exchange->move_in_flight)
        return;
    for (auto *exchange : exchanges)
      exchange->next_split = exchange->present_split;
    // Each rank's time per row: the mean of the steps so far, then an
    // exponential average over about twenty steps (the first three, with
    // their page faults, left out). A move needs five such steps, and ten
    // since the last move (doc/parallel.md, session 37: replayed on
    // recorded pass times, the first 200 steps with a slowed core took
    // 0.2-2.6 % less than with a first move after 20 steps, 20 between
    // moves and an average that the sixth step weighs half of; about the
    // same once balanced).
    constexpr unsigned int skipped = 3, least_averaged = 5, least_between = 10;
    if (++first.n_observations <= skipped)
      return;
    const unsigned int averaged = first.n_observations - skipped;
    const double       weight   = std::max(1. / averaged, 0.05);
    for (unsigned int p = 0; p < 2; ++p)
      {
        const double cost = seconds[p] / std::max(rows[p], 1.);
        first.cost_per_row[p] += weight * (cost - first.cost_per_row[p]);
      }
    for (auto *exchange : exchanges)
      exchange->cost_per_row = first.cost_per_row;
    if (first.claims_band())
      return; // (the time per row reported only)
    const auto &cost = first.cost_per_row;
    if (!(cost[0] > 0. && cost[1] > 0.) || averaged < least_averaged ||
        (first.last_move_observation > 0 &&
         first.n_observations < first.last_move_observation + least_between))
      return;
    // The positions of a cursor over the bands of all bodies in turn (each
    // from its min_split to its max_split): rank 0's rows at each, and the
    // splits there. The least predicted time max(c0 n0, c1 n1), moved to
    // only if it saves 2 % (the times of single steps scatter by more than
    // a layer's share, which is about 0.5 % at 1e6 unknowns).
    const double total     = rows[0] + rows[1];
    const auto   predicted = [&](const double rows_0) {
      return std::max(cost[0] * rows_0, cost[1] * (total - rows_0));
    };
    // Rank 0's rows with every body at its min_split.
    double rows_0 = rows[0];
    for (const auto *exchange : exchanges)
      for (int s = exchange->present_split; s > exchange->min_split; --s)
        rows_0 -= exchange->layer_lists[s - exchange->min_split].size();
    const double     present = predicted(rows[0]);
    double           best    = present;
    std::vector<int> best_splits, splits;
    for (const auto *exchange : exchanges)
      splits.push_back(exchange->min_split);
    const auto consider = [&]() {
      if (predicted(rows_0) < best)
        {
          best        = predicted(rows_0);
          best_splits = splits;
        }
    };
    consider();
    for (std::size_t e = 0; e < exchanges.size(); ++e)
      for (int s = exchanges[e]->min_split + 1; s <= exchanges[e]->max_split;
           ++s)
        {
          rows_0 +=
            exchanges[e]->layer_lists[s - exchanges[e]->min_split].size();
          splits[e] = s;
          consider();
        }
    if (best_splits.empty() || best > 0.98 * present)
      return;
    first.last_move_observation = first.n_observations;
    for (std::size_t e = 0; e < exchanges.size(); ++e)
      exchanges[e]->next_split = best_splits[e];
  }

  void
  UnknownExchange::apply_split(const std::vector<Vector<double> *> &state)
  {
    if (balancing == LoadBalancing::off || next_split == present_split)
      return;
    AssertThrow(!move_in_flight, ExcMessage("a move is under way"));
    // The layers that change hands, from their old owner.
    const int           low  = std::min(present_split, next_split) + 1;
    const int           high = std::max(present_split, next_split);
    const unsigned int  from = next_split > present_split ? 1 : 0;
    std::vector<double> buffer;
    for (int s = low; s <= high; ++s)
      buffer.resize(buffer.size() +
                    state.size() * layer_lists[s - min_split].size());
    if (rank == from)
      {
        std::size_t k = 0;
        for (const auto *vector : state)
          for (int s = low; s <= high; ++s)
            for (const auto i : layer_lists[s - min_split])
              buffer[k++] = (*vector)[i];
        WaitClock clock;
        const int ierr = MPI_Send(buffer.data(),
                                  buffer.size(),
                                  MPI_DOUBLE,
                                  1 - rank,
                                  4710,
                                  comm);
        AssertThrowMPI(ierr);
      }
    else
      {
        WaitClock clock;
        const int ierr = MPI_Recv(buffer.data(),
                                  buffer.size(),
                                  MPI_DOUBLE,
                                  1 - rank,
                                  4710,
                                  comm,
                                  MPI_STATUS_IGNORE);
        AssertThrowMPI(ierr);
        std::size_t k = 0;
        for (auto *vector : state)
          for (int s = low; s <= high; ++s)
            for (const auto i : layer_lists[s - min_split])
              (*vector)[i] = buffer[k++];
      }
    switch_split(next_split, rows_between(next_split));
    ++moves;
  }

  bool
  UnknownExchange::move_is_due() const
  {
    return balancing != LoadBalancing::off && !move_in_flight &&
           next_split != present_split;
  }

  void
  UnknownExchange::prepare_move()
  {
    AssertThrow(move_is_due(), ExcMessage("no move is due"));
    // The rows that change hands go from `from` to the other rank; each
    // rank sends what it owns now of the other's needs at the new split and
    // of those rows (the other computes the rest itself: it owns them now).
    const auto         moved        = rows_between(next_split);
    const unsigned int from         = next_split > present_split ? 1 : 0;
    const auto         owned_now_by = [&](const unsigned int p) {
      std::vector<types::global_dof_index> rows = needs_at(1 - p, next_split);
      if (p == from)
        rows.insert(rows.end(), moved.begin(), moved.end());
      std::sort(rows.begin(), rows.end());
      rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
      rows.erase(std::remove_if(rows.begin(),
                                rows.end(),
                                [&](const types::global_dof_index i) {
                                  return owner_of[i] != p;
                                }),
                 rows.end());
      return rows;
    };
    move_sent     = owned_now_by(rank);
    move_received = owned_now_by(1 - rank);
    move_sent_velocity_rows.clear();
    move_received_velocity_rows.clear();
    (rank == from ? move_sent_velocity_rows : move_received_velocity_rows) =
      moved;
    move_target = next_split;
  }

  const std::vector<types::global_dof_index> &
  UnknownExchange::move_sent_unknowns() const
  {
    return move_sent;
  }

  const std::vector<types::global_dof_index> &
  UnknownExchange::move_sent_rows() const
  {
    return move_sent_velocity_rows;
  }

  void
  UnknownExchange::start_move(const std::vector<double> &values,
                              const int                  tag,
                              UpdateUnderWay            &update)
  {
    AssertThrow(move_is_due() && move_target == next_split,
                ExcMessage("start_move() needs prepare_move() first"));
    AssertDimension(values.size(),
                    move_sent.size() + move_sent_velocity_rows.size());
    const std::size_t n_received =
      move_received.size() + move_received_velocity_rows.size();
    post_to_other_rank(values, n_received, tag, update);
    update.move    = true;
    move_in_flight = true;
  }

  void
  UnknownExchange::complete_move(Vector<double> *displacement,
                                 Vector<double> *half_step_velocity,
                                 UpdateUnderWay &update)
  {
    if (!update.started || !update.move)
      return;
    wait_for_receives(update);
    update.started = false;
    update.move    = false;
    move_in_flight = false;
    if (displacement == nullptr || half_step_velocity == nullptr)
      {
        next_split = present_split; // cancelled
        return;
      }
    const auto &received = update.receives[0];
    std::size_t k        = 0;
    for (const auto i : move_received)
      (*displacement)[i] = received[k++];
    for (const auto i : move_received_velocity_rows)
      (*half_step_velocity)[i] = received[k++];
    // (prepare_move() kept the moved rows with the velocities' lists.)
    const unsigned int from = move_target > present_split ? 1 : 0;
    switch_split(move_target,
                 rank == from ? move_sent_velocity_rows :
                                move_received_velocity_rows);
    ++moves;
    ++moves_without_meeting;
  }

  unsigned int
  UnknownExchange::n_moves_without_meeting() const
  {
    return moves_without_meeting;
  }

  void
  UnknownExchange::set_up_ranges()
  {
    ranges.clear();
    for (types::global_dof_index i = 0; i < owned_here.size(); ++i)
      if (owned_here[i] == 0)
        continue;
      else if (!ranges.empty() && ranges.back().second == i)
        ++ranges.back().second;
      else
        ranges.emplace_back(i, i + 1);
    set_up_range_offsets();
  }

  void
  UnknownExchange::set_up_range_offsets()
  {
    range_offsets.assign(1, 0);
    range_offsets.reserve(ranges.size() + 1);
    for (const auto &[first, end] : ranges)
      range_offsets.push_back(range_offsets.back() + (end - first));
  }

  const std::vector<types::global_dof_index> &
  UnknownExchange::owned_range_offsets() const
  {
    return range_offsets;
  }

  const std::vector<types::global_dof_index> &
  UnknownExchange::ghost_unknowns() const
  {
    return ghosts;
  }

  const std::vector<std::pair<types::global_dof_index, types::global_dof_index>>
    &
    UnknownExchange::owned_ranges() const
  {
    return ranges;
  }

  bool
  UnknownExchange::is_owned(const types::global_dof_index unknown) const
  {
    return n_procs == 1 || owned_here[unknown] != 0;
  }

  bool
  UnknownExchange::owns_cell(const unsigned int active_cell_index) const
  {
    return n_procs == 1 || cells_here[active_cell_index] != 0;
  }

  void
  UnknownExchange::finish_update(
    Vector<double>                         &vector,
    const std::vector<std::vector<double>> &receives) const
  {
    for (unsigned int k = 0; k < peers.size(); ++k)
      for (std::size_t j = 0; j < receive_lists[k].size(); ++j)
        vector[receive_lists[k][j]] = receives[k][j];
  }

  void
  UnknownExchange::update_ghost_values(Vector<double> &vector) const
  {
    update_ghost_values({{this, &vector}});
  }

  void
  UnknownExchange::update_ghost_values(
    const std::vector<std::pair<const UnknownExchange *, Vector<double> *>>
      &vectors)
  {
    if (std::all_of(vectors.begin(), vectors.end(), [](const auto &vector) {
          return vector.first->peers.empty();
        }))
      return; // one process: nothing to send
    // Every rank lists the vectors in the same order: the k-th vector's
    // messages carry tag k. (The sends are waited for when the updates go.)
    std::vector<UpdateUnderWay> updates(vectors.size());
    std::vector<double>         values;
    for (unsigned int v = 0; v < vectors.size(); ++v)
      {
        const auto &exchange = *vectors[v].first;
        values.clear();
        for (const auto i : exchange.all_sent)
          values.push_back((*vectors[v].second)[i]);
        exchange.start_ghost_update(values, 4711 + v, updates[v]);
      }
    for (unsigned int v = 0; v < vectors.size(); ++v)
      vectors[v].first->complete_ghost_update(*vectors[v].second, updates[v]);
  }

  void
  UnknownExchange::gather(Vector<double> &vector) const
  {
    if (n_procs == 1)
      return;
    refresh_owned_lists();
    // Each rank's owned entries in turn, in pieces broadcast from their
    // owner: no buffer of the vector's length (this runs at the memory
    // peak, in the initial acceleration).
    constexpr std::size_t piece = std::size_t(1) << 16;
    std::vector<double>   buffer;
    for (unsigned int p = 0; p < n_procs; ++p)
      {
        const auto &owned = owned_by_rank[p];
        for (std::size_t first = 0; first < owned.size(); first += piece)
          {
            const std::size_t end = std::min(owned.size(), first + piece);
            buffer.resize(end - first);
            if (p == rank)
              for (std::size_t j = first; j < end; ++j)
                buffer[j - first] = vector[owned[j]];
            const int ierr =
              MPI_Bcast(buffer.data(), buffer.size(), MPI_DOUBLE, p, comm);
            AssertThrowMPI(ierr);
            if (p != rank)
              for (std::size_t j = first; j < end; ++j)
                vector[owned[j]] = buffer[j - first];
          }
      }
  }

  void
  UnknownExchange::sum(std::vector<double> &values) const
  {
    if (n_procs == 1)
      return;
    SumUnderWay under_way;
    start_sum(values, under_way);
    complete_sum(under_way, values);
  }

  UnknownExchange::UpdateUnderWay::~UpdateUnderWay()
  {
    if (!mpi_is_running())
      return;
    for (auto &requests : send_requests)
      MPI_Waitall(requests.size(), requests.data(), MPI_STATUSES_IGNORE);
    if (started)
      MPI_Waitall(receive_requests.size(),
                  receive_requests.data(),
                  MPI_STATUSES_IGNORE);
  }

  UnknownExchange::SumUnderWay::~SumUnderWay()
  {
    if (started && shared_index < 0 && mpi_is_running())
      MPI_Wait(&request, MPI_STATUS_IGNORE);
  }

  const std::vector<types::global_dof_index> &
  UnknownExchange::sent_unknowns() const
  {
    return all_sent;
  }

  void
  UnknownExchange::start_ghost_update(const std::vector<double> &values,
                                      const int                  tag,
                                      UpdateUnderWay            &update) const
  {
    AssertDimension(values.size(), all_sent.size());
    post_update(
      values,
      [&](const unsigned int k) {
        return send_lists[k].size();
      },
      [&](const unsigned int k) {
        return receive_lists[k].size();
      },
      tag,
      update);
  }

  template <typename SendSize, typename ReceiveSize>
  void
  UnknownExchange::post_update(const std::vector<double> &values,
                               const SendSize            &send_size,
                               const ReceiveSize         &receive_size,
                               const int                  tag,
                               UpdateUnderWay            &update) const
  {
    AssertThrow(!update.started,
                ExcMessage("a ghost update is under way already"));
    if (peers.empty())
      return;
    // The sends of two updates ago, whose buffer is reused: long taken.
    update.last_sends   = 1 - update.last_sends;
    auto &sends         = update.sends[update.last_sends];
    auto &send_requests = update.send_requests[update.last_sends];
    int   ierr;
    {
      WaitClock clock;
      ierr = MPI_Waitall(send_requests.size(),
                         send_requests.data(),
                         MPI_STATUSES_IGNORE);
      AssertThrowMPI(ierr);
    }
    send_requests.assign(peers.size(), MPI_REQUEST_NULL);
    update.receive_requests.assign(peers.size(), MPI_REQUEST_NULL);
    sends.resize(peers.size());
    update.receives.resize(peers.size());
    for (unsigned int k = 0; k < peers.size(); ++k)
      {
        update.receives[k].resize(receive_size(k));
        ierr = MPI_Irecv(update.receives[k].data(),
                         update.receives[k].size(),
                         MPI_DOUBLE,
                         peers[k],
                         tag,
                         comm,
                         &update.receive_requests[k]);
        AssertThrowMPI(ierr);
      }
    std::size_t first = 0;
    for (unsigned int k = 0; k < peers.size(); ++k)
      {
        sends[k].assign(values.begin() + first,
                        values.begin() + first + send_size(k));
        first += send_size(k);
        ierr = MPI_Isend(sends[k].data(),
                         sends[k].size(),
                         MPI_DOUBLE,
                         peers[k],
                         tag,
                         comm,
                         &send_requests[k]);
        AssertThrowMPI(ierr);
      }
    update.started = true;
  }

  void
  UnknownExchange::complete_ghost_update(Vector<double> &vector,
                                         UpdateUnderWay &update) const
  {
    if (!update.started)
      return;
    AssertThrow(!update.move, ExcMessage("a move: see complete_move()"));
    wait_for_receives(update);
    update.started = false;
    finish_update(vector, update.receives);
  }

  void
  UnknownExchange::start_sum(const std::vector<double> &values,
                             SumUnderWay               &sum) const
  {
    AssertThrow(!sum.started, ExcMessage("a sum is under way already"));
    sum.own = values;
    if (n_procs == 1)
      return;
    // Both ranks on one node: through the claims' window, no message, one
    // such sum at a time (both ranks call the same sums in the same order,
    // so both take the same way). Its slot is free once the other rank has
    // read the sum that used it last (sum_slots sums ago).
    if (claim_window && n_procs == 2 &&
        values.size() <= ClaimWindow::sum_capacity &&
        claim_window->sums_started == claim_window->sums_completed)
      {
        ClaimWindow     &w    = *claim_window;
        const long long  k    = w.sums_started++;
        const long long *read = w.sums_completed_by + (1 - rank);
        wait_until([&]() {
          return __atomic_load_n(read, __ATOMIC_ACQUIRE) >=
                 k - ClaimWindow::sum_slots + 1;
        });
        std::copy(values.begin(), values.end(), w.sum_slot(rank, k));
        __atomic_store_n(w.sums_started_by + rank, k + 1, __ATOMIC_RELEASE);
        sum.shared_index = k;
        sum.started      = true;
        return;
      }
    sum.all.resize(values.size() * n_procs);
    const int ierr = MPI_Iallgather(sum.own.data(),
                                    sum.own.size(),
                                    MPI_DOUBLE,
                                    sum.all.data(),
                                    sum.own.size(),
                                    MPI_DOUBLE,
                                    comm,
                                    &sum.request);
    AssertThrowMPI(ierr);
    sum.started = true;
  }

  void
  UnknownExchange::complete_sum(SumUnderWay         &sum,
                                std::vector<double> &values) const
  {
    values = sum.own;
    if (!sum.started)
      return;
    if (sum.shared_index >= 0)
      {
        ClaimWindow     &w       = *claim_window;
        const long long  k       = sum.shared_index;
        const long long *started = w.sums_started_by + (1 - rank);
        wait_until([&]() {
          return __atomic_load_n(started, __ATOMIC_ACQUIRE) >= k + 1;
        });
        // In the ranks' order, as below: the same bits.
        const double *first  = w.sum_slot(0, k);
        const double *second = w.sum_slot(1, k);
        for (std::size_t j = 0; j < values.size(); ++j)
          values[j] = first[j] + second[j];
        AssertThrow(w.sums_completed == k,
                    ExcMessage("the ranks' sums complete in order"));
        __atomic_store_n(w.sums_completed_by + rank,
                         ++w.sums_completed,
                         __ATOMIC_RELEASE);
        sum.shared_index = -1;
        sum.started      = false;
        return;
      }
    {
      WaitClock clock;
      const int ierr = MPI_Wait(&sum.request, MPI_STATUS_IGNORE);
      AssertThrowMPI(ierr);
    }
    sum.started = false;
    // Gathered and summed in the ranks' order: the same bits everywhere.
    for (std::size_t j = 0; j < values.size(); ++j)
      {
        values[j] = sum.all[j];
        for (unsigned int p = 1; p < n_procs; ++p)
          values[j] += sum.all[p * values.size() + j];
      }
  }

  double
  UnknownExchange::max(const double value) const
  {
    return n_procs == 1 ? value : Utilities::MPI::max(value, comm);
  }

  template UnknownExchange::UnknownExchange(
    const UnknownPartition<2> &,
    const MPI_Comm,
    const std::vector<types::global_dof_index> &,
    const LoadBalancing,
    const double);
} // namespace isoimpact
