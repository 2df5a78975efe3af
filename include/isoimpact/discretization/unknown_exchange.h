// Layer 3: the communication of a step that runs on several MPI ranks
// (issue 13, doc/parallel.md): every rank holds vectors of all unknowns, but
// computes only the rows of the unknowns it owns (UnknownPartition); the
// other entries it reads, its ghosts, come from their owners.
#ifndef isoimpact_unknown_exchange_h
#define isoimpact_unknown_exchange_h

#include <deal.II/base/array_view.h>
#include <deal.II/base/mpi.h>

#include <deal.II/lac/vector.h>

#include <isoimpact/discretization/unknown_partition.h>
#include <isoimpact/nurbs/enum_names.h>

#include <array>
#include <memory>
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

  /**
   * Load balancing of a split over 2 ranks (doc/parallel.md, session 17):
   * the ranks' rows near their interface move between them at run time.
   * measured: after each step's passes, towards equal pass times (the
   * ranks' cores and memory run at unequal speeds for a whole run);
   * sweep: one layer of rows per step, back and forth over the whole band
   * (a check of the machinery; the motion has the same bits either way).
   * claimed: within each step: both ranks hold the whole band, compute
   * their rows outside it, then claim its chunks of consecutive rows one at
   * a time from either end (an atomic counter in memory both ranks share)
   * until they meet, and send each other what they computed
   * (doc/parallel.md, session 38).
   * shared_memory: claimed, with the body's state in memory both ranks map
   * (MPI_Win_allocate_shared): each rank writes its rows where the other
   * reads them, and the step sends no message (doc/parallel.md, session
   * 40).
   * automatic: shared_memory for a body whole on a rank where both ranks
   * are on one node and /dev/shm has room, measured else (the constructor
   * decides; doc/parallel.md, session 41).
   */
  enum class LoadBalancing
  {
    automatic,
    off,
    measured,
    sweep,
    claimed,
    shared_memory
  };

  // Their names in Parallel/Load balancing.
  inline constexpr EnumNames<LoadBalancing, 6> load_balancing_names{
    "load balancing",
    {{{LoadBalancing::automatic, "automatic"},
      {LoadBalancing::measured, "measured"},
      {LoadBalancing::off, "off"},
      {LoadBalancing::sweep, "sweep"},
      {LoadBalancing::claimed, "claimed"},
      {LoadBalancing::shared_memory, "shared memory"}}}};

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
    /**
     * With `balancing` (2 ranks only, else ignored) the unknowns of the
     * partition's interface layers (UnknownPartition::interface_layers())
     * up to `band_fraction` of each part's unknowns (at least one layer)
     * may move to the other
     * rank: rows_to_store() lists them with the owned ones.
     */
    template <int dim>
    UnknownExchange(const UnknownPartition<dim> &partition,
                    const MPI_Comm               communicator,
                    const std::vector<dealii::types::global_dof_index> &shared,
                    const LoadBalancing balancing     = LoadBalancing::off,
                    const double        band_fraction = 0.15);

    bool
    is_distributed() const;
    unsigned int
    n_ranks() const;
    unsigned int
    this_rank() const;
    MPI_Comm
    communicator() const;

    // The unknowns this rank owns and its ghosts (empty on one process).
    dealii::ArrayView<const dealii::types::global_dof_index>
    owned_unknowns() const;
    const std::vector<dealii::types::global_dof_index> &
    ghost_unknowns() const;
    // Their number (owned_unknowns().size(), without forming the list).
    dealii::types::global_dof_index
    n_owned_unknowns() const;
    // The owned unknowns as ranges [first, end) (ascending).
    const std::vector<std::pair<dealii::types::global_dof_index,
                                dealii::types::global_dof_index>> &
    owned_ranges() const;
    // Where each owned range starts in the count of owned unknowns, and the
    // count last (owned_ranges().size() + 1 entries).
    const std::vector<dealii::types::global_dof_index> &
    owned_range_offsets() const;
    // The rows this rank may own (sorted): the rows of the stiffness to
    // build (the owned ones without load balancing).
    std::vector<dealii::types::global_dof_index>
    rows_to_store() const;

    // Load balancing (collective calls, every rank alike).
    bool
    balances_load() const;
    // The balancing in force (off without it; automatic resolved).
    LoadBalancing
    load_balancing() const;

    // Claimed balancing (LoadBalancing::claimed): owned_ranges() and
    // n_owned_unknowns() are then the rows outside the band (each rank's
    // fixed rows; with them the band's shared unknowns, which only their
    // owner computes, but for a body whole on a rank with the state shared,
    // whose band holds them), is_owned() and the owned lists the
    // partition's split (the owners of output, sums and contact forces).
    // The band's other rows in chunks of consecutive rows, rank 0 claiming
    // them from the first, rank 1 from the last.
    bool
    claims_band() const;
    // Load balancing = shared memory (claims_band() too).
    bool
    shares_state() const;
    // The shared state's values per unknown (the present and the next
    // displacement, v^{n+1/2}, a, v).
    static constexpr unsigned int shared_state_values_per_unknown = 5;
    // Opens the claims' counter (collective: every rank opens those of
    // the bodies in the same order; nothing without claimed balancing),
    // and with shares_state() n_shared_values doubles in memory both ranks
    // map (shared_values()).
    void
    open_claims(const std::size_t n_shared_values = 0);
    double *
    shared_values() const;
    // shares_state(): this rank's pass over the shared values is over (its
    // writes become visible to the other rank), and the wait until the
    // other rank has ended as many passes (counted in seconds_waiting()).
    void
    end_shared_pass();
    void
    wait_for_other_pass() const;
    // The next chunk of the band for this rank in this step's pass, or
    // false once the ranks have met (the step's claims end; both ranks
    // claim until then, in every pass of the body).
    bool
    claim_chunk(int &chunk);
    // A chunk's rows as ranges [first, end) (ascending), and the chunks.
    const std::vector<std::pair<dealii::types::global_dof_index,
                                dealii::types::global_dof_index>> &
    chunk_ranges(const int chunk) const;
    int
    n_band_chunks() const;
    // The last pass's meeting: rank 0 computed that many chunks from the
    // first, rank 1 the others.
    int
    n_chunks_of_rank_0() const;
    // The chunks rank p computed in the last pass (first, last; none if
    // first > last), and their number of rows: those one rank sends, the
    // other receives, chunk by chunk in ascending order.
    std::pair<int, int>
    claimed_chunks(const unsigned int p) const;
    std::size_t
    n_claimed_rows(const unsigned int p) const;
    // f(first, end) for the rows [first, end) of those chunks, in order.
    template <typename RangeFunction>
    void
    for_each_claimed_range(const unsigned int p, const RangeFunction &f) const
    {
      const auto [low, high] = claimed_chunks(p);
      for (int c = low; c <= high; ++c)
        for (const auto &[first, end] : band_chunk_ranges[c])
          f(first, end);
    }
    // The next split from every rank's time of this step's pass over its
    // rows (seconds, in rank order; the same values on every rank), and
    // where each rank's pass ended on the monotonic clock (ends, recorded
    // only; none: zeros).
    void
    observe_pass_times(const std::vector<double> &seconds,
                       const std::vector<double> &ends = {});
    // Whether the partition put every unknown in one part (a body whole on
    // a rank): its split is chosen with the other such bodies'.
    bool
    balances_whole_body() const;
    // Bodies whole on ranks (balances_whole_body()): the next splits of
    // all of them at once from each rank's time of this step's passes over
    // all its rows (seconds, in rank order). A rank's time per row is
    // measured over all its bodies; the other rank takes the layers of the
    // first bodies' bands first (only one body is split at a time when
    // each band lies in one part).
    static void
    observe_pass_times(const std::vector<UnknownExchange *> &exchanges,
                       const std::vector<double>            &seconds,
                       const std::vector<double>            &ends = {});
    // One observed pass of the measured balancing (one per step): each
    // rank's pass time [s], its owned rows over the bodies balanced
    // together, and where its pass ended on the monotonic clock [s] (the
    // ranks' waits for each other: benchmarks/pass_ends.py). Recorded in
    // the first exchange of observe_pass_times()
    // (benchmarks/balance_replay.py replays rules on them).
    struct PassRecord
    {
      std::array<double, 2> seconds;
      std::array<double, 2> rows;
      std::array<double, 2> ends;
    };
    const std::vector<PassRecord> &
    pass_time_history() const;
    // Moves the rows to the split observe_pass_times() chose: their entries
    // of `state` (each vector whole-sized) go to their new owner, and the
    // ghost lists follow. Nothing to do if the split is unchanged. The
    // ranks meet here (blocking messages): see start_move() for a move
    // that needs no meeting.
    void
    apply_split(const std::vector<dealii::Vector<double> *> &state);
    // The present split (0: the partition's; > 0: rank 0 owns that many
    // layers of rank 1's part; < 0: the reverse), its bounds, the moves.
    int
    split() const;
    std::pair<int, int>
    split_bounds() const;
    unsigned int
    n_moves() const;
    // Owned unknowns of every rank at the present split.
    std::vector<dealii::types::global_dof_index>
    owned_counts() const;
    // Measured load balancing: every rank's averaged pass time per owned
    // row (s), as the last choice of the split saw it.
    const std::vector<double> &
    pass_time_per_row() const;
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

    // A ghost update whose messages are under way: the ranks need not meet
    // where it starts (doc/parallel.md, session 34).
    // (Destroyed while under way, it waits for its messages.)
    // complete_ghost_update() waits for the receives alone: a send of a
    // size above the eager limit completes only once its receiver has
    // taken it, and a rank that waited for that would meet the other at
    // every step again. Its buffer is reused two updates later (the sends
    // alternate between two buffers).
    struct UpdateUnderWay
    {
      ~UpdateUnderWay();
      std::array<std::vector<std::vector<double>>, 2> sends;
      std::array<std::vector<MPI_Request>, 2>         send_requests;
      std::vector<std::vector<double>>                receives;
      std::vector<MPI_Request>                        receive_requests;
      unsigned int                                    last_sends = 0;
      bool                                            started    = false;
      // A move's update (start_move()): complete it with complete_move().
      bool move = false;
    };
    // The owned unknowns that other ranks read, peer after peer in one list:
    // the order in which start_ghost_update() takes their values.
    const std::vector<dealii::types::global_dof_index> &
    sent_unknowns() const;
    // Sends `values` (those of sent_unknowns(), in its order) to the ranks
    // that read them and posts the receives of this rank's ghosts, with tag
    // `tag`, without waiting. Every rank starts its updates of one tag in
    // the same order.
    void
    start_ghost_update(const std::vector<double> &values,
                       const int                  tag,
                       UpdateUnderWay            &update) const;
    // Waits for an update under way (nothing if none): the ghosts of
    // `vector` receive their owners' values.
    void
    complete_ghost_update(dealii::Vector<double> &vector,
                          UpdateUnderWay         &update) const;

    // Claimed balancing: the band's values.
    // Sends `values` (`per_row` blocks of the values of this rank's
    // claimed_chunks(), each block in their order) and posts the receive of
    // the other rank's, without waiting.
    void
    start_band_update(const std::vector<double> &values,
                      const unsigned int         per_row,
                      const int                  tag,
                      UpdateUnderWay            &update) const;
    // Waits for it: the other rank's values (as it sent them), or nullptr
    // if none is under way.
    const std::vector<double> *
    complete_band_update(UpdateUnderWay &update) const;

    // A move without a meeting (doc/parallel.md, session 36): the pass
    // that forms the next displacement ahead sends, with the rows the
    // other rank reads, the state of the rows that change hands, and the
    // ranks switch to the new split where that update completes.
    // Whether observe_pass_times() chose a split that no move is under
    // way to yet.
    bool
    move_is_due() const;
    // The due move's lists (fixed until it completes or is cancelled): this
    // rank's unknowns whose next displacement it sends (those the other
    // rank reads at the new split or takes over; ascending), and the rows
    // it gives up, whose next half-step velocity goes along.
    void
    prepare_move();
    const std::vector<dealii::types::global_dof_index> &
    move_sent_unknowns() const;
    const std::vector<dealii::types::global_dof_index> &
    move_sent_rows() const;
    // Sends `values` (the displacement of move_sent_unknowns(), then the
    // velocity of move_sent_rows()) and posts the receive of the other
    // rank's, without waiting (as start_ghost_update(), which it replaces
    // in that pass).
    void
    start_move(const std::vector<double> &values,
               const int                  tag,
               UpdateUnderWay            &update);
    // Waits for the move's messages: `displacement` and
    // `half_step_velocity` receive the other rank's entries, and this rank
    // switches to the new split. Without the vectors the move is cancelled
    // (the values are dropped, the split stays and the rows their owners
    // kept compute on): for a step that does not take the displacement
    // formed ahead. Nothing to do if `update` is no move.
    void
    complete_move(dealii::Vector<double> *displacement,
                  dealii::Vector<double> *half_step_velocity,
                  UpdateUnderWay         &update);
    // The moves that were made that way (counted in n_moves() too).
    unsigned int
    n_moves_without_meeting() const;

    // A sum over the ranks under way (start_sum()).
    struct SumUnderWay
    {
      ~SumUnderWay();
      std::vector<double> own, all;
      MPI_Request         request      = MPI_REQUEST_NULL;
      bool                started      = false;
      long long           shared_index = -1; // in the claims' window
    };
    // sum() in two halves: the ranks meet only where it is completed.
    void
    start_sum(const std::vector<double> &values, SumUnderWay &sum) const;
    // The sum (the same bits as sum()) into `values`.
    void
    complete_sum(SumUnderWay &sum, std::vector<double> &values) const;
    // The largest value over the ranks.
    double
    max(const double value) const;

    // This process's time (s) in waits for other ranks' messages of the
    // steps, over all exchanges so far: the ghosts' and the moves'
    // receives, the sends' buffers, the sums and the blocking moves (not
    // gather(), which serves the output). What a rank loses to the
    // others; 0 on one process.
    static double
    seconds_waiting();

  private:
    MPI_Comm     comm    = MPI_COMM_SELF;
    unsigned int n_procs = 1;
    unsigned int rank    = 0;
    // The ghosts (sorted).
    std::vector<dealii::types::global_dof_index> ghosts;
    std::vector<unsigned char>                   owned_here;
    std::vector<unsigned char>                   cells_here; // several ranks
    std::vector<std::pair<dealii::types::global_dof_index,
                          dealii::types::global_dof_index>>
                                                 ranges;
    std::vector<dealii::types::global_dof_index> range_offsets;
    // Per peer rank: the entries sent to it and received from it, sorted.
    std::vector<unsigned int>                                 peers;
    std::vector<std::vector<dealii::types::global_dof_index>> send_lists,
      receive_lists;
    // The send lists one after the other (sent_unknowns()).
    std::vector<dealii::types::global_dof_index> all_sent;
    // Every rank's owned unknowns (sorted; this rank's are
    // owned_unknowns(), all of them serve gather()). With load balancing
    // formed again where read after a move (refresh_owned_lists()), and
    // counted in owned_count.
    mutable std::vector<std::vector<dealii::types::global_dof_index>>
                                                   owned_by_rank;
    mutable bool                                   owned_lists_stale = false;
    std::array<dealii::types::global_dof_index, 2> owned_count       = {{0, 0}};
    // Load balancing over 2 ranks (see LoadBalancing): layer_lists[s -
    // min_split] holds the unknowns of layer s (sorted), s = min_split ..
    // max_split + 1; rank 0 owns the layers <= present_split, rank 1 the
    // others (owner_of). The shared unknowns with their layers. The
    // controller: the mean time per owned row of each rank (exponential
    // average).
    LoadBalancing balancing  = LoadBalancing::off;
    bool          whole_body = false;
    int min_split = 0, max_split = 0, present_split = 0, next_split = 0,
        sweep_direction = 1;
    unsigned int moves = 0, moves_without_meeting = 0;
    // A move sent ahead (start_move()) to move_target, and its lists.
    bool                                         move_in_flight = false;
    int                                          move_target    = 0;
    std::vector<dealii::types::global_dof_index> move_sent, move_received,
      move_sent_velocity_rows, move_received_velocity_rows;
    std::vector<int>                                          layer_of_shared;
    std::vector<dealii::types::global_dof_index>              shared_unknowns;
    std::vector<std::vector<dealii::types::global_dof_index>> layer_lists;
    std::vector<unsigned char> owner_of; // per unknown: 0 or 1
    // The rows this rank may own (rows_to_store()).
    std::vector<dealii::types::global_dof_index> potential_rows;
    // Claimed balancing: the counter both ranks share (a window of
    // MPI-3 shared memory, freed with the last copy), its value where this
    // pass's claims began, this rank's claims so far, the last meeting,
    // each chunk's ranges and the band's rows before each chunk.
    struct ClaimWindow;
    std::shared_ptr<ClaimWindow> claim_window;
    long long                    claims_base = 0;
    int                          own_claims = 0, meeting_chunk = 0;
    std::vector<std::size_t>     chunk_prefix; // rows of the chunks before
    std::array<dealii::types::global_dof_index, 2> fixed_count = {{0, 0}};
    std::vector<std::vector<std::pair<dealii::types::global_dof_index,
                                      dealii::types::global_dof_index>>>
                            band_chunk_ranges;
    std::vector<double>     cost_per_row;
    unsigned int            n_observations = 0, last_move_observation = 0;
    std::vector<PassRecord> pass_history;
    // Lists, ranges and counts for the present split.
    void
    set_up_split();
    // The same after the layers between the present split and `target`
    // changed hands (the present split becomes `target`): `moved`, their
    // rows (rows_between(target)).
    void
    switch_split(const int                                           target,
                 const std::vector<dealii::types::global_dof_index> &moved);
    // The lists of owned unknowns from owner_of, if a split changed them.
    void
    refresh_owned_lists() const;
    // The ghosts and the send and receive lists of the present split.
    void
    set_up_ghosts();
    // The unknowns rank p reads from the other at a split (sorted): the
    // other's layer next to the interface and the shared unknowns it owns.
    std::vector<dealii::types::global_dof_index>
    needs_at(const unsigned int p, const int split) const;
    // The layers' rows between the present split and `target` (sorted),
    // and the rank that gives them up.
    std::vector<dealii::types::global_dof_index>
    rows_between(const int target) const;
    // Posts the receives of `update` (receive_size(k) values from peer k)
    // and sends `values` (send_size(k) of them to peer k, in the peers'
    // order), without waiting.
    template <typename SendSize, typename ReceiveSize>
    void
    post_update(const std::vector<double> &values,
                const SendSize            &send_size,
                const ReceiveSize         &receive_size,
                const int                  tag,
                UpdateUnderWay            &update) const;
    // post_update() of `values` all to the other of 2 ranks, and
    // n_received values from it.
    void
    post_to_other_rank(const std::vector<double> &values,
                       const std::size_t          n_received,
                       const int                  tag,
                       UpdateUnderWay            &update) const;
    // Waits for the receives of an update (counted in seconds_waiting()).
    static void
    wait_for_receives(UpdateUnderWay &update);
    // ranges and range_offsets from owned_here.
    void
    set_up_ranges();
    // range_offsets from ranges.
    void
    set_up_range_offsets();
    // The received values into the ghosts of `vector`.
    void
    finish_update(dealii::Vector<double>                 &vector,
                  const std::vector<std::vector<double>> &receives) const;
  };
} // namespace isoimpact

#endif
