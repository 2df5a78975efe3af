// Layer 3: what FEA and IGA share: the base class, the coarse mesh and the
// factory.
#include <deal.II/base/exceptions.h>

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
