#include "reconstruct/matting/closed_form.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <algorithm>
#include <vector>

#include "core/util/check.h"
#include "reconstruct/matting/matting.h"

namespace sylva {
namespace {

// Pixels i and j share a 3x3 window iff |dx|, |dy| <= 2: 25 neighbour slots.
constexpr int kReach = 2;
constexpr int kSlotsPerRow = (2 * kReach + 1) * (2 * kReach + 1);
constexpr int kWindowPixels = 9;
// Progress is reported every this many conjugate-gradient iterations.
constexpr int kProgressInterval = 25;

int Slot(int dx, int dy) { return (dy + kReach) * (2 * kReach + 1) + (dx + kReach); }

using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// The unknown pixels, the coefficients of their rows in the 25 slots, and
// the right-hand side from their known neighbours.
struct BandSystem {
  int width = 0;
  int height = 0;
  std::vector<int32_t> unknown_of_pixel;  // -1 for known pixels
  std::vector<int32_t> pixel_of_unknown;
  std::vector<double> known_alpha;  // 0 or 1 per pixel (unknown: 0)
  std::vector<double> slots;        // kSlotsPerRow per unknown
  Eigen::VectorXd rhs;
};

BandSystem IndexUnknowns(const FloatImage& trimap) {
  BandSystem system;
  system.width = trimap.width();
  system.height = trimap.height();
  const size_t n = trimap.NumPixels();
  system.unknown_of_pixel.assign(n, -1);
  system.known_alpha.assign(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const float t = trimap.values()[i];
    if (t >= kTrimapForegroundMin) {
      system.known_alpha[i] = 1.0;
    } else if (t > kTrimapBackgroundMax) {
      system.unknown_of_pixel[i] = static_cast<int32_t>(system.pixel_of_unknown.size());
      system.pixel_of_unknown.push_back(static_cast<int32_t>(i));
    }
  }
  system.slots.assign(system.pixel_of_unknown.size() * kSlotsPerRow, 0.0);
  system.rhs = Eigen::VectorXd::Zero(system.pixel_of_unknown.size());
  return system;
}

// Centres of the full 3x3 windows inside the image that contain an unknown pixel.
std::vector<int32_t> WindowCentres(const BandSystem& system) {
  std::vector<char> is_centre(system.unknown_of_pixel.size(), 0);
  for (int32_t pixel : system.pixel_of_unknown) {
    const int x = pixel % system.width, y = pixel / system.width;
    for (int cy = std::max(1, y - 1); cy <= std::min(system.height - 2, y + 1); ++cy) {
      for (int cx = std::max(1, x - 1); cx <= std::min(system.width - 2, x + 1); ++cx) {
        is_centre[static_cast<size_t>(cy) * system.width + cx] = 1;
      }
    }
  }
  std::vector<int32_t> centres;
  for (size_t i = 0; i < is_centre.size(); ++i) {
    if (is_centre[i]) centres.push_back(static_cast<int32_t>(i));
  }
  return centres;
}

// Adds one window's 9x9 block of the matting Laplacian (Levin et al. eq. 12).
void AddWindow(const FloatImage& photo, int centre, double epsilon, BandSystem* system) {
  const int cx = centre % system->width, cy = centre / system->width;
  Eigen::Matrix<double, kWindowPixels, 3> colours;
  int pixels[kWindowPixels];
  for (int k = 0; k < kWindowPixels; ++k) {
    const int x = cx + k % 3 - 1, y = cy + k / 3 - 1;
    pixels[k] = y * system->width + x;
    for (int c = 0; c < 3; ++c) colours(k, c) = photo.at(x, y, c);
  }
  const Eigen::RowVector3d mean = colours.colwise().mean();
  const Eigen::Matrix<double, kWindowPixels, 3> centred = colours.rowwise() - mean;
  const Eigen::Matrix3d covariance = centred.transpose() * centred / kWindowPixels +
                                     (epsilon / kWindowPixels) * Eigen::Matrix3d::Identity();
  const Eigen::Matrix<double, kWindowPixels, kWindowPixels> affinity =
      (Eigen::Matrix<double, kWindowPixels, kWindowPixels>::Ones() +
       centred * covariance.inverse() * centred.transpose()) /
      kWindowPixels;
  for (int a = 0; a < kWindowPixels; ++a) {
    const int32_t row = system->unknown_of_pixel[pixels[a]];
    if (row < 0) continue;
    for (int b = 0; b < kWindowPixels; ++b) {
      const double value = (a == b ? 1.0 : 0.0) - affinity(a, b);
      const int32_t col = system->unknown_of_pixel[pixels[b]];
      if (col >= 0) {
        system
            ->slots[static_cast<size_t>(row) * kSlotsPerRow + Slot(b % 3 - a % 3, b / 3 - a / 3)] +=
            value;
      } else {
        system->rhs[row] -= value * system->known_alpha[pixels[b]];
      }
    }
  }
}

// The slots as a row-major sparse matrix, plus the prior on the diagonal.
RowMatrix AssembleMatrix(const BandSystem& system, double prior_weight) {
  const int64_t n = static_cast<int64_t>(system.pixel_of_unknown.size());
  RowMatrix matrix(n, n);
  matrix.reserve(Eigen::VectorXi::Constant(n, kSlotsPerRow));
  for (int64_t row = 0; row < n; ++row) {
    const int x = system.pixel_of_unknown[row] % system.width;
    const int y = system.pixel_of_unknown[row] / system.width;
    for (int dy = -kReach; dy <= kReach; ++dy) {
      for (int dx = -kReach; dx <= kReach; ++dx) {
        double value = system.slots[row * kSlotsPerRow + Slot(dx, dy)];
        if (dx == 0 && dy == 0) value += prior_weight;
        if (value == 0.0) continue;
        const int32_t col =
            system.unknown_of_pixel[static_cast<size_t>(y + dy) * system.width + x + dx];
        matrix.insert(row, col) = value;
      }
    }
  }
  matrix.makeCompressed();
  return matrix;
}

// Jacobi-preconditioned conjugate gradients from x (in/out).
void SolveConjugateGradient(const RowMatrix& a, const Eigen::VectorXd& b,
                            const ClosedFormOptions& options, ProgressTask* progress,
                            Eigen::VectorXd* x, ClosedFormSummary* summary) {
  const Eigen::VectorXd inverse_diagonal = a.diagonal().cwiseInverse();
  Eigen::VectorXd r = b - a * *x;
  Eigen::VectorXd z = inverse_diagonal.cwiseProduct(r);
  Eigen::VectorXd p = z;
  double rz = r.dot(z);
  const double b_norm = std::max(b.norm(), 1e-30);
  int iteration = 0;
  for (; iteration < options.max_iterations && r.norm() > options.tolerance * b_norm; ++iteration) {
    if (progress != nullptr && iteration % kProgressInterval == 0) {
      progress->Update(static_cast<double>(iteration) / options.max_iterations);
    }
    const Eigen::VectorXd ap = a * p;
    const double step = rz / p.dot(ap);
    *x += step * p;
    r -= step * ap;
    z = inverse_diagonal.cwiseProduct(r);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  summary->iterations = iteration;
  summary->relative_residual = r.norm() / b_norm;
}

}  // namespace

FloatImage ClosedFormMatte(const FloatImage& photo, const FloatImage& trimap,
                           const ClosedFormOptions& options, ProgressTask* progress,
                           ClosedFormSummary* summary) {
  SYLVA_CHECK(photo.channels() >= 3 && trimap.channels() == 1 && photo.width() == trimap.width() &&
              photo.height() == trimap.height());
  BandSystem system = IndexUnknowns(trimap);
  ClosedFormSummary local_summary;
  local_summary.num_unknown = static_cast<int64_t>(system.pixel_of_unknown.size());
  FloatImage alpha(trimap.width(), trimap.height(), 1);
  for (size_t i = 0; i < alpha.NumPixels(); ++i) {
    alpha.values()[i] = static_cast<float>(system.known_alpha[i]);
  }
  if (local_summary.num_unknown > 0) {
    for (int32_t centre : WindowCentres(system)) AddWindow(photo, centre, options.epsilon, &system);
    system.rhs.array() += options.prior_weight * 0.5;
    const RowMatrix matrix = AssembleMatrix(system, options.prior_weight);
    Eigen::VectorXd solution = Eigen::VectorXd::Constant(local_summary.num_unknown, 0.5);
    SolveConjugateGradient(matrix, system.rhs, options, progress, &solution, &local_summary);
    for (int64_t u = 0; u < local_summary.num_unknown; ++u) {
      alpha.values()[system.pixel_of_unknown[u]] =
          static_cast<float>(std::clamp(solution[u], 0.0, 1.0));
    }
  }
  if (summary != nullptr) *summary = local_summary;
  return alpha;
}

}  // namespace sylva
