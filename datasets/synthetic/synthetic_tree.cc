#include "datasets/synthetic/synthetic_tree.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

constexpr int kNumLevels = 3;
constexpr double kDegree = M_PI / 180.0;
// Independent random streams, so that leaf options never change the skeleton.
constexpr uint64_t kSkeletonStream = 1;
constexpr uint64_t kLeafStream = 2;
// Crown shape: main branches are longest at this fraction of the crown's
// height and kCrownShapeMin times as long at its top.
constexpr double kCrownShapePeakFraction = 1.0 / 3.0;
constexpr double kCrownShapeMin = 0.35;
// Children of branches shorten towards their parent's tip down to this
// fraction; every child's length varies by +-kLengthJitter.
constexpr double kChildShapeAtTip = 0.5;
constexpr double kLengthJitter = 0.15;
// Children are spread along their parent in equal bins, each child placed
// uniformly within this central part of its bin.
constexpr double kBinJitterLo = 0.2;
constexpr double kBinJitterHi = 0.8;
// A leaf cluster's centre lies this fraction of its long semi-axis back from
// the tip, so the cluster wraps the twig's end.
constexpr double kClusterCentreBack = 0.3;

// Tubes continuing a branch start this many radii (at most this fraction of
// their length) back inside the previous tube, so bends leave no seam.
constexpr double kTubeOverlapRadii = 0.5;
constexpr double kTubeOverlapMaxFraction = 0.5;

const Eigen::Vector3d kUp = Eigen::Vector3d::UnitZ();

// A unit vector perpendicular to unit `v`.
Eigen::Vector3d AnyPerpendicular(const Eigen::Vector3d& v) {
  const Eigen::Vector3d helper =
      std::abs(v.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return v.cross(helper).normalized();
}

Eigen::Vector3d RandomUnitVector(RandomEngine* rng) {
  const double z = rng->Uniform(-1.0, 1.0);
  const double phi = rng->Uniform(0.0, 2.0 * M_PI);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z);
}

// Uniform in the unit ball (rejection sampling; deterministic per stream).
Eigen::Vector3d RandomInUnitBall(RandomEngine* rng) {
  for (;;) {
    const Eigen::Vector3d p(rng->Uniform(-1.0, 1.0), rng->Uniform(-1.0, 1.0),
                            rng->Uniform(-1.0, 1.0));
    if (p.squaredNorm() <= 1.0) return p;
  }
}

// The direction at angle `angle` from unit `axis`, rotated by `azimuth` about
// it from the reference perpendicular AnyPerpendicular(axis).
Eigen::Vector3d DirectionAround(const Eigen::Vector3d& axis, double angle, double azimuth) {
  const Eigen::Vector3d e1 = AnyPerpendicular(axis);
  const Eigen::Vector3d e2 = axis.cross(e1);
  return std::cos(angle) * axis +
         std::sin(angle) * (std::cos(azimuth) * e1 + std::sin(azimuth) * e2);
}

// One axis (trunk or branch) to grow from `base_node` (-1: the trunk's base).
struct Axis {
  int base_node = -1;
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = kUp;
  double length = 0.0;
  int order = 0;
};

class SkeletonGrower {
 public:
  SkeletonGrower(const SyntheticTreeOptions& options, uint64_t seed)
      : options_(options), rng_(seed, kSkeletonStream) {}

  SkeletonGraph Grow() {
    Axis trunk;
    trunk.length = options_.trunk_length;
    GrowWithChildren(trunk);
    AssignPipeModelRadii();
    skeleton_.radius_source = "ground truth";
    return std::move(skeleton_);
  }

 private:
  void GrowWithChildren(const Axis& axis) {
    const std::vector<int> nodes = GrowAxis(axis);
    if (axis.order < kNumLevels) GrowChildren(axis, nodes);
  }

