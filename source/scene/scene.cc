// Layer 6: building a scene.
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/stable_time_step.h>
#include <isoimpact/scene/scene.h>

#include <malloc.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <tuple>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    const char *body_names[2] = {"Body 1", "Body 2"};

    std::string
    text(const double value)
    {
      std::ostringstream out;
      out << value;
      return out.str();
    }

    std::string
    text(const Tensor<1, 2> &value)
    {
      std::ostringstream out;
      out << '(' << value[0] << ", " << value[1] << ')';
      return out.str();
    }

    [[noreturn]] void
    refuse(const std::string &parameter_file, const std::string &message)
    {
      throw InputError("in parameter file '" + parameter_file +
                       "': " + message);
    }

    // The parameters that place a body and their values.
    std::string
    placement(const Parameters &parameters, const unsigned int b)
    {
      const BodyGeometry &g = parameters.bodies[b].geometry;
      const std::string   s = std::string("'") + body_names[b] + "/";
      if (g.shape == BodyGeometry::Shape::rectangle)
        return s + "Lower left corner' = " + text(g.lower_left) + ", " + s +
               "Upper right corner' = " + text(g.upper_right);
      return s + "Center' = " + text(g.center) + ", " + s +
             "Radius' = " + text(g.radius);
    }

    // How deep a point lies inside a body: the distance to its boundary if
    // inside, else <= 0. Exact inside, as every shape is an intersection of
    // half planes and a disk.
    double
    depth_inside(const BodyGeometry &g, const Point<2> &p)
    {
      switch (g.shape)
        {
          case BodyGeometry::Shape::half_disk:
            return std::min(g.radius - p.distance(g.center),
                            p[0] - g.center[0]);
          case BodyGeometry::Shape::full_disk:
            return g.radius - p.distance(g.center);
          case BodyGeometry::Shape::rectangle:
            return std::min({p[0] - g.lower_left[0],
                             g.upper_right[0] - p[0],
                             p[1] - g.lower_left[1],
                             g.upper_right[1] - p[1]});
        }
      return 0.;
    }

    // Points along the boundary of a body, 20000 per curve or side: an
    // overlap deeper than 2e-8 of a radius is found.
    std::vector<Point<2>>
    boundary_points(const BodyGeometry &g)
    {
      const unsigned int    n = 20000;
      std::vector<Point<2>> points;
      const auto segment = [&](const Point<2> &a, const Point<2> &b) {
        for (unsigned int i = 0; i <= n; ++i)
          points.push_back(a + (double(i) / n) * (b - a));
      };
      const auto arc = [&](const double from, const double to) {
        for (unsigned int i = 0; i <= n; ++i)
          {
            const double angle = from + (to - from) * i / n;
            points.push_back(
              g.center + g.radius * Point<2>(std::cos(angle), std::sin(angle)));
          }
      };
      switch (g.shape)
        {
          case BodyGeometry::Shape::half_disk:
            arc(-numbers::PI / 2., numbers::PI / 2.);
            segment(Point<2>(g.center[0], g.center[1] - g.radius),
                    Point<2>(g.center[0], g.center[1] + g.radius));
            break;
          case BodyGeometry::Shape::full_disk:
            arc(-numbers::PI, numbers::PI);
            break;
          case BodyGeometry::Shape::rectangle:
            {
              const Point<2> a = g.lower_left, c = g.upper_right;
              const Point<2> b(c[0], a[1]), d(a[0], c[1]);
              segment(a, b), segment(b, c), segment(c, d), segment(d, a);
              break;
            }
        }
      return points;
    }

    // The velocity of the obstacle (0) or Body 2 relative to Body 1.
    Tensor<1, 2>
    relative_velocity(const Parameters &parameters)
    {
      Tensor<1, 2> velocity = -parameters.bodies[0].initial_velocity;
      if (!parameters.obstacle.active())
        velocity += parameters.bodies[1].initial_velocity;
      return velocity;
    }

    // The quasi-static Hertz impact of the parameters (deal.II exceptions
    // if it cannot describe it).
    std::unique_ptr<HertzImpactReference>
    make_reference(const Parameters &parameters)
    {
      const auto                    &obstacle = parameters.obstacle;
      std::array<ElasticCylinder, 2> cylinders;
      for (unsigned int b = 0; b < parameters.n_bodies(); ++b)
        {
          const auto &body = parameters.bodies[b];
          cylinders[b]     = {body.geometry.radius,
                              body.material.youngs_modulus,
                              body.material.poisson_ratio,
                              body.material.density};
        }
      double closing_speed = relative_velocity(parameters).norm();
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
      return std::make_unique<HertzImpactReference>(
        cylinders[0],
        cylinders[1],
        closing_speed,
        approach_law_names.from_string(parameters.approach_law));
    }

    // The deepest of the points by the given depth: (depth, point).
    template <typename Depth>
    std::pair<double, Point<2>>
    deepest(const std::vector<Point<2>> &points, const Depth &depth)
    {
      std::pair<double, Point<2>> result(-std::numeric_limits<double>::max(),
                                         Point<2>());
      for (const auto &p : points)
        if (const double d = depth(p); d > result.first)
          result = {d, p};
      return result;
    }

    // The bodies overlap, or Body 1 and the obstacle.
    void
    check_start_positions(const Parameters &parameters, const std::string &file)
    {
      const double tolerance = 1e-6 * parameters.smallest_body_size();
      const auto   allowed =
        "(allowed: " + text(tolerance) + " m, 1e-6 of the smallest body size)";
      if (!parameters.obstacle.active())
        {
          for (unsigned int a = 0; a < 2; ++a)
            {
              const auto &other = parameters.bodies[1 - a].geometry;
              const auto [depth, p] =
                deepest(boundary_points(parameters.bodies[a].geometry),
                        [&](const Point<2> &q) {
                          return depth_inside(other, q);
                        });
              if (depth > tolerance)
                refuse(file,
                       "Body 1 and Body 2 overlap at t = 0: the point " +
                         text(p) + " of " + body_names[a] +
                         "'s boundary lies " + text(depth) + " m inside " +
                         body_names[1 - a] + " (" + placement(parameters, 0) +
                         "; " + placement(parameters, 1) +
                         "). The bodies may touch but not overlap " + allowed +
                         ": move them apart");
            }
          return;
        }
      const auto &obstacle = parameters.obstacle;
      const auto &body     = parameters.bodies[0].geometry;
      const auto  points   = boundary_points(body);
      if (obstacle.type == "cylinder")
        {
          const std::string cylinder =
            "the rigid cylinder ('Obstacle/Center' = " + text(obstacle.center) +
            ", 'Obstacle/Radius' = " + text(obstacle.radius) + ")";
          if (const double depth = depth_inside(body, obstacle.center);
              depth > 0.)
            refuse(file,
                   cylinder + " has its centre " + text(depth) +
                     " m inside Body 1 (" + placement(parameters, 0) +
                     "): the obstacle must lie outside the body");
          const auto [depth, p] = deepest(points, [&](const Point<2> &q) {
            return obstacle.radius - q.distance(obstacle.center);
          });
          if (depth > tolerance)
            refuse(file,
                   "Body 1 starts inside " + cylinder + ": its point " +
                     text(p) + " lies " + text(depth) + " m inside (" +
                     placement(parameters, 0) +
                     "). Body 1 may touch the obstacle but not overlap " +
                     "it " + allowed + ": move it out");
          return;
        }
      const Tensor<1, 2> normal = obstacle.normal / obstacle.normal.norm();
      std::vector<std::tuple<Point<2>, Tensor<1, 2>, std::string>> walls = {
        {obstacle.point,
         normal,
         "the rigid plane through 'Obstacle/Point' = " + text(obstacle.point) +
           " with 'Obstacle/Normal' = " + text(obstacle.normal)}};
      if (obstacle.type == "channel")
        walls.emplace_back(obstacle.opposite_point,
                           -normal,
                           "the second plane of the channel, through "
                           "'Obstacle/Opposite point' = " +
                             text(obstacle.opposite_point));
      for (const auto &[point, n, name] : walls)
        {
          const auto [depth, p] = deepest(points, [&](const Point<2> &q) {
            return -((q - point) * n);
          });
          if (depth > tolerance)
            refuse(file,
                   "Body 1 starts inside " + name + ": its point " + text(p) +
                     " lies " + text(depth) + " m behind the plane (" +
                     placement(parameters, 0) +
                     "); the obstacle fills the side the normal points "
                     "away from. Body 1 may touch the plane but not cross "
                     "it " +
                     allowed + ": move it to the other side");
        }
    }

    // With an analytic reference: the scene it describes.
    void
    check_reference_scene(const Parameters &parameters, const std::string &file)
    {
      const std::string way_out =
        " or set 'Output/Analytic reference = none' to run without the "
        "analytic columns";
      const std::string reference =
        "'Output/Analytic reference' = " + parameters.approach_law +
        " describes a head-on impact ";
      const double tolerance = 1e-6 * parameters.smallest_body_size();
      const auto  &obstacle  = parameters.obstacle;
      const auto  &body      = parameters.bodies[0].geometry;
      // The partner's centre and radius (a plane: none), and the gap.
      if (obstacle.type != "plane")
        {
          const bool     cylinder = obstacle.type == "cylinder";
          const Point<2> center =
            cylinder ? obstacle.center : parameters.bodies[1].geometry.center;
          const double radius =
            cylinder ? obstacle.radius : parameters.bodies[1].geometry.radius;
          const std::string partner =
            cylinder ? "the rigid cylinder" : "Body 2";
          const double       distance = center.distance(body.center);
          const double       gap      = distance - body.radius - radius;
          const Tensor<1, 2> line     = (center - body.center) / distance;
          const Point<2>     first    = body.center + body.radius * line;
          const std::string  where =
            " (" + placement(parameters, 0) + "; " +
            (cylinder ? "'Obstacle/Center' = " + text(obstacle.center) +
                          ", 'Obstacle/Radius' = " + text(obstacle.radius) :
                        placement(parameters, 1)) +
            ")";
          if (gap > tolerance)
            refuse(file,
                   reference +
                     "of bodies that touch at t = 0, but Body 1 and " +
                     partner + " are " + text(gap) + " m apart" + where +
                     ": move them into contact" + way_out);
          for (unsigned int b = 0; b < parameters.n_bodies(); ++b)
            if (parameters.bodies[b].geometry.shape ==
                  BodyGeometry::Shape::half_disk &&
                first[0] < parameters.bodies[b].geometry.center[0] - tolerance)
              refuse(file,
                     reference +
                       "of disks that touch on their arcs, but the "
                       "first contact point " +
                       text(first) + " is not on the arc of half disk " +
                       body_names[b] + where + way_out);
          const Tensor<1, 2> closing = -relative_velocity(parameters);
          const double       along   = closing * line;
          if (!(along > 0. &&
                (closing - along * line).norm() <= 1e-6 * closing.norm()))
            refuse(file,
                   reference + "along the line of centres " + text(line) +
                     ", but the velocity of Body 1 relative to " + partner +
                     " is " + text(closing) + " ('Body 1/Initial velocity' = " +
                     text(parameters.bodies[0].initial_velocity) +
                     (cylinder ?
                        std::string() :
                        ", 'Body 2/Initial velocity' = " +
                          text(parameters.bodies[1].initial_velocity)) +
                     "): make it point along that line, towards " + partner +
                     way_out);
        }
      else
        {
          const Tensor<1, 2> normal = obstacle.normal / obstacle.normal.norm();
          const double       gap =
            (body.center - obstacle.point) * normal - body.radius;
          if (std::abs(gap) > tolerance)
            refuse(file,
                   reference +
                     "of Body 1 touching the rigid plane at t = 0, "
                     "but it is " +
                     text(gap) + " m from it (" + placement(parameters, 0) +
                     "; 'Obstacle/Point' = " + text(obstacle.point) +
                     ", 'Obstacle/Normal' = " + text(obstacle.normal) +
                     "): move it into contact" + way_out);
          const Point<2> first = body.center - body.radius * normal;
          if (body.shape == BodyGeometry::Shape::half_disk &&
              first[0] < body.center[0] - tolerance)
            refuse(file,
                   reference +
                     "of Body 1 touching the plane with its arc, but "
                     "the point of the full disk nearest the plane, " +
                     text(first) + ", is not on the half disk's arc (" +
                     placement(parameters, 0) + "; 'Obstacle/Normal' = " +
                     text(obstacle.normal) + ")" + way_out);
        }
      try
        {
          make_reference(parameters);
        }
      catch (const ExceptionBase &e)
        {
          std::ostringstream reason;
          e.print_info(reason);
          std::string message = reason.str();
          message.erase(0, message.find_first_not_of(" \n"));
          while (!message.empty() && std::isspace(message.back()))
            message.pop_back();
          refuse(file,
                 "'Output/Analytic reference' = " + parameters.approach_law +
                   " cannot describe this impact ('Body 1/Initial velocity' "
                   "= " +
                   text(parameters.bodies[0].initial_velocity) +
                   (parameters.obstacle.active() ?
                      std::string() :
                      ", 'Body 2/Initial velocity' = " +
                        text(parameters.bodies[1].initial_velocity)) +
                   "): " + message + " Lower the closing speed" + way_out);
        }
    }
  } // namespace



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

    std::vector<std::unique_ptr<Discretization<2>>> discretizations;
    for (unsigned int b = 0; b < parameters.n_bodies(); ++b)
      discretizations.push_back(
        create_discretization<2>(parameters.method,
                                 parameters.bodies[b].geometry,
                                 parameters.degree,
                                 parameters.fea_element));
    // Several MPI ranks: with as many ranks as bodies of equal size and the
    // owned-rows step (lumped mass, constraints u_i = 0 alone, neither the
    // bipenalty nor mass redistribution), each body whole on a rank of its
    // own: the partition of the scene's mesh with no cut, since the bodies
    // share no cell. The ranks then exchange the contact surfaces only.
    // Else every body is split over all ranks (Parallel/Distribution).
    const unsigned int n_ranks         = n_world_ranks();
    bool               bodies_on_ranks = false;
    if (n_ranks > 1 && n_ranks == discretizations.size() &&
        !parameters.split_every_body &&
        parameters.mass_scheme != MassScheme::consistent &&
        !parameters.bipenalty && !parameters.mass_redistribution)
      {
        bodies_on_ranks                  = true;
        types::global_dof_index smallest = discretizations[0]->n_dofs(),
                                largest  = smallest;
        for (const auto &discretization : discretizations)
          {
            smallest = std::min(smallest, discretization->n_dofs());
            largest  = std::max(largest, discretization->n_dofs());
            AffineConstraints<double> hanging_nodes;
            discretization->make_constraints(hanging_nodes);
            bodies_on_ranks &= hanging_nodes.n_constraints() == 0;
          }
        bodies_on_ranks &= largest <= 1.05 * smallest;
      }
    scene.bodies_on_ranks = bodies_on_ranks;
    // Contact is searched only on the declared surfaces: the arcs.
    for (const auto &discretization : discretizations)
      scene.contact_surfaces.push_back(
        discretization->boundary_segments(BodyGeometry::curved_boundary_id));
    const auto &surfaces = scene.contact_surfaces;
    // The meshes' and patches' temporaries, freed, go back to the system
    // (glibc keeps freed small blocks, and large arrays take fresh pages).
    malloc_trim(0);

    // Bodies whole on ranks: each rank builds its own body first, whose
    // matrix it then releases with load balancing (ElasticBody), and the
    // band of the other body in the room it leaves.
    std::vector<unsigned int> order(parameters.n_bodies());
    std::iota(order.begin(), order.end(), 0u);
    if (bodies_on_ranks)
      std::rotate(order.begin(), order.begin() + world_rank(), order.end());
    scene.bodies.resize(parameters.n_bodies());
    for (const unsigned int b : order)
      {
        const auto                  &body = parameters.bodies[b];
        std::vector<RollerCondition> rollers;
        if (body.symmetry_cut &&
            body.geometry.shape == BodyGeometry::Shape::half_disk)
          rollers.push_back({BodyGeometry::symmetry_boundary_id, 0});
        auto discretization = std::move(discretizations[b]);
        // Several MPI ranks: each builds and computes the rows of its own
        // unknowns, and reads the contact surfaces whole (their unknowns
        // are every rank's).
        std::optional<RankDistribution> ranks;
        if (n_ranks > 1)
          {
            // The bipenalty changes the state where the penalty masses
            // change, mass redistribution makes the surfaces massless: every
            // rank computes the whole state. The latter's boundary solve
            // reads the surfaces' stiffness rows on every rank.
            ranks.emplace(RankDistribution{MPI_COMM_WORLD,
                                           {},
                                           parameters.bipenalty ||
                                             parameters.mass_redistribution,
                                           parameters.mass_redistribution});
            ranks->load_balancing = parameters.load_balancing;
            ranks->index          = b;
            if (bodies_on_ranks)
              ranks->whole_on_rank = b;
            for (const auto &segment : surfaces[b])
              for (const auto &node : segment.node_dofs)
                ranks->shared.insert(ranks->shared.end(),
                                     node.begin(),
                                     node.end());
            std::sort(ranks->shared.begin(), ranks->shared.end());
            ranks->shared.erase(std::unique(ranks->shared.begin(),
                                            ranks->shared.end()),
                                ranks->shared.end());
          }
        scene.bodies[b] =
          std::make_unique<ElasticBody<2>>("body" + std::to_string(b + 1),
                                           std::move(discretization),
                                           body.material,
                                           parameters.mass_scheme,
                                           rollers,
                                           body.initial_velocity,
                                           ranks ? &*ranks : nullptr);
        scene.bodies[b]->set_pass_on_one_thread(
          parameters.pass_of_body_on_one_thread);
        malloc_trim(0); // the body's temporaries, as above
      }

    // Claimed load balancing: the claims' counters (collective, in the
    // bodies' order on every rank).
    for (const auto &body : scene.bodies)
      body->open_claims();

    // The surface masses: the lumped masses in use, or HRZ's for a
    // consistent mass. The contact damping and Penalty = auto need them.
    std::vector<Vector<double>> masses;
    if (parameters.contact.damping_ratio > 0. || parameters.automatic_penalty)
      for (const auto &body : scene.bodies)
        masses.push_back(body->lumped_masses().size() > 0 ?
                           body->lumped_masses() :
                           assemble_lumped_mass(body->discretization(),
                                                body->material().density,
                                                MassScheme::hrz,
                                                body->constraints()));

    // Penalty = auto: k = s mu / dt^2 (the surfaces' mean mass per length,
    // reduced for two bodies; dt the bodies' stable step bound without
    // contact), so that the contact mode has omega_c dt = sqrt(s) whatever
    // the mesh and the material.
    double automatic_penalty = 0.;
    // The bodies' stable step bound without contact (the bound where one
    // applies, else the power estimate): Penalty = auto.
    double bulk_step = std::numeric_limits<double>::infinity();
    if (parameters.automatic_penalty)
      for (const auto &body : scene.bodies)
        {
          const StableTimeStep step = compute_stable_time_step(*body, {});
          bulk_step =
            std::min(bulk_step,
                     step.bound() > 0. ? step.bound() : step.power_estimate);
        }
    if (parameters.automatic_penalty)
      {
        double inverse_mu = 0.;
        for (unsigned int b = 0; b < scene.bodies.size(); ++b)
          {
            inverse_mu +=
              1. /
              mean_surface_mass_density(surfaces[b],
                                        parameters.contact.n_quadrature_points,
                                        masses[b]);
          }
        automatic_penalty = parameters.penalty_scale_factor / inverse_mu /
                            (bulk_step * bulk_step);
      }

    const auto        &obstacle = parameters.obstacle;
    const Tensor<1, 2> relative = relative_velocity(parameters);
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
        settings.penalty =
          parameters.automatic_penalty ? automatic_penalty : obstacle.penalty;
        settings.n_quadrature_points = parameters.contact.n_quadrature_points;
        settings.damping_ratio       = parameters.contact.damping_ratio;
        for (const auto &wall : rigid)
          {
            scene.contacts.push_back(
              std::make_unique<RigidObstacleContact<2>>(settings,
                                                        wall,
                                                        surfaces[0]));
            scene.interactions.push_back({scene.contacts.back().get(), 0});
          }
      }
    else
      {
        ContactSettings settings = parameters.contact;
        if (parameters.automatic_penalty)
          settings.penalty = automatic_penalty;
        auto contact = std::make_unique<PenaltyContact<2>>(settings,
                                                           surfaces[0],
                                                           surfaces[1]);
        scene.contacts.push_back(std::move(contact));
        scene.interactions.push_back({scene.contacts.back().get(), 0, 1});
        // Bipenalty: the critical mass penalty makes the contact's bound
        // margin C / eps_m equal to the bodies' (2 / dt_bulk)^2.
        // Bipenalty: the critical mass penalty of the step in use, the
        // bound with the stiffness penalty's springs: margin C / eps_m =
        // (2 / dt)^2, so that the mass penalty does not lower that step
        // (Bipenalty mass scale factor f: the step becomes min(1, sqrt(f))
        // dt). Not the bodies' own step: runs there blow up
        // (doc/formulation.md).
        if (parameters.bipenalty)
          {
            for (auto &body : scene.bodies)
              body->set_penalty_switching(
                parameters.bipenalty_momentum_switching);
            const double step =
              scene_stable_time_step(scene.body_pointers(),
                                     scene.interactions,
                                     parameters.contact_activation_margin)
                .bound();
            scene.contacts.back()->set_bipenalty_mass(
              parameters.bipenalty_mass_scale_factor *
              parameters.contact_activation_margin *
              scene.contacts.back()->bipenalty_stiffness() * step * step / 4.);
          }
      }

    if (parameters.contact.damping_ratio > 0.)
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

    // Mass redistribution, after the surface masses of Penalty = auto were
    // taken: the surfaces become massless and the contact models return
    // their tangent for the quasi-static boundary solve.
    if (parameters.mass_redistribution)
      {
        for (unsigned int b = 0; b < scene.bodies.size(); ++b)
          scene.bodies[b]->redistribute_mass(surfaces[b]);
        for (auto &contact : scene.contacts)
          contact->set_linearize(true);
      }

    if (relative.norm() > 0.)
      scene.impact_direction = relative / relative.norm();
    else
      scene.impact_direction[1] = 1.;

    if (parameters.approach_law != "none")
      scene.reference = make_reference(parameters);

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

  std::pair<double, double>
  estimated_memory_and_cells(const Parameters &parameters)
  {
    double cells = 0.;
    for (unsigned int b = 0; b < parameters.n_bodies(); ++b)
      {
        const BodyGeometry &g = parameters.bodies[b].geometry;
        // The coarse mesh: cells and area.
        double coarse = 1., area = 0.;
        switch (g.shape)
          {
            case BodyGeometry::Shape::half_disk:
              coarse = 4., area = numbers::PI * g.radius * g.radius / 2.;
              break;
            case BodyGeometry::Shape::full_disk:
              coarse = 5., area = numbers::PI * g.radius * g.radius;
              break;
            case BodyGeometry::Shape::rectangle:
              {
                const auto d = g.upper_right - g.lower_left;
                area         = std::abs(d[0] * d[1]);
                break;
              }
          }
        // The part of the body within a distance of the refinement centre,
        // from a 200 x 200 grid over the disk of that radius.
        const auto zone_area = [&](const double radius) {
          const unsigned int m     = 200;
          const double       pixel = 2. * radius / m;
          unsigned int       count = 0;
          for (unsigned int i = 0; i < m; ++i)
            for (unsigned int j = 0; j < m; ++j)
              {
                const Point<2> p =
                  g.refinement_center + Point<2>((i + 0.5) * pixel - radius,
                                                 (j + 0.5) * pixel - radius);
                count += p.distance(g.refinement_center) < radius &&
                         depth_inside(g, p) > 0.;
              }
          return std::min(area, count * pixel * pixel);
        };
        // Each local pass splits the cells of the zone (a vertex within the
        // refinement radius: centres within about half a cell more) in four.
        double n         = coarse * std::pow(4., g.global_refinements);
        double cell_area = area / n;
        for (unsigned int k = 0; k < g.local_refinements; ++k)
          {
            n += 3. *
                 zone_area(g.refinement_radius + std::sqrt(cell_area) / 2.) /
                 cell_area;
            cell_area /= 4.;
          }
        // IGA halves knot spans along whole knot lines, through the
        // patches: measured 1.8 to 2.9 times the cells of FEA at levels 3
        // and 4 with 1 to 5 local passes.
        cells += (parameters.method == DiscretizationMethod::iga &&
                  g.local_refinements > 0) ?
                   3. * n :
                   n;
      }
    // Measured peak memory at degree 2 (FE_Q, HRZ, levels 4 to 6): about
    // 170 MB plus 6.5 kB per cell; the matrices grow with the coupling of
    // the (degree + 1)^2 functions of a cell, and a consistent mass
    // doubles them with its factorisation.
    const double per_cell =
      8192. * std::pow((parameters.degree + 1.) / 3., 4) *
      (parameters.mass_scheme == MassScheme::consistent ? 2. : 1.);
    return {2e8 + per_cell * cells, cells};
  }



  void
  check_scene(const Parameters  &parameters,
              const std::string &parameter_file,
              const unsigned int n_ranks)
  {
    check_start_positions(parameters, parameter_file);
    if (parameters.approach_law != "none")
      check_reference_scene(parameters, parameter_file);

    // Memory, before anything is allocated. Every rank holds the mesh and
    // the state, and its rows of the stiffness: counted as a whole scene per
    // rank (an upper bound).
    auto [bytes, cells] = estimated_memory_and_cells(parameters);
    bytes *= n_ranks;
    std::ifstream meminfo("/proc/meminfo");
    std::string   key;
    double        available_kB = 0.;
    while (meminfo >> key)
      if (key == "MemAvailable:")
        {
          meminfo >> available_kB;
          break;
        }
    const double available = 1024. * available_kB;
    if (available > 0. && bytes > available)
      {
        std::ostringstream message;
        const auto        &g = parameters.bodies[0].geometry;
        message << std::setprecision(3)
                << "'Discretization/Global refinements' = "
                << g.global_refinements
                << " and 'Discretization/Local refinements' = "
                << g.local_refinements << " (Degree " << parameters.degree
                << ", " << to_string(parameters.method) << ", "
                << to_string(parameters.mass_scheme) << " mass) give about "
                << cells << " cells, an estimated " << bytes / 1e9
                << " GB of memory, more than the " << available / 1e9
                << " GB available (MemAvailable in /proc/meminfo): use "
                   "fewer refinements (each global one needs about four "
                   "times the memory)";
        refuse(parameter_file, message.str());
      }

    if (!parameters.automatic_time_step)
      time_steps_to_end(parameters, parameters.time_step, parameter_file);
  }



  TimeSteps
  time_steps_to_end(const Parameters  &parameters,
                    const double       selected_time_step,
                    const std::string &parameter_file)
  {
    const double steps =
      std::ceil(parameters.end_time / selected_time_step - 1e-9);
    if (!(steps <= max_time_steps))
      {
        std::ostringstream message;
        message << "'Time integration/End time' = " << parameters.end_time
                << " s and 'Time integration/Time step' = ";
        if (parameters.automatic_time_step)
          message << "auto (" << selected_time_step << " s, "
                  << parameters.time_step_safety_factor
                  << " of the stable step bound)";
        else
          message << selected_time_step << " s";
        message << " need " << steps << " steps; at most " << max_time_steps
                << " are allowed: shorten the end time"
                << (parameters.automatic_time_step ?
                      " or the scene's stiffest part (penalty, modulus, "
                      "refinement)" :
                      " or lengthen the time step");
        refuse(parameter_file, message.str());
      }
    TimeSteps result;
    result.n_steps   = std::max<std::uint64_t>(1, steps);
    result.time_step = parameters.end_time / result.n_steps;
    // An end time that is a multiple of the step up to round-off keeps the
    // step as selected (bit for bit).
    if (std::abs(result.time_step - selected_time_step) <=
        1e-12 * selected_time_step)
      result.time_step = selected_time_step;
    return result;
  }



  double
  faces_across_contact_zone(const Scene &scene, const Parameters &parameters)
  {
    if (!scene.reference)
      return 0.;
    const BodyGeometry &geometry = parameters.bodies[0].geometry;
    // The impact direction is the partner's velocity relative to Body 1:
    // the partner comes from -impact_direction, where Body 1 meets it.
    const Point<2> first_contact =
      geometry.center - geometry.radius * scene.impact_direction;
    const auto         &segments = scene.contact_surfaces[0];
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
