// Open knot vectors: validation, B-spline basis, Bezier extraction, knot
// insertion and degree elevation.
#include <isoimpact/nurbs/knot_vector.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>

using namespace dealii;

namespace isoimpact
{
  namespace nurbs
  {
    std::string
    to_string(const double value)
    {
      // Shortest text that reads back as the same value.
      std::string text;
      for (int digits = 1; digits <= 17; ++digits)
        {
          std::ostringstream s;
          s.precision(digits);
          s << value;
          text = s.str();
          if (!std::isfinite(value) || std::stod(text) == value)
            break;
        }
      return text;
    }

    namespace
    {
      double
      binomial(const unsigned int n, const unsigned int k)
      {
        double result = 1.;
        for (unsigned int i = 1; i <= k; ++i)
          result = result * (n - k + i) / i;
        return result;
      }

      // A refinement of `old` with its matrix T: `transform(coefficients,
      // n_components)` (a coefficient version of the refinement) applied to
      // the identity, whose columns then hold T.
      template <typename CoefficientTransform>
      KnotVector::Refinement
      refinement_with_matrix(const KnotVector           &old,
                             const CoefficientTransform &transform)
      {
        const unsigned int  n_old = old.n_basis_functions();
        std::vector<double> identity(n_old * n_old, 0.);
        for (unsigned int i = 0; i < n_old; ++i)
          identity[i * n_old + i] = 1.;
        KnotVector::Refinement result;
        result.knot_vector       = transform(identity, n_old);
        const unsigned int n_new = result.knot_vector.n_basis_functions();
        result.matrix.reinit(n_new, n_old);
        for (unsigned int j = 0; j < n_new; ++j)
          for (unsigned int i = 0; i < n_old; ++i)
            result.matrix(j, i) = identity[j * n_old + i];
        return result;
      }
    } // namespace

    KnotVector::KnotVector(const std::vector<double> &knots,
                           const unsigned int         degree)
      : knot_values(knots)
      , p(degree)
    {
      AssertThrow(degree >= 1,
                  dealii::ExcMessage(
                    "knot vector: degree " + std::to_string(degree) +
                    " is not allowed; the degree must be at least 1"));
      AssertThrow(degree <= max_degree,
                  dealii::ExcMessage("knot vector: degree " +
                                     std::to_string(degree) +
                                     " is not supported; the degree must be "
                                     "at most " +
                                     std::to_string(max_degree)));
      const unsigned int m = knots.size();
      AssertThrow(m >= 2 * (p + 1),
                  dealii::ExcMessage(
                    "knot vector: " + std::to_string(m) +
                    " knots given for degree " + std::to_string(p) +
                    "; an open knot vector needs at least 2*(degree+1) = " +
                    std::to_string(2 * (p + 1)) + " knots"));
      for (unsigned int i = 0; i < m; ++i)
        AssertThrow(std::isfinite(knots[i]),
                    dealii::ExcMessage("knot vector: knot " +
                                       std::to_string(i) + " (value " +
                                       to_string(knots[i]) +
                                       ") is not finite; knots must be finite "
                                       "numbers"));
      for (unsigned int i = 1; i < m; ++i)
        AssertThrow(knots[i] >= knots[i - 1],
                    dealii::ExcMessage(
                      "knot vector: knot " + std::to_string(i) + " (value " +
                      to_string(knots[i]) + ") is smaller than knot " +
                      std::to_string(i - 1) + " (value " +
                      to_string(knots[i - 1]) +
                      "); knots must be non-decreasing"));
      AssertThrow(knots.front() < knots.back(),
                  dealii::ExcMessage(
                    "knot vector: first and last knot are both " +
                    to_string(knots.front()) +
                    "; at least one non-empty knot span (first knot < last "
                    "knot) is needed"));

      // Multiplicities of the distinct values.
      unsigned int i = 0;
      while (i < m)
        {
          unsigned int j = i;
          while (j + 1 < m && knots[j + 1] == knots[i])
            ++j;
          const unsigned int multiplicity = j - i + 1;
          const bool         at_end       = (i == 0 || j == m - 1);
          AssertThrow(!at_end || multiplicity == p + 1,
                      dealii::ExcMessage(
                        std::string("knot vector: the ") +
                        (i == 0 ? "first" : "last") + " knot value " +
                        to_string(knots[i]) + " has multiplicity " +
                        std::to_string(multiplicity) +
                        "; an open knot vector of degree " + std::to_string(p) +
                        " needs the first and last value repeated exactly " +
                        std::to_string(p + 1) + " (degree+1) times"));
          AssertThrow(at_end || multiplicity <= p,
                      dealii::ExcMessage(
                        "knot vector: interior knot value " +
                        to_string(knots[i]) + " has multiplicity " +
                        std::to_string(multiplicity) +
                        "; interior knots may be repeated at most degree = " +
                        std::to_string(p) + " times"));
          if (j + 1 < m)
            span_knot_index.push_back(j);
          i = j + 1;
        }
    }



