// A sparse least-squares system A x = b with row-compressed A and its
// transpose, and a CGLS solver over it.
//
// CGLS (conjugate gradients on the normal equations A^T A x = A^T b, without
// forming A^T A) is the thesis' "least square fitting" (eq. 3.3) done
// iteratively: each iteration costs one product with A and one with A^T.
#ifndef SYLVA_RECONSTRUCT_DENSITY_SPARSE_SYSTEM_H_
#define SYLVA_RECONSTRUCT_DENSITY_SPARSE_SYSTEM_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/util/progress.h"

namespace sylva {

// Row-compressed sparse matrix with float entries.
struct SparseRows {
  int64_t num_cols = 0;
  std::vector<int64_t> row_offsets = {0};  // size rows + 1
  std::vector<int32_t> cols;
  std::vector<float> values;

  int64_t NumRows() const { return static_cast<int64_t>(row_offsets.size()) - 1; }
  int64_t NumNonZeros() const { return static_cast<int64_t>(cols.size()); }
  // The transpose, in the same format (rows become columns).
  SparseRows Transposed() const;
  // y = this * x (parallel over rows, deterministic).
  void Multiply(const std::vector<double>& x, std::vector<double>* y) const;
};

struct CglsOptions {
  int max_iterations = 40;
  // Stop when |A^T r| <= tolerance * |A^T b|.
  double tolerance = 1e-3;
  // SolveProjectedGradient only: also stop when the projected gradient
  // |P(x - g) - x| is at most this (absolute, in the units of A^T b). A warm
  // start sets it to where the solve it continues stopped, so it stops on the
  // same criterion rather than relative to its own (smaller) start; 0 = off.
  double absolute_tolerance = 0.0;
  // SolveProjectedGradient only: every cauchy_every-th step (0 = none) is a
  // Cauchy step instead of a Barzilai-Borwein one (see there).
  int cauchy_every = 0;
};

struct CglsSummary {
  int iterations = 0;
  double initial_residual_norm = 0.0;  // |b - A x0|
  double final_residual_norm = 0.0;    // |b - A x|
  double relative_gradient = 0.0;      // |A^T r| / |A^T b| at the end
  // SolveProjectedGradient only: the projected gradient at the start and at
  // the end (absolute).
  double initial_gradient_norm = 0.0;
  double final_gradient_norm = 0.0;
  bool converged = false;  // tolerance reached
};

// Minimises |A x - b| starting from *x. Entries where `free` is false (if
// given) stay fixed. `transposed` must be a.Transposed().
CglsSummary SolveCgls(const SparseRows& a, const SparseRows& transposed,
                      const std::vector<double>& b, const CglsOptions& options,
                      const std::vector<char>* free, std::vector<double>* x,
                      ProgressTask* progress);

// Minimises |A x - b| subject to x >= 0 starting from max(*x, 0): projected
// gradient with Barzilai-Borwein step lengths and an exact line search along
// each projected step (the objective is quadratic), so the objective never
// increases. One product with A and one with A^T per iteration, like CGLS.
// Converged when the projected gradient |P(x - g) - x| falls below
// tolerance times its initial value, or below options.absolute_tolerance.
//
// With options.cauchy_every = k > 0, every k-th step instead moves the
// positive unknowns along their preconditioned gradient by its Cauchy
// length (the exact minimum along it, bounds ignored: g.Mg / |A Mg|^2),
// projected onto x >= 0 and searched exactly like the others; it costs one
// more product with A. Barzilai-Borwein's lengths shrink the fast-curving
// components, and a Cauchy step taken just then, when the gradient is left
// mostly with the slow ones, is long: several times a Barzilai-Borwein step
// (on the synthetic trees, k = 3 reaches in 20 iterations the fit that 50
// plain ones reached; k = 2 or 4 does not).
//
// `transposed` is a.Transposed(), or null: then the solve builds it only if
// it takes a step (the starting gradient is the same without it, to the
// bit). A warm start that has already converged (the app's density edits)
// saves the transpose: 0.05 s and 80 MB of fresh memory on 5 M non-zeros.
CglsSummary SolveProjectedGradient(const SparseRows& a, const SparseRows* transposed,
                                   const std::vector<double>& b, const CglsOptions& options,
                                   std::vector<double>* x, ProgressTask* progress);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_SPARSE_SYSTEM_H_
