#include "reconstruct/attractors/livewire_seeds.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <utility>

#include "core/util/random.h"
#include "core/util/thinning.h"

namespace sylva {
namespace {

// Cost factor of steps onto background pixels in geodesic distances.
constexpr float kOffMaskFactor = 8.0f;
constexpr int kNeighbours[8][2] = {{-1, -1}, {0, -1}, {1, -1}, {-1, 0},
                                   {1, 0},   {-1, 1}, {0, 1},  {1, 1}};

// The mask pixel with the largest finite distance (lowest index on ties), or
// (-1, -1) if every mask pixel is at distance 0.
cv::Point FarthestMaskPixel(const cv::Mat& mask, const cv::Mat& distance) {
  cv::Point best(-1, -1);
  float best_distance = 0;
  for (int y = 0; y < mask.rows; ++y) {
    for (int x = 0; x < mask.cols; ++x) {
      const float d = distance.at<float>(y, x);
      if (mask.at<uchar>(y, x) && d > best_distance) best_distance = d, best = cv::Point(x, y);
    }
  }
  return best;
}

std::vector<cv::Point> FarthestPointSeeds(const cv::Mat& mask, const cv::Point& target, int count) {
  cv::Mat distance(mask.size(), CV_32FC1, cv::Scalar(std::numeric_limits<float>::infinity()));
  LowerGeodesicDistance(mask, {target}, &distance);
  std::vector<cv::Point> seeds;
  while (static_cast<int>(seeds.size()) < count) {
    const cv::Point seed = FarthestMaskPixel(mask, distance);
    if (seed.x < 0) break;
    seeds.push_back(seed);
    LowerGeodesicDistance(mask, {seed}, &distance);
  }
  return seeds;
}

// End points of the mask's skeleton (thinning), farthest from the target
// first.
std::vector<cv::Point> SkeletonTipSeeds(const cv::Mat& mask, const cv::Point& target, int count) {
  cv::Mat skeleton = (mask != 0);  // a fresh continuous copy, 255 on the mask
  ThinZhangSuen(skeleton.cols, skeleton.rows, skeleton.step, skeleton.ptr<uchar>());
  cv::Mat distance(mask.size(), CV_32FC1, cv::Scalar(std::numeric_limits<float>::infinity()));
  LowerGeodesicDistance(mask, {target}, &distance);
  std::vector<std::pair<float, cv::Point>> tips;
  for (int y = 0; y < mask.rows; ++y) {
    for (int x = 0; x < mask.cols; ++x) {
      if (!skeleton.at<uchar>(y, x)) continue;
      int neighbours = 0;
      for (const auto& n : kNeighbours) {
        const cv::Point q(x + n[0], y + n[1]);
        neighbours += q.inside(cv::Rect(0, 0, mask.cols, mask.rows)) && skeleton.at<uchar>(q) != 0;
      }
      if (neighbours == 1) tips.push_back({distance.at<float>(y, x), cv::Point(x, y)});
    }
  }
  std::stable_sort(tips.begin(), tips.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<cv::Point> seeds;
  for (int k = 0; k < std::min<int>(count, tips.size()); ++k) seeds.push_back(tips[k].second);
  return seeds;
}

// Random distinct pixels of the mask's outline (mask pixels with a
// 4-neighbour off the mask or off the image).
std::vector<cv::Point> SilhouetteSeeds(const cv::Mat& mask, int count, uint64_t seed) {
  std::vector<cv::Point> outline;
  const cv::Rect image(0, 0, mask.cols, mask.rows);
  for (int y = 0; y < mask.rows; ++y) {
    for (int x = 0; x < mask.cols; ++x) {
      if (!mask.at<uchar>(y, x)) continue;
      bool edge = false;
      for (const cv::Point q :
           {cv::Point(x - 1, y), cv::Point(x + 1, y), cv::Point(x, y - 1), cv::Point(x, y + 1)}) {
        edge = edge || !q.inside(image) || !mask.at<uchar>(q);
      }
      if (edge) outline.emplace_back(x, y);
    }
  }
  RandomEngine random(seed);
  const int n = std::min<int>(count, outline.size());
  for (int k = 0; k < n; ++k) {  // partial Fisher-Yates
    const int pick =
        k + static_cast<int>(random.UniformInt(static_cast<uint32_t>(outline.size() - k)));
    std::swap(outline[k], outline[pick]);
  }
  outline.resize(n);
  return outline;
}

}  // namespace

void LowerGeodesicDistance(const cv::Mat& mask, const std::vector<cv::Point>& sources,
                           cv::Mat* distance) {
  using Entry = std::pair<float, int>;  // distance, pixel index
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  const int width = mask.cols;
  float* d = distance->ptr<float>(0);
  for (const cv::Point& source : sources) {
    d[source.y * width + source.x] = 0;
    queue.push({0.0f, source.y * width + source.x});
  }
  const float diagonal = std::sqrt(2.0f);
  while (!queue.empty()) {
    const auto [dist, index] = queue.top();
    queue.pop();
    if (dist > d[index]) continue;
    const int x = index % width, y = index / width;
    for (const auto& n : kNeighbours) {
      const int qx = x + n[0], qy = y + n[1];
      if (qx < 0 || qy < 0 || qx >= width || qy >= mask.rows) continue;
      const float step = (n[0] != 0 && n[1] != 0) ? diagonal : 1.0f;
      const float next = dist + step * (mask.at<uchar>(qy, qx) ? 1.0f : kOffMaskFactor);
      if (next < d[qy * width + qx]) {
        d[qy * width + qx] = next;
        queue.push({next, qy * width + qx});
      }
    }
  }
}

std::vector<cv::Point> AutomaticSeeds(const cv::Mat& mask, const cv::Point& target,
                                      const LivewireOptions& options) {
  if (options.seeds == "silhouette") return SilhouetteSeeds(mask, options.num_seeds, options.seed);
  if (options.seeds == "skeleton_tips") return SkeletonTipSeeds(mask, target, options.num_seeds);
  return FarthestPointSeeds(mask, target, options.num_seeds);
}

}  // namespace sylva
