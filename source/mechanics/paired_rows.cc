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
    *this               = PairedRows();
    const std::size_t n = matrix.m();
    if (n == 0 || n % 2 != 0 || matrix.n() != n ||
        n / 2 > std::numeric_limits<unsigned int>::max())
      return;

    // The order of vmult: the diagonal first, then ascending columns.
    for (std::size_t row = 0; row < n; ++row)
      {
        auto entry = matrix.begin(row);
        if (entry == matrix.end(row) || entry->column() != row)
          return;
        std::size_t previous = 0;
        bool        first    = true;
        for (++entry; entry != matrix.end(row); ++entry)
          {
            if (!first && entry->column() <= previous)
              return;
            previous = entry->column();
            first    = false;
          }
      }

    const std::size_t n_pairs = n / 2;
    pair_start.reserve(n_pairs + 1);
    pair_start.push_back(0);
    blocks_before_diagonal.resize(n_pairs);
    diagonal_values.resize(4 * n_pairs);
    // First the blocks (the column pairs of the two rows, the diagonal
    // pair apart), then their values.
    std::vector<unsigned int> columns;
    for (std::size_t p = 0; p < n_pairs; ++p)
      {
        columns.clear();
        for (std::size_t row = 2 * p; row < 2 * p + 2; ++row)
          for (auto entry = matrix.begin(row); entry != matrix.end(row);
               ++entry)
            if (entry->column() / 2 != p)
              columns.push_back(entry->column() / 2);
        std::sort(columns.begin(), columns.end());
        columns.erase(std::unique(columns.begin(), columns.end()),
                      columns.end());
        block_column_pair.insert(block_column_pair.end(),
                                 columns.begin(),
                                 columns.end());
        blocks_before_diagonal[p] =
          std::lower_bound(columns.begin(), columns.end(), p) - columns.begin();
        pair_start.push_back(block_column_pair.size());
      }
    block_values.resize(4 * block_column_pair.size(), 0.);
    for (std::size_t p = 0; p < n_pairs; ++p)
      {
        const auto first = block_column_pair.begin() + pair_start[p];
        const auto last  = block_column_pair.begin() + pair_start[p + 1];
        double    *d     = diagonal_values.data() + 4 * p;
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
           block_values.memory_consumption() +
           diagonal_values.memory_consumption();
  }
} // namespace isoimpact
