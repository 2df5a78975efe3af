// Layer 5: central differences.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/thread_management.h>

#include <isoimpact/time_integration/central_difference.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

using namespace dealii;

namespace isoimpact
{
  template <int dim>
  CentralDifference<dim>::CentralDifference(
    const std::vector<ElasticBody<dim> *>      &bodies,
    const std::vector<ContactInteraction<dim>> &contacts,
    const double                                time_step)
    : bodies(bodies)
    , contacts(contacts)
    , dt(time_step)
    , results(contacts.size())
  {
    AssertThrow(time_step > 0.,
                ExcMessage("time step " + std::to_string(time_step) +
                           " s is not allowed: it must be positive"));
    for (const auto &interaction : contacts)
      AssertThrow(interaction.contact != nullptr &&
                    interaction.first_body < bodies.size() &&
                    (interaction.contact->n_bodies() == 1 ||
                     interaction.second_body < bodies.size()),
                  ExcMessage("a contact interaction refers to a body that "
                             "the time integrator does not have"));
    for (const auto *body : bodies)
      {
        half_step_velocity.emplace_back(body->n_dofs());
        forces.emplace_back(body->n_dofs());
        force_is_zero.push_back(true);
      }
    body_penalty_masses.resize(bodies.size());
    bodies_step_side_by_side =
      bodies.size() > 1 &&
      std::none_of(bodies.begin(), bodies.end(), [](const auto *body) {
        return body->exchange().is_distributed();
      });
    step_order.resize(bodies.size());
    std::iota(step_order.begin(), step_order.end(), 0u);
    std::stable_partition(step_order.begin(),
                          step_order.end(),
                          [&](const unsigned int b) {
                            const auto &exchange = bodies[b]->exchange();
                            return !exchange.claims_band() ||
                                   exchange.n_owned_unknowns() > 0;
                          });
    bool damped_contact = false;
    for (const auto &interaction : contacts)
      {
        bipenalty |= interaction.contact->bipenalty_mass() > 0.;
        damped_contact |= interaction.contact->damping_ratio() > 0.;
      }
    for (unsigned int b = 0; b < bodies.size(); ++b)
      if (!bodies[b]->state_is_replicated())
        {
          ghost_vectors.emplace_back(&bodies[b]->exchange(),
                                     &bodies[b]->displacement);
          ghost_vector_displacement_of.push_back(b);
          if (damped_contact)
            {
              ghost_vectors.emplace_back(&bodies[b]->exchange(),
                                         &half_step_velocity[b]);
              ghost_vector_displacement_of.push_back(
                numbers::invalid_unsigned_int);
            }
        }
    for (const auto &interaction : contacts)
      {
        std::vector<unsigned int> involved = {interaction.first_body};
        if (interaction.contact->n_bodies() == 2)
          involved.push_back(interaction.second_body);
        contact_bodies.push_back(involved);
        contact_velocities.emplace_back();
        contact_forces.emplace_back();
        for (const unsigned int b : involved)
          {
            contact_velocities.back().push_back(&half_step_velocity[b]);
            contact_forces.back().push_back(&forces[b]);
          }
        // Only the contact damping reads the velocities.
        if (interaction.contact->damping_ratio() > 0.)
          for (const unsigned int b : involved)
            bodies[b]->set_contact_reads_velocity(true);
      }
    surface_unknowns.resize(bodies.size());
    for (const auto &interaction : contacts)
      {
        const auto springs = interaction.contact->surface_springs();
        for (unsigned int k = 0; k < springs.size(); ++k)
          {
            auto &unknowns = surface_unknowns[k == 0 ? interaction.first_body :
                                                       interaction.second_body];
            for (const auto &segment : *springs[k].segments)
              for (const auto &node : segment.node_dofs)
                unknowns.insert(unknowns.end(), node.begin(), node.end());
          }
      }
    for (auto &unknowns : surface_unknowns)
      {
        std::sort(unknowns.begin(), unknowns.end());
        unknowns.erase(std::unique(unknowns.begin(), unknowns.end()),
                       unknowns.end());
      }
    // Mass redistribution: the contact models must return their tangent
    // (ContactModel::set_linearize, done by the scene).
    if (std::any_of(bodies.begin(), bodies.end(), [](const auto *body) {
          return !body->massless_dofs().empty();
        }))
      {
        for (const auto &interaction : contacts)
          AssertThrow(interaction.contact->damping_ratio() == 0.,
                      ExcMessage("mass redistribution does not support "
                                 "contact damping"));
        boundary = std::make_unique<QuasiStaticBoundary<dim>>(bodies,
                                                              contacts,
                                                              forces,
                                                              results);
      }
    // The contacts are the only writers of the forces, each on its surface
    // springs' segments: a lumped body's pass reads and zeroes the forces
    // on those rows alone (not with the quasi-static boundary, whose
    // solution writes forces too). evaluate_contacts() checks the rest.
    if (!boundary)
      for (unsigned int b = 0; b < bodies.size(); ++b)
        if (bodies[b]->step_zeroes_force())
          bodies[b]->set_force_rows(surface_unknowns[b]);
    // Several ranks that need not meet at every step: each body's pass sends
    // what the others read, and the energies can wait.
    loose_steps =
      !bodies.empty() && !boundary && !bipenalty && !damped_contact &&
      std::all_of(bodies.begin(), bodies.end(), [](const auto *body) {
        return body->exchange().is_distributed() && body->step_zeroes_force();
      });
    // A body's contact forces that no pass of this rank reads (its contact
    // surfaces' rows stepped by another rank) are not formed here.
    if (!boundary && !bipenalty)
      for (unsigned int c = 0; c < contacts.size(); ++c)
        for (unsigned int k = 0; k < contact_bodies[c].size(); ++k)
          if (!bodies[contact_bodies[c][k]]->steps_contact_surface())
            contact_forces[c][k] = nullptr;
    contacts_beside_displacement =
      !contacts.empty() && !boundary &&
      std::none_of(bodies.begin(), bodies.end(), [](const auto *body) {
        return body->exchange().is_distributed();
      });
  }

