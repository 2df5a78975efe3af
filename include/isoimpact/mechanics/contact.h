// Layer 4: contact models seen by the time integrator (ContactModel), the
// Gauss points of contact surfaces shared by all of them, and the symmetric
// two-pass penalty contact between two deformable bodies (frictionless, 2D),
// on the boundary segments of layer 3. The rigid obstacle is in
// rigid_obstacle.h.
//
// Virtual work: delta Pi_c = sum over the two passes b = 0, 1 of
//   eps_pass * integral over the surface of body b of g_N delta g_N, g_N < 0,
// where pass b takes the Gauss points of body b's surface and projects them
// onto the surface of the other body. Convention (`PenaltyPerPass`):
//   half: eps_pass = eps_N / 2, so that the two passes together act like a
//         single-pass penalty eps_N (pressure ~ eps_N |g_N|), the default;
//   full: eps_pass = eps_N, the formulation written with eps_N on both
//         boundaries (effective penalty 2 eps_N).
#ifndef isoimpact_contact_h
#define isoimpact_contact_h

#include <deal.II/base/array_view.h>
#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/tensor.h>

#include <isoimpact/discretization/discretization.h>
#include <isoimpact/nurbs/enum_names.h>

#include <array>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace isoimpact
{
  enum class PenaltyPerPass
  {
    half,
    full
  };

  // "half" or "full".
  inline constexpr EnumNames<PenaltyPerPass, 2> penalty_per_pass_names{
    "penalty per pass",
    {{{PenaltyPerPass::half, "half"}, {PenaltyPerPass::full, "full"}}}};

  // How ranks that share a contact's Gauss points exchange what the
  // projections found (ContactModel::distribute_points()).
  enum class PointExchange
  {
    automatic, // in memory the ranks map where all are on one node
    messages   // MPI_Allgather wherever the ranks are
  };

  // "automatic" or "messages".
  inline constexpr EnumNames<PointExchange, 2> point_exchange_names{
    "contact point exchange",
    {{{PointExchange::automatic, "automatic"},
      {PointExchange::messages, "messages"}}}};

  struct ContactSettings
  {
    double         penalty             = 1e5; // eps_N, Pa/m
    PenaltyPerPass penalty_per_pass    = PenaltyPerPass::half;
    unsigned int   n_quadrature_points = 4; // Gauss points per segment
    // Viscous contact damping as a fraction xi of the critical damping
    // 2 sqrt(eps mu) of the penalty spring on the surface mass mu (see
    // SurfaceMassDensity); 0 = none.
    double damping_ratio = 0.;
    // Bipenalty (Contact/Bipenalty): the mass penalty eps_m per pass, kg/m^2
    // per unit thickness, set by the scene (set_bipenalty_mass); 0 = none.
    double bipenalty_mass = 0.;
  };

  // A Gauss point of a contact surface where the contact pressure is
  // positive.
  template <int dim>
  struct ContactPoint
  {
    dealii::Point<dim> reference_position; // of the Gauss point
    // The consistent pressure there (the surface's pressure field, see
    // SurfaceNodes::project_pressure), Pa.
    double pressure;
    // The pointwise value of the penalty traction at the Gauss point, Pa
    // (eps_N,effective |g_N| undamped; 0 where the point is not active).
    double       gauss_point_pressure;
    double       gap;  // g_N, m (negative if active)
    unsigned int body; // whose Gauss point: 0 or 1, the model's order
  };

  /**
   * The Gauss-Newton tangent of the penalty forces of one evaluation (the
   * gap's normal, projection and weights frozen): each active Gauss point t
   * adds k_t grad g_t grad g_t^T to the stiffness, k_t = eps_pass w_t and
   * grad g_t the gradient of its gap with respect to the unknowns (R_k n on
   * the point's own nodes, -R_l n on the nodes of its projection). Filled by
   * ContactModel::evaluate() only after set_linearize(true).
   */
  struct ContactLinearization
  {
    // One entry of a gap gradient: the body (model order), the unknown and
    // the derivative of the gap.
    struct Entry
    {
      unsigned int                    body;
      dealii::types::global_dof_index dof;
      double                          value;
    };
    std::vector<Entry>        entries;
    std::vector<unsigned int> term_begin; // entries of term t: [t], [t + 1]
    std::vector<double>       stiffness;  // k_t
    // Per term: its Gauss point and the segment it projects on; equal
    // signatures mean the same active set.
    std::vector<std::uint64_t> signature;

    unsigned int
    n_terms() const
    {
      return stiffness.size();
    }
    // Starts a term; its entries follow with add_gradient().
    void
    add_term(const double k, const std::uint64_t id)
    {
      if (term_begin.empty())
        term_begin.push_back(0);
      stiffness.push_back(k);
      signature.push_back(id);
      term_begin.push_back(entries.size());
    }
    // Adds sign * R_k n over the nodes of `segment` to the last term.
    template <int dim>
    void
    add_gradient(const BoundarySegment<dim>   &segment,
                 const std::vector<double>    &shape_values,
                 const dealii::Tensor<1, dim> &normal,
                 const double                  sign,
                 const unsigned int            body)
    {
      for (unsigned int k = 0; k < shape_values.size(); ++k)
        for (unsigned int d = 0; d < dim; ++d)
          entries.push_back({body,
                             segment.node_dofs[k][d],
                             sign * shape_values[k] * normal[d]});
      term_begin.back() = entries.size();
    }
  };

  // What a contact model reports for one evaluation. Bodies are numbered in
  // the order the model takes them (0, or 0 and 1).
  template <int dim>
  struct ContactResult
  {
    double energy = 0.; // J/m (per unit thickness)
    // Power removed by the contact damping, W/m (>= 0).
    double damping_power = 0.;
    // Maximum of the consistent pressure field over the surfaces' Gauss
    // points, Pa.
    double max_pressure = 0.;
    // Maximum of the pointwise penalty traction over the Gauss points, Pa.
    double                         max_gauss_point_pressure = 0.;
    double                         max_penetration          = 0.; // m, -min g_N
    dealii::Tensor<1, dim>         force_on_body_0; // N/m, resultant
    unsigned int                   n_active_points = 0;
    std::vector<ContactPoint<dim>> points;
    // With record_points: the nodal values p_k (Pa) of the consistent
    // pressure of each surface in contact, by the x unknown of the node,
    // for body 0 and body 1 of the model (for the ParaView output).
    std::array<std::vector<std::pair<dealii::types::global_dof_index, double>>,
               2>
      nodal_pressures;
    // Bipenalty: the lumped mass penalty of this evaluation, (unknown, kg/m)
    // entries for body 0 and body 1 (an unknown may repeat: add them up).
    std::array<std::vector<std::pair<dealii::types::global_dof_index, double>>,
               2>
      penalty_masses;
    // After ContactModel::set_linearize(true): the tangent of the forces.
    ContactLinearization linearization;

    // The elastic pressure less the contact damping c dg/dt, down to zero
    // (no adhesion); adds the power the damping removes at a point of
    // weight w, (pressure - damped) dg/dt w, to damping_power.
    double
    damp(const double pressure,
         const double damping,
         const double gap_rate,
         const double weight);

    // Counts an active Gauss point: adds its penalty energy and its force on
    // body 0, updates the maximal Gauss-point pressure and penetration.
    void
    add_active_point(const double                  gauss_point_pressure,
                     const double                  gap,
                     const double                  point_energy,
                     const dealii::Tensor<1, dim> &point_force_on_body_0);
  };

  /**
   * A Gauss point of a contact surface: its segment, the segment's nodal
   * functions there, the reference arc-length weight and the reference
   * position. Shared by every contact model that integrates over boundary
   * segments (two-body penalty contact, rigid obstacles).
   */
  template <int dim>
  struct SurfaceQuadraturePoint
  {
    unsigned int        segment;
    std::vector<double> shape_values;
    double              weight;
    dealii::Point<dim>  reference_position;
  };

  /**
   * The Gauss points (n_points per segment, QGauss on eta in [0, 1]) of the
   * segments. If `segment_lengths` is given it receives the reference
   * length of each segment (the sum of its weights).
   */
  template <int dim>
  std::vector<SurfaceQuadraturePoint<dim>>
  surface_quadrature(const std::vector<BoundarySegment<dim>> &segments,
                     const unsigned int                       n_points,
                     std::vector<double> *segment_lengths = nullptr);

  /**
   * Current position sum_k R_k (X_k + u_k) of a Gauss point of `segment`.
   */
  template <int dim>
  dealii::Point<dim>
  current_position(const BoundarySegment<dim>           &segment,
                   const SurfaceQuadraturePoint<dim>    &point,
                   const dealii::ArrayView<const double> u);

  /**
   * Adds the point force `force` (traction times weight) at a point where
   * the nodal functions of `segment` take `shape_values` to f.
   */
  template <int dim>
  void
  distribute_point_force(const BoundarySegment<dim>   &segment,
                         const std::vector<double>    &shape_values,
                         const dealii::Tensor<1, dim> &force,
                         dealii::Vector<double>       &f);

  /**
   * A penalty spring on a contact surface of a body: `stiffness` (Pa/m) is a
   * traction per unit normal displacement of the surface that bounds what
   * the contact model can exert there. Used for the stable time step bound
   * (mechanics/stable_time_step.h), with the whole surface active.
   */
  template <int dim>
  struct SurfaceSpring
  {
    const std::vector<BoundarySegment<dim>> *segments  = nullptr;
    double                                   stiffness = 0.;
  };

  /**
   * The nodes of a contact surface (shared by neighbouring segments) and
   * the lumped surface mass a_k = int R_k ds of each (m per unit thickness),
   * integrated with the surface's Gauss points.
   */
  template <int dim>
  class SurfaceNodes
  {
  public:
    SurfaceNodes() = default;
    SurfaceNodes(const std::vector<BoundarySegment<dim>>        &segments,
                 const std::vector<SurfaceQuadraturePoint<dim>> &points);

    /**
     * The consistent contact pressure: the L2 projection of the pressure
     * p_q at the Gauss points onto the surface trace of the
     * discretisation, with the lumped surface mass, p_k = sum_q p_q w_q
     * R_k(q) / a_k, evaluated at the Gauss points, field_q = sum_k R_k(q)
     * p_k. Lumped because it needs no solve and, with the non-negative
     * NURBS functions, keeps p_k >= 0 and does not overshoot at the edge of
     * the contact zone, where the pressure has a square-root profile (the
     * consistent surface mass oscillates there); a uniform pressure is
     * reproduced exactly. The quadratic Lagrange functions are negative in
     * parts of a face: their projection may exceed the largest point value
     * by a few per cent on coarse faces (tests/symmetric_contact.cc).
     * `points` are the constructor's; `nodal` is scratch.
     */
    void
    project_pressure(const std::vector<SurfaceQuadraturePoint<dim>> &points,
                     const std::vector<double> &point_pressure,
                     std::vector<double>       &nodal,
                     std::vector<double>       &field) const;

    // [segment][k]: the surface node of node k of the segment.
    std::vector<std::vector<unsigned int>> node_of_segment;
    // Per surface node: its x unknown and a_k.
    std::vector<dealii::types::global_dof_index> x_dof;
    std::vector<double>                          area;

  private:
    // The points' weights, and per point its nodes and their functions'
    // values (from first_value[q] on): one array each, read in order.
    std::vector<double>       point_weights;
    std::vector<unsigned int> first_value;
    std::vector<unsigned int> value_nodes;
    std::vector<double>       values;
  };

  /**
   * Mass per unit reference length of a contact surface (kg/m^2 per unit
   * thickness), from the lumped nodal masses m_k of its body: mu_k = m_k /
   * a_k at each surface node k, interpolated with the nodal functions. It
   * sets the critical damping 2 sqrt(eps mu) of a penalty spring eps on the
   * surface.
   */
  template <int dim>
  class SurfaceMassDensity
  {
  public:
    SurfaceMassDensity() = default;
    // `nodal_masses` per unknown (the x component is read).
    SurfaceMassDensity(const SurfaceNodes<dim>      &nodes,
                       const dealii::Vector<double> &nodal_masses);

    bool
    empty() const;

    // mu at a point of `segment` where its nodal functions take
    // `shape_values`.
    double
    operator()(const unsigned int         segment,
               const std::vector<double> &shape_values) const;

  private:
    std::vector<std::vector<double>> node_densities; // [segment][node]
  };

  /**
   * Adds the consistent pressure of one surface (body `body` of the model)
   * to `result`: projects the Gauss-point pressures, updates max_pressure
   * and, with `record_points`, records every Gauss point where either
   * pressure is positive. `nodal` and `field` are scratch.
   */
  template <int dim>
  void
  add_surface_pressure(const SurfaceNodes<dim>                        &nodes,
                       const std::vector<SurfaceQuadraturePoint<dim>> &points,
                       const std::vector<double> &point_pressure,
                       const std::vector<double> &point_gap,
                       const unsigned int         body,
                       const bool                 record_points,
                       std::vector<double>       &nodal,
                       std::vector<double>       &field,
                       ContactResult<dim>        &result);

  /**
   * The mean mass per unit reference length of a contact surface, sum_k m_k
   * / sum_k a_k over its nodes (kg/m^2 per unit thickness), with the lumped
   * nodal masses of its body (per unknown, the x component is read) and
   * n_points Gauss points per segment.
   */
  template <int dim>
  double
  mean_surface_mass_density(const std::vector<BoundarySegment<dim>> &segments,
                            const unsigned int                       n_points,
                            const dealii::Vector<double> &nodal_masses);

  /**
   * Velocity sum_k R_k v_k of a point of `segment` where its nodal functions
   * take `shape_values`.
   */
  template <int dim>
  dealii::Tensor<1, dim>
  point_velocity(const BoundarySegment<dim>   &segment,
                 const std::vector<double>    &shape_values,
                 const dealii::Vector<double> &v);

  /**
   * The interface through which the time integrator (layer 5) sees a contact
   * model: it acts on one body (against a rigid obstacle) or two. evaluate()
   * is the one entry of every model.
   */
  template <int dim>
  class ContactModel
  {
  public:
    virtual ~ContactModel() = default;

    // 1 or 2.
    virtual unsigned int
    n_bodies() const = 0;

    // Adds the contact forces for the current displacements (in each body's
    // unknowns) to the force vectors; one entry per body, in the model's
    // order (nullptr: that body's forces are not wanted on this process). The
    // velocities (the half-step velocities of central differences) are read
    // only with contact damping and may then not be empty. Returns energy,
    // pressure, damping power and the resultant on body 0; with `record_points`
    // also every active Gauss point. The displacements are views of each body's
    // values (on ranks that share the state, the window the passes write:
    // doc/parallel.md, session 43).
    virtual ContactResult<dim>
    evaluate(const std::vector<dealii::ArrayView<const double>> &displacements,
             const std::vector<const dealii::Vector<double> *>  &velocities,
             const std::vector<dealii::Vector<double> *>        &forces,
             const bool record_points) const = 0;
    // The same with the displacements as vectors ({&u_0, &u_1}).
    ContactResult<dim>
    evaluate(
      const std::initializer_list<const dealii::Vector<double> *> displacements,
      const std::vector<const dealii::Vector<double> *>          &velocities,
      const std::vector<dealii::Vector<double> *>                &forces,
      const bool record_points) const
    {
      std::vector<dealii::ArrayView<const double>> views;
      for (const auto *u : displacements)
        views.emplace_back(u->data(), u->size());
      return evaluate(views, velocities, forces, record_points);
    }

    // The lumped nodal masses of each body (model order), which the contact
    // damping needs; must be called before evaluate() if damping_ratio() >
    // 0.
    virtual void
    set_surface_masses(
      const std::vector<const dealii::Vector<double> *> &nodal_masses) = 0;

    // The contact damping as a fraction of critical (0: none).
    virtual double
    damping_ratio() const = 0;

    // One line for the program's set-up report.
    virtual std::string
    description() const = 0;

    /**
     * Bipenalty (doc/formulation.md): the mass penalty eps_m (kg/m^2 per
     * unit thickness) that evaluate() lumps onto the unknowns of every
     * active Gauss point, and the constant C of the bound
     * lambda_max(K_c, M_c) <= C / eps_m of the linearised penalty K_c
     * against that mass M_c, for any active set. A model without it has
     * C = 0 and refuses eps_m > 0.
     */
    virtual void
    set_bipenalty_mass(const double eps_m);
    // Several MPI ranks that meet at every step anyway (CentralDifference::
    // ranks_meet_at_every_step()): the ranks may share the contact's work;
    // evaluate() is then collective. Without this call (and by default)
    // every process evaluates the whole contact itself.
    virtual void
    distribute_points(const MPI_Comm communicator, const PointExchange how);
    // How this process gets the other ranks' share of the contact's work:
    // "none" (it does all of it), "shared memory" or "messages".
    virtual std::string
    point_exchange() const;
    virtual double
    bipenalty_mass() const;
    virtual double
    bipenalty_stiffness() const;
    // With true, evaluate() also returns the Gauss-Newton tangent of the
    // undamped penalty forces (ContactResult::linearization), which the
    // quasi-static boundary of mass redistribution needs.
    void
    set_linearize(const bool on)
    {
      linearize = on;
    }
    // With false, evaluate() projects the pressures (max_pressure, and the
    // points' and nodal pressures) only where record_points asks: for an MPI
    // rank that records no history.
    void
    set_pressures_at_every_step(const bool on)
    {
      pressures_at_every_step = on;
    }

    // The penalty spring the model can put on the surface of each of its
    // bodies (entry b for body b of evaluate()). evaluate() adds forces on
    // these segments' unknowns only: the lumped step reads forces there
    // alone (CentralDifference, ElasticBody::set_force_rows()).
    virtual std::vector<SurfaceSpring<dim>>
    surface_springs() const = 0;

  protected:
    bool linearize               = false;
    bool pressures_at_every_step = true;
  };

  template <int dim>
  inline void
  ContactModel<dim>::set_bipenalty_mass(const double eps_m)
  {
    AssertThrow(eps_m == 0.,
                dealii::ExcMessage("the contact model '" + description() +
                                   "' has no bipenalty (mass penalty)"));
  }

  template <int dim>
  inline void
  ContactModel<dim>::distribute_points(const MPI_Comm, const PointExchange)
  {}

  template <int dim>
  inline std::string
  ContactModel<dim>::point_exchange() const
  {
    return "none";
  }

  template <int dim>
  inline double
  ContactModel<dim>::bipenalty_mass() const
  {
    return 0.;
  }

  template <int dim>
  inline double
  ContactModel<dim>::bipenalty_stiffness() const
  {
    return 0.;
  }

  namespace internal
  {
    // A contact surface in its current configuration and its search
    // structure (contact.cc).
    template <int dim>
    class CurrentSurface;
    // The points' outcomes in memory the ranks of one node map (contact.cc).
    struct SharedOutcomeWindow;
  } // namespace internal

  /**
   * Two-pass penalty contact of body 0 and body 1. Pass b takes the Gauss
   * points of body b's surface and projects them onto the other body's
   * surface; the search structure (an R-tree of the segments' current
   * bounding boxes) is built in every evaluation.
   */
  template <int dim>
  class PenaltyContact : public ContactModel<dim>
  {
  public:
    PenaltyContact(const ContactSettings            &settings,
                   std::vector<BoundarySegment<dim>> surface_of_body_0,
                   std::vector<BoundarySegment<dim>> surface_of_body_1);
    ~PenaltyContact() override;

    unsigned int
    n_bodies() const override;

    using ContactModel<dim>::evaluate;
    ContactResult<dim>
    evaluate(const std::vector<dealii::ArrayView<const double>> &displacements,
             const std::vector<const dealii::Vector<double> *>  &velocities,
             const std::vector<dealii::Vector<double> *>        &forces,
             const bool record_points) const override;

    // The damping of a point pair uses the reduced surface mass
    // mu_0 mu_1 / (mu_0 + mu_1) and the spring of both passes, 2 eps_pass;
    // each pass carries half of it.
    void
    set_surface_masses(
      const std::vector<const dealii::Vector<double> *> &nodal_masses) override;

    double
    damping_ratio() const override;

    std::string
    description() const override;

    // Mass on both sides of each active pair: eps_m w |R_k| / sum |R| on the
    // Gauss point's nodes and on the nodes at its projection.
    void
    set_bipenalty_mass(const double eps_m) override;
    double
    bipenalty_mass() const override;
    // C = 2 Lambda^2 eps_pass, Lambda = max sum_k |R_k| over the surfaces
    // (1 for NURBS, 1.25 for quadratic Lagrange faces).
    double
    bipenalty_stiffness() const override;

    // 4 eps_pass on both surfaces: linearised, a point of one surface and
    // its projection on the other are joined by eps_pass n (x) n, and
    // (a - b)^2 <= 2 a^2 + 2 b^2 splits that into 2 eps_pass on each; each
    // surface projects in one pass and is projected on in the other.
    std::vector<SurfaceSpring<dim>>
    surface_springs() const override;

    double
    penalty_per_pass() const;

    // Number of Gauss points on the two surfaces together.
    unsigned int
    n_surface_points() const;

    /**
     * Several MPI ranks (issue 13): each rank projects every n-th Gauss
     * point of the two surfaces (numbered together, body 0 first; on 2
     * ranks with surfaces of as many points, rank b the points of body b)
     * and the ranks exchange what the projections found: in memory they
     * all map where they share a node (each writes its outcomes in place,
     * then waits for the others' count of evaluations), else (or with
     * PointExchange::messages) in one MPI_Allgather; then every rank adds
     * the forces of all points in the order of one process, so that the
     * forces and the result have its bits. evaluate() is then collective.
     * Without this call the process projects every point.
     */
    void
    distribute_points(const MPI_Comm      communicator,
                      const PointExchange how) override;

    std::string
    point_exchange() const override;

  private:
    // What the projection of one Gauss point found: the other surface's
    // segment (-1: no contact), its parameter there, the normal, the gap,
    // the pressure of the pass (damped) and the power its damping removed.
    struct PointOutcome
    {
      double                segment;
      double                eta;
      std::array<double, 2> normal;
      double                gap;
      double                pressure;
      double                damping_power;
    };
    // The outcomes of the points g = rank, rank + n_ranks, ... (padded to
    // the same count on every rank), and of every point after the exchange.
    MPI_Comm                          communicator = MPI_COMM_SELF;
    unsigned int                      n_ranks      = 1;
    unsigned int                      rank         = 0;
    mutable std::vector<PointOutcome> own_outcomes, all_outcomes;
    // 2 ranks and two surfaces of as many Gauss points: rank b projects the
    // points of body b (it then updates the search structure of the other
    // body's surface only), else every n_ranks-th point of both.
    bool points_by_body = false;
    // All ranks on one node: the outcomes in shared memory instead, and
    // this rank's count of evaluations (which slot it writes next).
    std::shared_ptr<internal::SharedOutcomeWindow> shared_outcomes;
    mutable long long                              n_evaluations = 0;
    // Scratch of evaluate(): the two surfaces in the current configuration.
    mutable std::array<std::unique_ptr<internal::CurrentSurface<dim>>, 2>
      current_surfaces;

    // A contact surface: its segments, their reference lengths and its Gauss
    // points.
    struct Surface
    {
      std::vector<BoundarySegment<dim>>        segments;
      std::vector<double>                      reference_lengths;
      std::vector<SurfaceQuadraturePoint<dim>> points;
      SurfaceNodes<dim>                        nodes;
      SurfaceMassDensity<dim>                  mass_density;
    };
    // Scratch of evaluate(): per surface, the Gauss-point pressure and gap.
    mutable std::array<std::vector<double>, 2> point_pressure, point_gap;
    mutable std::vector<double>                nodal_scratch, field_scratch;

    ContactSettings        settings;
    std::array<Surface, 2> surfaces;
    // max over both surfaces of sum_k |R_k| (sampled, see the constructor).
    double lebesgue_constant = 1.;
  };
} // namespace isoimpact

#endif
