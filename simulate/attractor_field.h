// Direction fields from 2D attractor graphs (thesis 3.5, eq. 3.7), and their
// lifting into the 3D direction field that steers the particle flow.
//
// Per photo, a 2D grid embedded in the image plane (by default 100 cells
// along the longer image side, square cells) holds at each cell centre x
//
//   f(x) = h(d) * unit(g - x) + (1 - h(d)) * t(g)                 (eq. 3.7)
//
// with g the point of the attractor graph closest to x (an exact vector
// distance transform of the graph's segments), d = |g - x| in pixels, and
// t(g) the graph's unit tangent at g pointing down the tree (along the edge
// towards its parent). The blend h is
//   - "linear":   h(d) = min(d / falloff, 1): far from the graph particles
//                 head for it, on it they follow it down (fig. 3.8a);
//   - "constant": h(d) = h0 for d > 0: particles approach the graph at a
//                 fixed angle atan(h0 / (1 - h0)) from its tangent (fig. 3.8b).
// On the graph (d = 0) f = t. Between cell centres f is interpolated
// bilinearly.
//
// In 3D (thesis 3.5: "we project the particle position into each of the
// image planes ... and compute the average"), a world point X is projected
// into every view with a graph; each view's f, a direction in pixels, is
// lifted to the world direction it depicts at X: the displacement parallel to
// the image plane at X's depth that moves X's projection along f, i.e.
// R^T (f_x / fx, f_y / fy, 0) normalised and scaled by |f| (the same
// formula for orthographic and pinhole cameras; lens distortion is ignored
// for the lifting). The views' lifted vectors are combined by
//   - "average":   their mean (the thesis), taken in the least-squares sense:
//                 the v whose projections onto the views' image planes best
//                 match the lifted vectors, (sum_k P_k) v = sum_k l_k with
//                 P_k = I - z_k z_k^T (z_k the optical axis). The
//                 plain mean would shorten every component a view cannot
//                 see (with views around a ring, halve horizontal ones);
//                 length at most 1;
//   - "intersect": the unit direction whose projection agrees with every
//                 view's f: each view restricts it to the plane through the
//                 viewing ray at X and the lifted f, and the least-squares
//                 intersection of these planes (the eigenvector of the
//                 smallest eigenvalue of sum n n^T, n the planes' normals)
//                 is taken, unit length, signed to agree with the mean. It
//                 recovers a 3D direction exactly from views that see it
//                 consistently, whatever the lengths of their 2D vectors.
//                 Where the planes do not pin a line down (one view, or
//                 parallel viewing directions) it falls back to the mean.
// Views in which X projects outside the image, or behind a pinhole camera,
// do not take part; where no view does, the direction is zero.
//
// The flow evaluates the field about ten times per particle and step, so the
// 3D field is sampled on a regular grid over the tree's bounds and
// interpolated trilinearly: its cost per particle step is a constant,
// independent of the number of views and particles. The grid is filled
// lazily, each sample the first time a particle needs it (particles visit
// the crown and the paths to the base, a fraction of the box); a sample's
// value does not depend on when it is filled, so the field is the same as
// one sampled whole.
#ifndef SYLVA_SIMULATE_ATTRACTOR_FIELD_H_
#define SYLVA_SIMULATE_ATTRACTOR_FIELD_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/types/attractor_graph.h"
#include "core/types/image_set.h"
#include "core/util/progress.h"
#include "simulate/direction_field.h"

namespace sylva {

struct AttractorFieldOptions {
  // Cells of each 2D field along the longer image side (the thesis: 100).
  int resolution = 100;
  // The blend h(d) of eq. 3.7: "linear" or "constant".
  std::string blend = "linear";
  // "linear": the distance at which h reaches 1, as a fraction of the longer
  // image side (0.05 gave the closest skeletons on synthetic trees; 0.03 and
  // 0.1 were within a few per cent).
  double falloff = 0.05;
  // "constant": h0 in (0, 1).
  double constant_h = 0.5;
  // How the views' lifted directions combine: "average" or "intersect".
  std::string combine = "average";
  // Cells of the sampled 3D field along the longest side of its box.
  int resolution_3d = 96;