  template <int dim>
  void
  CentralDifference<dim>::evaluate_contacts(const bool record_contact_points)
  {
    // A lumped body's step leaves its force zero (consumed in its pass).
    for (unsigned int b = 0; b < forces.size(); ++b)
      if (!force_is_zero[b])
        forces[b] = 0.;
    std::fill(force_is_zero.begin(), force_is_zero.end(), false);
    std::vector<ArrayView<const double>> displacements;
    for (unsigned int c = 0; c < contacts.size(); ++c)
      {
        displacements.clear();
        for (const unsigned int b : contact_bodies[c])
          displacements.push_back(bodies[b]->contact_displacement());
        results[c] = contacts[c].contact->evaluate(displacements,
                                                   contact_velocities[c],
                                                   contact_forces[c],
                                                   record_contact_points);
      }
      // A force outside the force rows would never reach a pass: every 128th
      // step (every step in debug builds) a stream over the forces makes
      // sure there is none.
#ifdef DEBUG
    constexpr unsigned int check_period = 1;
#else
    constexpr unsigned int check_period = 128;
#endif
    if (step % check_period == 0)
      for (unsigned int b = 0; b < bodies.size(); ++b)
        bodies[b]->check_force_rows(forces[b]);
  }

  template <int dim>
  void
  CentralDifference<dim>::compute_accelerations(
    const bool record_contact_points,
    const bool update_velocities,
    const bool form_whole_step_state,
    const bool contacts_evaluated)
  {
    // (advance() evaluates the contacts beside the displacement update only
    // without the quasi-static boundary.)
    Assert(!contacts_evaluated || !boundary, ExcInternalError());
    if (boundary)
      {
        // u_b in equilibrium with u_i; the forces and results are those of
        // the solution.
        boundary->solve(
          [this](const bool record) {
            evaluate_contacts(record);
          },
          record_contact_points);
        if (update_velocities)
          boundary->set_velocities(half_step_velocity, dt);
      }
    else if (!contacts_evaluated)
      evaluate_contacts(record_contact_points);
    if (bipenalty)
      {
        // The mass penalty of the new active set, at the half-step velocity
        // the masses meet (v^{n+1/2}; v^0 at t = 0).
        for (auto &masses : body_penalty_masses)
          masses.clear();
        for (unsigned int c = 0; c < contacts.size(); ++c)
          for (unsigned int k = 0; k < contacts[c].contact->n_bodies(); ++k)
            {
              auto &masses =
                body_penalty_masses[k == 0 ? contacts[c].first_body :
                                             contacts[c].second_body];
              masses.insert(masses.end(),
                            results[c].penalty_masses[k].begin(),
                            results[c].penalty_masses[k].end());
            }
        for (unsigned int b = 0; b < bodies.size(); ++b)
          bipenalty_switching_work +=
            bodies[b]->set_penalty_masses(body_penalty_masses[b],
                                          half_step_velocity[b]);
      }
    if (update_velocities)
      {
        // v^{n+1} = v^{n+1/2} + dt/2 a^{n+1}; v^{n+3/2} = v^{n+1/2} + dt a,
        // fused with the acceleration (one pass for lumped mass).
        const auto step_body = [&](const unsigned int b) {
          bodies[b]->compute_acceleration_and_velocities(
            forces[b],
            half_step_velocity[b],
            dt,
            // energy_balance() reads the bipenalty's acceleration.
            form_whole_step_state || bipenalty,
            // Several ranks: the next displacement ahead, in the pass (the
            // velocity does not change before the next step's update).
            !boundary && !bipenalty);
        };
        // The bodies' steps touch only their own data. On one process they
        // run side by side: while a consistent mass solve is in the root
        // of its elimination tree (one thread), the other threads take the
        // other body's work. Each body's step has the same bits either
        // way. On several ranks one after the other (their messages).
        const auto start = std::chrono::steady_clock::now();
        if (bodies_step_side_by_side)
          {
            Threads::TaskGroup<void> tasks;
            for (unsigned int b = 0; b < bodies.size(); ++b)
              tasks += Threads::new_task([&step_body, b]() {
                step_body(b);
              });
            tasks.join_all();
          }
        else
          for (const unsigned int b : step_order)
            step_body(b);
        seconds_in_passes += std::chrono::duration<double>(
                               std::chrono::steady_clock::now() - start)
                               .count();
        for (unsigned int b = 0; b < bodies.size(); ++b)
          force_is_zero[b] = bodies[b]->step_zeroes_force();
      }
    else
      {
        // Every body's product before any body's rest: on several ranks
        // each multiplies its own rows at once, rather than wait for the
        // other's product of one body before its own of the next.
        for (unsigned int b = 0; b < bodies.size(); ++b)
          bodies[b]->start_acceleration(bodies[b]->displacement);
        for (unsigned int b = 0; b < bodies.size(); ++b)
          bodies[b]->complete_acceleration(forces[b], bodies[b]->acceleration);
      }
  }

