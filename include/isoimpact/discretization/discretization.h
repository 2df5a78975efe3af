// Layer 3: discretisation. One interface that gives classical FEA (FE_Q on a
// deal.II mesh) and IGA (FE_NURBS on a NURBS patch) the same assembly,
// lumping, contact and output. Code above this layer never asks which one it
// has.
#ifndef isoimpact_discretization_h
#define isoimpact_discretization_h

#include <deal.II/base/point.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/base/types.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <isoimpact/nurbs/enum_names.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace isoimpact
{

  /**
   * One face of a body's boundary, seen as a curve x(eta), eta in [0,1], in
   * a form that holds for Lagrange and NURBS elements alike:
   *   N_k(eta) = sum_j bernstein_coefficients(k, j) B_j^p(eta),
   *   R_k(eta) = w_k N_k(eta) / sum_l w_l N_l(eta),
   *   x(eta)   = sum_k R_k(eta) (X_k + u_k).
   * For FE_Q the nodes are the face's support points (w = 1); for NURBS the
   * control points of the boundary knot span.
   */
  template <int dim>
  struct BoundarySegment
  {
    unsigned int degree = 0;
    // Per node: the unknown (global index) of each displacement component.
    std::vector<std::array<dealii::types::global_dof_index, dim>> node_dofs;
    // Per node: reference position X_k and weight w_k.
    std::vector<dealii::Point<dim>> node_positions;
    std::vector<double>             node_weights;
    // n_nodes x (degree + 1).
    dealii::FullMatrix<double> bernstein_coefficients;
    // +1 or -1: multiplies the tangent rotated by -90 degrees to give the
    // outward normal of the body.
    double normal_orientation = 1.;
    // Whether the end at eta = 0 (resp. 1) is an end of the whole boundary
    // (no neighbouring segment): a projection beyond it finds no contact.
    std::array<bool, 2> free_end = {{true, true}};
  };

  /**
   * Values R_k(eta) and derivatives dR_k/deta of the nodal functions of a
   * segment (both vectors are resized to the number of nodes).
   */
  template <int dim>
  void
  evaluate_segment_basis(const BoundarySegment<dim> &segment,
                         const double                eta,
                         std::vector<double>        &values,
                         std::vector<double>        &derivatives);

  /**
   * Sets BoundarySegment::free_end by matching the end points of the
   * segments (in the reference configuration). An end that meets an end of
   * a `continuation` segment is not free either: pass the segments of the
   * symmetry cut, where the surface goes on in its mirror image, so that a
   * projection beyond that end is clamped to it instead of dropped.
   */
  template <int dim>
  void
  mark_free_segment_ends(
    std::vector<BoundarySegment<dim>>       &segments,
    const std::vector<BoundarySegment<dim>> &continuation = {});

  /**
   * Sets segment.normal_orientation so that the tangent at the middle of the
   * segment (eta = 1/2), rotated by -90 degrees, points along
   * `outward_normal` there.
   */
  template <int dim>
  void
  orient_segment(BoundarySegment<dim>         &segment,
                 const dealii::Tensor<1, dim> &outward_normal);

  /**
   * Bernstein coefficients of nodal functions from their values at the
   * degree + 1 points eta_j = j / degree: row k of the result holds the
   * coefficients of the function whose values are row k of `values`.
   */
  dealii::FullMatrix<double>
  bernstein_coefficients_from_values(const dealii::FullMatrix<double> &values);

  /**
   * Shape of a body, understood by every discretisation. Boundary ids:
   * `curved_boundary_id` for the circular arc (the contact candidate),
   * `symmetry_boundary_id` for the cut of a half disk.
   */
  struct BodyGeometry
  {
    enum class Shape
    {
      half_disk,
      full_disk,
      rectangle
    };
    Shape            shape  = Shape::half_disk;
    dealii::Point<2> center = dealii::Point<2>(0., 4.);
    double           radius = 4.;
    dealii::Point<2> lower_left, upper_right; // for rectangles
    // Refinement: global levels, then local levels near `refinement_center`
    // within `refinement_radius` (FEA: cells; IGA: graded knots).
    unsigned int     global_refinements = 3;
    unsigned int     local_refinements  = 0;
    dealii::Point<2> refinement_center;
    double           refinement_radius = 0.;

    static constexpr dealii::types::boundary_id curved_boundary_id   = 0;
    static constexpr dealii::types::boundary_id symmetry_boundary_id = 1;
  };

  /**
   * The interface of layer 3. A discretisation owns a mesh, a vector-valued
   * finite element, a mapping and a DoFHandler usable with FEValues and
   * DataOut, and a numbering of the unknowns (displacement coefficients) that
   * may differ from the DoFHandler's (for splines, control points).
   */
  template <int dim>
  class Discretization
  {
  public:
    using cell_iterator =
      typename dealii::DoFHandler<dim>::active_cell_iterator;

    virtual ~Discretization() = default;

    virtual std::string
    name() const = 0;

    virtual const dealii::Triangulation<dim> &
    get_triangulation() const = 0;

    virtual const dealii::Mapping<dim> &
    get_mapping() const = 0;

    // The vector-valued element (dim displacement components).
    virtual const dealii::FiniteElement<dim> &
    get_fe() const = 0;

    virtual const dealii::DoFHandler<dim> &
    get_dof_handler() const = 0;

    // A Gauss rule that integrates the mass matrix of an affine cell exactly.
    virtual const dealii::Quadrature<dim> &
    get_cell_quadrature() const = 0;

    // Number of unknowns of the assembled system.
    virtual dealii::types::global_dof_index
    n_dofs() const = 0;

    // The unknowns of the cell's shape functions, in the element's order.
    virtual void
    get_dof_indices(
      const cell_iterator                          &cell,
      std::vector<dealii::types::global_dof_index> &indices) const = 0;

    // Component (0..dim-1) of each unknown.
    virtual unsigned int
    dof_component(const dealii::types::global_dof_index dof) const = 0;

    // Reference position of each unknown's node (support or control point).
    virtual dealii::Point<dim>
    dof_position(const dealii::types::global_dof_index dof) const = 0;

    // Constraints the discretisation itself needs (hanging nodes), closed
    // by the caller after adding its own.
    virtual void
    make_constraints(dealii::AffineConstraints<double> &constraints) const = 0;

    // u_component = 0 on the boundary with the given id (roller condition
    // on a straight symmetry line aligned with a coordinate axis).
    virtual void
    constrain_component_on_boundary(
      const dealii::types::boundary_id   boundary_id,
      const unsigned int                 component,
      dealii::AffineConstraints<double> &constraints) const = 0;

    // The faces of a boundary as curves (in no particular order; free_end
    // tells the ends of the boundary).
    virtual std::vector<BoundarySegment<dim>>
    boundary_segments(const dealii::types::boundary_id boundary_id) const = 0;

    // Turns a vector of unknowns into a vector on the DoFHandler, for
    // DataOut and for evaluation with FEValues.
    virtual void
    to_dof_handler_vector(const dealii::Vector<double> &unknowns,
                          dealii::Vector<double> &dof_handler_vector) const = 0;
  };

  /**
   * The last step of every Discretization::boundary_segments(): marks the
   * free ends of the segments of `boundary_id`, taking the symmetry cut
   * (BodyGeometry::symmetry_boundary_id) as the continuation of every other
   * boundary (mark_free_segment_ends()).
   */
  template <int dim>
  void
  mark_free_segment_ends(const Discretization<dim>         &discretization,
                         const dealii::types::boundary_id   boundary_id,
                         std::vector<BoundarySegment<dim>> &segments);

  /**
   * The coarse mesh of a body, where FEA and IGA both start: half disk =
   * GridGenerator::half_hyper_ball (4 cells), full disk = hyper_ball (5
   * cells), rectangle = one cell. Boundary ids: curved_boundary_id on arcs,
   * symmetry_boundary_id on the cut of the half disk, rectangle 0, 1, 2, 3
   * = left, right, bottom, top. No manifold is attached.
   */
  void
  make_coarse_mesh(const BodyGeometry       &geometry,
                   dealii::Triangulation<2> &mesh);

  /**
   * The scalar element of an FEA discretisation: `lagrange` is FE_Q(p) (the
   * 9-node Q9 for p = 2), `serendipity` the 8-node quadratic serendipity
   * element FE_Serendipity (Q8, p = 2 only).
   */
  enum class FEAElement
  {
    lagrange,
    serendipity
  };

  // "lagrange" or "serendipity".
  inline constexpr EnumNames<FEAElement, 2> fea_element_names{
    "FEA element",
    {{{FEAElement::lagrange, "lagrange"},
      {FEAElement::serendipity, "serendipity"}}}};

  inline std::string
  to_string(const FEAElement element)
  {
    return fea_element_names.to_string(element);
  }

  /**
   * The factory of layer 3: `kind` is "fea" (FE_Q of the given degree, or
   * with `fea_element` = serendipity the Q8 element, with MappingQ on exact
   * manifolds) or "iga" (NURBS of the given degree; `fea_element` must then
   * be lagrange, the default).
   */
  template <int dim>
  std::unique_ptr<Discretization<dim>>
  create_discretization(const std::string  &kind,
                        const BodyGeometry &geometry,
                        const unsigned int  degree,
                        const FEAElement    fea_element = FEAElement::lagrange);
} // namespace isoimpact

#endif
