// Layer 3: classical FEA, FESystem(FE_Q(p), dim) or FESystem(FE_Serendipity
// (2), dim) with MappingQ(p) on exact manifolds (circles are represented to
// the mapping's order).
#ifndef isoimpact_discretization_fea_h
#define isoimpact_discretization_fea_h

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

    // The DoFHandler's numbering (Cuthill-McKee).
    void
    get_dof_indices(
      const cell_iterator                          &cell,
      std::vector<dealii::types::global_dof_index> &indices) const override;

    // Hanging node constraints of locally refined meshes.
    void
    make_constraints(
      dealii::AffineConstraints<double> &constraints) const override;

    // Interpolated boundary values on the boundary's support points.
    void
    constrain_component_on_boundary(
      const dealii::types::boundary_id   boundary_id,
      const unsigned int                 component,
      dealii::AffineConstraints<double> &constraints) const override;

  private:
    // Renumbers the DoFHandler, whose numbering is that of the unknowns.
    void
    renumber_own_indices(
      const std::vector<dealii::types::global_dof_index> &new_numbers) override;

    // One segment per boundary face: its support points as nodes, the
    // Bernstein coefficients fitted to the face's shape functions.
    std::vector<BoundarySegment<dim>>
    unmarked_boundary_segments(
      const dealii::types::boundary_id boundary_id) const override;

    void
    make_mesh(const BodyGeometry &geometry);

    dealii::TransfiniteInterpolationManifold<dim> interior_manifold;
  };
} // namespace isoimpact

#endif
