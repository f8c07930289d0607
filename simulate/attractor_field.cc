#include "simulate/attractor_field.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "core/geometry/polyline.h"
#include "core/util/check.h"

namespace sylva {
namespace {

// Segment buckets along the longer image side (at most).
constexpr int kMaxBuckets = 64;
// Below this fraction of the eigenvalue sum, the second smallest eigenvalue
// of the plane normals' scatter means the planes do not pin a line down.
constexpr double kDegenerateEigenFraction = 1e-3;
int LongerSide(int width, int height) { return std::max(width, height); }

// Each bucket's Chebyshev distance (in buckets) to the nearest bucket that
// holds a segment (`start`: CSR offsets of the buckets' segments, at least
// one bucket holds one): two passes over the grid, each bucket taking its
// already visited 8-neighbours' distance + 1.
std::vector<int> EmptyRings(const std::vector<int>& start, int cols, int rows) {
  const int far = cols + rows;
  std::vector<int> rings(static_cast<size_t>(cols) * rows);
  for (size_t b = 0; b < rings.size(); ++b) rings[b] = start[b + 1] > start[b] ? 0 : far;
  const auto relax = [&](int c, int r, int dc, int dr) {
    const int nc = c + dc, nr = r + dr;
    if (nc < 0 || nc >= cols || nr < 0 || nr >= rows) return;
    int& ring = rings[static_cast<size_t>(r) * cols + c];
    ring = std::min(ring, rings[static_cast<size_t>(nr) * cols + nc] + 1);
  };
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      for (const auto& [dc, dr] : {std::pair{-1, 0}, {-1, -1}, {0, -1}, {1, -1}})
        relax(c, r, dc, dr);
    }
  }
  for (int r = rows - 1; r >= 0; --r) {
    for (int c = cols - 1; c >= 0; --c) {
      for (const auto& [dc, dr] : {std::pair{1, 0}, {1, 1}, {0, 1}, {-1, 1}}) relax(c, r, dc, dr);
    }
  }
  return rings;
}

}  // namespace

// ---------------------------------------------------------------------------
// DirectionField2D

DirectionField2D::DirectionField2D(const AttractorGraph2D& graph,
                                   const AttractorFieldOptions& options)
    : options_(options), width_(graph.width), height_(graph.height) {
  options.Check();
  graph.Check("attractor graph");
  const int longer = LongerSide(width_, height_);
  cell_size_ = static_cast<double>(longer) / options.resolution;
  inverse_cell_size_ = 1.0 / cell_size_;
  cols_ = std::max(1, static_cast<int>(std::ceil(width_ / cell_size_)));
  rows_ = std::max(1, static_cast<int>(std::ceil(height_ / cell_size_)));
  falloff_px_ = options.falloff * longer;
  linear_blend_ = options.blend == "linear";
  for (const auto& [a, b] : graph.Segments()) {
    const Eigen::Vector2d ab = b - a;
    const double length = ab.norm();
    segments_.push_back(
        {a, b, length > 0 ? Eigen::Vector2d(ab / length) : Eigen::Vector2d::Zero()});
  }
  // A graph of lone nodes (no edge) attracts without a tangent.
  if (segments_.empty()) {
    for (const AttractorNode& node : graph.nodes) {
      segments_.push_back({node.position, node.position, Eigen::Vector2d::Zero()});
    }
  }
  values_.assign(static_cast<size_t>(cols_) * rows_, Eigen::Vector2f::Zero());
  empty_ = segments_.empty();
  if (empty_) return;

  // Bucket the segments (each into every bucket its bounding box touches).
  const int buckets_along =
      std::clamp(static_cast<int>(std::sqrt(segments_.size())) * 2, 1, kMaxBuckets);
  bucket_size_ = static_cast<double>(longer) / buckets_along;
  bucket_cols_ = std::max(1, static_cast<int>(std::ceil(width_ / bucket_size_)));
  bucket_rows_ = std::max(1, static_cast<int>(std::ceil(height_ / bucket_size_)));
  const auto bucket_range = [&](const Segment& s, int* c0, int* c1, int* r0, int* r1) {
    const Eigen::Vector2d lo = s.a.cwiseMin(s.b) / bucket_size_;
    const Eigen::Vector2d hi = s.a.cwiseMax(s.b) / bucket_size_;
    *c0 = std::clamp(static_cast<int>(std::floor(lo.x())), 0, bucket_cols_ - 1);
    *c1 = std::clamp(static_cast<int>(std::floor(hi.x())), 0, bucket_cols_ - 1);
    *r0 = std::clamp(static_cast<int>(std::floor(lo.y())), 0, bucket_rows_ - 1);
    *r1 = std::clamp(static_cast<int>(std::floor(hi.y())), 0, bucket_rows_ - 1);
  };
  std::vector<int> counts(static_cast<size_t>(bucket_cols_) * bucket_rows_ + 1, 0);
  for (const Segment& s : segments_) {
    int c0, c1, r0, r1;
    bucket_range(s, &c0, &c1, &r0, &r1);
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) ++counts[static_cast<size_t>(r) * bucket_cols_ + c + 1];
    }
  }
  for (size_t k = 1; k < counts.size(); ++k) counts[k] += counts[k - 1];
  bucket_start_ = counts;
  bucket_items_.resize(bucket_start_.back());
  for (int i = 0; i < static_cast<int>(segments_.size()); ++i) {
    int c0, c1, r0, r1;
    bucket_range(segments_[i], &c0, &c1, &r0, &r1);
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c)
        bucket_items_[counts[static_cast<size_t>(r) * bucket_cols_ + c]++] = i;
    }
  }

  empty_rings_ = EmptyRings(bucket_start_, bucket_cols_, bucket_rows_);

  tbb::parallel_for(tbb::blocked_range<int>(0, rows_), [&](const tbb::blocked_range<int>& range) {
    for (int row = range.begin(); row < range.end(); ++row) {
      for (int col = 0; col < cols_; ++col) {
        const Eigen::Vector2d centre((col + 0.5) * cell_size_, (row + 0.5) * cell_size_);
        values_[static_cast<size_t>(row) * cols_ + col] = Evaluate(centre).cast<float>();
      }
    }
  });
}

