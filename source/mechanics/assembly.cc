// Layer 4: assembly of stiffness and mass through the discretisation
// interface.
#include <deal.II/base/exceptions.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/affine_constraints.templates.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <isoimpact/mechanics/assembly.h>

#include <algorithm>
#include <optional>
#include <sstream>
#include <tuple>
#include <vector>

using namespace dealii;

namespace isoimpact
{
  template <int dim>
  void
  make_sparsity_pattern(const Discretization<dim>       &discretization,
                        const AffineConstraints<double> &constraints,
                        SparsityPattern                 &sparsity_pattern,
                        const RowSelection              *selection)
  {
    const types::global_dof_index n = discretization.n_dofs();
    // With a selection, the dynamic pattern stores the selected rows alone
    // (and drops entries of other rows).
    DynamicSparsityPattern dsp(n, n, selection ? selection->rows : IndexSet());
    std::vector<types::global_dof_index> indices;
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      {
        if (selection && !selection->cells(cell->active_cell_index()))
          continue;
        discretization.get_dof_indices(cell, indices);
        constraints.add_entries_local_to_global(indices, dsp, false);
      }
    sparsity_pattern.copy_from(dsp);
  }

  namespace
  {
    // The rows of a SparseMatrix that a RowSelection selects, as a matrix
    // that AffineConstraints::distribute_local_to_global() writes to: it
    // condenses as for the whole matrix (the same entries, added in the same
    // order: the same bits) and hands each row over; the rows not selected
    // are dropped (the pattern lacks them).
    class SelectedRows
    {
    public:
      using value_type = double;
      using size_type  = types::global_dof_index;

      SelectedRows(SparseMatrix<double> &matrix, const RowSelection &selection)
        : matrix(matrix)
        , selection(selection)
      {}
      // Polymorphic: deal.II tries a dynamic_cast to SparseMatrix.
      virtual ~SelectedRows() = default;
      size_type
      m() const
      {
        return matrix.m();
      }
      size_type
      n() const
      {
        return matrix.n();
      }
      void
      add(const size_type row, const size_type column, const double value)
      {
        if (selection.rows.is_element(row))
          matrix.add(row, column, value);
      }
      void
      add(const size_type  row,
          const size_type  n_columns,
          const size_type *columns,
          const double    *values,
          const bool       elide_zero_values,
          const bool       columns_are_sorted)
      {
        if (selection.rows.is_element(row))
          matrix.add(row,
                     n_columns,
                     columns,
                     values,
                     elide_zero_values,
                     columns_are_sorted);
      }

    private:
      SparseMatrix<double> &matrix;
      const RowSelection   &selection;
    };

    // Loops over cells with FEValues and hands the local matrix of `local`
    // to the constraints for condensation into the global matrix; with a
    // selection, into its rows from the cells it accepts.
    template <int dim, typename LocalAssembler>
    void
    assemble_matrix(const Discretization<dim>       &discretization,
                    const UpdateFlags                flags,
                    const AffineConstraints<double> &constraints,
                    SparseMatrix<double>            &matrix,
                    const LocalAssembler            &local,
                    const RowSelection              *selection = nullptr)
    {
      const auto                          &fe = discretization.fe();
      FEValues<dim>                        fe_values(discretization.mapping(),
                              fe,
                              discretization.cell_quadrature(),
                              flags | update_JxW_values);
      FullMatrix<double>                   cell_matrix(fe.n_dofs_per_cell(),
                                     fe.n_dofs_per_cell());
      std::vector<types::global_dof_index> indices;
      matrix = 0.;
      std::optional<SelectedRows> selected_rows;
      if (selection)
        selected_rows.emplace(matrix, *selection);
      for (const auto &cell :
           discretization.dof_handler().active_cell_iterators())
        {
          if (selection && !selection->cells(cell->active_cell_index()))
            continue;
          fe_values.reinit(cell);
          cell_matrix = 0.;
          local(fe_values, cell_matrix);
          discretization.get_dof_indices(cell, indices);
          if (selected_rows)
            constraints.distribute_local_to_global(cell_matrix,
                                                   indices,
                                                   *selected_rows);
          else
            constraints.distribute_local_to_global(cell_matrix,
                                                   indices,
                                                   matrix);
        }
    }

