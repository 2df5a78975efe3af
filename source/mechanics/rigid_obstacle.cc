// Layer 4: rigid analytic obstacles and the penalty contact against them
// (see rigid_obstacle.h).
#include <deal.II/base/exceptions.h>

#include <isoimpact/mechanics/rigid_obstacle.h>

#include <cmath>
#include <sstream>

using namespace dealii;

namespace isoimpact
{
  template <int dim>
  RigidObstacle<dim>
  RigidObstacle<dim>::plane(const Point<dim>     &point,
                            const Tensor<1, dim> &normal)
  {
    const double length = normal.norm();
    AssertThrow(length > 0. && std::isfinite(length),
                ExcMessage("rigid plane: the normal must be a non-zero, "
                           "finite vector"));
    RigidObstacle obstacle;
    obstacle.kind        = Type::plane;
    obstacle.origin      = point;
    obstacle.unit_normal = normal / length;
    return obstacle;
  }

  template <int dim>
  RigidObstacle<dim>
  RigidObstacle<dim>::cylinder(const Point<dim> &center, const double radius)
  {
    AssertThrow(radius > 0. && std::isfinite(radius),
                ExcMessage("rigid cylinder: the radius " +
                           std::to_string(radius) + " must be positive"));
    RigidObstacle obstacle;
    obstacle.kind   = Type::cylinder;
    obstacle.origin = center;
    obstacle.radius = radius;
    return obstacle;
  }

  template <int dim>
  typename RigidObstacle<dim>::Type
  RigidObstacle<dim>::type() const
  {
    return kind;
  }

  template <int dim>
  double
  RigidObstacle<dim>::gap(const Point<dim> &x, Tensor<1, dim> &normal) const
  {
    if (kind == Type::plane)
      {
        normal = unit_normal;
        return (x - origin) * unit_normal;
      }
    const Tensor<1, dim> d        = x - origin;
    const double         distance = d.norm();
    if (distance > 0.)
      normal = d / distance;
    else
      {
        normal          = Tensor<1, dim>();
        normal[dim - 1] = 1.;
      }
    return distance - radius;
  }

  template <int dim>
  std::string
  RigidObstacle<dim>::description() const
  {
    std::ostringstream s;
    if (kind == Type::plane)
      s << "rigid plane through (" << origin << ") with normal (" << unit_normal
        << ")";
    else
      s << "rigid cylinder, centre (" << origin << "), radius " << radius
        << " m";
    return s.str();
  }



  template <int dim>
  RigidObstacleContact<dim>::RigidObstacleContact(
    const ObstacleContactSettings    &settings,
    const RigidObstacle<dim>         &obstacle,
    std::vector<BoundarySegment<dim>> surface)
    : settings(settings)
    , rigid_obstacle(obstacle)
    , segments(std::move(surface))
  {
    AssertThrow(settings.penalty > 0.,
                ExcMessage("obstacle penalty " +
                           std::to_string(settings.penalty) +
                           " is not allowed: it must be positive"));
    AssertThrow(!segments.empty(),
                ExcMessage("obstacle contact: the contact surface has no "
                           "faces; check the boundary id declared as contact "
                           "surface"));
    points = surface_quadrature(segments, settings.n_quadrature_points);
    nodes  = SurfaceNodes<dim>(segments, points);
    point_pressure.resize(points.size());
    point_gap.resize(points.size());
  }

  template <int dim>
  unsigned int
  RigidObstacleContact<dim>::n_bodies() const
  {
    return 1;
  }

  template <int dim>
  void
  RigidObstacleContact<dim>::set_surface_masses(
    const std::vector<const Vector<double> *> &nodal_masses)
  {
    AssertDimension(nodal_masses.size(), 1);
    mass_density = SurfaceMassDensity<dim>(nodes, *nodal_masses[0]);
  }

