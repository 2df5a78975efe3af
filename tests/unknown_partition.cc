// The distribution of the unknowns over MPI ranks (layer 3,
// UnknownPartition), for FEA Q9 and IGA p2 half disks, the first step of
// issue 13. Run as one process and, by ctest, as 2 ranks (mpirun). Checked:
// 1. At 5 refinements (33 154 FEA, 8 912 IGA unknowns), for 1, 2 and 3
//    parts: every unknown has exactly one owner (the owned sets are
//    disjoint and cover all n unknowns); METIS splits the cells within 3 %
//    (its default imbalance; measured at most 0.1 %), and the unknowns
//    follow within 10 % of n / parts (measured at most 1.4 % FEA, 7.2 %
//    IGA: the interface's unknowns go to the part of their first cell);
//    every column of an owned row of the stiffness pattern is relevant
//    (0 missing); a part's ghosts (relevant minus owned) are its interface,
//    at most 25 % of n / parts (measured at most 8.7 % FEA, 17.1 % IGA,
//    whose supports are wider; a scattered split would make most unknowns
//    ghosts); one part owns everything and has no ghost.
// 2. At 3 refinements, with the communicator's ranks as parts (measured
//    1060 and 1086 of 2146 FEA unknowns, 392 and 312 of 704 IGA unknowns
//    on 2 ranks; K u to 4e-16): a Trilinos stiffness matrix
//    with the owned rows, assembled from each rank's assembly cells without
//    communication, has the serial matrix's entries bit for bit (the same
//    element matrices added in the same order), and its product with a
//    distributed vector equals the serial K u on the owned rows to 1e-14
//    relative to max |K u| (the ghost values come through Trilinos' import;
//    the sums within a row may run in another order).
// 3. The part-major numbering gives each rank one contiguous range of
//    unknowns, in the ranks' order, and a LinearAlgebra::distributed::Vector
//    over it (owned range, relevant set renumbered) receives the value of
//    every relevant unknown through update_ghost_values() exactly.
// 4. The rows a rank of the program builds (RowSelection) with the
//    symmetry constraints: the owned rows equal deal.II's condensed serial
//    matrix bit for bit (0 difference), the other rows hold a zero
//    diagonal only, and the pattern stores the owned rows' entries plus
//    one per other row.
// 5. Discretization::renumber_unknowns() with that numbering: positions,
//    components, roller constraints, HRZ masses, stiffness entries, contact
//    segments' unknowns and the field on every cell equal the original's
//    with the unknowns permuted, bit for bit (0 difference).
// 6. The interface layers of 2 parts (load balancing): every unknown is
//    reached, on its owner's side (layer <= 0 in part 0, > 0 in part 1),
//    and no entry of the stiffness pattern couples layers more than one
//    apart (0 such entries), which makes every split at a layer a split
//    whose ghosts are one layer; 1 and 3 parts have no layers.
// 7. A body whole in one part: no interface, no layers.
// 8. The same with anchors, the contact surface's unknowns (load balancing
//    of bodies whole on ranks): layers from the unknowns farthest from the
//    anchors, every unknown reached, the anchors alone in the deepest
//    layer, no coupling across more than one layer.
// 9. UnknownExchange's halves (ranks that need not meet at every step,
//    doc/parallel.md session 34): three ghost updates started from the
//    values of sent_unknowns() and completed later (the sends alternate
//    between two buffers) give every ghost its owner's value exactly (0
//    difference), as update_ghost_values() does; a sum started and
//    completed later equals sum() bit for bit and the exact sum of the
//    ranks' numbers.
// 10. Claimed balancing's claims (2 ranks; FEA at 5 refinements, a band of
//    up to 40 % of each part: 6 chunks), in orders that messages
//    impose: rank 0 alone takes every chunk of the band while rank 1
//    waits, rank 1 alone takes every chunk while rank 0 waits, and rank 0
//    takes k chunks before rank 1 claims the rest; both ranks agree on the
//    meeting (n, 0, k chunks of rank 0), the chunks each was given are its
//    own end's in order, and the rows of the two sides add up to the
//    band's. (The program's history cannot show this: which rank takes a
//    chunk depends on the machine's timing.)
// 11. The band of a body whole on rank 0 with the state shared (the
//    default for two bodies on one node; a band of up to 30 %, the curved
//    boundary's unknowns shared), at 5 refinements: consecutive rows, one
//    range per chunk (session 60: the shared unknowns among them, where
//    sessions 54-59 left them out and they cut the band), more than 10 %
//    and at most 30 % of the rows, at the end of the index range with no
//    more shared unknowns among as many rows than the other end.
#include <deal.II/base/mpi.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>

