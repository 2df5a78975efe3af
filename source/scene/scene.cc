// Layer 6: building a scene.
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/scene/scene.h>

#include <cmath>
#include <limits>
#include <sstream>

using namespace dealii;

namespace isoimpact
{
  std::vector<ElasticBody<2> *>
  Scene::body_pointers() const
  {
    std::vector<ElasticBody<2> *> pointers;
    for (const auto &body : bodies)
      pointers.push_back(body.get());
    return pointers;
  }

  types::global_dof_index
  Scene::n_dofs() const
  {
    types::global_dof_index n = 0;
    for (const auto &body : bodies)
      n += body->n_dofs();
    return n;
  }

  Scene
  build_scene(const Parameters &parameters)
  {
    Scene scene;
    scene.symmetry_factor = parameters.symmetry_factor();

    for (unsigned int b = 0; b < parameters.n_bodies(); ++b)
      {
        const auto                  &body = parameters.bodies[b];
        std::vector<RollerCondition> rollers;
        if (body.symmetry_cut &&
            body.geometry.shape == BodyGeometry::Shape::half_disk)
          rollers.push_back({BodyGeometry::symmetry_boundary_id, 0});
        scene.bodies.push_back(std::make_unique<ElasticBody<2>>(
          "body" + std::to_string(b + 1),
          create_discretization<2>(parameters.method,
                                   body.geometry,
                                   parameters.degree,
                                   parameters.fea_element),
          body.material,
          parameters.mass_scheme,
          rollers,
          body.initial_velocity));
      }

    // Contact is searched only on the declared surfaces: the arcs.
    const auto  &obstacle          = parameters.obstacle;
    Tensor<1, 2> relative_velocity = -parameters.bodies[0].initial_velocity;
    if (obstacle.active())
      {
        std::vector<RigidObstacle<2>> rigid;
        if (obstacle.type == "cylinder")
          rigid.push_back(
            RigidObstacle<2>::cylinder(obstacle.center, obstacle.radius));
        else
          rigid.push_back(
            RigidObstacle<2>::plane(obstacle.point, obstacle.normal));
        if (obstacle.type == "channel")
          rigid.push_back(
            RigidObstacle<2>::plane(obstacle.opposite_point, -obstacle.normal));
        ObstacleContactSettings settings;
        settings.penalty             = obstacle.penalty;
        settings.n_quadrature_points = parameters.contact.n_quadrature_points;
        settings.damping_ratio       = parameters.contact.damping_ratio;
        for (const auto &wall : rigid)
          {
            scene.contacts.push_back(std::make_unique<RigidObstacleContact<2>>(
              settings,
              wall,
              scene.bodies[0]->discretization().boundary_segments(
                BodyGeometry::curved_boundary_id)));
            scene.interactions.push_back({scene.contacts.back().get(), 0});
          }
      }
    else
      {
        scene.contacts.push_back(std::make_unique<PenaltyContact<2>>(
          parameters.contact,
          scene.bodies[0]->discretization().boundary_segments(
            BodyGeometry::curved_boundary_id),
          scene.bodies[1]->discretization().boundary_segments(
            BodyGeometry::curved_boundary_id)));
        scene.interactions.push_back({scene.contacts.back().get(), 0, 1});
        relative_velocity += parameters.bodies[1].initial_velocity;
      }

    // The contact damping scales with the surface mass: the lumped masses
    // in use, or HRZ's for a consistent mass.
    if (parameters.contact.damping_ratio > 0.)
      {
        std::vector<Vector<double>> masses;
        for (const auto &body : scene.bodies)
          masses.push_back(body->lumped_masses().size() > 0 ?
                             body->lumped_masses() :
                             assemble_lumped_mass(body->discretization(),
                                                  body->material().density,
                                                  MassScheme::hrz,
                                                  body->constraints()));
        // scene.contacts[c] is the model of scene.interactions[c].
        for (unsigned int c = 0; c < scene.contacts.size(); ++c)
          {
            const auto &interaction = scene.interactions[c];
            std::vector<const Vector<double> *> model_masses = {
              &masses[interaction.first_body]};
            if (interaction.contact->n_bodies() == 2)
              model_masses.push_back(&masses[interaction.second_body]);
            scene.contacts[c]->set_surface_masses(model_masses);
          }
      }

    if (relative_velocity.norm() > 0.)
      scene.impact_direction = relative_velocity / relative_velocity.norm();
    else
      scene.impact_direction[1] = 1.;

    if (parameters.approach_law != "none")
      {
        std::array<ElasticCylinder, 2> cylinders;
        for (unsigned int b = 0; b < parameters.n_bodies(); ++b)
          {
            const auto &body = parameters.bodies[b];
            cylinders[b]     = {body.geometry.radius,
                                body.material.youngs_modulus,
                                body.material.poisson_ratio,
                                body.material.density};
          }
        double closing_speed = relative_velocity.norm();
        if (obstacle.type == "plane")
          {
            // The mirror image of body 1 in the plane, approaching at twice
            // the normal speed: the plane is the symmetry line of that
            // impact, which has the same force history.
            cylinders[1]  = cylinders[0];
            closing_speed = -2. * (parameters.bodies[0].initial_velocity *
                                   obstacle.normal / obstacle.normal.norm());
          }
        else if (obstacle.type == "cylinder")
          {
            // A rigid cylinder as the limit of a stiff and heavy one.
            const double rigid = 1e12;
            cylinders[1]       = {obstacle.radius,
                                  rigid * cylinders[0].youngs_modulus,
                                  cylinders[0].poisson_ratio,
                                  rigid * cylinders[0].density};
          }
        scene.reference =
          std::make_unique<HertzImpactReference>(cylinders[0],
                                                 cylinders[1],
                                                 closing_speed,
                                                 approach_law_names.from_string(
                                                   parameters.approach_law));
      }
    return scene;
  }

