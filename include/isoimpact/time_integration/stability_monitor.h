// Layer 5: the stability monitor of an explicit run. Central differences
// above their stable step (or with a contact stiffer than the step allows)
// blow up exponentially; the monitor finds that early and says what grew,
// so that a run stops instead of writing garbage.
#ifndef isoimpact_stability_monitor_h
#define isoimpact_stability_monitor_h

#include <isoimpact/mechanics/stable_time_step.h>
#include <isoimpact/time_integration/central_difference.h>

#include <string>

namespace isoimpact
{
  /**
   * Penalty contact is piecewise linear: a Gauss point that enters or leaves
   * contact inside a step gains or loses energy, and when the contact mode
   * is resolved by fewer than about three steps per half period this pumps
   * energy into the bodies impact after impact, at steps the linearised
   * bound calls stable (measured: 5 % energy growth in one impact at 0.8 of
   * that bound, doc/stability.md). The bound therefore counts the contact
   * springs this many times by default: the contact mode alone then needs
   * omega_c dt <= 2 / sqrt(2).
   */
  constexpr double default_contact_activation_margin = 2.;

  /**
   * The stable step of a scene: each body with the penalty springs of the
   * contacts it takes part in (times contact_activation_margin), the
   * minimum over the bodies. A contact with a bipenalty caps the steps by
   * 2 / sqrt(margin C / eps_m) (ContactModel::bipenalty_stiffness): for the
   * linearised system lambda_max(K + K_c, M + M_c) <= max(lambda_max(K, M),
   * lambda_max(K_c, M_c)) (the mediant of the Rayleigh quotients), so the
   * springs could be left out, but runs at the bodies' step blow up through
   * the contact's activation (doc/formulation.md): the springs stay.
   */
  template <int dim>
  StableTimeStep
  scene_stable_time_step(
    const std::vector<ElasticBody<dim> *>      &bodies,
    const std::vector<ContactInteraction<dim>> &contacts,
    const double contact_activation_margin = default_contact_activation_margin);

  struct StabilityLimits
  {
    // The energy put into the bodies (J/m, modelled bodies): the total
    // energy at t = 0 for a free impact.
    double input_energy = 0.;
    // Fraction of the input energy by which the energy may grow.
    double energy_growth_tolerance = 0.1;
    // Deepest admissible penetration of a contact, m.
    double maximum_penetration = 0.;
  };

  template <int dim>
  class StabilityMonitor
  {
  public:
    StabilityMonitor(const CentralDifference<dim> &integrator,
                     const StabilityLimits        &limits);

    /**
     * Checks the state after a step, cheaply enough for every step: the
     * kinetic plus contact energy (which the total energy bounds from above,
     * strain energy being non-negative) against the input energy, every
     * value finite, and the deepest penetration. Returns an empty string if
     * the state is sound, else what went wrong. The energy is that of the
     * step before where the ranks need not meet at every step
     * (CentralDifference::kinetic_and_contact_energy_at_hand()).
     */
    std::string
    check() const;

    /**
     * The same with a total energy computed anyway (at history steps).
     */
    std::string
    check_total_energy(const double total_energy) const;

  private:
    const CentralDifference<dim> &integrator;
    const StabilityLimits         limits;
  };
} // namespace isoimpact

#endif