    KnotVector
    KnotVector::uniform(const unsigned int degree,
                        const unsigned int n_spans,
                        const double       start,
                        const double       end)
    {
      AssertThrow(n_spans >= 1,
                  dealii::ExcMessage(
                    "uniform knot vector: " + std::to_string(n_spans) +
                    " spans requested; at least 1 is needed"));
      std::vector<double> knots(degree + 1, start);
      for (unsigned int i = 1; i < n_spans; ++i)
        knots.push_back(start + (end - start) * i / n_spans);
      knots.insert(knots.end(), degree + 1, end);
      return KnotVector(knots, degree);
    }



    double
    KnotVector::tolerance() const
    {
      return 1e-12 * (knot_values.back() - knot_values.front());
    }



    std::vector<double>
    KnotVector::breakpoints() const
    {
      std::vector<double> result;
      for (const unsigned int k : span_knot_index)
        result.push_back(knot_values[k]);
      if (!span_knot_index.empty())
        result.push_back(knot_values[span_knot_index.back() + 1]);
      return result;
    }



    std::pair<double, double>
    KnotVector::span_interval(const unsigned int span) const
    {
      AssertThrow(span < n_spans(),
                  dealii::ExcMessage("knot vector: span " +
                                     std::to_string(span) +
                                     " does not exist; spans are 0 to " +
                                     std::to_string(n_spans()) + "-1"));
      const unsigned int k = span_knot_index[span];
      return {knot_values[k], knot_values[k + 1]};
    }



    unsigned int
    KnotVector::knot_index_of_span(const unsigned int span) const
    {
      AssertThrow(span < n_spans(),
                  dealii::ExcMessage("knot vector: span " +
                                     std::to_string(span) +
                                     " does not exist; spans are 0 to " +
                                     std::to_string(n_spans()) + "-1"));
      return span_knot_index[span];
    }



    unsigned int
    KnotVector::span_of(const double u) const
    {
      AssertThrow(u >= front() - tolerance() && u <= back() + tolerance(),
                  dealii::ExcMessage("knot vector: parameter " + to_string(u) +
                                     " lies outside the parameter interval [" +
                                     to_string(front()) + ", " +
                                     to_string(back()) + "]"));
      // The first span whose right end exceeds u, else the last span.
      const auto it =
        std::upper_bound(span_knot_index.begin(),
                         span_knot_index.end(),
                         u,
                         [this](const double v, const unsigned int k) {
                           return v < knot_values[k + 1];
                         });
      if (it == span_knot_index.end())
        return n_spans() - 1;
      return it - span_knot_index.begin();
    }



    unsigned int
    KnotVector::multiplicity(const double u) const
    {
      unsigned int count = 0;
      for (const double t : knot_values)
        if (std::abs(t - u) <= tolerance())
          ++count;
      return count;
    }



