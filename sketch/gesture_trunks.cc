#include "sketch/gesture_trunks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/geometry/polyline.h"
#include "sketch/gesture_geometry.h"
#include "sketch/gesture_tree.h"

namespace sylva {
namespace gesture_internal {
namespace {

// A trunk joins at its start when a later trunk stroke begins this close to
// the trunk (fraction of the first trunk's length); else a connecting
// segment is added.
constexpr double kJoinFraction = 1e-6;
// Later trunk points are pushed this much beyond touching, in at most this
// many rounds.
constexpr double kPushMargin = 1.02;
constexpr int kPushRounds = 8;

// Arc-length resampling into `segments` pieces, with each piece's speed.
TrunkPath ResampleStroke(const GestureStroke& stroke, int segments, std::vector<double>* speeds) {
  std::vector<double> arc = {0.0};
  for (size_t k = 1; k < stroke.samples.size(); ++k) {
    arc.push_back(arc.back() +
                  (stroke.samples[k].position - stroke.samples[k - 1].position).norm());
  }
  auto at = [&](double s, double* t) {
    size_t k = std::upper_bound(arc.begin(), arc.end(), s) - arc.begin();
    k = std::clamp<size_t>(k, 1, arc.size() - 1);
    const double w = arc[k] > arc[k - 1] ? (s - arc[k - 1]) / (arc[k] - arc[k - 1]) : 0.0;
    *t = (1 - w) * stroke.samples[k - 1].t + w * stroke.samples[k].t;
    return Eigen::Vector3d((1 - w) * stroke.samples[k - 1].position +
                           w * stroke.samples[k].position);
  };
  TrunkPath path;
  std::vector<double> times;
  for (int i = 0; i <= segments; ++i) {
    double t = 0;
    path.points.push_back(at(arc.back() * i / segments, &t));
    times.push_back(t);
  }
  speeds->clear();
  for (int i = 0; i < segments; ++i) {
    speeds->push_back(arc.back() / segments / std::max(times[i + 1] - times[i], 1e-12));
  }
  return path;
}

void SmoothPath(int passes, std::vector<Eigen::Vector3d>* points) {
  for (int pass = 0; pass < passes; ++pass) {
    std::vector<Eigen::Vector3d> next = *points;
    for (size_t i = 1; i + 1 < points->size(); ++i) {
      next[i] = 0.5 * (*points)[i] + 0.25 * ((*points)[i - 1] + (*points)[i + 1]);
    }
    *points = std::move(next);
  }
}

// Murakami 5.2: "Trunk diameter increases in inverse proportion to the
// velocity of the stroke": radius = base x mean speed / speed, clamped.
std::vector<double> RadiiFromSpeed(const std::vector<double>& speeds, double base_radius,
                                   double max_ratio) {
  double mean = 0;
  for (double v : speeds) mean += 1.0 / v;  // time per piece (equal lengths)
  mean = speeds.size() / mean;              // length / time
  std::vector<double> radii;
  for (double v : speeds) {
    radii.push_back(base_radius * std::clamp(mean / v, 1.0 / max_ratio, max_ratio));
  }
  return radii;
}

std::vector<double> ArcLengths(const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> arc = {0.0};
  for (size_t k = 1; k < points.size(); ++k)
    arc.push_back(arc.back() + (points[k] - points[k - 1]).norm());
  return arc;
}

// One round of 4.1.5 for a later trunk: its segments that would pierce an
// earlier trunk's are pushed off it, away from its axis (or, when they
// cross it, along the normal of the plane holding both). Returns how many
// points moved.
int PushRound(const TrunkPlan& plan, int joined, int join_point, TrunkPath* path) {
  int pushed = 0;
  for (size_t j = 1; j < path->points.size(); ++j) {
    const double along_new = ArcLengths(path->points)[j - 1];
    for (size_t t = 0; t < plan.paths.size(); ++t) {
      const TrunkPath& other = plan.paths[t];
      for (size_t k = 0; k + 1 < other.points.size(); ++k) {
        const double reach = path->radii[j - 1] + other.radii[k];
        const double along = static_cast<int>(t) != joined
                                 ? std::numeric_limits<double>::infinity()
                                 : std::min(std::abs(plan.arc[t][k] - plan.arc[t][join_point]),
                                            std::abs(plan.arc[t][k + 1] - plan.arc[t][join_point]));
        if (along_new + along <= kAdjacentReach * reach) continue;  // one tube near the join
        Eigen::Vector3d cp, co;
        const double d = std::sqrt(SegmentSegmentDistance2(
            path->points[j - 1], path->points[j], other.points[k], other.points[k + 1], &cp, &co));
        if (d >= reach) continue;
        // Away from the obstacle's axis, across it (an axial push would
        // only slide the point along the trunk).
        const Eigen::Vector3d axis = (other.points[k + 1] - other.points[k]).normalized();
        Eigen::Vector3d away = cp - co - (cp - co).dot(axis) * axis;
        const double across = away.norm();
        if (across <= kBypassThreshold * reach) {
          away = axis.cross(path->points[j] - path->points[j - 1]);
          if (away.norm() < 1e-12) away = axis.unitOrthogonal();
        }
        const Eigen::Vector3d shift = away.normalized() * (reach * kPushMargin - across);
        for (size_t m : {j - 1, j}) {
          if (m > 0) path->points[m] += shift, ++pushed;
        }
      }
    }
  }
  return pushed;
}

int PushOffEarlierTrunks(const TrunkPlan& plan, int joined, int join_point, TrunkPath* path) {
  int pushed = 0;
  for (int round = 0; round < kPushRounds; ++round) {
    const int moved = PushRound(plan, joined, join_point, path);
    if (moved == 0) break;
    pushed += moved;
  }
  return pushed;
}

// The nearest point of the earlier trunks to `p`: (trunk, point index).
std::pair<int, int> NearestTrunkPoint(const TrunkPlan& plan, const Eigen::Vector3d& p) {
  std::pair<int, int> best = {0, 0};
  double best_d = std::numeric_limits<double>::infinity();
  for (size_t t = 0; t < plan.paths.size(); ++t) {
    for (size_t j = 0; j < plan.paths[t].points.size(); ++j) {
      const double d = (plan.paths[t].points[j] - p).squaredNorm();
      if (d < best_d) best_d = d, best = {static_cast<int>(t), static_cast<int>(j)};
    }
  }
  return best;
}

}  // namespace

// The trunk strokes resampled, smoothed, with radii from their speed
// (4.1.1, 5.2); later ones joined to the nearest trunk point.
TrunkPlan PlanTrunks(const std::vector<const GestureStroke*>& strokes, bool timed,
                     const GestureTreeOptions& o, int* pushed) {
  TrunkPlan plan;
  plan.first_length = strokes[0]->Length();
  for (size_t k = 0; k < strokes.size(); ++k) {
    std::vector<double> speeds;
    TrunkPath path = ResampleStroke(*strokes[k], o.trunk_segments, &speeds);
    SmoothPath(o.smoothing_passes, &path.points);
    std::pair<int, int> join = {-1, -1};
    double base = o.trunk_radius * plan.first_length;
    if (k > 0) {  // a main branch: thinner than the trunk it joins
      join = NearestTrunkPoint(plan, path.points.front());
      const std::vector<double>& radii = plan.paths[join.first].radii;
      base = o.branch_radius_ratio * radii[std::min<size_t>(join.second, radii.size() - 1)];
    }
    path.radii = timed ? RadiiFromSpeed(speeds, base, o.max_speed_ratio)
                       : std::vector<double>(speeds.size(), base);
    if (k > 0) {
      const Eigen::Vector3d at = plan.paths[join.first].points[join.second];
      if ((at - path.points.front()).norm() > kJoinFraction * plan.first_length) {
        path.points.insert(path.points.begin(), at);
        path.radii.insert(path.radii.begin(), path.radii.front());
      } else {
        path.points.front() = at;
      }
      *pushed += PushOffEarlierTrunks(plan, join.first, join.second, &path);
    }
    plan.paths.push_back(path);
    plan.arc.push_back(ArcLengths(path.points));
    plan.joins.emplace_back(path.points.size());
    if (k > 0) plan.joins[join.first][join.second].push_back(static_cast<int>(k));
  }
  return plan;
}

// Silhouette-based modelling (4.2) without a trunk: "the axiom at an
// arbitrary point in the region": a straight trunk up the region's axis,
// from the ground (z = 0, where sylva puts a tree's base) or the region's
// bottom if lower, to the region's centre height.
GestureStroke AxisTrunk(const Supertoroid& roi) {
  GestureStroke stroke;
  stroke.samples.push_back({0.0, roi.AxisAt(std::min(0.0, roi.center.z() - roi.az)), 1.0});
  stroke.samples.push_back({1.0, roi.AxisAt(roi.center.z()), 1.0});
  return stroke;
}

}  // namespace gesture_internal

double TrunkDeviationFraction(const GestureStroke& stroke, const SkeletonGraph& skeleton,
                              const std::vector<int>& trunk_nodes) {
  std::vector<Eigen::Vector3d> gesture, trunk;
  for (const GestureSample& s : stroke.samples) gesture.push_back(s.position);
  for (int node : trunk_nodes) trunk.push_back(skeleton.nodes[node].position);
  // Points of `from` (vertices and midpoints) against the polyline `to`.
  auto one_way = [](const std::vector<Eigen::Vector3d>& from,
                    const std::vector<Eigen::Vector3d>& to) {
    double worst = 0;
    for (size_t i = 0; i < from.size(); ++i) {
      for (const Eigen::Vector3d& p :
           {from[i], Eigen::Vector3d(0.5 * (from[i] + from[std::min(i + 1, from.size() - 1)]))}) {
        double best = std::numeric_limits<double>::infinity();
        for (size_t k = 0; k + 1 < to.size(); ++k)
          best = std::min(best, SegmentDistance2(p, to[k], to[k + 1]));
        worst = std::max(worst, std::sqrt(best));
      }
    }
    return worst;
  };
  return std::max(one_way(gesture, trunk), one_way(trunk, gesture)) / stroke.Length();
}

}  // namespace sylva
