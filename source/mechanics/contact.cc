// Layer 4: symmetric two-pass penalty contact (see contact.h).
#include <deal.II/base/exceptions.h>
#include <deal.II/base/quadrature_lib.h>

#include <isoimpact/mechanics/contact.h>

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>

#include <cmath>
#include <limits>
#include <sstream>

using namespace dealii;

namespace isoimpact
{
  namespace bg  = boost::geometry;
  namespace bgi = boost::geometry::index;

  PenaltyPerPass
  penalty_per_pass_from_string(const std::string &name)
  {
    if (name == "half")
      return PenaltyPerPass::half;
    if (name == "full")
      return PenaltyPerPass::full;
    AssertThrow(false,
                ExcMessage("unknown penalty per pass '" + name +
                           "': allowed are half, full"));
    return PenaltyPerPass::half;
  }

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
                   const Vector<double>              &u)
  {
    Point<dim> x;
    for (unsigned int k = 0; k < point.shape_values.size(); ++k)
      for (unsigned int d = 0; d < dim; ++d)
        x[d] += point.shape_values[k] *
                (segment.node_positions[k][d] + u(segment.node_dofs[k][d]));
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
  struct PenaltyContact<dim>::Surface
  {
    using BoostPoint = bg::model::point<double, 2, bg::cs::cartesian>;
    using Box        = bg::model::box<BoostPoint>;

    std::vector<BoundarySegment<dim>>        segments;
    std::vector<double>                      reference_lengths;
    std::vector<SurfaceQuadraturePoint<dim>> slave_points;

    // Scratch of one evaluation: current node positions per segment and the
    // R-tree of their bounding boxes.
    mutable std::vector<std::vector<Point<dim>>> current_nodes;
    mutable bgi::rtree<std::pair<Box, unsigned int>, bgi::quadratic<16>> tree;

    Surface(std::vector<BoundarySegment<dim>> segments_in,
            const unsigned int                n_quadrature_points)
      : segments(std::move(segments_in))
      , slave_points(
          surface_quadrature(segments, n_quadrature_points, &reference_lengths))
    {
      current_nodes.resize(segments.size());
    }

    void
    update_current_configuration(const Vector<double> &u) const
    {
      std::vector<std::pair<Box, unsigned int>> boxes;
      boxes.reserve(segments.size());
      for (unsigned int s = 0; s < segments.size(); ++s)
        {
          const auto &segment = segments[s];
          auto       &nodes   = current_nodes[s];
          nodes.resize(segment.node_positions.size());
          Point<dim> lower, upper;
          for (unsigned int d = 0; d < dim; ++d)
            {
              lower[d] = std::numeric_limits<double>::max();
              upper[d] = -std::numeric_limits<double>::max();
            }
          for (unsigned int k = 0; k < nodes.size(); ++k)
            {
              for (unsigned int d = 0; d < dim; ++d)
                {
                  nodes[k][d] =
                    segment.node_positions[k][d] + u(segment.node_dofs[k][d]);
                  lower[d] = std::min(lower[d], nodes[k][d]);
                  upper[d] = std::max(upper[d], nodes[k][d]);
                }
            }
          // Lagrange curves may leave the hull of their nodes, and a
          // penetrating point lies inside the other body: inflate the box.
          const double margin = 0.5 * reference_lengths[s];
          boxes.emplace_back(
            Box(BoostPoint(lower[0] - margin, lower[1] - margin),
                BoostPoint(upper[0] + margin, upper[1] + margin)),
            s);
        }
      tree = decltype(tree)(boxes.begin(), boxes.end()); // bulk loading
    }

    // Position and tangent of segment s at eta, current configuration.
    void
    evaluate(const unsigned int   s,
             const double         eta,
             std::vector<double> &r,
             std::vector<double> &dr,
             Point<dim>          &x,
             Tensor<1, dim>      &tangent) const
    {
      evaluate_segment_basis(segments[s], eta, r, dr);
      x       = Point<dim>();
      tangent = Tensor<1, dim>();
      for (unsigned int k = 0; k < r.size(); ++k)
        {
          x += r[k] * current_nodes[s][k];
          tangent += dr[k] * current_nodes[s][k];
        }
    }

    // Closest point of segment s to x: Gauss-Newton on
    // (x - x_s(eta)) . x_s'(eta) = 0 from the best of a few samples; if it
    // does not converge, a sampled golden-section search on the distance.
    double
    closest_point(const unsigned int   s,
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
  };

  template <int dim>
  PenaltyContact<dim>::PenaltyContact(
    const ContactSettings            &settings,
    std::vector<BoundarySegment<dim>> first_surface,
    std::vector<BoundarySegment<dim>> second_surface)
    : settings(settings)
  {
    AssertThrow(dim == 2, ExcMessage("contact is implemented for dim = 2"));
    AssertThrow(settings.penalty > 0.,
                ExcMessage("contact penalty " +
                           std::to_string(settings.penalty) +
                           " is not allowed: it must be positive"));
    AssertThrow(!first_surface.empty() && !second_surface.empty(),
                ExcMessage("contact: a contact surface has no faces; check "
                           "the boundary ids declared as contact surfaces"));
    surfaces[0] = std::make_unique<Surface>(std::move(first_surface),
                                            settings.n_quadrature_points);
    surfaces[1] = std::make_unique<Surface>(std::move(second_surface),
                                            settings.n_quadrature_points);
  }

  template <int dim>
  PenaltyContact<dim>::~PenaltyContact() = default;

  template <int dim>
  std::vector<SurfaceSpring<dim>>
  PenaltyContact<dim>::surface_springs() const
  {
    return {{&surfaces[0]->segments, 4. * penalty_per_pass()},
            {&surfaces[1]->segments, 4. * penalty_per_pass()}};
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
  ContactResult<dim>
  PenaltyContact<dim>::evaluate(
    const std::vector<const Vector<double> *> &displacements,
    const std::vector<Vector<double> *>       &forces,
    const bool                                 record_points) const
  {
    AssertDimension(displacements.size(), 2);
    AssertDimension(forces.size(), 2);
    return add_forces(*displacements[0],
                      *displacements[1],
                      *forces[0],
                      *forces[1],
                      record_points);
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
    return s.str();
  }

  template <int dim>
  unsigned int
  PenaltyContact<dim>::n_slave_points() const
  {
    return surfaces[0]->slave_points.size() + surfaces[1]->slave_points.size();
  }

  template <int dim>
  ContactResult<dim>
  PenaltyContact<dim>::add_forces(const Vector<double> &u_first,
                                  const Vector<double> &u_second,
                                  Vector<double>       &f_first,
                                  Vector<double>       &f_second,
                                  const bool            record_points) const
  {
    surfaces[0]->update_current_configuration(u_first);
    surfaces[1]->update_current_configuration(u_second);
    const std::array<Vector<double> *, 2> f = {{&f_first, &f_second}};

    const double eps = penalty_per_pass();
    // Both passes see (nearly) the same gap: the pressure they carry
    // together is 2 eps_pass |g|.
    const double reported_penalty = 2. * eps;

    ContactResult<dim>  result;
    std::vector<double> r, dr;
    using Candidate = std::pair<typename Surface::Box, unsigned int>;
    std::vector<Candidate> candidates;

    for (unsigned int pass = 0; pass < 2; ++pass)
      {
        const Surface &slave  = *surfaces[pass];
        const Surface &master = *surfaces[1 - pass];
        const double   sign   = (pass == 0) ? 1. : -1.; // force on first

        for (const auto &point : slave.slave_points)
          {
            // Current position of the Gauss point.
            const auto &segment = slave.segments[point.segment];
            Point<dim>  x;
            for (unsigned int k = 0; k < point.shape_values.size(); ++k)
              x +=
                point.shape_values[k] * slave.current_nodes[point.segment][k];

            candidates.clear();
            master.tree.query(bgi::intersects(
                                typename Surface::BoostPoint(x[0], x[1])),
                              std::back_inserter(candidates));

            double         best_distance = std::numeric_limits<double>::max();
            double         gap           = 0.;
            unsigned int   best_segment  = numbers::invalid_unsigned_int;
            double         best_eta      = 0.;
            Tensor<1, dim> best_normal;
            for (const auto &candidate : candidates)
              {
                const unsigned int s   = candidate.second;
                const double       eta = master.closest_point(s, x, r, dr);
                const auto        &ms  = master.segments[s];
                if ((eta <= 0. && ms.free_end[0]) ||
                    (eta >= 1. && ms.free_end[1]))
                  continue; // beyond the end of the master surface
                Point<dim>     y;
                Tensor<1, dim> t;
                master.evaluate(s, eta, r, dr, y, t);
                const double distance = (x - y).norm();
                if (distance < best_distance)
                  {
                    best_distance = distance;
                    best_segment  = s;
                    best_eta      = eta;
                    Tensor<1, dim> n;
                    n[0]        = t[1];
                    n[1]        = -t[0];
                    best_normal = ms.normal_orientation * n / n.norm();
                    gap         = (x - y) * best_normal;
                  }
              }
            if (best_segment == numbers::invalid_unsigned_int || !(gap < 0.))
              continue;

            // Penalty traction eps |g| n on the slave, the opposite on the
            // master, distributed with the nodal functions at both points.
            const double         pressure = -eps * gap;
            const Tensor<1, dim> traction =
              pressure * point.weight * best_normal;
            distribute_point_force(segment,
                                   point.shape_values,
                                   traction,
                                   *f[pass]);
            evaluate_segment_basis(master.segments[best_segment],
                                   best_eta,
                                   r,
                                   dr);
            distribute_point_force(master.segments[best_segment],
                                   r,
                                   -traction,
                                   *f[1 - pass]);

            result.energy += 0.5 * eps * gap * gap * point.weight;
            result.force_on_first_surface += sign * traction;
            result.max_pressure =
              std::max(result.max_pressure, -reported_penalty * gap);
            result.max_penetration = std::max(result.max_penetration, -gap);
            ++result.n_active_points;
            if (record_points)
              result.points.push_back(
                {point.reference_position, -reported_penalty * gap, gap, pass});
          }
      }
    return result;
  }

  template class PenaltyContact<2>;
  template std::vector<SurfaceQuadraturePoint<2>>
  surface_quadrature(const std::vector<BoundarySegment<2>> &,
                     const unsigned int,
                     std::vector<double> *);
  template Point<2>
  current_position(const BoundarySegment<2> &,
                   const SurfaceQuadraturePoint<2> &,
                   const Vector<double> &);
  template void
  distribute_point_force(const BoundarySegment<2> &,
                         const std::vector<double> &,
                         const Tensor<1, 2> &,
                         Vector<double> &);
} // namespace isoimpact