#include <isoimpact/discretization/discretization_fea.h>
#include <isoimpact/discretization/discretization_iga.h>
#include <isoimpact/discretization/unknown_exchange.h>
#include <isoimpact/discretization/unknown_partition.h>
#include <isoimpact/mechanics/assembly.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "tests.h"

using namespace dealii;
using namespace isoimpact;

namespace
{
  // The unknowns of the curved boundary (the contact surface), sorted.
  std::vector<types::global_dof_index>
  curved_boundary_unknowns(const Discretization<2> &discretization)
  {
    std::vector<types::global_dof_index> unknowns;
    for (const auto &segment :
         discretization.boundary_segments(BodyGeometry::curved_boundary_id))
      for (const auto &node : segment.node_dofs)
        unknowns.insert(unknowns.end(), node.begin(), node.end());
    std::sort(unknowns.begin(), unknowns.end());
    unknowns.erase(std::unique(unknowns.begin(), unknowns.end()),
                   unknowns.end());
    return unknowns;
  }

  std::unique_ptr<Discretization<2>>
  make_discretization(const bool iga, const unsigned int refinements)
  {
    BodyGeometry geometry;
    geometry.global_refinements = refinements;
    if (iga)
      return std::make_unique<DiscretizationIGA<2>>(geometry, 2);
    return std::make_unique<DiscretizationFEA<2>>(geometry, 2);
  }

