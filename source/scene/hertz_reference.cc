#include <deal.II/base/exceptions.h>
#include <deal.II/base/quadrature_lib.h>

#include <isoimpact/scene/hertz_reference.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    // Intervals per phase and Gauss points per interval: t_peak converges
    // to machine precision well below these (see doc/hertz-reference.md).
    constexpr unsigned int n_intervals    = 32;
    constexpr unsigned int n_gauss_points = 10;

    // sum_{m <= degree} c_m T_m(x) by Clenshaw's recurrence.
    double
    chebyshev_sum(const double *const c,
                  const unsigned int  degree,
                  const double        x)
    {
      double b_1 = 0., b_2 = 0.;
      for (unsigned int m = degree; m >= 1; --m)
        {
          const double b = 2. * x * b_1 - b_2 + c[m];
          b_2            = b_1;
          b_1            = b;
        }
      return x * b_1 - b_2 + c[0];
    }

    // The root of an increasing function in [lower, upper] by Newton from
    // `x`, safeguarded by bisection; residual_and_slope(x) returns both.
    // Stops when a step or the bracket is at most `tolerance`.
    template <typename Function>
    double
    safeguarded_newton(double          lower,
                       double          upper,
                       double          x,
                       const double    tolerance,
                       const Function &residual_and_slope)
    {
      for (unsigned int iteration = 0; iteration < 100; ++iteration)
        {
          const auto [residual, slope] = residual_and_slope(x);
          if (residual < 0.)
            lower = x;
          else
            upper = x;
          double x_new = (slope > 0.) ? x - residual / slope : lower - 1.;
          if (!(x_new >= lower && x_new <= upper))
            x_new = 0.5 * (lower + upper);
          const double step = std::abs(x_new - x);
          x                 = x_new;
          if (step <= tolerance || upper - lower <= tolerance)
            break;
        }
      return x;
    }

    const dealii::Quadrature<1> &
    gauss_rule()
    {
      static const dealii::QGauss<1> rule(n_gauss_points);
      return rule;
    }

    std::string
    number(const double value)
    {
      std::ostringstream stream;
      stream.precision(10);
      stream << value;
      return stream.str();
    }

    void
    check_cylinder(const ElasticCylinder &body, const std::string &name)
    {
      AssertThrow(std::isfinite(body.radius) && body.radius > 0.,
                  dealii::ExcMessage("HertzImpactReference: the radius of " +
                                     name + " is " + number(body.radius) +
                                     "; it must be positive."));
      AssertThrow(
        std::isfinite(body.youngs_modulus) && body.youngs_modulus > 0.,
        dealii::ExcMessage("HertzImpactReference: Young's modulus of " + name +
                           " is " + number(body.youngs_modulus) +
                           "; it must be positive."));
      AssertThrow(std::isfinite(body.poisson_ratio) &&
                    body.poisson_ratio > -1. && body.poisson_ratio < 0.5,
                  dealii::ExcMessage(
                    "HertzImpactReference: Poisson's ratio of " + name +
                    " is " + number(body.poisson_ratio) +
                    "; plane strain needs -1 < nu < 0.5."));
      AssertThrow(std::isfinite(body.density) && body.density > 0.,
                  dealii::ExcMessage("HertzImpactReference: the density of " +
                                     name + " is " + number(body.density) +
                                     "; it must be positive."));
    }
  } // namespace



  HertzImpactReference::HertzImpactReference(const ElasticCylinder &body_1,
                                             const ElasticCylinder &body_2,
                                             const double      closing_speed,
                                             const ApproachLaw law)
    : law(law)
    , v0(closing_speed)
  {
    check_cylinder(body_1, "body 1");
    check_cylinder(body_2, "body 2");
    AssertThrow(std::isfinite(closing_speed) && closing_speed > 0.,
                dealii::ExcMessage(
                  "HertzImpactReference: the closing speed is " +
                  number(closing_speed) + "; it must be positive."));

    const ElasticCylinder *bodies[2] = {&body_1, &body_2};

    r_star            = 1. / (1. / body_1.radius + 1. / body_2.radius);
    double compliance = 0.;
    for (const ElasticCylinder *body : bodies)
      compliance +=
        (1. - body->poisson_ratio * body->poisson_ratio) / body->youngs_modulus;
    e_star = 1. / compliance;

    const double m_1 = body_1.density * pi * body_1.radius * body_1.radius;
    const double m_2 = body_2.density * pi * body_2.radius * body_2.radius;
    m_star           = m_1 * m_2 / (m_1 + m_2);

    // delta = sum_i c_i P (2 ln(4 R_i) - ln(width_factor P) - k_i)
    //       = P (law_a - law_b ln P), law_b = sum_i c_i = 1 / (pi E*).
    width_factor = 4. * r_star / (pi * e_star);
    law_b        = 1. / (pi * e_star);
    // ln(P_r) = law_a / law_b - 1, where d delta / dP = 0.
    double log_force_r = -std::log(width_factor) - 1.;
    for (const ElasticCylinder *body : bodies)
      {
        const double nu = body->poisson_ratio;
        const double c  = (1. - nu * nu) / (pi * body->youngs_modulus) / law_b;
        const double k =
          (law == ApproachLaw::gerl_zippelius) ? 1. + nu / (1. - nu) : 1.;
        log_force_r += c * (2. * std::log(4. * body->radius) - k);
      }
    law_a      = law_b * (log_force_r + 1.);
    force_r    = std::exp(log_force_r);
    approach_r = law_b * force_r;
    work_r     = law_b * force_r * force_r / 4.;
    AssertThrow(std::isfinite(force_r) && force_r > 0.,
                dealii::ExcMessage(
                  "HertzImpactReference: the end of the rising branch of "
                  "delta(P), P_r = " +
                  number(force_r) + ", is not a positive finite number."));

    AssertThrow(impact_energy() < energy_capacity(),
                dealii::ExcMessage(
                  "HertzImpactReference: the impact energy m* v0^2/2 = " +
                  number(impact_energy()) +
                  " exceeds the work the rising branch of the " +
                  to_string(law) + " law can absorb, " +
                  number(energy_capacity()) + " (at P = " + number(force_r) +
                  "); the closing speed must be below " +
                  number(std::sqrt(2. * energy_capacity() / m_star)) + "."));

    force_max =
      force_r * relative_force_from_relative_work(impact_energy() / work_r);
    approach_max = approach(force_max);

    // Phase 0: delta in [0, delta_max / 2]. Phase 1: phi in [phi_split,
    // pi/2], where phi_split is the angle at delta_max / 2.
    const double delta_split = approach_max / 2.;
    const double phi_split   = std::asin(std::sqrt(
      contact_work(force_from_approach(delta_split)) / impact_energy()));
    const double ends[2][2]  = {{0., delta_split}, {phi_split, pi / 2.}};

    double time = 0.;
    for (unsigned int phase = 0; phase < 2; ++phase)
      {
        parameter_nodes[phase].resize(n_intervals + 1);
        time_nodes[phase].resize(n_intervals + 1);
        for (unsigned int k = 0; k <= n_intervals; ++k)
          parameter_nodes[phase][k] =
            ends[phase][0] +
            (ends[phase][1] - ends[phase][0]) * k / n_intervals;
        time_nodes[phase][0] = time;
        for (unsigned int k = 0; k < n_intervals; ++k)
          {
            time += time_between(phase,
                                 parameter_nodes[phase][k],
                                 parameter_nodes[phase][k + 1]);
            time_nodes[phase][k + 1] = time;
          }
        if (phase == 0)
          t_split = time;
      }
    t_peak = time;

    // Queries: t(s) on each interval as a Chebyshev series of the degree
    // chebyshev_degree, interpolating the quadrature at the Chebyshev-
    // Lobatto points, and the series of its slope. A query then solves the
    // series by Newton instead of the quadrature; the forces of the two
    // agree to 1e-14 of the peak force on the benchmark
    // (tests/hertz_reference.cc).
    constexpr unsigned int    n = chebyshev_degree;
    std::array<double, n + 1> values, coefficients;
    for (unsigned int phase = 0; phase < 2; ++phase)
      {
        time_coefficients[phase].assign(n_intervals * (n + 1), 0.);
        slope_coefficients_of_time[phase].assign(n_intervals * (n + 1), 0.);
        for (unsigned int k = 0; k < n_intervals; ++k)
          {
            const double s_k    = parameter_nodes[phase][k];
            const double length = parameter_nodes[phase][k + 1] - s_k;
            // x_j = cos(pi j / n), from x = 1 down to x = -1; the time
            // accumulated point to point, from s_k upwards.
            values[n] = time_nodes[phase][k];
            for (unsigned int j = n; j-- > 0;)
              values[j] =
                values[j + 1] +
                time_between(phase,
                             s_k +
                               0.5 * length * (1. + std::cos(pi * (j + 1) / n)),
                             s_k + 0.5 * length * (1. + std::cos(pi * j / n)));
            for (unsigned int m = 0; m <= n; ++m)
              {
                double sum = 0.;
                for (unsigned int j = 0; j <= n; ++j)
                  sum += ((j == 0 || j == n) ? 0.5 : 1.) * values[j] *
                         std::cos(pi * double(m * j % (2 * n)) / n);
                coefficients[m] = ((m == 0 || m == n) ? 1. : 2.) * sum / n;
              }
            double *const a = &time_coefficients[phase][k * (n + 1)];
            double *const b = &slope_coefficients_of_time[phase][k * (n + 1)];
            std::copy(coefficients.begin(), coefficients.end(), a);
            // d/dx sum a_m T_m = sum b_m T_m: b_{m-1} = b_{m+1} + 2 m a_m,
            // b_0 halved.
            for (unsigned int m = n; m >= 1; --m)
              b[m - 1] = ((m + 1 <= n) ? b[m + 1] : 0.) + 2. * m * a[m];
            b[0] *= 0.5;
          }
      }
  }



  double
  HertzImpactReference::relative_force_from_relative_approach(const double y)
  {
    // Solves x (1 - ln x) = y for x in [0, 1], as g(u) = u + ln(1 - u) - ln y
    // = 0 in u = ln x <= 0, g increasing; safeguarded Newton.
    Assert(y >= 0. && y <= 1., dealii::ExcInternalError());
    if (y <= 0.)
      return 0.;
    if (y >= 1.)
      return 1.;
    const double log_y = std::log(y);
    double       lower = log_y - std::log1p(-log_y) - 1.; // g(lower) < 0
    double       upper = 0.;                              // g(upper) > 0
    double       u     = std::min(log_y - std::log1p(-log_y), -1e-3);
    for (unsigned int iteration = 0; iteration < 200; ++iteration)
      {
        const double g = u + std::log1p(-u) - log_y;
        if (g < 0.)
          lower = u;
        else
          upper = u;
        const double slope = -u / (1. - u);
        double       u_new = (slope > 0.) ? u - g / slope : lower - 1.;
        if (!(u_new > lower && u_new < upper))
          u_new = 0.5 * (lower + upper);
        const double step = std::abs(u_new - u);
        u                 = u_new;
        if (step <= 2. * std::numeric_limits<double>::epsilon() *
                      std::max(1., std::abs(u)) ||
            upper - lower <= 2. * std::numeric_limits<double>::epsilon() *
                               std::max(1., std::abs(u)))
          break;
      }
    return std::exp(u);
  }



  double
  HertzImpactReference::relative_force_from_relative_work(const double z)
  {
    // x^2 (1 - 2 ln x) = f(x^2) with f(x) = x (1 - ln x).
    return std::sqrt(relative_force_from_relative_approach(z));
  }



  double
  HertzImpactReference::time_integrand(const unsigned int phase,
                                       const double       s) const
  {
    if (phase == 0)
      {
        // dt / d delta = 1 / v, v^2 = v0^2 (1 - W / (m* v0^2 / 2)).
        const double work = contact_work(force_from_approach(s));
        return 1. / (v0 * std::sqrt(std::max(0., 1. - work / impact_energy())));
      }
    // v = v0 cos phi, dt = -m* dv / P = m* v0 sin phi d phi / P.
    return m_star * v0 * std::sin(s) / force_at_parameter(phase, s);
  }



  double
  HertzImpactReference::force_at_parameter(const unsigned int phase,
                                           const double       s) const
  {
    if (phase == 0)
      return force_from_approach(s);
    const double sine = std::sin(s);
    return force_r * relative_force_from_relative_work(
                       std::min(1., impact_energy() * sine * sine / work_r));
  }



  double
  HertzImpactReference::time_between(const unsigned int phase,
                                     const double       s_begin,
                                     const double       s_end) const
  {
    const dealii::Quadrature<1> &rule   = gauss_rule();
    const double                 length = s_end - s_begin;
    double                       sum    = 0.;
    for (unsigned int q = 0; q < rule.size(); ++q)
      sum += rule.weight(q) *
             time_integrand(phase, s_begin + length * rule.point(q)[0]);
    return sum * length;
  }



  unsigned int
  HertzImpactReference::interval_of(const unsigned int phase,
                                    const double       time) const
  {
    const std::vector<double> &times = time_nodes[phase];
    return std::min<unsigned int>(
      std::max<long>(std::upper_bound(times.begin(), times.end(), time) -
                       times.begin() - 1,
                     0),
      times.size() - 2);
  }



  double
  HertzImpactReference::parameter_by_quadrature(const unsigned int phase,
                                                const unsigned int k,
                                                const double       time) const
  {
    const std::vector<double> &times = time_nodes[phase];
    const std::vector<double> &nodes = parameter_nodes[phase];
    // Newton on t_k + integral_{s_k}^s dt/ds = time within [s_k, s_k+1].
    const double start =
      nodes[k] +
      (nodes[k + 1] - nodes[k]) *
        std::clamp((time - times[k]) / (times[k + 1] - times[k]), 0., 1.);
    return safeguarded_newton(nodes[k],
                              nodes[k + 1],
                              start,
                              1e-15 * (nodes[k + 1] - nodes[k]),
                              [&](const double s) {
                                return std::make_pair(
                                  times[k] + time_between(phase, nodes[k], s) -
                                    time,
                                  time_integrand(phase, s));
                              });
  }



  double
  HertzImpactReference::parameter_by_interpolant(const unsigned int phase,
                                                 const unsigned int k,
                                                 const double       time) const
  {
    const std::vector<double> &times = time_nodes[phase];
    const std::vector<double> &nodes = parameter_nodes[phase];
    const double *const        value_coefficients =
      &time_coefficients[phase][k * (chebyshev_degree + 1)];
    const double *const slope_coefficients =
      &slope_coefficients_of_time[phase][k * (chebyshev_degree + 1)];
    // Newton on the Chebyshev series of t(x), x in [-1, 1] spanning
    // [s_k, s_k+1], safeguarded by bisection (t increases with x).
    const double start =
      -1. +
      2. * std::clamp((time - times[k]) / (times[k + 1] - times[k]), 0., 1.);
    const double x =
      safeguarded_newton(-1., 1., start, 2e-15, [&](const double x) {
        return std::make_pair(
          chebyshev_sum(value_coefficients, chebyshev_degree, x) - time,
          chebyshev_sum(slope_coefficients, chebyshev_degree - 1, x));
      });
    return nodes[k] + 0.5 * (x + 1.) * (nodes[k + 1] - nodes[k]);
  }



  void
  HertzImpactReference::loading_state(const double time,
                                      double      &force,
                                      double      &delta,
                                      const bool   by_quadrature) const
  {
    const unsigned int phase = (time <= t_split) ? 0 : 1;
    const unsigned int k     = interval_of(phase, time);
    const double s = by_quadrature ? parameter_by_quadrature(phase, k, time) :
                                     parameter_by_interpolant(phase, k, time);
    force          = force_at_parameter(phase, s);
    delta          = (phase == 0) ? s : approach(force);
  }



  ApproachLaw
  HertzImpactReference::approach_law() const
  {
    return law;
  }



  double
  HertzImpactReference::closing_speed() const
  {
    return v0;
  }



  double
  HertzImpactReference::effective_radius() const
  {
    return r_star;
  }



  double
  HertzImpactReference::effective_modulus() const
  {
    return e_star;
  }



  double
  HertzImpactReference::effective_mass() const
  {
    return m_star;
  }



  double
  HertzImpactReference::impact_energy() const
  {
    return 0.5 * m_star * v0 * v0;
  }



  double
  HertzImpactReference::approach(const double force) const
  {
    AssertThrow(std::isfinite(force) && force >= 0.,
                dealii::ExcMessage("HertzImpactReference::approach: the force "
                                   "is " +
                                   number(force) +
                                   "; it must be non-negative."));
    if (force == 0.)
      return 0.;
    const double x = force / force_r;
    return approach_r * x * (1. - std::log(x));
  }



  double
  HertzImpactReference::force_from_approach(const double delta) const
  {
    AssertThrow(
      std::isfinite(delta) && delta >= 0. && delta <= approach_r,
      dealii::ExcMessage(
        "HertzImpactReference::force_from_approach: the approach is " +
        number(delta) + "; allowed is 0 <= delta <= " + number(approach_r) +
        ", the maximum of delta(P) (end of the rising branch)."));
    return force_r * relative_force_from_relative_approach(delta / approach_r);
  }



  double
  HertzImpactReference::rising_branch_force_limit() const
  {
    return force_r;
  }



  double
  HertzImpactReference::rising_branch_approach_limit() const
  {
    return approach_r;
  }



  double
  HertzImpactReference::contact_work(const double force) const
  {
    AssertThrow(std::isfinite(force) && force >= 0. && force <= force_r,
                dealii::ExcMessage(
                  "HertzImpactReference::contact_work: the force is " +
                  number(force) + "; allowed is 0 <= P <= " + number(force_r) +
                  ", the end of the rising branch."));
    if (force == 0.)
      return 0.;
    const double x = force / force_r;
    return work_r * x * x * (1. - 2. * std::log(x));
  }



  double
  HertzImpactReference::energy_capacity() const
  {
    return work_r;
  }



  double
  HertzImpactReference::half_width(const double force) const
  {
    AssertThrow(std::isfinite(force) && force >= 0.,
                dealii::ExcMessage("HertzImpactReference::half_width: the "
                                   "force is " +
                                   number(force) +
                                   "; it must be non-negative."));
    return std::sqrt(width_factor * force);
  }



  double
  HertzImpactReference::peak_pressure_of_force(const double force) const
  {
    const double a = half_width(force);
    return (a > 0.) ? 2. * force / (pi * a) : 0.;
  }



  double
  HertzImpactReference::pressure(const double force, const double x) const
  {
    const double a = half_width(force);
    if (!(std::abs(x) < a))
      return 0.;
    const double ratio = x / a;
    return peak_pressure_of_force(force) * std::sqrt(1. - ratio * ratio);
  }



  double
  HertzImpactReference::contact_force(const double time) const
  {
    if (!(time > 0. && time < contact_duration()))
      return 0.;
    double force, delta;
    loading_state(std::min(time, contact_duration() - time), force, delta);
    return force;
  }



  double
  HertzImpactReference::contact_force_by_quadrature(const double time) const
  {
    if (!(time > 0. && time < contact_duration()))
      return 0.;
    double force, delta;
    loading_state(std::min(time, contact_duration() - time),
                  force,
                  delta,
                  true);
    return force;
  }



  double
  HertzImpactReference::approach_at_time(const double time) const
  {
    if (!(time > 0. && time < contact_duration()))
      return 0.;
    double force, delta;
    loading_state(std::min(time, contact_duration() - time), force, delta);
    return delta;
  }



  double
  HertzImpactReference::max_contact_pressure(const double time) const
  {
    return peak_pressure_of_force(contact_force(time));
  }



  double
  HertzImpactReference::peak_force() const
  {
    return force_max;
  }



  double
  HertzImpactReference::time_of_peak() const
  {
    return t_peak;
  }



  double
  HertzImpactReference::contact_duration() const
  {
    return 2. * t_peak;
  }



  double
  HertzImpactReference::max_approach() const
  {
    return approach_max;
  }



  double
  HertzImpactReference::half_width_at_peak() const
  {
    return half_width(force_max);
  }



  double
  HertzImpactReference::peak_pressure() const
  {
    return peak_pressure_of_force(force_max);
  }
} // namespace isoimpact
