#include "reconstruct/density/sparse_system.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/util/check.h"

namespace sylva {
namespace {

// Rows per parallel task: large enough to amortise scheduling.
constexpr int64_t kRowGrain = 1024;

double Dot(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += a[i] * b[i];
  return sum;
}

void MaskFixed(const std::vector<char>* free, std::vector<double>* v) {
  if (free == nullptr) return;
  for (size_t i = 0; i < v->size(); ++i) {
    if (!(*free)[i]) (*v)[i] = 0.0;
  }
}

// Row ranges of the parallel transpose: a fixed number, of about equal
// non-zeros, so the work splits the same way on any machine.
constexpr int kTransposeChunks = 4;

std::vector<int64_t> ChunkRows(const SparseRows& a, int chunks) {
  std::vector<int64_t> first_row(chunks + 1, a.NumRows());
  first_row[0] = 0;
  int64_t row = 0;
  for (int c = 1; c < chunks; ++c) {
    const int64_t target = a.NumNonZeros() * c / chunks;
    while (row < a.NumRows() && a.row_offsets[row] < target) ++row;
    first_row[c] = row;
  }
  return first_row;
}

}  // namespace

// Each chunk of rows counts its entries per column, the counts become each
// chunk's first slot in each of the transpose's rows, and the chunks fill
// their slots in row order: the same arrays as one serial pass over the rows.
SparseRows SparseRows::Transposed() const {
  SparseRows t;
  t.num_cols = NumRows();
  const std::vector<int64_t> first_row = ChunkRows(*this, kTransposeChunks);
  std::vector<std::vector<int64_t>> next(kTransposeChunks);
  tbb::parallel_for(0, kTransposeChunks, [&](int c) {
    next[c].assign(num_cols, 0);
    for (int64_t k = row_offsets[first_row[c]]; k < row_offsets[first_row[c + 1]]; ++k) {
      ++next[c][cols[k]];
    }
  });
  t.row_offsets.assign(num_cols + 1, 0);
  for (int64_t col = 0; col < num_cols; ++col) {
    int64_t slot = t.row_offsets[col];
    for (int c = 0; c < kTransposeChunks; ++c) {
      const int64_t count = next[c][col];
      next[c][col] = slot;
      slot += count;
    }
    t.row_offsets[col + 1] = slot;
  }
  t.cols.resize(cols.size());
  t.values.resize(values.size());
  tbb::parallel_for(0, kTransposeChunks, [&](int c) {
    std::vector<int64_t>& slots = next[c];
    for (int64_t row = first_row[c]; row < first_row[c + 1]; ++row) {
      for (int64_t k = row_offsets[row]; k < row_offsets[row + 1]; ++k) {
        const int64_t slot = slots[cols[k]]++;
        t.cols[slot] = static_cast<int32_t>(row);
        t.values[slot] = values[k];
      }
    }
  });
  return t;
}

void SparseRows::Multiply(const std::vector<double>& x, std::vector<double>* y) const {
  SYLVA_DCHECK(static_cast<int64_t>(x.size()) == num_cols);
  y->resize(NumRows());
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, NumRows(), kRowGrain),
                    [&](const tbb::blocked_range<int64_t>& range) {
                      for (int64_t row = range.begin(); row < range.end(); ++row) {
                        double sum = 0.0;
                        for (int64_t k = row_offsets[row]; k < row_offsets[row + 1]; ++k) {
                          sum += values[k] * x[cols[k]];
                        }
                        (*y)[row] = sum;
                      }
                    });
}

CglsSummary SolveCgls(const SparseRows& a, const SparseRows& transposed,
                      const std::vector<double>& b, const CglsOptions& options,
                      const std::vector<char>* free, std::vector<double>* x,
                      ProgressTask* progress) {
  SYLVA_CHECK(static_cast<int64_t>(b.size()) == a.NumRows());
  SYLVA_CHECK(static_cast<int64_t>(x->size()) == a.num_cols);
  CglsSummary summary;
  std::vector<double> r, q, s, ax;
  a.Multiply(*x, &ax);
  r.resize(b.size());
  for (size_t i = 0; i < b.size(); ++i) r[i] = b[i] - ax[i];
  summary.initial_residual_norm = std::sqrt(Dot(r, r));
  transposed.Multiply(b, &s);
  MaskFixed(free, &s);
  const double gradient_scale = std::sqrt(Dot(s, s));
  transposed.Multiply(r, &s);
  MaskFixed(free, &s);
  std::vector<double> p = s;
  double gamma = Dot(s, s);
  const double stop_gamma = std::pow(options.tolerance * gradient_scale, 2);
  summary.converged = gamma <= stop_gamma;
  while (!summary.converged && summary.iterations < options.max_iterations) {
    a.Multiply(p, &q);
    const double q_norm2 = Dot(q, q);
    if (!(q_norm2 > 0)) break;
    const double alpha = gamma / q_norm2;
    for (size_t j = 0; j < x->size(); ++j) (*x)[j] += alpha * p[j];
    for (size_t i = 0; i < r.size(); ++i) r[i] -= alpha * q[i];
    transposed.Multiply(r, &s);
    MaskFixed(free, &s);
    const double gamma_next = Dot(s, s);
    const double beta = gamma_next / gamma;
    for (size_t j = 0; j < p.size(); ++j) p[j] = s[j] + beta * p[j];
    gamma = gamma_next;
    ++summary.iterations;
    summary.converged = gamma <= stop_gamma;
    if (progress)
      progress->Update(static_cast<double>(summary.iterations) / options.max_iterations);
  }
  summary.final_residual_norm = std::sqrt(Dot(r, r));
  summary.relative_gradient = gradient_scale > 0 ? std::sqrt(gamma) / gradient_scale : 0.0;
  return summary;
}

