// Layer 3: the distribution of the unknowns over MPI ranks.
#include <deal.II/base/exceptions.h>

#include <deal.II/grid/grid_tools.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <isoimpact/discretization/unknown_partition.h>

#include <algorithm>
#include <numeric>

using namespace dealii;

namespace isoimpact
{
  template <int dim>
  UnknownPartition<dim>::UnknownPartition(
    const Discretization<dim>                  &discretization,
    const unsigned int                          n_parts,
    const unsigned int                          whole_in_part,
    const std::vector<types::global_dof_index> &anchors)
  {
    const auto        &mesh    = discretization.triangulation();
    const unsigned int n_cells = mesh.n_active_cells();
    AssertThrow(n_parts >= 1 && n_parts <= n_cells,
                ExcMessage("cannot split " + std::to_string(n_cells) +
                           " cells into " + std::to_string(n_parts) +
                           " parts: allowed are 1 to the number of cells"));

    const bool whole = whole_in_part != numbers::invalid_unsigned_int;
    AssertThrow(!whole || whole_in_part < n_parts,
                ExcMessage("cannot put the cells in part " +
                           std::to_string(whole_in_part) + " of " +
                           std::to_string(n_parts)));

    // METIS on the cells' face graph.
    cell_owners.assign(n_cells, whole ? whole_in_part : 0);
    if (n_parts > 1 && !whole)
      {
        DynamicSparsityPattern face_graph;
        GridTools::get_face_connectivity_of_cells(mesh, face_graph);
        SparsityPattern graph;
        graph.copy_from(face_graph);
        SparsityTools::partition(graph,
                                 n_parts,
                                 cell_owners,
                                 SparsityTools::Partitioner::metis);
      }

    // Owners: the part of the first cell that carries the unknown.
    const auto                           n_unknowns = discretization.n_dofs();
    constexpr unsigned int               none = numbers::invalid_unsigned_int;
    std::vector<types::global_dof_index> indices;
    unknown_owners.assign(n_unknowns, none);
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      {
        discretization.get_dof_indices(cell, indices);
        for (const auto i : indices)
          if (unknown_owners[i] == none)
            unknown_owners[i] = cell_owners[cell->active_cell_index()];
      }
    AssertThrow(std::find(unknown_owners.begin(), unknown_owners.end(), none) ==
                  unknown_owners.end(),
                ExcMessage("an unknown of the discretisation '" +
                           discretization.name() + "' is on no cell"));

    owned.assign(n_parts, IndexSet(n_unknowns));
    relevant.assign(n_parts, IndexSet(n_unknowns));
    {
      std::vector<std::vector<types::global_dof_index>> owned_lists(n_parts);
      for (types::global_dof_index i = 0; i < n_unknowns; ++i)
        owned_lists[unknown_owners[i]].push_back(i);
      for (unsigned int p = 0; p < n_parts; ++p)
        owned[p].add_indices(owned_lists[p].begin(), owned_lists[p].end());
    }
    // Relevant: every unknown of a cell that carries an owned one. (All in
    // one part: every unknown and every cell of that part, without the
    // lists of every cell's unknowns.)
    std::vector<std::vector<types::global_dof_index>> relevant_lists(n_parts);
    std::vector<unsigned int>                         parts_of_cell;
    assembly_cells.assign(n_parts, {});
    if (whole)
      {
        relevant_lists[whole_in_part].resize(n_unknowns);
        std::iota(relevant_lists[whole_in_part].begin(),
                  relevant_lists[whole_in_part].end(),
                  types::global_dof_index(0));
        assembly_cells[whole_in_part].resize(n_cells);
        std::iota(assembly_cells[whole_in_part].begin(),
                  assembly_cells[whole_in_part].end(),
                  0u);
      }
    else
      for (const auto &cell :
           discretization.dof_handler().active_cell_iterators())
        {
          discretization.get_dof_indices(cell, indices);
          parts_of_cell.clear();
          for (const auto i : indices)
            parts_of_cell.push_back(unknown_owners[i]);
          std::sort(parts_of_cell.begin(), parts_of_cell.end());
          parts_of_cell.erase(std::unique(parts_of_cell.begin(),
                                          parts_of_cell.end()),
                              parts_of_cell.end());
          for (const unsigned int p : parts_of_cell)
            {
              relevant_lists[p].insert(relevant_lists[p].end(),
                                       indices.begin(),
                                       indices.end());
              assembly_cells[p].push_back(cell->active_cell_index());
            }
        }
    for (unsigned int p = 0; p < n_parts; ++p)
      {
        auto &list = relevant_lists[p];
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        // Each owned unknown is on its first cell, so it is in the list.
        relevant[p].add_indices(list.begin(), list.end());
        relevant[p].compress();
        owned[p].compress();
      }

    // Two parts: breadth-first layers from the interface, each part's
    // within itself (a shortest path to the other part crosses none); a
    // body whole in one part: from the anchors, within the body.
    if (n_parts == 2 && (!whole || !anchors.empty()))
      {
        std::vector<std::vector<unsigned int>>            cells_of(n_unknowns);
        std::vector<std::vector<types::global_dof_index>> unknowns_of(n_cells);
        for (const auto &cell :
             discretization.dof_handler().active_cell_iterators())
          {
            const unsigned int c = cell->active_cell_index();
            discretization.get_dof_indices(cell, unknowns_of[c]);
            for (const auto i : unknowns_of[c])
              cells_of[i].push_back(c);
          }
        constexpr int                        unset = interface_layer_unreached;
        std::vector<int>                     distance(n_unknowns, unset);
        std::vector<types::global_dof_index> front, next;
        if (whole)
          for (const auto i : anchors)
            {
              AssertIndexRange(i, n_unknowns);
              if (distance[i] == unset)
                {
                  distance[i] = 0;
                  front.push_back(i);
                }
            }
        else
          for (unsigned int c = 0; c < n_cells; ++c)
            {
              bool both = false;
              for (const auto i : unknowns_of[c])
                both |= unknown_owners[i] != unknown_owners[unknowns_of[c][0]];
              if (both)
                for (const auto i : unknowns_of[c])
                  if (distance[i] == unset)
                    {
                      distance[i] = 0;
                      front.push_back(i);
                    }
            }
        int deepest = 0;
        for (int d = 1; !front.empty(); ++d)
          {
            next.clear();
            for (const auto i : front)
              for (const auto c : cells_of[i])
                for (const auto j : unknowns_of[c])
                  if (distance[j] == unset &&
                      unknown_owners[j] == unknown_owners[i])
                    {
                      distance[j] = d;
                      next.push_back(j);
                      deepest = d;
                    }
            front.swap(next);
          }
        // Whole: the farthest unknowns next to the (virtual) interface.
        if (whole)
          for (auto &d : distance)
            if (d != unset)
              d = deepest - d;
        layers.resize(n_unknowns);
        for (types::global_dof_index i = 0; i < n_unknowns; ++i)
          layers[i] = unknown_owners[i] == 0 ?
                        -distance[i] :
                        (distance[i] == unset ? unset : 1 + distance[i]);
      }
  }

