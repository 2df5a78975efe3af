// NURBS patch: validation, numbering, evaluation, rational basis per element
// and refinement.
#include <isoimpact/nurbs/patch.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

using namespace dealii;

namespace isoimpact
{
  namespace nurbs
  {
    namespace
    {
      constexpr unsigned int max_functions_1d = KnotVector::max_degree + 1;

      // Advances a lexicographic counter (first entry fastest) with the
      // given extents.
      template <int dim>
      inline void
      increment(std::array<unsigned int, dim>       &counter,
                const std::array<unsigned int, dim> &extent)
      {
        for (int d = 0; d < dim; ++d)
          {
            if (++counter[d] < extent[d])
              return;
            counter[d] = 0;
          }
      }
    } // namespace



    template <int dim, int spacedim>
    NURBSPatch<dim, spacedim>::NURBSPatch(
      const std::array<KnotVector, dim>          &knot_vectors,
      const std::vector<dealii::Point<spacedim>> &control_points,
      const std::vector<double>                  &weights)
      : knots(knot_vectors)
      , points(control_points)
      , point_weights(weights)
    {
      check();
    }



    template <int dim, int spacedim>
    NURBSPatch<dim, spacedim>::NURBSPatch(
      const std::array<KnotVector, dim>          &knot_vectors,
      const std::vector<dealii::Point<spacedim>> &control_points)
      : NURBSPatch(knot_vectors,
                   control_points,
                   std::vector<double>(control_points.size(), 1.))
    {}



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::check() const
    {
      unsigned int expected = 1;
      std::string  product;
      for (unsigned int d = 0; d < dim; ++d)
        {
          AssertThrow(knots[d].n_knots() > 0,
                      dealii::ExcMessage("NURBS patch: the knot vector of "
                                         "direction " +
                                         std::to_string(d) + " is empty"));
          expected *= knots[d].n_basis_functions();
          product +=
            (d > 0 ? " x " : "") + std::to_string(knots[d].n_basis_functions());
        }
      AssertThrow(points.size() == expected,
                  dealii::ExcMessage(
                    "NURBS patch: " + std::to_string(points.size()) +
                    " control points given; the knot vectors need " + product +
                    " = " + std::to_string(expected)));
      AssertThrow(point_weights.size() == expected,
                  dealii::ExcMessage(
                    "NURBS patch: " + std::to_string(point_weights.size()) +
                    " weights given; the knot vectors need " + product + " = " +
                    std::to_string(expected)));
      for (unsigned int a = 0; a < expected; ++a)
        {
          AssertThrow(std::isfinite(point_weights[a]) && point_weights[a] > 0.,
                      dealii::ExcMessage(
                        "NURBS patch: weight " + std::to_string(a) +
                        " (value " + to_string(point_weights[a]) +
                        ") is not allowed; weights must be positive and "
                        "finite"));
          for (unsigned int c = 0; c < spacedim; ++c)
            AssertThrow(std::isfinite(points[a][c]),
                        dealii::ExcMessage(
                          "NURBS patch: control point " + std::to_string(a) +
                          " has coordinate " + std::to_string(c) + " = " +
                          to_string(points[a][c]) +
                          "; coordinates must be finite"));
        }
    }



    template <int dim, int spacedim>
    unsigned int
    NURBSPatch<dim, spacedim>::control_point_index(
      const std::array<unsigned int, dim> &multi_index) const
    {
      unsigned int index = 0;
      for (int d = dim - 1; d >= 0; --d)
        index = index * knots[d].n_basis_functions() + multi_index[d];
      return index;
    }



    template <int dim, int spacedim>
    std::array<unsigned int, dim>
    NURBSPatch<dim, spacedim>::control_point_multi_index(
      const unsigned int index) const
    {
      std::array<unsigned int, dim> multi_index;
      unsigned int                  rest = index;
      for (unsigned int d = 0; d < dim; ++d)
        {
          multi_index[d] = rest % knots[d].n_basis_functions();
          rest /= knots[d].n_basis_functions();
        }
      return multi_index;
    }



