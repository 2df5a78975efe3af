// Layer 4: stable time step bounds and estimate.
#include <deal.II/base/quadrature_lib.h>

#include <isoimpact/mechanics/stable_time_step.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>

using namespace dealii;

namespace isoimpact
{
  double
  StableTimeStep::bound() const
  {
    return std::max(element_bound, gershgorin_bound);
  }

  StableTimeStep
  StableTimeStep::min(const StableTimeStep &other) const
  {
    return {std::min(element_bound, other.element_bound),
            std::min(gershgorin_bound, other.gershgorin_bound),
            std::min(power_estimate, other.power_estimate)};
  }

  namespace
  {
    double
    time_step_from_eigenvalue(const double lambda)
    {
      return lambda > 0. ? 2. / std::sqrt(lambda) :
                           std::numeric_limits<double>::infinity();
    }

    // The spring matrix of one segment, k int R_i R_j (e_a . e_b) ds over
    // the reference surface, with e_a . e_b = n_a n_b (`normal_only`: the
    // linearised penalty) or delta_ab (its upper bound). Rows and columns
    // are the segment's unknowns, node by node and component by component.
    template <int dim>
    FullMatrix<double>
    segment_spring_matrix(const BoundarySegment<dim> &segment,
                          const double                stiffness,
                          const bool                  normal_only)
    {
      const unsigned int  n_nodes = segment.node_positions.size();
      FullMatrix<double>  matrix(n_nodes * dim, n_nodes * dim);
      const QGauss<1>     quadrature(segment.degree + 2);
      std::vector<double> values, derivatives;
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        {
          evaluate_segment_basis(segment,
                                 quadrature.point(q)[0],
                                 values,
                                 derivatives);
          Tensor<1, dim> tangent;
          for (unsigned int k = 0; k < n_nodes; ++k)
            tangent += derivatives[k] * segment.node_positions[k];
          const double   ds = tangent.norm() * quadrature.weight(q);
          Tensor<1, dim> normal;
          normal[0] = tangent[1] / tangent.norm();
          normal[1] = -tangent[0] / tangent.norm();
          for (unsigned int i = 0; i < n_nodes; ++i)
            for (unsigned int j = 0; j < n_nodes; ++j)
              for (unsigned int a = 0; a < dim; ++a)
                for (unsigned int b = 0; b < dim; ++b)
                  matrix(i * dim + a, j * dim + b) +=
                    stiffness * values[i] * values[j] * ds *
                    (normal_only ? normal[a] * normal[b] : double(a == b));
        }
      return matrix;
    }

    template <int dim>
    std::vector<types::global_dof_index>
    segment_dofs(const BoundarySegment<dim> &segment)
    {
      std::vector<types::global_dof_index> dofs;
      for (const auto &node : segment.node_dofs)
        dofs.insert(dofs.end(), node.begin(), node.end());
      return dofs;
    }

    // lambda_max(K, M) of a small symmetric pencil, M positive definite.
    double
    largest_eigenvalue(const FullMatrix<double>        &stiffness,
                       const FullMatrix<double>        &mass,
                       const std::vector<unsigned int> &rows)
    {
      const unsigned int n = rows.size();
      Eigen::MatrixXd    k(n, n), m(n, n);
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < n; ++j)
          {
            k(i, j) = stiffness(rows[i], rows[j]);
            m(i, j) = mass(rows[i], rows[j]);
          }
      const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>
        solver(k, m, Eigen::EigenvaluesOnly);
      AssertThrow(solver.info() == Eigen::Success,
                  ExcMessage("element eigenvalue problem failed"));
      return solver.eigenvalues().maxCoeff();
    }

    // The springs' matrices C^T K_s C (C the constraints: rows and columns
    // of the unconstrained unknowns only) on the surface's rows alone, as
    // deal.II's SparseMatrix would hold them (each row's diagonal first,
    // then its other columns ascending; each entry summed over the
    // segments in their order), but without storing the empty rows of the
    // other unknowns: `linearised` the linearised penalty, `bound` its
    // upper bound.
    struct SurfaceSpringRows
    {
      struct Entry
      {
        types::global_dof_index column;
        double                  linearised, bound;
      };
      std::map<types::global_dof_index, std::vector<Entry>> rows;

      // Adds a segment's two matrices on its unknowns `dofs`.
      void
      add(const std::vector<types::global_dof_index> &dofs,
          const FullMatrix<double>                   &linearised,
          const FullMatrix<double>                   &bound,
          const AffineConstraints<double>            &constraints)
      {
        // Each unknown as a combination of unconstrained ones.
        std::vector<std::vector<std::pair<types::global_dof_index, double>>>
          targets(dofs.size());
        for (unsigned int a = 0; a < dofs.size(); ++a)
          if (!constraints.is_constrained(dofs[a]))
            targets[a] = {{dofs[a], 1.}};
          else
            targets[a] = *constraints.get_constraint_entries(dofs[a]);
        for (unsigned int a = 0; a < dofs.size(); ++a)
          for (const auto &[row, row_weight] : targets[a])
            for (unsigned int b = 0; b < dofs.size(); ++b)
              for (const auto &[column, column_weight] : targets[b])
                {
                  Entry       &entry  = find_or_insert(row, column);
                  const double weight = row_weight * column_weight;
                  entry.linearised += weight * linearised(a, b);
                  entry.bound += weight * bound(a, b);
                }
      }

