// Layer 5: the quasi-static boundary of mass redistribution (see
// quasi_static_boundary.h).
#include <deal.II/base/exceptions.h>

#include <isoimpact/time_integration/central_difference.h>
#include <isoimpact/time_integration/quasi_static_boundary.h>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <sstream>

using namespace dealii;

namespace isoimpact
{
  template <int dim>
  struct QuasiStaticBoundary<dim>::Data
  {
    Eigen::SparseMatrix<double>                        stiffness_bb;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor;
    std::vector<std::uint64_t> factor_signature, signature;
    bool                       have_factor = false;
    // u_b at the start of the last solve and now; f_c,b of the last
    // evaluation.
    Eigen::VectorXd previous, current, contact_force;
    bool            have_contact_force = false;
    Eigen::VectorXd residual, stiffness_times_u, step, start;
    // Per row: sum_j |K_ij u_j|, the size of the terms that cancel in the
    // residual (its round-off level).
    Eigen::VectorXd magnitude;
  };

  template <int dim>
  QuasiStaticBoundary<dim>::QuasiStaticBoundary(
    const std::vector<ElasticBody<dim> *>      &bodies,
    const std::vector<ContactInteraction<dim>> &contacts,
    const std::vector<Vector<double>>          &forces,
    const std::vector<ContactResult<dim>>      &results,
    const double                                relative_tolerance,
    const unsigned int                          max_iterations)
    : bodies(bodies)
    , contacts(contacts)
    , forces(forces)
    , results(results)
    , tolerance(relative_tolerance)
    , max_iterations(max_iterations)
    , data(std::make_unique<Data>())
  {
    for (unsigned int b = 0; b < bodies.size(); ++b)
      {
        index_of.emplace_back(bodies[b]->n_dofs(), -1);
        for (const auto dof : bodies[b]->massless_dofs())
          {
            index_of[b][dof] = unknowns.size();
            unknowns.emplace_back(b, dof);
          }
      }
    AssertThrow(!unknowns.empty(),
                ExcMessage("quasi-static boundary: no body has massless "
                           "unknowns"));
    // K_bb, from the rows of the condensed stiffness.
    std::vector<Eigen::Triplet<double>> triplets;
    for (unsigned int i = 0; i < unknowns.size(); ++i)
      {
        const auto [b, dof] = unknowns[i];
        const auto &k       = bodies[b]->stiffness_matrix();
        for (auto entry = k.begin(dof); entry != k.end(dof); ++entry)
          if (const int j = index_of[b][entry->column()]; j >= 0)
            triplets.emplace_back(i, j, entry->value());
      }
    const unsigned int n = unknowns.size();
    data->stiffness_bb.resize(n, n);
    data->stiffness_bb.setFromTriplets(triplets.begin(), triplets.end());
    data->previous.setZero(n);
    data->current.setZero(n);
    data->contact_force.setZero(n);
    for (unsigned int i = 0; i < n; ++i)
      data->current[i] =
        bodies[unknowns[i].first]->displacement(unknowns[i].second);
  }

  template <int dim>
  QuasiStaticBoundary<dim>::~QuasiStaticBoundary() = default;

  template <int dim>
  unsigned int
  QuasiStaticBoundary<dim>::n_unknowns() const
  {
    return unknowns.size();
  }

  template <int dim>
  const BoundarySolveWork &
  QuasiStaticBoundary<dim>::work() const
  {
    return statistics;
  }

  template <int dim>
  void
  QuasiStaticBoundary<dim>::gather_contact_forces()
  {
    for (unsigned int i = 0; i < unknowns.size(); ++i)
      data->contact_force[i] = forces[unknowns[i].first](unknowns[i].second);
    data->signature.clear();
    for (const auto &result : results)
      data->signature.insert(data->signature.end(),
                             result.linearization.signature.begin(),
                             result.linearization.signature.end());
    data->have_contact_force = true;
  }

  template <int dim>
  void
  QuasiStaticBoundary<dim>::scatter() const
  {
    for (unsigned int i = 0; i < unknowns.size(); ++i)
      bodies[unknowns[i].first]->displacement(unknowns[i].second) =
        data->current[i];
  }

  template <int dim>
  void
  QuasiStaticBoundary<dim>::factorize()
  {
    // K_bb + sum_t k_t g_t g_t^T over the terms of the last evaluation,
    // restricted to the massless unknowns (the others are fixed here).
    std::vector<Eigen::Triplet<double>> triplets;
    std::vector<std::pair<int, double>> gradient;
    for (unsigned int c = 0; c < results.size(); ++c)
      {
        const auto        &tangent       = results[c].linearization;
        const unsigned int scene_body[2] = {contacts[c].first_body,
                                            contacts[c].second_body};
        for (unsigned int t = 0; t < tangent.n_terms(); ++t)
          {
            gradient.clear();
            for (unsigned int e = tangent.term_begin[t];
                 e < tangent.term_begin[t + 1];
                 ++e)
              {
                const auto &entry = tangent.entries[e];
                if (const int i = index_of[scene_body[entry.body]][entry.dof];
                    i >= 0)
                  gradient.emplace_back(i, entry.value);
              }
            for (const auto &[i, gi] : gradient)
              for (const auto &[j, gj] : gradient)
                triplets.emplace_back(i, j, tangent.stiffness[t] * gi * gj);
          }
      }
    Eigen::SparseMatrix<double> contact(unknowns.size(), unknowns.size());
    contact.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::SparseMatrix<double> tangent = data->stiffness_bb + contact;
    data->factor.compute(tangent);
    AssertThrow(data->factor.info() == Eigen::Success,
                ExcMessage("quasi-static boundary: the factorisation of "
                           "K_bb + K_contact failed (is the body free to "
                           "move on its contact surface?)"));
    data->factor_signature = data->signature;
    data->have_factor      = true;
    ++statistics.factorizations;
  }

