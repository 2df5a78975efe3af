// Layer 4: symmetric two-pass penalty contact (see contact.h).
#include <deal.II/base/exceptions.h>
#include <deal.II/base/parallel.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/thread_management.h>

#include <isoimpact/mechanics/contact.h>

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <boost/iterator/function_output_iterator.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <thread>

using namespace dealii;

namespace isoimpact
{
  namespace bg  = boost::geometry;
  namespace bgi = boost::geometry::index;

  template <int dim>
  std::vector<SurfaceQuadraturePoint<dim>>
  surface_quadrature(const std::vector<BoundarySegment<dim>> &segments,
                     const unsigned int                       n_points,
                     std::vector<double>                     *segment_lengths)
  {
    const QGauss<1>                          gauss(n_points);
    std::vector<SurfaceQuadraturePoint<dim>> points;
    std::vector<double>                      r, dr;
    if (segment_lengths)
      segment_lengths->clear();
    for (unsigned int s = 0; s < segments.size(); ++s)
      {
        double length = 0.;
        for (unsigned int q = 0; q < gauss.size(); ++q)
          {
            evaluate_segment_basis(segments[s], gauss.point(q)[0], r, dr);
            Point<dim>     x;
            Tensor<1, dim> dx;
            for (unsigned int k = 0; k < r.size(); ++k)
              {
                x += r[k] * segments[s].node_positions[k];
                dx += dr[k] * segments[s].node_positions[k];
              }
            const double weight = dx.norm() * gauss.weight(q);
            points.push_back({s, r, weight, x});
            length += weight;
          }
        if (segment_lengths)
          segment_lengths->push_back(length);
      }
    return points;
  }

  template <int dim>
  Point<dim>
  current_position(const BoundarySegment<dim>        &segment,
                   const SurfaceQuadraturePoint<dim> &point,
                   const ArrayView<const double>      u)
  {
    Point<dim> x;
    for (unsigned int k = 0; k < point.shape_values.size(); ++k)
      for (unsigned int d = 0; d < dim; ++d)
        x[d] += point.shape_values[k] *
                (segment.node_positions[k][d] + u[segment.node_dofs[k][d]]);
    return x;
  }

  template <int dim>
  void
  distribute_point_force(const BoundarySegment<dim> &segment,
                         const std::vector<double>  &shape_values,
                         const Tensor<1, dim>       &force,
                         Vector<double>             &f)
  {
    for (unsigned int k = 0; k < shape_values.size(); ++k)
      for (unsigned int d = 0; d < dim; ++d)
        f(segment.node_dofs[k][d]) += shape_values[k] * force[d];
  }

  template <int dim>
  Tensor<1, dim>
  point_velocity(const BoundarySegment<dim> &segment,
                 const std::vector<double>  &shape_values,
                 const Vector<double>       &v)
  {
    Tensor<1, dim> velocity;
    for (unsigned int k = 0; k < shape_values.size(); ++k)
      for (unsigned int d = 0; d < dim; ++d)
        velocity[d] += shape_values[k] * v(segment.node_dofs[k][d]);
    return velocity;
  }

  template <int dim>
  SurfaceNodes<dim>::SurfaceNodes(
    const std::vector<BoundarySegment<dim>>        &segments,
    const std::vector<SurfaceQuadraturePoint<dim>> &points)
    : node_of_segment(segments.size())
  {
    std::map<types::global_dof_index, unsigned int> node_of_dof;
    for (unsigned int s = 0; s < segments.size(); ++s)
      for (const auto &dofs : segments[s].node_dofs)
        {
          const auto inserted = node_of_dof.emplace(dofs[0], x_dof.size());
          if (inserted.second)
            x_dof.push_back(dofs[0]);
          node_of_segment[s].push_back(inserted.first->second);
        }
    area.assign(x_dof.size(), 0.);
    for (const auto &point : points)
      {
        point_weights.push_back(point.weight);
        first_value.push_back(values.size());
        for (unsigned int k = 0; k < point.shape_values.size(); ++k)
          {
            area[node_of_segment[point.segment][k]] +=
              point.shape_values[k] * point.weight;
            value_nodes.push_back(node_of_segment[point.segment][k]);
            values.push_back(point.shape_values[k]);
          }
      }
    first_value.push_back(values.size());
  }

  template <int dim>
  void
  SurfaceNodes<dim>::project_pressure(
    const std::vector<SurfaceQuadraturePoint<dim>> &points,
    const std::vector<double>                      &point_pressure,
    std::vector<double>                            &nodal,
    std::vector<double>                            &field) const
  {
    AssertDimension(point_pressure.size(), points.size());
    AssertDimension(points.size(), point_weights.size());
    (void)points;
    nodal.assign(area.size(), 0.);
    for (unsigned int q = 0; q < point_weights.size(); ++q)
      if (point_pressure[q] != 0.)
        for (unsigned int j = first_value[q]; j < first_value[q + 1]; ++j)
          nodal[value_nodes[j]] +=
            point_pressure[q] * point_weights[q] * values[j];
    for (unsigned int i = 0; i < nodal.size(); ++i)
      nodal[i] = area[i] > 0. ? nodal[i] / area[i] : 0.;
    field.assign(point_weights.size(), 0.);
    for (unsigned int q = 0; q < point_weights.size(); ++q)
      for (unsigned int j = first_value[q]; j < first_value[q + 1]; ++j)
        field[q] += values[j] * nodal[value_nodes[j]];
  }

  template <int dim>
  void
  add_surface_pressure(const SurfaceNodes<dim>                        &nodes,
                       const std::vector<SurfaceQuadraturePoint<dim>> &points,
                       const std::vector<double> &point_pressure,
                       const std::vector<double> &point_gap,
                       const unsigned int         body,
                       const bool                 record_points,
                       std::vector<double>       &nodal,
                       std::vector<double>       &field,
                       ContactResult<dim>        &result)
  {
    if (result.n_active_points == 0)
      return;
    nodes.project_pressure(points, point_pressure, nodal, field);
    if (record_points)
      for (unsigned int k = 0; k < nodal.size(); ++k)
        result.nodal_pressures[body].emplace_back(nodes.x_dof[k], nodal[k]);
    for (unsigned int q = 0; q < points.size(); ++q)
      {
        result.max_pressure = std::max(result.max_pressure, field[q]);
        if (record_points && (field[q] > 0. || point_pressure[q] > 0.))
          result.points.push_back({points[q].reference_position,
                                   field[q],
                                   point_pressure[q],
                                   point_gap[q],
                                   body});
      }
  }

