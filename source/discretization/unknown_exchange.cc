// Layer 3: the ghost exchange of a step on several MPI ranks.
#include <deal.II/base/exceptions.h>

#include <isoimpact/discretization/unknown_exchange.h>

#include <algorithm>

using namespace dealii;

namespace isoimpact
{
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
    const std::vector<types::global_dof_index> &shared)
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
    // The ghosts of every rank (each rank computes all of them alike).
    std::vector<std::vector<types::global_dof_index>> ghosts_of(n_procs);
    owned_by_rank.resize(n_procs);
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
    owned  = owned_by_rank[rank];
    ghosts = ghosts_of[rank];
    owned_here.assign(n, 0);
    for (const auto i : owned)
      owned_here[i] = 1;
    cells_here.resize(partition.n_cells());
    for (unsigned int c = 0; c < cells_here.size(); ++c)
      cells_here[c] = partition.cell_owner(c) == rank;
    for (const auto i : owned)
      if (!ranges.empty() && ranges.back().second == i)
        ++ranges.back().second;
      else
        ranges.emplace_back(i, i + 1);
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

  const std::vector<types::global_dof_index> &
  UnknownExchange::owned_unknowns() const
  {
    return owned;
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
  UnknownExchange::start_update(const Vector<double>             &vector,
                                const int                         tag,
                                std::vector<std::vector<double>> &sends,
                                std::vector<std::vector<double>> &receives,
                                std::vector<MPI_Request> &requests) const
  {
    sends.resize(peers.size());
    receives.resize(peers.size());
    for (unsigned int k = 0; k < peers.size(); ++k)
      {
        receives[k].resize(receive_lists[k].size());
        requests.emplace_back();
        const int ierr = MPI_Irecv(receives[k].data(),
                                   receives[k].size(),
                                   MPI_DOUBLE,
                                   peers[k],
                                   tag,
                                   comm,
                                   &requests.back());
        AssertThrowMPI(ierr);
      }
    for (unsigned int k = 0; k < peers.size(); ++k)
      {
        sends[k].resize(send_lists[k].size());
        for (std::size_t j = 0; j < send_lists[k].size(); ++j)
          sends[k][j] = vector[send_lists[k][j]];
        requests.emplace_back();
        const int ierr = MPI_Isend(sends[k].data(),
                                   sends[k].size(),
                                   MPI_DOUBLE,
                                   peers[k],
                                   tag,
                                   comm,
                                   &requests.back());
        AssertThrowMPI(ierr);
      }
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
    // messages carry tag k.
    std::vector<std::vector<std::vector<double>>> sends(vectors.size()),
      receives(vectors.size());
    std::vector<MPI_Request> requests;
    for (unsigned int v = 0; v < vectors.size(); ++v)
      if (!vectors[v].first->peers.empty())
        vectors[v].first->start_update(*vectors[v].second,
                                       4711 + v,
                                       sends[v],
                                       receives[v],
                                       requests);
    const int ierr =
      MPI_Waitall(requests.size(), requests.data(), MPI_STATUSES_IGNORE);
    AssertThrowMPI(ierr);
    for (unsigned int v = 0; v < vectors.size(); ++v)
      if (!vectors[v].first->peers.empty())
        vectors[v].first->finish_update(*vectors[v].second, receives[v]);
  }

  void
  UnknownExchange::gather(Vector<double> &vector) const
  {
    if (n_procs == 1)
      return;
    std::vector<int> counts(n_procs), offsets(n_procs + 1, 0);
    for (unsigned int p = 0; p < n_procs; ++p)
      {
        counts[p]      = owned_by_rank[p].size();
        offsets[p + 1] = offsets[p] + counts[p];
      }
    gather_buffer.resize(offsets[n_procs]);
    std::vector<double> mine(owned.size());
    for (std::size_t j = 0; j < owned.size(); ++j)
      mine[j] = vector[owned[j]];
    const int ierr = MPI_Allgatherv(mine.data(),
                                    mine.size(),
                                    MPI_DOUBLE,
                                    gather_buffer.data(),
                                    counts.data(),
                                    offsets.data(),
                                    MPI_DOUBLE,
                                    comm);
    AssertThrowMPI(ierr);
    for (unsigned int p = 0; p < n_procs; ++p)
      for (std::size_t j = 0; j < owned_by_rank[p].size(); ++j)
        vector[owned_by_rank[p][j]] = gather_buffer[offsets[p] + j];
  }

  void
  UnknownExchange::sum(std::vector<double> &values) const
  {
    if (n_procs == 1)
      return;
    // Gathered and summed in the ranks' order: the same bits everywhere.
    std::vector<double> all(values.size() * n_procs);
    const int           ierr = MPI_Allgather(values.data(),
                                   values.size(),
                                   MPI_DOUBLE,
                                   all.data(),
                                   values.size(),
                                   MPI_DOUBLE,
                                   comm);
    AssertThrowMPI(ierr);
    for (std::size_t j = 0; j < values.size(); ++j)
      {
        values[j] = all[j];
        for (unsigned int p = 1; p < n_procs; ++p)
          values[j] += all[p * values.size() + j];
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
    const std::vector<types::global_dof_index> &);
} // namespace isoimpact
