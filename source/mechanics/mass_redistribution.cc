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
        const Tensor<1, dim> center = receiver_moment / receiver_mass;
        FullMatrix<double>   inertia(dim, dim);
        for (const auto i : result.receivers)
          if (discretization.dof_component(i) == c)
            {
              const Tensor<1, dim> d = discretization.dof_position(i) - center;
              for (unsigned int a = 0; a < dim; ++a)
                for (unsigned int b = 0; b < dim; ++b)
                  inertia(a, b) += lumped(i) * d[a] * d[b];
            }
        // sum dm_i = a M_R = m_S; sum dm_i X_i = a M_R Xbar + I b = S_S.
        const double   a   = surface_mass / receiver_mass;
        Tensor<1, dim> rhs = surface_moment - a * receiver_mass * center;
        AssertThrow(inertia.determinant() > 0.,
                    ExcMessage("mass redistribution: the unknowns next to "
                               "the contact surface lie on a line"));
        FullMatrix<double> inverse(dim, dim);
        inverse.invert(inertia);
        Tensor<1, dim> b;
        for (unsigned int p = 0; p < dim; ++p)
          for (unsigned int q = 0; q < dim; ++q)
            b[p] += inverse(p, q) * rhs[q];
        for (const auto i : result.receivers)
          if (discretization.dof_component(i) == c)
            {
              const double factor =
                1. + a + b * (discretization.dof_position(i) - center);
              AssertThrow(factor > 0.,
                          ExcMessage("mass redistribution: the unknown " +
                                     std::to_string(i) +
                                     " would get a non-positive mass "
                                     "(factor " +
                                     std::to_string(factor) +
                                     "); the mesh next to the contact "
                                     "surface is too distorted"));
              result.masses(i) = lumped(i) * factor;
            }
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
