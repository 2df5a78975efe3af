// The bipenalty's mass penalty (Contact/Bipenalty, doc/formulation.md) on
// two half disks (R = 4 m, 64 cells each, HRZ mass, FEA Q9 and IGA p2), the
// upper one displaced by -0.1 m so that the arcs overlap near the first
// point of contact, eps_N = 1e5 Pa/m, eps_m = 0.3 kg/m^2 per pass:
// 1. Lumping: the penalty mass of each body, summed per component, is the
//    same for x and y and for both bodies (each active point puts eps_m w on
//    its own nodes and eps_m w on those at its projection): 1e-12.
// 2. The bound of the stable step: lambda_max(K_c, M_c) of the contact
//    stiffness K_c (central differences of the contact forces in the
//    unknowns that carry penalty mass, 1e-7 m) against the lumped mass
//    penalty M_c is at most C / eps_m = 2 Lambda^2 eps_pass / eps_m with
//    Lambda = 1.25 (quadratic Lagrange faces) and 1 (NURBS), the constant
//    of PenaltyContact::bipenalty_stiffness (checked to 1e-12 against these
//    values). Measured ratio lambda_max eps_m / C: printed.
// 3. The spring-mass of one unknown: the lumped step with the penalty mass
//    gives a_i = (f - K u)_i / (m_i + m_p,i) to 1e-14; with the velocity
//    kept the energy the switch brings in is 1/2 m_p v^2, with the momentum
//    kept v' = m v / (m + m_p) (1e-15) and 1/2 (m + m_p) v'^2 - 1/2 m v^2
//    (1e-13); removing the masses restores the bulk accelerations bit for
//    bit.
// 4. The critical step ratio of the scene: with eps_m = f margin C
//    dt_bulk^2 / 4 the contact mode's bound 2 / omega_c, omega_c^2 = margin
//    C / eps_m, is sqrt(f) dt_bulk (1e-12), and scene_stable_time_step is
//    the bound with the stiffness springs capped by it (f = 0.01, 0.25, 1,
//    4; 1e-12).
#include <deal.II/lac/lapack_full_matrix.h>

#include <isoimpact/discretization/discretization.h>
#include <isoimpact/mechanics/contact.h>
#include <isoimpact/mechanics/elastic_body.h>
#include <isoimpact/mechanics/stable_time_step.h>
#include <isoimpact/time_integration/stability_monitor.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "tests.h"

using namespace dealii;
using namespace isoimpact;

namespace
{
  std::unique_ptr<ElasticBody<2>>
  make_body(const DiscretizationMethod method, const Point<2> &center)
  {
    BodyGeometry geometry;
    geometry.center             = center;
    geometry.global_refinements = 2; // right half disks, cut x = 0
    return std::make_unique<ElasticBody<2>>("body",
                                            create_discretization<2>(method,
                                                                     geometry,
                                                                     2),
                                            ElasticMaterial(),
                                            MassScheme::hrz,
                                            std::vector<RollerCondition>(),
                                            Tensor<1, 2>());
  }

