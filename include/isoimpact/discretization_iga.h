// Layer 3: isogeometric analysis on one NURBS patch: FESystem(FE_NURBS, dim)
// with MappingNURBS; the unknowns are control-point displacements.
#ifndef isoimpact_discretization_iga_h
#define isoimpact_discretization_iga_h

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_system.h>

#include <isoimpact/discretization.h>
#include <isoimpact/fe_nurbs.h>
#include <isoimpact/mapping_nurbs.h>
#include <isoimpact/nurbs_geometries.h>

#include <array>
#include <memory>
#include <vector>

namespace isoimpact
{
  /**
   * One NURBS patch built from a BodyGeometry (half disk, full disk,
   * rectangle) and refined: degree elevation to `degree` (>= 2 for the
   * disks, whose circles need quadratic NURBS), then each span split into
   * 2^global_refinements equal spans in every direction, then, if
   * local_refinements > 0 and the body has a contact point (half disk),
   * graded knots toward it: local_refinements layers halving the span
   * touching the contact corner in both directions.
   *
   * Mesh: one deal.II cell per knot span, vertices = images of the span
   * corners, cell->user_index() = element index of the patch, faces oriented
   * like the patch (cell face f lies on patch side f when at the boundary).
   * Boundary ids of patch sides: arc sides BodyGeometry::curved_boundary_id,
   * symmetry sides BodyGeometry::symmetry_boundary_id, other sides their
   * side number f (rectangle: 0 left, 1 right, 2 bottom, 3 top, as in the
   * FEA version).
   *
   * Cell quadrature: QGauss(p+1) for polynomial patches (all weights
   * equal), QGauss(p+6) for rational ones (the rational integrands are
   * then integrated to about round-off on refined patches).
   *
   * Unknowns (interleaved): global index = dim * control_point + component.
   * The DoFHandler holds the broken layout of FE_NURBS and is only used for
   * FEValues/DataOut; to_dof_handler_vector() maps between the two.
   */
  template <int dim>
  class DiscretizationIGA : public Discretization<dim>
  {
  public:
    using typename Discretization<dim>::cell_iterator;

    DiscretizationIGA(const BodyGeometry &geometry, const unsigned int degree);

    // From a ready-made patch (it is used as is, without refinement).
    DiscretizationIGA(const nurbs::PatchGeometry<dim> &patch_geometry);

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

    const nurbs::NURBSPatch<dim> &
    get_patch() const
    {
      return *patch;
    }

    // Boundary id given to patch side f.
    types::boundary_id
    side_boundary_id(const unsigned int side) const
    {
      return side_ids[side];
    }

  private:
    void
    initialize();

    nurbs::PatchGeometry<dim>                     geometry;
    std::shared_ptr<const nurbs::NURBSPatch<dim>> patch;
    std::array<types::boundary_id, 2 * dim>       side_ids;
    Triangulation<dim>                            triangulation;
    FESystem<dim>                                 fe;
    MappingNURBS<dim>                             mapping;
    QGauss<dim>                                   cell_quadrature;
    DoFHandler<dim>                               dof_handler;
  };
} // namespace isoimpact

#endif
