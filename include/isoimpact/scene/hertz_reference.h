// Layer 6 (scene): the analytic quasi-static Hertz reference for the
// dynamic impact of two elastic cylinders (plane strain, per unit thickness),
// see doc/hertz-reference.md. All quantities in SI units per unit thickness.
#ifndef isoimpact_hertz_reference_h
#define isoimpact_hertz_reference_h

#include <isoimpact/nurbs/enum_names.h>

#include <string>
#include <vector>

namespace isoimpact
{
  /**
   * A full elastic cylinder (disc in plane strain); its mass per unit
   * thickness is density * pi * radius^2.
   */
  struct ElasticCylinder
  {
    double radius;
    double youngs_modulus;
    double poisson_ratio;
    double density;
  };

  /**
   * Centre approach delta(P) of two cylinders in line contact:
   *  - johnson: delta_i = P (1-nu_i^2)/(pi E_i) (2 ln(4 R_i/a) - 1)
   *    (Johnson, Contact Mechanics),
   *  - gerl_zippelius: delta_i = P (1-nu_i^2)/(pi E_i) (2 ln(4 R_i/a) - 1 -
   *    nu_i/(1-nu_i)) (Gerl & Zippelius 1999, eq. 55, plane strain form).
   */
  enum class ApproachLaw
  {
    gerl_zippelius,
    johnson
  };

  // "Gerl-Zippelius" or "Johnson" (exact spelling).
  inline constexpr EnumNames<ApproachLaw, 2> approach_law_names{
    "Hertz approach law",
    {{{ApproachLaw::gerl_zippelius, "Gerl-Zippelius"},
      {ApproachLaw::johnson, "Johnson"}}}};

  inline std::string
  to_string(const ApproachLaw law)
  {
    return approach_law_names.to_string(law);
  }

  /**
   * Quasi-static Hertz impact of two cylinders: m* delta'' = -P(delta),
   * delta(0) = 0, delta'(0) = closing speed, with m* = m1 m2 / (m1 + m2).
   *
   * The law is written delta(P) = delta_r x (1 - ln x), x = P / P_r, where
   * P_r is the force at which delta(P) is largest (the end of the rising
   * branch); the contact work is W(P) = W_r x^2 (1 - 2 ln x), W_r = W(P_r).
   * The constructor solves the motion once by energy conservation: the time
   * t(delta) is a Gauss quadrature of d delta / v(delta) near the start and,
   * near the turning point, of m* dv / P written in the angle phi with
   * v = v0 cos(phi), where both integrands are smooth. Queries solve, by
   * Newton within one stored interval, a Chebyshev series of t(s) that
   * interpolates the quadrature (contact_force_by_quadrature() solves the
   * quadrature itself). Unloading mirrors loading: P(t) = P(duration - t).
   */
  class HertzImpactReference
  {
  public:
    HertzImpactReference(const ElasticCylinder &body_1,
                         const ElasticCylinder &body_2,
                         const double           closing_speed,
                         const ApproachLaw      law);

    ApproachLaw
    approach_law() const;
    double
    closing_speed() const;

    // 1/R* = 1/R1 + 1/R2.
    double
    effective_radius() const;
    // 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2.
    double
    effective_modulus() const;
    // m* = m1 m2 / (m1 + m2), m_i = rho_i pi R_i^2.
    double
    effective_mass() const;
    // m* v0^2 / 2.
    double
    impact_energy() const;

    // Centre approach delta(P) of the chosen law, P >= 0. Beyond
    // rising_branch_force_limit() the formula decreases and is not physical.
    double
    approach(const double force) const;
    // The inverse of approach() on the rising branch, 0 <= delta <=
    // rising_branch_approach_limit().
    double
    force_from_approach(const double delta) const;
    // The force P_r where delta(P) is largest, and delta(P_r).
    double
    rising_branch_force_limit() const;
    double
    rising_branch_approach_limit() const;
    // Contact work W = integral_0^delta(P) P d delta (closed form), for P on
    // the rising branch; energy_capacity() = W(P_r).
    double
    contact_work(const double force) const;
    double
    energy_capacity() const;

    // Half width a = sqrt(4 P R* / (pi E*)).
    double
    half_width(const double force) const;
    // p0 = 2P / (pi a).
    double
    peak_pressure_of_force(const double force) const;
    // p0 sqrt(1 - x^2/a^2) for |x| < a, 0 otherwise.
    double
    pressure(const double force, const double x) const;

    // P(t): 0 before t = 0 and from contact_duration() on.
    double
    contact_force(const double time) const;
    // P(t) by Newton on the quadrature itself, without the Chebyshev series
    // of t(s) that contact_force() solves (50 times slower; for checks).
    double
    contact_force_by_quadrature(const double time) const;
    // delta(t): 0 outside the contact.
    double
    approach_at_time(const double time) const;
    // p0(P(t)).
    double
    max_contact_pressure(const double time) const;

    double
    peak_force() const;
    double
    time_of_peak() const;
    double
    contact_duration() const;
    double
    max_approach() const;
    double
    half_width_at_peak() const;
    double
    peak_pressure() const;

  private:
    // x = P / P_r from y = delta / delta_r, and from z = W / W_r, on [0, 1].
    static double
    relative_force_from_relative_approach(const double y);
    static double
    relative_force_from_relative_work(const double z);

    // The two phases of the loading half: parameter s (delta in phase 0,
    // phi in phase 1), the time integrand dt/ds, and the force at s.
    double
    time_integrand(const unsigned int phase, const double s) const;
    double
    force_at_parameter(const unsigned int phase, const double s) const;
    double
    time_between(const unsigned int phase,
                 const double       s_begin,
                 const double       s_end) const;
    // The interval of a phase that holds a time, and the parameter s at
    // that time in it: Newton on the quadrature, or on the Chebyshev series.
    unsigned int
    interval_of(const unsigned int phase, const double time) const;
    double
    parameter_by_quadrature(const unsigned int phase,
                            const unsigned int k,
                            const double       time) const;
    double
    parameter_by_interpolant(const unsigned int phase,
                             const unsigned int k,
                             const double       time) const;
    // The force and approach on the loading half at 0 <= time <= time_of_peak.
    void
    loading_state(const double time,
                  double      &force,
                  double      &delta,
                  const bool   by_quadrature = false) const;

    ApproachLaw law;
    double      v0;
    double      r_star;
    double      e_star;
    double      m_star;
    // a^2 = width_factor * P.
    double width_factor;
    // delta(P) = P (law_a - law_b ln P).
    double law_a;
    double law_b;
    double force_r;
    double approach_r;
    double work_r;

    double force_max;
    double approach_max;
    double t_peak;
    double t_split;

    // Nodes of the parameter and the time at each, per phase.
    std::vector<double> parameter_nodes[2];
    std::vector<double> time_nodes[2];
    // Per phase and interval, chebyshev_degree + 1 Chebyshev coefficients
    // of t(x) (x in [-1, 1] over the interval) and of dt/dx.
    static constexpr unsigned int chebyshev_degree = 16;
    std::vector<double>           time_coefficients[2];
    std::vector<double>           slope_coefficients_of_time[2];
  };
} // namespace isoimpact

#endif
