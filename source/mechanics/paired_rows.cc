// Layer 4: the stiffness rows in pairs of unknowns.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/parallel.h>

#include <isoimpact/mechanics/paired_rows.h>

#include <algorithm>
#include <limits>

using namespace dealii;

namespace isoimpact
{
  void
  PairedRows::build(const SparseMatrix<double> &matrix)
  {
    build(std::vector<const SparseMatrix<double> *>{&matrix});
  }

  void
  PairedRows::build(const std::vector<const SparseMatrix<double> *> &matrices)
  {
    *this = PairedRows();
    if (matrices.empty())
      return;
    const std::size_t n = matrices[0]->m();
    if (n == 0 || n % 2 != 0 ||
        n / 2 > std::numeric_limits<unsigned int>::max())
      return;
    for (const auto *matrix : matrices)
      if (matrix->m() != n || matrix->n() != n)
        return;

    // The order of vmult: the diagonal first, then ascending columns.
    for (const auto *matrix : matrices)
      for (std::size_t row = 0; row < n; ++row)
        {
          auto entry = matrix->begin(row);
          if (entry == matrix->end(row) || entry->column() != row)
            return;
          std::size_t previous = 0;
          bool        first    = true;
          for (++entry; entry != matrix->end(row); ++entry)
            {
              if (!first && entry->column() <= previous)
                return;
              previous = entry->column();
              first    = false;
            }
        }

    const std::size_t n_pairs = n / 2;
    // The matrix that stores a row (more than its diagonal, or a diagonal
    // that is not zero), or nullptr.
    const auto stored_in =
      [&](const std::size_t row) -> const SparseMatrix<double> * {
      for (const auto *matrix : matrices)
        if (matrix->get_row_length(row) > 1 || matrix->diag_element(row) != 0.)
          return matrix;
      return nullptr;
    };
    // A pair's rows from the matrix that stores the first of them (the
    // other one's if not); both rows must come from one matrix.
    const auto source_of =
      [&](const std::size_t p) -> const SparseMatrix<double> * {
      const auto *matrix = stored_in(2 * p);
      return matrix ? matrix : stored_in(2 * p + 1);
    };
    if (matrices.size() > 1)
      for (std::size_t p = 0; p < n_pairs; ++p)
        {
          const auto *first = stored_in(2 * p), *second = stored_in(2 * p + 1);
          if (first && second && first != second)
            return;
        }
    // First the blocks (the diagonal pair's, then the other column pairs
    // of the two rows), counted and then filled, so that every array has
    // its exact size; then their values.
    std::vector<unsigned int> columns;
    const auto                pair_columns = [&](const std::size_t p) {
      columns.clear();
      const auto *matrix = source_of(p);
      if (!matrix)
        return false;
      for (std::size_t row = 2 * p; row < 2 * p + 2; ++row)
        for (auto entry = matrix->begin(row); entry != matrix->end(row);
             ++entry)
          if (entry->column() / 2 != p)
            columns.push_back(entry->column() / 2);
      std::sort(columns.begin(), columns.end());
      columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
      return true;
    };
    std::size_t n_blocks = 0;
    for (std::size_t p = 0; p < n_pairs; ++p)
      if (pair_columns(p))
        n_blocks += 1 + columns.size();
    pair_start.reserve(n_pairs + 1);
    pair_start.push_back(0);
    blocks_before_diagonal.resize(n_pairs);
    block_column_pair.reserve(n_blocks);
    for (std::size_t p = 0; p < n_pairs; ++p)
      {
        if (pair_columns(p))
          {
            block_column_pair.push_back(p);
            block_column_pair.insert(block_column_pair.end(),
                                     columns.begin(),
                                     columns.end());
            blocks_before_diagonal[p] =
              std::lower_bound(columns.begin(), columns.end(), p) -
              columns.begin();
          }
        pair_start.push_back(block_column_pair.size());
        some_rows_not_stored |= pair_start[p + 1] == pair_start[p];
      }
    block_values.resize(4 * block_column_pair.size(), 0.);
    for (std::size_t p = 0; p < n_pairs; ++p)
      {
        if (pair_start[p + 1] == pair_start[p])
          continue;
        const auto  first  = block_column_pair.begin() + pair_start[p] + 1;
        const auto  last   = block_column_pair.begin() + pair_start[p + 1];
        double     *d      = block_values.data() + 4 * pair_start[p];
        const auto &matrix = *source_of(p);
        for (unsigned int lane = 0; lane < 2; ++lane)
          {
            const std::size_t row = 2 * p + lane;
            for (auto entry = matrix.begin(row); entry != matrix.end(row);
                 ++entry)
              {
                const std::size_t column = entry->column();
                if (column == row)
                  d[lane] = entry->value();
                else if (column / 2 == p)
                  d[2 + lane] = entry->value();
                else
                  {
                    const std::size_t block =
                      std::lower_bound(first, last, column / 2) -
                      block_column_pair.begin();
                    block_values[4 * block + 2 * (column % 2) + lane] =
                      entry->value();
                  }
              }
          }
      }
  }

  void
  PairedRows::vmult(Vector<double> &y, const Vector<double> &u) const
  {
    AssertDimension(u.size(), 2 * n_pairs());
    AssertDimension(y.size(), 2 * n_pairs());
    const double *in  = u.data();
    double       *out = y.data();
    parallel::apply_to_subranges(
      std::size_t(0),
      n_pairs(),
      [this, in, out](const std::size_t begin, const std::size_t end) {
        for (std::size_t p = begin; p < end; ++p)
          if (some_rows_not_stored && pair_start[p + 1] == pair_start[p])
            out[2 * p] = out[2 * p + 1] = 0.; // rows not stored
          else
#ifdef __SSE2__
            _mm_storeu_pd(out + 2 * p, packed_products(p, in));
#else
            products(p, in, out[2 * p], out[2 * p + 1]);
#endif
      },
      1024);
  }

  std::size_t
  PairedRows::memory_consumption() const
  {
    return pair_start.capacity() * sizeof(std::size_t) +
           blocks_before_diagonal.capacity() * sizeof(unsigned int) +
           block_column_pair.capacity() * sizeof(unsigned int) +
           block_values.memory_consumption();
  }
} // namespace isoimpact