void DirectionField2D::Closest(const Eigen::Vector2d& p, Eigen::Vector2d* closest,
                               Eigen::Vector2d* tangent, double* distance) const {
  const int pc =
      std::clamp(static_cast<int>(std::floor(p.x() / bucket_size_)), 0, bucket_cols_ - 1);
  const int pr =
      std::clamp(static_cast<int>(std::floor(p.y() / bucket_size_)), 0, bucket_rows_ - 1);
  double best2 = std::numeric_limits<double>::infinity();
  int best = -1;
  double best_t = 0;
  const int max_ring = std::max(bucket_cols_, bucket_rows_);
  // Rings nearer than the first bucket with a segment hold none.
  const int first_ring = empty_rings_[static_cast<size_t>(pr) * bucket_cols_ + pc];
  for (int ring = first_ring; ring <= max_ring; ++ring) {
    // Segments not seen yet lie in buckets of this ring or farther, at least
    // this far from p (from its projection onto the grid if p is outside).
    const double reach = std::max(0.0, (ring - 1) * bucket_size_);
    if (best >= 0 && best2 <= reach * reach) break;
    for (int r = pr - ring; r <= pr + ring; ++r) {
      if (r < 0 || r >= bucket_rows_) continue;
      const bool edge_row = r == pr - ring || r == pr + ring;
      for (int c = pc - ring; c <= pc + ring; c += (edge_row ? 1 : 2 * ring)) {
        if (c >= 0 && c < bucket_cols_) {
          const size_t bucket = static_cast<size_t>(r) * bucket_cols_ + c;
          for (int k = bucket_start_[bucket]; k < bucket_start_[bucket + 1]; ++k) {
            const int i = bucket_items_[k];
            double t;
            const double d2 = SegmentDistance2(p, segments_[i].a, segments_[i].b, &t);
            // Ties go to the lower segment index, whatever the visiting order.
            if (d2 < best2 || (d2 == best2 && i < best)) best2 = d2, best = i, best_t = t;
          }
        }
        if (ring == 0) break;
      }
    }
  }
  const Segment& s = segments_[best];
  *closest = s.a + best_t * (s.b - s.a);
  *tangent = s.tangent;
  *distance = std::sqrt(best2);
}

Eigen::Vector2d DirectionField2D::Blend(const Eigen::Vector2d& p, const Eigen::Vector2d& closest,
                                        const Eigen::Vector2d& tangent, double distance) const {
  if (!(distance > 0)) return tangent;
  const Eigen::Vector2d toward = (closest - p) / distance;
  const double h = linear_blend_ ? std::min(distance / falloff_px_, 1.0) : options_.constant_h;
  return h * toward + (1 - h) * tangent;
}

Eigen::Vector2d DirectionField2D::Evaluate(const Eigen::Vector2d& point_in_image) const {
  if (empty_) return Eigen::Vector2d::Zero();
  Eigen::Vector2d closest, tangent;
  double distance;
  Closest(point_in_image, &closest, &tangent, &distance);
  return Blend(point_in_image, closest, tangent, distance);
}