  void
  check_partitions(const Discretization<2> &discretization)
  {
    AffineConstraints<double> none;
    none.close();
    SparsityPattern pattern;
    make_sparsity_pattern(discretization, none, pattern);
    const double n       = discretization.n_dofs();
    const double n_cells = discretization.triangulation().n_active_cells();
    for (const unsigned int n_parts : {1U, 2U, 3U})
      {
        const UnknownPartition<2> partition(discretization, n_parts);
        double                    owned_total = 0., cell_imbalance = 0.;
        double                    imbalance = 0., max_ghosts = 0.;
        double                    missing = 0.;
        IndexSet                  all(discretization.n_dofs());
        for (unsigned int p = 0; p < n_parts; ++p)
          {
            const IndexSet &owned    = partition.owned_unknowns(p);
            const IndexSet &relevant = partition.relevant_unknowns(p);
            owned_total += owned.n_elements();
            all.add_indices(owned);
            imbalance =
              std::max(imbalance,
                       std::abs(owned.n_elements() / (n / n_parts) - 1.));
            unsigned int cells = 0;
            for (unsigned int c = 0; c < n_cells; ++c)
              cells += (partition.cell_owner(c) == p) ? 1 : 0;
            cell_imbalance =
              std::max(cell_imbalance,
                       std::abs(cells / (n_cells / n_parts) - 1.));
            for (const auto i : owned)
              for (auto entry = pattern.begin(i); entry != pattern.end(i);
                   ++entry)
                missing += relevant.is_element(entry->column()) ? 0. : 1.;
            max_ghosts = std::max(max_ghosts,
                                  (relevant.n_elements() - owned.n_elements()) /
                                    (n / n_parts));
          }
        std::cout << discretization.name() << ", " << n_parts
                  << " parts: unknowns " << n << ", imbalance "
                  << 100. * imbalance << " % (cells " << 100. * cell_imbalance
                  << " %), ghosts at most " << 100. * max_ghosts
                  << " % of n / parts" << std::endl;
        CHECK_CLOSE_ABS(owned_total, n, 0.);
        CHECK_CLOSE_ABS(all.n_elements(), n, 0.);
        CHECK_CLOSE_ABS(cell_imbalance, 0., 0.03);
        CHECK_CLOSE_ABS(imbalance, 0., 0.10);
        CHECK_CLOSE_ABS(missing, 0., 0.);
        CHECK_CLOSE_ABS(max_ghosts, 0., n_parts == 1 ? 0. : 0.25);

        // 6. The interface layers (2 parts; none otherwise).
        const auto &layers = partition.interface_layers();
        CHECK_CLOSE_ABS(layers.size(), n_parts == 2 ? n : 0., 0.);
        if (n_parts != 2)
          continue;
        double wrong_side = 0., jumps = 0., unreached = 0.;
        int    deepest = 0, highest = 0;
        for (types::global_dof_index i = 0; i < layers.size(); ++i)
          {
            wrong_side += ((layers[i] <= 0) != (partition.owner(i) == 0));
            unreached += std::abs(layers[i]) ==
                         UnknownPartition<2>::interface_layer_unreached;
            deepest = std::min(deepest, layers[i]);
            highest = std::max(highest, layers[i]);
            for (auto entry = pattern.begin(i); entry != pattern.end(i);
                 ++entry)
              jumps += std::abs(layers[i] - layers[entry->column()]) > 1;
          }
        std::cout << "    interface layers " << deepest << " to " << highest
                  << ", couplings across more than one layer " << jumps
                  << std::endl;
        CHECK_CLOSE_ABS(wrong_side, 0., 0.);
        CHECK_CLOSE_ABS(unreached, 0., 0.);
        CHECK_CLOSE_ABS(jumps, 0., 0.);
        CHECK_TRUE(deepest < -2 && highest > 3);
      }

    // 7. A body whole in one part (Parallel/Distribution): part 1 of 2
    // owns every unknown and assembles every cell, part 0 nothing; no
    // interface layers.
    const UnknownPartition<2> whole(discretization, 2, 1);
    double                    cells_of_1 = 0., assembled_by_0 = 0.;
    for (unsigned int c = 0; c < n_cells; ++c)
      {
        cells_of_1 += whole.cell_owner(c) == 1 && whole.is_assembly_cell(c, 1);
        assembled_by_0 += whole.is_assembly_cell(c, 0);
      }
    std::cout << discretization.name() << ", whole in part 1 of 2: owned "
              << whole.owned_unknowns(0).n_elements() << " / "
              << whole.owned_unknowns(1).n_elements() << std::endl;
    CHECK_CLOSE_ABS(whole.owned_unknowns(1).n_elements(), n, 0.);
    CHECK_CLOSE_ABS(whole.relevant_unknowns(1).n_elements(), n, 0.);
    CHECK_CLOSE_ABS(whole.owned_unknowns(0).n_elements(), 0., 0.);
    CHECK_CLOSE_ABS(whole.relevant_unknowns(0).n_elements(), 0., 0.);
    CHECK_CLOSE_ABS(cells_of_1, n_cells, 0.);
    CHECK_CLOSE_ABS(assembled_by_0, 0., 0.);
    CHECK_CLOSE_ABS(whole.interface_layers().size(), 0., 0.);

    // 8. A body whole in one part with anchors, its contact surface's
    // unknowns (load balancing of whole bodies): the layers count from the
    // unknowns farthest from the anchors (layer 1 in part 1, 0 in part 0);
    // every unknown is reached, on the owner's side; the anchors are in the
    // deepest layer and no other unknown is; no entry of the pattern
    // couples layers more than one apart (0 such entries).
    const std::vector<types::global_dof_index> anchors =
      curved_boundary_unknowns(discretization);
    for (const unsigned int part : {0U, 1U})
      {
        const UnknownPartition<2> anchored(discretization, 2, part, anchors);
        const auto               &layers = anchored.interface_layers();
        CHECK_CLOSE_ABS(layers.size(), n, 0.);
        double wrong_side = 0., jumps = 0., anchors_elsewhere = 0.;
        double others_in_deepest = 0.;
        int    nearest = 1 << 30, deepest = 0;
        for (types::global_dof_index i = 0; i < layers.size(); ++i)
          {
            const int depth = part == 0 ? -layers[i] : layers[i] - 1;
            wrong_side += depth < 0;
            nearest = std::min(nearest, depth);
            deepest = std::max(deepest, depth);
            for (auto entry = pattern.begin(i); entry != pattern.end(i);
                 ++entry)
              jumps += std::abs(layers[i] - layers[entry->column()]) > 1;
          }
        for (types::global_dof_index i = 0; i < layers.size(); ++i)
          {
            const int  depth = part == 0 ? -layers[i] : layers[i] - 1;
            const bool is_anchor =
              std::binary_search(anchors.begin(), anchors.end(), i);
            anchors_elsewhere += is_anchor && depth != deepest;
            others_in_deepest += !is_anchor && depth == deepest;
          }
        std::cout << discretization.name() << ", whole in part " << part
                  << " with " << anchors.size() << " anchors: layers 0 to "
                  << deepest
                  << " from the farthest, couplings across more than one "
                  << "layer " << jumps << std::endl;
        CHECK_CLOSE_ABS(wrong_side, 0., 0.);
        CHECK_CLOSE_ABS(nearest, 0., 0.);
        CHECK_TRUE(deepest > 3 && deepest < (1 << 29));
        CHECK_CLOSE_ABS(anchors_elsewhere, 0., 0.);
        CHECK_CLOSE_ABS(others_in_deepest, 0., 0.);
        CHECK_CLOSE_ABS(jumps, 0., 0.);
      }
  }

