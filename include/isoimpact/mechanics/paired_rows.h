// Layer 4: the rows of a vector-valued stiffness in pairs of unknowns (2 x 2
// blocks), for the lumped step's product K u with the bits of deal.II's
// SparseMatrix::vmult.
#ifndef isoimpact_mechanics_paired_rows_h
#define isoimpact_mechanics_paired_rows_h

#include <deal.II/base/aligned_vector.h>

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <cstddef>
#include <vector>

#ifdef __SSE2__
#  include <emmintrin.h>
#endif

namespace isoimpact
{
  /**
   * The rows 2p and 2p + 1 of a square sparse matrix side by side, in 2 x 2
   * blocks over the column pairs (2j, 2j + 1): one column number per four
   * entries instead of one per entry, and each column pair of u read once
   * for both rows. An entry absent from the matrix is stored as a zero.
   *
   * products() sums each of the two rows in the order of deal.II's
   * SparseMatrix::vmult (the diagonal first, then the other columns in
   * ascending order, starting from 0), one addition per stored entry. With
   * IEEE arithmetic without fused multiply-add (x86-64's SSE2, both lanes
   * alike), adding a product 0 * u_j (u_j finite) leaves a sum that started
   * from +0 unchanged in every bit, so the padded zeros do not change the
   * results: K u has the bits of vmult.
   *
   * Built only where it applies: an even number of rows, each row's
   * columns after the diagonal ascending (deal.II's square patterns).
   * A pair whose rows hold only a zero diagonal (rows another MPI rank
   * computes) takes no space; its products are zero.
   */
  class PairedRows
  {
  public:
    // The pairs of `matrix` (empty() if the matrix does not qualify).
    void
    build(const dealii::SparseMatrix<double> &matrix);
    // The same for matrices of one size whose stored rows do not overlap
    // (each row from the first matrix that stores it): the rows of a rank
    // kept apart from those only its pass reads. A pair's two rows must
    // come from one matrix (else empty()).
    void
    build(const std::vector<const dealii::SparseMatrix<double> *> &matrices);

    bool
    empty() const
    {
      return pair_start.empty();
    }

    std::size_t
    n_pairs() const
    {
      return pair_start.empty() ? 0 : pair_start.size() - 1;
    }

    // The stored entries (4 per block, zeros included) against the
    // matrix's own entries.
    std::size_t
    n_stored_entries() const
    {
      return block_values.size();
    }

    // f(column, value) for every stored entry of row i (its pair stored),
    // in the order of the matrix's row: the diagonal first, then the other
    // columns ascending (padded zeros included).
    template <typename Function>
    void
    for_each_entry(const std::size_t i, const Function &f) const;
    // (K u)_{2p} and (K u)_{2p+1}, for a pair whose rows are stored.
    inline void
    products(const std::size_t p,
             const double     *u,
             double           &first,
             double           &second) const;

#ifdef __SSE2__
    // The same in the two lanes of an SSE2 register (lane 0 row 2p).
    inline __m128d
    packed_products(const std::size_t p, const double *u) const;
#endif

    // y = K u, every pair (u and y of the matrix's size, not aliased): the
    // bits of SparseMatrix::vmult, the pairs split into ranges over the
    // threads.
    void
    vmult(dealii::Vector<double> &y, const dealii::Vector<double> &u) const;

    std::size_t
    memory_consumption() const;

  private:
    // Where pair p's entries are: its off-diagonal blocks from begin to
    // end, those below the diagonal before middle; the arrays; its
    // diagonal block.
    struct Pair
    {
      std::size_t         begin, middle, end;
      const unsigned int *column_pairs;
      const double       *values;
      const double       *diagonal;
    };
    Pair
    pair(const std::size_t p) const
    {
      return {pair_start[p] + 1,
              pair_start[p] + 1 + blocks_before_diagonal[p],
              pair_start[p + 1],
              block_column_pair.data(),
              block_values.data(),
              block_values.data() + 4 * pair_start[p]};
    }