  template <int dim>
  void
  CentralDifference<dim>::initialize(const bool record_contact_points)
  {
    kinetic_energy_of_step = std::numeric_limits<double>::quiet_NaN();
    complete_energies_sum(false);
    energy_of_step_before.reset();
    // The contact damping reads half_step_velocity: v^0 at t = 0.
    for (unsigned int b = 0; b < bodies.size(); ++b)
      {
        bodies[b]->restart_steps();
        half_step_velocity[b] = bodies[b]->velocity;
      }
    compute_accelerations(record_contact_points);
    for (unsigned int b = 0; b < bodies.size(); ++b)
      half_step_velocity[b].add(0.5 * dt, bodies[b]->acceleration);
  }

  template <int dim>
  void
  CentralDifference<dim>::advance(const bool record_contact_points,
                                  const bool form_whole_step_state)
  {
    kinetic_energy_of_step = std::numeric_limits<double>::quiet_NaN();
    // On several ranks each body advances its owned entries, and the ghosts
    // of all bodies come from their owners in one round of messages (no
    // messages on one process).
    // One process whose lumped passes formed the next displacement: swapped
    // in, nothing left to stream beside the contacts.
    bool formed_ahead = true;
    for (unsigned int b = 0; b < bodies.size(); ++b)
      formed_ahead &=
        bodies[b]->displacement_formed_ahead(half_step_velocity[b], dt);
    if (contacts_beside_displacement && !formed_ahead)
      {
        // The contact surfaces' displacement first; then the contacts on
        // this thread while another advances the rest of the displacement
        // (a stream through memory that one core nearly saturates). The
        // two touch disjoint entries: the same bits as one after the other.
        for (unsigned int b = 0; b < bodies.size(); ++b)
          bodies[b]->advance_displacement_of_rows(half_step_velocity[b],
                                                  dt,
                                                  surface_unknowns[b],
                                                  false);
        Threads::Task<void> rest = Threads::new_task([this]() {
          for (unsigned int b = 0; b < bodies.size(); ++b)
            bodies[b]->advance_displacement_of_rows(half_step_velocity[b],
                                                    dt,
                                                    surface_unknowns[b],
                                                    true);
        });
        try
          {
            evaluate_contacts(record_contact_points);
          }
        catch (...)
          {
            rest.join();
            throw;
          }
        rest.join();
        compute_accelerations(record_contact_points,
                              true,
                              form_whole_step_state,
                              true);
      }
    else
      {
        // The ghosts of the displacement come with it if their owners sent
        // them from the last pass (and rows of the load balancing's moves);
        // the others here.
        for (unsigned int b = 0; b < bodies.size(); ++b)
          bodies[b]->advance_displacement(half_step_velocity[b], dt);
        std::vector<std::pair<const UnknownExchange *, Vector<double> *>>
          to_update;
        for (unsigned int v = 0; v < ghost_vectors.size(); ++v)
          {
            const unsigned int b = ghost_vector_displacement_of[v];
            if (b == numbers::invalid_unsigned_int ||
                !bodies[b]->displacement_ghosts_received())
              to_update.push_back(ghost_vectors[v]);
          }
        UnknownExchange::update_ghost_values(to_update);
        compute_accelerations(record_contact_points,
                              true,
                              form_whole_step_state);
      }
    // The bodies' step energies summed over the ranks in one message; where
    // the ranks need not meet at every step, the sum of the step before is
    // completed now (the other ranks are past it) and this step's started.
    if (loose_steps)
      {
        complete_energies_sum(false);
        ElasticBody<dim>::start_sum_of_step_energies(bodies,
                                                     energies_under_way);
        contact_energy_under_way = 0.;
        for (const auto &result : results)
          contact_energy_under_way += result.energy;
      }
    else
      ElasticBody<dim>::sum_step_energies(bodies);
    for (const auto &result : results)
      contact_damping_work += dt * result.damping_power;
    ++step;
    current_time = step * dt;
  }

