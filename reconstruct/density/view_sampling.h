// How the density stage samples views: per-view downsampling to about the
// grid's resolution, ray positions inside downsampled pixels, and voxel
// footprints (the image rectangle a voxel projects to).
#ifndef SYLVA_RECONSTRUCT_DENSITY_VIEW_SAMPLING_H_
#define SYLVA_RECONSTRUCT_DENSITY_VIEW_SAMPLING_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/geometry/voxel_traversal.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/util/progress.h"

namespace sylva {

// Sampling of one view: downsampled pixel (I, J) covers original pixels
// [I f, min((I+1) f, width)) x [J f, min((J+1) f, height)), and is sampled by
// n x n rays spread evenly over that block.
struct ViewSampling {
  int factor = 1;
  int rays_per_axis = 1;
  int original_width = 0;
  int original_height = 0;

  int width() const { return (original_width + factor - 1) / factor; }
  int height() const { return (original_height + factor - 1) / factor; }
  // Ray position (a, b) in [0, n)^2 of pixel (I, J), in original image
  // coordinates (COLMAP convention, pixel centres at +0.5).
  Eigen::Vector2d RayPosition(int pixel_x, int pixel_y, int a, int b) const;
};

// The integer factor that makes a voxel of `voxel_size` (world units) at
// `center_in_world` about `pixels_per_voxel` pixels wide in the view.
ViewSampling MakeViewSampling(const ImageSet& image_set, int view_idx,
                              const Eigen::Vector3d& center_in_world, double voxel_size,
                              double pixels_per_voxel, int rays_per_axis);

// Projects world points into one view with the pose as a matrix (faster
// than going through the quaternion for every point), and for a pinhole
// camera without distortion with its intrinsics at hand (the same
// arithmetic as Camera::ImgFromCam, without its calls).
class ViewProjector {
 public:
  ViewProjector(const ImageSet& image_set, int view_idx);
  // False if the point is behind a pinhole camera.
  bool Project(const Eigen::Vector3d& point_in_world, Eigen::Vector2d* point_in_image) const {
    const Eigen::Vector3d point_in_cam = rotation_ * point_in_world + translation_;
    // Camera::IsInFront, without the call.
    if (!orthographic_ && !(point_in_cam.z() > std::numeric_limits<double>::epsilon())) {
      return false;
    }
    if (plain_pinhole_) {
      *point_in_image = Eigen::Vector2d(focal_.x() * (point_in_cam.x() / point_in_cam.z()),
                                        focal_.y() * (point_in_cam.y() / point_in_cam.z())) +
                        principal_point_;
    } else {
      *point_in_image = camera_->ImgFromCam(point_in_cam);
    }
    return true;
  }
  // Whether the image of a convex body lies inside the convex hull of the
  // images of its points' extremes (no lens distortion to bulge it): then a
  // box's image lies inside the rectangle of its 8 projected corners.
  bool KeepsBoxesInCornerRects() const { return !camera_->HasDistortion(); }
  // The bounding rectangle of the projections of the 8 corners of the cube
  // of edge `size` whose lowest corner is `lower` (world units); false if a
  // corner is behind a pinhole camera.
  bool ProjectCube(const Eigen::Vector3d& lower, double size, Eigen::AlignedBox2d* rect) const {
    rect->setEmpty();
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d offset(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
      Eigen::Vector2d pixel;
      if (!Project(lower + size * offset, &pixel)) return false;
      rect->extend(pixel);
    }
    return true;
  }

 private:
  const Camera* camera_;
  Eigen::Matrix3d rotation_;
  Eigen::Vector3d translation_;
  bool orthographic_ = false;
  bool plain_pinhole_ = false;  // not orthographic, no distortion
  Eigen::Vector2d focal_, principal_point_;
};

// Summed-area tables of single-channel images, built in parallel.
std::vector<SummedAreaTable> MakeSummedAreaTables(const std::vector<FloatImage>& images);

// For every voxel of `block` (dense index), the minimum over views (all of
// them, or those listed in `views`) of the mean of `tables[view]`'s image over
// the voxel's footprint (the bounding rectangle of its 8 projected corners).
// Views in which the voxel is behind the camera or outside the image are
// skipped; a voxel no view sees gets 0. With mattes this is the thesis'
// initial density (3.3); with a binary foreground mask it is a conservative
// visual-hull test (> 0 = kept).
std::vector<float> MinFootprintMeans(const ImageSet& image_set,
                                     const std::vector<SummedAreaTable>& tables,
                                     const VoxelBlock& block, const ProgressTask& progress,
                                     const std::vector<int>* views = nullptr);

// Like MinFootprintMeans, but the (rank + 1)-th smallest mean over the views
// that see each voxel (rank 0: the minimum; where fewer views see a voxel,
// the largest of theirs): carving that `rank` views may disagree with.
std::vector<float> LowFootprintMeans(const ImageSet& image_set,
                                     const std::vector<SummedAreaTable>& tables,
                                     const VoxelBlock& block, int rank,
                                     const ProgressTask& progress);

// Per voxel of a block: how many of the given views see it, and how many of
// those carve it away (footprint mean <= a threshold). With at most
// kMaxVoterBits views, also which: bit k for views[k] (else empty).
struct FootprintVotes {
  static constexpr size_t kMaxVoterBits = 64;
  std::vector<uint16_t> seen;
  std::vector<uint16_t> vetoes;
  std::vector<uint64_t> seen_by;
  std::vector<uint64_t> vetoed_by;
};

// The votes of `views` (indices into image_set, at most 65535) on every voxel
// of `block`, or only on those where `wanted` (if not null; one entry per
// voxel) is non-zero. A view vetoes a voxel when the mean of its table over
// the voxel's footprint is <= `threshold`.
FootprintVotes CountFootprintVetoes(const ImageSet& image_set,
                                    const std::vector<SummedAreaTable>& tables,
                                    const std::vector<int>& views, const VoxelBlock& block,
                                    double threshold, const std::vector<char>* wanted,
                                    const ProgressTask& progress);

// Per view of `views`: how many voxels of `block` where `wanted` is non-zero
// (one entry per voxel) it sees, and how many of those it vetoes (mean <=
// `threshold`); both indexed like `views`. One pass for every view.
struct ViewVetoCounts {
  std::vector<int64_t> seen;
  std::vector<int64_t> vetoes;
};
ViewVetoCounts CountVetoesPerView(const ImageSet& image_set,
                                  const std::vector<SummedAreaTable>& tables,
                                  const std::vector<int>& views, const VoxelBlock& block,
                                  double threshold, const std::vector<char>& wanted,
                                  const ProgressTask& progress);
// The same counts from votes that say which view voted (seen_by and
// vetoed_by not empty), without a second pass over the footprints.
ViewVetoCounts CountVetoesPerView(const FootprintVotes& votes, size_t num_views,
                                  const std::vector<char>& wanted);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_VIEW_SAMPLING_H_
