// Layer 2: the 8-node serendipity quadrilateral (Q8).
#include <deal.II/base/exceptions.h>
#include <deal.II/base/geometry_info.h>

#include <deal.II/fe/fe_poly.h>

#include <deal.II/lac/vector.h>

#include <isoimpact/fe/fe_serendipity.h>

#include <array>
#include <cmath>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    constexpr unsigned int n_functions = 8;

    // Exponents (x, y) of the monomials spanning the serendipity space.
    constexpr std::array<std::array<unsigned int, 2>, n_functions> exponents = {
      {{{0, 0}},
       {{1, 0}},
       {{0, 1}},
       {{2, 0}},
       {{1, 1}},
       {{0, 2}},
       {{2, 1}},
       {{1, 2}}}};

    // d^k x^a / dx^k.
    double
    monomial_derivative(const unsigned int a,
                        const unsigned int k,
                        const double       x)
    {
      if (k > a)
        return 0.;
      double factor = 1.;
      for (unsigned int j = 0; j < k; ++j)
        factor *= a - j;
      return factor * std::pow(x, static_cast<int>(a - k));
    }

    unsigned int
    checked_degree(const unsigned int degree)
    {
      AssertThrow(degree == 2,
                  ExcMessage("FE_Serendipity: degree " +
                             std::to_string(degree) +
                             " is not available; only the quadratic 8-node "
                             "serendipity element (degree 2) is implemented"));
      return degree;
    }

    template <int dim>
    FiniteElementData<dim>
    make_fe_data(const unsigned int degree)
    {
      // One dof per vertex and per line, none inside.
      return FiniteElementData<dim>(std::vector<unsigned int>{1, 1, 0},
                                    1,
                                    checked_degree(degree),
                                    FiniteElementData<dim>::H1);
    }
  } // namespace



  template <int dim>
  Point<dim>
  SerendipityPolynomials<dim>::node(const unsigned int i)
  {
    AssertIndexRange(i, n_functions);
    static const std::array<Point<dim>, n_functions> nodes = {
      {Point<dim>(0., 0.),
       Point<dim>(1., 0.),
       Point<dim>(0., 1.),
       Point<dim>(1., 1.),
       Point<dim>(0., 0.5),
       Point<dim>(1., 0.5),
       Point<dim>(0.5, 0.),
       Point<dim>(0.5, 1.)}};
    return nodes[i];
  }



  template <int dim>
  SerendipityPolynomials<dim>::SerendipityPolynomials()
    : ScalarPolynomialsBase<dim>(2, n_functions)
    , coefficients(n_functions, n_functions)
  {
    // Vandermonde matrix V(k, m) = monomial m at node k; the nodal basis has
    // the coefficient matrix V^{-1} (column i: function i).
    for (unsigned int k = 0; k < n_functions; ++k)
      for (unsigned int m = 0; m < n_functions; ++m)
        coefficients(k, m) =
          monomial_derivative(exponents[m][0], 0, node(k)[0]) *
          monomial_derivative(exponents[m][1], 0, node(k)[1]);
    coefficients.gauss_jordan();
  }



  template <int dim>
  double
  SerendipityPolynomials<dim>::derivative(const unsigned int i,
                                          const unsigned int ax,
                                          const unsigned int ay,
                                          const Point<dim>  &p) const
  {
    AssertIndexRange(i, n_functions);
    double result = 0.;
    for (unsigned int m = 0; m < n_functions; ++m)
      result += coefficients(m, i) *
                monomial_derivative(exponents[m][0], ax, p[0]) *
                monomial_derivative(exponents[m][1], ay, p[1]);
    return result;
  }



  template <int dim>
  template <int order>
  Tensor<order, dim>
  SerendipityPolynomials<dim>::derivative_tensor(const unsigned int i,
                                                 const Point<dim>  &p) const
  {
    Tensor<order, dim> result;
    // Entry (d_1, ..., d_order) is the derivative with ay = number of d_j
    // equal to 1; run over all 2^order multi-indices as bit patterns.
    for (unsigned int bits = 0; bits < (1u << order); ++bits)
      {
        TableIndices<order> index;
        unsigned int        ay = 0;
        for (unsigned int j = 0; j < order; ++j)
          {
            index[j] = (bits >> j) & 1u;
            ay += index[j];
          }
        result[index] = derivative(i, order - ay, ay, p);
      }
    return result;
  }



  template <int dim>
  void
  SerendipityPolynomials<dim>::evaluate(
    const Point<dim>            &unit_point,
    std::vector<double>         &values,
    std::vector<Tensor<1, dim>> &grads,
    std::vector<Tensor<2, dim>> &grad_grads,
    std::vector<Tensor<3, dim>> &third_derivatives,
    std::vector<Tensor<4, dim>> &fourth_derivatives) const
  {
    Assert(values.size() == n_functions || values.size() == 0,
           ExcDimensionMismatch2(values.size(), n_functions, 0));
    Assert(grads.size() == n_functions || grads.size() == 0,
           ExcDimensionMismatch2(grads.size(), n_functions, 0));
    Assert(grad_grads.size() == n_functions || grad_grads.size() == 0,
           ExcDimensionMismatch2(grad_grads.size(), n_functions, 0));
    Assert(third_derivatives.size() == n_functions ||
             third_derivatives.size() == 0,
           ExcDimensionMismatch2(third_derivatives.size(), n_functions, 0));
    Assert(fourth_derivatives.size() == n_functions ||
             fourth_derivatives.size() == 0,
           ExcDimensionMismatch2(fourth_derivatives.size(), n_functions, 0));
    for (unsigned int i = 0; i < values.size(); ++i)
      values[i] = compute_value(i, unit_point);
    for (unsigned int i = 0; i < grads.size(); ++i)
      grads[i] = derivative_tensor<1>(i, unit_point);
    for (unsigned int i = 0; i < grad_grads.size(); ++i)
      grad_grads[i] = derivative_tensor<2>(i, unit_point);
    for (unsigned int i = 0; i < third_derivatives.size(); ++i)
      third_derivatives[i] = derivative_tensor<3>(i, unit_point);
    for (unsigned int i = 0; i < fourth_derivatives.size(); ++i)
      fourth_derivatives[i] = derivative_tensor<4>(i, unit_point);
  }



  template <int dim>
  double
  SerendipityPolynomials<dim>::compute_value(const unsigned int i,
                                             const Point<dim>  &p) const
  {
    return derivative(i, 0, 0, p);
  }

  template <int dim>
  Tensor<1, dim>
  SerendipityPolynomials<dim>::compute_1st_derivative(const unsigned int i,
                                                      const Point<dim> &p) const
  {
    return derivative_tensor<1>(i, p);
  }

  template <int dim>
  Tensor<2, dim>
  SerendipityPolynomials<dim>::compute_2nd_derivative(const unsigned int i,
                                                      const Point<dim> &p) const
  {
    return derivative_tensor<2>(i, p);
  }

  template <int dim>
  Tensor<3, dim>
  SerendipityPolynomials<dim>::compute_3rd_derivative(const unsigned int i,
                                                      const Point<dim> &p) const
  {
    return derivative_tensor<3>(i, p);
  }

  template <int dim>
  Tensor<4, dim>
  SerendipityPolynomials<dim>::compute_4th_derivative(const unsigned int i,
                                                      const Point<dim> &p) const
  {
    return derivative_tensor<4>(i, p);
  }

  template <int dim>
  Tensor<1, dim>
  SerendipityPolynomials<dim>::compute_grad(const unsigned int i,
                                            const Point<dim>  &p) const
  {
    return derivative_tensor<1>(i, p);
  }

  template <int dim>
  Tensor<2, dim>
  SerendipityPolynomials<dim>::compute_grad_grad(const unsigned int i,
                                                 const Point<dim>  &p) const
  {
    return derivative_tensor<2>(i, p);
  }

  template <int dim>
  std::unique_ptr<ScalarPolynomialsBase<dim>>
  SerendipityPolynomials<dim>::clone() const
  {
    return std::make_unique<SerendipityPolynomials<dim>>(*this);
  }

  template <int dim>
  std::string
  SerendipityPolynomials<dim>::name() const
  {
    return "SerendipityPolynomials";
  }



  template <int dim>
  FE_Serendipity<dim>::FE_Serendipity(const unsigned int degree)
    : FE_Poly<dim>(SerendipityPolynomials<dim>(),
                   make_fe_data<dim>(degree),
                   std::vector<bool>(n_functions, false),
                   std::vector<ComponentMask>(n_functions,
                                              ComponentMask(1, true)))
  {
    for (unsigned int i = 0; i < n_functions; ++i)
      this->unit_support_points.push_back(SerendipityPolynomials<dim>::node(i));

    // Face dofs in deal.II's order: the two vertices, then the line's dof.
    this->unit_face_support_points[0] = {Point<dim - 1>(0.),
                                         Point<dim - 1>(1.),
                                         Point<dim - 1>(0.5)};

    // Interface constraints of a refined face (rows: the new dofs of the
    // children, i.e. the midpoint vertex, then the dof of child line 0 and
    // of child line 1; columns: the dofs of the parent face). Entry (r, j)
    // is face function j of the parent at the position of new dof r, taken
    // from the trace on face 0 (x = 0, t = y).
    const std::array<double, 3> child_dof_positions = {{0.5, 0.25, 0.75}};
    const unsigned int          dofs_per_face       = this->n_dofs_per_face(0);
    this->interface_constraints.reinit(3, dofs_per_face);
    for (unsigned int r = 0; r < 3; ++r)
      for (unsigned int j = 0; j < dofs_per_face; ++j)
        this->interface_constraints(r, j) =
          this->shape_value(this->face_to_cell_index(j, 0),
                            Point<dim>(0., child_dof_positions[r]));

    // Prolongation to the children of an isotropic refinement: the space
    // is invariant under the affine child maps, so interpolation at the
    // children's nodes is exact.
    const unsigned int iso = RefinementCase<dim>::isotropic_refinement - 1;
    for (unsigned int c = 0; c < GeometryInfo<dim>::max_children_per_cell; ++c)
      {
        FullMatrix<double> &P = this->prolongation[iso][c];
        P.reinit(n_functions, n_functions);
        for (unsigned int i = 0; i < n_functions; ++i)
          {
            const Point<dim> x = GeometryInfo<dim>::child_to_cell_coordinates(
              this->unit_support_points[i],
              c);
            for (unsigned int j = 0; j < n_functions; ++j)
              P(i, j) = this->shape_value(j, x);
          }
      }
  }



  template <int dim>
  std::string
  FE_Serendipity<dim>::get_name() const
  {
    return "FE_Serendipity<" + std::to_string(dim) + ">(" +
           std::to_string(this->degree) + ")";
  }

  template <int dim>
  std::unique_ptr<FiniteElement<dim>>
  FE_Serendipity<dim>::clone() const
  {
    return std::make_unique<FE_Serendipity<dim>>(*this);
  }

  template <int dim>
  bool
  FE_Serendipity<dim>::has_support_on_face(const unsigned int shape_index,
                                           const unsigned int face_index) const
  {
    AssertIndexRange(shape_index, n_functions);
    AssertIndexRange(face_index, GeometryInfo<dim>::faces_per_cell);
    // Vertex functions vanish on the faces without their vertex, line
    // functions on every face but their own line (dim = 2: faces are
    // lines).
    if (shape_index < GeometryInfo<dim>::vertices_per_cell)
      {
        for (unsigned int v = 0; v < GeometryInfo<dim>::vertices_per_face; ++v)
          if (GeometryInfo<dim>::face_to_cell_vertices(face_index, v) ==
              shape_index)
            return true;
        return false;
      }
    return shape_index - GeometryInfo<dim>::vertices_per_cell == face_index;
  }

  template <int dim>
  void
  FE_Serendipity<dim>::convert_generalized_support_point_values_to_dof_values(
    const std::vector<Vector<double>> &support_point_values,
    std::vector<double>               &nodal_values) const
  {
    AssertDimension(support_point_values.size(), n_functions);
    AssertDimension(nodal_values.size(), n_functions);
    for (unsigned int i = 0; i < n_functions; ++i)
      {
        AssertDimension(support_point_values[i].size(), 1);
        nodal_values[i] = support_point_values[i](0);
      }
  }

  template class SerendipityPolynomials<2>;
  template class FE_Serendipity<2>;
} // namespace isoimpact