  // Throws InputError("Attractors.<field>", ...).
  void Check() const;
};

// The 2D direction field of one attractor graph.
class DirectionField2D {
 public:
  // Builds the field over the graph's image (graph.width x graph.height);
  // an empty graph gives a zero field. Throws InputError if the options or
  // the graph are invalid.
  DirectionField2D(const AttractorGraph2D& graph, const AttractorFieldOptions& options);

  int cols() const { return cols_; }
  int rows() const { return rows_; }
  double cell_size() const { return cell_size_; }  // pixels
  bool IsEmpty() const { return empty_; }
  // The field at a pixel position (bilinear between cell centres, clamped
  // at the border); length <= 1.
  Eigen::Vector2d At(const Eigen::Vector2d& point_in_image) const;
  // Eq. 3.7 evaluated exactly at a point (no grid): for tests and the
  // benchmark's reference.
  Eigen::Vector2d Evaluate(const Eigen::Vector2d& point_in_image) const;
  // The stored value of cell (col, row).
  Eigen::Vector2d Cell(int col, int row) const {
    return values_[static_cast<size_t>(row) * cols_ + col].cast<double>();
  }

 private:
  struct Segment {
    Eigen::Vector2d a, b;     // child, parent
    Eigen::Vector2d tangent;  // unit(b - a), or zero
  };
  // The closest point of the graph to p, the tangent there, and the
  // distance, using the bucket grid of segments (exact).
  void Closest(const Eigen::Vector2d& p, Eigen::Vector2d* closest, Eigen::Vector2d* tangent,
               double* distance) const;
  Eigen::Vector2d Blend(const Eigen::Vector2d& p, const Eigen::Vector2d& closest,
                        const Eigen::Vector2d& tangent, double distance) const;

  AttractorFieldOptions options_;
  int width_ = 0, height_ = 0;
  int cols_ = 0, rows_ = 0;
  double cell_size_ = 1.0;
  double inverse_cell_size_ = 1.0;
  double falloff_px_ = 1.0;
  bool linear_blend_ = true;  // options_.blend == "linear"
  bool empty_ = true;
  std::vector<Segment> segments_;
  // Segments bucketed on a coarse grid for the closest-point search.
  double bucket_size_ = 1.0;
  int bucket_cols_ = 1, bucket_rows_ = 1;
  std::vector<int> bucket_start_;  // CSR offsets, bucket_cols_ * bucket_rows_ + 1
  std::vector<int> bucket_items_;
  // Per bucket: how many rings around it hold no segment (its Chebyshev
  // distance, in buckets, to the nearest bucket that holds one).
  std::vector<int> empty_rings_;
  std::vector<Eigen::Vector2f> values_;  // rows_ x cols_
};

// The 3D direction field lifted from per-view 2D fields.
class AttractorDirectionField : public DirectionField {
 public:
  // `graphs` holds one graph per view of `image_set` (empty graphs: the view
  // has none and does not take part); each graph's size must match its
  // camera's image size (a graph for a scaled image is rescaled). The 3D
  // field is sampled over `bounds` (world frame); outside it, the nearest
  // sample is used. Throws InputError on a size mismatch or bad options.
  AttractorDirectionField(const ImageSet& image_set, const std::vector<AttractorGraph2D>& graphs,
                          const Eigen::AlignedBox3d& bounds, const AttractorFieldOptions& options,
                          ProgressReporter* progress = nullptr);

  ~AttractorDirectionField() override;

  // Trilinear interpolation of the sampled field (filling the samples it
  // reads). Thread-safe.
  Eigen::Vector3d Direction(const Eigen::Vector3d& point_in_world) const override;
  // The lifted and combined direction computed exactly at a point (no 3D
  // grid, but the views' 2D grids): for tests and the benchmark's reference.
  Eigen::Vector3d Lifted(const Eigen::Vector3d& point_in_world) const;

