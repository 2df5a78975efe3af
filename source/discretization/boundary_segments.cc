// Layer 3: evaluation, orientation and end marking of boundary segments.
#include <deal.II/base/exceptions.h>

#include <isoimpact/discretization/boundary_segments.h>
#include <isoimpact/nurbs/knot_vector.h>

#include <string>

using namespace dealii;

namespace isoimpact
{
  FullMatrix<double>
  bernstein_coefficients_from_values(const FullMatrix<double> &values)
  {
    const unsigned int n_points = values.n();
    AssertThrow(n_points >= 2,
                ExcMessage("Bernstein fit needs at least two points"));
    const unsigned int  degree = n_points - 1;
    FullMatrix<double>  vandermonde(n_points, n_points);
    std::vector<double> b(n_points);
    for (unsigned int j = 0; j < n_points; ++j)
      {
        nurbs::KnotVector::bernstein_values(degree,
                                            double(j) / degree,
                                            b.data());
        for (unsigned int m = 0; m < n_points; ++m)
          vandermonde(j, m) = b[m];
      }
    vandermonde.gauss_jordan();
    // coefficients^T = V^{-1} values^T, i.e. coefficients = values V^{-T}.
    FullMatrix<double> coefficients(values.m(), n_points);
    values.mTmult(coefficients, vandermonde);
    return coefficients;
  }

  template <int dim>
  void
  evaluate_segment_basis(const BoundarySegment<dim> &segment,
                         const double                eta,
                         std::vector<double>        &values,
                         std::vector<double>        &derivatives)
  {
    // The Bernstein values on the stack (this runs for every closest-point
    // iteration of the contact: no allocation, no thread-local look-up).
    constexpr unsigned int max_degree = 15;
    AssertThrow(segment.degree <= max_degree,
                ExcMessage("boundary segments of degree up to " +
                           std::to_string(max_degree) + " are supported"));
    double b[max_degree + 1], db[max_degree + 1];
    nurbs::KnotVector::bernstein_values(segment.degree, eta, b, db);
    const unsigned int n_nodes = segment.node_positions.size();
    values.resize(n_nodes);
    derivatives.resize(n_nodes);
    double weight_sum = 0., weight_sum_derivative = 0.;
    for (unsigned int k = 0; k < n_nodes; ++k)
      {
        double n = 0., dn = 0.;
        for (unsigned int j = 0; j <= segment.degree; ++j)
          {
            n += segment.bernstein_coefficients(k, j) * b[j];
            dn += segment.bernstein_coefficients(k, j) * db[j];
          }
        values[k]      = segment.node_weights[k] * n;
        derivatives[k] = segment.node_weights[k] * dn;
        weight_sum += values[k];
        weight_sum_derivative += derivatives[k];
      }
    for (unsigned int k = 0; k < n_nodes; ++k)
      {
        derivatives[k] =
          (derivatives[k] * weight_sum - values[k] * weight_sum_derivative) /
          (weight_sum * weight_sum);
        values[k] /= weight_sum;
      }
  }

  namespace
  {
    template <int dim>
    std::vector<std::array<Point<dim>, 2>>
    segment_ends(const std::vector<BoundarySegment<dim>> &segments)
    {
      std::vector<std::array<Point<dim>, 2>> ends(segments.size());
      std::vector<double>                    values, derivatives;
      for (unsigned int s = 0; s < segments.size(); ++s)
        for (unsigned int e = 0; e < 2; ++e)
          {
            evaluate_segment_basis(segments[s], double(e), values, derivatives);
            for (unsigned int k = 0; k < values.size(); ++k)
              ends[s][e] += values[k] * segments[s].node_positions[k];
          }
      return ends;
    }
  } // namespace

  template <int dim>
  void
  mark_free_segment_ends(std::vector<BoundarySegment<dim>>       &segments,
                         const std::vector<BoundarySegment<dim>> &continuation)
  {
    const auto ends  = segment_ends(segments);
    const auto other = segment_ends(continuation);
    // Quadratic in the number of segments, but done once in set-up.
    for (unsigned int s = 0; s < segments.size(); ++s)
      {
        const double tolerance = 1e-8 * ends[s][0].distance(ends[s][1]);
        const auto   meets     = [&](const std::array<Point<dim>, 2> &pair,
                               const Point<dim>                &x) {
          return x.distance(pair[0]) < tolerance ||
                 x.distance(pair[1]) < tolerance;
        };
        for (unsigned int e = 0; e < 2; ++e)
          {
            bool shared = false;
            for (unsigned int t = 0; t < segments.size() && !shared; ++t)
              shared = (t != s) && meets(ends[t], ends[s][e]);
            for (unsigned int t = 0; t < other.size() && !shared; ++t)
              shared = meets(other[t], ends[s][e]);
            segments[s].free_end[e] = !shared;
          }
      }
  }

  template <int dim>
  void
  orient_segment(BoundarySegment<dim> &segment,
                 const Tensor<1, dim> &outward_normal)
  {
    std::vector<double> r, dr;
    evaluate_segment_basis(segment, 0.5, r, dr);
    Tensor<1, dim> tangent;
    for (unsigned int k = 0; k < r.size(); ++k)
      tangent += dr[k] * segment.node_positions[k];
    Tensor<1, dim> rotated;
    rotated[0]                 = tangent[1];
    rotated[1]                 = -tangent[0];
    segment.normal_orientation = (rotated * outward_normal > 0) ? 1. : -1.;
  }


  template void
  evaluate_segment_basis(const BoundarySegment<2> &,
                         const double,
                         std::vector<double> &,
                         std::vector<double> &);
  template void
  mark_free_segment_ends(std::vector<BoundarySegment<2>> &,
                         const std::vector<BoundarySegment<2>> &);
  template void
  orient_segment(BoundarySegment<2> &, const Tensor<1, 2> &);
} // namespace isoimpact
