// A single NURBS patch: tensor-product knot vectors, control points and
// weights; evaluation, rational basis per element, refinement (layer 1).
#ifndef isoimpact_nurbs_patch_h
#define isoimpact_nurbs_patch_h

#include <deal.II/base/derivative_form.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <deal.II/lac/full_matrix.h>

#include <isoimpact/nurbs/knot_vector.h>

#include <array>
#include <utility>
#include <vector>

namespace isoimpact
{
  namespace nurbs
  {
    /**
     * A NURBS patch X(xi) = sum_a R_a(xi) P_a, R_a = w_a N_a / sum_b w_b N_b,
     * with tensor-product B-splines N_a over the knot vectors of the dim
     * parametric directions.
     *
     * Numbering conventions (all lexicographic, first direction fastest):
     * - control point a = i_0 + n_0 (i_1 + n_1 i_2), n_d =
     *   knot_vector(d).n_basis_functions();
     * - element (non-empty knot span box) e = s_0 + m_0 (s_1 + m_1 s_2), m_d =
     *   knot_vector(d).n_spans();
     * - local functions of an element a_loc = l_0 + (p_0+1)(l_1 + (p_1+1) l_2),
     *   global index (first_basis_function(s_d) + l_d) per direction;
     * - patch sides (faces) f = 2 d + s: side s (0: xi_d = lower end, 1: xi_d
     *   = upper end) of direction d, as deal.II numbers the faces of the unit
     *   cell.
     *
     * Refinement functions modify the patch in place and leave the geometry
     * (the map X) unchanged; they act on homogeneous coordinates (w P, w).
     */
    template <int dim, int spacedim = dim>
    class NURBSPatch
    {
    public:
      NURBSPatch() = default;

      /**
       * Checks that control_points.size() == weights.size() == product of the
       * n_basis_functions() of the knot vectors, and that the weights are
       * positive and finite and the control points finite.
       */
      NURBSPatch(const std::array<KnotVector, dim>          &knot_vectors,
                 const std::vector<dealii::Point<spacedim>> &control_points,
                 const std::vector<double>                  &weights);

      // B-spline patch: all weights 1.
      NURBSPatch(const std::array<KnotVector, dim>          &knot_vectors,
                 const std::vector<dealii::Point<spacedim>> &control_points);

      const std::array<KnotVector, dim> &
      knot_vectors() const
      {
        return knots;
      }

      const KnotVector &
      knot_vector(const unsigned int direction) const
      {
        return knots[direction];
      }

      unsigned int
      degree(const unsigned int direction) const
      {
        return knots[direction].degree();
      }

      const std::vector<dealii::Point<spacedim>> &
      control_points() const
      {
        return points;
      }

      const std::vector<double> &
      weights() const
      {
        return point_weights;
      }

      unsigned int
      n_control_points() const
      {
        return points.size();
      }

      // Control point (multi-index) <-> linear index.
      unsigned int
      control_point_index(
        const std::array<unsigned int, dim> &multi_index) const;

      std::array<unsigned int, dim>
      control_point_multi_index(const unsigned int index) const;

      /**
       * Global indices of the control points on patch side `face` (= 2
       * direction + side), in lexicographic order of the remaining
       * directions.
       */
      std::vector<unsigned int>
      side_control_points(const unsigned int face) const;

      unsigned int
      n_elements() const;

      std::array<unsigned int, dim>
      n_elements_per_direction() const;

      std::array<unsigned int, dim>
      element_multi_index(const unsigned int element) const;

      unsigned int
      element_index(const std::array<unsigned int, dim> &multi_index) const;

      // Lower and upper corner of the element's knot span box.
      std::pair<dealii::Point<dim>, dealii::Point<dim>>
      element_parameter_box(const unsigned int element) const;

      // Element containing the parameter point (upper ends belong to the last
      // span of each direction).
      unsigned int
      element_containing(const dealii::Point<dim> &parameter) const;

      // prod_d (p_d + 1): functions non-zero on one element.
      unsigned int
      n_functions_per_element() const;

      /**
       * Global indices of the control points whose functions are non-zero
       * on the element, in local lexicographic order (first direction
       * fastest).
       */
      std::vector<unsigned int>
      element_control_points(const unsigned int element) const;