    void
    KnotVector::basis_values(const unsigned int span,
                             const double       u,
                             double            *values) const
    {
      const unsigned int                 k = span_knot_index[span];
      std::array<double, max_degree + 1> left, right;
      values[0] = 1.;
      for (unsigned int j = 1; j <= p; ++j)
        {
          left[j]      = u - knot_values[k + 1 - j];
          right[j]     = knot_values[k + j] - u;
          double saved = 0.;
          for (unsigned int r = 0; r < j; ++r)
            {
              const double temp = values[r] / (right[r + 1] + left[j - r]);
              values[r]         = saved + right[r + 1] * temp;
              saved             = left[j - r] * temp;
            }
          values[j] = saved;
        }
    }



    void
    KnotVector::basis_values(const unsigned int   span,
                             const double         u,
                             std::vector<double> &values) const
    {
      AssertThrow(span < n_spans(),
                  dealii::ExcMessage("knot vector: span " +
                                     std::to_string(span) +
                                     " does not exist; spans are 0 to " +
                                     std::to_string(n_spans()) + "-1"));
      values.resize(p + 1);
      basis_values(span, u, values.data());
    }



    void
    KnotVector::basis_derivatives(const unsigned int span,
                                  const double       u,
                                  const unsigned int n,
                                  double            *ders) const
    {
      constexpr unsigned int               P = max_degree + 1;
      const unsigned int                   k = span_knot_index[span];
      std::array<std::array<double, P>, P> ndu;
      std::array<std::array<double, P>, 2> a;
      std::array<double, P>                left, right;
      const unsigned int                   n_functions = p + 1;

      // ndu(j, r): basis values (upper triangle incl. diagonal) and knot
      // differences (lower triangle).
      ndu[0][0] = 1.;
      for (unsigned int j = 1; j <= p; ++j)
        {
          left[j]      = u - knot_values[k + 1 - j];
          right[j]     = knot_values[k + j] - u;
          double saved = 0.;
          for (unsigned int r = 0; r < j; ++r)
            {
              ndu[j][r]         = right[r + 1] + left[j - r];
              const double temp = ndu[r][j - 1] / ndu[j][r];
              ndu[r][j]         = saved + right[r + 1] * temp;
              saved             = left[j - r] * temp;
            }
          ndu[j][j] = saved;
        }
      for (unsigned int j = 0; j <= p; ++j)
        ders[j] = ndu[j][p];

      const unsigned int n_computed = std::min(n, p);
      for (unsigned int r = 0; r <= p; ++r)
        {
          unsigned int s1 = 0, s2 = 1;
          a[0][0] = 1.;
          for (unsigned int order = 1; order <= n_computed; ++order)
            {
              double    d  = 0.;
              const int rk = static_cast<int>(r) - static_cast<int>(order);
              const int pk = static_cast<int>(p) - static_cast<int>(order);
              if (r >= order)
                {
                  a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                  d        = a[s2][0] * ndu[rk][pk];
                }
              const int j1 = (rk >= -1) ? 1 : -rk;
              const int j2 = (static_cast<int>(r) - 1 <= pk) ?
                               static_cast<int>(order) - 1 :
                               static_cast<int>(p) - static_cast<int>(r);
              for (int j = j1; j <= j2; ++j)
                {
                  a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
                  d += a[s2][j] * ndu[rk + j][pk];
                }
              if (static_cast<int>(r) <= pk)
                {
                  a[s2][order] = -a[s1][order - 1] / ndu[pk + 1][r];
                  d += a[s2][order] * ndu[r][pk];
                }
              ders[order * n_functions + r] = d;
              std::swap(s1, s2);
            }
        }
      // Multiply by p!/(p-k)!.
      double factor = p;
      for (unsigned int order = 1; order <= n_computed; ++order)
        {
          for (unsigned int j = 0; j <= p; ++j)
            ders[order * n_functions + j] *= factor;
          factor *= (p - order);
        }
      for (unsigned int order = n_computed + 1; order <= n; ++order)
        for (unsigned int j = 0; j <= p; ++j)
          ders[order * n_functions + j] = 0.;
    }