  void
  check_distributed_product(const Discretization<2> &discretization,
                            const MPI_Comm           communicator)
  {
    const unsigned int rank    = Utilities::MPI::this_mpi_process(communicator);
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(communicator);
    const UnknownPartition<2> partition(discretization, n_ranks);
    const IndexSet           &owned = partition.owned_unknowns(rank);
    const ElasticMaterial     material;

    // The serial matrix, on every rank.
    AffineConstraints<double> none;
    none.close();
    SparsityPattern pattern;
    make_sparsity_pattern(discretization, none, pattern);
    SparseMatrix<double> stiffness(pattern);
    assemble_stiffness_matrix(discretization, material, none, stiffness);

    // The owned rows, from the rank's assembly cells.
    const auto is_mine = [&](const unsigned int cell) {
      return partition.is_assembly_cell(cell, rank);
    };
    TrilinosWrappers::SparsityPattern distributed_pattern(owned,
                                                          owned,
                                                          communicator);
    for_each_element(
      discretization,
      material,
      MassScheme::hrz,
      [&](const std::vector<types::global_dof_index> &indices,
          const FullMatrix<double> &,
          const FullMatrix<double> &) {
        for (const auto i : indices)
          if (owned.is_element(i))
            for (const auto j : indices)
              distributed_pattern.add(i, j);
      },
      is_mine);
    distributed_pattern.compress();
    TrilinosWrappers::SparseMatrix distributed(distributed_pattern);
    for_each_element(
      discretization,
      material,
      MassScheme::hrz,
      [&](const std::vector<types::global_dof_index> &indices,
          const FullMatrix<double>                   &element_stiffness,
          const FullMatrix<double> &) {
        for (unsigned int a = 0; a < indices.size(); ++a)
          if (owned.is_element(indices[a]))
            for (unsigned int b = 0; b < indices.size(); ++b)
              distributed.add(indices[a], indices[b], element_stiffness(a, b));
      },
      is_mine);
    distributed.compress(VectorOperation::add);

    double entry_difference = 0.;
    for (const auto i : owned)
      for (auto entry = stiffness.begin(i); entry != stiffness.end(i); ++entry)
        entry_difference =
          std::max(entry_difference,
                   std::abs(distributed.el(i, entry->column()) -
                            entry->value()));
    entry_difference = Utilities::MPI::max(entry_difference, communicator);

    Vector<double> u(discretization.n_dofs()), product(u.size());
    for (unsigned int i = 0; i < u.size(); ++i)
      u(i) = std::sin(0.37 * i) * 1e-3;
    stiffness.vmult(product, u);
    TrilinosWrappers::MPI::Vector u_distributed(owned, communicator),
      product_distributed(owned, communicator);
    for (const auto i : owned)
      u_distributed(i) = u(i);
    u_distributed.compress(VectorOperation::insert);
    distributed.vmult(product_distributed, u_distributed);
    double difference = 0.;
    for (const auto i : owned)
      difference =
        std::max(difference, std::abs(product_distributed(i) - product(i)));
    difference =
      Utilities::MPI::max(difference, communicator) / product.linfty_norm();
    std::cout << discretization.name() << " on " << n_ranks << " ranks: rank "
              << rank << " owns " << owned.n_elements() << " of "
              << discretization.n_dofs() << " unknowns; entries differ by "
              << entry_difference << ", K u by " << difference
              << " of max |K u|" << std::endl;
    CHECK_CLOSE_ABS(Utilities::MPI::sum(double(owned.n_elements()),
                                        communicator),
                    discretization.n_dofs(),
                    0.);
    CHECK_CLOSE_ABS(entry_difference, 0., 0.);
    CHECK_CLOSE_ABS(difference, 0., 1e-14);

    // The part-major numbering: each rank's unknowns one contiguous range,
    // in the ranks' order; a distributed vector over it receives every
    // relevant value through the ghost exchange, exactly.
    const auto numbering   = partition.part_major_numbering();
    const auto owned_range = UnknownPartition<2>::renumber(owned, numbering);
    const auto relevant_range =
      UnknownPartition<2>::renumber(partition.relevant_unknowns(rank),
                                    numbering);
    types::global_dof_index first = 0;
    for (unsigned int r = 0; r < rank; ++r)
      first += partition.owned_unknowns(r).n_elements();
    IndexSet expected_range(discretization.n_dofs());
    expected_range.add_range(first, first + owned.n_elements());
    LinearAlgebra::distributed::Vector<double> ghosted(owned_range,
                                                       relevant_range,
                                                       communicator);
    for (const auto i : owned)
      ghosted(numbering[i]) = u(i);
    ghosted.update_ghost_values();
    double ghost_difference = 0.;
    for (const auto i : partition.relevant_unknowns(rank))
      ghost_difference =
        std::max(ghost_difference, std::abs(ghosted(numbering[i]) - u(i)));
    ghost_difference = Utilities::MPI::max(ghost_difference, communicator);
    std::cout << "    part-major numbering: rank " << rank << " owns [" << first
              << ", " << first + owned.n_elements() << "), "
              << relevant_range.n_elements() - owned_range.n_elements()
              << " ghosts, ghost values differ by " << ghost_difference
              << std::endl;
    CHECK_TRUE(owned_range == expected_range);
    CHECK_CLOSE_ABS(Utilities::MPI::sum(double(relevant_range.n_elements() -
                                               owned_range.n_elements()),
                                        communicator),
                    Utilities::MPI::sum(
                      double(partition.relevant_unknowns(rank).n_elements() -
                             owned.n_elements()),
                      communicator),
                    0.);
    CHECK_CLOSE_ABS(ghost_difference, 0., 0.);
  }
  // The rows a rank of the program builds (RowSelection, used by
  // ElasticBody on several ranks): with the symmetry constraints u_x = 0,
  // the owned rows of the restricted pattern and matrix equal the serial
  // ones (deal.II's condensation) bit for bit, and every other row holds its
  // diagonal only, so the pattern stores the owned rows' entries plus one
  // per other row.
  void
  check_row_selection(const Discretization<2> &discretization,
                      const MPI_Comm           communicator)
  {
    const unsigned int rank    = Utilities::MPI::this_mpi_process(communicator);
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(communicator);
    const UnknownPartition<2> partition(discretization, n_ranks);
    const IndexSet           &owned = partition.owned_unknowns(rank);
    const ElasticMaterial     material;
    AffineConstraints<double> constraints;
    discretization.constrain_component_on_boundary(
      BodyGeometry::symmetry_boundary_id,
      0,
      constraints);
    constraints.close();

    SparsityPattern pattern;
    make_sparsity_pattern(discretization, constraints, pattern);
    SparseMatrix<double> stiffness(pattern);
    assemble_stiffness_matrix(discretization, material, constraints, stiffness);

    const RowSelection selection{owned, [&](const unsigned int cell) {
                                   return partition.is_assembly_cell(cell,
                                                                     rank);
                                 }};
    SparsityPattern    rows_pattern;
    make_sparsity_pattern(discretization,
                          constraints,
                          rows_pattern,
                          &selection);
    SparseMatrix<double> rows(rows_pattern);
    assemble_stiffness_matrix(discretization,
                              material,
                              constraints,
                              rows,
                              &selection);

    double       entry_difference = 0.;
    std::size_t  owned_entries    = 0;
    unsigned int constrained_rows = 0, rows_of_other_length = 0;
    for (const auto i : owned)
      {
        owned_entries += pattern.row_length(i);
        constrained_rows += constraints.is_constrained(i);
        rows_of_other_length +=
          rows_pattern.row_length(i) != pattern.row_length(i);
        for (auto entry = stiffness.begin(i); entry != stiffness.end(i);
             ++entry)
          entry_difference =
            std::max(entry_difference,
                     std::abs(rows.el(i, entry->column()) - entry->value()));
      }
    double other_rows_norm = 0.;
    for (types::global_dof_index i = 0; i < rows.m(); ++i)
      if (!owned.is_element(i))
        other_rows_norm += std::abs(rows.diag_element(i));
    std::cout << discretization.name() << ": rank " << rank << " builds "
              << owned.n_elements() << " rows (" << constrained_rows
              << " constrained), " << rows_pattern.n_nonzero_elements()
              << " of the serial pattern's " << pattern.n_nonzero_elements()
              << " entries; entries differ by " << entry_difference
              << std::endl;
    CHECK_TRUE(Utilities::MPI::sum(constrained_rows, communicator) > 0);
    CHECK_CLOSE_ABS(double(rows_pattern.n_nonzero_elements()),
                    double(owned_entries + rows.m() - owned.n_elements()),
                    0.);
    CHECK_CLOSE_ABS(rows_of_other_length, 0, 0);
    CHECK_CLOSE_ABS(entry_difference, 0., 0.);
    CHECK_CLOSE_ABS(other_rows_norm, 0., 0.);
  }