  template <int dim>
  double
  mean_surface_mass_density(const std::vector<BoundarySegment<dim>> &segments,
                            const unsigned int                       n_points,
                            const Vector<double> &nodal_masses)
  {
    const SurfaceNodes<dim> nodes(segments,
                                  surface_quadrature(segments, n_points));
    double                  mass = 0., area = 0.;
    for (unsigned int k = 0; k < nodes.x_dof.size(); ++k)
      {
        mass += nodal_masses(nodes.x_dof[k]);
        area += nodes.area[k];
      }
    return mass / area;
  }

  template <int dim>
  SurfaceMassDensity<dim>::SurfaceMassDensity(
    const SurfaceNodes<dim> &nodes,
    const Vector<double>    &nodal_masses)
    : node_densities(nodes.node_of_segment.size())
  {
    for (unsigned int s = 0; s < node_densities.size(); ++s)
      for (const unsigned int node : nodes.node_of_segment[s])
        node_densities[s].push_back(nodes.area[node] > 0. ?
                                      nodal_masses(nodes.x_dof[node]) /
                                        nodes.area[node] :
                                      0.);
  }

  template <int dim>
  bool
  SurfaceMassDensity<dim>::empty() const
  {
    return node_densities.empty();
  }

  template <int dim>
  double
  SurfaceMassDensity<dim>::operator()(
    const unsigned int         segment,
    const std::vector<double> &shape_values) const
  {
    double mu = 0.;
    for (unsigned int k = 0; k < shape_values.size(); ++k)
      mu += shape_values[k] * node_densities[segment][k];
    return mu;
  }

  namespace
  {
    // The pressure less the damping c dg/dt, down to zero; `removed_power`
    // receives (pressure - damped) dg/dt w.
    double
    damped_pressure(const double pressure,
                    const double damping,
                    const double gap_rate,
                    const double weight,
                    double      &removed_power)
    {
      const double damped = std::max(0., pressure - damping * gap_rate);
      removed_power       = (pressure - damped) * gap_rate * weight;
      return damped;
    }
  } // namespace

  template <int dim>
  double
  ContactResult<dim>::damp(const double pressure,
                           const double damping,
                           const double gap_rate,
                           const double weight)
  {
    double       removed_power;
    const double damped =
      damped_pressure(pressure, damping, gap_rate, weight, removed_power);
    damping_power += removed_power;
    return damped;
  }

  template <int dim>
  void
  ContactResult<dim>::add_active_point(
    const double          gauss_point_pressure,
    const double          gap,
    const double          point_energy,
    const Tensor<1, dim> &point_force_on_body_0)
  {
    energy += point_energy;
    force_on_body_0 += point_force_on_body_0;
    max_gauss_point_pressure =
      std::max(max_gauss_point_pressure, gauss_point_pressure);
    max_penetration = std::max(max_penetration, -gap);
    ++n_active_points;
  }

  namespace internal
  {
    using BoostPoint  = bg::model::point<double, 2, bg::cs::cartesian>;
    using BoundingBox = bg::model::box<BoostPoint>;

    // Scratch of the evaluations: a contact surface in its current
    // configuration (the node positions of each segment and of its Gauss
    // points) and its search structure, an R-tree of the segments' bounding
    // boxes. Kept between evaluations so that its arrays are not allocated
    // again. The segments' and points' data are copied once into flat arrays
    // in the order they are read: an evaluation follows the step's pass,
    // which has streamed the whole state through the caches, and a walk
    // through one array per segment or point would wait for one miss after
    // another.
    template <int dim>
    class CurrentSurface
    {
    public:
      CurrentSurface(const std::vector<BoundarySegment<dim>>        &segments,
                     const std::vector<SurfaceQuadraturePoint<dim>> &points);

      // The configuration u of `segments` (the same as in the constructor;
      // the vector must outlive the use until the next update); with
      // `searched` the search structure and the hull boxes, which points of
      // the other surface need to be projected on this one; with `points`
      // the current positions of this surface's Gauss points, which their
      // own projections need.
      void
      update(const std::vector<BoundarySegment<dim>> &segments,
             const std::vector<double>               &reference_lengths,
             const ArrayView<const double>            u,
             const bool                               searched,
             const bool                               points);

      // Search: the segments whose bounding box contains x.
      void
      find_candidates(const Point<dim>          &x,
                      std::vector<unsigned int> &candidates) const;

      // Whether x lies in the box of all the segments' boxes (if not, it has
      // no candidate).
      bool
      may_have_candidates(const Point<dim> &x) const;

      // A lower bound of the distance from x to segment s: the distance to
      // the box of its Bezier control points, whose convex hull holds the
      // curve (0 for a segment whose Bezier weights are not all positive).
      double
      distance_bound(const unsigned int s, const Point<dim> &x) const;

      // Current position of Gauss point q (of the constructor's points).
      const Point<dim> &
      point_position(const unsigned int q) const
      {
        return point_positions[q];
      }

      // Position and tangent of segment s at eta.
      void
      evaluate(const unsigned int   s,
               const double         eta,
               std::vector<double> &r,
               std::vector<double> &dr,
               Point<dim>          &x,
               Tensor<1, dim>      &tangent) const;

      // The parameter eta of the closest point of segment s to x.
      double
      closest_point(const unsigned int   s,
                    const Point<dim>    &x,
                    std::vector<double> &r,
                    std::vector<double> &dr) const;

      const BoundarySegment<dim> &
      segment(const unsigned int s) const
      {
        return (*segments)[s];
      }

