#include "reconstruct/density/sparse_system.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <utility>

#include "core/util/random.h"

namespace sylva {
namespace {

SparseRows RandomSparse(int rows, int cols, double fill, RandomEngine* rng,
                        Eigen::MatrixXd* dense) {
  SparseRows a;
  a.num_cols = cols;
  dense->setZero(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (rng->Uniform() > fill) continue;
      const float value = static_cast<float>(rng->Uniform(0.1, 1.0));
      a.cols.push_back(c);
      a.values.push_back(value);
      (*dense)(r, c) = value;
    }
    a.row_offsets.push_back(static_cast<int64_t>(a.cols.size()));
  }
  return a;
}

// The parallel transpose (chunks of rows) gives the arrays of one serial
// pass: each column's entries in row order, whatever the rows' order of
// columns, with empty rows, empty columns and fewer rows than chunks.
TEST(SparseSystemTest, TransposeIsTheSerialOne) {
  RandomEngine rng(3);
  for (const auto& [rows, cols] : {std::pair{0, 5}, {2, 7}, {3, 1}, {700, 90}}) {
    SparseRows a;
    a.num_cols = cols;
    for (int r = 0; r < rows; ++r) {
      const int length = r % 11 == 0 ? 0 : static_cast<int>(rng.Uniform(1, 20));
      for (int e = 0; e < length; ++e) {
        // The last column stays empty (but for a single column).
        a.cols.push_back(static_cast<int32_t>(rng.Uniform(0, std::max(1, cols - 1))));
        a.values.push_back(static_cast<float>(rng.Normal()));
      }
      a.row_offsets.push_back(static_cast<int64_t>(a.cols.size()));
    }
    std::vector<std::vector<std::pair<int32_t, float>>> serial(cols);
    for (int r = 0; r < rows; ++r) {
      for (int64_t k = a.row_offsets[r]; k < a.row_offsets[r + 1]; ++k) {
        serial[a.cols[k]].emplace_back(r, a.values[k]);
      }
    }
    const SparseRows t = a.Transposed();
    ASSERT_EQ(t.NumRows(), cols);
    ASSERT_EQ(t.num_cols, rows);
    ASSERT_EQ(t.NumNonZeros(), a.NumNonZeros());
    for (int c = 0; c < cols; ++c) {
      ASSERT_EQ(t.row_offsets[c + 1] - t.row_offsets[c], static_cast<int64_t>(serial[c].size()));
      for (size_t e = 0; e < serial[c].size(); ++e) {
        EXPECT_EQ(t.cols[t.row_offsets[c] + e], serial[c][e].first);
        EXPECT_EQ(t.values[t.row_offsets[c] + e], serial[c][e].second);
      }
    }
  }
}

TEST(SparseSystemTest, TransposeAndMultiply) {
  RandomEngine rng(1);
  Eigen::MatrixXd dense;
  const SparseRows a = RandomSparse(30, 12, 0.3, &rng, &dense);
  const SparseRows t = a.Transposed();
  EXPECT_EQ(t.NumRows(), 12);
  EXPECT_EQ(t.num_cols, 30);
  std::vector<double> x(30), y;
  for (double& v : x) v = rng.Normal();
  t.Multiply(x, &y);
  const Eigen::VectorXd expected = dense.transpose() * Eigen::Map<Eigen::VectorXd>(x.data(), 30);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(y[i], expected[i], 1e-9);
}

TEST(SparseSystemTest, CglsReachesTheLeastSquaresSolution) {
  RandomEngine rng(2);
  Eigen::MatrixXd dense;
  const SparseRows a = RandomSparse(80, 25, 0.4, &rng, &dense);
  std::vector<double> b(80);
  for (double& v : b) v = rng.Normal();
  const Eigen::VectorXd b_vec = Eigen::Map<Eigen::VectorXd>(b.data(), 80);
  const Eigen::VectorXd expected = dense.colPivHouseholderQr().solve(b_vec);
  std::vector<double> x(25, 0.0);
  const CglsSummary summary =
      SolveCgls(a, a.Transposed(), b, CglsOptions{200, 1e-12}, nullptr, &x, nullptr);
  EXPECT_TRUE(summary.converged);
  EXPECT_LT(summary.final_residual_norm, summary.initial_residual_norm);
  for (int j = 0; j < 25; ++j) EXPECT_NEAR(x[j], expected[j], 1e-6);
}

TEST(SparseSystemTest, FixedEntriesStayFixed) {
  RandomEngine rng(3);
  Eigen::MatrixXd dense;
  const SparseRows a = RandomSparse(60, 10, 0.5, &rng, &dense);
  std::vector<double> b(60);
  for (double& v : b) v = rng.Normal();
  std::vector<double> x(10, 0.0);
  x[3] = 0.7;
  std::vector<char> free(10, 1);
  free[3] = 0;
  SolveCgls(a, a.Transposed(), b, CglsOptions{100, 1e-12}, &free, &x, nullptr);
  EXPECT_EQ(x[3], 0.7);
  // The others solve the reduced problem A' x' = b - a_3 * 0.7.
  Eigen::MatrixXd reduced(60, 9);
  reduced << dense.leftCols(3), dense.rightCols(6);
  const Eigen::VectorXd rhs = Eigen::Map<Eigen::VectorXd>(b.data(), 60) - dense.col(3) * 0.7;
  const Eigen::VectorXd expected = reduced.colPivHouseholderQr().solve(rhs);
  for (int j = 0, k = 0; j < 10; ++j) {
    if (j == 3) continue;
    EXPECT_NEAR(x[j], expected[k++], 1e-6);
  }
}

// Without the transpose, the projected-gradient solve starts from a
// scatter over A's rows and builds the transpose only when it steps: the
// same iterates to the bit, whether it steps (cold) or stops at once (a
// warm start that has converged).
TEST(SparseSystemTest, ProjectedGradientWithoutTheTransposeIsTheSame) {
  RandomEngine rng(4);
  Eigen::MatrixXd dense;
  const SparseRows a = RandomSparse(400, 150, 0.1, &rng, &dense);
  const SparseRows t = a.Transposed();
  std::vector<double> b(400), x0(150);
  for (double& v : b) v = rng.Uniform(0.0, 2.0);
  for (double& v : x0) v = rng.Normal();
  // 2 steps: every product by the scatter; 30: the transpose built after a few.
  for (const auto& [steps, absolute_tolerance] :
       {std::pair{30, 0.0}, std::pair{2, 0.0}, std::pair{30, 1e9}}) {
    SCOPED_TRACE(steps);
    const CglsOptions options{steps, 1e-9, absolute_tolerance};
    std::vector<double> with = x0, without = x0;
    const CglsSummary a_with = SolveProjectedGradient(a, &t, b, options, &with, nullptr);
    const CglsSummary a_without = SolveProjectedGradient(a, nullptr, b, options, &without, nullptr);
    EXPECT_EQ(a_with.iterations, absolute_tolerance > 0 ? 0 : steps);
    EXPECT_EQ(a_without.iterations, a_with.iterations);
    EXPECT_EQ(a_without.initial_gradient_norm, a_with.initial_gradient_norm);
    EXPECT_EQ(a_without.final_gradient_norm, a_with.final_gradient_norm);
    EXPECT_EQ(a_without.final_residual_norm, a_with.final_residual_norm);
    for (int j = 0; j < 150; ++j) ASSERT_EQ(without[j], with[j]) << j;
    if (absolute_tolerance == 0.0 && steps == 30) {
      EXPECT_LT(a_with.final_residual_norm, 0.5 * a_with.initial_residual_norm);
    }
  }
}

// Cauchy steps (CglsOptions::cauchy_every) on an under-determined,
// non-negative problem like the density's (more unknowns than rays, a
// sparse non-negative truth): the same optimum, reached in fewer
// iterations, and never a larger residual than where a step started.
TEST(SparseSystemTest, CauchyStepsReachTheSameOptimumSooner) {
  RandomEngine rng(11);
  Eigen::MatrixXd dense;
  const SparseRows a = RandomSparse(300, 500, 0.04, &rng, &dense);
  const SparseRows t = a.Transposed();
  Eigen::VectorXd truth = Eigen::VectorXd::Zero(500);
  for (int j = 0; j < 500; ++j) truth[j] = rng.Uniform() < 0.3 ? rng.Uniform(0.0, 2.0) : 0.0;
  const Eigen::VectorXd rhs = dense * truth;
  std::vector<double> b(rhs.data(), rhs.data() + rhs.size());
  for (double& v : b) v += rng.Normal(0.0, 0.05);
  const auto solve = [&](int iterations, int cauchy_every) {
    CglsOptions options{iterations, 0.0, 0.0, cauchy_every};
    std::vector<double> x(500, 0.1);
    const CglsSummary summary = SolveProjectedGradient(a, &t, b, options, &x, nullptr);
    return std::make_pair(summary, x);
  };
  const double optimum = solve(20000, 0).first.final_residual_norm;
  // The residual never grows from one iteration count to the next.
  for (const int cauchy_every : {0, 3}) {
    double last = 1e300;
    for (int n = 1; n <= 60; ++n) {
      const double residual = solve(n, cauchy_every).first.final_residual_norm;
      EXPECT_LE(residual, last) << n << " iterations, cauchy_every " << cauchy_every;
      last = residual;
    }
  }
  // Iterations until the residual is within 1 % of the optimum's (it falls
  // with the count: bisection).
  const auto iterations_to_fit = [&](int cauchy_every) {
    int low = 0, high = 4000;
    while (high - low > 1) {
      const int middle = (low + high) / 2;
      (solve(middle, cauchy_every).first.final_residual_norm <= 1.01 * optimum ? high : low) =
          middle;
    }
    return high;
  };
  const int plain = iterations_to_fit(0), with_cauchy = iterations_to_fit(3);
  std::printf("iterations to within 1 %% of the optimum: %d plain, %d with Cauchy steps\n", plain,
              with_cauchy);
  EXPECT_LT(with_cauchy, plain);
  const auto [summary, x] = solve(20000, 3);
  EXPECT_NEAR(summary.final_residual_norm, optimum, 1e-6 * optimum);
  for (double v : x) EXPECT_GE(v, 0.0);
}

}  // namespace
}  // namespace sylva
