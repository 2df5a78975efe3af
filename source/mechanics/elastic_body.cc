// Layer 4: a linear elastic body.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/parallel.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>

#include <isoimpact/mechanics/elastic_body.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <sstream>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    // The compressed rows of a SparsityPattern (deal.II 9.4 has no public
    // accessor for them; SparseMatrix reads them as a friend): the row
    // starts and column numbers that SparseMatrix::vmult loops over.
    struct CompressedRows : SparsityPatternBase
    {
      static const std::size_t *
      row_starts(const SparsityPatternBase &pattern)
      {
        return (pattern.*(&CompressedRows::rowstart)).get();
      }
      static const SparsityPatternBase::size_type *
      column_numbers(const SparsityPatternBase &pattern)
      {
        return (pattern.*(&CompressedRows::colnums)).get();
      }
    };

    // The messages of the displacement's ghosts sent ahead by the pass and
    // of the band's values (claimed balancing): these tags plus twice the
    // body's index.
    constexpr int ghost_update_tag = 6000, band_update_tag = 6001;

    // Whether every constraint is u_i = 0 (rollers; no hanging nodes): then
    // a lumped-mass step needs no condensation (the fused pass).
    bool
    only_zero_constraints(const AffineConstraints<double> &constraints)
    {
      for (const auto &line : constraints.get_lines())
        if (!line.entries.empty() || line.inhomogeneity != 0.)
          return false;
      return true;
    }

    // u_i += dt v_i for begin <= i < end, per entry as Vector::add does it
    // (the same bits). A 64-bit index: with the unsigned 32-bit
    // types::global_dof_index the loops took about twice as long (session
    // 22, doc/performance.md); GCC -O2 unrolls both without vectorising.
    void
    advance_range(double *__restrict__ u,
                  const double *__restrict__ v,
                  const double      dt,
                  const std::size_t begin,
                  const std::size_t end)
    {
      for (std::size_t i = begin; i < end; ++i)
        u[i] += dt * v[i];
    }

    // range_terms(begin, end, sums) for the rows k < n in blocks of a fixed
    // size over the threads (all on one thread if `one_task`), each block's
    // sums into block_sums; returns their total, added in block order: the
    // same bits whatever the threads.
    template <typename Sums, typename RangeTerms>
    Sums
    sum_over_blocks(const std::size_t  n,
                    std::vector<Sums> &block_sums,
                    const RangeTerms  &range_terms,
                    const bool         one_task)
    {
      constexpr std::size_t block_size = 4096; // even: rows in pairs
      const std::size_t     n_blocks   = (n + block_size - 1) / block_size;
      block_sums.resize(n_blocks);
      parallel::apply_to_subranges(
        std::size_t(0),
        n_blocks,
        [&](const std::size_t first_block, const std::size_t end_block) {
          for (std::size_t block = first_block; block < end_block; ++block)
            {
              Sums sums;
              range_terms(block * block_size,
                          std::min(n, (block + 1) * block_size),
                          sums);
              block_sums[block] = sums;
            }
        },
        one_task ? std::max<std::size_t>(n_blocks, 1) : 1);
      Sums total;
      for (const Sums &sums : block_sums)
        total += sums;
      return total;
    }

    // The same with row_terms(k, sums) row by row.
    template <typename Sums, typename RowTerms>
    Sums
    sum_by_blocks(const std::size_t  n,
                  std::vector<Sums> &block_sums,
                  const RowTerms    &row_terms,
                  const bool         one_task)
    {
      return sum_over_blocks(
        n,
        block_sums,
        [&](const std::size_t begin, const std::size_t end, Sums &sums) {
          for (std::size_t k = begin; k < end; ++k)
            row_terms(k, sums);
        },
        one_task);
    }

    // The diagonal and the nonzero entries of `matrix`, in their order, into
    // `compact` on a pattern of their own (`pattern`): a row of `compact`
    // is summed in the order of the same row of `matrix`, without its
    // zeros, so its products have the same bits.
    void
    copy_nonzero_entries(const SparseMatrix<double> &matrix,
                         SparsityPattern            &pattern,
                         SparseMatrix<double>       &compact)
    {
      const auto kept = [](const auto &entry, const unsigned int row) {
        return entry.value() != 0. || entry.column() == row;
      };
      DynamicSparsityPattern nonzero(matrix.m(), matrix.n());
      for (unsigned int i = 0; i < matrix.m(); ++i)
        for (auto entry = matrix.begin(i); entry != matrix.end(i); ++entry)
          if (kept(*entry, i))
            nonzero.add(i, entry->column());
      compact.clear();
      pattern.copy_from(nonzero);
      compact.reinit(pattern);
      for (unsigned int i = 0; i < matrix.m(); ++i)
        {
          auto target = compact.begin(i);
          for (auto entry = matrix.begin(i); entry != matrix.end(i); ++entry)
            if (kept(*entry, i))
              {
                Assert(target->column() == entry->column(), ExcInternalError());
                target->value() = entry->value();
                ++target;
              }
        }
    }
  } // namespace

  template <int dim>
  ElasticBody<dim>::ElasticBody(
    const std::string                   &name,
    std::unique_ptr<Discretization<dim>> discretization,
    const ElasticMaterial               &material,
    const MassScheme                     mass_scheme,
    const std::vector<RollerCondition>  &rollers,
    const Tensor<1, dim>                &initial_velocity,
    const RankDistribution              *ranks)
    : body_name(name)
    , discretization_ptr(std::move(discretization))
    , body_material(material)
    , scheme(mass_scheme)
  {
    const auto &disc = *discretization_ptr;
    disc.make_constraints(body_constraints);
    for (const auto &roller : rollers)
      disc.constrain_component_on_boundary(roller.boundary_id,
                                           roller.component,
                                           body_constraints);
    body_constraints.close();

    // Several ranks: the partition of the unknowns, then the rows of the
    // owned unknowns from the cells that carry them.
    std::optional<UnknownPartition<dim>> partition;
    std::optional<RowSelection>          owned_rows;
    // With load balancing: the band's rows this rank does not own at the
    // start, which only its lumped pass reads (in pairs, below).
    std::optional<RowSelection> band_rows;
    if (ranks && Utilities::MPI::job_supports_mpi() &&
        Utilities::MPI::n_mpi_processes(ranks->communicator) > 1)
      {
        const unsigned int n_ranks =
          Utilities::MPI::n_mpi_processes(ranks->communicator);
        // Load balancing needs the fused lumped step on owned rows. A body
        // whole on a rank: the other rank may take its layers farthest
        // from the contact surface (counted from the shared unknowns).
        const bool fused_step_possible =
          scheme != MassScheme::consistent && !ranks->whole_state &&
          !ranks->shared_rows && only_zero_constraints(body_constraints);
        const bool balancing =
          fused_step_possible && n_ranks == 2 &&
          ranks->load_balancing != LoadBalancing::off &&
          (ranks->whole_on_rank == numbers::invalid_unsigned_int ||
           !ranks->shared.empty());
        partition.emplace(disc,
                          n_ranks,
                          ranks->whole_on_rank,
                          balancing ? ranks->shared :
                                      std::vector<types::global_dof_index>());
        // The band: 15 % of each part at an interface (split bodies); 30 %
        // of a body whole on a rank, whose band the other rank builds in
        // the room its own matrix leaves (the ranks' times per row differed
        // by up to 39 % for whole runs here, doc/parallel.md, session 31;
        // with the state shared a third of that where the contact
        // surface's unknowns cut it, session 56: UnknownExchange).
        const bool whole_body =
          ranks->whole_on_rank != numbers::invalid_unsigned_int;
        row_exchange            = UnknownExchange(*partition,
                                       ranks->communicator,
                                       ranks->shared,
                                       balancing ? ranks->load_balancing :
                                                              LoadBalancing::off,
                                       whole_body ? 0.30 : 0.15);
        const unsigned int rank = row_exchange.this_rank();
        message_tag_offset      = 2 * ranks->index;
        if (row_exchange.shares_state())
          for (const auto i : ranks->shared)
            if (row_exchange.is_owned(i))
              own_surface_rows.push_back(i);
        // The rows: those the rank may own (with load balancing, the
        // band of the other rank's rows too), and with shared_rows the
        // shared unknowns' (on every rank).
        IndexSet rows(disc.n_dofs()), band(disc.n_dofs());
        {
          const auto owned = row_exchange.owned_unknowns();
          rows.add_indices(owned.begin(), owned.end());
          const auto stored = row_exchange.rows_to_store();
          band.add_indices(stored.begin(), stored.end());
          // A lumped body whole on another rank: this rank steps its band
          // rows at most (a consistent mass's solve, or whole_state, reads
          // every row's force); with the state shared the band may hold
          // contact surface rows, whose forces this rank then forms too.
          surface_rows_stepped =
            scheme == MassScheme::consistent || ranks->whole_state ||
            ranks->whole_on_rank == numbers::invalid_unsigned_int ||
            ranks->whole_on_rank == rank ||
            std::any_of(ranks->shared.begin(),
                        ranks->shared.end(),
                        [&band](const types::global_dof_index i) {
                          return band.is_element(i);
                        });
          band.subtract_set(rows);
          // With the state shared, the surface rows whose contact forces
          // this rank forms and the other rank's pass may step: its own
          // body's in the band, all of the other body's.
          if (row_exchange.shares_state() && surface_rows_stepped)
            {
              if (ranks->whole_on_rank == rank)
                {
                  IndexSet own_band(disc.n_dofs());
                  for (int c = 0; c < row_exchange.n_band_chunks(); ++c)
                    for (const auto &[first, end] :
                         row_exchange.chunk_ranges(c))
                      own_band.add_range(first, end);
                  for (const auto i : ranks->shared)
                    if (own_band.is_element(i))
                      surface_rows_of_other_pass.push_back(i);
                }
              else
                surface_rows_of_other_pass = ranks->shared;
            }
        }
        if (ranks->shared_rows)
          rows.add_indices(ranks->shared.begin(), ranks->shared.end());
        rows.compress();
        band.compress();
        // The cells that contribute to these rows: those that carry an
        // owned unknown or a shared row's and, with hanging nodes, those
        // that carry an unknown constrained to one of the rows; those that
        // carry a band row.
        std::vector<unsigned char> contributes(
          disc.triangulation().n_active_cells(),
          0),
          contributes_to_band(contributes.size(), 0);
        std::vector<types::global_dof_index> indices;
        for (const auto &cell : disc.dof_handler().active_cell_iterators())
          {
            const unsigned int c = cell->active_cell_index();
            contributes[c]       = partition->is_assembly_cell(c, rank);
            if ((contributes[c] || (body_constraints.n_constraints() == 0 &&
                                    !ranks->shared_rows)) &&
                band.is_empty())
              continue;
            disc.get_dof_indices(cell, indices);
            for (const auto i : indices)
              {
                contributes_to_band[c] |= band.is_element(i);
                // (A cell that is not an assembly cell carries no owned
                // unknown.)
                if (ranks->shared_rows)
                  contributes[c] |= rows.is_element(i);
                if (const auto *entries =
                      body_constraints.get_constraint_entries(i))
                  for (const auto &[master, weight] : *entries)
                    contributes[c] |= rows.is_element(master);
              }
          }
        // (The partition's tables are not needed any more.)
        partition.reset();
        owned_rows = RowSelection{rows, [contributes](const unsigned int cell) {
                                    return contributes[cell] != 0;
                                  }};
        if (!band.is_empty())
          band_rows =
            RowSelection{band, [contributes_to_band](const unsigned int cell) {
                           return contributes_to_band[cell] != 0;
                         }};
      }

    stiffness_rows =
      owned_rows ? owned_rows->rows : complete_index_set(disc.n_dofs());
    if (owned_rows)
      row_cells = owned_rows->cells;
    // A rank that owns no row of this body (the body whole on another
    // rank) keeps no stiffness of its own: a pattern of the body's size
    // would hold a row start and a diagonal entry for every unknown. With
    // load balancing it keeps the band's rows in pairs (below).
    const bool owns_no_rows = owned_rows && owned_rows->rows.n_elements() == 0;
    const bool builds_no_rows = owns_no_rows && !band_rows;
    if (!owns_no_rows)
      {
        make_sparsity_pattern(disc,
                              body_constraints,
                              sparsity_pattern,
                              owned_rows ? &*owned_rows : nullptr);
        // The dynamic pattern's rows, freed, go back to the system before
        // the matrix and its pairs take their (mapped) memory.
        malloc_trim(0);
        stiffness.reinit(sparsity_pattern);
        assemble_stiffness_matrix(disc,
                                  material,
                                  body_constraints,
                                  stiffness,
                                  owned_rows ? &*owned_rows : nullptr);
      }

    if (scheme == MassScheme::consistent)
      {
        // Several ranks: the mass and its factor whole on every rank,
        // assembled on the whole pattern.
        SparsityPattern whole_pattern;
        if (owned_rows)
          make_sparsity_pattern(disc, body_constraints, whole_pattern);
        SparseMatrix<double> assembled(owned_rows ? whole_pattern :
                                                    sparsity_pattern);
        assemble_consistent_mass_matrix(disc,
                                        material.density,
                                        body_constraints,
                                        assembled);
        // Stored without its zeros: the mass couples no two components, so
        // half of the stiffness pattern's entries are zero in it. The
        // products (the kinetic energy of every step) then read half the
        // bytes, with the same bits.
        copy_nonzero_entries(assembled, mass_sparsity_pattern, consistent_mass);
        // Each step solves M a = f with a Cholesky factor shared by the
        // components, computed here once; see solve_mass().
        std::vector<unsigned char> components(disc.n_dofs());
        for (types::global_dof_index i = 0; i < components.size(); ++i)
          components[i] = disc.dof_component(i);
        // Several ranks: each substitutes its own subtrees of the
        // factors' elimination trees.
        mass_solver = std::make_unique<ComponentMassSolver>();
        mass_solver->initialize(consistent_mass,
                                components,
                                owned_rows ? ranks->communicator :
                                             MPI_COMM_SELF);
      }
    else
      {
        lumped_mass = assemble_lumped_mass(disc,
                                           material.density,
                                           scheme,
                                           body_constraints);
        // With constraints u_i = 0 alone (rollers, no hanging nodes), the
        // acceleration is a_i = (f - K u)_i / m_i on free rows and 0 on
        // constrained ones: one pass after the mat-vec, no condensation.
        // Its inverse masses (zero on the constrained rows) then serve
        // every solve: the other inverse is not kept.
        fused_lumped_step = only_zero_constraints(body_constraints);
        set_inverse_masses();
      }

    // K u two rows at a time, the same bits as vmult's
    // (doc/performance.md, sessions 23 and 24): in the fused lumped pass
    // and in the consistent step. They pay where a node's components are
    // numbered 2p and 2p + 1 (IGA always, FEA's Cuthill-McKee numbering in
    // practice); a numbering that splits them would fill the blocks with
    // zeros: then one row at a time.
    // With load balancing the band's rows, which only the pass reads, are
    // kept in the pairs alone (assembled apart, then dropped); if the rows
    // do not pair up, they join the stiffness after all.
    if ((fused_lumped_step || mass_solver) && !builds_no_rows)
      {
        SparsityPattern      band_pattern;
        SparseMatrix<double> band_stiffness;
        std::size_t          n_entries =
          stiffness.empty() ? 0 : stiffness.n_nonzero_elements();
        if (band_rows)
          {
            make_sparsity_pattern(disc,
                                  body_constraints,
                                  band_pattern,
                                  &*band_rows);
            band_stiffness.reinit(band_pattern);
            assemble_stiffness_matrix(disc,
                                      material,
                                      body_constraints,
                                      band_stiffness,
                                      &*band_rows);
            n_entries += band_stiffness.n_nonzero_elements();
          }
        std::vector<const SparseMatrix<double> *> parts;
        if (!stiffness.empty())
          parts.push_back(&stiffness);
        if (band_rows)
          parts.push_back(&band_stiffness);
        paired_stiffness.build(parts);
        if (paired_stiffness.n_stored_entries() > 1.25 * n_entries)
          paired_stiffness = PairedRows();
        // Bodies whole on ranks with load balancing: the rank's matrix is
        // read no more (the pass, the power estimate and the Gershgorin
        // bound read the pairs), and the other body's band is built next
        // (Scene: the own body first) in the room it leaves.
        if (row_exchange.balances_whole_body() && !paired_stiffness.empty() &&
            !stiffness.empty())
          {
            stiffness.clear();
            sparsity_pattern.reinit(0, 0, 0);
            malloc_trim(0);
          }
      }
    if (band_rows && paired_stiffness.empty())
      {
        owned_rows->rows.add_indices(band_rows->rows);
        const auto own = owned_rows->cells, other = band_rows->cells;
        owned_rows->cells = [own, other](const unsigned int cell) {
          return own(cell) || other(cell);
        };
        stiffness_rows = owned_rows->rows;
        stiffness.clear();
        make_sparsity_pattern(disc,
                              body_constraints,
                              sparsity_pattern,
                              &*owned_rows);
        stiffness.reinit(sparsity_pattern);
        assemble_stiffness_matrix(disc,
                                  material,
                                  body_constraints,
                                  stiffness,
                                  &*owned_rows);
      }

    // Several ranks without the fused step (consistent mass, hanging
    // nodes): every rank computes the whole state from the whole K u.
    replicated_state = row_exchange.is_distributed() &&
                       (!fused_lumped_step || ranks->whole_state);

    const types::global_dof_index n = disc.n_dofs();
    displacement.reinit(n);
    velocity.reinit(n);
    acceleration.reinit(n);
    // (scratch takes its size where it is used: the lumped step never
    // needs it.)
    // Both bases form a partition of unity: a uniform velocity has equal
    // coefficients.
    for (types::global_dof_index i = 0; i < n; ++i)
      velocity(i) = initial_velocity[disc.dof_component(i)];
    body_constraints.distribute(velocity);

    // A rank with no row of this body reads its contact surface only: the
    // mapping's cache and the unknowns' numbering on the cells go (the band
    // of load balancing is in the pairs; the owner visits every cell).
    if (builds_no_rows || (owns_no_rows && !paired_stiffness.empty()))
      discretization_ptr->release_cell_unknowns();
  }

  template <int dim>
  const std::string &
  ElasticBody<dim>::name() const
  {
    return body_name;
  }

  template <int dim>
  const Discretization<dim> &
  ElasticBody<dim>::discretization() const
  {
    return *discretization_ptr;
  }

  template <int dim>
  const ElasticMaterial &
  ElasticBody<dim>::material() const
  {
    return body_material;
  }

  template <int dim>
  const AffineConstraints<double> &
  ElasticBody<dim>::constraints() const
  {
    return body_constraints;
  }

  template <int dim>
  MassScheme
  ElasticBody<dim>::mass_scheme() const
  {
    return scheme;
  }

  template <int dim>
  const SparseMatrix<double> &
  ElasticBody<dim>::stiffness_matrix() const
  {
    return stiffness;
  }

  template <int dim>
  const PairedRows &
  ElasticBody<dim>::paired_stiffness_rows() const
  {
    return paired_stiffness;
  }

  template <int dim>
  types::global_dof_index
  ElasticBody<dim>::n_dofs() const
  {
    return displacement.size();
  }

  template <int dim>
  void
  ElasticBody<dim>::solve_mass(Vector<double> &a, const Vector<double> &f) const
  {
    if (scheme == MassScheme::consistent && cg_tolerance > 0.)
      {
        // The reference solve: Jacobi CG from the previous acceleration.
        const double norm = f.l2_norm();
        if (norm == 0.)
          {
            a = 0.;
            return;
          }
        SolverControl control(10000, cg_tolerance * norm, false, false);
        SolverCG<Vector<double>> cg(control);
        cg.solve(consistent_mass, a, f, mass_preconditioner);
      }
    else if (scheme == MassScheme::consistent)
      mass_solver->solve(a, f);
    else
      {
        // (The fused step's inverse masses differ on constrained rows
        // only, which every caller sets to zero after the solve.)
        a = f;
        a.scale(fused_lumped_step ? step_inverse_mass : inverse_lumped_mass);
      }
  }

  template <int dim>
  void
  ElasticBody<dim>::set_inverse_masses()
  {
    Vector<double> &inverse =
      fused_lumped_step ? step_inverse_mass : inverse_lumped_mass;
    inverse.reinit(lumped_mass.size());
    for (unsigned int i = 0; i < lumped_mass.size(); ++i)
      inverse(i) = (lumped_mass(i) > 0.) ? 1. / lumped_mass(i) : 0.;
    if (fused_lumped_step)
      for (const auto &line : body_constraints.get_lines())
        step_inverse_mass(line.index) = 0.;
  }

  template <int dim>
  void
  ElasticBody<dim>::use_cg_mass_solve(const double relative_tolerance)
  {
    AssertThrow(scheme == MassScheme::consistent,
                ExcMessage("a CG mass solve needs the consistent mass"));
    AssertThrow(relative_tolerance >= 0.,
                ExcMessage("CG tolerance " +
                           std::to_string(relative_tolerance) +
                           " is not allowed: it must be >= 0"));
    cg_tolerance = relative_tolerance;
    if (cg_tolerance > 0.)
      mass_preconditioner.initialize(consistent_mass);
  }

  template <int dim>
  const ComponentMassSolver *
  ElasticBody<dim>::consistent_mass_solver() const
  {
    return mass_solver.get();
  }

  template <int dim>
  void
  ElasticBody<dim>::multiply_by_stiffness(Vector<double>       &y,
                                          const Vector<double> &u) const
  {
    if (!paired_stiffness.empty())
      paired_stiffness.vmult(y, u); // the same bits
    else if (!stiffness.empty())
      stiffness.vmult(y, u);
    else
      y = 0.; // no row of K on this rank
  }

  template <int dim>
  void
  ElasticBody<dim>::compute_acceleration(const Vector<double> &u,
                                         Vector<double>       &f,
                                         Vector<double>       &a) const
  {
    start_acceleration(u);
    complete_acceleration(f, a);
  }

  template <int dim>
  void
  ElasticBody<dim>::start_acceleration(const Vector<double> &u) const
  {
    step_energies.reset();
    step_energies_are_partial = false;
    stiffness_times_u.reinit(u.size(), true);
    multiply_by_stiffness(stiffness_times_u, u);
  }

  template <int dim>
  void
  ElasticBody<dim>::complete_acceleration(Vector<double> &f,
                                          Vector<double> &a) const
  {
    // Several ranks: each holds its rows of K; the whole product (the
    // initial acceleration) from their owners.
    row_exchange.gather(stiffness_times_u);
    if (fused_lumped_step)
      {
        lumped_step_pass(f, a);
        return;
      }
    body_constraints.condense(f);
    f -= stiffness_times_u;
    body_constraints.set_zero(f);
    solve_mass(a, f);
    body_constraints.distribute(a);
  }

  template <int dim>
  void
  ElasticBody<dim>::compute_acceleration_and_velocities(
    Vector<double> &f,
    Vector<double> &half_step_velocity,
    const double    dt,
    const bool      form_whole_step_state,
    const bool      advance_displacement_ahead)
  {
    displacement_ahead_velocity = nullptr;
    if (!fused_lumped_step || replicated_state)
      {
        // Resets step_energies: the separate functions compute them.
        compute_acceleration(displacement, f, acceleration);
        if (form_whole_step_state)
          {
            velocity = half_step_velocity;
            velocity.add(0.5 * dt, acceleration);
          }
        // Several ranks: the whole state on each (replicated_state), each
        // rank the same sums as one process.
        if (mass_solver && cg_tolerance == 0. &&
            (replicated_state || !row_exchange.is_distributed()))
          advance_velocity_with_mass_times_velocity(f, half_step_velocity, dt);
        else
          half_step_velocity.add(dt, acceleration);
        return;
      }
    // The next displacement too, in the pass (advance_range()'s operations,
    // the same bits): with the state shared into its second array, else into
    // a vector of its own that advance_displacement() swaps in (one
    // process) or takes the owned rows of (several ranks).
    const bool distributed = row_exchange.is_distributed();
    const auto start       = std::chrono::steady_clock::now();
    double    *ahead       = nullptr;
    if (distributed && row_exchange.shares_state())
      {
        AssertThrow(shared_state_live && advance_displacement_ahead,
                    ExcMessage("Load balancing = shared memory: the "
                               "step forms the next displacement "
                               "ahead, in the shared state"));
        ahead = shared_array(1 - present_displacement);
      }
    else if (advance_displacement_ahead)
      {
        if (displacement_ahead.size() != displacement.size())
          displacement_ahead.reinit(displacement.size());
        ahead = displacement_ahead.data();
      }
    if (distributed)
      {
        if (form_whole_step_state)
          fused_step<true, true>(f, half_step_velocity, dt, ahead);
        else
          fused_step<false, true>(f, half_step_velocity, dt, ahead);
      }
    else if (form_whole_step_state)
      fused_step<true, false>(f, half_step_velocity, dt, ahead);
    else
      fused_step<false, false>(f, half_step_velocity, dt, ahead);
    if (ahead != nullptr)
      {
        displacement_ahead_step     = dt;
        displacement_ahead_velocity = &half_step_velocity;
      }
    if (distributed)
      {
        if (row_exchange.shares_state())
          row_exchange.end_shared_pass();
        // Load balancing: the pass's time decides the next split.
        const auto end    = std::chrono::steady_clock::now();
        last_pass_seconds = std::chrono::duration<double>(end - start).count();
        last_pass_end =
          std::chrono::duration<double>(end.time_since_epoch()).count();
      }
  }

  template <int dim>
  void
  ElasticBody<dim>::set_pass_on_one_thread(const bool one_thread)
  {
    pass_on_one_thread = one_thread;
  }

  template <int dim>
  void
  ElasticBody<dim>::restart_steps()
  {
    velocity_of_mass_product    = nullptr;
    displacement_ahead_velocity = nullptr;
    drop_ghosts_sent_ahead();
    if (shared_state_live)
      copy_shared_state(nullptr, true);
  }

  template <int dim>
  void
  ElasticBody<dim>::receive_band_values()
  {
    const auto *values = row_exchange.complete_band_update(band_under_way);
    if (values == nullptr)
      return;
    std::size_t k = 0;
    for (Vector<double> *block : {band_velocity, &acceleration, &velocity})
      {
        row_exchange.for_each_claimed_range(
          1 - row_exchange.this_rank(),
          [&](const std::size_t first, const std::size_t end) {
            for (std::size_t i = first; i < end; ++i)
              (*block)[i] = (*values)[k++];
          });
        if (band_values_per_row == 1)
          break;
      }
    AssertDimension(k, values->size());
  }

  template <int dim>
  void
  ElasticBody<dim>::drop_ghosts_sent_ahead()
  {
    receive_band_values();
    // (A move sent with them is cancelled: the rows stay with the owners
    // that computed them.)
    if (ghosts_under_way.move)
      row_exchange.complete_move(nullptr, nullptr, ghosts_under_way);
    else
      row_exchange.complete_ghost_update(displacement_ahead, ghosts_under_way);
  }

  template <int dim>
  void
  ElasticBody<dim>::advance_velocity_with_mass_times_velocity(
    const Vector<double> &r,
    Vector<double>       &half_step_velocity,
    const double          dt)
  {
    if (velocity_of_mass_product != &half_step_velocity)
      {
        mass_times_half_step_velocity.reinit(n_dofs());
        mass_vmult(mass_times_half_step_velocity, half_step_velocity);
        velocity_of_mass_product = &half_step_velocity;
      }
    // M a = r on the free rows (the solve), r = 0 on the constrained ones,
    // where M v^{n+1/2} (of v constrained zero) is zero too. The kinetic
    // energy's constrained terms are then zero; the strain energy's are
    // taken out as in strain_energy_of_last_acceleration().
    const double *a        = acceleration.data();
    const double *rhs      = r.data();
    const double *u        = displacement.data();
    const double *ku       = stiffness_times_u.data();
    double       *vh       = half_step_velocity.data();
    double       *mv       = mass_times_half_step_velocity.data();
    StepEnergies  energies = sum_by_blocks(
      n_dofs(),
      block_energies,
      [&](const std::size_t i, StepEnergies &sums) {
        const double previous = vh[i];
        vh[i]                 = previous + dt * a[i];
        mv[i] += dt * rhs[i];
        sums.kinetic += previous * mv[i];
        sums.strain += u[i] * ku[i];
      },
      pass_on_one_thread);
    for (const auto &line : body_constraints.get_lines())
      energies.strain -= u[line.index] * ku[line.index];
    energies.kinetic *= 0.5;
    energies.strain *= 0.5;
    step_energies             = energies;
    step_energies_are_partial = false;
  }

  template <int dim>
  bool
  ElasticBody<dim>::step_zeroes_force() const
  {
    return fused_lumped_step && !replicated_state;
  }

  template <int dim>
  void
  ElasticBody<dim>::set_force_rows(std::vector<types::global_dof_index> rows)
  {
    AssertThrow(std::is_sorted(rows.begin(), rows.end()) &&
                  (rows.empty() || rows.back() < n_dofs()),
                ExcMessage("the force rows of body '" + body_name +
                           "' must be sorted unknowns of the body"));
    force_rows     = std::move(rows);
    force_rows_set = true;
  }

  template <int dim>
  void
  ElasticBody<dim>::check_force_rows(const Vector<double> &f) const
  {
    if (!force_rows_set)
      return;
    auto next = force_rows.begin();
    for (types::global_dof_index i = 0; i < f.size(); ++i)
      {
        while (next != force_rows.end() && *next < i)
          ++next;
        if (f[i] == 0. || (next != force_rows.end() && *next == i))
          continue;
        std::ostringstream force;
        force << f[i];
        AssertThrow(false,
                    ExcMessage("body '" + body_name + "': a force of " +
                               force.str() + " N/m on unknown " +
                               std::to_string(i) +
                               ", outside the contact surfaces' rows that "
                               "the step reads forces on (a contact model "
                               "wrote outside its surface_springs())"));
      }
  }

  template <int dim>
  template <bool form_whole_step_state, bool owned_rows_only>
  void
  ElasticBody<dim>::fused_step(Vector<double> &f,
                               Vector<double> &half_step_velocity,
                               const double    dt,
                               double         *u_ahead)
  {
    // Row by row, or two rows at a time (paired_stiffness): (K u)_i as
    // deal.II's vmult sums it (the same bits), then
    // a_i, v_i, v^{n+1/2}_i and the energies' terms while the row is at
    // hand. K u is not stored (strain_energy_of_last_acceleration() is then
    // not available: energies_of_last_step() replaces it). Blocks of a
    // fixed size keep the order of the energy sums independent of the
    // threads. The force is consumed: f is zero afterwards, ready for the
    // next step's contact forces without a pass of its own.
    // (No stiffness: this rank owns no row of the body.)
    const bool         has_rows = !stiffness.empty();
    const std::size_t *rowstart =
      has_rows ? CompressedRows::row_starts(stiffness.get_sparsity_pattern()) :
                 nullptr;
    const auto *columns =
      has_rows ?
        CompressedRows::column_numbers(stiffness.get_sparsity_pattern()) :
        nullptr;
    // The entries in the pattern's order: the diagonal of row 0 is the
    // first (square matrix, rowstart[0] = 0).
    const double *values = has_rows ? &stiffness.diag_element(0) : nullptr;
    // Load balancing = shared memory: the state where both ranks read and
    // write it.
    const bool    shared = owned_rows_only && row_exchange.shares_state();
    const double *u =
      shared ? shared_array(present_displacement) : displacement.data();
    double       *force = f.data();
    const double *w     = step_inverse_mass.data();
    const double *mass  = lumped_mass.data();
    double       *a     = shared ? shared_array(3) : acceleration.data();
    double       *v     = shared ? shared_array(4) : velocity.data();
    double       *vh    = shared ? shared_array(2) : half_step_velocity.data();
    // On several ranks the owned unknowns, as ranges of rows (ascending);
    // the energies' blocks count them in this order.
    const auto       &ranges = row_exchange.owned_ranges();
    const std::size_t n =
      owned_rows_only ? row_exchange.n_owned_unknowns() : displacement.size();
    // Where each range starts in the count of owned unknowns.
    const auto &range_offsets = row_exchange.owned_range_offsets();
    stiffness_times_u.reinit(0); // not computed: see above

    // One row's step, its product ku at hand; with_force false: a row
    // where no force acts (set_force_rows()), f_i = +0 neither read nor
    // written (the same operations on the same value: the same bits).
    const auto row_step = [&](const std::size_t i,
                              const double      ku,
                              StepEnergies     &sums,
                              auto              with_force) {
      double fi = 0.;
      if constexpr (decltype(with_force)::value)
        {
          fi       = force[i];
          force[i] = 0.; // consumed: zero for the next step
        }
      const double ai       = (w[i] == 0.) ? 0. : (fi - ku) * w[i];
      const double previous = vh[i];
      if constexpr (form_whole_step_state)
        {
          a[i] = ai;
          v[i] = previous + 0.5 * dt * ai;
        }
      vh[i] = previous + dt * ai;
      if (u_ahead != nullptr)
        u_ahead[i] = u[i] + dt * vh[i]; // advance_range()'s operations
      sums.kinetic += previous * mass[i] * vh[i];
      sums.strain += u[i] * ku;
    };
    // Rows 2p and 2p + 1 side by side where both are to be stepped
    // (paired_stiffness: the same bits as one at a time), else one row,
    // (K u)_i from the pairs if there are (the band's rows of a rank are
    // only there).
    const bool pairs       = !paired_stiffness.empty();
    const auto row_product = [&](const std::size_t i) {
      double ku = 0.;
      if (pairs)
        {
          double first, second;
          paired_stiffness.products(i / 2, u, first, second);
          ku = (i % 2 == 0) ? first : second;
        }
      else
        for (std::size_t j = rowstart[i]; j < rowstart[i + 1]; ++j)
          ku += values[j] * u[columns[j]];
      return ku;
    };
    // The rows [first, end), in pairs where both rows are among them.
    const auto step_rows_of = [&](const std::size_t first,
                                  const std::size_t end,
                                  StepEnergies     &sums,
                                  auto              with_force) {
      for (std::size_t i = first; i < end;)
        {
          if (pairs && i % 2 == 0 && i + 1 < end)
            {
#ifdef __SSE2__
              // row_step() of both rows lane by lane (the same
              // operations, the same bits), the energies' terms added
              // row 2p's first.
              const __m128d ku   = paired_stiffness.packed_products(i / 2, u);
              const __m128d zero = _mm_setzero_pd();
              const __m128d inverse = _mm_loadu_pd(w + i);
              __m128d       fi      = zero;
              if constexpr (decltype(with_force)::value)
                {
                  fi = _mm_loadu_pd(force + i);
                  _mm_storeu_pd(force + i, zero);
                }
              const __m128d ai =
                _mm_andnot_pd(_mm_cmpeq_pd(inverse, zero),
                              _mm_mul_pd(_mm_sub_pd(fi, ku), inverse));
              const __m128d previous = _mm_loadu_pd(vh + i);
              if constexpr (form_whole_step_state)
                {
                  _mm_storeu_pd(a + i, ai);
                  _mm_storeu_pd(v + i,
                                _mm_add_pd(previous,
                                           _mm_mul_pd(_mm_set1_pd(0.5 * dt),
                                                      ai)));
                }
              const __m128d next =
                _mm_add_pd(previous, _mm_mul_pd(_mm_set1_pd(dt), ai));
              _mm_storeu_pd(vh + i, next);
              const __m128d own_u = _mm_loadu_pd(u + i);
              if (u_ahead != nullptr)
                _mm_storeu_pd(u_ahead + i,
                              _mm_add_pd(own_u,
                                         _mm_mul_pd(_mm_set1_pd(dt), next)));
              const __m128d kinetic =
                _mm_mul_pd(_mm_mul_pd(previous, _mm_loadu_pd(mass + i)), next);
              const __m128d strain = _mm_mul_pd(own_u, ku);
              sums.kinetic += _mm_cvtsd_f64(kinetic);
              sums.strain += _mm_cvtsd_f64(strain);
              sums.kinetic += _mm_cvtsd_f64(_mm_unpackhi_pd(kinetic, kinetic));
              sums.strain += _mm_cvtsd_f64(_mm_unpackhi_pd(strain, strain));
#else
              double ku_first, ku_second;
              paired_stiffness.products(i / 2, u, ku_first, ku_second);
              row_step(i, ku_first, sums, with_force);
              row_step(i + 1, ku_second, sums, with_force);
#endif
              i += 2;
              continue;
            }
          row_step(i, row_product(i), sums, with_force);
          ++i;
        }
    };
    // The same, f read only on the pairs of the force rows where these are
    // set. The stretches between them end at even rows: the same pairs as
    // one stretch, so the same bits.
    const auto step_rows = [&](const std::size_t first,
                               const std::size_t end,
                               StepEnergies     &sums) {
      if (!force_rows_set)
        {
          step_rows_of(first, end, sums, std::true_type());
          return;
        }
      auto next = std::lower_bound(force_rows.begin(), force_rows.end(), first);
      for (std::size_t i = first; i < end;)
        {
          if (next == force_rows.end() || *next >= end)
            {
              step_rows_of(i, end, sums, std::false_type());
              break;
            }
          const std::size_t pair_start =
            std::max<std::size_t>(i, *next - *next % 2);
          if (pair_start > i)
            step_rows_of(i, pair_start, sums, std::false_type());
          const std::size_t pair_end =
            std::min<std::size_t>(end, *next - *next % 2 + 2);
          step_rows_of(pair_start, pair_end, sums, std::true_type());
          while (next != force_rows.end() && *next < pair_end)
            ++next;
          i = pair_end;
        }
    };
    // Several ranks, the next displacement ahead: first the rows that other
    // ranks read, sent at once, so that they need not wait for the rest of
    // the pass (row_step()'s operations: the same bits, checked below).
    // A move of the load balancing that is due goes with them: the rows the
    // other rank reads at the new split or takes over, and the velocity of
    // the latter (the ranks switch where it is received, the next
    // advance_displacement()).
    // (Nothing is sent with the state shared.)
    const bool sends  = owned_rows_only && u_ahead != nullptr && !shared;
    const bool moving = sends && row_exchange.move_is_due();
    if (moving)
      row_exchange.prepare_move();
    const std::vector<types::global_dof_index> none;
    const auto                                &sent = !sends ? none :
                                                      moving ? row_exchange.move_sent_unknowns() :
                                                               row_exchange.sent_unknowns();
    const auto &moved = moving ? row_exchange.move_sent_rows() : none;
    if constexpr (owned_rows_only)
      if (sends)
        {
          sent_values.resize(sent.size() + moved.size());
          const auto acceleration_of = [&](const std::size_t i) {
            const double ku = row_product(i);
            return (w[i] == 0.) ? 0. : (force[i] - ku) * w[i];
          };
          for (std::size_t j = 0; j < sent.size(); ++j)
            {
              const std::size_t i = sent[j];
              sent_values[j] = u[i] + dt * (vh[i] + dt * acceleration_of(i));
            }
          for (std::size_t j = 0; j < moved.size(); ++j)
            {
              const std::size_t i          = moved[j];
              sent_values[sent.size() + j] = vh[i] + dt * acceleration_of(i);
            }
          if (moving)
            row_exchange.start_move(sent_values,
                                    ghost_update_tag + message_tag_offset,
                                    ghosts_under_way);
          else
            row_exchange.start_ghost_update(sent_values,
                                            ghost_update_tag +
                                              message_tag_offset,
                                            ghosts_under_way);
        }
    StepEnergies energies = sum_over_blocks(
      n,
      block_energies,
      [&](const std::size_t begin, const std::size_t end, StepEnergies &sums) {
        if constexpr (!owned_rows_only)
          step_rows(begin, end, sums);
        else
          {
            // The owned unknowns begin to end of the count: the ranges'
            // pieces in turn (a pair spans no gap between ranges).
            std::size_t r = std::upper_bound(range_offsets.begin(),
                                             range_offsets.end(),
                                             begin) -
                            range_offsets.begin() - 1;
            for (std::size_t k = begin; k < end; ++r)
              {
                const std::size_t piece_end =
                  std::min<std::size_t>(end, range_offsets[r + 1]);
                const std::size_t first =
                  ranges[r].first + (k - range_offsets[r]);
                step_rows(first, first + (piece_end - k), sums);
                k = piece_end;
              }
          }
      },
      pass_on_one_thread);
    // Claimed balancing: the band's chunks as this rank claims them, then
    // their values sent to the other rank (which may claim any of them in
    // the next pass).
    const bool claims = owned_rows_only && row_exchange.claims_band();
    if (claims)
      {
        StepEnergies band_sums;
        int          chunk;
        while (row_exchange.claim_chunk(chunk))
          for (const auto &[first, end] : row_exchange.chunk_ranges(chunk))
            step_rows(first, end, band_sums);
        energies += band_sums;
      }
    if (claims && !shared)
      {
        band_values_per_row = form_whole_step_state ? 3 : 1;
        band_values.clear();
        for (const double *block : {vh, a, v})
          {
            row_exchange.for_each_claimed_range(
              row_exchange.this_rank(),
              [&](const std::size_t first, const std::size_t end) {
                band_values.insert(band_values.end(),
                                   block + first,
                                   block + end);
              });
            if (band_values_per_row == 1)
              break;
          }
        row_exchange.start_band_update(band_values,
                                       band_values_per_row,
                                       band_update_tag + message_tag_offset,
                                       band_under_way);
        band_velocity = &half_step_velocity;
      }
    // Constrained unknowns do not count (as in the separate functions), and
    // here their terms are zero: the fused pass has constraints u_i = 0
    // only (only_zero_constraints()), their velocity is zero from the
    // start (distribute() at set-up) and stays so (w_i = 0: a_i = 0), so
    // vh_i m_i vh_i = +0 and u_i (K u)_i = +-0, and subtracting them
    // changed no bit of the sums. They are not recomputed: each row's
    // product read its stiffness row and its neighbours' displacement from
    // memory again after the pass, 0.4 ms per body and step at FEA level 7,
    // which on several ranks the other rank waited for (doc/parallel.md,
    // session 42). (Checked in debug builds only.)
    for ([[maybe_unused]] const auto &line : body_constraints.get_lines())
      Assert(u[line.index] == 0. && vh[line.index] == 0.,
             ExcMessage("the fused pass expects u_i = v_i = 0 on the "
                        "constrained unknowns"));
    // The contact forces on the ghosts are their owners' to consume. With
    // the state shared only the contact surfaces' rows hold forces
    // (check_force_rows()), and both ranks form those of the rows either
    // may step: those the other rank stepped are consumed here too, read
    // first, since most are zero and long out of the caches (a store would
    // fetch and dirty each line; up to 16faf07 this stored zero into 7690
    // entries per rank and step, ghosts included, at FEA level 7:
    // doc/parallel.md, session 61).
    if constexpr (owned_rows_only)
      {
        if (!shared)
          for (const auto i : row_exchange.ghost_unknowns())
            force[i] = 0.;
        else
          for (const auto i : surface_rows_of_other_pass)
            if (force[i] != 0.)
              force[i] = 0.;
        if (u_ahead != nullptr)
          {
            for (std::size_t j = 0; j < sent.size(); ++j)
              AssertThrow(sent_values[j] == u_ahead[sent[j]],
                          ExcMessage("the displacement sent ahead differs "
                                     "from the pass's (same bits expected)"));
            for (std::size_t j = 0; j < moved.size(); ++j)
              AssertThrow(sent_values[sent.size() + j] == vh[moved[j]],
                          ExcMessage("the velocity sent ahead differs "
                                     "from the pass's (same bits expected)"));
          }
      }
    energies.kinetic *= 0.5;
    energies.strain *= 0.5;
    step_energies             = energies;
    step_energies_are_partial = owned_rows_only;
  }

  template <int dim>
  void
  ElasticBody<dim>::lumped_step_pass(const Vector<double> &f,
                                     Vector<double>       &a) const
  {
    // The same operations per entry as the separate passes (condense,
    // subtract, scale, distribute): the same bits.
    parallel::apply_to_subranges(
      types::global_dof_index(0),
      a.size(),
      [&](const types::global_dof_index begin,
          const types::global_dof_index end) {
        for (types::global_dof_index i = begin; i < end; ++i)
          {
            const double w = step_inverse_mass(i);
            a(i)           = (w == 0.) ? 0. : (f(i) - stiffness_times_u(i)) * w;
          }
      },
      4096);
  }

  template <int dim>
  bool
  ElasticBody<dim>::state_is_replicated() const
  {
    return replicated_state;
  }

  template <int dim>
  const UnknownExchange &
  ElasticBody<dim>::exchange() const
  {
    return row_exchange;
  }

  template <int dim>
  const CellFilter &
  ElasticBody<dim>::assembly_cells() const
  {
    return row_cells;
  }

  template <int dim>
  void
  ElasticBody<dim>::advance_displacement(Vector<double> &half_step_velocity,
                                         const double    dt)
  {
    if (!row_exchange.is_distributed() || replicated_state)
      {
        if (displacement_formed_ahead(half_step_velocity, dt))
          displacement.swap(displacement_ahead);
        else
          displacement.add(dt, half_step_velocity);
        displacement_ahead_velocity = nullptr;
        return;
      }
    ghosts_received         = false;
    const bool formed_ahead = displacement_formed_ahead(half_step_velocity, dt);
    if (shared_state_live)
      {
        if (formed_ahead)
          {
            // The next displacement is the present one, once the other
            // rank's pass is over; the contact reads its surfaces' rows
            // there (contact_displacement(): neither rank writes that array
            // before both have passed the next step). The contact damping's
            // v^{n+1/2}: this rank's own rows (the other rank's next pass
            // may be changing the other's: the damping's ghost update
            // brings them).
            present_displacement        = 1 - present_displacement;
            displacement_ahead_velocity = nullptr;
            row_exchange.wait_for_other_pass();
            const double *vh = shared_array(2);
            if (contact_reads_velocity)
              for (const auto i : own_surface_rows)
                half_step_velocity[i] = vh[i];
            ghosts_received = true;
            return;
          }
        copy_shared_state(&half_step_velocity, true);
      }
    if (formed_ahead)
      {
        // Formed by the last pass: its owned entries are those of the
        // update below; the ghosts the owners sent from their passes, and
        // with them the rows of a move and their velocity: this rank
        // switches to the new split here. A move due now goes with the
        // next pass.
        displacement.swap(displacement_ahead);
        displacement_ahead_velocity = nullptr;
        if (ghosts_under_way.move)
          row_exchange.complete_move(&displacement,
                                     &half_step_velocity,
                                     ghosts_under_way);
        else
          row_exchange.complete_ghost_update(displacement, ghosts_under_way);
        // The band's rows the other rank computed: u + dt v^{n+1/2} as its
        // pass formed them (the same operations, the same bits).
        if (row_exchange.claims_band())
          {
            receive_band_values();
            const double *u      = displacement_ahead.data();
            const double *v      = half_step_velocity.data();
            double       *u_next = displacement.data();
            row_exchange.for_each_claimed_range(
              1 - row_exchange.this_rank(),
              [&](const std::size_t first, const std::size_t end) {
                for (std::size_t i = first; i < end; ++i)
                  u_next[i] = u[i] + dt * v[i];
              });
          }
        ghosts_received = true;
        return;
      }
    drop_ghosts_sent_ahead(); // not needed
    for (const auto &[first, end] : row_exchange.owned_ranges())
      advance_range(displacement.data(),
                    half_step_velocity.data(),
                    dt,
                    first,
                    end);
    // Claimed balancing: both ranks advance the whole band.
    if (row_exchange.claims_band())
      for (int c = 0; c < row_exchange.n_band_chunks(); ++c)
        for (const auto &[first, end] : row_exchange.chunk_ranges(c))
          advance_range(displacement.data(),
                        half_step_velocity.data(),
                        dt,
                        first,
                        end);
    // A move due: here, the ranks meet (the ghosts then follow the new
    // split in the caller's update).
    row_exchange.apply_split({&displacement, &half_step_velocity});
    if (row_exchange.shares_state())
      fill_shared_state(half_step_velocity);
  }

  template <int dim>
  bool
  ElasticBody<dim>::displacement_formed_ahead(
    const Vector<double> &half_step_velocity,
    const double          dt) const
  {
    return displacement_ahead_velocity == &half_step_velocity &&
           displacement_ahead_step == dt;
  }

  template <int dim>
  void
  ElasticBody<dim>::advance_displacement_of_rows(
    const Vector<double>                       &half_step_velocity,
    const double                                dt,
    const std::vector<types::global_dof_index> &rows,
    const bool                                  all_but_rows)
  {
    AssertThrow(!row_exchange.is_distributed(),
                ExcMessage("advance_displacement_of_rows() is for one "
                           "process"));
    double       *u = displacement.data();
    const double *v = half_step_velocity.data();
    if (!all_but_rows)
      {
        for (const std::size_t row : rows)
          advance_range(u, v, dt, row, row + 1);
        return;
      }
    std::size_t first = 0;
    for (const std::size_t row : rows)
      {
        Assert(row >= first, ExcMessage("rows must ascend"));
        advance_range(u, v, dt, first, row);
        first = row + 1;
      }
    advance_range(u, v, dt, first, displacement.size());
  }

  template <int dim>
  void
  ElasticBody<dim>::sum_step_energies(
    const std::vector<ElasticBody<dim> *> &bodies)
  {
    StepEnergiesSum under_way;
    start_sum_of_step_energies(bodies, under_way);
    complete_sum_of_step_energies(under_way, true);
  }

  template <int dim>
  void
  ElasticBody<dim>::start_sum_of_step_energies(
    const std::vector<ElasticBody<dim> *> &bodies,
    StepEnergiesSum                       &under_way)
  {
    under_way.bodies.clear();
    std::vector<double> sums;
    for (auto *body : bodies)
      if (body->step_energies_are_partial)
        {
          AssertThrow(!body->step_energies_under_way,
                      ExcMessage("the body's energies are summed already"));
          under_way.bodies.push_back(body);
          body->step_energies_under_way = true;
          sums.push_back(body->step_energies->kinetic);
          sums.push_back(body->step_energies->strain);
          // Each rank's pass time and end in its own slots: the sum gathers
          // them.
          if (body->row_exchange.balances_load())
            for (const double value :
                 {body->last_pass_seconds, body->last_pass_end})
              for (unsigned int p = 0; p < body->row_exchange.n_ranks(); ++p)
                sums.push_back(p == body->row_exchange.this_rank() ? value :
                                                                     0.);
        }
    // Every rank has the same bodies with partial energies (the same
    // scene, the same steps).
    if (!under_way.bodies.empty())
      under_way.bodies[0]->row_exchange.start_sum(sums, under_way.sum);
  }

  template <int dim>
  std::vector<typename ElasticBody<dim>::StepEnergies>
  ElasticBody<dim>::complete_sum_of_step_energies(
    StepEnergiesSum &under_way,
    const bool       bodies_at_that_step)
  {
    std::vector<StepEnergies> summed;
    if (under_way.bodies.empty())
      return summed;
    std::vector<double> sums;
    under_way.bodies[0]->row_exchange.complete_sum(under_way.sum, sums);
    std::size_t k = 0;
    // Bodies whole on ranks: one split for all, from each rank's time over
    // all its rows.
    std::vector<UnknownExchange *> whole_bodies;
    std::vector<double>            whole_body_seconds, whole_body_ends;
    for (auto *body : under_way.bodies)
      {
        summed.push_back({sums[k], sums[k + 1]});
        body->step_energies_under_way = false;
        if (bodies_at_that_step)
          {
            body->step_energies             = summed.back();
            body->step_energies_are_partial = false;
          }
        k += 2;
        if (body->row_exchange.balances_load())
          {
            const unsigned int        n = body->row_exchange.n_ranks();
            const std::vector<double> seconds(sums.begin() + k,
                                              sums.begin() + k + n),
              ends(sums.begin() + k + n, sums.begin() + k + 2 * n);
            k += 2 * n;
            if (!body->row_exchange.balances_whole_body())
              {
                body->row_exchange.observe_pass_times(seconds, ends);
                continue;
              }
            whole_bodies.push_back(&body->row_exchange);
            whole_body_seconds.resize(n, 0.);
            whole_body_ends.resize(n, 0.);
            for (unsigned int p = 0; p < n; ++p)
              {
                whole_body_seconds[p] += seconds[p];
                whole_body_ends[p] = std::max(whole_body_ends[p], ends[p]);
              }
          }
      }
    under_way.bodies.clear();
    UnknownExchange::observe_pass_times(whole_bodies,
                                        whole_body_seconds,
                                        whole_body_ends);
    return summed;
  }

  template <int dim>
  bool
  ElasticBody<dim>::displacement_ghosts_received() const
  {
    return ghosts_received;
  }

  template <int dim>
  ArrayView<const double>
  ElasticBody<dim>::contact_displacement() const
  {
    if (shared_state_live)
      return {shared_array(present_displacement), n_dofs()};
    return {displacement.data(), displacement.size()};
  }

  template <int dim>
  void
  ElasticBody<dim>::set_contact_reads_velocity(const bool reads)
  {
    contact_reads_velocity = reads;
  }

  template <int dim>
  bool
  ElasticBody<dim>::steps_contact_surface() const
  {
    return surface_rows_stepped;
  }

  template <int dim>
  void
  ElasticBody<dim>::open_claims()
  {
    row_exchange.open_claims(shared_state_arrays * shared_array_stride());
    if (row_exchange.shares_state())
      shared_state = row_exchange.shared_values();
  }

  template <int dim>
  double *
  ElasticBody<dim>::shared_array(const unsigned int k) const
  {
    return shared_state + std::size_t(k) * shared_array_stride();
  }

  template <int dim>
  std::size_t
  ElasticBody<dim>::shared_array_stride() const
  {
    // Each array at a cache line's boundary (the window's start is one).
    return (std::size_t(n_dofs()) + 7) / 8 * 8;
  }

  template <int dim>
  void
  ElasticBody<dim>::fill_shared_state(const Vector<double> &half_step_velocity)
  {
    double    *u    = shared_array(present_displacement);
    double    *vh   = shared_array(2);
    const auto fill = [&](const std::size_t first, const std::size_t end) {
      std::copy(displacement.data() + first,
                displacement.data() + end,
                u + first);
      std::copy(half_step_velocity.data() + first,
                half_step_velocity.data() + end,
                vh + first);
    };
    for (const auto &[first, end] : row_exchange.owned_ranges())
      fill(first, end);
    if (row_exchange.this_rank() == 0)
      for (int c = 0; c < row_exchange.n_band_chunks(); ++c)
        for (const auto &[first, end] : row_exchange.chunk_ranges(c))
          fill(first, end);
    const int ierr = MPI_Barrier(row_exchange.communicator());
    AssertThrowMPI(ierr);
    shared_state_live = true;
  }

  template <int dim>
  void
  ElasticBody<dim>::copy_shared_state(Vector<double> *half_step_velocity,
                                      const bool      release)
  {
    row_exchange.wait_for_other_pass();
    const std::size_t n = n_dofs();
    const double     *u = shared_array(present_displacement);
    std::copy(u, u + n, displacement.data());
    std::copy(shared_array(3), shared_array(3) + n, acceleration.data());
    std::copy(shared_array(4), shared_array(4) + n, velocity.data());
    if (half_step_velocity != nullptr)
      std::copy(shared_array(2),
                shared_array(2) + n,
                half_step_velocity->data());
    // (The other rank's next pass writes the arrays.)
    const int ierr = MPI_Barrier(row_exchange.communicator());
    AssertThrowMPI(ierr);
    shared_state_live = !release;
  }

  template <int dim>
  void
  ElasticBody<dim>::gather_state()
  {
    if (replicated_state)
      return;
    if (shared_state_live)
      {
        copy_shared_state(nullptr, false);
        return;
      }
    receive_band_values(); // the band's whole-step state
    row_exchange.gather(displacement);
    row_exchange.gather(velocity);
    row_exchange.gather(acceleration);
  }

  template <int dim>
  const std::optional<typename ElasticBody<dim>::StepEnergies> &
  ElasticBody<dim>::energies_of_last_step() const
  {
    // Summed by this body alone if nobody summed them with the others'
    // (only mutable members change).
    AssertThrow(!step_energies_under_way,
                ExcMessage("the step's energies are being summed"));
    if (step_energies_are_partial)
      sum_step_energies({const_cast<ElasticBody<dim> *>(this)});
    return step_energies;
  }

  template <int dim>
  void
  ElasticBody<dim>::mass_vmult(Vector<double> &y, const Vector<double> &x) const
  {
    if (scheme == MassScheme::consistent)
      {
        scratch = x;
        body_constraints.set_zero(scratch);
        consistent_mass.vmult(y, scratch);
      }
    else
      {
        y = x;
        body_constraints.set_zero(y);
        y.scale(lumped_mass);
      }
  }

  template <int dim>
  double
  ElasticBody<dim>::kinetic_energy(const Vector<double> &v) const
  {
    return kinetic_energy(v, v);
  }

  template <int dim>
  double
  ElasticBody<dim>::kinetic_energy(const Vector<double> &x,
                                   const Vector<double> &y) const
  {
    // mass_vmult zeroes the constrained entries of y; the rows of M for
    // them are then zero, so those of x do not count either.
    mass_times_scratch.reinit(y.size(), true);
    mass_vmult(mass_times_scratch, y);
    return 0.5 * (x * mass_times_scratch);
  }

  template <int dim>
  double
  ElasticBody<dim>::kinetic_energy_at_full_step(const Vector<double> &v,
                                                const double          dt) const
  {
    if (scheme == MassScheme::consistent)
      {
        scratch_previous_velocity = v;
        scratch_previous_velocity.add(-dt, acceleration);
        if (!replicated_state)
          return kinetic_energy(scratch_previous_velocity, v);
        // Several ranks: each sums the rows it owns of x . M v, and the
        // sums are added over the ranks (collective).
        scratch = v;
        body_constraints.set_zero(scratch);
        const SparsityPattern &pattern = consistent_mass.get_sparsity_pattern();
        const std::size_t     *rowstart = CompressedRows::row_starts(pattern);
        const auto *columns = CompressedRows::column_numbers(pattern);
        // The entries in the pattern's order (read only; the const
        // diag_element() returns a copy).
        const double *values =
          &const_cast<SparseMatrix<double> &>(consistent_mass).diag_element(0);
        const double *x      = scratch_previous_velocity.data();
        const double *y      = scratch.data();
        double        energy = 0.;
        for (const auto i : row_exchange.owned_unknowns())
          {
            double my = 0.;
            for (std::size_t j = rowstart[i]; j < rowstart[i + 1]; ++j)
              my += values[j] * y[columns[j]];
            energy += x[i] * my;
          }
        std::vector<double> sum = {energy};
        row_exchange.sum(sum);
        return 0.5 * sum[0];
      }
    AssertDimension(v.size(), lumped_mass.size());
    AssertDimension(acceleration.size(), lumped_mass.size());
    double energy = 0.;
    for (unsigned int i = 0; i < lumped_mass.size(); ++i)
      energy += (v[i] - dt * acceleration[i]) * lumped_mass[i] * v[i];
    for (const auto &line : body_constraints.get_lines())
      {
        const unsigned int i = line.index;
        energy -= (v[i] - dt * acceleration[i]) * lumped_mass[i] * v[i];
      }
    return 0.5 * energy;
  }

  template <int dim>
  double
  ElasticBody<dim>::strain_energy(const Vector<double> &u) const
  {
    AssertThrow(!row_exchange.is_distributed(),
                ExcMessage("strain_energy() of " + body_name +
                           " on several MPI ranks: use the step energies"));
    scratch = u;
    body_constraints.set_zero(scratch);
    return 0.5 * stiffness.matrix_norm_square(scratch);
  }

  template <int dim>
  double
  ElasticBody<dim>::strain_energy_of_last_acceleration(
    const Vector<double> &u) const
  {
    AssertThrow(stiffness_times_u.size() == u.size(),
                ExcMessage("strain_energy_of_last_acceleration() needs a "
                           "call of compute_acceleration() first"));
    // K is condensed: constrained rows hold only their diagonal and the
    // other rows have zeros in constrained columns, so dropping the
    // constrained entries gives u_0 . K u_0 with u_0 = u constrained zero.
    // A plain loop: deal.II's parallel dot costs more than the sum at this
    // size, and the history calls this every step.
    double energy = 0.;
    for (unsigned int i = 0; i < u.size(); ++i)
      energy += u[i] * stiffness_times_u[i];
    for (const auto &line : body_constraints.get_lines())
      energy -= u[line.index] * stiffness_times_u[line.index];
    return 0.5 * energy;
  }

  template <int dim>
  Tensor<1, dim>
  ElasticBody<dim>::momentum(const Vector<double> &v) const
  {
    // With a partition of unity, the momentum of component c is the sum of
    // (M v)_i over the unknowns of that component; constrained unknowns
    // carry no mass of their own after condensation.
    Vector<double> mv(v.size());
    mass_vmult(mv, v);
    Tensor<1, dim> p;
    for (types::global_dof_index i = 0; i < v.size(); ++i)
      if (!body_constraints.is_constrained(i))
        p[discretization_ptr->dof_component(i)] += mv(i);
    return p;
  }

  template <int dim>
  double
  ElasticBody<dim>::total_mass() const
  {
    // The mass seen by a uniform motion of each component; a roller removes
    // the mass of its constrained unknowns from that component only, so the
    // largest over the components is the mass of the body.
    double mass = 0.;
    for (unsigned int c = 0; c < dim; ++c)
      {
        Vector<double> ones(n_dofs());
        for (types::global_dof_index i = 0; i < ones.size(); ++i)
          ones(i) = (discretization_ptr->dof_component(i) == c) ? 1. : 0.;
        body_constraints.distribute(ones);
        Tensor<1, dim> unit;
        unit[c] = 1.;
        mass    = std::max(mass, momentum(ones) * unit);
      }
    return mass;
  }

  template <int dim>
  double
  ElasticBody<dim>::estimate_critical_time_step(
    const unsigned int n_iterations,
    const std::function<void(Vector<double> &, const Vector<double> &)>
      &add_additional) const
  {
    // Several ranks: each holds its rows of K, the rest of K x comes from
    // their owners; every rank then iterates the same whole vectors.
    const auto stiffness_vmult = [&](Vector<double>       &y,
                                     const Vector<double> &x) {
      multiply_by_stiffness(y, x);
      row_exchange.gather(y);
      if (add_additional)
        add_additional(y, x);
    };
    // Power iteration on M^{-1} K in the M inner product: x_{k+1} =
    // M^{-1} K x_k / |.|_M, and the Rayleigh quotient x^T K x of the last
    // (M-normalised) x. Each K x serves both: the quotient of x_k and the
    // next iterate. Two vectors (y holds M x before it holds K x).
    Vector<double>                         x(n_dofs()), y(n_dofs());
    std::mt19937                           generator(42);
    std::uniform_real_distribution<double> uniform(-1., 1.);
    for (auto &value : x)
      value = uniform(generator);
    body_constraints.set_zero(x);
    const auto normalise = [&]() {
      mass_vmult(y, x);
      x /= std::sqrt(y * x);
    };
    normalise();
    double lambda = 0.;
    for (unsigned int it = 0; it <= n_iterations; ++it)
      {
        stiffness_vmult(y, x);
        lambda = y * x;
        if (it == n_iterations)
          break;
        body_constraints.set_zero(y);
        solve_mass(x, y);
        body_constraints.set_zero(x);
        normalise();
      }
    AssertThrow(lambda > 0. && std::isfinite(lambda),
                ExcMessage("critical time step estimate failed for body " +
                           body_name));
    return 2. / std::sqrt(lambda);
  }

  template <int dim>
  const Vector<double> &
  ElasticBody<dim>::lumped_masses() const
  {
    return lumped_mass;
  }

  template <int dim>
  double
  ElasticBody<dim>::set_penalty_masses(
    const std::vector<std::pair<types::global_dof_index, double>> &masses,
    Vector<double>                                                &v)
  {
    AssertThrow(scheme != MassScheme::consistent,
                ExcMessage("penalty masses (bipenalty) need a lumped mass; " +
                           body_name + " has the consistent mass"));
    AssertThrow(!row_exchange.is_distributed() || replicated_state,
                ExcMessage("penalty masses (bipenalty) of " + body_name +
                           " on several MPI ranks need the whole state on "
                           "every rank (RankDistribution::whole_state)"));
    if (penalty_scratch.size() != n_dofs())
      {
        penalty_scratch.reinit(n_dofs());
        previous_penalty_scratch.reinit(n_dofs());
      }
    // The unknowns whose penalty mass changes: those of the last call and
    // those of this one.
    std::vector<types::global_dof_index> touched;
    for (const auto &[i, m] : penalty_masses)
      {
        previous_penalty_scratch(i) = m;
        touched.push_back(i);
      }
    const auto add = [&](const types::global_dof_index i, const double m) {
      if (m == 0.)
        return;
      if (penalty_scratch(i) == 0. && previous_penalty_scratch(i) == 0.)
        touched.push_back(i);
      penalty_scratch(i) += m;
    };
    for (const auto &[i, m] : masses)
      if (!body_constraints.is_constrained(i))
        add(i, m);
      else
        for (const auto &[j, weight] :
             *body_constraints.get_constraint_entries(i))
          add(j, std::abs(weight) * m);
    penalty_masses.clear();
    double change = 0.;
    for (const types::global_dof_index i : touched)
      {
        const double old_mass = lumped_mass(i) + previous_penalty_scratch(i);
        const double new_mass = lumped_mass(i) + penalty_scratch(i);
        if (penalty_scratch(i) > 0.)
          penalty_masses.emplace_back(i, penalty_scratch(i));
        const double v_old = v(i);
        // Momentum form: (m + m_p) v is continuous across the change.
        if (penalty_momentum_switching)
          v(i) = old_mass / new_mass * v_old;
        change += new_mass * v(i) * v(i) - old_mass * v_old * v_old;
        // (No penalty mass on a constrained unknown.)
        (fused_lumped_step ? step_inverse_mass(i) : inverse_lumped_mass(i)) =
          new_mass > 0. ? 1. / new_mass : 0.;
        penalty_scratch(i)          = 0.;
        previous_penalty_scratch(i) = 0.;
      }
    return 0.5 * change;
  }

  template <int dim>
  void
  ElasticBody<dim>::set_penalty_switching(const bool conserve_momentum)
  {
    penalty_momentum_switching = conserve_momentum;
  }

  template <int dim>
  double
  ElasticBody<dim>::penalty_kinetic_energy(const Vector<double> &x,
                                           const Vector<double> &y) const
  {
    double energy = 0.;
    for (const auto &[i, m] : penalty_masses)
      energy += m * x(i) * y(i);
    return 0.5 * energy;
  }

  template <int dim>
  void
  ElasticBody<dim>::redistribute_mass(
    const std::vector<BoundarySegment<dim>> &surface)
  {
    AssertThrow(scheme != MassScheme::consistent,
                ExcMessage("mass redistribution of " + body_name +
                           " needs a lumped mass (row-sum or HRZ); the "
                           "consistent mass is not supported"));
    for (const auto &line : body_constraints.get_lines())
      AssertThrow(line.entries.empty() && line.inhomogeneity == 0.,
                  ExcMessage("mass redistribution of " + body_name +
                             " supports constraints u_i = 0 only (no "
                             "hanging nodes: no local refinement)"));
    AssertThrow(massless.empty(),
                ExcMessage("the mass of " + body_name +
                           " is redistributed already"));
    const MassRedistribution redistribution =
      redistribute_lumped_mass(*discretization_ptr,
                               lumped_mass,
                               body_constraints,
                               surface);
    // Several ranks: every rank computes the whole state and has the
    // stiffness rows of the massless unknowns (RankDistribution::
    // whole_state and shared_rows), which the boundary solve reads.
    if (row_exchange.is_distributed())
      for (const auto i : redistribution.massless)
        AssertThrow(replicated_state && stiffness_rows.is_element(i),
                    ExcMessage("mass redistribution of " + body_name +
                               " on several MPI ranks needs the whole state "
                               "and the surfaces' stiffness rows on every "
                               "rank (RankDistribution)"));
    mass_before_redistribution = lumped_mass;
    lumped_mass                = redistribution.masses;
    massless                   = redistribution.massless;
    set_inverse_masses();
  }

  template <int dim>
  const std::vector<types::global_dof_index> &
  ElasticBody<dim>::massless_dofs() const
  {
    return massless;
  }

  template <int dim>
  const Vector<double> &
  ElasticBody<dim>::lumped_masses_before_redistribution() const
  {
    return mass_before_redistribution;
  }

  template class ElasticBody<2>;
} // namespace isoimpact
