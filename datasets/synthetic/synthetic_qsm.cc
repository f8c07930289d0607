#include "datasets/synthetic/synthetic_qsm.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

// The tree generator uses streams 1 and 2 of the seed; the table's noise is
// its own stream, so the skeleton stays the synthetic tree of that seed.
constexpr uint64_t kQsmStream = 3;

// Uniform in the unit ball (rejection sampling; deterministic per stream).
Eigen::Vector3d InUnitBall(RandomEngine* rng) {
  for (;;) {
    const Eigen::Vector3d p(rng->Uniform(-1.0, 1.0), rng->Uniform(-1.0, 1.0),
                            rng->Uniform(-1.0, 1.0));
    if (p.squaredNorm() <= 1.0) return p;
  }
}

// A branch axis as a polyline with arc lengths and the radius at each point.
struct AxisLine {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> arc, radius;

  double Length() const { return arc.back(); }
  // The segment holding arc length s (clamped), and where on it.
  int Segment(double s, double* f) const {
    int k = 0;
    while (k + 2 < static_cast<int>(arc.size()) && arc[k + 1] < s) ++k;
    const double span = arc[k + 1] - arc[k];
    *f = span > 0 ? std::clamp((s - arc[k]) / span, 0.0, 1.0) : 0.0;
    return k;
  }
  Eigen::Vector3d PointAt(double s) const {
    double f = 0.0;
    const int k = Segment(s, &f);
    return (1 - f) * points[k] + f * points[k + 1];
  }
  double RadiusAt(double s) const {
    double f = 0.0;
    const int k = Segment(s, &f);
    return (1 - f) * radius[k] + f * radius[k + 1];
  }
};

}  // namespace

SyntheticTreeOptions SyntheticQsmOptions::ThinTwigTree() {
  SyntheticTreeOptions tree;
  // A tip carries almost nothing beyond itself, so the pipe model thins the
  // twigs down to the floor.
  tree.tip_length = 0.005;
  tree.min_radius = 0.001;
  return tree;
}

void SyntheticQsmOptions::Check() const {
  tree.Check();
  SYLVA_CHECK_INPUT(cylinder_length_radii > 0, "SyntheticQsm.cylinder_length_radii")
      << "must be > 0, got " << cylinder_length_radii;
  SYLVA_CHECK_INPUT(min_cylinder_length > 0 && min_cylinder_length <= max_cylinder_length,
                    "SyntheticQsm.min_cylinder_length")
      << "must be in (0, max_cylinder_length], got " << min_cylinder_length;
  SYLVA_CHECK_INPUT(position_noise >= 0, "SyntheticQsm.position_noise")
      << "must be >= 0, got " << position_noise;
  SYLVA_CHECK_INPUT(radius_noise >= 0 && radius_noise < 1, "SyntheticQsm.radius_noise")
      << "must be in [0, 1), got " << radius_noise;
  SYLVA_CHECK_INPUT(overlap_radii >= 0 && overlap_radii < 1, "SyntheticQsm.overlap_radii")
      << "must be in [0, 1), got " << overlap_radii;
  SYLVA_CHECK_INPUT(child_start_depth >= 0 && child_start_depth <= 1,
                    "SyntheticQsm.child_start_depth")
      << "must be in [0, 1], got " << child_start_depth;
  SYLVA_CHECK_INPUT(fragments >= 0, "SyntheticQsm.fragments") << "must be >= 0, got " << fragments;
}

