// Automatic seed points of livewire tracing (LivewireOptions::seeds).
// Internal to reconstruct/attractors (includes OpenCV).
#ifndef SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_SEEDS_H_
#define SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_SEEDS_H_

#include <opencv2/core.hpp>
#include <vector>

#include "reconstruct/attractors/livewire.h"

namespace sylva {

// Geodesic distances from `sources` over the 8-connected pixel grid (steps of
// 1 and sqrt 2), where a step onto a pixel off `mask` costs kOffMaskFactor
// times more: small gaps in a matte do not cut the crown apart. `distance`
// (CV_32FC1, mask's size) is lowered in place: only pixels that get closer
// than their current value are visited, so farthest-point sampling pays for
// each new seed's own region only.
void LowerGeodesicDistance(const cv::Mat& mask, const std::vector<cv::Point>& sources,
                           cv::Mat* distance);

// Seed pixels on the mask (CV_8UC1, 1 = tree) chosen by options.seeds, at
// most options.num_seeds, in tracing order. `target` is a traced pixel.
std::vector<cv::Point> AutomaticSeeds(const cv::Mat& mask, const cv::Point& target,
                                      const LivewireOptions& options);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_SEEDS_H_
