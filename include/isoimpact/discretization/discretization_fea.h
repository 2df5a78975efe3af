// Layer 3: classical FEA, FESystem(FE_Q(p), dim) or FESystem(FE_Serendipity
// (2), dim) with MappingQ(p) on exact manifolds (circles are represented to
// the mapping's order).
#ifndef isoimpact_discretization_fea_h
#define isoimpact_discretization_fea_h

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>

#include <deal.II/grid/manifold_lib.h>

#include <isoimpact/discretization/discretization.h>

namespace isoimpact
{
  template <int dim>
  class DiscretizationFEA : public Discretization<dim>
  {
  public:
    using typename Discretization<dim>::cell_iterator;

    // `element` = serendipity: the 8-node Q8 element, only for degree 2
    // (other degrees throw); the mapping stays MappingQ(degree).
    DiscretizationFEA(const BodyGeometry &geometry,
                      const unsigned int  degree,
                      const FEAElement    element = FEAElement::lagrange);

    std::string
    name() const override;
    const dealii::Triangulation<dim> &
    get_triangulation() const override;
    const dealii::Mapping<dim> &
    get_mapping() const override;
    const dealii::FiniteElement<dim> &
    get_fe() const override;
    const dealii::DoFHandler<dim> &
    get_dof_handler() const override;
    const dealii::Quadrature<dim> &
    get_cell_quadrature() const override;
    dealii::types::global_dof_index
    n_dofs() const override;
    void
    get_dof_indices(
      const cell_iterator                          &cell,
      std::vector<dealii::types::global_dof_index> &indices) const override;
    unsigned int
    dof_component(const dealii::types::global_dof_index dof) const override;
    dealii::Point<dim>
    dof_position(const dealii::types::global_dof_index dof) const override;
    void
    make_constraints(
      dealii::AffineConstraints<double> &constraints) const override;
    void
    constrain_component_on_boundary(
      const dealii::types::boundary_id   boundary_id,
      const unsigned int                 component,
      dealii::AffineConstraints<double> &constraints) const override;
    std::vector<BoundarySegment<dim>>
    boundary_segments(
      const dealii::types::boundary_id boundary_id) const override;
    void
    to_dof_handler_vector(
      const dealii::Vector<double> &unknowns,
      dealii::Vector<double>       &dof_handler_vector) const override;

  private:
    void
    make_mesh(const BodyGeometry &geometry);

    dealii::Triangulation<dim>                    triangulation;
    dealii::TransfiniteInterpolationManifold<dim> interior_manifold;
    dealii::FESystem<dim>                         fe;
    dealii::MappingQ<dim>                         mapping;
    dealii::QGauss<dim>                           cell_quadrature;
    dealii::DoFHandler<dim>                       dof_handler;
    std::vector<dealii::Point<dim>>               support_points;
    std::vector<unsigned char>                    components;
  };
} // namespace isoimpact

#endif