    // Pair p's blocks: pair_start[p] to pair_start[p + 1] (none if its rows
    // are not stored). The first is the diagonal block, a(2p, 2p),
    // a(2p + 1, 2p + 1), a(2p, 2p + 1), a(2p + 1, 2p); then the blocks of
    // columns below 2p, blocks_before_diagonal[p] of them, then the others.
    std::vector<std::size_t>  pair_start;
    std::vector<unsigned int> blocks_before_diagonal;
    // Column pair j of each block (its columns are 2j and 2j + 1; p for the
    // diagonal block).
    std::vector<unsigned int> block_column_pair;
    // Per off-diagonal block, column by column: a(2p, 2j), a(2p + 1, 2j),
    // a(2p, 2j + 1), a(2p + 1, 2j + 1).
    dealii::AlignedVector<double> block_values;
    // Whether some pair's rows are not stored (vmult() then tests each).
    bool some_rows_not_stored = false;
  };


#ifdef __SSE2__
  inline __m128d
  PairedRows::packed_products(const std::size_t p, const double *u) const
  {
    const auto [begin, middle, end, pairs, values, d] = pair(p);
    const __m128d own                                 = _mm_loadu_pd(u + 2 * p);
    __m128d sum = _mm_add_pd(_mm_setzero_pd(), _mm_mul_pd(_mm_load_pd(d), own));
    const auto add_blocks = [&](const std::size_t from, const std::size_t to) {
      for (std::size_t b = from; b < to; ++b)
        {
          const __m128d column_pair =
            _mm_loadu_pd(u + 2 * std::size_t(pairs[b]));
          sum =
            _mm_add_pd(sum,
                       _mm_mul_pd(_mm_load_pd(values + 4 * b),
                                  _mm_unpacklo_pd(column_pair, column_pair)));
          sum =
            _mm_add_pd(sum,
                       _mm_mul_pd(_mm_load_pd(values + 4 * b + 2),
                                  _mm_unpackhi_pd(column_pair, column_pair)));
        }
    };
    add_blocks(begin, middle);
    sum =
      _mm_add_pd(sum,
                 _mm_mul_pd(_mm_load_pd(d + 2), _mm_shuffle_pd(own, own, 1)));
    add_blocks(middle, end);
    return sum;
  }
#endif


  template <typename Function>
  void
  PairedRows::for_each_entry(const std::size_t i, const Function &f) const
  {
    const std::size_t p = i / 2, r = i % 2;
    const auto [begin, middle, end, pairs, values, d] = pair(p);
    f(i, d[r]);
    const auto blocks = [&](const std::size_t from, const std::size_t to) {
      for (std::size_t b = from; b < to; ++b)
        {
          const std::size_t column = 2 * std::size_t(pairs[b]);
          f(column, values[4 * b + r]);
          f(column + 1, values[4 * b + 2 + r]);
        }
    };
    blocks(begin, middle);
    f(r == 0 ? i + 1 : i - 1, d[2 + r]);
    blocks(middle, end);
  }

  inline void
  PairedRows::products(const std::size_t p,
                       const double     *u,
                       double           &first,
                       double           &second) const
  {
#ifdef __SSE2__
    const __m128d sum = packed_products(p, u);
    first             = _mm_cvtsd_f64(sum);
    second            = _mm_cvtsd_f64(_mm_unpackhi_pd(sum, sum));
#else
    const auto [begin, middle, end, pairs, values, d] = pair(p);
    double     sum0                                   = 0. + d[0] * u[2 * p];
    double     sum1       = 0. + d[1] * u[2 * p + 1];
    const auto add_blocks = [&](const std::size_t from, const std::size_t to) {
      for (std::size_t b = from; b < to; ++b)
        {
          const double *column = u + 2 * std::size_t(pairs[b]);
          sum0 += values[4 * b] * column[0];
          sum1 += values[4 * b + 1] * column[0];
          sum0 += values[4 * b + 2] * column[1];
          sum1 += values[4 * b + 3] * column[1];
        }
    };
    add_blocks(begin, middle);
    sum0 += d[2] * u[2 * p + 1];
    sum1 += d[3] * u[2 * p];
    add_blocks(middle, end);
    first  = sum0;
    second = sum1;
#endif
  }
} // namespace isoimpact

#endif