  template <int dim>
  double
  CentralDifference<dim>::time() const
  {
    return current_time;
  }

  template <int dim>
  unsigned int
  CentralDifference<dim>::step_number() const
  {
    return step;
  }

  template <int dim>
  double
  CentralDifference<dim>::time_step() const
  {
    return dt;
  }

  template <int dim>
  void
  CentralDifference<dim>::complete_energies_sum(
    const bool bodies_at_that_step) const
  {
    if (energies_under_way.bodies.empty())
      return;
    const auto summed =
      ElasticBody<dim>::complete_sum_of_step_energies(energies_under_way,
                                                      bodies_at_that_step);
    // kinetic_energy()'s sum (every body's energies are summed here).
    double energy = 0.;
    for (const auto &energies : summed)
      energy += energies.kinetic;
    energy_of_step_before = energy + contact_energy_under_way;
  }

  template <int dim>
  bool
  CentralDifference<dim>::ranks_meet_at_every_step() const
  {
    return !loose_steps;
  }

  template <int dim>
  std::optional<double>
  CentralDifference<dim>::kinetic_and_contact_energy_at_hand() const
  {
    if (loose_steps && !energies_under_way.bodies.empty())
      return energy_of_step_before;
    double energy = kinetic_energy();
    for (const auto &result : results)
      energy += result.energy;
    return energy;
  }

  template <int dim>
  double
  CentralDifference<dim>::kinetic_energy() const
  {
    if (!std::isnan(kinetic_energy_of_step))
      return kinetic_energy_of_step;
    // This step's sum over the ranks, if under way.
    complete_energies_sum(true);
    double energy = 0.;
    // 1/2 v^{n-1/2} . M v^{n+1/2}, v^{n-1/2} = v^{n+1/2} - dt a^n.
    // A lumped body summed it in its step already.
    for (unsigned int b = 0; b < bodies.size(); ++b)
      if (const auto &summed = bodies[b]->energies_of_last_step())
        energy += summed->kinetic;
      else
        energy +=
          bodies[b]->kinetic_energy_at_full_step(half_step_velocity[b], dt);
    kinetic_energy_of_step = energy;
    return energy;
  }

  template <int dim>
  EnergyBalance
  CentralDifference<dim>::energy_balance() const
  {
    EnergyBalance energy;
    energy.kinetic = kinetic_energy();
    for (const auto *body : bodies)
      if (const auto &summed = body->energies_of_last_step())
        energy.strain += summed->strain;
      else
        // K u of this step's acceleration: no further product.
        energy.strain +=
          body->strain_energy_of_last_acceleration(body->displacement);
    for (const auto &result : results)
      energy.contact += result.energy;
    energy.contact_damping = contact_damping_work;
    if (bipenalty)
      {
        for (unsigned int b = 0; b < bodies.size(); ++b)
          {
            previous_half_step_velocity = half_step_velocity[b];
            previous_half_step_velocity.add(-dt, bodies[b]->acceleration);
            energy.bipenalty_kinetic +=
              bodies[b]->penalty_kinetic_energy(previous_half_step_velocity,
                                                half_step_velocity[b]);
          }
        energy.bipenalty_switching = bipenalty_switching_work;
      }
    return energy;
  }

  template <int dim>
  const std::vector<ContactResult<dim>> &
  CentralDifference<dim>::contact_results() const
  {
    return results;
  }

  template <int dim>
  double
  CentralDifference<dim>::time_in_passes() const
  {
    return seconds_in_passes;
  }

  template <int dim>
  const QuasiStaticBoundary<dim> *
  CentralDifference<dim>::quasi_static_boundary() const
  {
    return boundary.get();
  }

  template class CentralDifference<2>;
} // namespace isoimpact
