// Distances between point sets (e.g. skeletons sampled along their edges).
#ifndef SYLVA_DATASETS_EVAL_POINT_METRICS_H_
#define SYLVA_DATASETS_EVAL_POINT_METRICS_H_

#include <Eigen/Core>
#include <vector>

namespace sylva {

struct PointSetDistances {
  double mean_a_to_b = 0.0;  // mean over a of the distance to the nearest b
  double mean_b_to_a = 0.0;
  double chamfer = 0.0;    // (mean_a_to_b + mean_b_to_a) / 2
  double hausdorff = 0.0;  // max of both directed maxima
};

// Exact nearest neighbours on a uniform hash grid; both sets non-empty.
PointSetDistances ComparePointSets(const std::vector<Eigen::Vector3d>& a,
                                   const std::vector<Eigen::Vector3d>& b);

}  // namespace sylva

#endif  // SYLVA_DATASETS_EVAL_POINT_METRICS_H_
