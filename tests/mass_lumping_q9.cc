// Mass matrices of one undistorted Q9 element (FE_Q(2)^2 on a single
// rectangular cell): consistent diagonal, row-sum and HRZ lumped masses as
// fractions of the element mass, against the exact values of
// /work/shared/notes/lumping-and-timestep.md:
//   consistent diagonal: corner 4/225, mid-side 16/225, centre 64/225,
//   row-sum = HRZ:       corner 1/36,  mid-side 1/9,    centre 4/9,
// of m_e = rho * area, per displacement component; and the totals of every
// scheme equal rho * area.
//
// Tolerance 1e-13 (relative): on an affine cell the 3x3 Gauss rule integrates
// the products of biquadratic functions (degree 4 per direction) exactly, so
// the only error is round-off of sums of at most 81 products of O(1) numbers
// (about 1e-15). The fractions are distinct by at least 1e-2, so a wrongly
// placed mass or a wrong scheme fails by 12 orders of magnitude.
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <isoimpact/discretization/discretization_fea.h>
#include <isoimpact/mechanics/assembly.h>

#include <cmath>
#include <string>

#include "tests.h"

using namespace dealii;

using namespace isoimpact;

namespace
{
  enum class NodeType
  {
    corner,
    mid_side,
    centre
  };

  // Position of a node of the Q9 element on the rectangle [a, b].
  NodeType
  classify(const Point<2> &x, const Point<2> &a, const Point<2> &b)
  {
    unsigned int n_on_edge = 0;
    for (unsigned int d = 0; d < 2; ++d)
      {
        const double h = b[d] - a[d];
        if (std::abs(x[d] - a[d]) < 1e-12 * h ||
            std::abs(x[d] - b[d]) < 1e-12 * h)
          ++n_on_edge;
        else
          // A Q9 node that is not on an edge coordinate is at its middle.
          AssertThrow(std::abs(x[d] - 0.5 * (a[d] + b[d])) < 1e-12 * h,
                      ExcMessage("unexpected node position"));
      }
    return n_on_edge == 2 ?
             NodeType::corner :
             (n_on_edge == 1 ? NodeType::mid_side : NodeType::centre);
  }

  std::string
  name(const NodeType type)
  {
    return type == NodeType::corner ?
             "corner" :
             (type == NodeType::mid_side ? "mid-side" : "centre");
  }

  void
  check_rectangle(const Point<2> &a, const Point<2> &b, const double density)
  {
    std::cout << "--- rectangle (" << a << ") - (" << b << "), rho " << density
              << std::endl;
    BodyGeometry geometry;
    geometry.shape              = BodyGeometry::Shape::rectangle;
    geometry.lower_left         = a;
    geometry.upper_right        = b;
    geometry.global_refinements = 0;
    const DiscretizationFEA<2> discretization(geometry, 2);

    const double element_mass = density * (b[0] - a[0]) * (b[1] - a[1]);
    CHECK_TRUE(discretization.triangulation().n_active_cells() == 1);
    CHECK_TRUE(discretization.n_dofs() == 18);

    AffineConstraints<double> no_constraints;
    no_constraints.close();
    SparsityPattern sparsity;
    make_sparsity_pattern(discretization, no_constraints, sparsity);
    SparseMatrix<double> consistent(sparsity);
    assemble_consistent_mass_matrix(discretization,
                                    density,
                                    no_constraints,
                                    consistent);
    const Vector<double> row_sum = assemble_lumped_mass(discretization,
                                                        density,
                                                        MassScheme::row_sum,
                                                        no_constraints);
    const Vector<double> hrz     = assemble_lumped_mass(discretization,
                                                    density,
                                                    MassScheme::hrz,
                                                    no_constraints);

    const double consistent_fraction[3] = {4. / 225., 16. / 225., 64. / 225.};
    const double lumped_fraction[3]     = {1. / 36., 1. / 9., 4. / 9.};
    unsigned int n_of_type[3]           = {0, 0, 0};

    double consistent_total[2] = {0., 0.};
    double row_sum_total[2]    = {0., 0.};
    double hrz_total[2]        = {0., 0.};
    double cross_component     = 0.;
    for (types::global_dof_index i = 0; i < discretization.n_dofs(); ++i)
      {
        const unsigned int c = discretization.dof_component(i);
        const NodeType type  = classify(discretization.dof_position(i), a, b);
        ++n_of_type[static_cast<int>(type)];
        const std::string where = name(type) + " dof " + std::to_string(i) +
                                  " component " + std::to_string(c);
        std::cout << "  " << where << std::endl;
        const int t = static_cast<int>(type);
        isoimpact_tests::check_close("consistent diagonal / m_e, " + where,
                                     consistent.diag_element(i) / element_mass,
                                     consistent_fraction[t],
                                     1e-13);
        isoimpact_tests::check_close("row-sum / m_e, " + where,
                                     row_sum(i) / element_mass,
                                     lumped_fraction[t],
                                     1e-13);
        isoimpact_tests::check_close("HRZ / m_e, " + where,
                                     hrz(i) / element_mass,
                                     lumped_fraction[t],
                                     1e-13);
        for (auto entry = consistent.begin(i); entry != consistent.end(i);
             ++entry)
          {
            if (discretization.dof_component(entry->column()) == c)
              consistent_total[c] += entry->value();
            else
              cross_component += std::abs(entry->value());
          }
        row_sum_total[c] += row_sum(i);
        hrz_total[c] += hrz(i);
      }
    // Each component: 4 corners, 4 mid-sides, 1 centre.
    CHECK_TRUE(n_of_type[0] == 8 && n_of_type[1] == 8 && n_of_type[2] == 2);
    // The components are not coupled by the mass.
    CHECK_CLOSE_ABS(cross_component, 0., 1e-13 * element_mass);

    for (unsigned int c = 0; c < 2; ++c)
      {
        const std::string comp = " (component " + std::to_string(c) + ")";
        isoimpact_tests::check_close("consistent total" + comp,
                                     consistent_total[c],
                                     element_mass,
                                     1e-13);
        isoimpact_tests::check_close("row-sum total" + comp,
                                     row_sum_total[c],
                                     element_mass,
                                     1e-13);
        isoimpact_tests::check_close("HRZ total" + comp,
                                     hrz_total[c],
                                     element_mass,
                                     1e-13);
      }
    CHECK_CLOSE(integrate_mass(discretization, density), element_mass, 1e-13);
  }
} // namespace

int
main()
{
  // Unit square, then a non-square rectangle off the origin with another
  // density (aspect ratio 4: the fractions do not depend on it).
  check_rectangle(Point<2>(0., 0.), Point<2>(1., 1.), 1.);
  check_rectangle(Point<2>(-1., 0.5), Point<2>(3., 1.5), 2.7);
  return isoimpact_tests::report();
}