namespace {

// Vector passes run in parallel over fixed chunks, and reductions combine
// the chunks in a fixed order (parallel_deterministic_reduce), so results do
// not depend on scheduling.
constexpr size_t kVectorGrain = 16384;

// Two sums in one pass (each over its own terms, in the chunks and order a
// sum alone would have, so the same bits).
struct TwoSums {
  double first = 0.0, second = 0.0;
  TwoSums operator+(const TwoSums& other) const {
    return {first + other.first, second + other.second};
  }
};

template <typename Body>
TwoSums DeterministicSums(size_t size, const Body& body) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(0, size, kVectorGrain), TwoSums(),
      [&](const tbb::blocked_range<size_t>& range, TwoSums sums) {
        for (size_t j = range.begin(); j < range.end(); ++j) {
          const TwoSums terms = body(j);
          sums.first += terms.first;
          sums.second += terms.second;
        }
        return sums;
      },
      std::plus<TwoSums>());
}

// Inverse squared column norms of A (1 for empty columns): the Jacobi
// preconditioner of A^T A, which equalises voxels crossed by many or few
// rays. Each column's sum is taken in row order: over the transpose's row
// (in parallel) if given, else by one serial pass over A's rows, the same
// bits either way.
std::vector<double> InverseColumnNorms(const SparseRows& a, const SparseRows* transposed) {
  std::vector<double> norm2(a.num_cols, 0.0);
  if (transposed != nullptr) {
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, a.num_cols, kRowGrain),
                      [&](const tbb::blocked_range<int64_t>& range) {
                        for (int64_t j = range.begin(); j < range.end(); ++j) {
                          double sum = 0.0;
                          for (int64_t k = transposed->row_offsets[j];
                               k < transposed->row_offsets[j + 1]; ++k) {
                            sum += double{transposed->values[k]} * transposed->values[k];
                          }
                          norm2[j] = sum;
                        }
                      });
  } else {
    for (int64_t k = 0; k < a.NumNonZeros(); ++k) {
      norm2[a.cols[k]] += double{a.values[k]} * a.values[k];
    }
  }
  std::vector<double> metric(a.num_cols, 1.0);
  for (int64_t j = 0; j < a.num_cols; ++j) {
    if (norm2[j] > 0) metric[j] = 1.0 / norm2[j];
  }
  return metric;
}

// y = A^T x by one serial scatter over A's rows: each entry sums its terms
// in row order, as transposed.Multiply does, so the result is the same to
// the bit; it saves building the transpose where one product is all a
// solve needs.
void MultiplyTransposed(const SparseRows& a, const std::vector<double>& x, std::vector<double>* y) {
  y->assign(a.num_cols, 0.0);
  for (int64_t row = 0; row < a.NumRows(); ++row) {
    for (int64_t k = a.row_offsets[row]; k < a.row_offsets[row + 1]; ++k) {
      (*y)[a.cols[k]] += a.values[k] * x[row];
    }
  }
}

// One fused pass: the projected step d = max(x - alpha m g, 0) - x in the
// diagonal metric m, its slope g . d, and |max(x - m g, 0) - x|^2 (the
// projected gradient, for the stopping test).
struct StepPass {
  double slope = 0.0;
  double projected_gradient2 = 0.0;
};

StepPass ProjectedStep(const std::vector<double>& x, const std::vector<double>& g,
                       const std::vector<double>& metric, double alpha, std::vector<double>* d) {
  const TwoSums sums = DeterministicSums(x.size(), [&](size_t j) {
    (*d)[j] = std::max(x[j] - alpha * metric[j] * g[j], 0.0) - x[j];
    const double step = std::max(x[j] - metric[j] * g[j], 0.0) - x[j];
    return TwoSums{g[j] * (*d)[j], step * step};
  });
  return {sums.first, sums.second};
}

