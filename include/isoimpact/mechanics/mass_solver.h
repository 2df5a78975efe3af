// Layer 4: solves M a = f for a consistent mass matrix with a sparse
// Cholesky factorisation computed once (CHOLMOD, nested dissection
// ordering (NESDIS), supernodal). The mass rho N_A N_B couples no two
// displacement components, so it is factorised per component: a factor of n /
// dim rows, shared by the components whose blocks are equal up to rows that
// carry a diagonal entry only (a roller's constrained unknowns). Such rows are
// ordered last, so that the factor of the smaller block is the leading block of
// the shared factor; the components of a factor are solved together (one pass
// over the factor for all of them), and the independent subtrees of its
// elimination tree in parallel: by threads, and on several MPI ranks by the
// ranks, each solving its own subtrees (doc/parallel.md, "consistent mass").
#ifndef isoimpact_mass_solver_h
#define isoimpact_mass_solver_h

#include <deal.II/base/mpi.h>

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <cstddef>
#include <memory>
#include <vector>

namespace isoimpact
{
  class ComponentMassSolver
  {
  public:
    ComponentMassSolver();
    ~ComponentMassSolver();
    ComponentMassSolver(const ComponentMassSolver &) = delete;
    ComponentMassSolver &
    operator=(const ComponentMassSolver &) = delete;

    /**
     * Factorises the condensed mass matrix `mass` (constrained rows carry a
     * positive diagonal entry only). dof_component[i] is the component of
     * unknown i. Throws if an entry couples two components or if a block is
     * not positive definite.
     *
     * Each factor's elimination tree is split into at least two groups of
     * independent subtrees (ranks x threads where that is more), whatever
     * the number of threads, so a solve has the same bits on 1 or 2
     * threads and on 2 ranks of one thread. With a `communicator` of
     * several ranks, every rank holds the whole matrix and factor, solve()
     * is collective and each rank substitutes its own subtrees; two
     * MPI_Allgatherv per factor (the subtrees' updates of the rows they
     * share, and the solution) give every rank the whole a.
     *
     * A row of the factor below a supernode's diagonal block whose entries
     * are all negligible, |L_rj| < negligible sqrt(L_rr L_jj) for every
     * column j of the supernode, is not stored: the factor of a mass matrix
     * decays with the distance between the unknowns, and such rows are
     * numerous at fine levels (32 % of the entries at IGA p2 level 8).
     * A solve without them differs from one with every row by round-off
     * (2.1e-16 relative there; tests/consistent_mass_solve.cc); 0 keeps
     * every row.
     */
    void
    initialize(const dealii::SparseMatrix<double> &mass,
               const std::vector<unsigned char>   &dof_component,
               const MPI_Comm                      communicator = MPI_COMM_SELF,
               const double                        negligible   = 1e-16);

    // a = M^{-1} f (a and f of the full size, may not alias). Collective
    // over the communicator of initialize().
    void
    solve(dealii::Vector<double> &a, const dealii::Vector<double> &f) const;

    // Number of distinct factors (1 if all components share one).
    unsigned int
    n_factors() const;
    // Number of subtrees of the elimination trees solved side by side (the
    // sum over the factors, over all ranks; 1 per factor if it is not
    // split).
    unsigned int
    n_parallel_subtrees() const;
    // Nonzeros of the factors L (all factors).
    std::size_t
    factor_nonzeros() const;
    // Entries stored in the supernodes (nonzeros and the zeros of relaxed
    // amalgamation, without the negligible rows), stored once, in the order
    // in which both substitutions read them.
    std::size_t
    factor_stored_entries() const;
    // Bytes held by the factors and the work arrays of the solve.
    std::size_t
    memory_consumption() const;
    // Wall time of initialize() (extraction, ordering, factorisation), s.
    double
    setup_time() const;

  private:
    struct Factor;
    // Forward and backward substitution with one factor, for the
    // components that share it.
    static void
    solve_with_factor(const Factor                 &factor,
                      dealii::Vector<double>       &a,
                      const dealii::Vector<double> &f);
    template <int n_components>
    static void
    substitute(const Factor &factor, double *y);

    std::vector<std::unique_ptr<Factor>> factors;
    MPI_Comm                             communicator  = MPI_COMM_SELF;
    double                               setup_seconds = 0.;
  };
} // namespace isoimpact

#endif
