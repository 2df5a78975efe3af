// Layer 3: the communication of a step that runs on several MPI ranks
// (issue 13, doc/parallel.md): every rank holds vectors of all unknowns, but
// computes only the rows of the unknowns it owns (UnknownPartition); the
// other entries it reads, its ghosts, come from their owners.
#ifndef isoimpact_unknown_exchange_h
#define isoimpact_unknown_exchange_h

#include <deal.II/base/mpi.h>

#include <deal.II/lac/vector.h>

#include <isoimpact/discretization/unknown_partition.h>

#include <utility>
#include <vector>

namespace isoimpact
{
  // The ranks of MPI_COMM_WORLD and this process's rank: 1 and 0 if MPI is
  // not initialised (the program started without a launcher).
  unsigned int
  n_world_ranks();
  unsigned int
  world_rank();

  class UnknownExchange
  {
  public:
    // One process: every unknown is owned, nothing is exchanged.
    UnknownExchange() = default;

    /**
     * The rank's ghosts are its relevant unknowns that another rank owns,
     * and the `shared` unknowns (those every rank reads, the contact
     * surfaces') that another rank owns. Every rank evaluates the same
     * partition, so each knows what to send to whom without asking.
     */
    template <int dim>
    UnknownExchange(const UnknownPartition<dim> &partition,
                    const MPI_Comm               communicator,
                    const std::vector<dealii::types::global_dof_index> &shared);

    bool
    is_distributed() const;
    unsigned int
    n_ranks() const;
    unsigned int
    this_rank() const;
    MPI_Comm
    communicator() const;

    // The unknowns this rank owns and its ghosts (both sorted; empty on one
    // process).
    const std::vector<dealii::types::global_dof_index> &
    owned_unknowns() const;
    const std::vector<dealii::types::global_dof_index> &
    ghost_unknowns() const;
    // The owned unknowns as ranges [first, end) (ascending).
    const std::vector<std::pair<dealii::types::global_dof_index,
                                dealii::types::global_dof_index>> &
    owned_ranges() const;
    // Whether this rank owns an unknown (every unknown on one process).
    bool
    is_owned(const dealii::types::global_dof_index unknown) const;
    // Whether the cell (active_cell_index()) is one of this rank's part
    // (every cell on one process): the cells it writes to ParaView.
    bool
    owns_cell(const unsigned int active_cell_index) const;

    // The ghosts of `vector` receive their owners' values.
    void
    update_ghost_values(dealii::Vector<double> &vector) const;
    // The same for several vectors (of several bodies) in one round of
    // messages: the ranks wait for each other once.
    static void
    update_ghost_values(
      const std::vector<
        std::pair<const UnknownExchange *, dealii::Vector<double> *>> &vectors);
    // Every entry of `vector` receives its owner's value.
    void
    gather(dealii::Vector<double> &vector) const;
    // The sum over the ranks (the same bits on every rank).
    void
    sum(std::vector<double> &values) const;
    // The largest value over the ranks.
    double
    max(const double value) const;

  private:
    MPI_Comm                                     comm    = MPI_COMM_SELF;
    unsigned int                                 n_procs = 1;
    unsigned int                                 rank    = 0;
    std::vector<dealii::types::global_dof_index> owned, ghosts;
    std::vector<unsigned char>                   owned_here;
    std::vector<unsigned char>                   cells_here; // several ranks
    std::vector<std::pair<dealii::types::global_dof_index,
                          dealii::types::global_dof_index>>
      ranges;
    // Per peer rank: the entries sent to it and received from it, sorted.
    std::vector<unsigned int>                                 peers;
    std::vector<std::vector<dealii::types::global_dof_index>> send_lists,
      receive_lists;
    // For gather(): every rank's owned unknowns, sorted.
    std::vector<std::vector<dealii::types::global_dof_index>> owned_by_rank;
    // Posts the receives and sends of `vector` (tag `tag`) into `requests`
    // with buffers of its own; finish_update() unpacks after the wait.
    void
    start_update(const dealii::Vector<double>     &vector,
                 const int                         tag,
                 std::vector<std::vector<double>> &sends,
                 std::vector<std::vector<double>> &receives,
                 std::vector<MPI_Request>         &requests) const;
    void
                                finish_update(dealii::Vector<double>                 &vector,
                                              const std::vector<std::vector<double>> &receives) const;
    mutable std::vector<double> gather_buffer;
  };
} // namespace isoimpact

#endif
