// Layer 3: the distribution of a discretisation's unknowns over MPI ranks
// (issue 13; the design is in doc/parallel.md).
#ifndef isoimpact_unknown_partition_h
#define isoimpact_unknown_partition_h

#include <deal.II/base/index_set.h>

#include <isoimpact/discretization/discretization.h>

#include <vector>

namespace isoimpact
{
  /**
   * The cells are split by METIS into parts of equal size along their face
   * graph (every rank computes the same split). An unknown belongs to the
   * part of the first active cell whose shape functions it carries: one
   * rule for FEA nodes and IGA control points, whose support spans several
   * cells. A part's relevant unknowns are those of every cell that carries
   * one of its own: the columns of its rows of the stiffness and mass
   * matrices (without hanging-node constraints), so the ghosts a step must
   * receive are relevant minus owned.
   *
   * With `whole_in_part` < n_parts every cell goes to that part and the
   * others own nothing: a body whole on one rank (Parallel/Distribution),
   * which the other ranks see through its shared unknowns only. Then,
   * with two parts and `anchors` (the contact surface's unknowns), the
   * layers of interface_layers() count from the unknowns farthest from the
   * anchors: the rows the other rank may take lie far from the contact.
   */
  template <int dim>
  class UnknownPartition
  {
  public:
    UnknownPartition(
      const Discretization<dim> &discretization,
      const unsigned int         n_parts,
      const unsigned int whole_in_part = dealii::numbers::invalid_unsigned_int,
      const std::vector<dealii::types::global_dof_index> &anchors = {});

    unsigned int
    n_parts() const;

    // The active cells, and the part of one (by its active_cell_index()).
    unsigned int
    n_cells() const;
    unsigned int
    cell_owner(const unsigned int active_cell_index) const;

    // Part that owns an unknown.
    unsigned int
    owner(const dealii::types::global_dof_index unknown) const;

    const dealii::IndexSet &
    owned_unknowns(const unsigned int part) const;

    const dealii::IndexSet &
    relevant_unknowns(const unsigned int part) const;

    // Whether an active cell carries one of the part's unknowns: the cells
    // its rows of K and M are assembled from (without communication; the
    // cells at the parts' interface are computed by both).
    bool
    is_assembly_cell(const unsigned int active_cell_index,
                     const unsigned int part) const;

    /**
     * A numbering in which each part's unknowns form one contiguous range,
     * the parts in order and each part's unknowns in their present order:
     * entry i is the new number of unknown i. deal.II's distributed vectors
     * need contiguous owned ranges; the serial program keeps its numbering.
     */
    std::vector<dealii::types::global_dof_index>
    part_major_numbering() const;

    /**
     * Two parts only (empty otherwise): the signed layer of every unknown
     * from the parts' interface in the graph of unknowns that share a cell
     * (the stiffness's graph): 0, -1, -2, ... in part 0 (0 next to part
     * 1), 1, 2, ... in part 1 (1 next to part 0). Coupled unknowns differ
     * by at most one layer, so the unknowns with layer <= s and > s form
     * another split of the same kind, whose ghosts are layer s + 1 and
     * layer s (UnknownExchange's load balancing). An unknown of a part
     * that does not touch the other keeps the largest magnitude
     * (interface_layer_unreached). For a body whole in one part with
     * anchors: D - d for part 1 (1 + D - d) and -(D - d) for part 0, with
     * d the distance from the anchors and D the largest; else empty.
     */
    const std::vector<int>                      &
    interface_layers() const;
    static constexpr int interface_layer_unreached = 1 << 30;

    // An index set of the unknowns, renumbered by `numbering`.
    static dealii::IndexSet
    renumber(const dealii::IndexSet                             &unknowns,
             const std::vector<dealii::types::global_dof_index> &numbering);

  private:
    std::vector<unsigned int>              cell_owners;
    std::vector<unsigned int>              unknown_owners;
    std::vector<dealii::IndexSet>          owned, relevant;
    std::vector<std::vector<unsigned int>> assembly_cells; // sorted
    std::vector<int>                       layers;
  };
} // namespace isoimpact

#endif
