// Layer 4: consistent mass solve by a sparse Cholesky factorisation per
// displacement component (CHOLMOD).
#include <deal.II/base/exceptions.h>
#include <deal.II/base/timer.h>

#include <isoimpact/mechanics/mass_solver.h>

#include <cholmod.h>

#include <algorithm>
#include <string>
#include <tuple>

using namespace dealii;

namespace isoimpact
{
  // One factor and the components that share it; the work arrays of the
  // solve are allocated at the first solve and reused.
  struct ComponentMassSolver::Factor
  {
    // Unknowns of each component that uses this factor, in the order of the
    // factor's rows.
    std::vector<std::vector<types::global_dof_index>> dofs;
    cholmod_common                                    common;
    cholmod_factor                                   *L = nullptr;
    cholmod_dense                                    *B = nullptr;
    cholmod_dense *X = nullptr, *Y = nullptr, *E = nullptr;

    Factor()
    {
      cholmod_start(&common);
      // METIS nested dissection: on 2D meshes its fill grows like
      // n log n, less than AMD's at 1e5 unknowns and more.
      common.nmethods           = 1;
      common.method[0].ordering = CHOLMOD_METIS;
      common.postorder          = 1;
      common.print              = 0;
    }

    ~Factor()
    {
      cholmod_free_dense(&B, &common);
      cholmod_free_dense(&X, &common);
      cholmod_free_dense(&Y, &common);
      cholmod_free_dense(&E, &common);
      cholmod_free_factor(&L, &common);
      cholmod_finish(&common);
    }
  };

  ComponentMassSolver::ComponentMassSolver() = default;

  ComponentMassSolver::~ComponentMassSolver() = default;

  void
  ComponentMassSolver::initialize(
    const SparseMatrix<double>       &mass,
    const std::vector<unsigned char> &dof_component)
  {
    Timer timer;
    factors.clear();
    const types::global_dof_index n = mass.m();
    AssertThrow(dof_component.size() == n,
                ExcDimensionMismatch(dof_component.size(), n));
    const unsigned int n_components =
      n == 0 ?
        0 :
        1 + *std::max_element(dof_component.begin(), dof_component.end());

    // Local index of each unknown within its component.
    std::vector<types::global_dof_index>              local(n);
    std::vector<std::vector<types::global_dof_index>> component_dofs(
      n_components);
    for (types::global_dof_index i = 0; i < n; ++i)
      {
        local[i] = component_dofs[dof_component[i]].size();
        component_dofs[dof_component[i]].push_back(i);
      }

    // The lower triangle of each component's block, row by row.
    using Entry =
      std::tuple<types::global_dof_index, types::global_dof_index, double>;
    std::vector<std::vector<Entry>> blocks(n_components);
    for (types::global_dof_index i = 0; i < n; ++i)
      for (auto it = mass.begin(i); it != mass.end(i); ++it)
        {
          const types::global_dof_index j = it->column();
          if (it->value() == 0.)
            continue;
          AssertThrow(dof_component[i] == dof_component[j],
                      ExcMessage("the consistent mass matrix couples "
                                 "unknowns " +
                                 std::to_string(i) + " and " +
                                 std::to_string(j) +
                                 " of different components: it cannot be "
                                 "factorised per component"));
          if (local[j] <= local[i])
            blocks[dof_component[i]].emplace_back(local[i],
                                                  local[j],
                                                  it->value());
        }

    // Components with equal blocks share a factor.
    std::vector<int> owner(n_components, -1);
    for (unsigned int c = 0; c < n_components; ++c)
      {
        for (unsigned int d = 0; d < c && owner[c] < 0; ++d)
          if (owner[d] == int(d) &&
              component_dofs[d].size() == component_dofs[c].size() &&
              blocks[d] == blocks[c])
            owner[c] = d;
        if (owner[c] >= 0)
          continue;
        owner[c] = c;

        auto                          factor  = std::make_unique<Factor>();
        cholmod_common               *cm      = &factor->common;
        const types::global_dof_index m       = component_dofs[c].size();
        cholmod_triplet              *triplet = cholmod_allocate_triplet(m,
                                                            m,
                                                            blocks[c].size(),
                                                            -1,
                                                            CHOLMOD_REAL,
                                                            cm);
        AssertThrow(triplet != nullptr,
                    ExcMessage("CHOLMOD could not allocate the mass block"));
        auto *rows   = static_cast<int *>(triplet->i);
        auto *cols   = static_cast<int *>(triplet->j);
        auto *values = static_cast<double *>(triplet->x);
        for (std::size_t k = 0; k < blocks[c].size(); ++k)
          {
            rows[k]   = std::get<0>(blocks[c][k]);
            cols[k]   = std::get<1>(blocks[c][k]);
            values[k] = std::get<2>(blocks[c][k]);
          }
        triplet->nnz      = blocks[c].size();
        cholmod_sparse *A = cholmod_triplet_to_sparse(triplet, 0, cm);
        cholmod_free_triplet(&triplet, cm);
        factor->L = cholmod_analyze(A, cm);
        if (factor->L != nullptr)
          cholmod_factorize(A, factor->L, cm);
        cholmod_free_sparse(&A, cm);
        AssertThrow(factor->L != nullptr && cm->status == CHOLMOD_OK &&
                      factor->L->minor == m,
                    ExcMessage("the consistent mass block of component " +
                               std::to_string(c) +
                               " is not positive definite (CHOLMOD status " +
                               std::to_string(cm->status) + ")"));
        factors.push_back(std::move(factor));
      }
    // Attach each component to its factor, in the order of the components.
    for (unsigned int c = 0; c < n_components; ++c)
      {
        unsigned int f = 0;
        for (int d = 0; d < owner[c]; ++d)
          f += (owner[d] == int(d));
        factors[f]->dofs.push_back(component_dofs[c]);
      }
    for (auto &factor : factors)
      factor->B = cholmod_zeros(factor->dofs[0].size(),
                                factor->dofs.size(),
                                CHOLMOD_REAL,
                                &factor->common);
    setup_seconds = timer.wall_time();
  }

