// The stiffness rows in pairs (PairedRows, used by the lumped step's fused
// pass): the product K u of each pair equals deal.II's SparseMatrix::vmult
// bit for bit, for FEA Q9, FEA Q8 and IGA p2 and p3 half disks with the
// roller constraints of the symmetry cut (whose rows and columns are absent
// from the pattern, so those blocks hold padded zeros), for a random u and
// for a u with exact zeros and negative zeros. Checked per body:
// 1. the pairs qualify (the rows come in pairs, each row after its diagonal
//    ascending) and cover every row;
// 2. the padding: without constraints every pair's two rows have the same
//    2 x 2 blocks, so the pairs store exactly the matrix's nonzeros; with
//    the rollers the padded zeros are exactly the entries the constraints
//    took out: the stored entries equal the nonzeros of the unconstrained
//    matrix (at these coarse levels 3-13 % more than the constrained
//    matrix's; 0.2 % at the benchmark's level 7);
// 3. max_i |(K u)_i (pairs) - (K u)_i (vmult)| = 0 exactly. Control: the
//    same sums in another order (the coupling inside the pair added last)
//    differ from vmult; and a mutation of PairedRows::products() that adds
//    that coupling last fails check 3 by up to 3.6e-12 (FEA Q9).
// 4. Rows from several matrices (a rank's own rows and its load-balancing
//    band, ElasticBody): K's pairs split over matrices A (pairs p = 0 mod 3)
//    and B (p = 1 mod 3), the others stored in neither (only a zero
//    diagonal). The pairs built from A and B give vmult's bits on their
//    rows and zero on the others, and store only their own rows: their
//    stored entries plus those of the pairs of the rest equal the whole
//    matrix's. A pair whose two rows come from different matrices gives no
//    pairs.
// Also: a matrix with an odd number of rows gives no pairs.
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <isoimpact/discretization/discretization_fea.h>
#include <isoimpact/mechanics/elastic_body.h>
#include <isoimpact/mechanics/paired_rows.h>

#include <random>

#include "test_helpers.h"
#include "tests.h"

using namespace dealii;
using namespace isoimpact;
using namespace isoimpact_tests;

namespace
{
  // The largest |x_i - y_i|.
  double
  largest_difference(const Vector<double> &x, const Vector<double> &y)
  {
    double largest = 0.;
    for (unsigned int i = 0; i < x.size(); ++i)
      largest = std::max(largest, std::abs(x(i) - y(i)));
    return largest;
  }

  // The rows of K for which keep(row) holds; the other rows hold only a
  // zero diagonal (as the rows another rank computes).
  struct SelectedRows
  {
    SparsityPattern      pattern;
    SparseMatrix<double> matrix;
  };
  template <typename Keep>
  std::unique_ptr<SelectedRows>
  select_rows(const SparseMatrix<double> &K, const Keep &keep)
  {
    DynamicSparsityPattern dsp(K.m(), K.n());
    for (unsigned int row = 0; row < K.m(); ++row)
      if (keep(row))
        for (auto entry = K.begin(row); entry != K.end(row); ++entry)
          dsp.add(row, entry->column());
    auto selected = std::make_unique<SelectedRows>();
    selected->pattern.copy_from(dsp);
    selected->matrix.reinit(selected->pattern);
    for (unsigned int row = 0; row < K.m(); ++row)
      if (keep(row))
        for (auto entry = K.begin(row); entry != K.end(row); ++entry)
          selected->matrix.set(row, entry->column(), entry->value());
    return selected;
  }

  std::unique_ptr<ElasticBody<2>>
  make_body(const std::string                  &name,
            std::unique_ptr<Discretization<2>>  discretization,
            const std::vector<RollerCondition> &rollers)
  {
    ElasticMaterial material;
    material.youngs_modulus = 1000.;
    material.poisson_ratio  = 0.3;
    material.plane_strain   = true;
    return std::make_unique<ElasticBody<2>>(name,
                                            std::move(discretization),
                                            material,
                                            MassScheme::hrz,
                                            rollers,
                                            Tensor<1, 2>());
  }