  // Nodes along the axis, starting with its base node.
  std::vector<int> GrowAxis(const Axis& axis) {
    const int segments =
        std::max(1, static_cast<int>(std::ceil(axis.length / options_.max_segment_length)));
    const double step = axis.length / segments;
    std::vector<int> nodes = {axis.base_node};
    if (axis.base_node < 0) nodes[0] = skeleton_.AddNode(axis.start, 0.0, -1, axis.order);
    Eigen::Vector3d position = axis.start;
    Eigen::Vector3d direction = axis.direction;
    for (int s = 0; s < segments; ++s) {
      // The trunk's first segment stays vertical, so its base sits flat at z = 0.
      if (axis.base_node >= 0 || s > 0) direction = Bend(direction, step, axis.order);
      position += step * direction;
      nodes.push_back(skeleton_.AddNode(position, 0.0, nodes.back(), axis.order));
    }
    return nodes;
  }

  // Random wobble plus upward tropism over one step of `step` metres.
  Eigen::Vector3d Bend(const Eigen::Vector3d& direction, double step, int order) {
    const double wobble = order == 0 ? options_.trunk_wobble : options_.branch_wobble;
    const Eigen::Vector3d noise(rng_.Normal(), rng_.Normal(), rng_.Normal());
    Eigen::Vector3d bent = direction + wobble * std::sqrt(step) * noise;
    bent.normalize();
    // Towards +Z, in proportion to the sine of the angle from vertical.
    bent += options_.upward_tropism * step * (kUp - bent.dot(kUp) * bent);
    return bent.normalized();
  }

  void GrowChildren(const Axis& parent, const std::vector<int>& nodes) {
    const int level = parent.order;
    const int count = options_.num_children[level];
    const bool on_trunk = level == 0;
    const double lo = on_trunk ? options_.crown_base : options_.child_start;
    const double hi = on_trunk ? options_.crown_top : 1.0;
    const double azimuth0 = rng_.Uniform(0.0, 2.0 * M_PI);
    for (int k = 0; k < count; ++k) {
      const double u = lo + (hi - lo) * (k + rng_.Uniform(kBinJitterLo, kBinJitterHi)) / count;
      const double jitter = rng_.Uniform(-1.0, 1.0) * options_.phyllotaxis_jitter_deg;
      const double azimuth = azimuth0 + (k * options_.phyllotaxis_angle_deg + jitter) * kDegree;
      const double shape =
          on_trunk ? CrownShape((u - lo) / (hi - lo)) : 1.0 - (1.0 - kChildShapeAtTip) * u;
      GrowWithChildren(ChildAxis(parent, nodes, u, azimuth, shape));
    }
  }

  Axis ChildAxis(const Axis& parent, const std::vector<int>& nodes, double u, double azimuth,
                 double shape) {
    // Attach at an interior node when there is one, so the parent keeps its tip.
    const int segments = static_cast<int>(nodes.size()) - 1;
    const int i =
        std::clamp(static_cast<int>(std::lround(u * segments)), 1, std::max(1, segments - 1));
    const Eigen::Vector3d& position = skeleton_.nodes[nodes[i]].position;
    const Eigen::Vector3d parent_direction =
        (position - skeleton_.nodes[nodes[i - 1]].position).normalized();
    const double angle =
        rng_.Uniform(options_.branch_angle_min_deg, options_.branch_angle_max_deg) * kDegree;
    Axis child;
    child.base_node = nodes[i];
    child.start = position;
    child.direction = DirectionAround(parent_direction, angle, azimuth);
    child.length = parent.length * options_.length_ratio[parent.order] * shape *
                   rng_.Uniform(1.0 - kLengthJitter, 1.0 + kLengthJitter);
    child.order = parent.order + 1;
    return child;
  }

  // Main branch length factor at relative crown height h in [0, 1]: rises
  // from 0.8 at the crown base to 1 at the peak, then falls to kCrownShapeMin.
  static double CrownShape(double h) {
    const double peak = kCrownShapePeakFraction;
    const double x = h < peak ? 0.5 + 0.5 * h / peak : 1.0 + (h - peak) / (1.0 - peak);
    return kCrownShapeMin + (1.0 - kCrownShapeMin) * std::sin(0.5 * M_PI * x);
  }

