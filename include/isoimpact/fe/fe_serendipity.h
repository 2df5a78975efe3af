// Layer 2: the quadratic 8-node serendipity quadrilateral (Q8) as a deal.II
// finite element.
#ifndef isoimpact_fe_serendipity_h
#define isoimpact_fe_serendipity_h

#include <deal.II/base/scalar_polynomials_base.h>
#include <deal.II/lac/full_matrix.h>

#include <deal.II/fe/fe_poly.h>

#include <memory>
#include <string>
#include <vector>

namespace isoimpact
{

  /**
   * The quadratic serendipity space on the unit square,
   *   span{1, x, y, x^2, xy, y^2, x^2 y, x y^2},
   * in its nodal basis: function i is 1 at node i and 0 at the seven others,
   * the nodes in deal.II's order of the degrees of freedom of a quadrilateral
   * with one dof per vertex and per line:
   *   0: (0,0), 1: (1,0), 2: (0,1), 3: (1,1)          (vertices),
   *   4: (0,1/2), 5: (1,1/2), 6: (1/2,0), 7: (1/2,1)  (midpoints of lines
   *                                                    0..3: x=0, x=1, y=0,
   *                                                    y=1).
   * The functions are stored as coefficients of the eight monomials, so
   * derivatives of every order are exact. Only dim = 2.
   */
  template <int dim>
  class SerendipityPolynomials : public dealii::ScalarPolynomialsBase<dim>
  {
    static_assert(dim == 2, "serendipity polynomials: only dim = 2");

  public:
    SerendipityPolynomials();

    // Node i of the basis (see above).
    static dealii::Point<dim>
    node(const unsigned int i);

    void
    evaluate(
      const dealii::Point<dim>            &unit_point,
      std::vector<double>                 &values,
      std::vector<dealii::Tensor<1, dim>> &grads,
      std::vector<dealii::Tensor<2, dim>> &grad_grads,
      std::vector<dealii::Tensor<3, dim>> &third_derivatives,
      std::vector<dealii::Tensor<4, dim>> &fourth_derivatives) const override;

    double
    compute_value(const unsigned int        i,
                  const dealii::Point<dim> &p) const override;

    dealii::Tensor<1, dim>
    compute_1st_derivative(const unsigned int        i,
                           const dealii::Point<dim> &p) const override;
    dealii::Tensor<2, dim>
    compute_2nd_derivative(const unsigned int        i,
                           const dealii::Point<dim> &p) const override;
    dealii::Tensor<3, dim>
    compute_3rd_derivative(const unsigned int        i,
                           const dealii::Point<dim> &p) const override;
    dealii::Tensor<4, dim>
    compute_4th_derivative(const unsigned int        i,
                           const dealii::Point<dim> &p) const override;
    dealii::Tensor<1, dim>
    compute_grad(const unsigned int        i,
                 const dealii::Point<dim> &p) const override;
    dealii::Tensor<2, dim>
    compute_grad_grad(const unsigned int        i,
                      const dealii::Point<dim> &p) const override;

    std::unique_ptr<dealii::ScalarPolynomialsBase<dim>>
    clone() const override;

    std::string
    name() const override;

  private:
    // d^(ax + ay) phi_i / dx^ax dy^ay at p.
    double
    derivative(const unsigned int        i,
               const unsigned int        ax,
               const unsigned int        ay,
               const dealii::Point<dim> &p) const;

    template <int order>
    dealii::Tensor<order, dim>
    derivative_tensor(const unsigned int i, const dealii::Point<dim> &p) const;

    // coefficients(m, i): coefficient of monomial m in function i.
    dealii::FullMatrix<double> coefficients;
  };



  /**
   * The 8-node serendipity quadrilateral Q8 (degree 2): one dof per vertex
   * and one per line, none in the interior, nodal at the vertices and the
   * midpoints of the lines (SerendipityPolynomials). Its trace on a line is
   * the quadratic Lagrange polynomial of the two vertices and the midpoint,
   * as for FE_Q(2), so it is H1-conforming with itself and with FE_Q(2)
   * across faces, and its hanging-node (interface) constraints are those of
   * FE_Q(2). Usable with FEValues, FEFaceValues, FESystem, DataOut,
   * DoFTools::map_dofs_to_support_points,
   * DoFTools::make_hanging_node_constraints and VectorTools::interpolate.
   * Prolongation matrices for isotropic refinement are provided (the space
   * is invariant under the affine maps to the children); restriction
   * matrices are not.
   */
  template <int dim>
  class FE_Serendipity : public dealii::FE_Poly<dim>
  {
    static_assert(dim == 2, "FE_Serendipity: only dim = 2");

  public:
    // Only degree 2 exists; any other degree throws.
    explicit FE_Serendipity(const unsigned int degree = 2);

    // "FE_Serendipity<2>(2)".
    std::string
    get_name() const override;

    std::unique_ptr<dealii::FiniteElement<dim>>
    clone() const override;

    bool
    has_support_on_face(const unsigned int shape_index,
                        const unsigned int face_index) const override;

    // Nodal values: dof i is the value at support point i.
    void
    convert_generalized_support_point_values_to_dof_values(
      const std::vector<dealii::Vector<double>> &support_point_values,
      std::vector<double>                       &nodal_values) const override;
  };
} // namespace isoimpact

#endif