  // make_discretization() twice: the body with and without the rollers.
  template <typename MakeDiscretization>
  void
  check_body(const std::string        &name,
             const MakeDiscretization &make_discretization)
  {
    const auto free_body = make_body(name, make_discretization(), {});
    {
      PairedRows free_pairs;
      free_pairs.build(free_body->stiffness_matrix());
      check_close(name + " without constraints: stored entries",
                  free_pairs.n_stored_entries(),
                  free_body->stiffness_matrix().n_nonzero_elements(),
                  0.);
    }
    const auto                  body = make_body(name,
                                make_discretization(),
                                {{BodyGeometry::symmetry_boundary_id, 0}});
    const SparseMatrix<double> &K    = body->stiffness_matrix();
    std::cout << "--- " << name << ": " << K.m() << " unknowns, "
              << K.n_nonzero_elements() << " nonzeros, "
              << body->constraints().n_constraints() << " constrained"
              << std::endl;
    CHECK_TRUE(body->constraints().n_constraints() > 0);

    PairedRows pairs;
    pairs.build(K);
    check_true(name + ": the rows pair up", !pairs.empty());
    if (pairs.empty())
      return;
    check_true(name + ": every row is in a pair", 2 * pairs.n_pairs() == K.m());
    check_close(name + ": stored entries (with padded zeros)",
                pairs.n_stored_entries(),
                free_body->stiffness_matrix().n_nonzero_elements(),
                0.);
    check_true(name + ": padded zeros where the rollers took entries out",
               pairs.n_stored_entries() > K.n_nonzero_elements());

    std::mt19937                           generator(17);
    std::uniform_real_distribution<double> uniform(-1., 1.);
    Vector<double>                         u(K.m());
    for (auto &value : u)
      value = uniform(generator);
    // The same with exact zeros and negative zeros in every third entry.
    Vector<double> sparse_u = u;
    for (unsigned int i = 0; i < u.size(); i += 3)
      sparse_u(i) = (i % 2 == 0) ? 0. : -0.;

    for (const Vector<double> *x : {&u, &sparse_u})
      {
        Vector<double> by_vmult(K.m()), by_pairs(K.m()), reordered(K.m());
        K.vmult(by_vmult, *x);
        for (std::size_t p = 0; p < pairs.n_pairs(); ++p)
          pairs.products(p, x->data(), by_pairs(2 * p), by_pairs(2 * p + 1));
        check_close(name + (x == &u ? "" : ", u with zeros") +
                      ": max |K u (pairs) - K u (vmult)|",
                    largest_difference(by_pairs, by_vmult),
                    0.,
                    1.,
                    0.,
                    true);
        // PairedRows::vmult: the pairs in ranges over the threads.
        Vector<double> by_paired_vmult(K.m());
        pairs.vmult(by_paired_vmult, *x);
        check_close(name + (x == &u ? "" : ", u with zeros") +
                      ": max |PairedRows::vmult - K u (vmult)|",
                    largest_difference(by_paired_vmult, by_vmult),
                    0.,
                    1.,
                    0.,
                    true);
        // Control: the row sums in another order (the coupling inside the
        // pair added last) do not have vmult's bits.
        for (unsigned int row = 0; row < K.m(); ++row)
          {
            const unsigned int partner = row ^ 1u;
            double             sum     = 0.;
            for (auto entry = K.begin(row); entry != K.end(row); ++entry)
              if (entry->column() != partner)
                sum += entry->value() * (*x)(entry->column());
            reordered(row) = sum + K.el(row, partner) * (*x)(partner);
          }
        check_true(name + ": control, another order differs from vmult",
                   largest_difference(reordered, by_vmult) > 0.);
      }

    // 4. The rows from two matrices, a third of the pairs in neither.
    const auto a    = select_rows(K, [](unsigned int row) {
      return (row / 2) % 3 == 0;
    });
    const auto b    = select_rows(K, [](unsigned int row) {
      return (row / 2) % 3 == 1;
    });
    const auto rest = select_rows(K, [](unsigned int row) {
      return (row / 2) % 3 == 2;
    });
    PairedRows split_pairs, rest_pairs;
    split_pairs.build({&a->matrix, &b->matrix});
    rest_pairs.build(rest->matrix);
    check_true(name + ": rows from two matrices pair up",
               !split_pairs.empty() && !rest_pairs.empty());
    if (split_pairs.empty() || rest_pairs.empty())
      return;
    check_close(name + ": stored entries of two matrices' pairs + the rest's",
                split_pairs.n_stored_entries() + rest_pairs.n_stored_entries(),
                pairs.n_stored_entries(),
                0.);
    Vector<double> by_vmult(K.m()), by_split_pairs(K.m());
    K.vmult(by_vmult, u);
    for (unsigned int row = 0; row < K.m(); ++row)
      if ((row / 2) % 3 == 2)
        by_vmult(row) = 0.;
    split_pairs.vmult(by_split_pairs, u);
    check_close(name + ": two matrices' pairs: max |K u - K u (vmult)| on "
                       "their rows, |K u| on the others",
                largest_difference(by_split_pairs, by_vmult),
                0.,
                1.,
                0.,
                true);
    // A pair's two rows from two matrices: no pairs.
    const auto first_rows  = select_rows(K, [](unsigned int row) {
      return row % 2 == 0;
    });
    const auto second_rows = select_rows(K, [](unsigned int row) {
      return row % 2 == 1;
    });
    PairedRows torn_pairs;
    torn_pairs.build({&first_rows->matrix, &second_rows->matrix});
    check_true(name + ": a pair's rows from two matrices give no pairs",
               torn_pairs.empty());
  }
} // namespace

int
main()
{
  check_body("FEA Q9", [] {
    return std::make_unique<DiscretizationFEA<2>>(half_disk(3), 2);
  });
  check_body("FEA Q8", [] {
    return std::make_unique<DiscretizationFEA<2>>(half_disk(3),
                                                  2,
                                                  FEAElement::serendipity);
  });
  check_body("IGA p2", [] {
    return graded_half_disk_iga(3, 0, 2);
  });
  check_body("IGA p3", [] {
    return graded_half_disk_iga(3, 0, 3);
  });

  // An odd number of rows: no pairs.
  {
    DynamicSparsityPattern dsp(3, 3);
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        dsp.add(i, j);
    SparsityPattern pattern;
    pattern.copy_from(dsp);
    SparseMatrix<double> matrix(pattern);
    for (unsigned int i = 0; i < 3; ++i)
      matrix.set(i, i, 2.);
    PairedRows pairs;
    pairs.build(matrix);
    CHECK_TRUE(pairs.empty());
  }
  return report();
}