      void
      element_control_points(const unsigned int         element,
                             std::vector<unsigned int> &indices) const;

      // X(xi) for a parameter point in the knot-vector box.
      dealii::Point<spacedim>
      evaluate(const dealii::Point<dim> &parameter) const;

      // dX_i / dxi_j at a parameter point.
      dealii::DerivativeForm<1, dim, spacedim>
      jacobian(const dealii::Point<dim> &parameter) const;

      /**
       * The rational basis functions non-zero on `element` at a point of the
       * element's reference cell [0,1]^dim (parameter xi_d = lower_d +
       * reference_d * (upper_d - lower_d)): values[a] = R_a and
       * gradients[a][d] = dR_a / dreference_d, a local as in
       * element_control_points(). The vectors are resized only if their size
       * differs from n_functions_per_element(); no other allocation.
       */
      void
      element_rational_basis(
        const unsigned int                   element,
        const dealii::Point<dim>            &reference_point,
        std::vector<double>                 &values,
        std::vector<dealii::Tensor<1, dim>> &gradients) const;

      /**
       * The same at several points of the element's reference cell:
       * values[q * n + a] and gradients[q * n + a] at reference_points[q], n
       * = n_functions_per_element(), each with the bits of the one-point
       * version. The B-splines of a direction are evaluated once per distinct
       * coordinate (a tensor-product rule of m^dim points needs m per
       * direction).
       */
      void
      element_rational_basis(
        const unsigned int                     element,
        const std::vector<dealii::Point<dim>> &reference_points,
        std::vector<double>                   &values,
        std::vector<dealii::Tensor<1, dim>>   &gradients) const;

      /**
       * Bezier extraction operator of the element: the Kronecker product of
       * the directions' 1D operators, C(a, b) = prod_d C_d(l_d, k_d) with a,b
       * local lexicographic indices, so that N_a = sum_b C(a,b) B_b with the
       * tensor-product Bernstein polynomials B_b of the reference cell.
       * Computes the 1D operators of the whole patch on each call: cache the
       * result when it is needed repeatedly.
       */
      dealii::FullMatrix<double>
      element_extraction_operator(const unsigned int element) const;

      // h-refinement: inserts the given knot values in one direction.
      void
      insert_knots(const unsigned int         direction,
                   const std::vector<double> &new_knots);

      // Splits every span of `direction` into n_subdivisions equal parts.
      void
      refine_uniformly(const unsigned int direction,
                       const unsigned int n_subdivisions);

      // Same in all directions.
      void
      refine_uniformly(const unsigned int n_subdivisions);

      // p-refinement: raises the degree in `direction` by `times`, keeping
      // the continuity across existing knots.
      void
      elevate_degree(const unsigned int direction, const unsigned int times);

      /**
       * k-refinement: first elevates the degree by `times`, then splits each
       * span into n_subdivisions parts, so the new knots have maximal
       * continuity C^{p+times-1}. Directions: one, or all (the second form).
       */
      void
      k_refine(const unsigned int direction,
               const unsigned int times,
               const unsigned int n_subdivisions);

      void
      k_refine(const unsigned int times, const unsigned int n_subdivisions);

      /**
       * Graded refinement toward one end of `direction` (side 0: lower end,
       * 1: upper end): the span touching that end is split into n_layers + 1
       * spans whose lengths grow by the factor `ratio` (> 0) away from the
       * end; ratio 1 is a uniform split, ratio 2 halves the span touching the
       * end at every layer. Repeated calls keep grading toward the end.
       */
      void
      refine_graded(const unsigned int direction,
                    const unsigned int side,
                    const unsigned int n_layers,
                    const double       ratio);

    private:
      std::array<KnotVector, dim>          knots;
      std::vector<dealii::Point<spacedim>> points;
      std::vector<double>                  point_weights;

      void
      check() const;

      // Homogeneous control net in rows along `direction`: row i_d holds the
      // (w P, w) of all control points with that index.
      std::vector<double>
      homogeneous_rows(const unsigned int direction) const;

      void
      set_from_homogeneous_rows(const unsigned int         direction,
                                const std::vector<double> &rows,
                                const KnotVector          &new_knot_vector);
    };
  } // namespace nurbs
} // namespace isoimpact

#endif
