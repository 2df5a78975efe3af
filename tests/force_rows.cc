// The lumped step's force rows (ElasticBody::set_force_rows()): on a half
// disk (R = 4 m, FEA Q9 at 2 global refinements, 562 unknowns, and IGA p2 at
// 3, 704 unknowns; HRZ mass), a
// displacement and a half-step velocity of sines and forces on a set of rows
// (the curved surface's unknowns, as the contacts write them, or a set with
// odd rows, neighbours, the first and the last row), the fused pass that
// reads forces on the force rows alone gives
// 1. the acceleration, v and v^{n+1/2} and the step's energies of the pass
//    that reads every row's force, bit for bit (difference 0), and leaves
//    the forces zero (0);
// 2. check_force_rows() throws for a force of 1 N/m on a row outside the set
//    and passes forces on the set (counted: 1 throw of 1 try, 0 of 1).
#include <isoimpact/discretization/discretization.h>
#include <isoimpact/mechanics/elastic_body.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "test_helpers.h"
#include "tests.h"

using namespace dealii;
using namespace isoimpact;

namespace
{
  std::unique_ptr<ElasticBody<2>>
  make_body(const DiscretizationMethod method)
  {
    return std::make_unique<ElasticBody<2>>(
      "half disk",
      create_discretization<2>(method,
                               isoimpact_tests::half_disk(
                                 method == DiscretizationMethod::fea ? 2 : 3),
                               2),
      ElasticMaterial(),
      MassScheme::hrz,
      std::vector<RollerCondition>(),
      Tensor<1, 2>());
  }

  // One step of `body` from the given state with the forces `f`; returns
  // the acceleration, v, v^{n+1/2}, the energies and what is left of f.
  std::vector<double>
  step(ElasticBody<2> &body, Vector<double> f, const Vector<double> &v0)
  {
    Vector<double> vh = v0;
    body.compute_acceleration_and_velocities(f, vh, 1e-3);
    std::vector<double> out;
    for (const Vector<double> *x : {&body.acceleration, &body.velocity, &vh})
      out.insert(out.end(), x->begin(), x->end());
    const auto &energies = body.energies_of_last_step();
    CHECK_TRUE(energies.has_value());
    out.push_back(energies->kinetic);
    out.push_back(energies->strain);
    out.push_back(f.linfty_norm());
    return out;
  }

  void
  run(const DiscretizationMethod method)
  {
    std::cout << "--- " << (method == DiscretizationMethod::fea ? "FEA" : "IGA")
              << std::endl;
    auto               body = make_body(method);
    const unsigned int n    = body->n_dofs();
    Vector<double>     v0(n);
    for (unsigned int i = 0; i < n; ++i)
      {
        body->displacement(i) = 1e-3 * std::sin(0.91 * i);
        v0(i)                 = std::sin(0.37 * i);
      }
    CHECK_TRUE(body->step_zeroes_force());

    // The curved surface's unknowns, and rows of every parity.
    std::vector<types::global_dof_index> surface;
    for (const auto &segment : body->discretization().boundary_segments(
           BodyGeometry::curved_boundary_id))
      for (const auto &node : segment.node_dofs)
        surface.insert(surface.end(), node.begin(), node.end());
    std::sort(surface.begin(), surface.end());
    surface.erase(std::unique(surface.begin(), surface.end()), surface.end());
    const std::vector<types::global_dof_index> scattered =
      {0, 3, 4, 5, 10, 17, n / 2, n / 2 + 1, n - 2, n - 1};
    for (const auto &rows : {surface, scattered})
      {
        Vector<double> f(n);
        for (const auto i : rows)
          f(i) = 1e3 * std::cos(1.3 * i);
        const std::vector<double> every_row = step(*body, f, v0);
        auto                      reading   = make_body(method);
        reading->displacement               = body->displacement;
        reading->set_force_rows(rows);
        const std::vector<double> force_rows = step(*reading, f, v0);
        double                    difference = 0.;
        for (std::size_t k = 0; k < every_row.size(); ++k)
          difference =
            std::max(difference, std::abs(every_row[k] - force_rows[k]));
        std::cout << "    " << rows.size() << " force rows of " << n
                  << std::endl;
        CHECK_TRUE(every_row.size() == force_rows.size());
        CHECK_CLOSE_ABS(difference, 0., 0.);
        CHECK_CLOSE_ABS(force_rows.back(), 0., 0.);

        // 2. A force outside the rows, then on them only.
        unsigned int outside = 0;
        while (std::binary_search(rows.begin(), rows.end(), outside))
          ++outside;
        Vector<double> stray(n);
        stray(outside)      = 1.;
        unsigned int throws = 0;
        try
          {
            reading->check_force_rows(stray);
          }
        catch (const std::exception &e)
          {
            ++throws;
            std::cout << "    thrown: " << e.what() << std::endl;
          }
        CHECK_CLOSE_ABS(throws, 1., 0.);
        throws = 0;
        try
          {
            reading->check_force_rows(f);
          }
        catch (const std::exception &)
          {
            ++throws;
          }
        CHECK_CLOSE_ABS(throws, 0., 0.);
      }
  }
} // namespace

int
main()
{
  run(DiscretizationMethod::fea);
  run(DiscretizationMethod::iga);
  return isoimpact_tests::report();
}
