// Open knot vectors and the B-spline basis they define (layer 1: geometry).
#ifndef isoimpact_nurbs_knot_vector_h
#define isoimpact_nurbs_knot_vector_h

#include <deal.II/base/exceptions.h>

#include <deal.II/lac/full_matrix.h>

#include <string>
#include <utility>
#include <vector>

namespace isoimpact
{
  namespace nurbs
  {
    // Shortest text that reads back as the same value (error messages).
    std::string
    to_string(const double value);

    /**
     * An open knot vector U = {u_0, ..., u_{m-1}} of degree p and the
     * B-spline basis N_0, ..., N_{n-1} (n = m - p - 1) it defines.
     *
     * Rules checked by the constructor (violations throw dealii::ExcMessage
     * naming the offending value): 1 <= p <= max_degree; finite,
     * non-decreasing knots; first and last knot values each repeated exactly
     * p+1 times; interior knot values repeated at most p times; first knot <
     * last knot (at least one non-empty span).
     *
     * "Spans" are the non-empty intervals [u_k, u_{k+1}), numbered 0, 1, ...
     * from left to right; the last span is closed at the right. Exactly p+1
     * basis functions, first_basis_function(span) + 0..p, are non-zero on a
     * span; all per-span arrays below use that local numbering.
     */
    class KnotVector
    {
    public:
      // Largest supported degree (per-span work uses fixed-size buffers).
      static constexpr unsigned int max_degree = 20;

      /**
       * An empty object (degree 0, no knots); only useful as a placeholder
       * to be assigned to.
       */
      KnotVector() = default;

      KnotVector(const std::vector<double> &knots, const unsigned int degree);

      /**
       * The open uniform knot vector of the given degree with n_spans equal
       * spans on [start, end] (interior knots simple: C^{p-1} continuity).
       */
      static KnotVector
      uniform(const unsigned int degree,
              const unsigned int n_spans,
              const double       start = 0.,
              const double       end   = 1.);

      unsigned int
      degree() const
      {
        return p;
      }

      const std::vector<double> &
      knots() const
      {
        return knot_values;
      }

      unsigned int
      n_knots() const
      {
        return knot_values.size();
      }

      // n = n_knots - p - 1.
      unsigned int
      n_basis_functions() const
      {
        return knot_values.size() - p - 1;
      }

      // Number of non-empty knot spans (elements).
      unsigned int
      n_spans() const
      {
        return span_knot_index.size();
      }

      // First and last knot value: the parameter interval.
      double
      front() const
      {
        return knot_values.front();
      }

      double
      back() const
      {
        return knot_values.back();
      }

      // The distinct knot values, increasing (n_spans() + 1 of them).
      std::vector<double>
      breakpoints() const;

      // [u_k, u_{k+1}] of the span.
      std::pair<double, double>
      span_interval(const unsigned int span) const;

      // Index k into knots() with knots()[k] < knots()[k+1] bounding span.
      unsigned int
      knot_index_of_span(const unsigned int span) const;

      /**
       * The span containing u; u = back() belongs to the last span. Values
       * outside [front(), back()] by more than 1e-12 of the parameter length
       * throw; values within that tolerance are clamped.
       */
      unsigned int
      span_of(const double u) const;

      // Global index of the first of the p+1 basis functions non-zero on span.
      unsigned int
      first_basis_function(const unsigned int span) const
      {
        return span_knot_index[span] - p;
      }

      /**
       * Number of knots equal to u (compared with a tolerance of 1e-12 times
       * the parameter length); 0 if u is not a knot.
       */
      unsigned int
      multiplicity(const double u) const;

      /**
       * The p+1 basis functions non-zero on span at u (Cox-de Boor, The NURBS
       * Book A2.2). u may lie outside the span (polynomial extension).
       * values must have room for p+1 entries. This raw-pointer form does
       * not check span (it is the fast path); the vector form does.
       */
      void
      basis_values(const unsigned int span,
                   const double       u,
                   double            *values) const;