      // The row of `row`, nullptr if it has no springs.
      const std::vector<Entry> *
      row(const types::global_dof_index row) const
      {
        const auto found = rows.find(row);
        return found == rows.end() ? nullptr : &found->second;
      }

      // y += K_s x (the linearised penalty), each row's products added to
      // y in the row's order, as SparseMatrix::vmult_add adds them.
      void
      vmult_add(Vector<double> &y, const Vector<double> &x) const
      {
        for (const auto &[row, entries] : rows)
          {
            double sum = y(row);
            for (const Entry &entry : entries)
              sum += entry.linearised * x(entry.column);
            y(row) = sum;
          }
      }

      // The bound's entry (row, column) of a row's entries; 0 if absent.
      static double
      bound(const std::vector<Entry>     &entries,
            const types::global_dof_index row,
            const types::global_dof_index column)
      {
        if (column == row)
          return entries.front().bound;
        const auto position = std::lower_bound(entries.begin() + 1,
                                               entries.end(),
                                               column,
                                               by_column);
        return position != entries.end() && position->column == column ?
                 position->bound :
                 0.;
      }

    private:
      static bool
      by_column(const Entry &entry, const types::global_dof_index column)
      {
        return entry.column < column;
      }

      Entry &
      find_or_insert(const types::global_dof_index row,
                     const types::global_dof_index column)
      {
        auto &entries = rows[row];
        if (entries.empty())
          entries.push_back({row, 0., 0.});
        if (column == row)
          return entries.front();
        const auto position = std::lower_bound(entries.begin() + 1,
                                               entries.end(),
                                               column,
                                               by_column);
        if (position != entries.end() && position->column == column)
          return *position;
        return *entries.insert(position, {column, 0., 0.});
      }
    };
  } // namespace

  template <int dim>
  StableTimeStep
  compute_stable_time_step(const ElasticBody<dim>                &body,
                           const std::vector<SurfaceSpring<dim>> &springs,
                           const unsigned int n_power_iterations)
  {
    const auto &constraints = body.constraints();
    const bool  lumped      = body.mass_scheme() != MassScheme::consistent;

    // The springs, once as the linearised penalty (for the estimate) and
    // once as its upper bound (for the bounds), per segment.
    struct SegmentSpring
    {
      std::vector<types::global_dof_index> dofs;
      FullMatrix<double>                   bound;
    };
    std::vector<SegmentSpring> segment_springs;
    // Their assembled rows, the surface's alone: a matrix of K's size would
    // hold a row start, a diagonal entry and its value for every unknown.
    SurfaceSpringRows spring_rows;
    for (const auto &spring : springs)
      for (const auto &segment : *spring.segments)
        {
          const auto dofs = segment_dofs(segment);
          segment_springs.push_back(
            {dofs, segment_spring_matrix(segment, spring.stiffness, false)});
          spring_rows.add(dofs,
                          segment_spring_matrix(segment,
                                                spring.stiffness,
                                                true),
                          segment_springs.back().bound,
                          constraints);
        }

    StableTimeStep result;
    result.power_estimate =
      body.estimate_critical_time_step(n_power_iterations,
                                       [&spring_rows](Vector<double>       &y,
                                                      const Vector<double> &x) {
                                         spring_rows.vmult_add(y, x);
                                       });

    // Element by element: every segment joins the first element that holds
    // all its unknowns. Unknowns fixed to zero are left out (a subspace);
    // with hanging nodes a condensed lumped mass is not the sum of the
    // element masses, and the bound does not apply.
    std::multimap<types::global_dof_index, unsigned int> segments_by_dof;
    for (unsigned int s = 0; s < segment_springs.size(); ++s)
      segments_by_dof.emplace(*std::min_element(segment_springs[s].dofs.begin(),
                                                segment_springs[s].dofs.end()),
                              s);
    std::vector<bool> segment_used(segment_springs.size(), false);
    const bool        redistributed = !body.massless_dofs().empty();
    const auto       &before = body.lumped_masses_before_redistribution();
    const auto       &now    = body.lumped_masses();
    bool              element_bound_applies = true;
    double            element_lambda        = 0.;
    for_each_element<dim>(
      body.discretization(),
      body.material(),
      body.mass_scheme(),
      [&](const std::vector<types::global_dof_index> &indices,
          const FullMatrix<double>                   &element_stiffness,
          const FullMatrix<double>                   &element_mass) {
        FullMatrix<double>        stiffness = element_stiffness;
        std::vector<unsigned int> free_rows;
        // Mass redistribution: the element's share of the new masses is
        // D M_e D, D = sqrt(m_new / m_old) per unknown (the shares still
        // add up to the lumped mass), and the massless unknowns are left
        // out: K_ii = sum_e of the elements' interior blocks bounds the
        // interior's stiffness whatever the contact (formulation.md).
        FullMatrix<double> mass = element_mass;
        if (redistributed)
          for (unsigned int i = 0; i < indices.size(); ++i)
            {
              const double old_mass = before(indices[i]);
              const double scale =
                old_mass > 0. ? std::sqrt(now(indices[i]) / old_mass) : 1.;
              for (unsigned int j = 0; j < indices.size(); ++j)
                {
                  mass(i, j) *= scale;
                  mass(j, i) *= scale;
                }
            }
        for (unsigned int i = 0; i < indices.size(); ++i)
          {
            if (!constraints.is_constrained(indices[i]))
              {
                if (!(redistributed && now(indices[i]) == 0.))
                  free_rows.push_back(i);
              }
            else if (!constraints.get_constraint_entries(indices[i])->empty())
              element_bound_applies &= !lumped;
            const auto range = segments_by_dof.equal_range(indices[i]);
            for (auto it = range.first; it != range.second; ++it)
              {
                const auto               &spring = segment_springs[it->second];
                std::vector<unsigned int> local(spring.dofs.size());
                bool                      inside = !segment_used[it->second];
                for (unsigned int d = 0; inside && d < local.size(); ++d)
                  {
                    const auto found =
                      std::find(indices.begin(), indices.end(), spring.dofs[d]);
                    inside   = found != indices.end();
                    local[d] = found - indices.begin();
                  }
                if (!inside)
                  continue;
                segment_used[it->second] = true;
                for (unsigned int a = 0; a < local.size(); ++a)
                  for (unsigned int b = 0; b < local.size(); ++b)
                    stiffness(local[a], local[b]) += spring.bound(a, b);
              }
          }
        if (!free_rows.empty())
          element_lambda =
            std::max(element_lambda,
                     largest_eigenvalue(stiffness, mass, free_rows));
      },
      body.assembly_cells());
    // Several ranks: each visited its own cells (together every cell).
    const auto &exchange  = body.exchange();
    element_lambda        = exchange.max(element_lambda);
    element_bound_applies = exchange.max(element_bound_applies ? 0. : 1.) == 0.;
    {
      std::vector<double> used(segment_used.begin(), segment_used.end());
      exchange.sum(used);
      AssertThrow(std::find(used.begin(), used.end(), 0.) == used.end(),
                  ExcMessage("a contact segment of " + body.name() +
                             " lies in no element: stable step bound failed"));
    }
    if (element_bound_applies)
      result.element_bound = time_step_from_eigenvalue(element_lambda);

    // Gershgorin on M^{-1} (K + K_c) for a diagonal mass.
    if (lumped)
      {
        const auto &stiffness = body.stiffness_matrix();
        // (Released after set-up with load balancing of whole bodies: then
        // the pairs, whose rows have the matrix's entries in its order and
        // zeros, which add nothing.)
        const auto &pairs     = body.paired_stiffness_rows();
        const bool  use_pairs = stiffness.empty() && !pairs.empty();
        const auto &mass      = body.lumped_masses();
        double      lambda    = 0.;
        // (No stiffness on a rank that owns no row of the body.)
        const types::global_dof_index n_rows =
          use_pairs ? 2 * pairs.n_pairs() :
                      (stiffness.empty() ? 0 : stiffness.m());
        for (types::global_dof_index i = 0; i < n_rows; ++i)
          {
            // Massless unknowns (mass redistribution) are not part of the
            // explicit system: M_I^{-1} K_II bounds it (see below).
            if (constraints.is_constrained(i) || mass(i) == 0.)
              continue;
            // Several ranks: each has the rows of its own unknowns.
            if (!body.exchange().is_owned(i))
              continue;
            // The springs' couplings lie inside K's pattern (segments lie
            // in cells); only the surface's rows have them.
            double     row_sum = 0.;
            const auto springs = spring_rows.row(i);
            const auto add     = [&](const types::global_dof_index column,
                                 const double                  value) {
              row_sum += std::abs(
                value +
                (springs ? SurfaceSpringRows::bound(*springs, i, column) : 0.));
            };
            if (use_pairs)
              pairs.for_each_entry(i, add);
            else
              for (auto entry = stiffness.begin(i); entry != stiffness.end(i);
                   ++entry)
                add(entry->column(), entry->value());
            lambda = std::max(lambda, row_sum / mass(i));
          }
        result.gershgorin_bound =
          time_step_from_eigenvalue(body.exchange().max(lambda));
      }
    return result;
  }

  template StableTimeStep
  compute_stable_time_step(const ElasticBody<2> &,
                           const std::vector<SurfaceSpring<2>> &,
                           const unsigned int);
} // namespace isoimpact