  int NumViewsWithGraphs() const { return static_cast<int>(views_.size()); }
  Eigen::Vector3i SampleDims() const { return dims_; }
  // Samples filled so far, and in all (for tests and profiles).
  int FilledSamples() const;
  int NumSamples() const { return dims_.prod(); }
  // The 2D field of view `view_idx`, or null if it has no graph.
  const DirectionField2D* Field2D(int view_idx) const;

 private:
  struct ViewField {
    int view_idx;
    Eigen::Matrix3d world_from_cam;  // rotation
    Eigen::Vector3d center;          // projection centre (pinhole)
    bool orthographic;
    bool plain_pinhole;  // no distortion: projected here, as Camera::ImgFromCam does
    double fx, fy;
    Eigen::Vector2d principal_point;
    int width, height;
    DirectionField2D field;
    const Camera* camera = nullptr;  // image_set_'s
    Rigid3d cam_from_world;
    Eigen::Matrix3d cam_from_world_rotation;  // cam_from_world's, as a matrix
    // An image vector (dx, dy) lifts to dx * lift_x + dy * lift_y (world).
    Eigen::Vector3d lift_x, lift_y;
    Eigen::Matrix3d projector;  // onto the image plane: I - z z^T, z the optical axis
  };
  // Where `view` sees a world point (pixels); false if it does not (behind
  // the camera or outside the image).
  static bool PixelIn(const ViewField& view, const Eigen::Vector3d& point_in_world,
                      Eigen::Vector2d* pixel);
  // The eigen decomposition of a sum of the views' projectors (Lifted).
  struct PlaneSolve {
    Eigen::Vector3d values = Eigen::Vector3d::Zero();
    Eigen::Matrix3d vectors = Eigen::Matrix3d::Identity();
  };
  static PlaneSolve SolvePlanes(const Eigen::Matrix3d& planes);
  // Its pseudo-inverse: directions of eigenvalues below
  // kDegenerateEigenFraction of their sum (seen by no view) are left out.
  static Eigen::Matrix3d PseudoInverse(const PlaneSolve& planes);
  // Lifted, in two parts: each view's share, then their combination.
  struct LiftSums {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();      // of the lifted vectors
    Eigen::Matrix3d normals = Eigen::Matrix3d::Zero();  // of w n n^T ("intersect")
    int seen = 0;                                       // views that see the point
  };
  void Accumulate(const ViewField& view, const Eigen::Vector3d& point_in_world,
                  LiftSums* sums) const;
  Eigen::Vector3d Combine(const Eigen::Vector3d& point_in_world, const LiftSums& sums) const;

  ImageSet image_set_;
  AttractorFieldOptions options_;
  std::vector<ViewField> views_;
  bool intersect_ = false;  // options_.combine == "intersect"
  // The sum of every view's projector and its pseudo-inverse: most points
  // are seen by every view.
  Eigen::Matrix3d all_planes_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d all_planes_inverse_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();  // centre of sample (0, 0, 0)
  double spacing_ = 1.0;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Ones();
  // Fills the samples at the given linear indices (at most 8), which the
  // caller has claimed (kFilling), and marks them kFilled.
  void FillSamples(const size_t* indices, int count) const;

  // Lazily filled samples, x fastest. A sample's state goes from kEmpty to
  // kFilling (claimed by one thread, which computes and writes it) to
  // kFilled (release); it is read after kFilled is seen (acquire). A thread
  // that finds it being filled waits for it. Value and state share a slot
  // (one cache line to read both).
  static constexpr uint32_t kEmpty = 0, kFilling = 1, kFilled = 2;
  struct alignas(16) Slot {
    Eigen::Vector3f value = Eigen::Vector3f::Zero();
    std::atomic<uint32_t> state{kEmpty};
  };
  size_t num_samples_ = 0;
  std::unique_ptr<Slot[]> samples_;
};

}  // namespace sylva

#endif  // SYLVA_SIMULATE_ATTRACTOR_FIELD_H_