  // Pipe model: r^e proportional to the carried length (edges below the node
  // plus tip_length per tip). Parents precede children in the node list.
  void AssignPipeModelRadii() {
    const int n = skeleton_.NumNodes();
    std::vector<double> carried(n, 0.0);
    std::vector<int> num_children(n, 0);
    for (int i = 1; i < n; ++i) ++num_children[skeleton_.nodes[i].parent_idx];
    for (int i = n - 1; i >= 0; --i) {
      const SkeletonNode& node = skeleton_.nodes[i];
      if (num_children[i] == 0) carried[i] += options_.tip_length;
      if (node.parent_idx < 0) continue;
      const double edge = (node.position - skeleton_.nodes[node.parent_idx].position).norm();
      carried[node.parent_idx] += carried[i] + edge;
    }
    const double root_carried = carried[skeleton_.RootIdx()];
    for (int i = 0; i < n; ++i) {
      const double fraction = std::pow(carried[i] / root_carried, 1.0 / options_.pipe_exponent);
      skeleton_.nodes[i].radius =
          std::max(options_.min_radius, options_.trunk_base_radius * fraction);
    }
  }

  const SyntheticTreeOptions& options_;
  RandomEngine rng_;
  SkeletonGraph skeleton_;
};

// --- Mesh ---

int NumTubeSides(double radius, const SyntheticTreeOptions& options) {
  const int sides = static_cast<int>(std::ceil(2.0 * M_PI * radius / options.tube_edge_length));
  return std::clamp(sides, options.tube_min_sides, options.tube_max_sides);
}

// A closed frustum from `a` (radius ra) to `b` (radius rb): side quads
// counter-clockwise seen from outside, and a fan cap at each end.
void AddFrustum(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double ra, double rb, int sides,
                int material, TriangleMesh* mesh) {
  const Eigen::Vector3d axis = (b - a).normalized();
  const Eigen::Vector3d e1 = AnyPerpendicular(axis);
  const Eigen::Vector3d e2 = axis.cross(e1);
  const int base = mesh->NumVertices();
  for (int k = 0; k < sides; ++k) {
    const double angle = 2.0 * M_PI * k / sides;
    const Eigen::Vector3d radial = std::cos(angle) * e1 + std::sin(angle) * e2;
    mesh->AddVertex((a + ra * radial).cast<float>());  // base + 2k
    mesh->AddVertex((b + rb * radial).cast<float>());  // base + 2k + 1
  }
  const int centre_a = mesh->AddVertex(a.cast<float>());
  const int centre_b = mesh->AddVertex(b.cast<float>());
  for (int k = 0; k < sides; ++k) {
    const int a0 = base + 2 * k, b0 = a0 + 1;
    const int a1 = base + 2 * ((k + 1) % sides), b1 = a1 + 1;
    mesh->AddTriangle(a0, a1, b1, material);
    mesh->AddTriangle(a0, b1, b0, material);
    mesh->AddTriangle(centre_a, a1, a0, material);
    mesh->AddTriangle(centre_b, b0, b1, material);
  }
}

// A rhombus leaf centred at `centre`, long axis `along`, across `across`.
void AddLeaf(const Eigen::Vector3d& centre, const Eigen::Vector3d& along,
             const Eigen::Vector3d& across, double length, double width, int material,
             TriangleMesh* mesh) {
  const int stalk = mesh->AddVertex((centre - 0.5 * length * along).cast<float>());
  const int right = mesh->AddVertex((centre + 0.5 * width * across).cast<float>());
  const int tip = mesh->AddVertex((centre + 0.5 * length * along).cast<float>());
  const int left = mesh->AddVertex((centre - 0.5 * width * across).cast<float>());
  mesh->AddTriangle(stalk, right, tip, material);
  mesh->AddTriangle(stalk, tip, left, material);
}

