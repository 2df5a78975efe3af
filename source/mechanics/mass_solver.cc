// Layer 4: consistent mass solve by supernodal sparse Cholesky factors per
// displacement component (CHOLMOD).
#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/multithread_info.h>
#include <deal.II/base/thread_management.h>
#include <deal.II/base/timer.h>

#include <isoimpact/mechanics/mass_solver.h>

#include <cholmod.h>

#include <algorithm>
#include <climits>
#include <numeric>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    using Index = types::global_dof_index;

    // Ranks of `comm`; 1 if the program did not start MPI (no launcher).
    unsigned int
    n_processes(const MPI_Comm comm)
    {
      return Utilities::MPI::job_supports_mpi() ?
               Utilities::MPI::n_mpi_processes(comm) :
               1;
    }

    // One component's block of the mass matrix in the component's own
    // numbering: the lower triangle row by row, and which rows carry a
    // diagonal entry only.
    struct Block
    {
      std::vector<std::tuple<Index, Index, double>> lower;
      std::vector<bool>                             diagonal_only;
      std::vector<double>                           diagonal;
      std::size_t                                   n_diagonal_only = 0;
    };

    // Whether a and b are equal once the rows and columns marked in skip
    // are removed.
    bool
    equal_outside(const Block &a, const Block &b, const std::vector<bool> &skip)
    {
      auto       ia = a.lower.begin(), ib = b.lower.begin();
      const auto skipped = [&skip](const auto &entry) {
        return skip[std::get<0>(entry)] || skip[std::get<1>(entry)];
      };
      for (;;)
        {
          while (ia != a.lower.end() && skipped(*ia))
            ++ia;
          while (ib != b.lower.end() && skipped(*ib))
            ++ib;
          if (ia == a.lower.end() || ib == b.lower.end())
            return ia == a.lower.end() && ib == b.lower.end();
          if (*ia != *ib)
            return false;
          ++ia;
          ++ib;
        }
    }

    // The rows of `block` that are diagonal-only there but not in `ref`.
    std::vector<bool>
    extra_diagonal_rows(const Block &block, const Block &ref)
    {
      std::vector<bool> rows(block.diagonal_only.size());
      for (std::size_t r = 0; r < rows.size(); ++r)
        rows[r] = block.diagonal_only[r] && !ref.diagonal_only[r];
      return rows;
    }

    // The lower triangle of `block` restricted to the rows with
    // position[r] >= 0, renumbered to position[r], as a CHOLMOD matrix.
    cholmod_sparse *
    to_cholmod(const Block            &block,
               const std::vector<int> &position,
               const int               size,
               cholmod_common         *common)
    {
      std::size_t n_entries = 0;
      for (const auto &[row, column, value] : block.lower)
        n_entries += (position[row] >= 0 && position[column] >= 0);
      cholmod_triplet *triplet = cholmod_allocate_triplet(size,
                                                          size,
                                                          n_entries,
                                                          -1,
                                                          CHOLMOD_REAL,
                                                          common);
      AssertThrow(triplet != nullptr,
                  ExcMessage("CHOLMOD could not allocate the mass block"));
      auto       *rows    = static_cast<int *>(triplet->i);
      auto       *columns = static_cast<int *>(triplet->j);
      auto       *values  = static_cast<double *>(triplet->x);
      std::size_t k       = 0;
      for (const auto &[row, column, value] : block.lower)
        if (position[row] >= 0 && position[column] >= 0)
          {
            // Lower triangle of the renumbered matrix.
            rows[k]    = std::max(position[row], position[column]);
            columns[k] = std::min(position[row], position[column]);
            values[k]  = value;
            ++k;
          }
      triplet->nnz      = n_entries;
      cholmod_sparse *A = cholmod_triplet_to_sparse(triplet, 0, common);
      cholmod_free_triplet(&triplet, common);
      AssertThrow(A != nullptr,
                  ExcMessage("CHOLMOD could not convert the mass block"));
      return A;
    }

    // A supernodal factor's values as the substitutions read them, in the
    // order of the forward substitution: per supernode (columns [k1, k1 +
    // n_cols), n_below rows below its diagonal block) the rows in groups of
    // rows_per_group, each group column by column (so that one pass over
    // the solution so far serves the group's rows). First the diagonal
    // block's lower triangle: per group (rows [f, f + m)) the columns [0,
    // f), m values each, then the group's own triangle column by column
    // (the diagonal, then the group's rows below it); then the rows below
    // the diagonal block, n_cols values per row. The backward substitution
    // reads the same copy from its end to its start.
    // CHOLMOD's block also stores the upper triangle, and its columns are
    // read with gaps; this copy has neither.
    // A row below a diagonal block whose entries are all negligible,
    // |L_rj| < negligible * sqrt(L_rr L_jj) for every column j of the
    // supernode, is left out (with its row number): the factor of a mass
    // matrix decays with the distance between the unknowns, and the rows
    // of distant separators hold only such entries.
    struct PackedValues
    {
      // The forward substitution forms its products for this many rows at
      // once.
      static constexpr int     rows_per_group = 4;
      std::vector<double>      values;
      std::vector<std::size_t> offset; // per supernode, and the end
      // The rows kept below each supernode's diagonal block:
      // rows[row_offset[s]] to rows[row_offset[s + 1]].
      std::vector<int>         rows;
      std::vector<std::size_t> row_offset;

      void
      pack(const cholmod_factor &L, const double negligible)
      {
        const auto *super = static_cast<const int *>(L.super);
        const auto *pi    = static_cast<const int *>(L.pi);
        const auto *px    = static_cast<const int *>(L.px);
        const auto *Ls    = static_cast<const int *>(L.s);
        const auto *x     = static_cast<const double *>(L.x);
        // Entry (row r, column j) of supernode s's block is
        // x[px[s] + j * n_rows + r].
        std::vector<double> diagonal(L.n);
        for (std::size_t s = 0; s < L.nsuper; ++s)
          {
            const int n_rows = pi[s + 1] - pi[s];
            for (int j = 0; j < super[s + 1] - super[s]; ++j)
              diagonal[super[s] + j] = x[px[s] + std::size_t(j) * n_rows + j];
          }
        std::vector<int> kept; // per supernode, its kept rows' positions
        row_offset.assign(L.nsuper + 1, 0);
        for (std::size_t s = 0; s < L.nsuper; ++s)
          {
            const int     n_cols = super[s + 1] - super[s];
            const int     n_rows = pi[s + 1] - pi[s];
            const double *block  = x + px[s];
            for (int r = n_cols; r < n_rows; ++r)
              {
                const double row_diagonal = diagonal[Ls[pi[s] + r]];
                bool         keep         = false;
                for (int j = 0; j < n_cols && !keep; ++j)
                  keep = std::abs(block[std::size_t(j) * n_rows + r]) >=
                         negligible *
                           std::sqrt(row_diagonal * diagonal[super[s] + j]);
                if (keep)
                  kept.push_back(r);
              }
            row_offset[s + 1] = kept.size();
          }
        rows.resize(kept.size());
        offset.assign(L.nsuper + 1, 0);
        for (std::size_t s = 0; s < L.nsuper; ++s)
          {
            const std::size_t n_cols = super[s + 1] - super[s];
            const std::size_t n_kept = row_offset[s + 1] - row_offset[s];
            offset[s + 1] =
              offset[s] + n_cols * (n_cols + 1) / 2 + n_kept * n_cols;
            for (std::size_t k = row_offset[s]; k < row_offset[s + 1]; ++k)
              rows[k] = Ls[pi[s] + kept[k]];
          }
        values.resize(offset.back());
        for (std::size_t s = 0; s < L.nsuper; ++s)
          {
            const std::size_t n_cols = super[s + 1] - super[s];
            const std::size_t n_rows = pi[s + 1] - pi[s];
            const double     *block  = x + px[s];
            double           *target = values.data() + offset[s];
            for (std::size_t first = 0; first < n_cols; first += rows_per_group)
              {
                const std::size_t end =
                  std::min(n_cols, first + rows_per_group);
                for (std::size_t j = 0; j < first; ++j)
                  for (std::size_t r = first; r < end; ++r)
                    *target++ = block[j * n_rows + r];
                for (std::size_t j = first; j < end; ++j)
                  for (std::size_t r = j; r < end; ++r)
                    *target++ = block[j * n_rows + r];
              }
            // The kept rows below in groups of rows_per_group, column by
            // column within a group (the last, shorter group likewise).
            const int        *below  = kept.data() + row_offset[s];
            const std::size_t n_kept = row_offset[s + 1] - row_offset[s];
            for (std::size_t first = 0; first < n_kept; first += rows_per_group)
              {
                const std::size_t end =
                  std::min(n_kept, first + rows_per_group);
                for (std::size_t j = 0; j < n_cols; ++j)
                  for (std::size_t r = first; r < end; ++r)
                    *target++ = block[j * n_rows + below[r]];
              }
          }
      }
    };

    // Supernode s of a supernodal factor: columns [k1, k1 + n_cols), the
    // diagonal block's rows k1... first, then the n_below kept rows `rows`
    // below it; values from PackedValues.
    struct Supernode
    {
      int           k1, n_cols, n_below;
      const int    *rows;
      const double *triangle, *lower;

      Supernode(const cholmod_factor &L,
                const PackedValues   &packed,
                const int             s)
      {
        const auto *super = static_cast<const int *>(L.super);
        k1                = super[s];
        n_cols            = super[s + 1] - k1;
        n_below           = packed.row_offset[s + 1] - packed.row_offset[s];
        rows              = packed.rows.data() + packed.row_offset[s];
        triangle          = packed.values.data() + packed.offset[s];
        lower             = triangle + std::size_t(n_cols) * (n_cols + 1) / 2;
      }

      // The values of the diagonal block's group of rows that starts at
      // row `first` (a multiple of rows_per_group): every group before it
      // has rows_per_group rows.
      const double *
      diagonal_group(const int first) const
      {
        const std::size_t     g = first / PackedValues::rows_per_group;
        constexpr std::size_t m = PackedValues::rows_per_group;
        return triangle + g * (g - 1) / 2 * m * m + g * m * (m + 1) / 2;
      }

      // The group of rows below the diagonal block that starts at row
      // `first` (a multiple of rows_per_group): n_cols columns of
      // min(rows_per_group, n_below - first) values.
      const double *
      below_group(const int first) const
      {
        return lower + std::size_t(first) * n_cols;
      }
    };

    // f(std::integral_constant<int, m>()) for a group of m rows, 1 <= m <=
    // rows_per_group: the kernels below take the group's size as a
    // template argument, so that their loops over it unroll.
    template <typename Function>
    inline void
    with_group_size(const int m, const Function &f)
    {
      static_assert(PackedValues::rows_per_group == 4,
                    "with_group_size() covers 1 to 4 rows");
      switch (m)
        {
          case 4:
            f(std::integral_constant<int, 4>());
            break;
          case 3:
            f(std::integral_constant<int, 3>());
            break;
          case 2:
            f(std::integral_constant<int, 2>());
            break;
          default:
            AssertIndexRange(m - 1, 1);
            f(std::integral_constant<int, 1>());
        }
    }

    // sum[q][c] = sum_j group[j * n_rows + q] z[j * nc + c] for the n_rows
    // rows of a group, each sum in the order of j (as a column-by-column
    // update would add them): the group's rows are independent chains.
    template <int nc, int n_rows>
    inline void
    group_products(const double *__restrict group,
                   const double *__restrict z,
                   const int n_cols,
                   double (&sum)[PackedValues::rows_per_group][nc])
    {
      double partial[n_rows][nc] = {};
      for (int j = 0; j < n_cols; ++j)
        for (int q = 0; q < n_rows; ++q)
          for (int c = 0; c < nc; ++c)
            partial[q][c] += group[j * n_rows + q] * z[j * nc + c];
      for (int q = 0; q < n_rows; ++q)
        for (int c = 0; c < nc; ++c)
          sum[q][c] = partial[q][c];
    }

    // The forward substitution of the diagonal block's rows [first, first
    // + m) (stored as PackedValues says, from `values` on), its rows
    // [0, first) solved already: z of the group's rows in place. Each row
    // subtracts its products in the order of the columns, as a column by
    // column update would: the group's rows are independent chains until
    // their own triangle. Returns the end of the group's values.
    template <int nc, int m>
    inline const double *
    triangle_group(const double *__restrict values,
                   double *__restrict z,
                   const int first)
    {
      double partial[m][nc];
      for (int q = 0; q < m; ++q)
        for (int c = 0; c < nc; ++c)
          partial[q][c] = z[(first + q) * nc + c];
      for (int j = 0; j < first; ++j)
        for (int q = 0; q < m; ++q)
          for (int c = 0; c < nc; ++c)
            partial[q][c] -= values[j * m + q] * z[j * nc + c];
      values += std::size_t(first) * m;
      for (int i = 0; i < m; ++i)
        {
          const double diagonal = *values++;
          for (int c = 0; c < nc; ++c)
            z[(first + i) * nc + c] = (partial[i][c] /= diagonal);
          for (int q = i + 1; q < m; ++q, ++values)
            for (int c = 0; c < nc; ++c)
              partial[q][c] -= *values * partial[i][c];
        }
      return values;
    }

    // Forward substitution L z = y over the supernodes [s_begin, s_end),
    // nc right-hand sides interleaved in y. Updates of rows >=
    // separator_column go to `separator` (a subtree's private share of the
    // rows its task does not own) instead of y.
    template <int nc>
    void
    forward(const cholmod_factor &L,
            const PackedValues   &packed,
            const int             s_begin,
            const int             s_end,
            double *__restrict y,
            const int separator_column,
            double *__restrict separator)
    {
      constexpr int group_size = PackedValues::rows_per_group;
      for (int s = s_begin; s < s_end; ++s)
        {
          const Supernode node(L, packed, s);
          double *__restrict z = y + std::size_t(node.k1) * nc;
          const double *values = node.triangle;
          for (int first = 0; first < node.n_cols; first += group_size)
            with_group_size(std::min(group_size, node.n_cols - first),
                            [&](const auto m) {
                              values =
                                triangle_group<nc, decltype(m)::value>(values,
                                                                       z,
                                                                       first);
                            });
          for (int first = 0; first < node.n_below; first += group_size)
            {
              const int n_rows = std::min(group_size, node.n_below - first);
              double    sum[group_size][nc];
              with_group_size(n_rows, [&](const auto m) {
                group_products<nc, decltype(m)::value>(node.below_group(first),
                                                       z,
                                                       node.n_cols,
                                                       sum);
              });
              for (int q = 0; q < n_rows; ++q)
                {
                  const int row = node.rows[first + q];
                  double   *target =
                    row >= separator_column ?
                        separator + std::size_t(row - separator_column) * nc :
                        y + std::size_t(row) * nc;
                  for (int c = 0; c < nc; ++c)
                    target[c] -= sum[q][c];
                }
            }
        }
    }

    // sums[j * nc + c] += sum_q group[j * m + q] x[q][c] for the columns j
    // of a group of m rows (stored column by column), q in the order of
    // the rows: the transposed products of the backward substitution, the
    // columns last first (the group's values read from its end).
    template <int nc, int m>
    inline void
    add_transposed_products(const double *__restrict group,
                            const double (&x)[PackedValues::rows_per_group][nc],
                            const int n_cols,
                            double *__restrict sums)
    {
      for (int j = n_cols - 1; j >= 0; --j)
        for (int c = 0; c < nc; ++c)
          {
            double sum = sums[j * nc + c];
            for (int q = 0; q < m; ++q)
              sum += group[j * m + q] * x[q][c];
            sums[j * nc + c] = sum;
          }
    }

    // Backward substitution L^T x = z over the supernodes [s_begin, s_end),
    // last first; the rows below them must be final. It reads the forward
    // substitution's copy (no second copy in another order) from its end
    // towards its start, one descending stream: per supernode the groups
    // of rows below the diagonal block last first, then the diagonal
    // block's groups last first, each group's products added to one sum
    // per column (`work`: n_cols * nc values), each group's own rows solved
    // when the groups after it are done.
    template <int nc>
    void
    backward(const cholmod_factor &L,
             const PackedValues   &packed,
             const int             s_begin,
             const int             s_end,
             double *__restrict y,
             double *__restrict work)
    {
      constexpr int group_size = PackedValues::rows_per_group;
      for (int s = s_end - 1; s >= s_begin; --s)
        {
          const Supernode node(L, packed, s);
          double *__restrict x    = y + std::size_t(node.k1) * nc;
          double *__restrict sums = work;
          for (int i = 0; i < node.n_cols * nc; ++i)
            sums[i] = 0.;
          for (int first = node.n_below > 0 ?
                             (node.n_below - 1) / group_size * group_size :
                             -1;
               first >= 0;
               first -= group_size)
            {
              const int n_rows = std::min(group_size, node.n_below - first);
              double    below[group_size][nc];
              for (int q = 0; q < n_rows; ++q)
                for (int c = 0; c < nc; ++c)
                  below[q][c] = y[std::size_t(node.rows[first + q]) * nc + c];
              with_group_size(n_rows, [&](const auto m) {
                add_transposed_products<nc, decltype(m)::value>(
                  node.below_group(first),
                  below,
                  node.n_cols,
                  sums);
              });
            }
          const int last_group = (node.n_cols - 1) / group_size * group_size;
          for (int first = last_group; first >= 0; first -= group_size)
            with_group_size(std::min(group_size, node.n_cols - first),
                            [&](const auto m) {
                              constexpr int n_rows = decltype(m)::value;
                              const double *values = node.diagonal_group(first);
                              // The group's own triangle, column by column (its
                              // diagonal entry, then the group's rows below
                              // it), solved last column first.
                              const double *own =
                                values + std::size_t(first) * n_rows;
                              double solved[group_size][nc];
                              for (int i = n_rows - 1; i >= 0; --i)
                                {
                                  const double *column =
                                    own + i * n_rows - i * (i - 1) / 2;
                                  for (int c = 0; c < nc; ++c)
                                    {
                                      double sum = sums[(first + i) * nc + c];
                                      for (int q = i + 1; q < n_rows; ++q)
                                        sum += column[q - i] * solved[q][c];
                                      solved[i][c] = x[(first + i) * nc + c] =
                                        (x[(first + i) * nc + c] - sum) /
                                        column[0];
                                    }
                                }
                              // Its rows' products with the columns before the
                              // group.
                              add_transposed_products<nc, n_rows>(values,
                                                                  solved,
                                                                  first,
                                                                  sums);
                            });
        }
    }


    // Several ranks: every rank receives the values that the other ranks'
    // tasks computed, those of task t at [offset(t), offset(t + 1)) of
    // `values`.
    template <typename FactorType, typename Offset>
    void
    all_gather_tasks(const FactorType &factor,
                     double           *values,
                     const Offset     &offset)
    {
      std::vector<int> counts(factor.n_ranks()), offsets(factor.n_ranks());
      for (unsigned int r = 0; r < factor.n_ranks(); ++r)
        {
          offsets[r] = offset(factor.rank_task_begin[r]);
          counts[r]  = offset(factor.rank_task_begin[r + 1]) - offsets[r];
        }
      const int error = MPI_Allgatherv(MPI_IN_PLACE,
                                       0,
                                       MPI_DATATYPE_NULL,
                                       values,
                                       counts.data(),
                                       offsets.data(),
                                       MPI_DOUBLE,
                                       factor.communicator);
      AssertThrowMPI(error);
    }
  } // namespace

  // One factor and the components that share it.
  struct ComponentMassSolver::Factor
  {
    cholmod_common common;
    // The factor's structure (its values moved to `packed`).
    cholmod_factor *L = nullptr;
    PackedValues    packed;
    // Components sharing the factor.
    unsigned int n_components = 0;
    // Row k of the factor, its c-th component, is unknown
    // gather[k * n_components + c]; rows k >= leading[c] are not the
    // component's (invalid index): its diagonal-only rows, solved apart.
    std::vector<Index> gather;
    std::vector<int>   leading;
    // (unknown, diagonal entry) of the diagonal-only rows left out.
    std::vector<std::pair<Index, double>> diagonal_rows;
    // The elimination tree split for parallel substitution: supernodes
    // [task_begin[t], task_begin[t + 1]) are the independent subtrees of
    // task t, supernodes from task_begin.back() on (the separator, first
    // column separator_column) the rows they share. One task: no split.
    std::vector<int> task_begin;
    int              separator_column = INT_MAX;
    // Several MPI ranks: rank r substitutes the tasks [rank_task_begin[r],
    // rank_task_begin[r + 1]), contiguous in the postorder.
    MPI_Comm                  communicator = MPI_COMM_SELF;
    unsigned int              rank         = 0;
    std::vector<unsigned int> rank_task_begin;
    // Work: right-hand sides interleaved by component; per task (and the
    // separator) the backward substitution's sums per column of one
    // supernode; the tasks' updates of the separator rows, task after task
    // (separator_size() values each).
    mutable std::vector<double>              y;
    mutable std::vector<std::vector<double>> column_sums;
    mutable std::vector<double>              separator_updates;

    Factor()
    {
      cholmod_start(&common);
      common.print = 0;
      // Supernodal: dense column blocks with one row index per block row,
      // so the substitutions stream through the values. Less relaxed
      // amalgamation than CHOLMOD's default (zeros would cost bandwidth in
      // every solve, and the factorisation is done once).
      common.supernodal = CHOLMOD_SUPERNODAL;
      common.zrelax[0]  = 0.05;
      common.zrelax[1]  = 0.02;
      common.zrelax[2]  = 0.01;
    }

    ~Factor()
    {
      cholmod_free_factor(&L, &common);
      cholmod_finish(&common);
    }

    unsigned int
    n_tasks() const
    {
      return task_begin.size() - 1;
    }

    std::size_t
    separator_size() const
    {
      return std::size_t(L->n - separator_column) * n_components;
    }

    unsigned int
    n_ranks() const
    {
      return rank_task_begin.size() - 1;
    }

    // Assigns the tasks to the ranks of `comm`, contiguous and about equal
    // in number; checks that every rank split its tree alike.
    void
    distribute_tasks(const MPI_Comm comm)
    {
      communicator = comm;
      rank = n_processes(comm) > 1 ? Utilities::MPI::this_mpi_process(comm) : 0;
      const unsigned int n_rank = n_processes(comm);
      rank_task_begin.resize(n_rank + 1);
      for (unsigned int r = 0; r <= n_rank; ++r)
        rank_task_begin[r] = n_tasks() > 1 ? r * n_tasks() / n_rank : 0;
      if (n_rank > 1)
        {
          const std::vector<int> ranks_first =
            Utilities::MPI::broadcast(comm, task_begin, 0);
          AssertThrow(Utilities::MPI::min(int(ranks_first == task_begin),
                                          comm) == 1,
                      ExcMessage("the MPI ranks ordered the consistent mass "
                                 "differently: its elimination tree is "
                                 "not split alike"));
        }
    }

    // The first column of the factor that task t computes (t = n_tasks():
    // the separator's); the tasks' columns follow each other.
    std::size_t
    first_column(const unsigned int t) const
    {
      return static_cast<const int *>(L->super)[task_begin[t]];
    }

    // Splits the supernodal elimination tree: below the chain of
    // supernodes from the root down to the first branching, the subtrees
    // are independent; they are grouped, contiguous in the postorder, into
    // at most n_groups tasks of about equal size.
    void
    split_tree(const unsigned int n_groups)
    {
      const int   n_super = L->nsuper;
      const auto *super   = static_cast<const int *>(L->super);
      const auto *pi      = static_cast<const int *>(L->pi);
      const auto *px      = static_cast<const int *>(L->px);
      const auto *Ls      = static_cast<const int *>(L->s);
      task_begin          = {0, n_super};
      if (n_groups < 2 || n_super < 2)
        return;
      std::vector<int> column_supernode(L->n);
      for (int s = 0; s < n_super; ++s)
        for (int k = super[s]; k < super[s + 1]; ++k)
          column_supernode[k] = s;
      // Parent: the supernode of the first row below the diagonal block.
      std::vector<std::vector<int>> children(n_super + 1);
      std::vector<std::size_t>      subtree_size(n_super, 1);
      std::vector<double>           subtree_entries(n_super, 0.);
      for (int s = 0; s < n_super; ++s)
        {
          const int n_cols = super[s + 1] - super[s];
          const int parent = (pi[s + 1] - pi[s] > n_cols) ?
                               column_supernode[Ls[pi[s] + n_cols]] :
                               n_super; // a root: child of a virtual node
          AssertThrow(parent > s, ExcInternalError());
          children[parent].push_back(s);
          subtree_entries[s] += px[s + 1] - px[s];
          if (parent < n_super)
            {
              subtree_size[parent] += subtree_size[s];
              subtree_entries[parent] += subtree_entries[s];
            }
        }
      // Down the chain from the (virtual) root to the first branching.
      int branch = n_super;
      while (children[branch].size() == 1)
        branch = children[branch][0];
      const std::vector<int> &subtrees = children[branch];
      if (subtrees.size() < 2)
        return;
      // The chain must be the supernodes [branch, n_super) (branch itself
      // too unless virtual) and the subtrees must tile [0, branch) in
      // order, as they do in a postordered tree.
      const int separator = (branch == n_super) ? n_super : branch;
      int       next      = 0;
      for (const int s : subtrees)
        {
          if (s + 1 - int(subtree_size[s]) != next)
            return;
          next = s + 1;
        }
      if (next != separator)
        return;
      double total = 0.;
      for (const int s : subtrees)
        total += subtree_entries[s];
      std::vector<int> begins = {0};
      double           done   = 0.;
      for (std::size_t i = 0; i + 1 < subtrees.size(); ++i)
        {
          // A task ends after this subtree if that is nearer its share
          // than ending after the next one.
          done += subtree_entries[subtrees[i]];
          const double target = total * begins.size() / n_groups;
          if (begins.size() < n_groups &&
              (done >= target ||
               target - done <
                 done + subtree_entries[subtrees[i + 1]] - target))
            begins.push_back(subtrees[i] + 1);
        }
      if (begins.size() < 2)
        return;
      begins.push_back(separator);
      task_begin       = begins;
      separator_column = (separator < n_super) ? super[separator] : L->n;
    }
  };

  ComponentMassSolver::ComponentMassSolver() = default;

  ComponentMassSolver::~ComponentMassSolver() = default;

  void
  ComponentMassSolver::initialize(
    const SparseMatrix<double>       &mass,
    const std::vector<unsigned char> &dof_component,
    const MPI_Comm                    mpi_communicator,
    const double                      negligible)
  {
    Timer timer;
    factors.clear();
    communicator  = mpi_communicator;
    const Index n = mass.m();
    AssertThrow(dof_component.size() == n,
                ExcDimensionMismatch(dof_component.size(), n));
    const unsigned int n_components =
      n == 0 ?
        0 :
        1 + *std::max_element(dof_component.begin(), dof_component.end());

    // Local index of each unknown within its component.
    std::vector<Index>              local(n);
    std::vector<std::vector<Index>> component_dofs(n_components);
    for (Index i = 0; i < n; ++i)
      {
        local[i] = component_dofs[dof_component[i]].size();
        component_dofs[dof_component[i]].push_back(i);
      }

    // Each component's block.
    std::vector<Block> blocks(n_components);
    for (unsigned int c = 0; c < n_components; ++c)
      {
        blocks[c].diagonal_only.assign(component_dofs[c].size(), true);
        blocks[c].diagonal.assign(component_dofs[c].size(), 0.);
      }
    for (Index i = 0; i < n; ++i)
      {
        Block &block = blocks[dof_component[i]];
        for (auto it = mass.begin(i); it != mass.end(i); ++it)
          {
            const Index j = it->column();
            if (it->value() == 0.)
              continue;
            AssertThrow(dof_component[i] == dof_component[j],
                        ExcMessage("the consistent mass matrix couples "
                                   "unknowns " +
                                   std::to_string(i) + " and " +
                                   std::to_string(j) +
                                   " of different components: it cannot be "
                                   "factorised per component"));
            if (j == i)
              block.diagonal[local[i]] = it->value();
            else
              block.diagonal_only[local[i]] = false;
            if (local[j] <= local[i])
              block.lower.emplace_back(local[i], local[j], it->value());
          }
      }
    for (auto &block : blocks)
      block.n_diagonal_only = std::count(block.diagonal_only.begin(),
                                         block.diagonal_only.end(),
                                         true);

    // Components share a factor if their blocks are equal but for rows
    // that are diagonal-only in one of them, and these row sets are nested
    // (then each is a trailing set of one ordering). The reference of a
    // group is its member with the fewest diagonal-only rows.
    const auto reference_of = [&blocks](const std::vector<unsigned int> &g) {
      return *std::min_element(g.begin(),
                               g.end(),
                               [&blocks](const unsigned a, const unsigned b) {
                                 return blocks[a].n_diagonal_only <
                                        blocks[b].n_diagonal_only;
                               });
    };
    const auto compatible = [&](const std::vector<unsigned int> &group) {
      const unsigned int             ref = reference_of(group);
      std::vector<std::vector<bool>> extra;
      for (const unsigned int c : group)
        {
          if (component_dofs[c].size() != component_dofs[ref].size())
            return false;
          extra.push_back(extra_diagonal_rows(blocks[c], blocks[ref]));
          if (!equal_outside(blocks[c], blocks[ref], extra.back()))
            return false;
        }
      for (const auto &a : extra)
        for (const auto &b : extra)
          {
            bool a_in_b = true, b_in_a = true;
            for (std::size_t r = 0; r < a.size(); ++r)
              {
                a_in_b = a_in_b && (!a[r] || b[r]);
                b_in_a = b_in_a && (!b[r] || a[r]);
              }
            if (!a_in_b && !b_in_a)
              return false;
          }
      return true;
    };
    std::vector<std::vector<unsigned int>> groups;
    for (unsigned int c = 0; c < n_components; ++c)
      {
        bool placed = false;
        for (auto &group : groups)
          {
            auto candidate = group;
            candidate.push_back(c);
            if (compatible(candidate))
              {
                group  = candidate;
                placed = true;
                break;
              }
          }
        if (!placed)
          groups.push_back({c});
      }

    for (const auto &group : groups)
      {
        const unsigned int ref = reference_of(group);
        const int          m   = component_dofs[ref].size();
        // The members' extra diagonal-only rows, largest set first.
        std::vector<std::pair<unsigned int, std::vector<bool>>> members;
        for (const unsigned int c : group)
          members.emplace_back(c, extra_diagonal_rows(blocks[c], blocks[ref]));
        const auto count = [](const std::vector<bool> &rows) {
          return std::count(rows.begin(), rows.end(), true);
        };
        std::stable_sort(members.begin(),
                         members.end(),
                         [&count](const auto &a, const auto &b) {
                           return count(a.second) > count(b.second);
                         });

        auto            factor = std::make_unique<Factor>();
        cholmod_common *cm     = &factor->common;
        cm->nmethods           = 1;

        // The ordering: CHOLMOD's nested dissection (NESDIS: METIS node
        // separators, constrained minimum degree inside; postordered) of
        // the rows that every member has, then the layers of the members'
        // extra diagonal-only rows, the largest set's own rows first.
        // NESDIS fills less than METIS_NodeND (doc/performance.md, session
        // 24: IGA level 8 83.0 against 85.6 nonzeros per unknown, FEA level
        // 7 27.4 against 28.8).
        std::vector<int> perm;
        {
          const std::vector<bool> &largest = members.front().second;
          std::vector<int>         position(m, -1);
          int                      size = 0;
          for (int r = 0; r < m; ++r)
            if (!largest[r])
              position[r] = size++;
          cm->method[0].ordering = CHOLMOD_NESDIS;
          cm->postorder          = 1;
          cholmod_sparse *A      = to_cholmod(blocks[ref], position, size, cm);
          cholmod_factor *Lp     = cholmod_analyze(A, cm);
          cholmod_free_sparse(&A, cm);
          AssertThrow(Lp != nullptr,
                      ExcMessage("CHOLMOD could not order the mass block"));
          std::vector<int> row_of(size);
          for (int r = 0; r < m; ++r)
            if (position[r] >= 0)
              row_of[position[r]] = r;
          const auto *ordering = static_cast<const int *>(Lp->Perm);
          for (int k = 0; k < size; ++k)
            perm.push_back(row_of[ordering[k]]);
          cholmod_free_factor(&Lp, cm);
          for (std::size_t i = 0; i < members.size(); ++i)
            for (int r = 0; r < m; ++r)
              if (members[i].second[r] &&
                  (i + 1 == members.size() || !members[i + 1].second[r]))
                perm.push_back(r);
          AssertThrow(int(perm.size()) == m, ExcInternalError());
        }

        std::vector<int> identity(m);
        std::iota(identity.begin(), identity.end(), 0);
        cholmod_sparse *A = to_cholmod(blocks[ref], identity, m, cm);
        if (count(members.front().second) == 0)
          factor->L = cholmod_analyze(A, cm); // the NESDIS order as it is
        else
          {
            // The given order, not postordered: that would move the
            // trailing rows.
            cm->method[0].ordering = CHOLMOD_GIVEN;
            cm->postorder          = 0;
            factor->L = cholmod_analyze_p(A, perm.data(), nullptr, 0, cm);
          }
        if (factor->L != nullptr)
          cholmod_factorize(A, factor->L, cm);
        cholmod_free_sparse(&A, cm);
        AssertThrow(factor->L != nullptr && cm->status == CHOLMOD_OK &&
                      int(factor->L->minor) == m,
                    ExcMessage("the consistent mass block of component " +
                               std::to_string(ref) +
                               " is not positive definite (CHOLMOD status " +
                               std::to_string(cm->status) + ")"));
        AssertThrow(factor->L->is_super && factor->L->is_ll,
                    ExcMessage("CHOLMOD returned no supernodal mass factor"));
        factor->packed.pack(*factor->L, negligible);
        factor->L->x =
          cholmod_free(factor->L->xsize, sizeof(double), factor->L->x, cm);
        factor->L->xsize = 0;

        // Components, in the order of the group.
        const auto *ordering = static_cast<const int *>(factor->L->Perm);
        const int   nc       = members.size();
        factor->n_components = nc;
        factor->gather.assign(std::size_t(m) * nc, numbers::invalid_dof_index);
        factor->leading.resize(nc);
        for (int i = 0; i < nc; ++i)
          {
            const unsigned int       c     = members[i].first;
            const std::vector<bool> &extra = members[i].second;
            factor->leading[i]             = m - count(extra);
            for (int k = 0; k < factor->leading[i]; ++k)
              {
                AssertThrow(!extra[ordering[k]], ExcInternalError());
                factor->gather[std::size_t(k) * nc + i] =
                  component_dofs[c][ordering[k]];
              }
            for (int r = 0; r < m; ++r)
              if (extra[r])
                factor->diagonal_rows.emplace_back(component_dofs[c][r],
                                                   blocks[c].diagonal[r]);
          }
        // At least two groups, so that the bits do not depend on one or
        // two threads or ranks.
        factor->split_tree(
          std::max(2u,
                   MultithreadInfo::n_threads() * n_processes(communicator)));
        factor->distribute_tasks(communicator);
        factor->y.resize(std::size_t(m) * nc);
        // One sum per column of a supernode (backward).
        int max_columns = 0;
        for (std::size_t s = 0; s < factor->L->nsuper; ++s)
          max_columns =
            std::max(max_columns,
                     Supernode(*factor->L, factor->packed, s).n_cols);
        factor->column_sums.assign(factor->n_tasks() + 1,
                                   std::vector<double>(
                                     std::size_t(max_columns) * nc));
        if (factor->n_tasks() > 1)
          factor->separator_updates.assign(factor->n_tasks() *
                                             factor->separator_size(),
                                           0.);
        factors.push_back(std::move(factor));
      }
    setup_seconds = timer.wall_time();
  }

  template <int nc>
  void
  ComponentMassSolver::substitute(const Factor &factor, double *y)
  {
    const cholmod_factor &L       = *factor.L;
    const int             n_super = L.nsuper;
    const unsigned int    n_tasks = factor.n_tasks();
    const int             split   = factor.task_begin[n_tasks];
    // This rank's tasks (all of them on one rank).
    const unsigned int first_task = factor.rank_task_begin[factor.rank];
    const unsigned int end_task   = factor.rank_task_begin[factor.rank + 1];
    const std::size_t  n_shared   = factor.separator_size();
    if (n_tasks > 1)
      {
        Threads::TaskGroup<void> tasks;
        for (unsigned int t = first_task; t < end_task; ++t)
          tasks += Threads::new_task([&factor, &L, y, t, n_shared]() {
            double *updates = factor.separator_updates.data() + t * n_shared;
            std::fill(updates, updates + n_shared, 0.);
            forward<nc>(L,
                        factor.packed,
                        factor.task_begin[t],
                        factor.task_begin[t + 1],
                        y,
                        factor.separator_column,
                        updates);
          });
        tasks.join_all();
        if (factor.n_ranks() > 1)
          all_gather_tasks(factor,
                           factor.separator_updates.data(),
                           [n_shared](const unsigned int t) {
                             return t * n_shared;
                           });
        // Added in the order of the tasks, on every rank alike.
        double *separator = y + std::size_t(factor.separator_column) * nc;
        for (unsigned int t = 0; t < n_tasks; ++t)
          {
            const double *updates =
              factor.separator_updates.data() + t * n_shared;
            for (std::size_t i = 0; i < n_shared; ++i)
              separator[i] += updates[i];
          }
      }
    forward<nc>(L,
                factor.packed,
                n_tasks > 1 ? split : 0,
                n_super,
                y,
                INT_MAX,
                nullptr);
    // A component's rows outside its leading block take no part in its
    // backward substitution.
    for (int c = 0; c < nc; ++c)
      for (std::size_t k = factor.leading[c]; k < L.n; ++k)
        y[k * nc + c] = 0.;
    backward<nc>(L,
                 factor.packed,
                 n_tasks > 1 ? split : 0,
                 n_super,
                 y,
                 factor.column_sums[n_tasks].data());
    if (n_tasks > 1)
      {
        Threads::TaskGroup<void> tasks;
        for (unsigned int t = first_task; t < end_task; ++t)
          tasks += Threads::new_task([&factor, &L, y, t]() {
            backward<nc>(L,
                         factor.packed,
                         factor.task_begin[t],
                         factor.task_begin[t + 1],
                         y,
                         factor.column_sums[t].data());
          });
        tasks.join_all();
        // Every rank's subtrees' values, from the ranks that computed them.
        if (factor.n_ranks() > 1)
          all_gather_tasks(factor, y, [&factor](const unsigned int t) {
            return factor.first_column(t) * nc;
          });
      }
  }

  void
  ComponentMassSolver::solve_with_factor(const Factor         &factor,
                                         Vector<double>       &a,
                                         const Vector<double> &f)
  {
    const std::size_t n_values = factor.gather.size();
    double *const     y        = factor.y.data();
    for (std::size_t k = 0; k < n_values; ++k)
      y[k] = factor.gather[k] == numbers::invalid_dof_index ?
               0. :
               f(factor.gather[k]);
    switch (factor.n_components)
      {
        case 1:
          substitute<1>(factor, y);
          break;
        case 2:
          substitute<2>(factor, y);
          break;
        case 3:
          substitute<3>(factor, y);
          break;
        default:
          AssertThrow(false, ExcNotImplemented());
      }
    for (std::size_t k = 0; k < n_values; ++k)
      if (factor.gather[k] != numbers::invalid_dof_index)
        a(factor.gather[k]) = y[k];
    for (const auto &[dof, diagonal] : factor.diagonal_rows)
      a(dof) = f(dof) / diagonal;
  }

  void
  ComponentMassSolver::solve(Vector<double> &a, const Vector<double> &f) const
  {
    // The factors write disjoint entries of a: one task each (one after
    // the other on several ranks, whose exchanges are not thread-safe).
    if (factors.size() == 1 || n_processes(communicator) > 1)
      {
        for (const auto &factor : factors)
          solve_with_factor(*factor, a, f);
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

  unsigned int
  ComponentMassSolver::n_parallel_subtrees() const
  {
    unsigned int n = 0;
    for (const auto &factor : factors)
      n += factor->n_tasks();
    return n;
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
  ComponentMassSolver::factor_stored_entries() const
  {
    std::size_t entries = 0;
    for (const auto &factor : factors)
      entries += factor->packed.values.size();
    return entries;
  }

  std::size_t
  ComponentMassSolver::memory_consumption() const
  {
    std::size_t bytes = 0;
    for (const auto &factor : factors)
      {
        const cholmod_factor *L = factor->L;
        // Values, supernode patterns and pointers, permutation; gather
        // indices and the work arrays of the solve.
        bytes += factor->packed.values.size() * sizeof(double) +
                 factor->packed.offset.size() * sizeof(std::size_t) +
                 factor->packed.rows.size() * sizeof(int) +
                 factor->packed.row_offset.size() * sizeof(std::size_t) +
                 L->ssize * sizeof(int) +
                 (3 * L->nsuper + 3 + L->n) * sizeof(int) +
                 factor->gather.size() * sizeof(Index) +
                 factor->y.size() * sizeof(double);
        for (const auto &work : factor->column_sums)
          bytes += work.size() * sizeof(double);
        bytes += factor->separator_updates.size() * sizeof(double);
      }
    return bytes;
  }

  double
  ComponentMassSolver::setup_time() const
  {
    return setup_seconds;
  }
} // namespace isoimpact