    // The shape functions of FESystem(scalar element, dim): shape function i
    // is base function base_index[i] times the unit vector of component[i];
    // representative[a] is the first shape function of base function a.
    struct BaseFunctions
    {
      std::vector<unsigned int> component, base_index, representative;
      unsigned int              n_base = 0;

      template <int dim>
      explicit BaseFunctions(const FiniteElement<dim> &fe)
        : component(fe.n_dofs_per_cell())
        , base_index(fe.n_dofs_per_cell())
      {
        Assert(fe.n_base_elements() == 1, ExcNotImplemented());
        const unsigned int n = fe.n_dofs_per_cell();
        for (unsigned int i = 0; i < n; ++i)
          {
            std::tie(component[i], base_index[i]) =
              fe.system_to_component_index(i);
            n_base = std::max(n_base, base_index[i] + 1);
          }
        representative.assign(n_base, n);
        for (unsigned int i = 0; i < n; ++i)
          if (representative[base_index[i]] == n)
            representative[base_index[i]] = i;
      }
    };

    template <int dim>
    void
    local_mass_matrix(const FEValues<dim> &fe_values,
                      const double         density,
                      FullMatrix<double>  &cell_matrix)
    {
      // The mass couples no two components and is the same for each: it is
      // integrated once over the base element's functions (each product as
      // rho phi_i JxW phi_j, summed over the points in their order, as it
      // would be per entry) and copied to every component's block.
      const BaseFunctions base(fe_values.get_fe());
      const unsigned int  n = base.component.size(), n_base = base.n_base;
      const auto &component = base.component, &base_index = base.base_index,
                 &representative = base.representative;
      std::vector<double> value(n_base), scalar_mass(n_base * n_base, 0.);
      for (const unsigned int q : fe_values.quadrature_point_indices())
        {
          for (unsigned int a = 0; a < n_base; ++a)
            value[a] =
              fe_values.shape_value_component(representative[a],
                                              q,
                                              component[representative[a]]);
          for (unsigned int a = 0; a < n_base; ++a)
            {
              const double rho_phi_a = density * value[a] * fe_values.JxW(q);
              for (unsigned int b = 0; b < n_base; ++b)
                scalar_mass[a * n_base + b] += rho_phi_a * value[b];
            }
        }
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < n; ++j)
          if (component[j] == component[i])
            cell_matrix(i, j) +=
              scalar_mass[base_index[i] * n_base + base_index[j]];
    }
    template <int dim>
    void
    local_stiffness_matrix(const FEValues<dim>   &fe_values,
                           const ElasticMaterial &material,
                           FullMatrix<double>    &cell_matrix)
    {
      // Each shape function phi_i = N_a e_c has one component c: its strain
      // is sym(e_c (x) grad N_a), and for the isotropic material
      // (ElasticMaterial::stress) sigma(eps_i) : eps_j
      //   = lambda dN_a/dx_c dN_b/dx_d
      //     + mu (delta_cd grad N_a . grad N_b + dN_a/dx_d dN_b/dx_c)
      // for phi_j = N_b e_d. The integrals are taken once per pair of base
      // functions and pair of components (not per pair of shape functions
      // through their strain tensors): as sums over the points of products
      // of the base functions' gradients.
      const BaseFunctions base(fe_values.get_fe());
      const unsigned int  n = base.component.size(), n_base = base.n_base;
      const auto &component = base.component, &base_index = base.base_index,
                 &representative = base.representative;
      const unsigned int n_q     = fe_values.n_quadrature_points;
      // gradient[(c * n_base + a) * n_q + q] = dN_a/dx_c at point q, and
      // the same times JxW.
      std::vector<double> gradient(dim * n_base * n_q),
        weighted(dim * n_base * n_q);
      for (const unsigned int q : fe_values.quadrature_point_indices())
        for (unsigned int a = 0; a < n_base; ++a)
          {
            const Tensor<1, dim> g =
              fe_values.shape_grad_component(representative[a],
                                             q,
                                             component[representative[a]]);
            for (unsigned int c = 0; c < dim; ++c)
              {
                gradient[(c * n_base + a) * n_q + q] = g[c];
                weighted[(c * n_base + a) * n_q + q] = g[c] * fe_values.JxW(q);
              }
          }
      // product[(c * dim + d) * n_base^2 + a * n_base + b]
      //   = sum_q JxW dN_a/dx_c dN_b/dx_d
      std::vector<double> product(dim * dim * n_base * n_base);
      for (unsigned int c = 0; c < dim; ++c)
        for (unsigned int d = 0; d < dim; ++d)
          for (unsigned int a = 0; a < n_base; ++a)
            {
              const double *wa = &weighted[(c * n_base + a) * n_q];
              for (unsigned int b = 0; b < n_base; ++b)
                {
                  const double *gb  = &gradient[(d * n_base + b) * n_q];
                  double        sum = 0.;
                  for (unsigned int q = 0; q < n_q; ++q)
                    sum += wa[q] * gb[q];
                  product[(c * dim + d) * n_base * n_base + a * n_base + b] =
                    sum;
                }
            }
      const double lambda = material.lame_lambda();
      const double mu     = material.lame_mu();
      const auto   P      = [&](const unsigned int c,
                         const unsigned int d,
                         const unsigned int a,
                         const unsigned int b) {
        return product[(c * dim + d) * n_base * n_base + a * n_base + b];
      };
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < n; ++j)
          {
            const unsigned int c = component[i], d = component[j];
            const unsigned int a = base_index[i], b = base_index[j];
            double entry = lambda * P(c, d, a, b) + mu * P(d, c, a, b);
            if (c == d)
              for (unsigned int e = 0; e < dim; ++e)
                entry += mu * P(e, e, a, b);
            cell_matrix(i, j) += entry;
          }
    }

    // The element's lumped masses (row-sum or HRZ) from its consistent mass
    // matrix; returns the element mass. A non-positive entry is an error.
    template <int dim>
    double
    local_lumped_mass(const FEValues<dim>      &fe_values,
                      const double              density,
                      const MassScheme          scheme,
                      const FullMatrix<double> &cell_matrix,
                      const std::string        &where,
                      Vector<double>           &cell_mass)
    {
      const auto        &fe = fe_values.get_fe();
      const unsigned int n  = fe.n_dofs_per_cell();
      // Mass of the element (each displacement component carries it).
      double element_mass = 0.;
      for (const unsigned int q : fe_values.quadrature_point_indices())
        element_mass += density * fe_values.JxW(q);

      for (unsigned int i = 0; i < n; ++i)
        {
          cell_mass(i) = 0.;
          if (scheme == MassScheme::row_sum)
            for (unsigned int j = 0; j < n; ++j)
              cell_mass(i) += cell_matrix(i, j);
          else
            cell_mass(i) = cell_matrix(i, i);
        }
      if (scheme == MassScheme::hrz)
        for (unsigned int c = 0; c < fe.n_components(); ++c)
          {
            double diagonal_sum = 0.;
            for (unsigned int i = 0; i < n; ++i)
              if (fe.system_to_component_index(i).first == c)
                diagonal_sum += cell_mass(i);
            for (unsigned int i = 0; i < n; ++i)
              if (fe.system_to_component_index(i).first == c)
                cell_mass(i) *= element_mass / diagonal_sum;
          }

      for (unsigned int i = 0; i < n; ++i)
        if (!(cell_mass(i) > 0.))
          {
            std::ostringstream message;
            message << to_string(scheme)
                    << " mass lumping gives the non-positive mass "
                    << cell_mass(i) << " kg/m (" << cell_mass(i) / element_mass
                    << " of the element mass) to local function " << i
                    << " of element " << where
                    << ": a lumped mass must be positive for explicit "
                       "dynamics; choose another mass matrix (HRZ or "
                       "consistent)";
            AssertThrow(false, ExcMessage(message.str()));
          }
      return element_mass;
    }
  } // namespace

  template <int dim>
  void
  assemble_stiffness_matrix(const Discretization<dim>       &discretization,
                            const ElasticMaterial           &material,
                            const AffineConstraints<double> &constraints,
                            SparseMatrix<double>            &stiffness_matrix,
                            const RowSelection              *selection)
  {
    assemble_matrix<dim>(
      discretization,
      update_gradients,
      constraints,
      stiffness_matrix,
      [&](const FEValues<dim> &fe_values, FullMatrix<double> &cell_matrix) {
        local_stiffness_matrix(fe_values, material, cell_matrix);
      },
      selection);
  }

  template <int dim>
  void
  assemble_consistent_mass_matrix(const Discretization<dim> &discretization,
                                  const double               density,
                                  const AffineConstraints<double> &constraints,
                                  SparseMatrix<double>            &mass_matrix)
  {
    assemble_matrix<dim>(discretization,
                         update_values,
                         constraints,
                         mass_matrix,
                         [&](const FEValues<dim> &fe_values,
                             FullMatrix<double>  &cell_matrix) {
                           local_mass_matrix(fe_values, density, cell_matrix);
                         });
  }

  template <int dim>
  Vector<double>
  assemble_lumped_mass(const Discretization<dim>       &discretization,
                       const double                     density,
                       const MassScheme                 scheme,
                       const AffineConstraints<double> &constraints)
  {
    AssertThrow(scheme != MassScheme::consistent,
                ExcMessage("assemble_lumped_mass needs row-sum or HRZ"));
    const auto                          &fe = discretization.fe();
    FEValues<dim>                        fe_values(discretization.mapping(),
                            fe,
                            discretization.cell_quadrature(),
                            update_values | update_JxW_values);
    const unsigned int                   n = fe.n_dofs_per_cell();
    FullMatrix<double>                   cell_matrix(n, n);
    Vector<double>                       cell_mass(n);
    Vector<double>                       lumped(discretization.n_dofs());
    std::vector<types::global_dof_index> indices;
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      {
        fe_values.reinit(cell);
        cell_matrix = 0.;
        local_mass_matrix(fe_values, density, cell_matrix);

        std::ostringstream where;
        where << cell->id() << " of the discretisation "
              << discretization.name();
        local_lumped_mass(fe_values,
                          density,
                          scheme,
                          cell_matrix,
                          where.str(),
                          cell_mass);

        discretization.get_dof_indices(cell, indices);
        constraints.distribute_local_to_global(cell_mass, indices, lumped);
      }

    for (types::global_dof_index i = 0; i < lumped.size(); ++i)
      if (constraints.is_constrained(i))
        lumped(i) = 0.;
      else
        AssertThrow(lumped(i) > 0.,
                    ExcMessage(to_string(scheme) +
                               " mass lumping gives the non-positive mass " +
                               std::to_string(lumped(i)) + " to unknown " +
                               std::to_string(i) +
                               " after condensation of the constraints"));
    return lumped;
  }

  template <int dim>
  double
  integrate_mass(const Discretization<dim> &discretization,
                 const double               density)
  {
    FEValues<dim> fe_values(discretization.mapping(),
                            discretization.fe(),
                            discretization.cell_quadrature(),
                            update_JxW_values);
    double        mass = 0.;
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      {
        fe_values.reinit(cell);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          mass += density * fe_values.JxW(q);
      }
    return mass;
  }

  template <int dim>
  void
  assemble_load_vector(
    const Discretization<dim>                               &discretization,
    const std::function<Tensor<1, dim>(const Point<dim> &)> &body_force,
    const AffineConstraints<double>                         &constraints,
    Vector<double>                                          &rhs)
  {
    const auto                          &fe = discretization.fe();
    FEValues<dim>                        fe_values(discretization.mapping(),
                            fe,
                            discretization.cell_quadrature(),
                            update_values | update_quadrature_points |
                              update_JxW_values);
    Vector<double>                       cell_rhs(fe.n_dofs_per_cell());
    std::vector<types::global_dof_index> indices;
    rhs.reinit(discretization.n_dofs());
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      {
        fe_values.reinit(cell);
        cell_rhs = 0.;
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            const Tensor<1, dim> b = body_force(fe_values.quadrature_point(q));
            for (const unsigned int i : fe_values.dof_indices())
              {
                const unsigned int c = fe.system_to_component_index(i).first;
                cell_rhs(i) += b[c] * fe_values.shape_value_component(i, q, c) *
                               fe_values.JxW(q);
              }
          }
        discretization.get_dof_indices(cell, indices);
        constraints.distribute_local_to_global(cell_rhs, indices, rhs);
      }
  }

  template <int dim>
  void
  for_each_element(const Discretization<dim> &discretization,
                   const ElasticMaterial     &material,
                   const MassScheme           scheme,
                   const ElementVisitor      &visit,
                   const CellFilter          &cell_filter)
  {
    const auto                          &fe = discretization.fe();
    FEValues<dim>                        fe_values(discretization.mapping(),
                            fe,
                            discretization.cell_quadrature(),
                            update_values | update_gradients |
                              update_JxW_values);
    const unsigned int                   n = fe.n_dofs_per_cell();
    FullMatrix<double>                   stiffness(n, n), mass(n, n);
    Vector<double>                       cell_mass(n);
    std::vector<types::global_dof_index> indices;
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      {
        if (cell_filter && !cell_filter(cell->active_cell_index()))
          continue;
        fe_values.reinit(cell);
        stiffness = 0.;
        mass      = 0.;
        local_stiffness_matrix(fe_values, material, stiffness);
        local_mass_matrix(fe_values, material.density, mass);
        if (scheme != MassScheme::consistent)
          {
            std::ostringstream where;
            where << cell->id();
            local_lumped_mass(fe_values,
                              material.density,
                              scheme,
                              mass,
                              where.str(),
                              cell_mass);
            mass = 0.;
            for (unsigned int i = 0; i < n; ++i)
              mass(i, i) = cell_mass(i);
          }
        discretization.get_dof_indices(cell, indices);
        visit(indices, stiffness, mass);
      }
  }

  template void
  make_sparsity_pattern(const Discretization<2> &,
                        const AffineConstraints<double> &,
                        SparsityPattern &,
                        const RowSelection *);
  template void
  assemble_stiffness_matrix(const Discretization<2> &,
                            const ElasticMaterial &,
                            const AffineConstraints<double> &,
                            SparseMatrix<double> &,
                            const RowSelection *);
  template void
  assemble_consistent_mass_matrix(const Discretization<2> &,
                                  const double,
                                  const AffineConstraints<double> &,
                                  SparseMatrix<double> &);
  template Vector<double>
  assemble_lumped_mass(const Discretization<2> &,
                       const double,
                       const MassScheme,
                       const AffineConstraints<double> &);
  template void
  assemble_load_vector(const Discretization<2> &,
                       const std::function<Tensor<1, 2>(const Point<2> &)> &,
                       const AffineConstraints<double> &,
                       Vector<double> &);
  template double
  integrate_mass(const Discretization<2> &, const double);
  template void
  for_each_element(const Discretization<2> &,
                   const ElasticMaterial &,
                   const MassScheme,
                   const ElementVisitor &,
                   const CellFilter &);
} // namespace isoimpact