// One ellipsoidal cluster of leaves around the tip `tip_idx`; returns its
// ellipsoid.
SyntheticLeafCluster AddLeafCluster(const SkeletonGraph& skeleton, int tip_idx,
                                    const SyntheticTreeOptions& options, int material,
                                    RandomEngine* rng, TriangleMesh* mesh) {
  const SkeletonNode& tip = skeleton.nodes[tip_idx];
  const Eigen::Vector3d axis =
      tip.parent_idx >= 0 ? (tip.position - skeleton.nodes[tip.parent_idx].position).normalized()
                          : kUp;
  const Eigen::Vector3d e1 = AnyPerpendicular(axis);
  const Eigen::Vector3d e2 = axis.cross(e1);
  const double across = options.cluster_radius * rng->Uniform(1.0 - options.cluster_size_jitter,
                                                              1.0 + options.cluster_size_jitter);
  const double along = across * options.cluster_elongation;
  const Eigen::Vector3d centre = tip.position - kClusterCentreBack * along * axis;
  for (int l = 0; l < options.leaves_per_cluster; ++l) {
    const Eigen::Vector3d p = RandomInUnitBall(rng);
    const Eigen::Vector3d leaf_centre =
        centre + across * (p.x() * e1 + p.y() * e2) + along * p.z() * axis;
    const Eigen::Vector3d leaf_along = RandomUnitVector(rng);
    const Eigen::Vector3d leaf_across =
        DirectionAround(leaf_along, 0.5 * M_PI, rng->Uniform(0.0, 2.0 * M_PI));
    const double length = rng->Uniform(options.leaf_length_min, options.leaf_length_max);
    AddLeaf(leaf_centre, leaf_along, leaf_across, length, length * options.leaf_aspect, material,
            mesh);
  }
  return {centre, axis, along, across};
}

void CheckPositive(double value, const char* name) {
  SYLVA_CHECK_INPUT(value > 0 && std::isfinite(value), std::string("SyntheticTreeOptions.") + name)
      << "must be > 0, got " << value;
}

void CheckRange(double value, double lo, double hi, const char* name) {
  SYLVA_CHECK_INPUT(value >= lo && value <= hi, std::string("SyntheticTreeOptions.") + name)
      << "must be in [" << lo << ", " << hi << "], got " << value;
}

}  // namespace

bool SyntheticLeafCluster::Contains(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d d = point - centre;
  const double on_axis = d.dot(axis);
  const double off_axis_squared = d.squaredNorm() - on_axis * on_axis;
  return on_axis * on_axis / (along * along) + off_axis_squared / (across * across) <= 1.0;
}

double SyntheticLeafCluster::Volume() const { return 4.0 / 3.0 * M_PI * along * across * across; }

double LeafClustersUnionVolume(const std::vector<SyntheticLeafCluster>& clusters,
                               int samples_per_cluster, uint64_t seed) {
  SYLVA_CHECK(samples_per_cluster > 0);
  RandomEngine random(seed);
  double volume = 0.0;
  for (size_t k = 0; k < clusters.size(); ++k) {
    const SyntheticLeafCluster& c = clusters[k];
    std::vector<size_t> earlier;  // whose bounding spheres overlap this one's
    for (size_t j = 0; j < k; ++j) {
      const double reach =
          std::max(c.along, c.across) + std::max(clusters[j].along, clusters[j].across);
      if ((clusters[j].centre - c.centre).norm() < reach) earlier.push_back(j);
    }
    const Eigen::Vector3d e1 = AnyPerpendicular(c.axis), e2 = c.axis.cross(e1);
    int first = 0;
    for (int s = 0; s < samples_per_cluster; ++s) {
      const Eigen::Vector3d u = RandomInUnitBall(&random);
      const Eigen::Vector3d p =
          c.centre + c.across * (u.x() * e1 + u.y() * e2) + c.along * u.z() * c.axis;
      first += std::none_of(earlier.begin(), earlier.end(),
                            [&](size_t j) { return clusters[j].Contains(p); });
    }
    volume += c.Volume() * first / samples_per_cluster;
  }
  return volume;
}