    private:
      const std::vector<BoundarySegment<dim>> *segments = nullptr;
      // Segment s has the nodes first_node[s] to first_node[s + 1] - 1.
      std::vector<unsigned int> first_node;
      std::vector<unsigned int> degrees;
      // Per node: the unknowns of its components, its reference position.
      std::vector<types::global_dof_index> node_dofs;
      std::vector<Point<dim>>              reference_nodes;
      // Per segment, node-major: w_k C_kj (weight times Bernstein
      // coefficient), from first_coefficient[s] on.
      std::vector<double>       hull_coefficients;
      std::vector<unsigned int> first_coefficient;
      // Per Gauss point: its segment and nodal function values (from
      // first_shape_value[q] on, as many as its segment has nodes).
      std::vector<unsigned int> point_segments;
      std::vector<unsigned int> first_shape_value;
      std::vector<double>       shape_values;

      // The current configuration.
      std::vector<Point<dim>>                           nodes;
      std::vector<Point<dim>>                           point_positions;
      std::vector<std::pair<BoundingBox, unsigned int>> boxes;
      std::array<Point<dim>, 2>                         all_boxes;
      // Per segment: the box of its Bezier control points (lower, upper),
      // or an empty box (lower > upper) if it does not bound the curve.
      std::vector<std::array<Point<dim>, 2>> hull_boxes;
      bgi::rtree<std::pair<BoundingBox, unsigned int>, bgi::quadratic<16>> tree;
    };

    template <int dim>
    CurrentSurface<dim>::CurrentSurface(
      const std::vector<BoundarySegment<dim>>        &segments,
      const std::vector<SurfaceQuadraturePoint<dim>> &points)
    {
      first_node.push_back(0);
      first_coefficient.push_back(0);
      for (const auto &segment : segments)
        {
          degrees.push_back(segment.degree);
          for (unsigned int k = 0; k < segment.node_positions.size(); ++k)
            {
              for (unsigned int d = 0; d < dim; ++d)
                node_dofs.push_back(segment.node_dofs[k][d]);
              reference_nodes.push_back(segment.node_positions[k]);
              for (unsigned int j = 0; j <= segment.degree; ++j)
                hull_coefficients.push_back(
                  segment.node_weights[k] *
                  segment.bernstein_coefficients(k, j));
            }
          first_node.push_back(reference_nodes.size());
          first_coefficient.push_back(hull_coefficients.size());
        }
      for (const auto &point : points)
        {
          AssertDimension(point.shape_values.size(),
                          first_node[point.segment + 1] -
                            first_node[point.segment]);
          point_segments.push_back(point.segment);
          first_shape_value.push_back(shape_values.size());
          shape_values.insert(shape_values.end(),
                              point.shape_values.begin(),
                              point.shape_values.end());
        }
      nodes.resize(reference_nodes.size());
      point_positions.resize(points.size());
      hull_boxes.resize(segments.size());
    }

    template <int dim>
    void
    CurrentSurface<dim>::update(
      const std::vector<BoundarySegment<dim>> &segments,
      const std::vector<double>               &reference_lengths,
      const ArrayView<const double>            u,
      const bool                               searched,
      const bool                               points)
    {
      AssertDimension(segments.size() + 1, first_node.size());
      this->segments = &segments;
      boxes.clear();
      // The entries of u are scattered through a vector much larger than
      // the caches: ask for all of them at once, so that their misses
      // overlap (no arithmetic changes).
      for (std::size_t i = 0; i < node_dofs.size(); i += dim)
        __builtin_prefetch(u.data() + node_dofs[i]);
      for (unsigned int d = 0; d < dim; ++d)
        {
          all_boxes[0][d] = std::numeric_limits<double>::max();
          all_boxes[1][d] = -std::numeric_limits<double>::max();
        }
      for (unsigned int s = 0; s < segments.size(); ++s)
        {
          const unsigned int first   = first_node[s];
          const unsigned int n_nodes = first_node[s + 1] - first;
          const unsigned int degree  = degrees[s];
          Point<dim>         lower, upper;
          for (unsigned int d = 0; d < dim; ++d)
            {
              lower[d] = std::numeric_limits<double>::max();
              upper[d] = -std::numeric_limits<double>::max();
            }
          for (unsigned int k = first; k < first + n_nodes; ++k)
            for (unsigned int d = 0; d < dim; ++d)
              {
                nodes[k][d] = reference_nodes[k][d] + u[node_dofs[dim * k + d]];
                lower[d]    = std::min(lower[d], nodes[k][d]);
                upper[d]    = std::max(upper[d], nodes[k][d]);
              }
          if (!searched)
            continue;
          // x(eta) = sum_j b_j W_j P_j / sum_j b_j W_j with the Bezier
          // weights W_j = sum_k w_k C_kj and points P_j = sum_k w_k C_kj
          // x_k / W_j: with all W_j > 0 the curve lies in the hull of the
          // P_j.
          auto &hull = hull_boxes[s];
          for (unsigned int d = 0; d < dim; ++d)
            {
              hull[0][d] = std::numeric_limits<double>::infinity();
              hull[1][d] = -std::numeric_limits<double>::infinity();
            }
          bool          bounded      = true;
          const double *coefficients = &hull_coefficients[first_coefficient[s]];
          for (unsigned int j = 0; j <= degree; ++j)
            {
              double     weight = 0.;
              Point<dim> weighted;
              for (unsigned int k = 0; k < n_nodes; ++k)
                {
                  const double c = coefficients[k * (degree + 1) + j];
                  weight += c;
                  weighted += c * nodes[first + k];
                }
              bounded = bounded && weight > 0.;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  hull[0][d] = std::min(hull[0][d], weighted[d] / weight);
                  hull[1][d] = std::max(hull[1][d], weighted[d] / weight);
                }
            }
          if (!bounded)
            hull[0][0] = 1., hull[1][0] = -1.;
          // Lagrange curves may leave the hull of their nodes, and a
          // penetrating point lies inside the other body: inflate the box.
          const double margin = 0.5 * reference_lengths[s];
          boxes.emplace_back(
            BoundingBox(BoostPoint(lower[0] - margin, lower[1] - margin),
                        BoostPoint(upper[0] + margin, upper[1] + margin)),
            s);
          for (unsigned int d = 0; d < dim; ++d)
            {
              all_boxes[0][d] = std::min(all_boxes[0][d], lower[d] - margin);
              all_boxes[1][d] = std::max(all_boxes[1][d], upper[d] + margin);
            }
        }
      if (searched)
        tree = decltype(tree)(boxes.begin(), boxes.end()); // bulk loading
      if (!points)
        return;
      for (unsigned int q = 0; q < point_positions.size(); ++q)
        {
          const unsigned int first  = first_node[point_segments[q]];
          const unsigned int n      = first_node[point_segments[q] + 1] - first;
          const double      *values = &shape_values[first_shape_value[q]];
          Point<dim>         x;
          for (unsigned int k = 0; k < n; ++k)
            x += values[k] * nodes[first + k];
          point_positions[q] = x;
        }
    }