    void
    KnotVector::basis_derivatives(const unsigned int          span,
                                  const double                u,
                                  const unsigned int          n,
                                  dealii::FullMatrix<double> &ders) const
    {
      AssertThrow(span < n_spans(),
                  dealii::ExcMessage("knot vector: span " +
                                     std::to_string(span) +
                                     " does not exist; spans are 0 to " +
                                     std::to_string(n_spans()) + "-1"));
      std::vector<double> buffer((n + 1) * (p + 1));
      basis_derivatives(span, u, n, buffer.data());
      ders.reinit(n + 1, p + 1);
      for (unsigned int k = 0; k <= n; ++k)
        for (unsigned int i = 0; i <= p; ++i)
          ders(k, i) = buffer[k * (p + 1) + i];
    }



    void
    KnotVector::bernstein_values(const unsigned int p,
                                 const double       t,
                                 double            *values,
                                 double            *derivatives)
    {
      // de Casteljau-like recursion B^j_i = (1-t) B^{j-1}_i + t B^{j-1}_{i-1}.
      const auto raise_degree = [values, t](const unsigned int j) {
        double saved = 0.;
        for (unsigned int i = 0; i < j; ++i)
          {
            const double temp = values[i];
            values[i]         = saved + (1. - t) * temp;
            saved             = t * temp;
          }
        values[j] = saved;
      };
      values[0] = 1.;
      for (unsigned int j = 1; j < p; ++j)
        raise_degree(j);
      // dB^p_i/dt = p (B^{p-1}_{i-1} - B^{p-1}_i), from degree p-1.
      if (derivatives != nullptr)
        for (unsigned int i = 0; i <= p; ++i)
          derivatives[i] =
            p * ((i > 0 ? values[i - 1] : 0.) - (i < p ? values[i] : 0.));
      if (p > 0)
        raise_degree(p);
    }



    std::vector<dealii::FullMatrix<double>>
    KnotVector::extraction_operators() const
    {
      // Borden et al. 2011, Algorithm 1, with 1-based knot access U(i).
      const auto U = [this](const unsigned int i) {
        return knot_values[i - 1];
      };
      const unsigned int                      m = n_knots();
      std::vector<dealii::FullMatrix<double>> C;
      C.reserve(n_spans() + 1);
      const auto identity = [this]() {
        dealii::FullMatrix<double> I(p + 1, p + 1);
        for (unsigned int i = 0; i <= p; ++i)
          I(i, i) = 1.;
        return I;
      };
      C.push_back(identity());
      std::vector<double> alphas(p + 1);
      unsigned int        a  = p + 1;
      unsigned int        b  = a + 1;
      unsigned int        nb = 0; // 0-based index of the current operator
      while (b < m)
        {
          C.push_back(identity());
          const unsigned int i = b;
          while (b < m && U(b + 1) == U(b))
            ++b;
          const unsigned int mult = b - i + 1;
          if (mult < p)
            {
              const double numer = U(b) - U(a);
              for (unsigned int j = p; j >= mult + 1; --j)
                alphas[j - mult - 1] = numer / (U(a + j) - U(a));
              const unsigned int r = p - mult;
              for (unsigned int j = 1; j <= r; ++j)
                {
                  const unsigned int save = r - j + 1;
                  const unsigned int s    = mult + j;
                  for (unsigned int k = p + 1; k >= s + 1; --k)
                    {
                      const double alpha = alphas[k - s - 1];
                      for (unsigned int row = 0; row <= p; ++row)
                        C[nb](row, k - 1) = alpha * C[nb](row, k - 1) +
                                            (1. - alpha) * C[nb](row, k - 2);
                    }
                  if (b < m)
                    for (unsigned int l = 0; l <= j; ++l)
                      C[nb + 1](save - 1 + l, save - 1) = C[nb](p - j + l, p);
                }
            }
          ++nb;
          if (b < m)
            {
              a = b;
              ++b;
            }
        }
      C.resize(n_spans());
      return C;
    }



