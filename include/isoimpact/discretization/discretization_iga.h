// Layer 3: isogeometric analysis on NURBS patches glued C0:
// FESystem(FE_NURBS, dim) with MappingNURBS; the unknowns are control-point
// displacements.
#ifndef isoimpact_discretization_iga_h
#define isoimpact_discretization_iga_h

#include <isoimpact/discretization/discretization.h>
#include <isoimpact/fe/fe_nurbs.h>
#include <isoimpact/fe/mapping_nurbs.h>
#include <isoimpact/nurbs/geometries.h>
#include <isoimpact/nurbs/multipatch.h>

#include <array>
#include <memory>
#include <vector>

namespace isoimpact
{
  /**
   * NURBS patches built from a BodyGeometry: one biquadratic patch per cell
   * of the body's coarse mesh (make_coarse_mesh(), the mesh the FEA
   * discretisation starts from: 4 cells for the half disk, 5 for the disk,
   * 1 for the rectangle), with exact arcs on the curved boundary
   * (nurbs::quadrilateral()), degree-elevated to `degree` (>= 2: circles
   * need quadratic NURBS), each span split into 2^global_refinements equal
   * spans per direction. The patches share their interface control points
   * (nurbs::MultiPatch), so the space is C0 across interfaces and
   * C^(p-1) inside patches; every patch corner is a regular corner (det J >
   * 0 everywhere), unlike a single patch covering a half disk. Then
   * local_refinements passes halve every knot span that carries an element
   * with a corner within refinement_radius of refinement_center, along the
   * whole knot line through the patches (nurbs::refine_near_point), so the
   * interfaces stay conforming.
   *
   * Mesh: one deal.II cell per knot span, vertices = images of the span
   * corners (shared across interfaces), cell->user_index() = global element
   * of the MultiPatch, faces oriented like the patch (a boundary face f of
   * a cell lies on side f of its patch). Boundary ids: those of the coarse
   * mesh (arc BodyGeometry::curved_boundary_id, cut
   * BodyGeometry::symmetry_boundary_id, rectangle 0..3 = left, right,
   * bottom, top), as in the FEA version.
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

    // From one ready-made patch (used as is, without refinement). Side
    // boundary ids: arc sides BodyGeometry::curved_boundary_id, symmetry
    // sides BodyGeometry::symmetry_boundary_id, other sides their number f.
    DiscretizationIGA(const nurbs::PatchGeometry<dim> &patch_geometry);

    std::string
    name() const override;

    // Interleaved: dim * (global control point) + component (until
    // renumber_unknowns()).
    void
    get_dof_indices(
      const cell_iterator                          &cell,
      std::vector<dealii::types::global_dof_index> &indices) const override;

    // Fixes the component of the control points of the boundary's patch
    // sides (they alone define the side's curve).
    void
    constrain_component_on_boundary(
      const dealii::types::boundary_id   boundary_id,
      const unsigned int                 component,
      dealii::AffineConstraints<double> &constraints) const override;

    // A rational Bezier cell (VTK_BEZIER_QUADRILATERAL): the Bezier
    // extraction of the element's homogeneous control net gives the
    // weights; values_to_nodes inverts the rational Bernstein collocation
    // at the node points. Cached per element at the first call.
    HigherOrderCell
    higher_order_cell(const cell_iterator &cell) const override;

    // The patches with their global control point numbering.
    const nurbs::MultiPatch<dim> &
    patches() const
    {
      return *shared_patches;
    }

  private:
    // Patches glued into a MultiPatch and the boundary id of each of their
    // sides (numbers::internal_face_boundary_id on interfaces).
    struct PatchSet
    {
      std::shared_ptr<const nurbs::MultiPatch<dim>>                patches;
      std::vector<std::array<dealii::types::boundary_id, 2 * dim>> side_ids;
    };

    explicit DiscretizationIGA(const PatchSet &patch_set);

    static PatchSet
    make_patches(const BodyGeometry &geometry, const unsigned int degree);

    static PatchSet
    make_patches(const nurbs::PatchGeometry<dim> &patch_geometry);

    // One segment per knot span of a boundary side: the span's control
    // points as nodes, its Bezier extraction rows as Bernstein coefficients.
    std::vector<BoundarySegment<dim>>
    unmarked_boundary_segments(
      const dealii::types::boundary_id boundary_id) const override;

    void
    make_mesh();

    // The unknown of dim * (global control point) + component: the same
    // until renumber_unknowns().
    dealii::types::global_dof_index
    unknown(const dealii::types::global_dof_index control_point_component) const
    {
      return renumbered.empty() ? control_point_component :
                                  renumbered[control_point_component];
    }
    void
    renumber_own_indices(
      const std::vector<dealii::types::global_dof_index> &new_numbers) override;

    std::vector<dealii::types::global_dof_index> renumbered;
    mutable std::vector<HigherOrderCell>         bezier_cells;

    // Shared with FE_NURBS and MappingNURBS.
    std::shared_ptr<const nurbs::MultiPatch<dim>>                shared_patches;
    std::vector<std::array<dealii::types::boundary_id, 2 * dim>> side_ids;
  };
} // namespace isoimpact

#endif
