// Conversions between FloatImage and cv::Mat. Internal to
// reconstruct/matting: it includes OpenCV, so only .cc files include it and
// no public header may.
#ifndef SYLVA_RECONSTRUCT_MATTING_CV_IMAGE_H_
#define SYLVA_RECONSTRUCT_MATTING_CV_IMAGE_H_

#include <opencv2/core.hpp>

#include "core/types/float_image.h"

namespace sylva {

// The first three channels of an RGB(A) photo as CV_32FC3 in RGB order.
cv::Mat RgbToMat(const FloatImage& photo);
// One channel as CV_32FC1 (copy).
cv::Mat GrayToMat(const FloatImage& image);
// CV_32FC1 or CV_32FC3 (any channel order kept) to a FloatImage.
FloatImage MatToImage(const cv::Mat& mat);
// CV_32FC3 RGB in [0, 1] to CV_8UC3 BGR (rounded), OpenCV's usual 8-bit layout.
cv::Mat RgbToBgr8(const cv::Mat& rgb);

// A disk-shaped structuring element of the given radius (pixels).
cv::Mat Disk(int radius);

// Smallest integer factor that box-downsamples `size` to at most
// `max_megapixels`, and the reduced size (rounded up).
int ReductionFactor(cv::Size size, double max_megapixels);
cv::Size ReducedSize(cv::Size size, int factor);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MATTING_CV_IMAGE_H_