    KnotVector
    KnotVector::insert_knots(const std::vector<double> &new_knots_in,
                             std::vector<double>       &coefficients,
                             const unsigned int         n_components) const
    {
      const unsigned int n_old = n_basis_functions();
      AssertThrow(coefficients.size() == n_old * n_components,
                  dealii::ExcMessage(
                    "knot insertion: " + std::to_string(coefficients.size()) +
                    " coefficient values given; expected n_basis_functions * "
                    "n_components = " +
                    std::to_string(n_old * n_components)));
      if (new_knots_in.empty())
        return *this;
      std::vector<double> X(new_knots_in);
      std::sort(X.begin(), X.end());
      for (const double x : X)
        {
          AssertThrow(x > front() && x < back(),
                      dealii::ExcMessage(
                        "knot insertion: value " + to_string(x) +
                        " is not strictly inside the parameter interval (" +
                        to_string(front()) + ", " + to_string(back()) + ")"));
          const unsigned int new_multiplicity =
            std::count(knot_values.begin(), knot_values.end(), x) +
            std::count(X.begin(), X.end(), x);
          AssertThrow(new_multiplicity <= p,
                      dealii::ExcMessage(
                        "knot insertion: value " + to_string(x) +
                        " would get multiplicity " +
                        std::to_string(new_multiplicity) +
                        "; interior knots may be repeated at most degree = " +
                        std::to_string(p) + " times"));
        }

      // The NURBS Book A5.4 with rows of n_components values.
      const std::vector<double> &Uk = knot_values;
      const unsigned int         n  = n_old - 1; // last control point index
      const unsigned int         mm = n + p + 1; // last knot index
      const unsigned int         r  = X.size() - 1;
      // Largest i with U[i] <= u < U[i+1] (u interior).
      const auto find_knot_span = [&](const double u) {
        return static_cast<unsigned int>(
                 std::upper_bound(Uk.begin(), Uk.end(), u) - Uk.begin()) -
               1;
      };
      const unsigned int  a = find_knot_span(X.front());
      const unsigned int  b = find_knot_span(X.back()) + 1;
      std::vector<double> Ubar(mm + r + 2);
      std::vector<double> Q((n_old + r + 1) * n_components);
      const auto          P_row = [&](const unsigned int i) {
        return coefficients.data() + i * n_components;
      };
      const auto Q_row = [&](const unsigned int i) {
        return Q.data() + i * n_components;
      };
      const auto copy_row = [&](const double *from, double *to) {
        std::copy(from, from + n_components, to);
      };
      for (unsigned int j = 0; j <= a - p; ++j)
        copy_row(P_row(j), Q_row(j));
      for (unsigned int j = b - 1; j <= n; ++j)
        copy_row(P_row(j), Q_row(j + r + 1));
      for (unsigned int j = 0; j <= a; ++j)
        Ubar[j] = Uk[j];
      for (unsigned int j = b + p; j <= mm; ++j)
        Ubar[j + r + 1] = Uk[j];
      int i = b + p - 1;
      int k = b + p + r;
      for (int j = r; j >= 0; --j)
        {
          while (X[j] <= Uk[i] && i > static_cast<int>(a))
            {
              copy_row(P_row(i - p - 1), Q_row(k - p - 1));
              Ubar[k] = Uk[i];
              --k;
              --i;
            }
          copy_row(Q_row(k - p), Q_row(k - p - 1));
          for (unsigned int l = 1; l <= p; ++l)
            {
              const int ind   = k - p + l;
              double    alpha = Ubar[k + l] - X[j];
              double   *q0    = Q_row(ind - 1);
              double   *q1    = Q_row(ind);
              if (alpha == 0.)
                copy_row(q1, q0);
              else
                {
                  alpha /= (Ubar[k + l] - Uk[i - p + l]);
                  for (unsigned int c = 0; c < n_components; ++c)
                    q0[c] = alpha * q0[c] + (1. - alpha) * q1[c];
                }
            }
          Ubar[k] = X[j];
          --k;
        }
      coefficients.swap(Q);
      return KnotVector(Ubar, p);
    }



