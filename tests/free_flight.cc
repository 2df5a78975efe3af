// Free flight of two half disks (R = 4, centres (0, 4) and (0, -5), 1 m
// apart, flying apart at 2 m/s each, so they never touch) with a non-uniform
// initial state that makes them vibrate: body 1 starts with a smooth
// non-rigid displacement, body 2 with a velocity that has shear and rotation
// parts. A PenaltyContact between the arcs is part of the run and must stay
// inactive. CentralDifference, 1000 steps of dt = 0.5 dt_crit
// (ElasticBody::estimate_critical_time_step, minimum of the bodies), with
// consistent, row-sum and HRZ mass. Checked:
// 1. Linear momentum of each body: with no external force
//    1_c^T M a = -1_c^T K u = 0 (K annihilates translations), so the
//    momentum is constant up to round-off: 1e-12 relative to |p|. Measured
//    5.9e-13 (row-sum), 5.7e-13 (HRZ), 2.2e-13 (consistent) after 1000
//    steps (t = 1.79 s resp. 1.11 s). The error grows like t^2: the round-off
//    of K times a translation (1_y^T K 1_y = 1.3e-11 for this mesh) is
//    multiplied by the rigid displacement 2 t that u accumulates, so the
//    tolerance is tied to this run length. The centre of mass moves with
//    p / m to the same accuracy.
// 2. Linearised angular momentum about the origin, L = r^T M v with
//    r_i = (-Y, X)[component] the infinitesimal rotation of the reference
//    nodes: r^T M a = -r^T K u = 0 (K r = 0, K symmetric), so L is conserved
//    to round-off as well: 1e-11 relative to |L| + |X| |p| (the momentum
//    moment sets the size of the terms that cancel).
// 3. Energy. For linear problems central differences conserve a modified
//    energy exactly: with v^n = v^{n+1/2} - dt/2 a^n and
//    u^{n+1} = u^n + dt v^{n+1/2}, the quadratic form
//      H^n = 1/2 v^{n+1/2} M v^{n+1/2} + 1/2 u^n K u^{n+1}
//    satisfies H^{n+1} = H^n identically, and expanding it in whole-step
//    quantities gives
//      H^n = E^n - dt^2/8 a^n M a^n,  E^n = 1/2 v^n M v^n + 1/2 u^n K u^n.
//    Hence (a) H^n is constant to round-off: 1e-10 relative to E^0 over the
//    1000 steps (round-off per step ~1e-15, accumulating at most linearly;
//    measured <= 2e-12); its drift over steps 500-1000 is at round-off like
//    over 0-500; and (b)
//    the energy the program reports oscillates but does not drift:
//      0 <= E^n - H <= dt^2/8 a^T M a <= dt^2 lambda_max / 4 * E_strain^n
//                   = (dt / dt_crit)^2 E_strain^n,
//    a rigorous bound (lambda_max = omega_max^2 = (2 / dt_crit)^2) asserted
//    at every step, with 1 % slack on dt_crit because the power iteration
//    only bounds lambda_max from below. Measured max |E - E0| / E0 =
//    6.5e-6 (row-sum), 6.7e-6 (HRZ), 3.5e-6 (consistent), no larger over steps
//    500-1000 than over 0-500. (c) The oscillation is O(dt^2): a
//    second run with dt/2 over the same time (2000 steps) must give a
//    maximum |E^n - E^0| smaller by a factor 4 (asserted in [3, 5]; the
//    accelerations at equal times agree up to the O(dt^2) phase error of the
//    scheme). Measured 3.99 for all three mass matrices.
// 4. The strain energy of the integrator's balance, which reuses the
//    product K u of the step's acceleration, equals 1/2 u.K u by a separate
//    product (ElasticBody::strain_energy) to 1e-12 of E^0 at every step.
// 5. A twin run that forms the whole-step velocity and acceleration only
//    every 7th step (as the program between outputs) has the same bits.
// 6. The displacement update split as a step beside the contact splits it
//    (ElasticBody::advance_displacement_of_rows: some rows, then all but
//    them) equals the whole update bit for bit.
#include <deal.II/base/numbers.h>

#include <isoimpact/discretization/discretization_fea.h>
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/contact.h>
#include <isoimpact/mechanics/elastic_body.h>
#include <isoimpact/time_integration/central_difference.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "tests.h"