  // Everything a body is built from, in the renumbered discretisation,
  // equals the original's with the unknowns permuted, bit for bit.
  void
  check_renumbering(const bool iga)
  {
    const auto original   = make_discretization(iga, 3);
    auto       renumbered = make_discretization(iga, 3);
    const auto numbering =
      UnknownPartition<2>(*original, 2).part_major_numbering();
    renumbered->renumber_unknowns(numbering);
    const auto n = original->n_dofs();

    const ElasticMaterial     material;
    AffineConstraints<double> constraints[2];
    SparsityPattern           patterns[2];
    SparseMatrix<double>      stiffness[2];
    Vector<double>            masses[2];
    const Discretization<2>  *discretizations[2] = {original.get(),
                                                    renumbered.get()};
    for (unsigned int k = 0; k < 2; ++k)
      {
        discretizations[k]->make_constraints(constraints[k]);
        discretizations[k]->constrain_component_on_boundary(
          BodyGeometry::symmetry_boundary_id,
          0,
          constraints[k]);
        constraints[k].close();
        make_sparsity_pattern(*discretizations[k], constraints[k], patterns[k]);
        stiffness[k].reinit(patterns[k]);
        assemble_stiffness_matrix(*discretizations[k],
                                  material,
                                  constraints[k],
                                  stiffness[k]);
        masses[k] = assemble_lumped_mass(*discretizations[k],
                                         material.density,
                                         MassScheme::hrz,
                                         constraints[k]);
      }
    double differences = 0.;
    for (types::global_dof_index i = 0; i < n; ++i)
      {
        const auto j = numbering[i];
        differences +=
          (original->dof_position(i) - renumbered->dof_position(j)).norm() +
          std::abs(double(original->dof_component(i)) -
                   renumbered->dof_component(j)) +
          std::abs(masses[0](i) - masses[1](j)) +
          (constraints[0].is_constrained(i) !=
           constraints[1].is_constrained(j));
        for (auto entry = stiffness[0].begin(i); entry != stiffness[0].end(i);
             ++entry)
          differences += std::abs(
            stiffness[1].el(j, numbering[entry->column()]) - entry->value());
      }
    differences += std::abs(double(stiffness[0].n_nonzero_elements()) -
                            stiffness[1].n_nonzero_elements());
    const auto segments =
      original->boundary_segments(BodyGeometry::curved_boundary_id);
    const auto renumbered_segments =
      renumbered->boundary_segments(BodyGeometry::curved_boundary_id);
    differences +=
      std::abs(double(segments.size()) - renumbered_segments.size());
    for (unsigned int s = 0; s < segments.size(); ++s)
      for (unsigned int k = 0; k < segments[s].node_dofs.size(); ++k)
        for (unsigned int d = 0; d < 2; ++d)
          differences += (numbering[segments[s].node_dofs[k][d]] !=
                          renumbered_segments[s].node_dofs[k][d]);
    // The field on every cell (as DataOut sees it) is the same.
    Vector<double> u(n), u_renumbered(n), field[2];
    for (types::global_dof_index i = 0; i < n; ++i)
      u_renumbered(numbering[i]) = u(i) = std::cos(0.11 * i);
    original->to_dof_handler_vector(u, field[0]);
    renumbered->to_dof_handler_vector(u_renumbered, field[1]);
    Vector<double> cell_values[2] = {
      Vector<double>(original->fe().n_dofs_per_cell()),
      Vector<double>(original->fe().n_dofs_per_cell())};
    auto cell = original->dof_handler().begin_active();
    for (const auto &renumbered_cell :
         renumbered->dof_handler().active_cell_iterators())
      {
        cell->get_dof_values(field[0], cell_values[0]);
        renumbered_cell->get_dof_values(field[1], cell_values[1]);
        cell_values[0] -= cell_values[1];
        differences += cell_values[0].linfty_norm();
        ++cell;
      }
    std::cout << original->name() << ": renumbered by 2 parts, "
              << constraints[1].n_constraints() << " constraints, "
              << segments.size() << " contact segments, sum of differences "
              << differences << std::endl;
    // The numbering moves unknowns (else the check proves nothing).
    unsigned int moved = 0;
    for (types::global_dof_index i = 0; i < n; ++i)
      moved += (numbering[i] != i) ? 1 : 0;
    std::cout << "    " << moved << " of " << n << " unknowns moved"
              << std::endl;
    CHECK_TRUE(moved > n / 4);
    CHECK_CLOSE_ABS(differences, 0., 0.);
  }

