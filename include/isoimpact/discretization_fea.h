// Layer 3: classical FEA, FESystem(FE_Q(p), dim) or FESystem(FE_Serendipity
// (2), dim) with MappingQ(p) on exact manifolds (circles are represented to
// the mapping's order).
#ifndef isoimpact_discretization_fea_h
#define isoimpact_discretization_fea_h

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>

#include <deal.II/grid/manifold_lib.h>

#include <isoimpact/discretization.h>

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
    const Triangulation<dim> &
    get_triangulation() const override;
    const Mapping<dim> &
    get_mapping() const override;
    const FiniteElement<dim> &
    get_fe() const override;
    const DoFHandler<dim> &
    get_dof_handler() const override;
    const Quadrature<dim> &
    get_cell_quadrature() const override;
    types::global_dof_index
    n_dofs() const override;
    void
    get_dof_indices(
      const cell_iterator                  &cell,
      std::vector<types::global_dof_index> &indices) const override;
    unsigned int
    dof_component(const types::global_dof_index dof) const override;
    Point<dim>
    dof_position(const types::global_dof_index dof) const override;
    void
    make_constraints(AffineConstraints<double> &constraints) const override;
    void
    constrain_component_on_boundary(
      const types::boundary_id   boundary_id,
      const unsigned int         component,
      AffineConstraints<double> &constraints) const override;
    std::vector<BoundarySegment<dim>>
    boundary_segments(const types::boundary_id boundary_id) const override;
    void
    to_dof_handler_vector(const Vector<double> &unknowns,
                          Vector<double> &dof_handler_vector) const override;

  private:
    void
    make_mesh(const BodyGeometry &geometry);

    Triangulation<dim>                    triangulation;
    TransfiniteInterpolationManifold<dim> interior_manifold;
    FESystem<dim>                         fe;
    MappingQ<dim>                         mapping;
    QGauss<dim>                           cell_quadrature;
    DoFHandler<dim>                       dof_handler;
    std::vector<Point<dim>>               support_points;
    std::vector<unsigned char>            components;
  };
} // namespace isoimpact

#endif
