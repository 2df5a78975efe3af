// Layer 3: what FEA and IGA share: the base class, the coarse mesh and the
// factory.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <deal.II/fe/mapping_q_cache.h>

#include <deal.II/grid/grid_generator.h>

#include <isoimpact/discretization/discretization.h>
#include <isoimpact/discretization/discretization_fea.h>
#include <isoimpact/discretization/discretization_iga.h>

#include <utility>

using namespace dealii;

namespace isoimpact
{
  template <int dim>
  Discretization<dim>::Discretization(
    const FiniteElement<dim>           &scalar_fe,
    std::unique_ptr<const Mapping<dim>> mapping,
    const unsigned int                  n_gauss_points)
    : vector_fe(scalar_fe, dim)
    , cell_mapping(std::move(mapping))
    , gauss_quadrature(n_gauss_points)
  {}

  template <int dim>
  void
  Discretization<dim>::set_unknowns(std::vector<Point<dim>>    positions,
                                    std::vector<unsigned char> components)
  {
    AssertDimension(positions.size(), components.size());
    unknown_positions  = std::move(positions);
    unknown_components = std::move(components);
  }

  template <int dim>
  void
  Discretization<dim>::renumber_unknowns(
    const std::vector<types::global_dof_index> &new_numbers)
  {
    const types::global_dof_index n = n_dofs();
    AssertThrow(new_numbers.size() == n,
                ExcMessage(
                  "renumber_unknowns: " + std::to_string(new_numbers.size()) +
                  " new numbers for " + std::to_string(n) + " unknowns"));
    std::vector<bool> taken(n, false);
    for (const auto i : new_numbers)
      {
        AssertThrow(i < n && !taken[i],
                    ExcMessage("renumber_unknowns: the new numbers are not "
                               "a permutation of 0.." +
                               std::to_string(n - 1)));
        taken[i] = true;
      }
    std::vector<Point<dim>>    positions(n);
    std::vector<unsigned char> components(n);
    for (types::global_dof_index i = 0; i < n; ++i)
      {
        positions[new_numbers[i]]  = unknown_positions[i];
        components[new_numbers[i]] = unknown_components[i];
      }
    renumber_own_indices(new_numbers);
    set_unknowns(std::move(positions), std::move(components));
  }

  template <int dim>
  void
  Discretization<dim>::cache_mapping(const unsigned int degree)
  {
    auto cache = std::make_unique<MappingQCache<dim>>(degree);
    cache->initialize(*cell_mapping, mesh);
    uncached_mapping = std::move(cell_mapping);
    cell_mapping     = std::move(cache);
  }

  template <int dim>
  void
  Discretization<dim>::release_cell_unknowns()
  {
    if (uncached_mapping)
      cell_mapping = std::move(uncached_mapping);
    dofs.reinit(mesh); // attached to the mesh, no element, no unknowns
  }

  template <int dim>
  void
  Discretization<dim>::make_constraints(AffineConstraints<double> &) const
  {}

  template <int dim>
  std::vector<BoundarySegment<dim>>
  Discretization<dim>::boundary_segments(
    const types::boundary_id boundary_id) const
  {
    AssertThrow(dim == 2,
                ExcMessage("boundary segments are implemented for dim = 2"));
    auto segments = unmarked_boundary_segments(boundary_id);
    // The contact surface goes on across the symmetry cut (mirror image).
    mark_free_segment_ends(segments,
                           boundary_id == BodyGeometry::symmetry_boundary_id ?
                             std::vector<BoundarySegment<dim>>() :
                             unmarked_boundary_segments(
                               BodyGeometry::symmetry_boundary_id));
    return segments;
  }

  template <int dim>
  HigherOrderCell
  Discretization<dim>::higher_order_cell(const cell_iterator &) const
  {
    HigherOrderCell cell;
    cell.degree = vector_fe.degree;
    cell.weights.assign(Utilities::pow(cell.degree + 1, dim), 1.);
    return cell;
  }

  std::vector<Point<2>>
  vtk_node_points(const unsigned int degree)
  {
    AssertThrow(degree >= 1, ExcMessage("a VTK cell needs degree >= 1"));
    const double          p      = degree;
    std::vector<Point<2>> points = {Point<2>(0., 0.),
                                    Point<2>(1., 0.),
                                    Point<2>(1., 1.),
                                    Point<2>(0., 1.)};
    for (unsigned int i = 1; i < degree; ++i) // edge 0: y = 0
      points.emplace_back(i / p, 0.);
    for (unsigned int j = 1; j < degree; ++j) // edge 1: x = 1
      points.emplace_back(1., j / p);
    for (unsigned int i = 1; i < degree; ++i) // edge 2: y = 1
      points.emplace_back(i / p, 1.);
    for (unsigned int j = 1; j < degree; ++j) // edge 3: x = 0
      points.emplace_back(0., j / p);
    for (unsigned int j = 1; j < degree; ++j)
      for (unsigned int i = 1; i < degree; ++i)
        points.emplace_back(i / p, j / p);
    return points;
  }

  template <int dim>
  void
  Discretization<dim>::to_dof_handler_vector(
    const Vector<double> &unknowns,
    Vector<double>       &dof_handler_vector) const
  {
    AssertDimension(unknowns.size(), n_dofs());
    dof_handler_vector.reinit(dofs.n_dofs());
    std::vector<types::global_dof_index> local(vector_fe.n_dofs_per_cell());
    std::vector<types::global_dof_index> global(vector_fe.n_dofs_per_cell());
    for (const auto &cell : dofs.active_cell_iterators())
      {
        cell->get_dof_indices(local);
        get_dof_indices(cell, global);
        for (unsigned int i = 0; i < local.size(); ++i)
          dof_handler_vector[local[i]] = unknowns[global[i]];
      }
  }

  void
  make_coarse_mesh(const BodyGeometry &geometry, Triangulation<2> &mesh)
  {
    using Shape = BodyGeometry::Shape;
    switch (geometry.shape)
      {
        case Shape::half_disk:
          // Boundary 0: the arc; boundary 1: the cut x = center_x.
          GridGenerator::half_hyper_ball(mesh,
                                         geometry.center,
                                         geometry.radius);
          break;
        case Shape::full_disk:
          GridGenerator::hyper_ball(mesh, geometry.center, geometry.radius);
          break;
        case Shape::rectangle:
          GridGenerator::hyper_rectangle(mesh,
                                         geometry.lower_left,
                                         geometry.upper_right,
                                         true);
          break;
      }
  }

  template <int dim>
  std::unique_ptr<Discretization<dim>>
  create_discretization(const DiscretizationMethod method,
                        const BodyGeometry        &geometry,
                        const unsigned int         degree,
                        const FEAElement           fea_element)
  {
    if (method == DiscretizationMethod::fea)
      return std::make_unique<DiscretizationFEA<dim>>(geometry,
                                                      degree,
                                                      fea_element);
    AssertThrow(fea_element == FEAElement::lagrange,
                ExcMessage("the FEA element '" + to_string(fea_element) +
                           "' was asked for the discretisation '" +
                           to_string(method) +
                           "': it is allowed only with 'fea'"));
    return std::make_unique<DiscretizationIGA<dim>>(geometry, degree);
  }

  template class Discretization<2>;
  template std::unique_ptr<Discretization<2>>
  create_discretization<2>(const DiscretizationMethod,
                           const BodyGeometry &,
                           const unsigned int,
                           const FEAElement);
} // namespace isoimpact