  // (9) above.
  void
  check_exchange_halves(const Discretization<2> &discretization,
                        const MPI_Comm           communicator)
  {
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(communicator);
    const UnknownPartition<2> partition(discretization, n_ranks);
    const UnknownExchange     exchange(partition, communicator, {});
    const auto value = [](const std::size_t i, const unsigned int round) {
      return std::sin(0.37 * i + round) * 1e-3;
    };
    UnknownExchange::UpdateUnderWay update;
    double                          difference = 0.;
    std::size_t                     n_ghosts = exchange.ghost_unknowns().size();
    for (unsigned int round = 0; round < 3; ++round)
      {
        std::vector<double> sent;
        for (const auto i : exchange.sent_unknowns())
          sent.push_back(value(i, round));
        Vector<double> u(discretization.n_dofs());
        exchange.start_ghost_update(sent, 4900, update);
        exchange.complete_ghost_update(u, update);
        Vector<double> expected(discretization.n_dofs());
        for (const auto i : exchange.owned_unknowns())
          expected(i) = value(i, round);
        exchange.update_ghost_values(expected);
        for (const auto i : exchange.ghost_unknowns())
          difference = std::max({difference,
                                 std::abs(u(i) - value(i, round)),
                                 std::abs(expected(i) - value(i, round))});
      }
    difference                 = Utilities::MPI::max(difference, communicator);
    std::vector<double> halves = {double(exchange.this_rank() + 1),
                                  value(exchange.this_rank(), 7)},
                        whole  = halves;
    UnknownExchange::SumUnderWay sum;
    exchange.start_sum(halves, sum);
    exchange.sum(whole);
    exchange.complete_sum(sum, halves);
    std::cout << discretization.name() << " on " << n_ranks
              << " ranks: ghosts of three updates in halves differ by "
              << difference << " (" << n_ghosts
              << " ghosts on this rank); the sums in halves and at once "
              << halves[0] << ", " << halves[1] << " and " << whole[0] << ", "
              << whole[1] << std::endl;
    CHECK_CLOSE_ABS(difference, 0., 0.);
    CHECK_TRUE(n_ranks == 1 ||
               Utilities::MPI::sum(double(n_ghosts), communicator) > 0);
    CHECK_CLOSE_ABS(halves[0], n_ranks * (n_ranks + 1) / 2., 0.);
    CHECK_CLOSE_ABS(halves[1], whole[1], 0.);
  }

