// The per-pixel costs of livewire tracing (see livewire.h), shared by the
// tracer, SnapGraphToImage and the benchmark's reference implementation.
// Internal to reconstruct/attractors: it includes OpenCV, so only .cc files
// include it and no public header may.
#ifndef SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_FEATURES_H_
#define SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_FEATURES_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/types/float_image.h"
#include "reconstruct/attractors/livewire.h"

namespace sylva {

// The photo and matte reduced to the traced size, and the features of
// cv::segmentation::IntelligentScissorsMB::applyImageFeatures.
struct LivewireFeatures {
  int full_width = 0;
  int full_height = 0;
  // Traced pixels per full-resolution pixel along x and y (<= 1).
  double scale_x = 1;
  double scale_y = 1;
  cv::Mat mask;        // CV_8UC1, 1 on the tree (matte >= threshold)
  cv::Mat outside;     // CV_8UC1 "non-edge": 1 - mask
  cv::Mat direction;   // CV_32FC2, unit gradient orientation across branches (or 0)
  cv::Mat centerline;  // CV_32FC1, cost in [0, 1], low on branch centre lines

  // Pixel of the traced copy holding a full-resolution position (clamped).
  cv::Point ToTraced(const Eigen::Vector2d& point_in_image) const;
  // Full-resolution position of a traced pixel's centre.
  Eigen::Vector2d ToFull(const cv::Point& pixel) const;
};

// Checks the inputs (InputError naming "photo"/"matte") and computes the
// features on the reduced copy.
LivewireFeatures ComputeLivewireFeatures(const FloatImage& photo, const FloatImage& matte,
                                         const LivewireOptions& options);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_FEATURES_H_