  template <int dim>
  const std::vector<int> &
  UnknownPartition<dim>::interface_layers() const
  {
    return layers;
  }

  template <int dim>
  unsigned int
  UnknownPartition<dim>::n_parts() const
  {
    return owned.size();
  }

  template <int dim>
  unsigned int
  UnknownPartition<dim>::n_cells() const
  {
    return cell_owners.size();
  }

  template <int dim>
  unsigned int
  UnknownPartition<dim>::cell_owner(const unsigned int active_cell_index) const
  {
    AssertIndexRange(active_cell_index, cell_owners.size());
    return cell_owners[active_cell_index];
  }

  template <int dim>
  unsigned int
  UnknownPartition<dim>::owner(const types::global_dof_index unknown) const
  {
    AssertIndexRange(unknown, unknown_owners.size());
    return unknown_owners[unknown];
  }

  template <int dim>
  const IndexSet &
  UnknownPartition<dim>::owned_unknowns(const unsigned int part) const
  {
    AssertIndexRange(part, owned.size());
    return owned[part];
  }

  template <int dim>
  const IndexSet &
  UnknownPartition<dim>::relevant_unknowns(const unsigned int part) const
  {
    AssertIndexRange(part, relevant.size());
    return relevant[part];
  }

  template <int dim>
  bool
  UnknownPartition<dim>::is_assembly_cell(const unsigned int active_cell_index,
                                          const unsigned int part) const
  {
    AssertIndexRange(part, assembly_cells.size());
    return std::binary_search(assembly_cells[part].begin(),
                              assembly_cells[part].end(),
                              active_cell_index);
  }

  template <int dim>
  std::vector<types::global_dof_index>
  UnknownPartition<dim>::part_major_numbering() const
  {
    std::vector<types::global_dof_index> numbering(unknown_owners.size());
    types::global_dof_index              next = 0;
    for (const auto &part : owned)
      for (const auto i : part)
        numbering[i] = next++;
    return numbering;
  }

  template <int dim>
  IndexSet
  UnknownPartition<dim>::renumber(
    const IndexSet                             &unknowns,
    const std::vector<types::global_dof_index> &numbering)
  {
    AssertDimension(unknowns.size(), numbering.size());
    std::vector<types::global_dof_index> renumbered;
    renumbered.reserve(unknowns.n_elements());
    for (const auto i : unknowns)
      renumbered.push_back(numbering[i]);
    std::sort(renumbered.begin(), renumbered.end());
    IndexSet result(unknowns.size());
    result.add_indices(renumbered.begin(), renumbered.end());
    result.compress();
    return result;
  }

  template class UnknownPartition<2>;
} // namespace isoimpact