using namespace dealii;

using namespace isoimpact;

namespace
{
  struct Body
  {
    std::unique_ptr<ElasticBody<2>> body;
    SparsityPattern                 sparsity;
    SparseMatrix<double>            consistent_mass;
    Vector<double>                  lumped_mass;
    Vector<double>                  rotation; // r_i

    double
    angular_momentum(const Vector<double> &v) const
    {
      if (body->mass_scheme() == MassScheme::consistent)
        return consistent_mass.matrix_scalar_product(rotation, v);
      double L = 0.;
      for (unsigned int i = 0; i < v.size(); ++i)
        L += rotation(i) * lumped_mass(i) * v(i);
      return L;
    }
  };

  std::unique_ptr<Body>
  make_body(const Point<2>    &center,
            const MassScheme   scheme,
            const Tensor<1, 2> velocity)
  {
    BodyGeometry geometry;
    geometry.center             = center;
    geometry.global_refinements = 2;
    auto result                 = std::make_unique<Body>();
    result->body                = std::make_unique<ElasticBody<2>>(
      "body",
      std::make_unique<DiscretizationFEA<2>>(geometry, 2),
      ElasticMaterial(),
      scheme,
      std::vector<RollerCondition>(),
      velocity);
    const Discretization<2>  &d = result->body->discretization();
    AffineConstraints<double> none;
    none.close();
    if (scheme == MassScheme::consistent)
      {
        make_sparsity_pattern(d, none, result->sparsity);
        result->consistent_mass.reinit(result->sparsity);
        assemble_consistent_mass_matrix(d, 1., none, result->consistent_mass);
      }
    else
      result->lumped_mass = assemble_lumped_mass(d, 1., scheme, none);
    result->rotation.reinit(d.n_dofs());
    for (unsigned int i = 0; i < d.n_dofs(); ++i)
      {
        const Point<2> X    = d.dof_position(i);
        result->rotation(i) = (d.dof_component(i) == 0) ? -X[1] : X[0];
      }
    return result;
  }

  double
  energy(const ElasticBody<2> &body,
         const Vector<double> &v,
         const Vector<double> &u)
  {
    return body.kinetic_energy(v) + body.strain_energy(u);
  }