QsmModel GenerateSyntheticQsm(const SyntheticQsmOptions& options, uint64_t seed) {
  options.Check();
  const SkeletonGraph skeleton = GenerateSyntheticSkeleton(options.tree, seed);
  RandomEngine rng(seed, kQsmStream);
  std::vector<int> orders;
  const std::vector<BranchAxis> axes = skeleton.BranchAxes(&orders);
  QsmModel qsm;
  qsm.radius_source = qsm.position_source = qsm.branching_source = "ground truth";
  qsm.units = "m";
  // The cylinder (index into qsm.cylinders) each node lies on, along its axis.
  std::vector<int> cylinder_at(skeleton.NumNodes(), -1);
  std::vector<int> first_cylinders;  // of each branch axis but the trunk
  for (size_t a = 0; a < axes.size(); ++a) {
    const BranchAxis& axis = axes[a];
    if (axis.size() < 2) continue;
    AxisLine line;
    for (size_t k = 0; k < axis.size(); ++k) {
      const SkeletonNode& node = skeleton.nodes[axis[k]];
      line.points.push_back(node.position);
      line.arc.push_back(k == 0 ? 0.0
                                : line.arc.back() + (node.position - line.points[k - 1]).norm());
      // A lateral's first point takes its first edge's radius, not the parent's.
      line.radius.push_back(k == 0 && a > 0 ? skeleton.nodes[axis[1]].radius : node.radius);
    }
    if (line.Length() <= 0) continue;
    // A lateral starts inside its parent, near the parent's axis.
    const double parent_radius = a > 0 ? skeleton.nodes[axis[0]].radius : 0.0;
    double s = std::min((1 - options.child_start_depth) * parent_radius, 0.5 * line.Length());
    std::vector<double> cuts = {s};
    while (s < line.Length()) {
      const double length = std::clamp(options.cylinder_length_radii * line.RadiusAt(s),
                                       options.min_cylinder_length, options.max_cylinder_length);
      s = line.Length() - (s + length) < 0.5 * length ? line.Length() : s + length;
      cuts.push_back(s);
    }
    std::vector<Eigen::Vector3d> points;
    for (double cut : cuts) {
      points.push_back(line.PointAt(cut) +
                       options.position_noise * line.RadiusAt(cut) * InUnitBall(&rng));
    }
    const int first = static_cast<int>(qsm.cylinders.size());
    for (size_t j = 0; j + 1 < cuts.size(); ++j) {
      QsmCylinder c;
      c.id = static_cast<int64_t>(qsm.cylinders.size()) + 1;
      const double mid = 0.5 * (cuts[j] + cuts[j + 1]);
      c.radius = std::max(options.tree.min_radius,
                          line.RadiusAt(mid) * (1 + rng.Uniform(-1.0, 1.0) * options.radius_noise));
      const Eigen::Vector3d d = (points[j + 1] - points[j]).normalized();
      c.start = points[j] - (j > 0 ? options.overlap_radii * c.radius : 0.0) * d;
      c.length = (points[j + 1] - c.start).norm();
      c.axis = d;
      c.branch = static_cast<int64_t>(a) + 1;
      c.branch_order = orders[a];
      if (j > 0) {
        c.parent_id = qsm.cylinders.back().id;
      } else if (a > 0) {
        c.parent_id = qsm.cylinders[cylinder_at[axis[0]]].id;
      }
      qsm.cylinders.push_back(c);
    }
    // Nodes hang from the cylinder whose stretch of the axis holds them.
    for (size_t k = a == 0 ? 0 : 1; k < axis.size(); ++k) {
      size_t j = 0;
      while (j + 2 < cuts.size() && cuts[j + 1] < line.arc[k]) ++j;
      cylinder_at[axis[k]] = first + static_cast<int>(j);
    }
    if (a > 0) first_cylinders.push_back(first);
  }
  // Detached fragments: branches whose first cylinder lost its parent.
  const int fragments = std::min(options.fragments, static_cast<int>(first_cylinders.size()));
  for (int f = 0; f < fragments; ++f) {
    const int pick = f + static_cast<int>(rng.UniformInt(first_cylinders.size() - f));
    std::swap(first_cylinders[f], first_cylinders[pick]);
    qsm.cylinders[first_cylinders[f]].parent_id = 0;
  }
  qsm.Check();
  return qsm;
}

}  // namespace sylva