    template <int dim>
    void
    CurrentSurface<dim>::find_candidates(
      const Point<dim>          &x,
      std::vector<unsigned int> &candidates) const
    {
      candidates.clear();
      tree.query(bgi::intersects(BoostPoint(x[0], x[1])),
                 boost::make_function_output_iterator(
                   [&](const std::pair<BoundingBox, unsigned int> &value) {
                     candidates.push_back(value.second);
                   }));
    }

    template <int dim>
    bool
    CurrentSurface<dim>::may_have_candidates(const Point<dim> &x) const
    {
      for (unsigned int d = 0; d < dim; ++d)
        if (!(x[d] >= all_boxes[0][d] && x[d] <= all_boxes[1][d]))
          return false;
      return true;
    }

    template <int dim>
    double
    CurrentSurface<dim>::distance_bound(const unsigned int s,
                                        const Point<dim>  &x) const
    {
      const auto &hull = hull_boxes[s];
      if (hull[0][0] > hull[1][0])
        return 0.;
      double square = 0.;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const double outside =
            std::max({hull[0][d] - x[d], x[d] - hull[1][d], 0.});
          square += outside * outside;
        }
      // Less a margin for the round-off of the box and of the curve's
      // points.
      return std::max(0.,
                      std::sqrt(square) - 1e-12 * hull[0].distance(hull[1]));
    }

    template <int dim>
    void
    CurrentSurface<dim>::evaluate(const unsigned int   s,
                                  const double         eta,
                                  std::vector<double> &r,
                                  std::vector<double> &dr,
                                  Point<dim>          &x,
                                  Tensor<1, dim>      &tangent) const
    {
      evaluate_segment_basis((*segments)[s], eta, r, dr);
      x                               = Point<dim>();
      tangent                         = Tensor<1, dim>();
      const Point<dim> *segment_nodes = &nodes[first_node[s]];
      for (unsigned int k = 0; k < r.size(); ++k)
        {
          x += r[k] * segment_nodes[k];
          tangent += dr[k] * segment_nodes[k];
        }
    }

    // Gauss-Newton on (x - x_s(eta)) . x_s'(eta) = 0 from the best of a few
    // samples; if it does not converge, a sampled golden-section search on
    // the distance.
    template <int dim>
    double
    CurrentSurface<dim>::closest_point(const unsigned int   s,
                                       const Point<dim>    &x,
                                       std::vector<double> &r,
                                       std::vector<double> &dr) const
    {
      Point<dim>     y;
      Tensor<1, dim> t;
      const auto     distance_squared = [&](const double eta) {
        evaluate(s, eta, r, dr, y, t);
        return (x - y).norm_square();
      };

      double    eta = 0.5, best = std::numeric_limits<double>::max();
      const int n_samples = 5;
      for (int i = 0; i < n_samples; ++i)
        {
          const double e = double(i) / (n_samples - 1);
          const double d = distance_squared(e);
          if (d < best)
            best = d, eta = e;
        }
      bool converged = false;
      for (unsigned int iteration = 0; iteration < 30; ++iteration)
        {
          evaluate(s, eta, r, dr, y, t);
          const double step  = ((x - y) * t) / t.norm_square();
          const double next  = std::min(1., std::max(0., eta + step));
          const bool   small = std::abs(next - eta) < 1e-13;
          eta                = next;
          if (small)
            {
              converged = true;
              break;
            }
        }
      if (!converged || !std::isfinite(eta))
        {
          const int n_fine = 33;
          double    a = 0., b = 1.;
          best = std::numeric_limits<double>::max();
          for (int i = 0; i < n_fine; ++i)
            {
              const double e = double(i) / (n_fine - 1);
              const double d = distance_squared(e);
              if (d < best)
                best = d, eta = e;
            }
          a                   = std::max(0., eta - 1. / (n_fine - 1));
          b                   = std::min(1., eta + 1. / (n_fine - 1));
          const double golden = 0.5 * (std::sqrt(5.) - 1.);
          for (unsigned int iteration = 0; iteration < 60; ++iteration)
            {
              const double c = b - golden * (b - a), d = a + golden * (b - a);
              if (distance_squared(c) < distance_squared(d))
                b = d;
              else
                a = c;
            }
          eta = 0.5 * (a + b);
          AssertThrow(std::isfinite(eta),
                      ExcMessage("contact: the closest-point projection of "
                                 "the point (" +
                                 std::to_string(x[0]) + ", " +
                                 std::to_string(x[1]) +
                                 ") failed (non-finite parameter); the mesh "
                                 "is probably inverted"));
        }
      return eta;
    }

  } // namespace internal

  namespace
  {
    using internal::CurrentSurface;

    // The closest point of a surface to a point x.
    template <int dim>
    struct Projection
    {
      unsigned int   segment = numbers::invalid_unsigned_int; // none found
      double         eta     = 0.;
      Tensor<1, dim> normal;   // unit outward normal of the surface there
      double         gap = 0.; // (x - y) . normal, negative if penetrating
    };

    // Closest-point projection of x onto the candidate segments of
    // `surface`; a point beyond a free end of the surface is no contact.
    // The candidates are visited nearest bound first, and those whose bound
    // exceeds the closest distance found are not projected. Of equally
    // distant ones the first in `candidates` is taken, as in their order.
    // `order`, `r` and `dr` are scratch.
    template <int dim>
    Projection<dim>
    project(const CurrentSurface<dim>                    &surface,
            const Point<dim>                             &x,
            const std::vector<unsigned int>              &candidates,
            std::vector<std::pair<double, unsigned int>> &order,
            std::vector<double>                          &r,
            std::vector<double>                          &dr)
    {
      order.clear();
      for (unsigned int i = 0; i < candidates.size(); ++i)
        order.emplace_back(surface.distance_bound(candidates[i], x), i);
      std::sort(order.begin(), order.end());

      Projection<dim> closest;
      double          closest_distance = std::numeric_limits<double>::max();
      unsigned int    closest_position = numbers::invalid_unsigned_int;
      for (const auto &[bound, position] : order)
        {
          if (closest_position != numbers::invalid_unsigned_int &&
              bound > closest_distance)
            break;
          const unsigned int s       = candidates[position];
          const double       eta     = surface.closest_point(s, x, r, dr);
          const auto        &segment = surface.segment(s);
          if ((eta <= 0. && segment.free_end[0]) ||
              (eta >= 1. && segment.free_end[1]))
            continue;
          Point<dim>     y;
          Tensor<1, dim> t;
          surface.evaluate(s, eta, r, dr, y, t);
          const double distance = (x - y).norm();
          if (distance < closest_distance ||
              (distance == closest_distance && position < closest_position))
            {
              closest_distance = distance;
              closest_position = position;
              closest.segment  = s;
              closest.eta      = eta;
              Tensor<1, dim> n;
              n[0]           = t[1];
              n[1]           = -t[0];
              closest.normal = segment.normal_orientation * n / n.norm();
              closest.gap    = (x - y) * closest.normal;
            }
        }
      return closest;
    }

    // Traction assembly for a penetrating Gauss point: the traction
    // pressure n times the point's weight acts on the point's own body, the
    // opposite on the other body at the projection (where the nodal
    // functions r were evaluated), each distributed with the nodal
    // functions there. Returns the force on the own body.
    template <int dim>
    Tensor<1, dim>
    add_contact_traction(const BoundarySegment<dim>        &segment,
                         const SurfaceQuadraturePoint<dim> &point,
                         const BoundarySegment<dim>        &other_segment,
                         const std::vector<double>         &r,
                         const Tensor<1, dim>              &normal,
                         const double                       pressure,
                         Vector<double>                    *f,
                         Vector<double>                    *f_other)
    {
      const Tensor<1, dim> force = pressure * point.weight * normal;
      if (f != nullptr)
        distribute_point_force(segment, point.shape_values, force, *f);
      if (f_other != nullptr)
        distribute_point_force(other_segment, r, -force, *f_other);
      return force;
    }
  } // namespace

  namespace internal
  {
    // The points' outcomes of every rank in memory the ranks of one node
    // map (MPI_Win_allocate_shared, in a passive epoch for the whole run):
    // per rank a count of its evaluations, each on a cache line of its own,
    // then two slots of outcomes per rank, by the parity of the evaluation.
    // A rank writes its outcomes in place, publishes its count (release)
    // and reads the others' slots once their counts reach its own
    // (acquire). The parity keeps a rank's writes off the slots the others
    // may still read: it writes a slot again two evaluations on, after the
    // others published the evaluation between, which each does only after
    // it has added the forces of this one.
    struct SharedOutcomeWindow
    {
      MPI_Comm   node   = MPI_COMM_NULL;
      MPI_Win    window = MPI_WIN_NULL;
      long long *counts = nullptr; // rank p's at counts[p * count_stride]
      double    *slots  = nullptr;
      static constexpr unsigned int count_stride = 8; // 64 bytes

      // Leaves node == MPI_COMM_NULL where the ranks are not all on one
      // node.
      SharedOutcomeWindow(const MPI_Comm     communicator,
                          const unsigned int rank,
                          const unsigned int n_ranks,
                          const std::size_t  doubles_per_slot)
      {
        int ierr = MPI_Comm_split_type(communicator,
                                       MPI_COMM_TYPE_SHARED,
                                       rank,
                                       MPI_INFO_NULL,
                                       &node);
        AssertThrowMPI(ierr);
        int node_size = 0;
        MPI_Comm_size(node, &node_size);
        if (static_cast<unsigned int>(node_size) != n_ranks)
          {
            MPI_Comm_free(&node);
            node = MPI_COMM_NULL;
            return;
          }
        const std::size_t count_bytes =
          n_ranks * count_stride * sizeof(long long);
        const std::size_t bytes =
          count_bytes + 2 * n_ranks * doubles_per_slot * sizeof(double) + 64;
        char *base = nullptr;
        ierr       = MPI_Win_allocate_shared(rank == 0 ? bytes : 0,
                                       1,
                                       MPI_INFO_NULL,
                                       node,
                                       &base,
                                       &window);
        AssertThrowMPI(ierr);
        MPI_Aint size = 0;
        int      unit = 0;
        ierr          = MPI_Win_shared_query(window, 0, &size, &unit, &base);
        AssertThrowMPI(ierr);
        AssertThrow(static_cast<std::size_t>(size) == bytes,
                    ExcInternalError());
        // A cache line's boundary first (the counts apart).
        base = reinterpret_cast<char *>(
          (reinterpret_cast<std::uintptr_t>(base) + 63) / 64 * 64);
        counts = reinterpret_cast<long long *>(base);
        slots  = reinterpret_cast<double *>(base + count_bytes);
        ierr   = MPI_Win_lock_all(MPI_MODE_NOCHECK, window);
        AssertThrowMPI(ierr);
        if (rank == 0)
          std::fill(counts, counts + n_ranks * count_stride, 0LL);
        MPI_Win_sync(window);
        MPI_Barrier(node);
        MPI_Win_sync(window);
      }

      ~SharedOutcomeWindow()
      {
        int finalized = 1;
        MPI_Finalized(&finalized);
        if (finalized || node == MPI_COMM_NULL)
          return;
        MPI_Win_unlock_all(window);
        MPI_Win_free(&window);
        MPI_Comm_free(&node);
      }

      // This rank's outcomes of evaluation `count` are written: published,
      // and the wait until every rank has published as many.
      void
      publish_and_wait(const unsigned int rank,
                       const unsigned int n_ranks,
                       const long long    count) const
      {
        __atomic_store_n(counts + rank * count_stride, count, __ATOMIC_RELEASE);
        for (unsigned int p = 0; p < n_ranks; ++p)
          for (unsigned int spins = 0;
               __atomic_load_n(counts + p * count_stride, __ATOMIC_ACQUIRE) <
               count;
               ++spins)
            if (spins > 1000)
              std::this_thread::yield(); // (more ranks than cores)
      }
    };
  } // namespace internal

  template <int dim>
  PenaltyContact<dim>::PenaltyContact(
    const ContactSettings            &settings,
    std::vector<BoundarySegment<dim>> surface_of_body_0,
    std::vector<BoundarySegment<dim>> surface_of_body_1)
    : settings(settings)
  {
    AssertThrow(dim == 2, ExcMessage("contact is implemented for dim = 2"));
    AssertThrow(settings.penalty > 0.,
                ExcMessage("contact penalty " +
                           std::to_string(settings.penalty) +
                           " is not allowed: it must be positive"));
    AssertThrow(!surface_of_body_0.empty() && !surface_of_body_1.empty(),
                ExcMessage("contact: a contact surface has no faces; check "
                           "the boundary ids declared as contact surfaces"));
    surfaces[0].segments = std::move(surface_of_body_0);
    surfaces[1].segments = std::move(surface_of_body_1);
    for (unsigned int b = 0; b < 2; ++b)
      {
        Surface &surface = surfaces[b];
        surface.points   = surface_quadrature(surface.segments,
                                            settings.n_quadrature_points,
                                            &surface.reference_lengths);
        surface.nodes    = SurfaceNodes<dim>(surface.segments, surface.points);
        point_pressure[b].resize(surface.points.size());
        point_gap[b].resize(surface.points.size());
        // The bipenalty's bound needs max sum_k |R_k| over every point a
        // projection can reach: sampled at 101 points per segment (1 for
        // the non-negative NURBS, 1.25 for quadratic Lagrange faces).
        std::vector<double> r, dr;
        for (const auto &segment : surface.segments)
          for (unsigned int i = 0; i <= 100; ++i)
            {
              evaluate_segment_basis(segment, i / 100., r, dr);
              double sum = 0.;
              for (const double value : r)
                sum += std::abs(value);
              lebesgue_constant = std::max(lebesgue_constant, sum);
            }
      }
  }

  template <int dim>
  PenaltyContact<dim>::~PenaltyContact() = default;

  template <int dim>
  void
  PenaltyContact<dim>::set_bipenalty_mass(const double eps_m)
  {
    AssertThrow(eps_m >= 0. && std::isfinite(eps_m),
                ExcMessage("bipenalty mass " + std::to_string(eps_m) +
                           " kg/m^2 is not allowed: it must be >= 0"));
    AssertThrow(eps_m == 0. || settings.damping_ratio == 0.,
                ExcMessage("the bipenalty and the contact damping cannot be "
                           "combined"));
    settings.bipenalty_mass = eps_m;
  }

  template <int dim>
  double
  PenaltyContact<dim>::bipenalty_mass() const
  {
    return settings.bipenalty_mass;
  }

  template <int dim>
  double
  PenaltyContact<dim>::bipenalty_stiffness() const
  {
    // Per active pair: eps_pass w ((a - b) . n)^2 <= 2 eps_pass w (a.n^2 +
    // b.n^2), and (sum_k R_k x_k)^2 <= s^2 sum_k |R_k|/s x_k^2 with s =
    // sum_k |R_k| <= Lambda, while the mass penalty of the pair is eps_m w
    // sum_k |R_k|/s |x_k|^2 on each side.
    return 2. * lebesgue_constant * lebesgue_constant * penalty_per_pass();
  }

  template <int dim>
  std::vector<SurfaceSpring<dim>>
  PenaltyContact<dim>::surface_springs() const
  {
    return {{&surfaces[0].segments, 4. * penalty_per_pass()},
            {&surfaces[1].segments, 4. * penalty_per_pass()}};
  }

  template <int dim>
  double
  PenaltyContact<dim>::penalty_per_pass() const
  {
    return settings.penalty_per_pass == PenaltyPerPass::half ?
             0.5 * settings.penalty :
             settings.penalty;
  }

  template <int dim>
  unsigned int
  PenaltyContact<dim>::n_bodies() const
  {
    return 2;
  }

  template <int dim>
  std::string
  PenaltyContact<dim>::description() const
  {
    std::ostringstream s;
    s << "two-body penalty " << settings.penalty << " Pa/m, "
      << settings.n_quadrature_points
      << " Gauss points per face, penalty per pass " << penalty_per_pass()
      << " Pa/m";
    if (settings.damping_ratio > 0.)
      s << ", contact damping " << settings.damping_ratio << " of critical";
    if (settings.bipenalty_mass > 0.)
      s << ", bipenalty: mass penalty " << settings.bipenalty_mass
        << " kg/m^2 per pass (eps_pass / eps_m = "
        << penalty_per_pass() / settings.bipenalty_mass << " 1/s^2)";
    return s.str();
  }

  template <int dim>
  unsigned int
  PenaltyContact<dim>::n_surface_points() const
  {
    return surfaces[0].points.size() + surfaces[1].points.size();
  }

  template <int dim>
  void
  PenaltyContact<dim>::set_surface_masses(
    const std::vector<const Vector<double> *> &nodal_masses)
  {
    AssertDimension(nodal_masses.size(), 2);
    for (unsigned int b = 0; b < 2; ++b)
      surfaces[b].mass_density =
        SurfaceMassDensity<dim>(surfaces[b].nodes, *nodal_masses[b]);
  }

  template <int dim>
  void
  PenaltyContact<dim>::distribute_points(const MPI_Comm      comm,
                                         const PointExchange how)
  {
    communicator = comm;
    n_ranks      = Utilities::MPI::n_mpi_processes(comm);
    rank         = Utilities::MPI::this_mpi_process(comm);
    shared_outcomes.reset();
    n_evaluations = 0;
    // Two ranks and surfaces of as many points: rank b projects body b's
    // points, and searches only the other body's surface.
    points_by_body =
      n_ranks == 2 && surfaces[0].points.size() == surfaces[1].points.size();
    if (n_ranks > 1 && how == PointExchange::automatic)
      {
        const unsigned int n_points =
          surfaces[0].points.size() + surfaces[1].points.size();
        const unsigned int per_rank = (n_points + n_ranks - 1) / n_ranks;
        auto window = std::make_shared<internal::SharedOutcomeWindow>(
          comm,
          rank,
          n_ranks,
          std::size_t(per_rank) * (sizeof(PointOutcome) / sizeof(double)));
        if (window->node != MPI_COMM_NULL)
          shared_outcomes = std::move(window);
      }
  }

  template <int dim>
  std::string
  PenaltyContact<dim>::point_exchange() const
  {
    return n_ranks == 1    ? "none" :
           shared_outcomes ? "shared memory" :
                             "messages";
  }

  template <int dim>
  double
  PenaltyContact<dim>::damping_ratio() const
  {
    return settings.damping_ratio;
  }

  template <int dim>
  ContactResult<dim>
  PenaltyContact<dim>::evaluate(
    const std::vector<ArrayView<const double>> &displacements,
    const std::vector<const Vector<double> *>  &velocities,
    const std::vector<Vector<double> *>        &forces,
    const bool                                  record_points) const
  {
    AssertDimension(displacements.size(), 2);
    AssertDimension(forces.size(), 2);
    const bool damped = settings.damping_ratio > 0.;
    AssertThrow(!damped || (velocities.size() == 2 &&
                            !surfaces[0].mass_density.empty() &&
                            !surfaces[1].mass_density.empty()),
                ExcMessage("contact damping needs the velocities and the "
                           "surface masses of both bodies"));
    // The two surfaces side by side (each task touches its own). A rank
    // that projects the points of one body only (points_by_body) needs
    // that surface's points and the other's search structure only.
    {
      Threads::TaskGroup<void> updates;
      for (unsigned int b = 0; b < 2; ++b)
        {
          if (!current_surfaces[b])
            current_surfaces[b] =
              std::make_unique<CurrentSurface<dim>>(surfaces[b].segments,
                                                    surfaces[b].points);
          const bool searched = !points_by_body || b != rank;
          const bool points   = !points_by_body || b == rank;
          updates +=
            Threads::new_task([this, &displacements, b, searched, points]() {
              current_surfaces[b]->update(surfaces[b].segments,
                                          surfaces[b].reference_lengths,
                                          displacements[b],
                                          searched,
                                          points);
            });
        }
      updates.join_all();
    }
    const std::array<const CurrentSurface<dim> *, 2> current = {
      {current_surfaces[0].get(), current_surfaces[1].get()}};

    // Both passes see (nearly) the same gap: the pressure they carry
    // together is twice the pressure of one pass, 2 eps_pass |g| undamped.
    const double eps = penalty_per_pass();

    // The projections of this rank's points g = rank, rank + n_ranks, ...
    // (g numbers the points of body 0, then those of body 1), or with
    // points_by_body those of body `rank`, over the threads: each point's
    // outcome has a slot of its own (rank g % n_ranks's slot g / n_ranks,
    // or by body rank g / per_rank's slot g % per_rank), and the forces are
    // added below in one order whatever the threads.
    const unsigned int n_points_0  = surfaces[0].points.size();
    const unsigned int n_points    = n_points_0 + surfaces[1].points.size();
    const unsigned int per_rank    = (n_points + n_ranks - 1) / n_ranks;
    const unsigned int point_step  = points_by_body ? 1 : n_ranks;
    const unsigned int first_point = points_by_body ? rank * per_rank : rank;
    // (Each point below marks its own slot first; the padding is not read.)
    // Ranks on one node: the slots in shared memory, by the parity of
    // this evaluation.
    PointOutcome *own_slots = nullptr;
    PointOutcome *all_slots = nullptr;
    if (shared_outcomes)
      {
        all_slots = reinterpret_cast<PointOutcome *>(shared_outcomes->slots) +
                    std::size_t(n_evaluations % 2) * n_ranks * per_rank;
        own_slots = all_slots + std::size_t(rank) * per_rank;
      }
    else
      {
        own_outcomes.resize(per_rank);
        own_slots = own_outcomes.data();
      }
    const auto project_points = [&](const unsigned int first,
                                    const unsigned int end) {
      std::vector<double>                          r, dr;
      std::vector<unsigned int>                    candidates;
      std::vector<std::pair<double, unsigned int>> order;
      for (unsigned int k = first; k < end; ++k)
        {
          const unsigned int g = first_point + k * point_step;
          if (g >= n_points)
            break;
          const unsigned int body  = (g < n_points_0) ? 0 : 1;
          const unsigned int other = 1 - body;
          const unsigned int q     = (body == 0) ? g : g - n_points_0;
          own_slots[k].segment     = -1.;
          const Point<dim> &x      = current[body]->point_position(q);
          if (!current[other]->may_have_candidates(x))
            continue;
          const auto &point = surfaces[body].points[q];
          current[other]->find_candidates(x, candidates);
          const Projection<dim> projection =
            project(*current[other], x, candidates, order, r, dr);
          if (projection.segment == numbers::invalid_unsigned_int ||
              !(projection.gap < 0.))
            continue;

          const double gap           = projection.gap;
          double       pressure      = -eps * gap;
          double       damping_power = 0.;
          if (damped)
            {
              const auto &segment = surfaces[body].segments[point.segment];
              const auto &other_segment =
                surfaces[other].segments[projection.segment];
              evaluate_segment_basis(other_segment, projection.eta, r, dr);
              // c_pass = xi sqrt(2 eps_pass mu): the two passes together
              // damp the pair's spring 2 eps_pass critically at xi = 1.
              const double mu_own =
                surfaces[body].mass_density(point.segment, point.shape_values);
              const double mu_other =
                surfaces[other].mass_density(projection.segment, r);
              const double mu = mu_own * mu_other / (mu_own + mu_other);
              const double damping =
                settings.damping_ratio * std::sqrt(2. * eps * mu);
              const double gap_rate =
                (point_velocity(segment,
                                point.shape_values,
                                *velocities[body]) -
                 point_velocity(other_segment, r, *velocities[other])) *
                projection.normal;
              pressure = damped_pressure(pressure,
                                         damping,
                                         gap_rate,
                                         point.weight,
                                         damping_power);
            }
          own_slots[k] = {double(projection.segment),
                          projection.eta,
                          {{projection.normal[0], projection.normal[1]}},
                          gap,
                          pressure,
                          damping_power};
        }
    };
    parallel::apply_to_subranges(0U, per_rank, project_points, 64);
    const PointOutcome *outcomes = own_slots;
    if (shared_outcomes)
      {
        shared_outcomes->publish_and_wait(rank, n_ranks, ++n_evaluations);
        outcomes = all_slots;
      }
    else if (n_ranks > 1)
      {
        all_outcomes.resize(std::size_t(per_rank) * n_ranks);
        const int n_doubles =
          per_rank * (sizeof(PointOutcome) / sizeof(double));
        const int error = MPI_Allgather(own_outcomes.data(),
                                        n_doubles,
                                        MPI_DOUBLE,
                                        all_outcomes.data(),
                                        n_doubles,
                                        MPI_DOUBLE,
                                        communicator);
        AssertThrowMPI(error);
        outcomes = all_outcomes.data();
      }

    // Every point's forces, in the order of one process.
    std::vector<double> r, dr;
    ContactResult<dim>  result;
    for (unsigned int body = 0; body < 2; ++body)
      {
        std::fill(point_pressure[body].begin(), point_pressure[body].end(), 0.);
        std::fill(point_gap[body].begin(), point_gap[body].end(), 0.);
      }
    for (unsigned int g = 0; g < n_points; ++g)
      {
        const PointOutcome &outcome =
          points_by_body ?
            outcomes[g] :
            outcomes[std::size_t(g % n_ranks) * per_rank + g / n_ranks];
        if (outcome.segment < 0.)
          continue;
        const unsigned int body           = (g < n_points_0) ? 0 : 1;
        const unsigned int other          = 1 - body;
        const unsigned int q              = (body == 0) ? g : g - n_points_0;
        const double       sign_on_body_0 = (body == 0) ? 1. : -1.;
        const auto        &point          = surfaces[body].points[q];
        const unsigned int other_index    = (unsigned int)(outcome.segment);
        const auto        &segment   = surfaces[body].segments[point.segment];
        const auto    &other_segment = surfaces[other].segments[other_index];
        Tensor<1, dim> normal;
        for (unsigned int d = 0; d < dim; ++d)
          normal[d] = outcome.normal[d];
        const double gap      = outcome.gap;
        const double pressure = outcome.pressure;
        // (r: the other segment's functions at the projection, which only
        // its forces, the bipenalty and the tangent read.)
        if (forces[other] != nullptr || settings.bipenalty_mass > 0. ||
            this->linearize)
          evaluate_segment_basis(other_segment, outcome.eta, r, dr);
        if (damped)
          result.damping_power += outcome.damping_power;
        const Tensor<1, dim> force = add_contact_traction(segment,
                                                          point,
                                                          other_segment,
                                                          r,
                                                          normal,
                                                          pressure,
                                                          forces[body],
                                                          forces[other]);
        if (settings.bipenalty_mass > 0.)
          {
            // Lumped: eps_m w |R_k| / sum |R| per component on both
            // sides (NURBS: eps_m w R_k).
            const auto add_mass = [&](const BoundarySegment<dim> &seg,
                                      const std::vector<double>  &values,
                                      const unsigned int          side) {
              double sum = 0.;
              for (const double value : values)
                sum += std::abs(value);
              for (unsigned int k = 0; k < values.size(); ++k)
                for (unsigned int d = 0; d < dim; ++d)
                  result.penalty_masses[side].emplace_back(
                    seg.node_dofs[k][d],
                    settings.bipenalty_mass * point.weight *
                      std::abs(values[k]) / sum);
            };
            add_mass(segment, point.shape_values, body);
            add_mass(other_segment, r, other);
          }
        if (this->linearize)
          {
            auto &tangent = result.linearization;
            tangent.add_term(eps * point.weight,
                             (std::uint64_t(body) << 63) |
                               (std::uint64_t(q) << 31) | other_index);
            tangent.add_gradient(segment, point.shape_values, normal, 1., body);
            tangent.add_gradient(other_segment, r, normal, -1., other);
          }
        point_pressure[body][q] = 2. * pressure;
        point_gap[body][q]      = gap;
        result.add_active_point(2. * pressure,
                                gap,
                                0.5 * eps * gap * gap * point.weight,
                                sign_on_body_0 * force);
      }
    if (record_points || this->pressures_at_every_step)
      for (unsigned int body = 0; body < 2; ++body)
        add_surface_pressure(surfaces[body].nodes,
                             surfaces[body].points,
                             point_pressure[body],
                             point_gap[body],
                             body,
                             record_points,
                             nodal_scratch,
                             field_scratch,
                             result);
    return result;
  }

  template struct ContactResult<2>;
  template class SurfaceNodes<2>;
  template double
  mean_surface_mass_density(const std::vector<BoundarySegment<2>> &,
                            const unsigned int,
                            const Vector<double> &);
  template class SurfaceMassDensity<2>;
  template void
  add_surface_pressure(const SurfaceNodes<2> &,
                       const std::vector<SurfaceQuadraturePoint<2>> &,
                       const std::vector<double> &,
                       const std::vector<double> &,
                       const unsigned int,
                       const bool,
                       std::vector<double> &,
                       std::vector<double> &,
                       ContactResult<2> &);
  template Tensor<1, 2>
  point_velocity(const BoundarySegment<2> &,
                 const std::vector<double> &,
                 const Vector<double> &);
  template class PenaltyContact<2>;
  template std::vector<SurfaceQuadraturePoint<2>>
  surface_quadrature(const std::vector<BoundarySegment<2>> &,
                     const unsigned int,
                     std::vector<double> *);
  template Point<2>
  current_position(const BoundarySegment<2> &,
                   const SurfaceQuadraturePoint<2> &,
                   const ArrayView<const double>);
  template void
  distribute_point_force(const BoundarySegment<2> &,
                         const std::vector<double> &,
                         const Tensor<1, 2> &,
                         Vector<double> &);
} // namespace isoimpact
