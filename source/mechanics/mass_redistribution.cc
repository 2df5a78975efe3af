// Layer 4: mass redistribution (see mass_redistribution.h).
#include <deal.II/base/exceptions.h>

#include <deal.II/lac/full_matrix.h>

#include <isoimpact/mechanics/mass_redistribution.h>

#include <algorithm>
#include <cmath>
#include <string>

using namespace dealii;

namespace isoimpact
{
  template <int dim>
  MassRedistribution
  redistribute_lumped_mass(const Discretization<dim>       &discretization,
                           const Vector<double>            &lumped,
                           const AffineConstraints<double> &constraints,
                           const std::vector<BoundarySegment<dim>> &surface)
  {
    const types::global_dof_index n = discretization.n_dofs();
    AssertThrow(lumped.size() == n,
                ExcMessage("mass redistribution: the lumped masses do not "
                           "match the unknowns"));
    MassRedistribution result;
    result.masses = lumped;

    std::vector<bool> on_surface(n, false);
    for (const auto &segment : surface)
      for (const auto &node : segment.node_dofs)
        for (const auto dof : node)
          if (!constraints.is_constrained(dof))
            on_surface[dof] = true;
    std::vector<bool>                    receiver(n, false);
    std::vector<types::global_dof_index> indices;
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      {
        discretization.get_dof_indices(cell, indices);
        if (std::none_of(indices.begin(), indices.end(), [&](const auto i) {
              return on_surface[i];
            }))
          continue;
        for (const auto i : indices)
          if (!on_surface[i] && !constraints.is_constrained(i))
            receiver[i] = true;
      }
    for (types::global_dof_index i = 0; i < n; ++i)
      {
        if (on_surface[i])
          result.massless.push_back(i);
        if (receiver[i])
          result.receivers.push_back(i);
      }
    AssertThrow(!result.massless.empty(),
                ExcMessage("mass redistribution: the contact surface has no "
                           "free unknowns"));

    for (unsigned int c = 0; c < dim; ++c)
      {
        // The surface's mass and first moment, the receivers' mass, centre
        // and second moment about it.
        double         surface_mass = 0., receiver_mass = 0.;
        Tensor<1, dim> surface_moment, receiver_moment;
        for (const auto i : result.massless)
          if (discretization.dof_component(i) == c)
            {
              surface_mass += lumped(i);
              surface_moment += lumped(i) * discretization.dof_position(i);
            }
        for (const auto i : result.receivers)
          if (discretization.dof_component(i) == c)
            {
              receiver_mass += lumped(i);
              receiver_moment += lumped(i) * discretization.dof_position(i);
            }
        if (surface_mass == 0.)
          continue;
        AssertThrow(receiver_mass > 0.,
                    ExcMessage("mass redistribution: no interior unknowns "
                               "next to the contact surface"));
        // Exponential tilt: dm_i = m_S w_i / W, w_i = m_i exp(beta . d_i),
        // d_i = (X_i - target) / L, target = S_S / m_S, so that every
        // receiver gains mass; beta minimises log sum_i m_i exp(beta . d_i)
        // (convex; its gradient is the weighted mean of d, zero when the
        // receivers take the first moment S_S). Newton with halving.
        std::vector<types::global_dof_index> own;
        for (const auto i : result.receivers)
          if (discretization.dof_component(i) == c)
            own.push_back(i);
        const Point<dim> target(surface_moment / surface_mass);
        double           length = 0.;
        for (const auto i : own)
          length =
            std::max(length, discretization.dof_position(i).distance(target));
        std::vector<Tensor<1, dim>> d(own.size());
        for (unsigned int k = 0; k < own.size(); ++k)
          d[k] = (discretization.dof_position(own[k]) - target) / length;
        std::vector<double> w(own.size());
        const auto          weigh = [&](const Tensor<1, dim> &beta,
                               Tensor<1, dim>       &mean,
                               FullMatrix<double>   &covariance) {
          double largest = -1e300;
          for (unsigned int k = 0; k < own.size(); ++k)
            largest = std::max(largest, beta * d[k]);
          double sum = 0.;
          mean       = Tensor<1, dim>();
          for (unsigned int k = 0; k < own.size(); ++k)
            {
              w[k] = lumped(own[k]) * std::exp(beta * d[k] - largest);
              sum += w[k];
              mean += w[k] * d[k];
            }
          mean /= sum;
          covariance = 0.;
          for (unsigned int k = 0; k < own.size(); ++k)
            for (unsigned int a = 0; a < dim; ++a)
              for (unsigned int b = 0; b < dim; ++b)
                covariance(a, b) +=
                  w[k] * (d[k][a] - mean[a]) * (d[k][b] - mean[b]) / sum;
          return std::log(sum) + largest;
        };
        Tensor<1, dim>     beta, mean, trial_mean;
        FullMatrix<double> covariance(dim, dim), trial_covariance(dim, dim);
        double             value     = weigh(beta, mean, covariance);
        bool               converged = false;
        for (unsigned int iteration = 0; iteration < 100; ++iteration)
          {
            if (mean.norm() <= 1e-15)
              {
                converged = true;
                break;
              }
            FullMatrix<double> inverse(dim, dim);
            AssertThrow(covariance.determinant() > 0.,
                        ExcMessage("mass redistribution: the unknowns next "
                                   "to the contact surface lie on a line"));
            inverse.invert(covariance);
            Tensor<1, dim> step;
            for (unsigned int a = 0; a < dim; ++a)
              for (unsigned int b = 0; b < dim; ++b)
                step[a] -= inverse(a, b) * mean[b];
            double alpha = 1.;
            for (unsigned int cut = 0; cut < 30; ++cut, alpha *= 0.5)
              {
                const double trial =
                  weigh(beta + alpha * step, trial_mean, trial_covariance);
                if (trial <= value + 1e-4 * alpha * (mean * step) ||
                    trial_mean.norm() < mean.norm())
                  {
                    value = trial;
                    break;
                  }
              }
            beta += alpha * step;
            value = weigh(beta, mean, covariance);
          }
        AssertThrow(converged,
                    ExcMessage("mass redistribution: the centre of mass of "
                               "the contact surface lies outside the unknowns "
                               "next to it; the first moment cannot be kept "
                               "with positive masses"));
        double sum = 0.;
        for (const double wk : w)
          sum += wk;
        for (unsigned int k = 0; k < own.size(); ++k)
          result.masses(own[k]) = lumped(own[k]) + surface_mass * w[k] / sum;
        for (const auto i : result.massless)
          if (discretization.dof_component(i) == c)
            result.masses(i) = 0.;
      }
    return result;
  }

  template MassRedistribution
  redistribute_lumped_mass(const Discretization<2> &,
                           const Vector<double> &,
                           const AffineConstraints<double> &,
                           const std::vector<BoundarySegment<2>> &);
} // namespace isoimpact