    template <int dim, int spacedim>
    std::vector<unsigned int>
    NURBSPatch<dim, spacedim>::side_control_points(
      const unsigned int face) const
    {
      AssertThrow(face < 2 * dim,
                  dealii::ExcMessage("NURBS patch: side " +
                                     std::to_string(face) +
                                     " does not exist; sides are 0 to " +
                                     std::to_string(2 * dim - 1)));
      const unsigned int direction = face / 2;
      const unsigned int fixed =
        (face % 2 == 0) ? 0 : knots[direction].n_basis_functions() - 1;
      std::vector<unsigned int> result;
      for (unsigned int a = 0; a < points.size(); ++a)
        if (control_point_multi_index(a)[direction] == fixed)
          result.push_back(a);
      return result;
    }



    template <int dim, int spacedim>
    unsigned int
    NURBSPatch<dim, spacedim>::n_elements() const
    {
      unsigned int n = 1;
      for (unsigned int d = 0; d < dim; ++d)
        n *= knots[d].n_spans();
      return n;
    }



    template <int dim, int spacedim>
    std::array<unsigned int, dim>
    NURBSPatch<dim, spacedim>::n_elements_per_direction() const
    {
      std::array<unsigned int, dim> n;
      for (unsigned int d = 0; d < dim; ++d)
        n[d] = knots[d].n_spans();
      return n;
    }



    template <int dim, int spacedim>
    std::array<unsigned int, dim>
    NURBSPatch<dim, spacedim>::element_multi_index(
      const unsigned int element) const
    {
      AssertThrow(element < n_elements(),
                  dealii::ExcMessage("NURBS patch: element " +
                                     std::to_string(element) +
                                     " does not exist; elements are 0 to " +
                                     std::to_string(n_elements()) + "-1"));
      std::array<unsigned int, dim> multi_index;
      unsigned int                  rest = element;
      for (unsigned int d = 0; d < dim; ++d)
        {
          multi_index[d] = rest % knots[d].n_spans();
          rest /= knots[d].n_spans();
        }
      return multi_index;
    }



    template <int dim, int spacedim>
    unsigned int
    NURBSPatch<dim, spacedim>::element_index(
      const std::array<unsigned int, dim> &multi_index) const
    {
      unsigned int index = 0;
      for (int d = dim - 1; d >= 0; --d)
        {
          AssertThrow(multi_index[d] < knots[d].n_spans(),
                      dealii::ExcMessage(
                        "NURBS patch: element index " +
                        std::to_string(multi_index[d]) + " in direction " +
                        std::to_string(d) + " does not exist; there are " +
                        std::to_string(knots[d].n_spans()) + " spans"));
          index = index * knots[d].n_spans() + multi_index[d];
        }
      return index;
    }



    template <int dim, int spacedim>
    std::pair<dealii::Point<dim>, dealii::Point<dim>>
    NURBSPatch<dim, spacedim>::element_parameter_box(
      const unsigned int element) const
    {
      const auto         multi_index = element_multi_index(element);
      dealii::Point<dim> lower, upper;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const auto interval = knots[d].span_interval(multi_index[d]);
          lower[d]            = interval.first;
          upper[d]            = interval.second;
        }
      return {lower, upper};
    }



    template <int dim, int spacedim>
    unsigned int
    NURBSPatch<dim, spacedim>::element_containing(
      const dealii::Point<dim> &parameter) const
    {
      std::array<unsigned int, dim> multi_index;
      for (unsigned int d = 0; d < dim; ++d)
        multi_index[d] = knots[d].span_of(parameter[d]);
      return element_index(multi_index);
    }



