// Layer 5: the quasi-static boundary of mass redistribution. The massless
// unknowns b of the contact surfaces (ElasticBody::redistribute_mass) carry
// no inertia, so at every time step they obey equilibrium with the interior
// displacements u_i given:
//   r_b(u_b) = f_contact,b(u) - (K u)_b = 0,   (K u)_b = K_bb u_b + K_bi u_i.
// The contact force depends on u_b only (the surface unknowns are all in
// b). Newton with the Gauss-Newton tangent of the penalty forces
// (ContactLinearization): (K_bb + K_c) du = r, K_c = sum_t k_t grad g_t
// grad g_t^T over the active Gauss points, factorised by Eigen's
// SimplicialLDLT. The factor is kept while the active set (the Gauss points
// and the segments they project on) does not change and the iteration
// contracts well (modified Newton): most steps reuse the factor of an
// earlier step. A step whose residual grows is cut back (halved, up to 8
// times). The first iteration of a step needs no contact evaluation: the
// contact force of the previous step's solution is exact for its u_b.
#ifndef isoimpact_quasi_static_boundary_h
#define isoimpact_quasi_static_boundary_h

#include <deal.II/lac/vector.h>

#include <isoimpact/mechanics/contact.h>
#include <isoimpact/mechanics/elastic_body.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace isoimpact
{
  template <int dim>
  struct ContactInteraction;

  // The work of the boundary solve, summed over the steps.
  struct BoundarySolveWork
  {
    std::uint64_t solves         = 0; // one per time step
    std::uint64_t evaluations    = 0; // contact evaluations (residuals)
    std::uint64_t substitutions  = 0; // back-substitutions (Newton steps)
    std::uint64_t factorizations = 0; // LDL^T factorisations
    std::uint64_t step_cuts      = 0; // halvings of a Newton step
    // Solves accepted at 100 times the tolerance after 20 iterations.
    std::uint64_t loose_solves = 0;
    // Solves accepted after max_iterations within 1e4 times the tolerance.
    std::uint64_t stalled_solves     = 0;
    unsigned int  max_evaluations    = 0;  // of one solve
    unsigned int  last_evaluations   = 0;  // of the last solve
    double        max_residual_ratio = 0.; // |r| / scale at convergence
  };

  template <int dim>
  class QuasiStaticBoundary
  {
  public:
    // Fills the contact forces (the integrator's force vectors, zeroed
    // first) and results for the current displacements, with the
    // linearisation (ContactModel::set_linearize(true)); the argument says
    // whether to record the contact points.
    using Evaluate = std::function<void(bool)>;

    /**
     * The massless unknowns of the bodies (ElasticBody::massless_dofs());
     * `forces` and `results` are the integrator's, which `evaluate` fills.
     * `relative_tolerance`: converged when |r| <= tol (|f_c,b| + |(|K|
     * |u|)_b|).
     */
    QuasiStaticBoundary(const std::vector<ElasticBody<dim> *>      &bodies,
                        const std::vector<ContactInteraction<dim>> &contacts,
                        const std::vector<dealii::Vector<double>>  &forces,
                        const std::vector<ContactResult<dim>>      &results,
                        const double       relative_tolerance = 1e-8,
                        const unsigned int max_iterations     = 100);
    ~QuasiStaticBoundary();

    /**
     * Sets the massless unknowns of the bodies' displacements so that r_b =
     * 0 for the current interior displacements; on return the forces and
     * results are those of the solution. Throws if it does not converge.
     */
    void
    solve(const Evaluate &evaluate, const bool record_points);

    // v_b^{n+1/2} = (u_b^{n+1} - u_b^n) / dt of the last solve into the
    // half-step velocities (per body).
    void
    set_velocities(std::vector<dealii::Vector<double>> &half_step_velocity,
                   const double                         dt) const;

    // Number of massless unknowns of all bodies.
    unsigned int
    n_unknowns() const;

    const BoundarySolveWork &
    work() const;

  private:
    // Eigen's matrices, vectors and factor (Eigen stays inside the library).
    struct Data;

    void
    gather_contact_forces();
    void
    factorize();
    void
    scatter() const;

    const std::vector<ElasticBody<dim> *>       bodies;
    const std::vector<ContactInteraction<dim>> &contacts;
    const std::vector<dealii::Vector<double>>  &forces;
    const std::vector<ContactResult<dim>>      &results;
    const double                                tolerance;
    const unsigned int                          max_iterations;

    // The unknowns: (body, dof), and per body the index of each dof (-1:
    // not massless).
    std::vector<std::pair<unsigned int, dealii::types::global_dof_index>>
                                  unknowns;
    std::vector<std::vector<int>> index_of;
    std::unique_ptr<Data>         data;
    BoundarySolveWork             statistics;
  };
} // namespace isoimpact

#endif