  void
  run(const DiscretizationMethod method, const double lebesgue)
  {
    std::cout << "--- " << (method == DiscretizationMethod::fea ? "FEA" : "IGA")
              << std::endl;
    auto body_1 = make_body(method, Point<2>(0., 4.));
    auto body_2 = make_body(method, Point<2>(0., -4.));
    for (unsigned int i = 0; i < body_1->n_dofs(); ++i)
      if (body_1->discretization().dof_component(i) == 1)
        body_1->displacement(i) = -0.1;

    ContactSettings settings;
    settings.penalty = 1e5;
    PenaltyContact<2> contact(settings,
                              body_1->discretization().boundary_segments(
                                BodyGeometry::curved_boundary_id),
                              body_2->discretization().boundary_segments(
                                BodyGeometry::curved_boundary_id));
    const double      C = contact.bipenalty_stiffness();
    CHECK_CLOSE(C, 2. * lebesgue * lebesgue * 0.5e5, 1e-12);
    const double eps_m = 0.3;
    contact.set_bipenalty_mass(eps_m);

    std::vector<ElasticBody<2> *> bodies = {body_1.get(), body_2.get()};
    const auto evaluate                  = [&](std::vector<Vector<double>> &f) {
      f.assign(2, Vector<double>());
      f[0].reinit(body_1->n_dofs());
      f[1].reinit(body_2->n_dofs());
      return contact.evaluate({&body_1->displacement, &body_2->displacement},
                              {},
                              {&f[0], &f[1]},
                              false);
    };
    std::vector<Vector<double>> f0;
    const ContactResult<2>      result = evaluate(f0);
    CHECK_TRUE(result.n_active_points > 4);

    // 1. Sums per body and component.
    double sums[2][2] = {{0., 0.}, {0., 0.}};
    // The unknowns with penalty mass, (body, unknown) -> mass.
    std::map<std::pair<unsigned int, unsigned int>, double> masses;
    double                                                  smallest = 0.;
    for (unsigned int b = 0; b < 2; ++b)
      for (const auto &[i, m] : result.penalty_masses[b])
        {
          smallest = std::min(smallest, m);
          sums[b][bodies[b]->discretization().dof_component(i)] += m;
          masses[{b, i}] += m;
        }
    std::cout << "    penalty mass per component " << sums[0][0] << " kg/m"
              << std::endl;
    CHECK_TRUE(smallest >= 0. && sums[0][0] > 0.);
    CHECK_CLOSE(sums[0][1], sums[0][0], 1e-12);
    CHECK_CLOSE(sums[1][0], sums[0][0], 1e-12);
    CHECK_CLOSE(sums[1][1], sums[0][0], 1e-12);

    // 2. lambda_max(K_c, M_c) on the unknowns with penalty mass.
    std::vector<std::pair<unsigned int, unsigned int>> unknowns;
    std::vector<double>                                mass;
    for (const auto &[key, m] : masses)
      if (m > 0.)
        {
          unknowns.push_back(key);
          mass.push_back(m);
        }
    const unsigned int            n = unknowns.size();
    LAPACKFullMatrix<double>      stiffness(n, n);
    const double                  h   = 1e-7;
    std::vector<ElasticBody<2> *> all = bodies;
    for (unsigned int j = 0; j < n; ++j)
      {
        std::vector<Vector<double>> fp, fm;
        auto                       &u = all[unknowns[j].first]->displacement;
        u(unknowns[j].second) += h;
        evaluate(fp);
        u(unknowns[j].second) -= 2. * h;
        evaluate(fm);
        u(unknowns[j].second) += h;
        for (unsigned int i = 0; i < n; ++i)
          // K = -d f / d u, scaled by the masses.
          stiffness(i, j) = -(fp[unknowns[i].first](unknowns[i].second) -
                              fm[unknowns[i].first](unknowns[i].second)) /
                            (2. * h) / std::sqrt(mass[i] * mass[j]);
      }
    LAPACKFullMatrix<double> symmetric(n, n);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        symmetric(i, j) = 0.5 * (stiffness(i, j) + stiffness(j, i));
    symmetric.compute_eigenvalues();
    double lambda = 0.;
    for (unsigned int i = 0; i < n; ++i)
      lambda = std::max(lambda, symmetric.eigenvalue(i).real());
    std::cout << "    " << n << " unknowns with penalty mass; lambda_max(K_c, "
              << "M_c) eps_m / C = " << lambda * eps_m / C << std::endl;
    CHECK_TRUE(lambda > 0. && lambda <= C / eps_m);

    // 3. The lumped step with the penalty masses.
    auto          &body = *body_1;
    Vector<double> v0(body.n_dofs());
    for (unsigned int i = 0; i < v0.size(); ++i)
      v0(i) = std::sin(0.37 * i);
    const std::vector<std::pair<types::global_dof_index, double>> list =
      result.penalty_masses[0];
    const auto step = [&](Vector<double> &a) {
      Vector<double> f = f0[0], vh = v0;
      body.compute_acceleration_and_velocities(f, vh, 1e-3);
      a = body.acceleration;
    };
    Vector<double> bulk, with_mass, restored;
    step(bulk);
    Vector<double> stiffness_times_u(body.n_dofs());
    body.stiffness_matrix().vmult(stiffness_times_u, body.displacement);
    for (const bool momentum : {false, true})
      {
        std::cout << "    switching: " << (momentum ? "momentum" : "velocity")
                  << std::endl;
        body.set_penalty_switching(momentum);
        Vector<double> v        = v0;
        const double   switched = body.set_penalty_masses(list, v);
        step(with_mass);
        double expected_energy = 0., max_error = 0., max_a = 0.,
               momentum_error = 0., kinetic = 0.;
        for (const auto &[i, m] : masses)
          if (i.first == 0)
            {
              const unsigned int k = i.second;
              const double       M = body.lumped_masses()(k);
              // velocity: 1/2 m_p v^2 comes in; momentum: v' = M v / (M +
              // m_p), and 1/2 (M + m_p) v'^2 - 1/2 M v^2 comes in.
              const double v_new = momentum ? M * v0(k) / (M + m) : v0(k);
              expected_energy +=
                0.5 * ((M + m) * v_new * v_new - M * v0(k) * v0(k));
              kinetic += 0.5 * m * v_new * v_new;
              momentum_error = std::max(momentum_error, std::abs(v(k) - v_new));
              const double a = (f0[0](k) - stiffness_times_u(k)) / (M + m);
              max_error      = std::max(max_error, std::abs(with_mass(k) - a));
              max_a          = std::max(max_a, std::abs(a));
            }
        CHECK_CLOSE(switched, expected_energy, 1e-13);
        CHECK_CLOSE_ABS(momentum_error, 0., 1e-15);
        CHECK_CLOSE_ABS(max_error / max_a, 0., 1e-14);
        CHECK_CLOSE(body.penalty_kinetic_energy(v, v), kinetic, 1e-13);
        Vector<double> w = v;
        body.set_penalty_masses({}, w);
        step(restored);
        restored -= bulk;
        CHECK_CLOSE_ABS(restored.linfty_norm(), 0., 0.);
      }

    // 4. The scene's stable step with the bipenalty: the bound with the
    // springs, capped by 2 / omega_c = sqrt(f) dt_bulk.
    const double margin    = default_contact_activation_margin;
    double       bulk_step = 1e300;
    for (const auto *b : bodies)
      bulk_step = std::min(bulk_step, compute_stable_time_step(*b, {}).bound());
    contact.set_bipenalty_mass(0.);
    const double plain =
      scene_stable_time_step<2>(bodies, {{&contact, 0, 1}}, margin).bound();
    for (const double factor : {0.01, 0.25, 1., 4.})
      {
        contact.set_bipenalty_mass(factor * margin * C * bulk_step * bulk_step /
                                   4.);
        const double omega_c = std::sqrt(margin * C / contact.bipenalty_mass());
        const StableTimeStep stable =
          scene_stable_time_step<2>(bodies, {{&contact, 0, 1}}, margin);
        std::cout << "    f = " << factor << ": bound " << stable.bound()
                  << " s, with springs alone " << plain << " s, bulk "
                  << bulk_step << " s, 2 / omega_c " << 2. / omega_c << " s"
                  << std::endl;
        CHECK_CLOSE(2. / omega_c / bulk_step, std::sqrt(factor), 1e-12);
        CHECK_CLOSE(stable.bound(), std::min(plain, 2. / omega_c), 1e-12);
      }
  }
} // namespace

int
main()
{
  run(DiscretizationMethod::fea, 1.25);
  run(DiscretizationMethod::iga, 1.);
  return isoimpact_tests::report();
}
