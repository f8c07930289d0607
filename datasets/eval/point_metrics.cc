#include "datasets/eval/point_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/geometry/point_grid.h"
#include "core/util/check.h"

namespace sylva {
namespace {

void Directed(const std::vector<Eigen::Vector3d>& from, const PointGrid& to, double* mean,
              double* max) {
  double sum = 0.0;
  *max = 0.0;
  for (const auto& p : from) {
    double d = 0.0;
    to.Nearest(p, std::numeric_limits<double>::infinity(), &d);
    sum += d;
    *max = std::max(*max, d);
  }
  *mean = sum / from.size();
}

}  // namespace

PointSetDistances ComparePointSets(const std::vector<Eigen::Vector3d>& a,
                                   const std::vector<Eigen::Vector3d>& b) {
  SYLVA_CHECK(!a.empty() && !b.empty()) << "comparing an empty point set";
  const PointGrid grid_a(a), grid_b(b);
  PointSetDistances result;
  double max_ab, max_ba;
  Directed(a, grid_b, &result.mean_a_to_b, &max_ab);
  Directed(b, grid_a, &result.mean_b_to_a, &max_ba);
  result.chamfer = 0.5 * (result.mean_a_to_b + result.mean_b_to_a);
  result.hausdorff = std::max(max_ab, max_ba);
  return result;
}

}  // namespace sylva
