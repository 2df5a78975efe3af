// Layer 4: a rigid, fixed, frictionless analytic obstacle and the penalty
// contact of one deformable body's contact boundary against it.
//
// Obstacles (2D):
//   plane:    a point p and a unit normal n pointing out of the obstacle
//             (into the half plane where the body lives);
//             g(x) = (x - p) . n, normal n;
//   cylinder: centre c and radius R, the body lives outside the circle;
//             g(x) = |x - c| - R, normal (x - c) / |x - c|.
// g is the signed distance to the obstacle surface (negative inside).
//
// Contact: the Gauss points of the body's contact boundary (the same
// surface_quadrature() as the two-body contact, reference arc-length
// weights); where g < 0 the traction on the body is t = -eps g n (pressure
// eps |g|, pushing the body out along the obstacle's normal). The forces
// derive from the potential  Pi = int eps/2 g^2 ds_ref  (over g < 0), so
// central differences conserve energy as with the two-body contact.
//
// Penalty equivalence (doc/formulation.md): a symmetric two-body impact with
// the two-pass contact ('half': eps_N/2 per pass) has the pressure
// ~ eps_N |g_total|; against its rigid symmetry plane each body penetrates
// g_total / 2, so the same pressure needs eps_obstacle = 2 eps_N.
#ifndef isoimpact_rigid_obstacle_h
#define isoimpact_rigid_obstacle_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <isoimpact/discretization/discretization.h>
#include <isoimpact/mechanics/contact.h>

#include <string>
#include <vector>

namespace isoimpact
{
  template <int dim>
  class RigidObstacle
  {
  public:
    enum class Type
    {
      plane,
      cylinder
    };

    // A plane through `point` with the normal `normal` (normalised here;
    // it must not be zero).
    static RigidObstacle
    plane(const dealii::Point<dim>     &point,
          const dealii::Tensor<1, dim> &normal);

    // A cylinder (circle in 2D) of the given centre and radius (> 0); the
    // body is outside.
    static RigidObstacle
    cylinder(const dealii::Point<dim> &center, const double radius);

    Type
    type() const;

    // Signed distance g of x to the obstacle surface (negative inside the
    // obstacle) and the unit normal of the obstacle at the closest point
    // (pointing out of the obstacle). At the centre of a cylinder, where the
    // normal is undefined, the normal is +e_y.
    double
    gap(const dealii::Point<dim> &x, dealii::Tensor<1, dim> &normal) const;

    std::string
    description() const;

  private:
    RigidObstacle()             = default;
    Type                   kind = Type::plane;
    dealii::Point<dim>     origin; // plane point or cylinder centre
    dealii::Tensor<1, dim> unit_normal;
    double                 radius = 0.;
  };

  struct ObstacleContactSettings
  {
    double       penalty             = 2e5; // eps_obstacle, Pa/m
    unsigned int n_quadrature_points = 4;   // Gauss points per segment
    double       damping_ratio       = 0.;  // fraction of critical
  };

  /**
   * Penalty contact of one body's contact boundary against a rigid obstacle.
   * A ContactModel with n_bodies() = 1: the resultant reported
   * (force_on_body_0) is the force of the obstacle on the body; the
   * Gauss-point pressure eps |g| (less the damping), the energy int eps/2 g^2
   * ds_ref; recorded points have body 0.
   */
  template <int dim>
  class RigidObstacleContact : public ContactModel<dim>
  {
  public:
    RigidObstacleContact(const ObstacleContactSettings    &settings,
                         const RigidObstacle<dim>         &obstacle,
                         std::vector<BoundarySegment<dim>> surface);

    unsigned int
    n_bodies() const override;

    using ContactModel<dim>::evaluate;
    ContactResult<dim>
    evaluate(const std::vector<dealii::ArrayView<const double>> &displacements,
             const std::vector<const dealii::Vector<double> *>  &velocities,
             const std::vector<dealii::Vector<double> *>        &forces,
             const bool record_points) const override;

    void
    set_surface_masses(
      const std::vector<const dealii::Vector<double> *> &nodal_masses) override;

    double
    damping_ratio() const override;

    std::string
    description() const override;

    // The obstacle's penalty on the body's surface.
    std::vector<SurfaceSpring<dim>>
    surface_springs() const override;

    const RigidObstacle<dim> &
    obstacle() const;

    double
    penalty() const;

    unsigned int
    n_points() const;

  private:
    ObstacleContactSettings                  settings;
    RigidObstacle<dim>                       rigid_obstacle;
    std::vector<BoundarySegment<dim>>        segments;
    std::vector<SurfaceQuadraturePoint<dim>> points;
    SurfaceNodes<dim>                        nodes;
    SurfaceMassDensity<dim>                  mass_density;
    // Scratch of evaluate().
    mutable std::vector<double> point_pressure, point_gap, nodal_scratch,
      field_scratch;
  };
} // namespace isoimpact

#endif
