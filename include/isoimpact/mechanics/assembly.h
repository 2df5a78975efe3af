// Layer 4: stiffness and mass matrices and mass lumping, assembled through
// the discretisation interface (identical code for FEA and IGA).
#ifndef isoimpact_assembly_h
#define isoimpact_assembly_h

#include <deal.II/base/index_set.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <isoimpact/discretization/discretization.h>
#include <isoimpact/mechanics/material.h>
#include <isoimpact/nurbs/enum_names.h>

#include <functional>
#include <string>

namespace isoimpact
{
  enum class MassScheme
  {
    consistent,
    row_sum,
    hrz
  };

  // "consistent", "row-sum", "HRZ" (the spelling of the parameter files).
  inline constexpr EnumNames<MassScheme, 3> mass_scheme_names{
    "mass matrix",
    {{{MassScheme::consistent, "consistent"},
      {MassScheme::row_sum, "row-sum"},
      {MassScheme::hrz, "HRZ"}}}};

  inline std::string
  to_string(const MassScheme scheme)
  {
    return mass_scheme_names.to_string(scheme);
  }

  // With a filter: the cells whose active_cell_index() it accepts only (in
  // the same order).
  using CellFilter = std::function<bool(unsigned int active_cell_index)>;

  /**
   * Issue 13: the rows of a matrix that one MPI rank builds, those of the
   * unknowns it owns (`rows`), from the cells that contribute to them
   * (`cells`: those that carry one of them, and with hanging nodes those
   * that carry an unknown constrained to one of them). The other rows hold
   * a zero diagonal entry only. The rows built have the entries of the
   * whole matrix, condensed by deal.II as for the whole matrix: bit for
   * bit.
   */
  struct RowSelection
  {
    dealii::IndexSet rows;
    CellFilter       cells;
  };

  template <int dim>
  void
  make_sparsity_pattern(const Discretization<dim>               &discretization,
                        const dealii::AffineConstraints<double> &constraints,
                        dealii::SparsityPattern &sparsity_pattern,
                        const RowSelection      *selection = nullptr);

  template <int dim>
  void
  assemble_stiffness_matrix(
    const Discretization<dim>               &discretization,
    const ElasticMaterial                   &material,
    const dealii::AffineConstraints<double> &constraints,
    dealii::SparseMatrix<double>            &stiffness_matrix,
    const RowSelection                      *selection = nullptr);

  template <int dim>
  void
  assemble_consistent_mass_matrix(
    const Discretization<dim>               &discretization,
    const double                             density,
    const dealii::AffineConstraints<double> &constraints,
    dealii::SparseMatrix<double>            &mass_matrix);

  /**
   * Lumped (diagonal) mass, row-sum or HRZ, computed per element in the
   * basis of the unknowns and condensed with the constraints. A non-positive
   * element entry throws an error that names the scheme and the element.
   * Constrained unknowns get mass zero.
   */
  template <int dim>
  dealii::Vector<double>
  assemble_lumped_mass(const Discretization<dim>               &discretization,
                       const double                             density,
                       const MassScheme                         scheme,
                       const dealii::AffineConstraints<double> &constraints);

  // Load vector of a body force b(x) [N/m^3] (per unit thickness in 2D),
  // condensed with `constraints`; `rhs` is resized to n_dofs.
  template <int dim>
  void
  assemble_load_vector(
    const Discretization<dim> &discretization,
    const std::function<dealii::Tensor<1, dim>(const dealii::Point<dim> &)>
                                            &body_force,
    const dealii::AffineConstraints<double> &constraints,
    dealii::Vector<double>                  &rhs);

  /**
   * Called for every element with its unknowns, its stiffness matrix and its
   * share of the mass matrix in use: the consistent element matrix, or the
   * diagonal matrix of the element's lumped masses (row-sum or HRZ), whose
   * assembly is the lumped mass. Element-level analyses (the stable time
   * step bound) use it.
   */
  using ElementVisitor =
    std::function<void(const std::vector<dealii::types::global_dof_index> &,
                       const dealii::FullMatrix<double> &stiffness,
                       const dealii::FullMatrix<double> &mass)>;

  template <int dim>
  void
  for_each_element(const Discretization<dim> &discretization,
                   const ElasticMaterial     &material,
                   const MassScheme           scheme,
                   const ElementVisitor      &visit,
                   const CellFilter          &cell_filter = {});

  // Integral of the density over the mesh (exact geometry of the mapping).
  template <int dim>
  double
  integrate_mass(const Discretization<dim> &discretization,
                 const double               density);
} // namespace isoimpact

#endif