Eigen::Vector2d DirectionField2D::At(const Eigen::Vector2d& point_in_image) const {
  if (empty_) return Eigen::Vector2d::Zero();
  // Cell centres at (k + 0.5) * cell_size.
  const double x = std::clamp(point_in_image.x() * inverse_cell_size_ - 0.5, 0.0, cols_ - 1.0);
  const double y = std::clamp(point_in_image.y() * inverse_cell_size_ - 0.5, 0.0, rows_ - 1.0);
  const int c0 = std::min(static_cast<int>(x), cols_ - 1),
            r0 = std::min(static_cast<int>(y), rows_ - 1);
  const int c1 = std::min(c0 + 1, cols_ - 1), r1 = std::min(r0 + 1, rows_ - 1);
  const double fx = x - c0, fy = y - r0;
  return (1 - fy) * ((1 - fx) * Cell(c0, r0) + fx * Cell(c1, r0)) +
         fy * ((1 - fx) * Cell(c0, r1) + fx * Cell(c1, r1));
}

// ---------------------------------------------------------------------------
// AttractorDirectionField

AttractorDirectionField::AttractorDirectionField(const ImageSet& image_set,
                                                 const std::vector<AttractorGraph2D>& graphs,
                                                 const Eigen::AlignedBox3d& bounds,
                                                 const AttractorFieldOptions& options,
                                                 ProgressReporter* progress)
    : image_set_(image_set), options_(options) {
  options.Check();
  SYLVA_CHECK_INPUT(static_cast<int>(graphs.size()) == image_set.NumViews(), "attractor graphs")
      << graphs.size() << " graphs for " << image_set.NumViews() << " views";
  SYLVA_CHECK_INPUT(!bounds.isEmpty() && bounds.min().allFinite() && bounds.max().allFinite(),
                    "attractor field bounds")
      << "the 3D field needs a non-empty, finite box";
  ProgressTask task(progress, "simulate: attractor direction fields");
  for (int v = 0; v < image_set.NumViews(); ++v) {
    if (graphs[v].IsEmpty()) continue;
    const Camera& camera = image_set.CameraOf(v);
    const std::string name = "attractor graph of " + image_set.views[v].name;
    AttractorGraph2D graph = graphs[v];
    if (graph.width != camera.width() || graph.height != camera.height()) {
      // A graph drawn on a resized copy of the photo: same aspect, rescaled.
      SYLVA_CHECK_INPUT(graph.FitsAspectOf(camera.width(), camera.height()), name)
          << "is for a " << graph.width << " x " << graph.height << " image, the photo is "
          << camera.width() << " x " << camera.height();
      graph = graph.Scaled(static_cast<double>(camera.width()) / graph.width);
      graph.width = camera.width();
      graph.height = camera.height();
    }
    const View& view = image_set.views[v];
    const Eigen::Matrix3d world_from_cam =
        view.cam_from_world.rotation.inverse().toRotationMatrix();
    const Eigen::Vector3d axis = world_from_cam.col(2);
    // The view projects with image_set_'s camera (the copy this field keeps).
    views_.push_back({v, world_from_cam, view.ProjectionCenter(), camera.IsOrthographic(),
                      !camera.IsOrthographic() && !camera.HasDistortion(), camera.FocalLengthX(),
                      camera.FocalLengthY(), camera.PrincipalPoint(), camera.width(),
                      camera.height(), DirectionField2D(graph, options), &image_set_.CameraOf(v),
                      view.cam_from_world, world_from_cam.transpose(),
                      world_from_cam.col(0) / camera.FocalLengthX(),
                      world_from_cam.col(1) / camera.FocalLengthY(),
                      Eigen::Matrix3d::Identity() - axis * axis.transpose()});
    all_planes_ += views_.back().projector;
  }
  intersect_ = options.combine == "intersect";
  all_planes_inverse_ = PseudoInverse(SolvePlanes(all_planes_));

  // Sample points at origin + spacing * (i, j, k), covering the bounds grown
  // by one spacing.
  const Eigen::Vector3d extent = bounds.sizes();
  spacing_ = std::max(extent.maxCoeff() / options.resolution_3d, 1e-9);
  origin_ = bounds.min().array() - spacing_;
  dims_ = ((extent.array() / spacing_).ceil() + 3).cast<int>().max(2);
  num_samples_ = static_cast<size_t>(dims_.x()) * dims_.y() * dims_.z();
  samples_ = std::make_unique<Slot[]>(num_samples_);
  task.Update(1.0);
}