  // (10) above.
  void
  check_claims(const Discretization<2> &discretization,
               const MPI_Comm           communicator)
  {
    if (Utilities::MPI::n_mpi_processes(communicator) != 2)
      return;
    const UnknownPartition<2> partition(discretization, 2);
    UnknownExchange           exchange(partition,
                             communicator,
                             {},
                             LoadBalancing::claimed,
                             0.4);
    exchange.open_claims();
    const unsigned int rank      = exchange.this_rank();
    const int          n_chunks  = exchange.n_band_chunks();
    std::size_t        band_rows = 0;
    for (int c = 0; c < n_chunks; ++c)
      for (const auto &[first, end] : exchange.chunk_ranges(c))
        band_rows += end - first;
    // Passes of the claims: `first` claims `limit` chunks (all while it
    // can if limit < 0), tells the other rank, which claims until the
    // ranks meet and answers; then `first` claims once more (the meeting).
    const auto pass = [&](const unsigned int first, const int limit) {
      std::vector<int> given;
      int              chunk = -1, token = 0;
      const auto       claim_all = [&]() {
        while (exchange.claim_chunk(chunk))
          given.push_back(chunk);
      };
      if (rank == first)
        {
          if (limit < 0)
            claim_all();
          else
            for (int k = 0; k < limit; ++k)
              {
                AssertThrow(exchange.claim_chunk(chunk), ExcInternalError());
                given.push_back(chunk);
              }
          MPI_Send(&token, 1, MPI_INT, 1 - rank, 4910, communicator);
          MPI_Recv(&token,
                   1,
                   MPI_INT,
                   1 - rank,
                   4911,
                   communicator,
                   MPI_STATUS_IGNORE);
          if (limit >= 0)
            claim_all();
        }
      else
        {
          MPI_Recv(&token,
                   1,
                   MPI_INT,
                   1 - rank,
                   4910,
                   communicator,
                   MPI_STATUS_IGNORE);
          claim_all();
          MPI_Send(&token, 1, MPI_INT, 1 - rank, 4911, communicator);
        }
      // A rank's chunks: its own end's, in order.
      bool in_order = true;
      for (unsigned int k = 0; k < given.size(); ++k)
        in_order =
          in_order && given[k] == (rank == 0 ? int(k) : n_chunks - 1 - int(k));
      return std::make_pair(int(given.size()), in_order);
    };
    const std::vector<std::pair<unsigned int, int>> orders = {{0, -1},
                                                              {1, -1},
                                                              {0, 1},
                                                              {1, 2},
                                                              {0, -1}};
    for (const auto &[first, limit] : orders)
      {
        const auto [n_given, in_order] = pass(first, limit);
        const int expected_of_rank_0 =
          limit < 0 ? (first == 0 ? n_chunks : 0) :
                      (first == 0 ? limit : n_chunks - limit);
        const int of_rank_0 = exchange.n_chunks_of_rank_0();
        std::cout << "claims, rank " << rank << ", rank " << first << " first ("
                  << (limit < 0 ? "all" : std::to_string(limit))
                  << " chunks): this rank took " << n_given << " of "
                  << n_chunks << " chunks, the meeting after " << of_rank_0
                  << " chunks of rank 0; rows " << exchange.n_claimed_rows(0)
                  << " + " << exchange.n_claimed_rows(1) << " of " << band_rows
                  << std::endl;
        CHECK_TRUE(n_chunks >= 3);
        CHECK_TRUE(in_order);
        CHECK_CLOSE_ABS(of_rank_0, expected_of_rank_0, 0);
        CHECK_CLOSE_ABS(n_given,
                        rank == 0 ? expected_of_rank_0 :
                                    n_chunks - expected_of_rank_0,
                        0);
        CHECK_CLOSE_ABS(Utilities::MPI::max(of_rank_0, communicator),
                        Utilities::MPI::min(of_rank_0, communicator),
                        0);
        CHECK_CLOSE_ABS(exchange.n_claimed_rows(0) + exchange.n_claimed_rows(1),
                        band_rows,
                        0);
      }
  }

