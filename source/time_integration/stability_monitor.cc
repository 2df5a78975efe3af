// Layer 5: stability monitor.
#include <isoimpact/time_integration/stability_monitor.h>

#include <algorithm>
#include <cmath>
#include <sstream>

using namespace dealii;

namespace isoimpact
{
  template <int dim>
  StableTimeStep
  scene_stable_time_step(const std::vector<ElasticBody<dim> *>      &bodies,
                         const std::vector<ContactInteraction<dim>> &contacts,
                         const double contact_activation_margin)
  {
    std::vector<std::vector<SurfaceSpring<dim>>> springs(bodies.size());
    double                                       bipenalty_eigenvalue = 0.;
    for (const auto &interaction : contacts)
      {
        if (interaction.contact->bipenalty_mass() > 0.)
          {
            bipenalty_eigenvalue =
              std::max(bipenalty_eigenvalue,
                       contact_activation_margin *
                         interaction.contact->bipenalty_stiffness() /
                         interaction.contact->bipenalty_mass());
          }
        auto model_springs = interaction.contact->surface_springs();
        for (auto &spring : model_springs)
          spring.stiffness *= contact_activation_margin;
        springs[interaction.first_body].push_back(model_springs[0]);
        if (model_springs.size() > 1)
          springs[interaction.second_body].push_back(model_springs[1]);
      }
    StableTimeStep step;
    step.element_bound = step.gershgorin_bound =
      std::numeric_limits<double>::infinity();
    for (unsigned int b = 0; b < bodies.size(); ++b)
      step = step.min(compute_stable_time_step(*bodies[b], springs[b]));
    if (bipenalty_eigenvalue > 0.)
      {
        const double bipenalty_step = 2. / std::sqrt(bipenalty_eigenvalue);
        step = step.min({bipenalty_step, bipenalty_step, bipenalty_step});
      }
    // A damper c with the half-step velocity on a spring-mass of frequency
    // omega and damping ratio xi = c / (2 m omega) is stable for omega dt <=
    // 2 (sqrt(1 + xi^2) - xi). The contact damping is xi of the critical
    // damping of a contact spring smaller than the one counted above, so
    // its ratio in the highest mode is at most xi: the factor is safe.
    double xi = 0.;
    for (const auto &interaction : contacts)
      xi = std::max(xi, interaction.contact->damping_ratio());
    const double damping_factor = std::sqrt(1. + xi * xi) - xi;
    step.element_bound *= damping_factor;
    step.gershgorin_bound *= damping_factor;
    step.power_estimate *= damping_factor;
    return step;
  }

  template <int dim>
  StabilityMonitor<dim>::StabilityMonitor(
    const CentralDifference<dim> &integrator,
    const StabilityLimits        &limits)
    : integrator(integrator)
    , limits(limits)
  {}

  template <int dim>
  std::string
  StabilityMonitor<dim>::check() const
  {
    // Ranks that need not meet at every step have the energies of the step
    // before at hand (CentralDifference::ranks_meet_at_every_step()): the
    // energy's checks come one step late there.
    const std::optional<double> energy =
      integrator.kinetic_and_contact_energy_at_hand();
    double penetration = 0.;
    for (const auto &result : integrator.contact_results())
      {
        penetration = std::max(penetration, result.max_penetration);
        if (!std::isfinite(result.force_on_body_0.norm()))
          return "the contact force became non-finite";
      }
    if (energy && !std::isfinite(*energy))
      return "the kinetic energy became non-finite";
    if (!(penetration <= limits.maximum_penetration))
      {
        std::ostringstream message;
        message << "a contact penetration of " << penetration
                << " m exceeds the maximum of " << limits.maximum_penetration
                << " m (Time integration/Maximum penetration)";
        return message.str();
      }
    return energy ? check_total_energy(*energy) : "";
  }

  template <int dim>
  std::string
  StabilityMonitor<dim>::check_total_energy(const double total_energy) const
  {
    const double limit =
      (1. + limits.energy_growth_tolerance) * limits.input_energy;
    if (std::isfinite(total_energy) && total_energy <= limit)
      return "";
    std::ostringstream message;
    message << "the energy of the modelled bodies grew to " << total_energy
            << " J/m, above " << limit << " J/m = (1 + "
            << limits.energy_growth_tolerance << ") times the input energy "
            << limits.input_energy
            << " J/m (Time integration/Energy growth tolerance)";
    return message.str();
  }

  template StableTimeStep
  scene_stable_time_step(const std::vector<ElasticBody<2> *> &,
                         const std::vector<ContactInteraction<2>> &,
                         const double);
  template class StabilityMonitor<2>;
} // namespace isoimpact
