// Layer 3: boundary segments, the one form in which FEA and IGA hand a body's
// boundary to contact: curves x(eta) of rational Bernstein-based nodal
// functions.
#ifndef isoimpact_boundary_segments_h
#define isoimpact_boundary_segments_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>

#include <deal.II/lac/full_matrix.h>

#include <array>
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
   * segment (both vectors are resized to the number of nodes). The
   * Bernstein polynomials come from nurbs::KnotVector::bernstein_values().
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
} // namespace isoimpact

#endif