    KnotVector::Refinement
    KnotVector::insert_knots(const std::vector<double> &new_knots) const
    {
      const auto transform = [&](auto &coefficients, auto n_components) {
        return insert_knots(new_knots, coefficients, n_components);
      };
      return refinement_with_matrix(*this, transform);
    }



    KnotVector::Refinement
    KnotVector::insert_knot(const double u, const unsigned int times) const
    {
      return insert_knots(std::vector<double>(times, u));
    }



    KnotVector
    KnotVector::elevated_knot_vector(const unsigned int times) const
    {
      std::vector<double> knots;
      for (unsigned int i = 0; i < knot_values.size(); ++i)
        {
          knots.push_back(knot_values[i]);
          if (i + 1 == knot_values.size() ||
              knot_values[i + 1] != knot_values[i])
            knots.insert(knots.end(), times, knot_values[i]);
        }
      return KnotVector(knots, p + times);
    }



    KnotVector
    KnotVector::elevate_degree(const unsigned int   times,
                               std::vector<double> &coefficients,
                               const unsigned int   n_components) const
    {
      const unsigned int n_old = n_basis_functions();
      AssertThrow(coefficients.size() == n_old * n_components,
                  dealii::ExcMessage(
                    "degree elevation: " + std::to_string(coefficients.size()) +
                    " coefficient values given; expected n_basis_functions * "
                    "n_components = " +
                    std::to_string(n_old * n_components)));
      if (times == 0)
        return *this;
      const KnotVector   elevated = elevated_knot_vector(times);
      const unsigned int q        = p + times;
      const unsigned int n_new    = elevated.n_basis_functions();

      // Bernstein degree elevation B^p_i = sum_k D(i,k) B^q_k.
      dealii::FullMatrix<double> D(p + 1, q + 1);
      for (unsigned int i = 0; i <= p; ++i)
        for (unsigned int k = i; k <= i + times; ++k)
          D(i, k) = binomial(p, i) * binomial(times, k - i) / binomial(q, k);

      const auto C_old = extraction_operators();
      const auto C_new = elevated.extraction_operators();

      std::vector<double> Q(n_new * n_components, 0.);
      std::vector<bool>   done(n_new, false);
      for (unsigned int e = 0; e < n_spans(); ++e)
        {
          // M = C_old D C_new^{-1}: N_old_loc = M N_new_loc.
          dealii::FullMatrix<double> C_new_inverse(q + 1, q + 1);
          C_new_inverse.invert(C_new[e]);
          dealii::FullMatrix<double> CD(p + 1, q + 1), M(p + 1, q + 1);
          C_old[e].mmult(CD, D);
          CD.mmult(M, C_new_inverse);
          const unsigned int first_old = first_basis_function(e);
          const unsigned int first_new = elevated.first_basis_function(e);
          for (unsigned int jl = 0; jl <= q; ++jl)
            {
              const unsigned int j = first_new + jl;
              if (done[j])
                continue;
              done[j]   = true;
              double *q = Q.data() + j * n_components;
              for (unsigned int il = 0; il <= p; ++il)
                {
                  const double  t = M(il, jl);
                  const double *c =
                    coefficients.data() + (first_old + il) * n_components;
                  for (unsigned int comp = 0; comp < n_components; ++comp)
                    q[comp] += t * c[comp];
                }
            }
        }
      coefficients.swap(Q);
      return elevated;
    }



    KnotVector::Refinement
    KnotVector::elevate_degree(const unsigned int times) const
    {
      const auto transform = [&](auto &coefficients, auto n_components) {
        return elevate_degree(times, coefficients, n_components);
      };
      return refinement_with_matrix(*this, transform);
    }
  } // namespace nurbs
} // namespace isoimpact