  double
  select_time_step(const Parameters     &parameters,
                   const StableTimeStep &stable,
                   const std::string    &parameter_file)
  {
    const double bound = stable.bound();
    AssertThrow(bound > 0. && std::isfinite(bound),
                ExcMessage("the stable time step bound is " +
                           std::to_string(bound) +
                           " s: no step can be chosen"));
    if (parameters.automatic_time_step)
      return parameters.time_step_safety_factor * bound;
    if (parameters.time_step > bound && !parameters.allow_time_step_above_bound)
      {
        std::ostringstream message;
        message << "in parameter file '" << parameter_file
                << "': parameter 'Time integration/Time step' has the value "
                << parameters.time_step
                << "; it must not exceed the stable step bound " << bound
                << " s of this scene (power estimate " << stable.power_estimate
                << " s; both include the contact penalty). Use Time step = "
                   "auto, a smaller step, or set 'Allow time step above the "
                   "stable estimate = true'";
        throw InputError(message.str());
      }
    return parameters.time_step;
  }

  double
  faces_across_contact_zone(const Scene &scene, const Parameters &parameters)
  {
    if (!scene.reference)
      return 0.;
    const BodyGeometry &geometry = parameters.bodies[0].geometry;
    // Body 1 moves along the impact direction into its partner.
    const Point<2> first_contact =
      geometry.center + geometry.radius * scene.impact_direction;
    const auto segments = scene.bodies[0]->discretization().boundary_segments(
      BodyGeometry::curved_boundary_id);
    std::vector<double> r, dr;
    double              nearest = std::numeric_limits<double>::max();
    double              length  = 0.;
    for (const auto &segment : segments)
      {
        std::array<Point<2>, 2> ends;
        for (unsigned int e = 0; e < 2; ++e)
          {
            evaluate_segment_basis(segment, double(e), r, dr);
            for (unsigned int k = 0; k < r.size(); ++k)
              ends[e] += r[k] * segment.node_positions[k];
          }
        const double distance = std::min(ends[0].distance(first_contact),
                                         ends[1].distance(first_contact));
        if (distance < nearest)
          nearest = distance, length = ends[0].distance(ends[1]);
      }
    return length > 0. ? 2. * scene.reference->half_width_at_peak() / length :
                         0.;
  }
} // namespace isoimpact