AttractorDirectionField::~AttractorDirectionField() = default;

int AttractorDirectionField::FilledSamples() const {
  int filled = 0;
  for (size_t s = 0; s < num_samples_; ++s) {
    filled += samples_[s].state.load(std::memory_order_acquire) == kFilled;
  }
  return filled;
}

const DirectionField2D* AttractorDirectionField::Field2D(int view_idx) const {
  for (const ViewField& view : views_) {
    if (view.view_idx == view_idx) return &view.field;
  }
  return nullptr;
}

AttractorDirectionField::PlaneSolve AttractorDirectionField::SolvePlanes(
    const Eigen::Matrix3d& planes) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(planes);
  return {solver.eigenvalues(), solver.eigenvectors()};
}

bool AttractorDirectionField::PixelIn(const ViewField& view, const Eigen::Vector3d& point_in_world,
                                      Eigen::Vector2d* pixel) {
  // ImageSet::Project with the view's camera at hand.
  if (view.plain_pinhole) {
    const Eigen::Vector3d point_in_cam =
        view.cam_from_world_rotation * point_in_world + view.cam_from_world.translation;
    if (!(point_in_cam.z() > std::numeric_limits<double>::epsilon())) return false;
    const double inverse_z = 1.0 / point_in_cam.z();
    *pixel = Eigen::Vector2d(view.fx * point_in_cam.x() * inverse_z,
                             view.fy * point_in_cam.y() * inverse_z) +
             view.principal_point;
  } else {
    const Eigen::Vector3d point_in_cam = view.cam_from_world * point_in_world;
    if (!view.camera->IsInFront(point_in_cam)) return false;
    *pixel = view.camera->ImgFromCam(point_in_cam);
  }
  return pixel->x() >= 0 && pixel->y() >= 0 && pixel->x() <= view.width &&
         pixel->y() <= view.height;
}

void AttractorDirectionField::Accumulate(const ViewField& view,
                                         const Eigen::Vector3d& point_in_world,
                                         LiftSums* sums) const {
  Eigen::Vector2d pixel;
  if (!PixelIn(view, point_in_world, &pixel)) return;
  ++sums->seen;
  // The lifted vectors lie in the image plane, normal to the optical axis:
  // the field's vector f lifted (l) and scaled to f's length.
  const Eigen::Vector2d f = view.field.At(pixel);
  const double f2 = f.squaredNorm();
  if (!(f2 > 0)) return;
  const Eigen::Vector3d l = f.x() * view.lift_x + f.y() * view.lift_y;
  const double l2 = l.squaredNorm();
  if (!(l2 > 0)) return;
  sums->sum += std::sqrt(f2 / l2) * l;
  if (intersect_) {
    const Eigen::Vector3d lifted = l / std::sqrt(l2);
    const Eigen::Vector3d viewing = view.orthographic ? Eigen::Vector3d(view.world_from_cam.col(2))
                                                      : (point_in_world - view.center).normalized();
    const Eigen::Vector3d normal = viewing.cross(lifted);
    const double n = normal.norm();
    if (n > 0) sums->normals += std::sqrt(f2) * (normal / n) * (normal / n).transpose();
  }
}

Eigen::Vector3d AttractorDirectionField::Combine(const Eigen::Vector3d& point_in_world,
                                                 const LiftSums& sums) const {
  if (sums.seen == 0) return Eigen::Vector3d::Zero();
  // The sum of the image-plane projectors of the views that see the point
  // (most points: every view's, decomposed once).
  const bool every_view = sums.seen == static_cast<int>(views_.size());
  Eigen::Matrix3d planes = Eigen::Matrix3d::Zero();
  if (!every_view) {
    for (const ViewField& view : views_) {
      Eigen::Vector2d pixel;
      if (PixelIn(view, point_in_world, &pixel)) planes += view.projector;
    }
  }
  // The least-squares mean: the v whose projections onto the image planes
  // best match the lifted vectors, (sum P_k) v = sum l_k; a pseudo-inverse
  // where a direction is seen by no view.
  Eigen::Vector3d mean =
      (every_view ? all_planes_inverse_ : PseudoInverse(SolvePlanes(planes))) * sums.sum;
  if (mean.squaredNorm() > 1) mean.normalize();
  if (!intersect_) return mean;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(sums.normals);
  const Eigen::Vector3d values = solver.eigenvalues();  // ascending
  if (!(values.sum() > 0) || values(1) < kDegenerateEigenFraction * values.sum() ||
      !(mean.norm() > 0)) {
    return mean;
  }
  const Eigen::Vector3d direction = solver.eigenvectors().col(0);
  return direction.dot(mean) >= 0 ? direction : Eigen::Vector3d(-direction);
}

