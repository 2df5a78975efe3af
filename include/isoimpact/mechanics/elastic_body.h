// Layer 4: a linear elastic body: its discretisation, constraints, stiffness
// and mass (consistent or lumped), and its state u, v, a.
#ifndef isoimpact_elastic_body_h
#define isoimpact_elastic_body_h

#include <deal.II/base/array_view.h>

#include <deal.II/lac/precondition.h>

#include <isoimpact/discretization/unknown_exchange.h>
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/mass_redistribution.h>
#include <isoimpact/mechanics/mass_solver.h>
#include <isoimpact/mechanics/paired_rows.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace isoimpact
{
  // u_component = 0 on a boundary (symmetry or roller support).
  struct RollerCondition
  {
    dealii::types::boundary_id boundary_id;
    unsigned int               component;
  };

  // Issue 13 (doc/parallel.md): the MPI ranks a body is split over, and the
  // unknowns every rank reads whole (the contact surfaces').
  // whole_state: every rank computes the whole state (the bipenalty's
  // penalty masses change it on the contact surfaces; mass redistribution
  // makes them massless). shared_rows: every rank also builds the stiffness
  // rows of the shared unknowns (mass redistribution's boundary solve reads
  // them).
  struct RankDistribution
  {
    MPI_Comm                                     communicator;
    std::vector<dealii::types::global_dof_index> shared;
    bool                                         whole_state = false;
    bool                                         shared_rows = false;
    // 2 ranks, lumped mass, no hanging nodes, no whole_state: rows move
    // between the ranks at run time (UnknownExchange).
    LoadBalancing load_balancing = LoadBalancing::off;
    // A rank of `communicator` that owns the whole body (the others read
    // its shared unknowns only; with load balancing on 2 ranks the other
    // may take the layers farthest from them), or invalid: the body split
    // over all ranks.
    unsigned int whole_on_rank = dealii::numbers::invalid_unsigned_int;
    // The body's index in the scene: its messages' tags (the ranks may
    // step the bodies in different orders).
    unsigned int index = 0;
  };

  template <int dim>
  class ElasticBody
  {
  public:
    /**
     * With `ranks` of several processes, the body is split over them
     * (doc/parallel.md): each rank builds the rows of the stiffness matrix
     * of the unknowns it owns (UnknownPartition), and the step
     * (compute_acceleration_and_velocities) computes those rows only; the
     * displacement must then receive its ghosts (UnknownExchange::
     * update_ghost_values) before the next step. The state vectors and the
     * masses stay whole on every rank. The energies of a step are summed
     * over the ranks (sum_step_energies, or when first read). With the
     * consistent mass, hanging nodes (local refinement) or
     * ranks->whole_state the ranks split K u only and every rank computes
     * the whole state (state_is_replicated()); the consistent mass's
     * solve is split by the subtrees of its factor's elimination tree
     * (ComponentMassSolver). No mass redistribution; penalty masses need the
     * whole state; throws otherwise.
     */
    ElasticBody(const std::string                   &name,
                std::unique_ptr<Discretization<dim>> discretization,
                const ElasticMaterial               &material,
                const MassScheme                     mass_scheme,
                const std::vector<RollerCondition>  &rollers,
                const dealii::Tensor<1, dim>        &initial_velocity,
                const RankDistribution              *ranks = nullptr);

    const std::string &
    name() const;
    const Discretization<dim> &
    discretization() const;
    const ElasticMaterial &
    material() const;
    const dealii::AffineConstraints<double> &
    constraints() const;
    MassScheme
    mass_scheme() const;
    // On several ranks: the rows of this rank's unknowns only.
    const dealii::SparseMatrix<double> &
    stiffness_matrix() const;
    // Its rows in pairs (empty if they do not pair up): with load balancing
    // of bodies whole on ranks the matrix itself is released after set-up.
    const PairedRows &
    paired_stiffness_rows() const;
    dealii::types::global_dof_index
    n_dofs() const;

    /**
     * a = M^{-1} (f - K u) with f a force vector in the unknowns before
     * condensation (it is condensed in place); a satisfies the constraints.
     */
    void
    compute_acceleration(const dealii::Vector<double> &u,
                         dealii::Vector<double>       &f,
                         dealii::Vector<double>       &a) const;
    /**
     * compute_acceleration() in two halves: K u of this rank's rows, then
     * the rest (the product's other rows from their owners, the mass). With
     * bodies whole on ranks, every body's first half before any second
     * half lets the ranks multiply side by side (the second halves meet).
     */
    void
    start_acceleration(const dealii::Vector<double> &u) const;
    void
    complete_acceleration(dealii::Vector<double> &f,
                          dealii::Vector<double> &a) const;

    /**
     * One step of central differences after the forces: compute_acceleration
     * of the displacement into `acceleration`, then velocity = v^{n+1/2} +
     * dt/2 a and v^{n+1/2} += dt a (half_step_velocity). With lumped mass and
     * constraints u_i = 0 alone, all of it in one pass with the mat-vec,
     * which consumes f: it is zero on return (step_zeroes_force()).
     * form_whole_step_state = false leaves `velocity` as it was (that of an
     * earlier step), and in the fused pass `acceleration` too: the step
     * needs only v^{n+1/2}, and the two writes cost 5 % of a lumped step at
     * 1e6 unknowns (doc/performance.md). Everything else has the same bits
     * either way.
     *
     * advance_displacement_ahead (the fused pass): the pass also forms
     * u + dt v^{n+3/2} of the owned rows, the next step's displacement,
     * while the row is at hand; the next advance_displacement() with the
     * same dt and velocity vector takes it instead of a pass of its own
     * (the same bits; on one process a second vector, swapped in). The
     * caller must not change the velocity in between. On several ranks the
     * rows other ranks read are formed
     * first and sent at once (UnknownExchange::start_ghost_update()), and
     * that advance_displacement() receives theirs
     * (displacement_ghosts_received()).
     */
    void
    compute_acceleration_and_velocities(
      dealii::Vector<double> &f,
      dealii::Vector<double> &half_step_velocity,
      const double            dt,
      const bool              form_whole_step_state      = true,
      const bool              advance_displacement_ahead = false);

    // Each pass of this body as one task (its rows on one thread; the
    // blocks and their sums as before, so the same bits), or in blocks
    // that the threads share as they come (the default).
    void
    set_pass_on_one_thread(const bool one_thread);

    // A new run of steps (CentralDifference::initialize()): the consistent
    // mass's M v^{n+1/2} carried between steps is formed again by the next
    // step (see energies_of_last_step()).
    void
    restart_steps();

    // Whether compute_acceleration_and_velocities() leaves f zero.
    bool
    step_zeroes_force() const;

    // The only rows where the forces f that reach
    // compute_acceleration_and_velocities() can be nonzero (the contact
    // surfaces' unknowns; sorted): its fused pass then reads and zeroes f on
    // these rows alone and takes f_i = +0 elsewhere, 16 bytes less of a
    // row's traffic, the same bits. Rows outside them must stay zero:
    // check_force_rows() throws where a force there would be lost.
    void
    set_force_rows(std::vector<dealii::types::global_dof_index> rows);
    void
    check_force_rows(const dealii::Vector<double> &f) const;

    // Energies per unit thickness (J/m) and momentum (kg/s per m) of the
    // modelled body, with the mass matrix in use.
    double
    kinetic_energy(const dealii::Vector<double> &v) const;
    // 1/2 x . M y, constrained entries of y set to zero.
    double
    kinetic_energy(const dealii::Vector<double> &x,
                   const dealii::Vector<double> &y) const;
    // 1/2 (v - dt a) . M v with the body's acceleration a: the kinetic
    // energy of central differences at a full step from the half-step
    // velocity v = v^{n+1/2}; one pass for a lumped mass (the history
    // computes it every step). With the consistent mass on several ranks
    // (state_is_replicated()) each rank sums its own rows and the sums are
    // added over the ranks: collective.
    double
    kinetic_energy_at_full_step(const dealii::Vector<double> &v,
                                const double                  dt) const;
    double
    strain_energy(const dealii::Vector<double> &u) const;
    // strain_energy(u) from the product K u that the last call of
    // compute_acceleration() computed: no further product. u must be the
    // displacement of that call, unchanged since.
    double
    strain_energy_of_last_acceleration(const dealii::Vector<double> &u) const;
    // With lumped mass, compute_acceleration_and_velocities() sums both
    // energies in its pass: kinetic_energy_at_full_step(v^{n+1/2}, dt) and
    // strain_energy_of_last_acceleration(u) of that step, exact in the
    // same operations but in another order. With the consistent mass
    // (direct solve; on several ranks each rank alike, on the whole state)
    // it sums them in its velocity update, the kinetic energy
    // 1/2 v^{n-1/2} . M v^{n+1/2} from M v^{n+1/2} carried from step to
    // step (mass_times_half_step_velocity): equal to round-off. Empty
    // otherwise and once compute_acceleration() has been called since.
    struct StepEnergies
    {
      double kinetic = 0.;
      double strain  = 0.;

      StepEnergies &
      operator+=(const StepEnergies &other)
      {
        kinetic += other.kinetic;
        strain += other.strain;
        return *this;
      }
    };
    const std::optional<StepEnergies> &
    energies_of_last_step() const;
    dealii::Tensor<1, dim>
    momentum(const dealii::Vector<double> &v) const;
    // Mass of the body as the mass matrix sees it (kg/m).
    double
    total_mass() const;

    /**
     * Estimate of the stable step of central differences, 2 / omega_max,
     * omega_max^2 = lambda_max(M^{-1} (K + K_c)) by power iteration, K_c an
     * optional additional stiffness (contact springs): add_additional(y, x)
     * adds K_c x to y. Power iteration approaches lambda_max from below,
     * so the estimate approaches the critical step from above (4e-4 relative
     * after 200 iterations in tests/free_flight.cc): keep a margin.
     */
    double
    estimate_critical_time_step(
      const unsigned int n_iterations = 200,
      const std::function<void(dealii::Vector<double> &,
                               const dealii::Vector<double> &)>
        &add_additional = {}) const;
    /**
     * Consistent mass only: solve M a = f by Jacobi-preconditioned CG to
     * relative_tolerance instead of the Cholesky factors (the reference of
     * tests/consistent_mass_solve.cc); 0 returns to the factors.
     */
    void
    use_cg_mass_solve(const double relative_tolerance);
    // The factorised consistent mass (nullptr for lumped mass).
    const ComponentMassSolver *
    consistent_mass_solver() const;

    // The diagonal of a lumped mass matrix (empty for consistent mass).
    const dealii::Vector<double> &
    lumped_masses() const;

    /**
     * Bipenalty (lumped mass only): masses (unknown, kg/m; an unknown may
     * repeat) added to the lumped diagonal that the accelerations use,
     * replacing those of the previous call; the mass of a hanging unknown
     * goes to its masters with |weight|, one on a fixed unknown is dropped.
     * Where a mass changes, the velocity v (the half-step velocity) keeps
     * the momentum (m + m_p) v_i (default; see set_penalty_switching) or
     * stays as it is. Returns the kinetic energy the change brought in,
     * 1/2 sum_i ((m + m_p,new) v_new,i^2 - (m + m_p,old) v_old,i^2).
     */
    double
    set_penalty_masses(
      const std::vector<std::pair<dealii::types::global_dof_index, double>>
                             &masses,
      dealii::Vector<double> &v);
    // true (default): momentum-conserving change of the penalty masses;
    // false: the velocity is kept (Contact/Bipenalty switching).
    void
    set_penalty_switching(const bool conserve_momentum);
    // 1/2 x . M_p y with the penalty masses in use.
    double
    penalty_kinetic_energy(const dealii::Vector<double> &x,
                           const dealii::Vector<double> &y) const;

    /**
     * Mass redistribution (mechanics/mass_redistribution.h): the unknowns of
     * `surface` become massless, their mass goes to the interior unknowns
     * next to them (total mass and first moment kept). Lumped mass only,
     * without hanging-node constraints; throws otherwise. The massless
     * unknowns then get zero acceleration from compute_acceleration(): the
     * time integrator must set them (quasi-static boundary).
     */
    void
    redistribute_mass(const std::vector<BoundarySegment<dim>> &surface);
    // The massless unknowns after redistribute_mass() (sorted; else empty).
    const std::vector<dealii::types::global_dof_index> &
    massless_dofs() const;
    // The lumped masses before redistribute_mass() (empty if none).
    const dealii::Vector<double> &
    lumped_masses_before_redistribution() const;

    // The rows this rank computes and its ghosts (see the constructor).
    const UnknownExchange &
    exchange() const;
    // The cells (active cell indices) whose element matrices this rank
    // computes: those that carry a row it builds; over the ranks, every
    // cell. Null on one process: every cell.
    const CellFilter &
    assembly_cells() const;
    // On several ranks with the consistent mass, hanging nodes or the
    // whole state asked for (see the constructor): every rank computes the
    // whole state from K u, whose rows the ranks compute and gather every step;
    // no ghost values are needed.
    bool
    state_is_replicated() const;
    // u += dt v: on one process the whole displacement; on several ranks
    // the owned entries (the ghosts must then come from their owners),
    // taken from the last pass if it formed them ahead. Several ranks with
    // load balancing: a move the last pass sent ahead completes here (the
    // rows this rank takes over receive their displacement and their
    // entries of half_step_velocity, without a meeting); else a move due
    // is made here (collective, the ranks meet).
    void
    advance_displacement(dealii::Vector<double> &half_step_velocity,
                         const double            dt);
    // Whether the last pass formed the next displacement for this velocity
    // vector and dt (advance_displacement() then swaps it in).
    bool
    displacement_formed_ahead(const dealii::Vector<double> &half_step_velocity,
                              const double                  dt) const;
    // One process: u_i += dt v_i for the unknowns in `rows` (ascending,
    // unique) alone, or with `all_but_rows` for all the others. The two
    // calls together are advance_displacement(), with its bits, and touch
    // no entry twice: the contact can read its surfaces' new displacement
    // while the rest of it is updated.
    void
    advance_displacement_of_rows(
      const dealii::Vector<double>                       &half_step_velocity,
      const double                                        dt,
      const std::vector<dealii::types::global_dof_index> &rows,
      const bool                                          all_but_rows);
    // On several ranks: the energies of the bodies' last steps summed over
    // the ranks in one message (the ranks wait for each other once); with
    // load balancing the message also carries each rank's time of its
    // pass, from which every rank chooses the same next split.
    static void
    sum_step_energies(const std::vector<ElasticBody<dim> *> &bodies);
    // The same in two halves, so that the ranks need not meet at every step
    // (doc/parallel.md, session 34): the sum of the bodies' last steps is
    // started, and completed later. While it is under way the bodies'
    // energies must not be read.
    struct StepEnergiesSum
    {
      std::vector<ElasticBody<dim> *> bodies;
      UnknownExchange::SumUnderWay    sum;
    };
    static void
    start_sum_of_step_energies(const std::vector<ElasticBody<dim> *> &bodies,
                               StepEnergiesSum &under_way);
    // Waits for the sum; the load balancing observes the passes' times. The
    // bodies' energies become the sums if `bodies_at_that_step` (no pass
    // since the start). Returns the sums of the bodies in the sum, in
    // their order (empty if nothing was under way).
    static std::vector<StepEnergies>
    complete_sum_of_step_energies(StepEnergiesSum &under_way,
                                  const bool       bodies_at_that_step);
    // Several ranks: whether the ghosts of `displacement` came with the last
    // advance_displacement() (the owners sent them from the pass before,
    // which formed the displacement ahead); else the caller must update
    // them (after a move of the load balancing too).
    bool
    displacement_ghosts_received() const;
    // The displacement the contact reads (its surfaces' rows are current
    // after advance_displacement()): with the state shared between ranks,
    // the present displacement where the passes wrote it; else the vector.
    dealii::ArrayView<const double>
    contact_displacement() const;
    // Whether a contact reads this body's v^{n+1/2} (contact damping): with
    // the state shared, advance_displacement() then copies the surfaces'
    // rows this rank owns into the caller's vector. Off by default.
    void
    set_contact_reads_velocity(const bool reads);
    // Whether this rank's steps read the contact forces on the body's
    // contact surfaces (the shared unknowns' rows): false on a rank that
    // steps none of those rows (the body whole on another rank, this rank
    // taking at most rows far from them), where the contacts need not form
    // them. True on one process.
    bool
    steps_contact_surface() const;
    // Displacement, velocity and acceleration complete on every rank (for
    // the output; nothing on one process).
    void
    gather_state();
    // Several ranks with claimed load balancing: opens the claims' counter
    // (collective: every rank calls it for the bodies in the same order,
    // before the first step); with Load balancing = shared memory the
    // state's arrays in memory both ranks map.
    void
    open_claims();

    // The state: displacement, velocity and acceleration at the current
    // time, in the unknowns of the discretisation.
    dealii::Vector<double> displacement;
    dealii::Vector<double> velocity;
    dealii::Vector<double> acceleration;

  private:
    // y = M x with the mass in use, constrained entries ignored.
    void
    mass_vmult(dealii::Vector<double>       &y,
               const dealii::Vector<double> &x) const;
    // a = (f - K u) / m on free rows, 0 on constrained ones, K u in
    // stiffness_times_u.
    void
    lumped_step_pass(const dealii::Vector<double> &f,
                     dealii::Vector<double>       &a) const;
    // v^{n+3/2} = v^{n+1/2} + dt a with the consistent mass, and the step's
    // energies: M v^{n+3/2} = M v^{n+1/2} + dt r with r = f - K u
    // condensed (the solve's right-hand side, in f), so that the kinetic
    // energy needs no product with M. The first call, or one with another
    // velocity vector, forms M v^{n+1/2} by a product.
    void
    advance_velocity_with_mass_times_velocity(
      const dealii::Vector<double> &r,
      dealii::Vector<double>       &half_step_velocity,
      const double                  dt);
    // compute_acceleration_and_velocities() with lumped mass: the
    // product K u and the pass of lumped_step_pass() fused row by row.
    // owned_rows_only: the rows of the unknowns this rank owns.
    // u_ahead: where the pass writes u + dt v^{n+3/2} (or nullptr).
    template <bool form_whole_step_state, bool owned_rows_only>
    void
    fused_step(dealii::Vector<double> &f,
               dealii::Vector<double> &half_step_velocity,
               const double            dt,
               double                 *u_ahead = nullptr);
    void
    solve_mass(dealii::Vector<double>       &a,
               const dealii::Vector<double> &f) const;
    // Lumped mass: 1 / m_i (0 where m_i = 0) into inverse_lumped_mass, or
    // with the fused step into step_inverse_mass, zero on constrained rows.
    void
    set_inverse_masses();
    // y = K u (this rank's rows), through the pairs where they exist.
    void
    multiply_by_stiffness(dealii::Vector<double>       &y,
                          const dealii::Vector<double> &u) const;

    std::string                          body_name;
    std::unique_ptr<Discretization<dim>> discretization_ptr;
    ElasticMaterial                      body_material;
    MassScheme                           scheme;
    dealii::AffineConstraints<double>    body_constraints;
    dealii::SparsityPattern              sparsity_pattern;
    dealii::SparseMatrix<double>         stiffness;
    // A copy of the stiffness rows in pairs, for the step's K u.
    PairedRows                   paired_stiffness;
    dealii::SparseMatrix<double> consistent_mass;
    // Several ranks: the whole pattern of the consistent mass (the
    // stiffness has this rank's rows only).
    dealii::SparsityPattern mass_sparsity_pattern;
    dealii::Vector<double>  lumped_mass;
    // Lumped mass without the fused step: 1 / m_i.
    dealii::Vector<double> inverse_lumped_mass;
    dealii::PreconditionJacobi<dealii::SparseMatrix<double>>
                                         mass_preconditioner;
    std::unique_ptr<ComponentMassSolver> mass_solver;
    double                               cg_tolerance = 0.;
    // Lumped mass with constraints u_i = 0 alone: the fused step, with the
    // inverse masses zeroed on the constrained rows.
    bool fused_lumped_step = false;
    // set_force_rows(): whether the fused pass reads f on force_rows only.
    bool                                         force_rows_set = false;
    std::vector<dealii::types::global_dof_index> force_rows;
    std::vector<dealii::types::global_dof_index> massless;
    // The rows of the stiffness this rank built (all on one process).
    dealii::IndexSet               stiffness_rows;
    CellFilter                     row_cells;
    dealii::Vector<double>         mass_before_redistribution;
    dealii::Vector<double>         step_inverse_mass;
    mutable dealii::Vector<double> scratch, mass_times_scratch,
      scratch_previous_velocity;
    // K u of the last compute_acceleration().
    mutable dealii::Vector<double> stiffness_times_u;
    // The energies the fused pass summed (energies_of_last_step()), and its
    // partial sums per block of unknowns (a fixed order: the same bits
    // whatever the threads).
    mutable std::optional<StepEnergies> step_energies;
    // On several ranks: step_energies holds this rank's part only.
    mutable bool step_energies_are_partial = false;
    // ... and are being summed (StepEnergiesSum).
    bool   step_energies_under_way = false;
    double last_pass_seconds       = 0.;
    // Where it ended on the monotonic clock [s] (pass_times.csv).
    double last_pass_end = 0.;
    // The next displacement's rows that other ranks read, sent by the pass
    // before the rest of it (UnknownExchange::sent_unknowns()), and whether
    // the last advance_displacement() received the ghosts.
    std::vector<double>             sent_values;
    UnknownExchange::UpdateUnderWay ghosts_under_way;
    bool                            ghosts_received = false;
    // Claimed balancing: the band's values this rank computed in the last
    // pass, sent after it (v^{n+1/2}, then with the whole step's state a
    // and v), their number per row, and the vector v^{n+1/2} they belong
    // to.
    std::vector<double>             band_values;
    int                             message_tag_offset = 0;
    UnknownExchange::UpdateUnderWay band_under_way;
    unsigned int                    band_values_per_row = 1;
    dealii::Vector<double>         *band_velocity       = nullptr;
    // Waits for the band's values of the other rank's last pass (nothing if
    // received): its v^{n+1/2} (and a, v) into this rank's vectors.
    void
    receive_band_values();
    // Waits for the ghosts sent ahead and drops them (and cancels a move
    // sent with them).
    void
    drop_ghosts_sent_ahead();
    // Load balancing = shared memory (doc/parallel.md, session 40): the
    // state in memory both ranks map, shared_state_arrays arrays of
    // n_dofs() values: two displacements (the present one and the next,
    // which the pass forms ahead), v^{n+1/2}, a and v. The passes read and
    // write them in place; the contact reads the present displacement
    // there (contact_displacement()), the caller's v^{n+1/2} receives its
    // own surface rows for the contact damping, and the vectors above the
    // rest where the ranks meet (gather_state(), a new run of steps).
    // live: the arrays hold the state (filled by the first step's
    // advance_displacement()).
    static constexpr unsigned int shared_state_arrays =
      UnknownExchange::shared_state_values_per_unknown;
    double      *shared_state         = nullptr;
    bool         shared_state_live    = false;
    unsigned int present_displacement = 0;
    // The contact surfaces' unknowns this rank owns (whose v^{n+1/2} it
    // copies for the contact damping: only the owner writes them), at
    // set-up.
    std::vector<dealii::types::global_dof_index> own_surface_rows;
    // With the state shared: the contact surface rows whose forces this
    // rank forms and the other rank's pass may step (the pass leaves them
    // zero), at set-up.
    std::vector<dealii::types::global_dof_index> surface_rows_of_other_pass;
    // steps_contact_surface(), at set-up.
    bool surface_rows_stepped   = true;
    bool contact_reads_velocity = false;
    double *
    shared_array(const unsigned int k) const;
    // The distance between two arrays of the shared state (n_dofs() rounded
    // up to whole cache lines).
    std::size_t
    shared_array_stride() const;
    // This rank's rows of the vectors (its fixed rows, rank 0 the band's
    // too) into the arrays; then the ranks meet: the arrays are live.
    void
    fill_shared_state(const dealii::Vector<double> &half_step_velocity);
    // The whole arrays into the vectors (the caller's v^{n+1/2} if given)
    // once the other rank's pass is over; the ranks meet after it, and the
    // arrays stay live unless `release`.
    void
    copy_shared_state(dealii::Vector<double> *half_step_velocity,
                      const bool              release);
    // The next displacement the pass formed ahead, the step and the
    // velocity vector it belongs to (none: nullptr).
    dealii::Vector<double>            displacement_ahead;
    double                            displacement_ahead_step     = 0.;
    const dealii::Vector<double>     *displacement_ahead_velocity = nullptr;
    mutable std::vector<StepEnergies> block_energies;
    bool                              pass_on_one_thread = false;
    // The consistent mass: M v^{n+1/2} and the vector it belongs to (see
    // advance_velocity_with_mass_times_velocity()).
    dealii::Vector<double>        mass_times_half_step_velocity;
    const dealii::Vector<double> *velocity_of_mass_product = nullptr;
    // Bipenalty: the condensed penalty masses in use and a dense scratch.
    std::vector<std::pair<dealii::types::global_dof_index, double>>
                           penalty_masses;
    dealii::Vector<double> penalty_scratch, previous_penalty_scratch;
    bool                   penalty_momentum_switching = true;
    // The rows this rank computes and its ghosts (serial: all, none).
    UnknownExchange row_exchange;
    bool            replicated_state = false;
  };
} // namespace isoimpact

#endif