// The Cauchy step (SolveProjectedGradient): z = M g on the positive
// unknowns (0 elsewhere), length c = g.z / |A z|^2, d = max(x - c z, 0) - x;
// returns the slope g.d (0 if there is no such step). `scratch` holds A z.
double CauchyStep(const SparseRows& a, const std::vector<double>& x, const std::vector<double>& g,
                  const std::vector<double>& metric, std::vector<double>* d,
                  std::vector<double>* scratch) {
  std::vector<double>& z = *d;
  const double gz = DeterministicSums(x.size(), [&](size_t j) {
                      z[j] = x[j] > 0 ? metric[j] * g[j] : 0.0;
                      return TwoSums{g[j] * z[j], 0.0};
                    }).first;
  a.Multiply(z, scratch);
  const double az2 = Dot(*scratch, *scratch);
  if (!(gz > 0) || !(az2 > 0)) return 0.0;
  const double length = gz / az2;
  return DeterministicSums(x.size(),
                           [&](size_t j) {
                             z[j] = std::max(x[j] - length * z[j], 0.0) - x[j];  // z becomes d
                             return TwoSums{g[j] * z[j], 0.0};
                           })
      .first;
}

// A solve given no transpose (a warm start, usually 1-3 steps) takes its
// first steps with MultiplyTransposed's serial scatter and builds the
// transpose only for the step after these: on the bundled demo's 5.1 M
// non-zeros (2 threads) the scatter takes 18 ms, building the transpose
// 64-77 ms and a product with it 4 ms, so 4 scattered steps cost about what
// the transpose would.
constexpr int kStepsBeforeTranspose = 5;

// Bounds on the Barzilai-Borwein step (the Jacobi step is 1).
constexpr double kMinStep = 1e-10;
constexpr double kMaxStep = 1e10;

}  // namespace

CglsSummary SolveProjectedGradient(const SparseRows& a, const SparseRows* transposed,
                                   const std::vector<double>& b, const CglsOptions& options,
                                   std::vector<double>* x, ProgressTask* progress) {
  SYLVA_CHECK(static_cast<int64_t>(b.size()) == a.NumRows());
  SYLVA_CHECK(static_cast<int64_t>(x->size()) == a.num_cols);
  for (double& value : *x) value = std::max(value, 0.0);
  CglsSummary summary;
  const std::vector<double> metric = InverseColumnNorms(a, transposed);
  std::vector<double> r, g, g_next, d(x->size()), ad;
  a.Multiply(*x, &r);
  for (size_t i = 0; i < r.size(); ++i) r[i] -= b[i];  // r = A x - b
  summary.initial_residual_norm = std::sqrt(Dot(r, r));
  SparseRows built;  // the transpose, if not given, once the solve iterates
  if (transposed != nullptr) {
    transposed->Multiply(r, &g);
  } else {
    MultiplyTransposed(a, r, &g);
  }
  double alpha = 1.0;  // step length in the metric
  double initial_projected = -1.0, projected = 0.0;
  for (;;) {
    bool cauchy = options.cauchy_every > 0 && initial_projected >= 0 &&
                  summary.iterations < options.max_iterations &&
                  (summary.iterations + 1) % options.cauchy_every == 0;
    StepPass pass;
    if (cauchy) {
      pass.slope = CauchyStep(a, *x, g, metric, &d, &ad);
      cauchy = pass.slope < 0;  // else a Barzilai-Borwein step
    }
    if (!cauchy) {
      pass = ProjectedStep(*x, g, metric, alpha, &d);
      projected = std::sqrt(pass.projected_gradient2);
      if (initial_projected < 0) initial_projected = projected;
      summary.converged = projected <= options.tolerance * initial_projected ||
                          projected <= options.absolute_tolerance;
      if (summary.converged || summary.iterations >= options.max_iterations) break;
    }
    a.Multiply(d, &ad);
    const double ad2 = Dot(ad, ad);
    if (!(ad2 > 0) || pass.slope >= 0) break;  // no descent left
    const double lambda = std::min(1.0, -pass.slope / ad2);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, x->size(), kVectorGrain),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t j = range.begin(); j < range.end(); ++j) {
                          (*x)[j] = std::max((*x)[j] + lambda * d[j], 0.0);
                        }
                      });
    for (size_t i = 0; i < r.size(); ++i) r[i] += lambda * ad[i];
    if (transposed == nullptr && summary.iterations + 1 >= kStepsBeforeTranspose) {
      built = a.Transposed();
      transposed = &built;
    }
    if (transposed != nullptr) {
      transposed->Multiply(r, &g_next);
    } else {
      MultiplyTransposed(a, r, &g_next);  // the same values
    }
    // Barzilai-Borwein in the metric: alpha = s.M^-1 s / s.y, s = lambda d,
    // y = g_next - g (a Cauchy step leaves alpha as it was).
    if (!cauchy) {
      const auto [ss, sy] = DeterministicSums(d.size(), [&](size_t j) {
        return TwoSums{d[j] * d[j] / metric[j], d[j] * (g_next[j] - g[j])};
      });
      alpha = sy > 0 ? std::clamp(lambda * ss / sy, kMinStep, kMaxStep) : kMaxStep;
    }
    g.swap(g_next);
    ++summary.iterations;
    if (progress)
      progress->Update(static_cast<double>(summary.iterations) / options.max_iterations);
  }
  summary.final_residual_norm = std::sqrt(Dot(r, r));
  summary.relative_gradient = initial_projected > 0 ? projected / initial_projected : 0.0;
  summary.initial_gradient_norm = initial_projected;
  summary.final_gradient_norm = projected;
  return summary;
}

}  // namespace sylva
