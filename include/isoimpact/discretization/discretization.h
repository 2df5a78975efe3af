// Layer 3: discretisation. One interface that gives classical FEA (FE_Q on a
// deal.II mesh) and IGA (FE_NURBS on a NURBS patch) the same assembly,
// lumping, contact and output. Code above this layer never asks which one it
// has.
#ifndef isoimpact_discretization_h
#define isoimpact_discretization_h

#include <deal.II/base/point.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/types.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <isoimpact/discretization/boundary_segments.h>

#include <isoimpact/nurbs/enum_names.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace isoimpact
{
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
   * One cell as one higher-order VTK cell that carries the exact geometry
   * and fields of the discretisation: VTK_LAGRANGE_QUADRILATERAL (70) for
   * FE_Q and Q8 (a Q8 field is biquadratic too), VTK_BEZIER_QUADRILATERAL
   * (77) with rational weights for NURBS. The nodes are the sample points
   * vtk_node_points(degree) of the reference cell; the coefficient of node
   * j is sum_k values_to_nodes(j, k) f(x_k) for a field f in the cell's
   * space (exact, by interpolation).
   */
  struct HigherOrderCell
  {
    static constexpr unsigned int lagrange_quadrilateral = 70;
    static constexpr unsigned int bezier_quadrilateral   = 77;

    unsigned int vtk_type = lagrange_quadrilateral;
    unsigned int degree   = 1;
    // Rational weights of the nodes (all 1 for Lagrange cells).
    std::vector<double> weights;
    // Empty: the identity (the node values are the coefficients).
    dealii::FullMatrix<double> values_to_nodes;
  };

  // The points (i/p, j/p) of the unit square in VTK's node order of a
  // higher-order quadrilateral of degree p: corners, edges (each in the
  // direction of increasing parameter), then the interior, i fastest.
  std::vector<dealii::Point<2>>
  vtk_node_points(const unsigned int degree);

  /**
   * The interface of layer 3 and what FEA and IGA share. A discretisation
   * owns a mesh, a vector-valued finite element, a mapping and a DoFHandler
   * usable with FEValues and DataOut, and a numbering of the unknowns
   * (displacement coefficients) that may differ from the DoFHandler's (for
   * splines, control points).
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

    const dealii::Triangulation<dim> &
    triangulation() const
    {
      return mesh;
    }

    const dealii::Mapping<dim> &
    mapping() const
    {
      return *cell_mapping;
    }

    // Gives up the unknowns' numbering on the cells (the DoFHandler's
    // storage) and the support points cached by cache_mapping() (the
    // mapping then evaluates the same geometry on each use), for a process that
    // holds none of this body's cells and reads only its contact surface. The
    // mesh, the unknowns' positions and components stay; code that reads the
    // unknowns of cells must then skip the body (holds_cell_unknowns()).
    void
    release_cell_unknowns();

    bool
    holds_cell_unknowns() const
    {
      return dofs.has_active_dofs();
    }

    // The vector-valued element (dim displacement components).
    const dealii::FiniteElement<dim> &
    fe() const
    {
      return vector_fe;
    }

    const dealii::DoFHandler<dim> &
    dof_handler() const
    {
      return dofs;
    }

    // A Gauss rule that integrates the mass matrix of an affine cell exactly.
    const dealii::Quadrature<dim> &
    cell_quadrature() const
    {
      return gauss_quadrature;
    }

    // Number of unknowns of the assembled system.
    dealii::types::global_dof_index
    n_dofs() const
    {
      return unknown_positions.size();
    }

    // The unknowns of the cell's shape functions, in the element's order.
    virtual void
    get_dof_indices(
      const cell_iterator                          &cell,
      std::vector<dealii::types::global_dof_index> &indices) const = 0;

    // Component (0..dim-1) of each unknown.
    unsigned int
    dof_component(const dealii::types::global_dof_index dof) const
    {
      return unknown_components[dof];
    }

    // Reference position of each unknown's node (support or control point).
    dealii::Point<dim>
    dof_position(const dealii::types::global_dof_index dof) const
    {
      return unknown_positions[dof];
    }

    // Constraints the discretisation itself needs (hanging nodes), closed
    // by the caller after adding its own. None unless overridden.
    virtual void
    make_constraints(dealii::AffineConstraints<double> &constraints) const;

    // u_component = 0 on the boundary with the given id (roller condition
    // on a straight symmetry line aligned with a coordinate axis).
    virtual void
    constrain_component_on_boundary(
      const dealii::types::boundary_id   boundary_id,
      const unsigned int                 component,
      dealii::AffineConstraints<double> &constraints) const = 0;

    // The faces of a boundary as curves (in no particular order). Their
    // free ends are marked with the symmetry cut
    // (BodyGeometry::symmetry_boundary_id) as the continuation of every
    // other boundary (mark_free_segment_ends()).
    std::vector<BoundarySegment<dim>>
    boundary_segments(const dealii::types::boundary_id boundary_id) const;

    // The cell as a higher-order VTK cell. Default: a Lagrange cell of the
    // element's degree (FEA).
    virtual HigherOrderCell
    higher_order_cell(const cell_iterator &cell) const;

    /**
     * Renumbers the unknowns: unknown i becomes new_numbers[i] (a
     * permutation) in every index the discretisation gives from then on
     * (cells, constraints, boundary segments, positions, output). For
     * several MPI ranks (UnknownPartition::part_major_numbering()); the
     * serial program keeps the discretisation's own numbering.
     */
    void
    renumber_unknowns(
      const std::vector<dealii::types::global_dof_index> &new_numbers);

    // Turns a vector of unknowns into a vector on the DoFHandler, for
    // DataOut and for evaluation with FEValues.
    void
    to_dof_handler_vector(const dealii::Vector<double> &unknowns,
                          dealii::Vector<double> &dof_handler_vector) const;

  protected:
    // The element is FESystem(scalar_fe, dim), the cell quadrature
    // QGauss(n_gauss_points).
    Discretization(const dealii::FiniteElement<dim>           &scalar_fe,
                   std::unique_ptr<const dealii::Mapping<dim>> mapping,
                   const unsigned int                          n_gauss_points);

    // The segments of boundary_segments(), free ends not yet marked.
    virtual std::vector<BoundarySegment<dim>>
    unmarked_boundary_segments(
      const dealii::types::boundary_id boundary_id) const = 0;

    // The derived class's part of renumber_unknowns() (positions and
    // components are permuted by the base class).
    virtual void
    renumber_own_indices(
      const std::vector<dealii::types::global_dof_index> &new_numbers) = 0;

    // Stores the reference position and the component of every unknown;
    // their number is n_dofs(). Called once the unknowns are numbered.
    void
    set_unknowns(std::vector<dealii::Point<dim>> positions,
                 std::vector<unsigned char>      components);

    // Replaces the mapping by MappingQCache(degree) of its support points
    // on the final mesh: the same geometry, without the manifold
    // evaluations of every FEValues::reinit (the ParaView output samples
    // every cell at each write). Called once the mesh is final.
    void
    cache_mapping(const unsigned int degree);

    // Built by the constructors of the derived classes.
    dealii::Triangulation<dim> mesh;
    dealii::DoFHandler<dim>    dofs;

  private:
    const dealii::FESystem<dim>                 vector_fe;
    std::unique_ptr<const dealii::Mapping<dim>> cell_mapping;
    // The mapping cache_mapping() cached (else null).
    std::unique_ptr<const dealii::Mapping<dim>> uncached_mapping;
    const dealii::QGauss<dim>                   gauss_quadrature;
    std::vector<dealii::Point<dim>>             unknown_positions;
    std::vector<unsigned char>                  unknown_components;
  };

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
   * The method of a discretisation: `fea` is classical FEA (FE_Q, or the Q8
   * element, with MappingQ on exact manifolds), `iga` isogeometric analysis
   * (NURBS patches glued C0).
   */
  enum class DiscretizationMethod
  {
    fea,
    iga
  };

  // "fea" or "iga".
  inline constexpr EnumNames<DiscretizationMethod, 2>
    discretization_method_names{"discretisation method",
                                {{{DiscretizationMethod::fea, "fea"},
                                  {DiscretizationMethod::iga, "iga"}}}};

  inline std::string
  to_string(const DiscretizationMethod method)
  {
    return discretization_method_names.to_string(method);
  }

  /**
   * The factory of layer 3, the one place that chooses the method: FEA with
   * FE_Q of the given degree (or with `fea_element` = serendipity the Q8
   * element) or IGA with NURBS of the given degree (`fea_element` must then
   * be lagrange, the default).
   */
  template <int dim>
  std::unique_ptr<Discretization<dim>>
  create_discretization(const DiscretizationMethod method,
                        const BodyGeometry        &geometry,
                        const unsigned int         degree,
                        const FEAElement fea_element = FEAElement::lagrange);
} // namespace isoimpact

#endif
