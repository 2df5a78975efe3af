// Layer 4: the stable time step of central differences, dt_crit =
// 2 / omega_max, omega_max^2 = lambda_max(M^{-1} (K + K_c)), with the
// penalty springs K_c of the contact surfaces. Two guaranteed bounds (never
// above the true stable step) and one sharper estimate.
#ifndef isoimpact_stable_time_step_h
#define isoimpact_stable_time_step_h

#include <isoimpact/discretization/boundary_segments.h>
#include <isoimpact/mechanics/contact.h>
#include <isoimpact/mechanics/elastic_body.h>

#include <limits>
#include <vector>

namespace isoimpact
{
  /**
   * Stable steps in seconds. The two bounds are guaranteed not to exceed
   * the critical step of the linearised system (each from an upper bound on
   * omega_max): the element-by-element bound max_e lambda_max(K_e + K_c,e,
   * M_e) (with the element's share M_e of the mass in use) and, for lumped
   * mass, Gershgorin's bound max_i sum_j |K_ij + K_c,ij| / m_i. A bound that
   * does not apply is 0 (the element bound with a lumped mass condensed over
   * hanging nodes; Gershgorin with consistent mass). The estimate is a power
   * iteration on the global system: sharper, but approached from above.
   */
  struct StableTimeStep
  {
    double element_bound    = 0.;
    double gershgorin_bound = 0.;
    double power_estimate   = std::numeric_limits<double>::infinity();

    // The larger of the two guaranteed bounds.
    double
    bound() const;
    // Componentwise minimum of two bodies' steps.
    StableTimeStep
    min(const StableTimeStep &other) const;
  };

  template <int dim>
  StableTimeStep
  compute_stable_time_step(const ElasticBody<dim>                &body,
                           const std::vector<SurfaceSpring<dim>> &springs,
                           const unsigned int n_power_iterations = 200);
} // namespace isoimpact

#endif
