// Layer 5: explicit central-difference time integration of elastic bodies in
// contact, in the half-step velocity form, with the energy balance.
//   v^{n+1/2} = v^{n-1/2} + dt a^n,   u^{n+1} = u^n + dt v^{n+1/2},
//   a^{n+1}   = M^{-1} (f_c(u^{n+1}) - K u^{n+1}),
// started with v^{1/2} = v^0 + dt/2 a^0. The velocity at whole steps, used
// for the kinetic energy and the output, is v^n = v^{n-1/2} + dt/2 a^n.
// With mass redistribution the massless unknowns of the contact surfaces are
// not advanced: after u_i^{n+1} they are solved from equilibrium
// (QuasiStaticBoundary), and their velocity is (u_b^{n+1} - u_b^n) / dt.
#ifndef isoimpact_central_difference_h
#define isoimpact_central_difference_h

#include <isoimpact/mechanics/contact.h>
#include <isoimpact/mechanics/elastic_body.h>
#include <isoimpact/time_integration/quasi_static_boundary.h>

#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace isoimpact
{
  // A contact model and the bodies it acts on (indices into the bodies of
  // CentralDifference): two for the two-body contact, one
  // (second_body = invalid) for a rigid obstacle.
  template <int dim>
  struct ContactInteraction
  {
    const ContactModel<dim> *contact;
    unsigned int             first_body;
    unsigned int second_body = dealii::numbers::invalid_unsigned_int;
  };

  // Energies per unit thickness (J/m) of the modelled bodies.
  struct EnergyBalance
  {
    double kinetic = 0.;
    double strain  = 0.;
    double contact = 0.;
    // Work removed by the contact damping since t = 0.
    double contact_damping = 0.;
    // Bipenalty: the kinetic energy of the mass penalty, 1/2 v^{n-1/2} . M_p
    // v^{n+1/2} like `kinetic`, and the energy that the mass penalty brought
    // in since t = 0 as it appeared and vanished (1/2 sum dm v^2 at each
    // change, at the half-step velocity).
    double bipenalty_kinetic   = 0.;
    double bipenalty_switching = 0.;
    // What the input energy should equal: the energies plus the work
    // removed, less the energy the mass penalty brought in.
    double
    total() const
    {
      return kinetic + strain + contact + contact_damping + bipenalty_kinetic -
             bipenalty_switching;
    }
  };

  template <int dim>
  class CentralDifference
  {
  public:
    CentralDifference(const std::vector<ElasticBody<dim> *>      &bodies,
                      const std::vector<ContactInteraction<dim>> &contacts,
                      const double                                time_step);

    // Holds pointers into its own force vectors: not copyable.
    CentralDifference(const CentralDifference &) = delete;
    CentralDifference &
    operator=(const CentralDifference &) = delete;

    // Computes a^0 and v^{1/2} from the bodies' initial state.
    void
    initialize(const bool record_contact_points = false);

    // One step; the bodies' displacement, velocity (whole step) and
    // acceleration are those of the new time afterwards. With
    // form_whole_step_state = false a body leaves its velocity (and
    // a lumped body its acceleration) those of an earlier step (ElasticBody::
    // compute_acceleration_and_velocities): for the steps whose state nobody
    // reads. The displacement, the energies and the contact results are
    // those of the new time either way, with the same bits.
    void
    advance(const bool record_contact_points = false,
            const bool form_whole_step_state = true);

    double
    time() const;
    unsigned int
    step_number() const;
    double
    time_step() const;

    /**
     * The energies at the current step. The kinetic energy is the one that
     * central differences conserve exactly for a linear system,
     * 1/2 v^{n-1/2} . M v^{n+1/2} = 1/2 v^n . M v^n - dt^2/8 a^n . M a^n:
     * with v^n alone the balance of a stable run would seem to grow by up to
     * (omega dt / 2)^2 of the energy in the highest modes, which the contact
     * chatter fills impact after impact (doc/stability.md).
     */
    EnergyBalance
    energy_balance() const;
    // The kinetic energy of energy_balance() alone (no product with the
    // stiffness).
    double
    kinetic_energy() const;

    /**
     * Several ranks: whether they meet at every step. They need not with
     * lumped mass (the fused pass) on all bodies, no mass redistribution,
     * no bipenalty and no contact damping (doc/parallel.md, session 34):
     * each rank sends the displacement other ranks read from its pass, as
     * soon as it is formed, and the bodies' energies are summed over the
     * ranks one step late unless someone asks for them (kinetic_energy(),
     * energy_balance()); each rank then projects every contact point
     * itself (ContactModel::distribute_points() is for ranks that meet).
     * One process: true.
     */
    bool
    ranks_meet_at_every_step() const;
    // The kinetic plus the contacts' energy of the latest step whose sums
    // are at hand without waiting for another rank (the stability
    // monitor's): this step's, or the step before's where the ranks do not
    // meet at every step; empty if there is none yet.
    std::optional<double>
    kinetic_and_contact_energy_at_hand() const;

    // Contact result of the last evaluation, per interaction.
    const std::vector<ContactResult<dim>> &
    contact_results() const;

    // Wall time (s) this process spent in the bodies' steps (their passes:
    // acceleration, velocities, next displacement; on several ranks the
    // claims of the band too) since construction: the time loop's share
    // that is not the contacts, the waits or the step's end. Not the
    // initial acceleration.
    double
    time_in_passes() const;

    // With mass redistribution (a body with massless unknowns): the
    // quasi-static boundary solve and its work; else nullptr.
    const QuasiStaticBoundary<dim> *
    quasi_static_boundary() const;

  private:
    // Zeroes the forces and evaluates every contact into them and results.
    void
    evaluate_contacts(const bool record_contact_points);
    // contacts_evaluated: evaluate_contacts() has been called for this
    // state already.
    void
    compute_accelerations(const bool record_contact_points,
                          const bool update_velocities     = false,
                          const bool form_whole_step_state = true,
                          const bool contacts_evaluated    = false);

    std::vector<ElasticBody<dim> *>      bodies;
    std::vector<ContactInteraction<dim>> contacts;
    double                               dt;
    double                               current_time = 0.;
    unsigned int                         step         = 0;
    std::vector<dealii::Vector<double>>  half_step_velocity;
    mutable dealii::Vector<double>       previous_half_step_velocity;
    // kinetic_energy() of the current step (the stability monitor and the
    // history both ask for it); NaN once the state has moved on.
    mutable double kinetic_energy_of_step =
      std::numeric_limits<double>::quiet_NaN();
    std::vector<dealii::Vector<double>> forces;
    // Per body: forces[b] is zero (left so by the body's step).
    std::vector<bool> force_is_zero;
    // Whether the bodies' steps run as parallel tasks (no body exchanges
    // messages in its step: one process).
    bool bodies_step_side_by_side = false;
    // Otherwise the bodies' order in a step: with claimed balancing a rank
    // first steps the bodies of which it has rows outside the band, then
    // claims what is left of the others' bands (so it may reach into all
    // of them); else the scene's order.
    std::vector<unsigned int> step_order;
    // Per body: the unknowns of its contact surfaces (ascending), the only
    // ones a contact reads the displacement of and adds forces to. On one
    // process without mass redistribution a step advances these first and
    // evaluates the contacts while another thread advances the rest of the
    // displacement.
    std::vector<std::vector<dealii::types::global_dof_index>> surface_unknowns;
    bool contacts_beside_displacement = false;
    // Per contact interaction, built once: its bodies, their velocities
    // and force vectors, in the order the contact model expects (the
    // displacements are asked of the bodies at each evaluation:
    // ElasticBody::contact_displacement()).
    std::vector<std::vector<unsigned int>>                   contact_bodies;
    std::vector<std::vector<const dealii::Vector<double> *>> contact_velocities;
    std::vector<std::vector<dealii::Vector<double> *>>       contact_forces;
    // Work of the contact damping since t = 0: dt times its power at each
    // step (the power with the half-step velocities the damping uses).
    double contact_damping_work = 0.;
    // Bipenalty: sum of the bodies' set_penalty_masses() since t = 0, and
    // per body the penalty masses of the last evaluation.
    double bipenalty_switching_work = 0.;
    bool   bipenalty                = false;
    // time_in_passes().
    double seconds_in_passes = 0.;
    // The vectors whose ghosts each step updates (several MPI ranks): the
    // displacements, and the half-step velocities if a contact is damped
    // (the damping reads them).
    std::vector<std::pair<const UnknownExchange *, dealii::Vector<double> *>>
      ghost_vectors;
    // Per entry of ghost_vectors: the body whose displacement it is, or
    // invalid (a velocity).
    std::vector<unsigned int> ghost_vector_displacement_of;
    // Ranks that need not meet at every step (ranks_meet_at_every_step()):
    // the energies' sum of the last step under way, and the kinetic and
    // contact energy of the step before, once summed.
    bool                                               loose_steps = false;
    mutable typename ElasticBody<dim>::StepEnergiesSum energies_under_way;
    double                        contact_energy_under_way = 0.;
    mutable std::optional<double> energy_of_step_before;
    // Completes the energies' sum under way: the bodies' energies if no
    // step has passed since.
    void
    complete_energies_sum(const bool bodies_at_that_step) const;
    std::vector<std::vector<std::pair<dealii::types::global_dof_index, double>>>
                                    body_penalty_masses;
    std::vector<ContactResult<dim>> results;
    // Mass redistribution: the massless unknowns in equilibrium.
    std::unique_ptr<QuasiStaticBoundary<dim>> boundary;
  };
} // namespace isoimpact

#endif