void SyntheticTreeOptions::Check() const {
  CheckPositive(trunk_length, "trunk_length");
  CheckPositive(trunk_base_radius, "trunk_base_radius");
  CheckRange(trunk_wobble, 0, 10, "trunk_wobble");
  CheckRange(crown_base, 0, 1, "crown_base");
  CheckRange(crown_top, crown_base, 1, "crown_top");
  SYLVA_CHECK_INPUT(crown_top > crown_base, "SyntheticTreeOptions.crown_top")
      << "must be > crown_base";
  for (int level = 0; level < kNumLevels; ++level) {
    CheckRange(num_children[level], 0, 1000, "num_children");
    CheckPositive(length_ratio[level], "length_ratio");
  }
  CheckRange(child_start, 0, 1, "child_start");
  CheckRange(branch_angle_min_deg, 0, 180, "branch_angle_min_deg");
  CheckRange(branch_angle_max_deg, branch_angle_min_deg, 180, "branch_angle_max_deg");
  CheckRange(phyllotaxis_jitter_deg, 0, 180, "phyllotaxis_jitter_deg");
  CheckRange(branch_wobble, 0, 10, "branch_wobble");
  CheckRange(upward_tropism, 0, 100, "upward_tropism");
  CheckPositive(max_segment_length, "max_segment_length");
  CheckPositive(pipe_exponent, "pipe_exponent");
  CheckPositive(tip_length, "tip_length");
  CheckPositive(min_radius, "min_radius");
  CheckRange(leaves_per_cluster, 0, 100000, "leaves_per_cluster");
  CheckPositive(cluster_radius, "cluster_radius");
  CheckRange(cluster_size_jitter, 0, 0.99, "cluster_size_jitter");
  CheckPositive(cluster_elongation, "cluster_elongation");
  CheckPositive(leaf_length_min, "leaf_length_min");
  CheckRange(leaf_length_max, leaf_length_min, 1e3, "leaf_length_max");
  CheckPositive(leaf_aspect, "leaf_aspect");
  CheckPositive(tube_edge_length, "tube_edge_length");
  CheckRange(tube_min_sides, 3, 1000, "tube_min_sides");
  CheckRange(tube_max_sides, tube_min_sides, 1000, "tube_max_sides");
}

SkeletonGraph GenerateSyntheticSkeleton(const SyntheticTreeOptions& options, uint64_t seed) {
  options.Check();
  return SkeletonGrower(options, seed).Grow();
}

void AddBranchTubes(const SkeletonGraph& skeleton, const SyntheticTreeOptions& options,
                    int material, TriangleMesh* mesh) {
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.parent_idx < 0) continue;
    const SkeletonNode& parent = skeleton.nodes[node.parent_idx];
    // A branch's first edge starts inside its parent with its own radius;
    // other edges reach back into the previous tube, closing the seam at bends.
    const bool continues = parent.order == node.order && parent.parent_idx >= 0;
    const double start_radius = parent.order == node.order ? parent.radius : node.radius;
    const Eigen::Vector3d edge = node.position - parent.position;
    const double overlap = continues ? std::min(kTubeOverlapRadii * start_radius,
                                                kTubeOverlapMaxFraction * edge.norm())
                                     : 0.0;
    const Eigen::Vector3d start = parent.position - overlap * edge.normalized();
    AddFrustum(start, node.position, start_radius, node.radius, NumTubeSides(start_radius, options),
               material, mesh);
  }
}

SyntheticTree GenerateSyntheticTree(const SyntheticTreeOptions& options, uint64_t seed) {
  SyntheticTree tree;
  tree.skeleton = GenerateSyntheticSkeleton(options, seed);
  const int bark = tree.mesh.AddMaterial({"bark", options.bark_color, false});
  const int leaves = tree.mesh.AddMaterial({"leaves", options.leaf_color, true});
  AddBranchTubes(tree.skeleton, options, bark, &tree.mesh);
  RandomEngine rng(seed, kLeafStream);
  const std::vector<std::vector<int>> children = tree.skeleton.Children();
  for (int i = 0; i < tree.skeleton.NumNodes(); ++i) {
    if (!children[i].empty()) continue;
    tree.clusters.push_back(AddLeafCluster(tree.skeleton, i, options, leaves, &rng, &tree.mesh));
    ++tree.num_clusters;
  }
  tree.num_leaves = tree.num_clusters * options.leaves_per_cluster;
  return tree;
}

}  // namespace sylva