  void
  ComponentMassSolver::solve(Vector<double> &a, const Vector<double> &f) const
  {
    for (const auto &factor : factors)
      {
        const std::size_t m = factor->dofs[0].size();
        auto             *b = static_cast<double *>(factor->B->x);
        for (std::size_t k = 0; k < factor->dofs.size(); ++k)
          {
            const auto &dofs = factor->dofs[k];
            for (std::size_t i = 0; i < m; ++i)
              b[k * m + i] = f(dofs[i]);
          }
        const int ok = cholmod_solve2(CHOLMOD_A,
                                      factor->L,
                                      factor->B,
                                      nullptr,
                                      &factor->X,
                                      nullptr,
                                      &factor->Y,
                                      &factor->E,
                                      &factor->common);
        AssertThrow(ok, ExcMessage("CHOLMOD could not solve with the mass"));
        const auto *x = static_cast<const double *>(factor->X->x);
        for (std::size_t k = 0; k < factor->dofs.size(); ++k)
          {
            const auto &dofs = factor->dofs[k];
            for (std::size_t i = 0; i < m; ++i)
              a(dofs[i]) = x[k * m + i];
          }
      }
  }

  unsigned int
  ComponentMassSolver::n_factors() const
  {
    return factors.size();
  }

  std::size_t
  ComponentMassSolver::factor_nonzeros() const
  {
    std::size_t nonzeros = 0;
    for (const auto &factor : factors)
      nonzeros += std::size_t(factor->common.lnz);
    return nonzeros;
  }

  std::size_t
  ComponentMassSolver::memory_consumption() const
  {
    std::size_t bytes = 0;
    for (const auto &factor : factors)
      {
        const cholmod_factor *L = factor->L;
        bytes += L->is_super ?
                   L->xsize * sizeof(double) + L->ssize * sizeof(int) :
                   L->nzmax * (sizeof(double) + sizeof(int));
        bytes += L->n * 3 * sizeof(int); // permutation, column counts
        for (const cholmod_dense *dense :
             {factor->B, factor->X, factor->Y, factor->E})
          if (dense != nullptr)
            bytes += dense->nzmax * sizeof(double);
        for (const auto &dofs : factor->dofs)
          bytes += dofs.size() * sizeof(types::global_dof_index);
      }
    return bytes;
  }

  double
  ComponentMassSolver::setup_time() const
  {
    return setup_seconds;
  }
} // namespace isoimpact