  // Returns max_n |E^n - E^0| / E^0.
  double
  run(const MassScheme scheme, const double dt_factor, double &dt_used)
  {
    std::cout << "--- " << to_string(scheme) << " mass, dt = " << dt_factor
              << " dt_crit" << std::endl;
    auto body_1 = make_body(Point<2>(0., 4.), scheme, Tensor<1, 2>({0., 2.}));
    auto body_2 = make_body(Point<2>(0., -5.), scheme, Tensor<1, 2>({0., -2.}));
    std::vector<Body *> bodies = {body_1.get(), body_2.get()};

    // Body 1: smooth non-rigid displacement (max about 2 cm).
    {
      const auto &d = body_1->body->discretization();
      for (unsigned int i = 0; i < d.n_dofs(); ++i)
        {
          const Point<2> X = d.dof_position(i);
          const double   s = X[0] / 4., t = (X[1] - 4.) / 4.;
          body_1->body->displacement(i) =
            (d.dof_component(i) == 0) ? 0.02 * s * t : 0.01 * (s * s - t * t);
        }
    }
    // Body 2: shear and rotation on top of the translation.
    {
      const auto &d = body_2->body->discretization();
      for (unsigned int i = 0; i < d.n_dofs(); ++i)
        {
          const Point<2> X = d.dof_position(i);
          body_2->body->velocity(i) +=
            (d.dof_component(i) == 0) ? 0.1 * (X[1] + 5.) : 0.05 * X[0];
        }
    }

    const double dt_crit =
      std::min(body_1->body->estimate_critical_time_step(),
               body_2->body->estimate_critical_time_step());
    const double dt            = dt_factor * dt_crit;
    dt_used                    = dt;
    const unsigned int n_steps = std::lround(1000 * 0.5 / dt_factor);
    std::cout << "    dt_crit " << dt_crit << " s, dt " << dt << " s, "
              << n_steps << " steps" << std::endl;

    const PenaltyContact<2> contact(
      ContactSettings(),
      body_1->body->discretization().boundary_segments(
        BodyGeometry::curved_boundary_id),
      body_2->body->discretization().boundary_segments(
        BodyGeometry::curved_boundary_id));
    CentralDifference<2> integrator({body_1->body.get(), body_2->body.get()},
                                    {{&contact, 0, 1}},
                                    dt);
    integrator.initialize();

    // 5. A twin of the run whose steps form the whole-step velocity and
    // acceleration only every 7th step (CentralDifference::advance with
    // form_whole_step_state = false, as the program between outputs): the
    // displacements and the energy balance at every step, and the velocity
    // and acceleration at the forming steps, have the same bits as the run's.
    auto twin_1 = make_body(Point<2>(0., 4.), scheme, Tensor<1, 2>({0., 2.}));
    auto twin_2 = make_body(Point<2>(0., -5.), scheme, Tensor<1, 2>({0., -2.}));
    twin_1->body->displacement = body_1->body->displacement;
    twin_1->body->velocity     = body_1->body->velocity;
    twin_2->body->displacement = body_2->body->displacement;
    twin_2->body->velocity     = body_2->body->velocity;
    const PenaltyContact<2> twin_contact(
      ContactSettings(),
      twin_1->body->discretization().boundary_segments(
        BodyGeometry::curved_boundary_id),
      twin_2->body->discretization().boundary_segments(
        BodyGeometry::curved_boundary_id));
    CentralDifference<2> twin({twin_1->body.get(), twin_2->body.get()},
                              {{&twin_contact, 0, 1}},
                              dt);
    twin.initialize();
    double       max_twin_difference  = 0.;
    unsigned int twin_states_compared = 0;
    const auto   twin_difference      = [](const Vector<double> &x,
                                    const Vector<double> &y) {
      double difference = 0.;
      for (unsigned int i = 0; i < x.size(); ++i)
        difference = std::max(difference, std::abs(x(i) - y(i)));
      return difference;
    };

    std::vector<Tensor<1, 2>> p0, first_moment;
    std::vector<double>       L0, L_scale;
    double                    E0 = 0.;
    for (const Body *b : bodies)
      {
        p0.push_back(b->body->momentum(b->body->velocity));
        first_moment.push_back(b->body->momentum(b->body->displacement));
        L0.push_back(b->angular_momentum(b->body->velocity));
        L_scale.push_back(std::abs(L0.back()) + 9. * p0.back().norm());
        E0 += energy(*b->body, b->body->velocity, b->body->displacement);
      }
    // The integrator's balance uses the kinetic energy that central
    // differences conserve exactly, 1/2 v^- . M v^+ = K(v) - dt^2/4 K(a).
    double accelerations = 0.;
    for (const Body *b : bodies)
      accelerations += b->body->kinetic_energy(b->body->acceleration);
    const double E_balance0 = integrator.energy_balance().total();
    CHECK_CLOSE(E_balance0, E0 - 0.25 * dt * dt * accelerations, 1e-14);
    double max_balance_drift = 0.;
    // The balance's strain energy reuses the step's product K u
    // (ElasticBody::strain_energy_of_last_acceleration): equal to
    // 1/2 u.K u by a separate product to round-off.
    double       max_strain_mismatch = 0., max_kinetic_mismatch = 0.;
    unsigned int fused_energies_seen = 0;

    const auto shadow = [&]() {
      double H = 0.;
      for (const Body *b : bodies)
        {
          const auto    &body   = *b->body;
          Vector<double> v_half = body.velocity;
          v_half.add(-0.5 * dt, body.acceleration);
          Vector<double> u_old = body.displacement;
          u_old.add(-dt, v_half);
          H +=
            body.kinetic_energy(v_half) +
            0.5 *
              body.stiffness_matrix().matrix_scalar_product(u_old,
                                                            body.displacement);
        }
      return H;
    };

    double max_p_error = 0., max_L_error = 0.;
    double max_energy_deviation = 0., max_bound_violation = -1.;
    double shadow_first = 0., shadow_drift[2] = {0., 0.};
    double max_contact = 0., energy_deviation_half[2] = {0., 0.};
    double H_half = 0.;
    for (unsigned int n = 1; n <= n_steps; ++n)
      {
        integrator.advance();
        const EnergyBalance balance = integrator.energy_balance();
        {
          const bool form_state = (n % 7 == 0);
          twin.advance(false, form_state);
          max_twin_difference =
            std::max({max_twin_difference,
                      std::abs(twin.energy_balance().total() - balance.total()),
                      twin_difference(twin_1->body->displacement,
                                      body_1->body->displacement),
                      twin_difference(twin_2->body->displacement,
                                      body_2->body->displacement)});
          if (form_state)
            {
              for (const auto &[twin_body, body] :
                   {std::make_pair(twin_1->body.get(), body_1->body.get()),
                    std::make_pair(twin_2->body.get(), body_2->body.get())})
                max_twin_difference = std::max(
                  {max_twin_difference,
                   twin_difference(twin_body->velocity, body->velocity),
                   twin_difference(twin_body->acceleration,
                                   body->acceleration)});
              ++twin_states_compared;
            }
        }
        max_contact =
          std::max({max_contact,
                    balance.contact,
                    integrator.contact_results()[0].force_on_body_0.norm(),
                    double(integrator.contact_results()[0].n_active_points)});

        double strain = 0.;
        for (unsigned int b = 0; b < 2; ++b)
          {
            const auto &body = *bodies[b]->body;
            max_p_error =
              std::max(max_p_error,
                       (body.momentum(body.velocity) - p0[b]).norm() /
                         p0[b].norm());
            max_L_error =
              std::max(max_L_error,
                       std::abs(bodies[b]->angular_momentum(body.velocity) -
                                L0[b]) /
                         L_scale[b]);
            strain += body.strain_energy(body.displacement);
          }
        max_strain_mismatch =
          std::max(max_strain_mismatch, std::abs(balance.strain - strain) / E0);
        // The kinetic energy 1/2 v^{n-1/2} . M v^{n+1/2}: summed in the step,
        // equal to the separate function.
        double kinetic = 0.;
        for (const Body *b : bodies)
          {
            const auto    &body   = *b->body;
            Vector<double> v_half = body.velocity;
            v_half.add(0.5 * dt, body.acceleration);
            kinetic += body.kinetic_energy_at_full_step(v_half, dt);
            fused_energies_seen +=
              body.energies_of_last_step().has_value() ? 1 : 0;
          }
        max_kinetic_mismatch =
          std::max(max_kinetic_mismatch,
                   std::abs(balance.kinetic - kinetic) / E0);
        max_balance_drift =
          std::max(max_balance_drift,
                   std::abs(balance.total() - E_balance0) / E0);
        double E = 0.;
        for (const Body *b : bodies)
          E += energy(*b->body, b->body->velocity, b->body->displacement);
        const double H = shadow();
        if (n == 1)
          shadow_first = H;
        if (n == n_steps / 2)
          H_half = H;
        // Drift of H over the first and the second half of the run.
        if (n <= n_steps / 2)
          shadow_drift[0] =
            std::max(shadow_drift[0], std::abs(H - shadow_first) / E0);
        else
          shadow_drift[1] =
            std::max(shadow_drift[1], std::abs(H - H_half) / E0);
        // 0 <= E - H <= (dt / dt_crit)^2 E_strain (1 % slack on dt_crit).
        const double bound = std::pow(dt / (0.99 * dt_crit), 2) * strain;
        max_bound_violation =
          std::max({max_bound_violation, (E - H) - bound, H - E - 1e-12 * E0});
        max_energy_deviation =
          std::max(max_energy_deviation, std::abs(E - E0) / E0);
        energy_deviation_half[n <= n_steps / 2 ? 0 : 1] =
          std::max(energy_deviation_half[n <= n_steps / 2 ? 0 : 1],
                   std::abs(E - E0) / E0);
      }
    std::cout << "    E0 " << E0 << " J/m, max |E - E0| / E0 "
              << max_energy_deviation << ", shadow drift " << shadow_drift[0]
              << " (first half), " << shadow_drift[1] << " (second half)"
              << "; max |E - E0| / E0 " << energy_deviation_half[0]
              << " (first half), " << energy_deviation_half[1]
              << " (second half)" << std::endl;
    std::cout << "    twin run forming the state every 7th step: max "
                 "difference "
              << max_twin_difference << " over " << n_steps << " steps, "
              << twin_states_compared << " states compared" << std::endl;
    CHECK_CLOSE_ABS(max_twin_difference, 0., 0.);
    CHECK_CLOSE_ABS(twin_states_compared, n_steps / 7, 0.);
    CHECK_CLOSE_ABS(max_p_error, 0., 1e-12);
    CHECK_CLOSE_ABS(max_L_error, 0., 1e-11);
    CHECK_CLOSE_ABS(max_contact, 0., 0.);
    CHECK_CLOSE_ABS(max_balance_drift, 0., 1e-10);
    CHECK_CLOSE_ABS(max_strain_mismatch, 0., 1e-12);
    CHECK_CLOSE_ABS(max_kinetic_mismatch, 0., 1e-12);
    // Every body sums both energies in the step (every step, both bodies):
    // lumped ones in the fused pass, consistent ones in the velocity update
    // from the M v^{n+1/2} they carry, equal to the separate product to
    // 1e-12 above.
    CHECK_CLOSE_ABS(fused_energies_seen, 2. * n_steps, 0.);
    CHECK_CLOSE_ABS(shadow_drift[0], 0., 1e-10);
    CHECK_CLOSE_ABS(shadow_drift[1], 0., 1e-10);
    CHECK_TRUE(max_bound_violation <= 0.);
    // No growth: the oscillation of E over steps 500-1000 is not larger than
    // over 0-500 (measured ratios 0.87 .. 0.94; 1.5 allows for where the
    // peaks of |a|_M fall, a growing energy would exceed it).
    CHECK_TRUE(energy_deviation_half[1] <= 1.5 * energy_deviation_half[0]);
    // The state does change: energy is exchanged between the modes, and the
    // bodies have moved 2 m/s * t.
    CHECK_TRUE(max_energy_deviation > 1e-8);
    // Centre of mass: 1_c^T M u^n = 1_c^T M u^0 + t p (u advances with the
    // half-step velocities, whose momentum is p), 1e-12 relative to |t p|.
    for (unsigned int b = 0; b < 2; ++b)
      {
        const auto        &body = *bodies[b]->body;
        const Tensor<1, 2> moved =
          body.momentum(body.displacement) - first_moment[b];
        CHECK_CLOSE_ABS((moved - integrator.time() * p0[b]).norm() /
                          (integrator.time() * p0[b].norm()),
                        0.,
                        1e-12);
      }
    // 6. The split displacement update of a step beside the contact (the
    //    surfaces' rows, then all but them) equals the whole one, bit for
    //    bit: rows at both ends and adjacent ones, and no rows at all.
    {
      ElasticBody<2>      &body  = *body_1->body;
      const Vector<double> start = body.displacement;
      Vector<double>       v     = body.velocity;
      body.advance_displacement(v, dt);
      const Vector<double>          whole            = body.displacement;
      const types::global_dof_index n                = body.n_dofs();
      double                        split_difference = 0.;
      for (const std::vector<types::global_dof_index> &rows :
           {std::vector<types::global_dof_index>{0, 5, 6, n / 2, n - 1},
            std::vector<types::global_dof_index>{}})
        {
          body.displacement = start;
          body.advance_displacement_of_rows(v, dt, rows, false);
          body.advance_displacement_of_rows(v, dt, rows, true);
          split_difference =
            std::max(split_difference,
                     twin_difference(body.displacement, whole));
        }
      body.displacement = start;
      std::cout << "    split displacement update against the whole: max "
                   "difference "
                << split_difference << std::endl;
      CHECK_CLOSE_ABS(split_difference, 0., 0.);
      CHECK_TRUE(whole.l2_norm() != start.l2_norm());
    }
    return max_energy_deviation;
  }
} // namespace

int
main()
{
  for (const MassScheme scheme :
       {MassScheme::row_sum, MassScheme::hrz, MassScheme::consistent})
    {
      double       dt_1, dt_2;
      const double deviation_1 = run(scheme, 0.5, dt_1);
      const double deviation_2 = run(scheme, 0.25, dt_2);
      const double ratio       = deviation_1 / deviation_2;
      std::cout << "    ratio of the energy oscillations for dt and dt/2: "
                << ratio << std::endl;
      CHECK_TRUE(ratio > 3. && ratio < 5.);
    }
  return isoimpact_tests::report();
}