      void
      basis_values(const unsigned int   span,
                   const double         u,
                   std::vector<double> &values) const;

      /**
       * Values and derivatives up to order n of the p+1 non-zero functions
       * on span (The NURBS Book A2.3): ders[k*(p+1) + i] = d^k N_i / du^k,
       * k = 0..n, i local. ders must have room for (n+1)*(p+1) entries;
       * orders above p are zero.
       */
      void
      basis_derivatives(const unsigned int span,
                        const double       u,
                        const unsigned int n,
                        double            *ders) const;

      // As above, ders(k, i) = d^k N_i / du^k (resized to (n+1) x (p+1)).
      void
      basis_derivatives(const unsigned int          span,
                        const double                u,
                        const unsigned int          n,
                        dealii::FullMatrix<double> &ders) const;

      /**
       * Bezier extraction operators C^e, one (p+1) x (p+1) matrix per span
       * (Borden, Scott, Evans, Hughes 2011, Algorithm 1): on span e,
       * N_{first_basis_function(e)+i}(u) = sum_j C^e(i,j) B_j(t), with the
       * Bernstein polynomials B_j(t) = binom(p,j) t^j (1-t)^(p-j) of the
       * span's local coordinate t = (u - u_k) / (u_{k+1} - u_k) in [0,1].
       */
      std::vector<dealii::FullMatrix<double>>
      extraction_operators() const;

      /**
       * The p+1 Bernstein polynomials of degree p at t in [0,1] and, if
       * `derivatives` is given, their derivatives d/dt (room for p+1 values
       * each). The one Bernstein evaluator of the library.
       */
      static void
      bernstein_values(const unsigned int p,
                       const double       t,
                       double            *values,
                       double            *derivatives = nullptr);

      /**
       * Result of a refinement of the basis: the new knot vector and the
       * matrix T (n_new x n_old) with N_old_i = sum_j T(j,i) N_new_j, so that
       * control points (in homogeneous coordinates for NURBS) transform as
       * P_new = T P_old.
       */
      struct Refinement;

      // Inserts u (strictly inside the parameter interval) `times` times.
      Refinement
      insert_knot(const double u, const unsigned int times = 1) const;

      // Inserts all the given values (any order, repetitions allowed).
      Refinement
      insert_knots(const std::vector<double> &new_knots) const;

      /**
       * Knot insertion applied directly to coefficients (The NURBS Book A5.4,
       * cost O(n_new * p * n_components)): on input, `coefficients` holds
       * n_basis_functions() rows of n_components values (row-major); on
       * output, the rows for the refined basis. Returns the refined knot
       * vector. The resulting interior multiplicity must not exceed p.
       */
      KnotVector
      insert_knots(const std::vector<double> &new_knots,
                   std::vector<double>       &coefficients,
                   const unsigned int         n_components) const;

      /**
       * Knot vector of degree p + times with the same breakpoints, each knot
       * value's multiplicity raised by `times` (continuity is kept).
       */
      KnotVector
      elevated_knot_vector(const unsigned int times) const;

      // Degree elevation by `times` with its transformation matrix.
      Refinement
      elevate_degree(const unsigned int times) const;

      /**
       * Degree elevation applied to coefficients (same row layout as
       * insert_knots above); returns the elevated knot vector. Each new
       * function's row of T is computed on one span from the extraction
       * operators, T_loc^T = C_old^e D (C_new^e)^{-1}, D the Bernstein degree
       * elevation matrix.
       */
      KnotVector
      elevate_degree(const unsigned int   times,
                     std::vector<double> &coefficients,
                     const unsigned int   n_components) const;

    private:
      std::vector<double> knot_values;
      unsigned int        p = 0;
      // knot_values[span_knot_index[s]] < knot_values[span_knot_index[s]+1].
      std::vector<unsigned int> span_knot_index;

      double
      tolerance() const;
    };

    struct KnotVector::Refinement
    {
      KnotVector                 knot_vector;
      dealii::FullMatrix<double> matrix;
    };
  } // namespace nurbs
} // namespace isoimpact

#endif