    template <int dim, int spacedim>
    unsigned int
    NURBSPatch<dim, spacedim>::n_functions_per_element() const
    {
      unsigned int n = 1;
      for (unsigned int d = 0; d < dim; ++d)
        n *= knots[d].degree() + 1;
      return n;
    }



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::element_control_points(
      const unsigned int         element,
      std::vector<unsigned int> &indices) const
    {
      const auto                    multi_index = element_multi_index(element);
      std::array<unsigned int, dim> first, extent, local, global;
      for (unsigned int d = 0; d < dim; ++d)
        {
          first[d]  = knots[d].first_basis_function(multi_index[d]);
          extent[d] = knots[d].degree() + 1;
          local[d]  = 0;
        }
      const unsigned int n = n_functions_per_element();
      indices.resize(n);
      for (unsigned int a = 0; a < n; ++a, increment<dim>(local, extent))
        {
          for (unsigned int d = 0; d < dim; ++d)
            global[d] = first[d] + local[d];
          indices[a] = control_point_index(global);
        }
    }



    template <int dim, int spacedim>
    std::vector<unsigned int>
    NURBSPatch<dim, spacedim>::element_control_points(
      const unsigned int element) const
    {
      std::vector<unsigned int> indices;
      element_control_points(element, indices);
      return indices;
    }