  template <int dim>
  double
  RigidObstacleContact<dim>::damping_ratio() const
  {
    return settings.damping_ratio;
  }

  template <int dim>
  ContactResult<dim>
  RigidObstacleContact<dim>::evaluate(
    const std::vector<ArrayView<const double>> &displacements,
    const std::vector<const Vector<double> *>  &velocities,
    const std::vector<Vector<double> *>        &forces,
    const bool                                  record_points) const
  {
    AssertDimension(displacements.size(), 1);
    AssertDimension(forces.size(), 1);
    const bool damped = settings.damping_ratio > 0.;
    AssertThrow(!damped || (velocities.size() == 1 && !mass_density.empty()),
                ExcMessage("contact damping needs the velocity and the "
                           "surface masses of the body"));
    const double       eps = settings.penalty;
    ContactResult<dim> result;
    std::fill(point_pressure.begin(), point_pressure.end(), 0.);
    std::fill(point_gap.begin(), point_gap.end(), 0.);
    for (unsigned int q = 0; q < points.size(); ++q)
      {
        const auto      &point   = points[q];
        const auto      &segment = segments[point.segment];
        const Point<dim> x = current_position(segment, point, displacements[0]);
        Tensor<1, dim>   n;
        const double     g = rigid_obstacle.gap(x, n);
        if (!(g < 0.))
          continue;
        // Traction -eps g n on the body, i.e. -dPi/dx with Pi = eps/2 g^2,
        // less the damping c dg/dt, c = xi 2 sqrt(eps mu), down to zero.
        double pressure = -eps * g;
        if (damped)
          {
            const double damping =
              settings.damping_ratio * 2. *
              std::sqrt(eps * mass_density(point.segment, point.shape_values));
            const double gap_rate =
              point_velocity(segment, point.shape_values, *velocities[0]) * n;
            pressure = result.damp(pressure, damping, gap_rate, point.weight);
          }
        const Tensor<1, dim> force = pressure * point.weight * n;
        if (forces[0] != nullptr)
          distribute_point_force(segment,
                                 point.shape_values,
                                 force,
                                 *forces[0]);
        if (this->linearize)
          {
            // grad g = R_k n (the obstacle's curvature term left out).
            result.linearization.add_term(eps * point.weight, q);
            result.linearization.add_gradient(segment,
                                              point.shape_values,
                                              n,
                                              1.,
                                              0);
          }
        point_pressure[q] = pressure;
        point_gap[q]      = g;
        result.add_active_point(pressure,
                                g,
                                0.5 * eps * g * g * point.weight,
                                force);
      }
    if (record_points || this->pressures_at_every_step)
      add_surface_pressure(nodes,
                           points,
                           point_pressure,
                           point_gap,
                           0,
                           record_points,
                           nodal_scratch,
                           field_scratch,
                           result);
    return result;
  }

  template <int dim>
  std::string
  RigidObstacleContact<dim>::description() const
  {
    std::ostringstream s;
    s << rigid_obstacle.description() << ", penalty " << settings.penalty
      << " Pa/m, " << settings.n_quadrature_points << " Gauss points per face";
    if (settings.damping_ratio > 0.)
      s << ", contact damping " << settings.damping_ratio << " of critical";
    return s.str();
  }

  template <int dim>
  const RigidObstacle<dim> &
  RigidObstacleContact<dim>::obstacle() const
  {
    return rigid_obstacle;
  }

  template <int dim>
  std::vector<SurfaceSpring<dim>>
  RigidObstacleContact<dim>::surface_springs() const
  {
    return {{&segments, settings.penalty}};
  }

  template <int dim>
  double
  RigidObstacleContact<dim>::penalty() const
  {
    return settings.penalty;
  }

  template <int dim>
  unsigned int
  RigidObstacleContact<dim>::n_points() const
  {
    return points.size();
  }

  template class RigidObstacle<2>;
  template class RigidObstacleContact<2>;
} // namespace isoimpact