  template <int dim>
  void
  QuasiStaticBoundary<dim>::solve(const Evaluate &evaluate,
                                  const bool      record_points)
  {
    Data &d = *data;
    // The solution of the last step: its contact force is still valid (it
    // depends on u_b only), so the first Newton step needs no evaluation.
    d.previous = d.current;
    scatter();
    const auto residual = [&]() {
      // r = f_c,b - (K u)_b, with the rows of the massless unknowns.
      for (unsigned int i = 0; i < unknowns.size(); ++i)
        {
          const auto [b, dof] = unknowns[i];
          const auto &k       = bodies[b]->stiffness_matrix();
          const auto &u       = bodies[b]->displacement;
          double      sum = 0., magnitude = 0.;
          for (auto entry = k.begin(dof); entry != k.end(dof); ++entry)
            {
              const double term = entry->value() * u(entry->column());
              sum += term;
              magnitude += std::abs(term);
            }
          d.stiffness_times_u[i] = sum;
          d.magnitude[i]         = magnitude;
        }
      d.residual = d.contact_force - d.stiffness_times_u;
      return d.residual.norm();
    };
    const auto fresh_evaluation = [&]() {
      evaluate(record_points);
      ++statistics.evaluations;
      gather_contact_forces();
    };
    d.stiffness_times_u.resize(unknowns.size());
    d.magnitude.resize(unknowns.size());

    const std::uint64_t evaluations_before = statistics.evaluations;
    if (!d.have_contact_force)
      fresh_evaluation();
    double       norm      = residual();
    double       scale     = d.contact_force.norm() + d.magnitude.norm();
    bool         evaluated = statistics.evaluations > evaluations_before;
    bool         refresh   = false;
    unsigned int iteration = 0;
    for (;; ++iteration)
      {
        // A point whose projection switches segments or whose gap crosses
        // zero makes r_b non-smooth, and Newton may stall just above the
        // tolerance: after 20 iterations 100 times the tolerance is
        // accepted (counted in the work).
        const bool loose = iteration >= 20 && norm <= 100. * tolerance * scale;
        statistics.loose_solves += loose && !(norm <= tolerance * scale);
        // A stall beyond that: accepted at max_iterations if within 1e4
        // times the tolerance (counted), else the run stops.
        const bool stalled = iteration >= max_iterations && !loose &&
                             norm <= 1e4 * tolerance * scale;
        statistics.stalled_solves += stalled;
        if (norm <= tolerance * scale || loose || stalled)
          {
            if (!evaluated)
              // The forces of the integrator must be those of u_b now.
              fresh_evaluation();
            statistics.max_residual_ratio =
              std::max(statistics.max_residual_ratio,
                       scale > 0. ? norm / scale : 0.);
            break;
          }
        if (iteration >= max_iterations)
          {
            std::ostringstream message;
            message << "quasi-static boundary (mass redistribution): the "
                       "Newton solve for the massless unknowns did not "
                       "converge in "
                    << max_iterations << " iterations (residual " << norm
                    << " N/m against the tolerance " << tolerance * scale
                    << " N/m); try a smaller penalty or time step";
            AssertThrow(false, ExcMessage(message.str()));
          }
        // Modified Newton: a new factor when the active set changed or the
        // last step contracted poorly.
        if (!d.have_factor || refresh || d.signature != d.factor_signature)
          factorize();
        d.step = d.factor.solve(d.residual);
        ++statistics.substitutions;
        d.start            = d.current;
        double       alpha = 1.;
        double       next  = 0.;
        unsigned int cuts  = 0;
        for (;;)
          {
            d.current = d.start + alpha * d.step;
            scatter();
            fresh_evaluation();
            next = residual();
            // A step that does not reduce the residual is halved (the
            // active set may have jumped); at most 8 times.
            if (next < norm || cuts == 8)
              break;
            alpha *= 0.5;
            ++cuts;
            ++statistics.step_cuts;
          }
        evaluated = true;
        refresh   = next > 0.1 * norm;
        norm      = next;
        scale     = d.contact_force.norm() + d.magnitude.norm();
      }
    ++statistics.solves;
    statistics.last_evaluations = statistics.evaluations - evaluations_before;
    statistics.max_evaluations =
      std::max(statistics.max_evaluations, statistics.last_evaluations);
  }

  template <int dim>
  void
  QuasiStaticBoundary<dim>::set_velocities(
    std::vector<Vector<double>> &half_step_velocity,
    const double                 dt) const
  {
    for (unsigned int i = 0; i < unknowns.size(); ++i)
      half_step_velocity[unknowns[i].first](unknowns[i].second) =
        (data->current[i] - data->previous[i]) / dt;
  }

  template class QuasiStaticBoundary<2>;
} // namespace isoimpact