Eigen::Matrix3d AttractorDirectionField::PseudoInverse(const PlaneSolve& planes) {
  Eigen::Matrix3d inverse = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) {
    if (planes.values(k) > kDegenerateEigenFraction * planes.values.sum()) {
      const Eigen::Vector3d e = planes.vectors.col(k);
      inverse += e * e.transpose() / planes.values(k);
    }
  }
  return inverse;
}

Eigen::Vector3d AttractorDirectionField::Lifted(const Eigen::Vector3d& point_in_world) const {
  LiftSums sums;
  for (const ViewField& view : views_) Accumulate(view, point_in_world, &sums);
  return Combine(point_in_world, sums);
}

void AttractorDirectionField::FillSamples(const size_t* indices, int count) const {
  // Views outermost: the points' computations are independent, so the
  // processor overlaps their latencies (divisions, square roots, look-ups).
  // Only the corners a look-up needs are filled: bricks of 2^3 cells filled
  // 129k samples where the benchmark's flow reads about half as many.
  Eigen::Vector3d points[8];
  LiftSums sums[8];
  SYLVA_CHECK(count <= 8);
  const size_t dy = dims_.x(), dz = static_cast<size_t>(dims_.x()) * dims_.y();
  for (int n = 0; n < count; ++n) {
    const size_t index = indices[n];
    const Eigen::Vector3d ijk(static_cast<double>(index % dy),
                              static_cast<double>(index / dy % dims_.y()),
                              static_cast<double>(index / dz));
    points[n] = origin_ + spacing_ * ijk;
  }
  for (const ViewField& view : views_) {
    for (int n = 0; n < count; ++n) Accumulate(view, points[n], &sums[n]);
  }
  for (int n = 0; n < count; ++n) {
    Slot& slot = samples_[indices[n]];
    slot.value = Combine(points[n], sums[n]).cast<float>();
    slot.state.store(kFilled, std::memory_order_release);
  }
}

Eigen::Vector3d AttractorDirectionField::Direction(const Eigen::Vector3d& point_in_world) const {
  if (views_.empty()) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d g = ((point_in_world - origin_) / spacing_)
                                .cwiseMax(Eigen::Vector3d::Zero())
                                .cwiseMin((dims_.array() - 1).cast<double>().matrix());
  const Eigen::Vector3i i0 = g.cast<int>().cwiseMin(dims_ - Eigen::Vector3i::Constant(2));
  const Eigen::Vector3d t = g - i0.cast<double>();
  // The cell's 8 samples, x fastest, each filled first if needed.
  const size_t dy = dims_.x(), dz = static_cast<size_t>(dims_.x()) * dims_.y();
  const size_t base = i0.z() * dz + i0.y() * dy + i0.x();
  const size_t corners[8] = {base,      base + 1,      base + dy,      base + dy + 1,
                             base + dz, base + dz + 1, base + dz + dy, base + dz + dy + 1};
  // Those no thread has filled or is filling are claimed and filled
  // together; then those another thread was filling are waited for.
  size_t claimed[8], waiting[8];
  int num_claimed = 0, num_waiting = 0;
  for (const size_t corner : corners) {
    std::atomic<uint32_t>& slot_state = samples_[corner].state;
    uint32_t state = slot_state.load(std::memory_order_acquire);
    if (state == kFilled) continue;
    if (state == kEmpty &&
        slot_state.compare_exchange_strong(state, kFilling, std::memory_order_acquire)) {
      claimed[num_claimed++] = corner;
    } else if (state != kFilled) {
      waiting[num_waiting++] = corner;
    }
  }
  if (num_claimed > 0) FillSamples(claimed, num_claimed);
  for (int w = 0; w < num_waiting; ++w) {
    while (samples_[waiting[w]].state.load(std::memory_order_acquire) != kFilled) {
      std::this_thread::yield();
    }
  }
  const auto at = [&](int c) { return samples_[corners[c]].value.cast<double>(); };
  const Eigen::Vector3d x00 = (1 - t.x()) * at(0) + t.x() * at(1);
  const Eigen::Vector3d x10 = (1 - t.x()) * at(2) + t.x() * at(3);
  const Eigen::Vector3d x01 = (1 - t.x()) * at(4) + t.x() * at(5);
  const Eigen::Vector3d x11 = (1 - t.x()) * at(6) + t.x() * at(7);
  return (1 - t.z()) * ((1 - t.y()) * x00 + t.y() * x10) +
         t.z() * ((1 - t.y()) * x01 + t.y() * x11);
}

}  // namespace sylva