    template <int dim, int spacedim>
    dealii::Point<spacedim>
    NURBSPatch<dim, spacedim>::evaluate(
      const dealii::Point<dim> &parameter) const
    {
      std::array<std::array<double, max_functions_1d>, dim> N;
      std::array<unsigned int, dim> first, extent, local, stride;
      unsigned int                  n = 1;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const unsigned int span = knots[d].span_of(parameter[d]);
          knots[d].basis_values(span, parameter[d], N[d].data());
          first[d]  = knots[d].first_basis_function(span);
          extent[d] = knots[d].degree() + 1;
          local[d]  = 0;
          stride[d] =
            (d == 0) ? 1 : stride[d - 1] * knots[d - 1].n_basis_functions();
          n *= extent[d];
        }
      dealii::Tensor<1, spacedim> numerator;
      double                      denominator = 0.;
      for (unsigned int a = 0; a < n; ++a, increment<dim>(local, extent))
        {
          double       wN    = 1.;
          unsigned int index = 0;
          for (unsigned int d = 0; d < dim; ++d)
            {
              wN *= N[d][local[d]];
              index += (first[d] + local[d]) * stride[d];
            }
          wN *= point_weights[index];
          numerator += wN * points[index];
          denominator += wN;
        }
      return dealii::Point<spacedim>(numerator / denominator);
    }



    template <int dim, int spacedim>
    dealii::DerivativeForm<1, dim, spacedim>
    NURBSPatch<dim, spacedim>::jacobian(
      const dealii::Point<dim> &parameter) const
    {
      // ders[d][k*(p_d+1) + i], k = 0, 1.
      std::array<std::array<double, 2 * max_functions_1d>, dim> ders;
      std::array<unsigned int, dim> first, extent, local, stride;
      unsigned int                  n = 1;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const unsigned int span = knots[d].span_of(parameter[d]);
          knots[d].basis_derivatives(span, parameter[d], 1, ders[d].data());
          first[d]  = knots[d].first_basis_function(span);
          extent[d] = knots[d].degree() + 1;
          local[d]  = 0;
          stride[d] =
            (d == 0) ? 1 : stride[d - 1] * knots[d - 1].n_basis_functions();
          n *= extent[d];
        }
      dealii::Tensor<1, spacedim>                  A;
      std::array<dealii::Tensor<1, spacedim>, dim> dA;
      double                                       W = 0.;
      dealii::Tensor<1, dim>                       dW;
      for (unsigned int a = 0; a < n; ++a, increment<dim>(local, extent))
        {
          double                 N = 1.;
          dealii::Tensor<1, dim> dN;
          for (unsigned int j = 0; j < dim; ++j)
            dN[j] = 1.;
          unsigned int index = 0;
          for (unsigned int d = 0; d < dim; ++d)
            {
              const double value      = ders[d][local[d]];
              const double derivative = ders[d][extent[d] + local[d]];
              N *= value;
              for (unsigned int j = 0; j < dim; ++j)
                dN[j] *= (j == d) ? derivative : value;
              index += (first[d] + local[d]) * stride[d];
            }
          const double w = point_weights[index];
          A += (w * N) * points[index];
          W += w * N;
          for (unsigned int j = 0; j < dim; ++j)
            {
              dA[j] += (w * dN[j]) * points[index];
              dW[j] += w * dN[j];
            }
        }
      const dealii::Tensor<1, spacedim>        X = A / W;
      dealii::DerivativeForm<1, dim, spacedim> J;
      for (unsigned int i = 0; i < spacedim; ++i)
        for (unsigned int j = 0; j < dim; ++j)
          J[i][j] = (dA[j][i] - X[i] * dW[j]) / W;
      return J;
    }



    namespace
    {
      // Where an element lies in each parametric direction: its span's
      // first knot and length, its first basis function and the number of
      // them, and the stride of the control point grid.
      template <int dim>
      struct ElementSpans
      {
        std::array<unsigned int, dim> span, first, extent, stride;
        std::array<double, dim>       lower, length;
        unsigned int                  n_functions = 1;
      };

      template <int dim>
      ElementSpans<dim>
      element_spans(const std::array<KnotVector, dim> &knots,
                    const unsigned int                 element,
                    const unsigned int                 n_elements)
      {
        AssertThrow(element < n_elements,
                    dealii::ExcMessage("NURBS patch: element " +
                                       std::to_string(element) +
                                       " does not exist; elements are 0 to " +
                                       std::to_string(n_elements) + "-1"));
        ElementSpans<dim> spans;
        unsigned int      rest = element;
        for (unsigned int d = 0; d < dim; ++d)
          {
            const KnotVector &kv = knots[d];
            spans.span[d]        = rest % kv.n_spans();
            rest /= kv.n_spans();
            const unsigned int k = kv.knot_index_of_span(spans.span[d]);
            spans.lower[d]       = kv.knots()[k];
            spans.length[d]      = kv.knots()[k + 1] - spans.lower[d];
            spans.first[d]       = k - kv.degree();
            spans.extent[d]      = kv.degree() + 1;
            spans.stride[d] =
              (d == 0) ? 1 :
                         spans.stride[d - 1] * knots[d - 1].n_basis_functions();
            spans.n_functions *= spans.extent[d];
          }
        return spans;
      }

      // R_a and dR_a/dreference at one point from the B-spline values and
      // first derivatives of each direction (ders[d][0, extent) and
      // ders[d][extent, 2 extent)).
      template <int dim>
      void
      rational_basis_from_1d(const ElementSpans<dim>               &spans,
                             const std::array<const double *, dim> &ders,
                             const std::vector<double>             &weights,
                             double                                *values,
                             dealii::Tensor<1, dim>                *gradients)
      {
        std::array<unsigned int, dim> local;
        local.fill(0);
        // First pass: w_a N_a and w_a dN_a/dreference; sums W and dW.
        double                 W = 0.;
        dealii::Tensor<1, dim> dW;
        for (unsigned int a = 0; a < spans.n_functions;
             ++a, increment<dim>(local, spans.extent))
          {
            double                 N = 1.;
            dealii::Tensor<1, dim> dN;
            for (unsigned int j = 0; j < dim; ++j)
              dN[j] = spans.length[j];
            unsigned int index = 0;
            for (unsigned int d = 0; d < dim; ++d)
              {
                const double value      = ders[d][local[d]];
                const double derivative = ders[d][spans.extent[d] + local[d]];
                N *= value;
                for (unsigned int j = 0; j < dim; ++j)
                  dN[j] *= (j == d) ? derivative : value;
                index += (spans.first[d] + local[d]) * spans.stride[d];
              }
            const double w = weights[index];
            values[a]      = w * N;
            gradients[a]   = w * dN;
            W += values[a];
            dW += gradients[a];
          }
        // Second pass: R = wN / W, dR = (w dN - R dW) / W.
        const double inverse_W = 1. / W;
        for (unsigned int a = 0; a < spans.n_functions; ++a)
          {
            values[a] *= inverse_W;
            gradients[a] = (gradients[a] - values[a] * dW) * inverse_W;
          }
      }
    } // namespace



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::element_rational_basis(
      const unsigned int                   element,
      const dealii::Point<dim>            &reference_point,
      std::vector<double>                 &values,
      std::vector<dealii::Tensor<1, dim>> &gradients) const
    {
      const ElementSpans<dim> spans =
        element_spans<dim>(knots, element, n_elements());
      std::array<std::array<double, 2 * max_functions_1d>, dim> ders;
      std::array<const double *, dim>                           pointers;
      for (unsigned int d = 0; d < dim; ++d)
        {
          knots[d].basis_derivatives(spans.span[d],
                                     spans.lower[d] +
                                       reference_point[d] * spans.length[d],
                                     1,
                                     ders[d].data());
          pointers[d] = ders[d].data();
        }
      if (values.size() != spans.n_functions)
        values.resize(spans.n_functions);
      if (gradients.size() != spans.n_functions)
        gradients.resize(spans.n_functions);
      rational_basis_from_1d<dim>(spans,
                                  pointers,
                                  point_weights,
                                  values.data(),
                                  gradients.data());
    }



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::element_rational_basis(
      const unsigned int                     element,
      const std::vector<dealii::Point<dim>> &reference_points,
      std::vector<double>                   &values,
      std::vector<dealii::Tensor<1, dim>>   &gradients) const
    {
      const ElementSpans<dim> spans =
        element_spans<dim>(knots, element, n_elements());
      const unsigned int n_points = reference_points.size();
      const unsigned int n        = spans.n_functions;
      // The B-splines of each direction once per distinct coordinate.
      std::array<std::vector<double>, dim>       coordinates, ders;
      std::vector<std::array<unsigned int, dim>> which(n_points);
      for (unsigned int d = 0; d < dim; ++d)
        for (unsigned int q = 0; q < n_points; ++q)
          {
            const double u = reference_points[q][d];
            const auto   found =
              std::find(coordinates[d].begin(), coordinates[d].end(), u);
            which[q][d] = found - coordinates[d].begin();
            if (found == coordinates[d].end())
              {
                coordinates[d].push_back(u);
                ders[d].resize(coordinates[d].size() * 2 * spans.extent[d]);
                knots[d].basis_derivatives(
                  spans.span[d],
                  spans.lower[d] + u * spans.length[d],
                  1,
                  &ders[d][which[q][d] * 2 * spans.extent[d]]);
              }
          }
      if (values.size() != n_points * n)
        values.resize(n_points * n);
      if (gradients.size() != n_points * n)
        gradients.resize(n_points * n);
      for (unsigned int q = 0; q < n_points; ++q)
        {
          std::array<const double *, dim> pointers;
          for (unsigned int d = 0; d < dim; ++d)
            pointers[d] = &ders[d][which[q][d] * 2 * spans.extent[d]];
          rational_basis_from_1d<dim>(spans,
                                      pointers,
                                      point_weights,
                                      &values[q * n],
                                      &gradients[q * n]);
        }
    }



    template <int dim, int spacedim>
    dealii::FullMatrix<double>
    NURBSPatch<dim, spacedim>::element_extraction_operator(
      const unsigned int element) const
    {
      const auto multi_index = element_multi_index(element);
      std::array<dealii::FullMatrix<double>, dim> C;
      std::array<unsigned int, dim>               extent;
      for (unsigned int d = 0; d < dim; ++d)
        {
          C[d]      = knots[d].extraction_operators()[multi_index[d]];
          extent[d] = knots[d].degree() + 1;
        }
      const unsigned int            n = n_functions_per_element();
      dealii::FullMatrix<double>    result(n, n);
      std::array<unsigned int, dim> row_index;
      row_index.fill(0);
      for (unsigned int a = 0; a < n; ++a, increment<dim>(row_index, extent))
        {
          std::array<unsigned int, dim> column_index;
          column_index.fill(0);
          for (unsigned int b = 0; b < n;
               ++b, increment<dim>(column_index, extent))
            {
              double value = 1.;
              for (unsigned int d = 0; d < dim; ++d)
                value *= C[d](row_index[d], column_index[d]);
              result(a, b) = value;
            }
        }
      return result;
    }



    template <int dim, int spacedim>
    std::vector<double>
    NURBSPatch<dim, spacedim>::homogeneous_rows(
      const unsigned int direction) const
    {
      const unsigned int  n_rows    = knots[direction].n_basis_functions();
      const unsigned int  n_columns = points.size() / n_rows * (spacedim + 1);
      std::vector<double> rows(n_rows * n_columns);
      for (unsigned int a = 0; a < points.size(); ++a)
        {
          const auto   multi_index = control_point_multi_index(a);
          unsigned int column      = 0;
          for (int d = dim - 1; d >= 0; --d)
            if (static_cast<unsigned int>(d) != direction)
              column = column * knots[d].n_basis_functions() + multi_index[d];
          double *row = rows.data() + multi_index[direction] * n_columns +
                        column * (spacedim + 1);
          for (unsigned int c = 0; c < spacedim; ++c)
            row[c] = point_weights[a] * points[a][c];
          row[spacedim] = point_weights[a];
        }
      return rows;
    }



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::set_from_homogeneous_rows(
      const unsigned int         direction,
      const std::vector<double> &rows,
      const KnotVector          &new_knot_vector)
    {
      knots[direction]             = new_knot_vector;
      const unsigned int n_rows    = new_knot_vector.n_basis_functions();
      const unsigned int n_columns = rows.size() / n_rows;
      unsigned int       n_total   = 1;
      for (unsigned int d = 0; d < dim; ++d)
        n_total *= knots[d].n_basis_functions();
      points.resize(n_total);
      point_weights.resize(n_total);
      for (unsigned int a = 0; a < n_total; ++a)
        {
          const auto   multi_index = control_point_multi_index(a);
          unsigned int column      = 0;
          for (int d = dim - 1; d >= 0; --d)
            if (static_cast<unsigned int>(d) != direction)
              column = column * knots[d].n_basis_functions() + multi_index[d];
          const double *row = rows.data() + multi_index[direction] * n_columns +
                              column * (spacedim + 1);
          point_weights[a] = row[spacedim];
          for (unsigned int c = 0; c < spacedim; ++c)
            points[a][c] = row[c] / row[spacedim];
        }
      check();
    }



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::insert_knots(
      const unsigned int         direction,
      const std::vector<double> &new_knots)
    {
      AssertThrow(direction < dim,
                  dealii::ExcMessage("NURBS patch: direction " +
                                     std::to_string(direction) +
                                     " does not exist; directions are 0 to " +
                                     std::to_string(dim - 1)));
      if (new_knots.empty())
        return;
      std::vector<double> rows = homogeneous_rows(direction);
      const unsigned int  n_columns =
        rows.size() / knots[direction].n_basis_functions();
      const KnotVector refined =
        knots[direction].insert_knots(new_knots, rows, n_columns);
      set_from_homogeneous_rows(direction, rows, refined);
    }



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::refine_uniformly(
      const unsigned int direction,
      const unsigned int n_subdivisions)
    {
      AssertThrow(n_subdivisions >= 1,
                  dealii::ExcMessage(
                    "NURBS patch: " + std::to_string(n_subdivisions) +
                    " subdivisions requested; at least 1 "
                    "is needed"));
      AssertThrow(direction < dim,
                  dealii::ExcMessage("NURBS patch: direction " +
                                     std::to_string(direction) +
                                     " does not exist; directions are 0 to " +
                                     std::to_string(dim - 1)));
      const std::vector<double> breaks = knots[direction].breakpoints();
      std::vector<double>       new_knots;
      for (unsigned int s = 0; s + 1 < breaks.size(); ++s)
        for (unsigned int i = 1; i < n_subdivisions; ++i)
          new_knots.push_back(breaks[s] +
                              (breaks[s + 1] - breaks[s]) * i / n_subdivisions);
      insert_knots(direction, new_knots);
    }



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::refine_uniformly(
      const unsigned int n_subdivisions)
    {
      for (unsigned int d = 0; d < dim; ++d)
        refine_uniformly(d, n_subdivisions);
    }



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::elevate_degree(const unsigned int direction,
                                              const unsigned int times)
    {
      AssertThrow(direction < dim,
                  dealii::ExcMessage("NURBS patch: direction " +
                                     std::to_string(direction) +
                                     " does not exist; directions are 0 to " +
                                     std::to_string(dim - 1)));
      AssertThrow(knots[direction].degree() + times <= KnotVector::max_degree,
                  dealii::ExcMessage("NURBS patch: elevating degree " +
                                     std::to_string(knots[direction].degree()) +
                                     " by " + std::to_string(times) +
                                     " exceeds the maximal degree " +
                                     std::to_string(KnotVector::max_degree)));
      if (times == 0)
        return;
      std::vector<double> rows = homogeneous_rows(direction);
      const unsigned int  n_columns =
        rows.size() / knots[direction].n_basis_functions();
      const KnotVector elevated =
        knots[direction].elevate_degree(times, rows, n_columns);
      set_from_homogeneous_rows(direction, rows, elevated);
    }



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::k_refine(const unsigned int direction,
                                        const unsigned int times,
                                        const unsigned int n_subdivisions)
    {
      elevate_degree(direction, times);
      refine_uniformly(direction, n_subdivisions);
    }



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::k_refine(const unsigned int times,
                                        const unsigned int n_subdivisions)
    {
      for (unsigned int d = 0; d < dim; ++d)
        k_refine(d, times, n_subdivisions);
    }



    template <int dim, int spacedim>
    void
    NURBSPatch<dim, spacedim>::refine_graded(const unsigned int direction,
                                             const unsigned int side,
                                             const unsigned int n_layers,
                                             const double       ratio)
    {
      AssertThrow(direction < dim,
                  dealii::ExcMessage("NURBS patch: direction " +
                                     std::to_string(direction) +
                                     " does not exist; directions are 0 to " +
                                     std::to_string(dim - 1)));
      AssertThrow(side <= 1,
                  dealii::ExcMessage("NURBS patch: graded refinement side " +
                                     std::to_string(side) +
                                     " is not allowed; use 0 (lower end) or 1 "
                                     "(upper end)"));
      AssertThrow(std::isfinite(ratio) && ratio > 0.,
                  dealii::ExcMessage("NURBS patch: grading ratio " +
                                     to_string(ratio) +
                                     " is not allowed; it must be positive"));
      const KnotVector  &kv       = knots[direction];
      const unsigned int span     = (side == 0) ? 0 : kv.n_spans() - 1;
      const auto         interval = kv.span_interval(span);
      const double       length   = interval.second - interval.first;
      // Spans h, h r, ..., h r^{n_layers}, the first touching the end.
      double total = 0., h = 1.;
      for (unsigned int i = 0; i <= n_layers; ++i, h *= ratio)
        total += h;
      std::vector<double> new_knots;
      double              distance = 0.;
      h                            = length / total;
      for (unsigned int i = 0; i < n_layers; ++i, h *= ratio)
        {
          distance += h;
          new_knots.push_back(side == 0 ? interval.first + distance :
                                          interval.second - distance);
        }
      insert_knots(direction, new_knots);
    }



    template class NURBSPatch<1, 1>;
    template class NURBSPatch<1, 2>;
    template class NURBSPatch<2, 2>;
    template class NURBSPatch<2, 3>;
    template class NURBSPatch<3, 3>;
  } // namespace nurbs
} // namespace isoimpact