  // (11) above.
  void
  check_band_position(const Discretization<2> &discretization,
                      const MPI_Comm           communicator)
  {
    if (Utilities::MPI::n_mpi_processes(communicator) != 2)
      return;
    const std::vector<types::global_dof_index> anchors =
      curved_boundary_unknowns(discretization);
    const UnknownPartition<2> partition(discretization, 2, 0, anchors);
    const UnknownExchange     exchange(partition,
                                   communicator,
                                   anchors,
                                   LoadBalancing::shared_memory,
                                   0.30);
    const auto                is_anchor = [&](const types::global_dof_index i) {
      return std::binary_search(anchors.begin(), anchors.end(), i);
    };
    // The band's rows in order, and where they are not consecutive.
    std::vector<types::global_dof_index> rows;
    std::size_t                          n_ranges = 0;
    for (int c = 0; c < exchange.n_band_chunks(); ++c)
      for (const auto &[first, end] : exchange.chunk_ranges(c))
        {
          ++n_ranges;
          for (auto i = first; i < end; ++i)
            rows.push_back(i);
        }
    std::size_t cuts = 0;
    for (std::size_t k = 1; k < rows.size(); ++k)
      cuts += rows[k] != rows[k - 1] + 1;
    const types::global_dof_index n = discretization.n_dofs();
    const std::size_t             in_band =
      std::count_if(rows.begin(), rows.end(), is_anchor);
    // As many rows at the other end.
    const bool  at_start     = rows.front() == 0;
    std::size_t at_other_end = 0;
    for (std::size_t k = 0; k < rows.size(); ++k)
      at_other_end += is_anchor(at_start ? n - 1 - k : k);
    const double share = double(rows.size()) / n;
    std::cout << discretization.name() << ", whole on rank 0, state shared: "
              << "band of " << rows.size() << " rows (rows " << rows.front()
              << " to " << rows.back() << ", " << share << " of the rows) in "
              << exchange.n_band_chunks() << " chunks and " << n_ranges
              << " ranges, " << in_band << " of the " << anchors.size()
              << " shared unknowns among them (" << at_other_end
              << " among as many rows at the other end)" << std::endl;
    CHECK_CLOSE_ABS(cuts, 0, 0);
    CHECK_CLOSE_ABS(n_ranges, exchange.n_band_chunks(), 0);
    CHECK_TRUE(at_start || rows.back() == n - 1);
    CHECK_TRUE(in_band <= at_other_end);
    CHECK_TRUE(share > 0.10 && share <= 0.30);
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  for (const bool iga : {false, true})
    {
      check_partitions(*make_discretization(iga, 5));
      check_distributed_product(*make_discretization(iga, 3), MPI_COMM_WORLD);
      check_row_selection(*make_discretization(iga, 3), MPI_COMM_WORLD);
      check_renumbering(iga);
      check_exchange_halves(*make_discretization(iga, 3), MPI_COMM_WORLD);
    }
  check_claims(*make_discretization(false, 5), MPI_COMM_WORLD);
  for (const bool iga : {false, true})
    check_band_position(*make_discretization(iga, 5), MPI_COMM_WORLD);
  return isoimpact_tests::report();
}
