// Guided upsampling of a matte computed at reduced resolution (internal to
// reconstruct/matting; includes OpenCV).
//
// The fast guided filter (He, Sun: "Fast Guided Filter", 2015; the colour
// guided filter of He, Sun, Tang, PAMI 2013): in every window of the reduced
// image alpha is fitted as an affine function of the colour, alpha ~ a . I + b
// (ridge regression with regulariser epsilon); the window-averaged a and b
// are upsampled bilinearly and applied to the full-resolution colours, so
// edges follow the full-resolution photo.
#ifndef SYLVA_RECONSTRUCT_MATTING_GUIDED_UPSAMPLE_H_
#define SYLVA_RECONSTRUCT_MATTING_GUIDED_UPSAMPLE_H_

#include <opencv2/core.hpp>

namespace sylva {

// small_rgb: CV_32FC3, small_alpha: CV_32FC1 of the same size; full_rgb:
// CV_32FC3 of the target size. `radius` in reduced pixels. Returns CV_32FC1
// of full_rgb's size, clamped to [0, 1].
cv::Mat GuidedUpsample(const cv::Mat& small_rgb, const cv::Mat& small_alpha,
                       const cv::Mat& full_rgb, int radius, double epsilon);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MATTING_GUIDED_UPSAMPLE_H_
