// Layer 4: mass redistribution (Khenous, Laborde and Renard 2008; Hager,
// Hueber and Wohlmuth 2008): the lumped mass of the unknowns of a contact
// surface is moved to nearby interior unknowns so that the surface carries
// no inertia, while the total mass and the first moment (centre of mass) of
// each displacement component are kept.
#ifndef isoimpact_mass_redistribution_h
#define isoimpact_mass_redistribution_h

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <isoimpact/discretization/discretization.h>

#include <vector>

namespace isoimpact
{
  struct MassRedistribution
  {
    // The lumped masses after redistribution (zero on `massless`).
    dealii::Vector<double> masses;
    // The unconstrained unknowns whose nodal functions are nonzero on the
    // contact surface (sorted): they carry no mass afterwards.
    std::vector<dealii::types::global_dof_index> massless;
    // The unknowns that received the mass: the other unconstrained unknowns
    // of the cells that hold a massless one (sorted).
    std::vector<dealii::types::global_dof_index> receivers;
  };

  /**
   * Takes the lumped masses `lumped` (per unknown) off the unconstrained
   * unknowns of the segments `surface` (their node_dofs) and adds them to
   * the receivers, per displacement component c, as
   *   dm_i = m_S w_i / sum_j w_j,   w_i = m_i exp(beta_c . (X_i - Xs_c) / L),
   * m_S and Xs_c the surface's mass and centre of mass, L the largest
   * |X_i - Xs_c|, with beta_c (Newton) such that the receivers take the
   * surface's first moment sum m_b X_b exactly (X = dof_position). Every
   * receiver gains mass (dm_i > 0), so the total mass and the first moment
   * are kept and no mass shrinks. Constrained unknowns keep their masses.
   * Throws if the surface's centre of mass is not inside the receivers'
   * hull (no positive tilt exists).
   */
  template <int dim>
  MassRedistribution
  redistribute_lumped_mass(const Discretization<dim>    &discretization,
                           const dealii::Vector<double> &lumped,
                           const dealii::AffineConstraints<double> &constraints,
                           const std::vector<BoundarySegment<dim>> &surface);
} // namespace isoimpact

#endif
