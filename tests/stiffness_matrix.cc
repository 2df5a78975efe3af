// The assembled stiffness (assemble_stiffness_matrix, which integrates
// products of the base functions' gradients) against the textbook form
// K_ij = sum_q sigma(eps(phi_i)) : eps(phi_j) JxW, evaluated here with
// FEValues' symmetric gradients and the stress of E and nu
// (reference_stress, independent of ElasticMaterial), entry by entry:
// FEA Q9 and Q8 and IGA p2 and p3 on the benchmark's half disk, plane
// strain and plane stress, nu = 0.2 and 0.49 (nearly incompressible, where
// lambda dominates). Tolerance 1e-12 of the largest entry: the two differ
// by round-off (measured below 1e-14). Control: swapping lambda and mu in
// the reference moves the largest difference to O(1) of it.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <isoimpact/discretization/discretization.h>
#include <isoimpact/mechanics/assembly.h>

#include "test_helpers.h"

using namespace dealii;
using namespace isoimpact;
using namespace isoimpact_tests;

namespace
{
  // Largest |K_ij - K_ref_ij| over the entries, and the largest |K_ref_ij|.
  // `swap`: the reference with lambda and mu exchanged (the control).
  std::pair<double, double>
  largest_difference(const Discretization<2> &discretization,
                     const ElasticMaterial   &material,
                     const bool               swap)
  {
    AffineConstraints<double> none;
    none.close();
    SparsityPattern pattern;
    make_sparsity_pattern(discretization, none, pattern);
    SparseMatrix<double> stiffness(pattern), reference(pattern);
    assemble_stiffness_matrix(discretization, material, none, stiffness);

    double E = material.youngs_modulus, nu = material.poisson_ratio;
    if (swap)
      {
        // lambda' = mu, mu' = lambda of the plane-strain material.
        const double lambda = material.lame_lambda(), mu = material.lame_mu();
        nu = mu / (2. * (mu + lambda));
        E  = 2. * lambda * (1. + nu);
      }
    const FEValuesExtractors::Vector displacement(0);
    FEValues<2>                      fe_values(discretization.mapping(),
                          discretization.fe(),
                          discretization.cell_quadrature(),
                          update_gradients | update_JxW_values);
    const unsigned int               n = discretization.fe().n_dofs_per_cell();
    FullMatrix<double>               cell_matrix(n, n);
    std::vector<types::global_dof_index> indices;
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      {
        fe_values.reinit(cell);
        cell_matrix = 0.;
        for (const unsigned int q : fe_values.quadrature_point_indices())
          for (unsigned int i = 0; i < n; ++i)
            {
              const SymmetricTensor<2, 2> stress =
                reference_stress(fe_values[displacement].symmetric_gradient(i,
                                                                            q),
                                 E,
                                 nu,
                                 material.plane_strain);
              for (unsigned int j = 0; j < n; ++j)
                cell_matrix(i, j) +=
                  stress * fe_values[displacement].symmetric_gradient(j, q) *
                  fe_values.JxW(q);
            }
        discretization.get_dof_indices(cell, indices);
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j < n; ++j)
            reference.add(indices[i], indices[j], cell_matrix(i, j));
      }
    double difference = 0., largest = 0.;
    for (types::global_dof_index i = 0; i < stiffness.m(); ++i)
      for (auto entry = reference.begin(i); entry != reference.end(i); ++entry)
        {
          largest    = std::max(largest, std::abs(entry->value()));
          difference = std::max(difference,
                                std::abs(entry->value() -
                                         stiffness.el(i, entry->column())));
        }
    return {difference, largest};
  }
} // namespace

int
main()
{
  struct Case
  {
    std::string name;
    std::unique_ptr<Discretization<2>> (*create)();
  };
  const auto fea_q9 = []() {
    return create_discretization<2>(DiscretizationMethod::fea, half_disk(2), 2);
  };
  const auto fea_q8 = []() {
    return create_discretization<2>(DiscretizationMethod::fea,
                                    half_disk(2),
                                    2,
                                    FEAElement::serendipity);
  };
  const auto iga_p2 = []() {
    return create_discretization<2>(DiscretizationMethod::iga, half_disk(2), 2);
  };
  const auto iga_p3 = []() {
    return create_discretization<2>(DiscretizationMethod::iga, half_disk(1), 3);
  };
  const std::vector<Case> cases = {{"FEA Q9", fea_q9},
                                   {"FEA Q8", fea_q8},
                                   {"IGA p2", iga_p2},
                                   {"IGA p3", iga_p3}};
  for (const auto &c : cases)
    {
      const auto discretization = c.create();
      for (const bool plane_strain : {true, false})
        for (const double nu : {0.2, 0.49})
          {
            ElasticMaterial material;
            material.youngs_modulus = 1000.;
            material.poisson_ratio  = nu;
            material.plane_strain   = plane_strain;
            const auto [difference, largest] =
              largest_difference(*discretization, material, false);
            check_close(c.name +
                          (plane_strain ? ", plane strain" : ", plane stress") +
                          ", nu " + std::to_string(nu) +
                          ": largest |K - K_ref| / max |K_ref|",
                        difference / largest,
                        0.,
                        1.,
                        1e-12,
                        true);
          }
      // The control: the check can fail.
      ElasticMaterial material;
      const auto [difference, largest] =
        largest_difference(*discretization, material, true);
      check_true(c.name + ": control (lambda and mu swapped) differs by " +
                   std::to_string(difference / largest) + " > 0.01",
                 difference / largest > 0.01);
    }
  return report();
}
