// Layer 4: consistent mass solve by a sparse Cholesky factorisation per
// displacement component (CHOLMOD).
#include <deal.II/base/exceptions.h>
#include <deal.II/base/thread_management.h>
#include <deal.II/base/timer.h>

#include <isoimpact/mechanics/mass_solver.h>

#include <cholmod.h>

#include <algorithm>
#include <string>
#include <tuple>

using namespace dealii;

namespace isoimpact
{
  // One factor and the components that share it.
  struct ComponentMassSolver::Factor
  {
    // Unknowns of each component that uses this factor, in the order of the
    // factor's rows.
    std::vector<std::vector<types::global_dof_index>> dofs;
    cholmod_common                                    common;
    cholmod_factor                                   *L = nullptr;
    // Row k of the permuted system is unknown dofs[c][perm[k]] of
    // component c.
    std::vector<int> perm;
    // Work: the right-hand sides, interleaved by component.
    mutable std::vector<double> y;

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
        // A packed simplicial L L^T (column-wise, diagonal first): the
        // solve below runs over it once forwards and once backwards, for
        // all the components that share it.
        cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, factor->L, cm);
        AssertThrow(cm->status == CHOLMOD_OK && !factor->L->is_super &&
                      factor->L->is_ll,
                    ExcMessage("CHOLMOD could not convert the mass factor"));
        const int *permutation = static_cast<const int *>(factor->L->Perm);
        factor->perm.assign(permutation, permutation + m);
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
      factor->y.resize(factor->dofs[0].size() * factor->dofs.size());
    setup_seconds = timer.wall_time();
  }

  void
  ComponentMassSolver::solve_with_factor(const Factor         &factor_ref,
                                         Vector<double>       &a,
                                         const Vector<double> &f)
  {
    const Factor *factor = &factor_ref;

    {
      const int     m  = factor->perm.size();
      const int     nc = factor->dofs.size();
      const auto   *Lp = static_cast<const int *>(factor->L->p);
      const auto   *Li = static_cast<const int *>(factor->L->i);
      const auto   *Lx = static_cast<const double *>(factor->L->x);
      double *const y  = factor->y.data();
      for (int k = 0; k < m; ++k)
        for (int c = 0; c < nc; ++c)
          y[k * nc + c] = f(factor->dofs[c][factor->perm[k]]);
      // L z = y, column by column.
      for (int j = 0; j < m; ++j)
        for (int c = 0; c < nc; ++c)
          {
            const double zj = y[j * nc + c] / Lx[Lp[j]];
            y[j * nc + c]   = zj;
            for (int q = Lp[j] + 1; q < Lp[j + 1]; ++q)
              y[Li[q] * nc + c] -= Lx[q] * zj;
          }
      // L^T x = z, backwards.
      for (int j = m - 1; j >= 0; --j)
        for (int c = 0; c < nc; ++c)
          {
            double sum = y[j * nc + c];
            for (int q = Lp[j] + 1; q < Lp[j + 1]; ++q)
              sum -= Lx[q] * y[Li[q] * nc + c];
            y[j * nc + c] = sum / Lx[Lp[j]];
          }
      for (int k = 0; k < m; ++k)
        for (int c = 0; c < nc; ++c)
          a(factor->dofs[c][factor->perm[k]]) = y[k * nc + c];
    }
  }

  void
  ComponentMassSolver::solve(Vector<double> &a, const Vector<double> &f) const
  {
    // The factors write disjoint entries of a: one task each. A triangular
    // solve is bound by the latency of its indirect accesses rather than by
    // the memory bandwidth, so two of them run side by side.
    if (factors.size() == 1)
      {
        solve_with_factor(*factors[0], a, f);
        return;
      }
    Threads::TaskGroup<void> tasks;
    for (const auto &factor : factors)
      {
        const Factor *pointer = factor.get();
        tasks += Threads::new_task([&a, &f, pointer]() {
          solve_with_factor(*pointer, a, f);
        });
      }
    tasks.join_all();
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
        // Values, row indices; column pointers, counts, permutation.
        bytes += L->nzmax * (sizeof(double) + sizeof(int)) +
                 L->n * 6 * sizeof(int) + factor->y.size() * sizeof(double);
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
