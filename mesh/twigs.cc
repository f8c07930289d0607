#include "mesh/twigs.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

#include "core/util/check.h"
#include "core/util/random.h"
#include "mesh/phyllotaxis.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;
// Successive twigs on one branch turn by the golden angle (spiral phyllotaxis).
const double kGoldenAngle = M_PI * (3.0 - std::sqrt(5.0));
// Monopodial laterals are this fraction of their twig's length.
constexpr double kLateralLength = 0.5;
// Sympodial units: the spent apex left behind is this fraction of a unit long.
constexpr double kSpentApexLength = 0.3;

// Local opacity relative to the mean of the active voxels (1 without a grid).
class DensityFactor {
 public:
  DensityFactor(const DensityGrid& density, double max_factor)
      : density_(density), max_factor_(max_factor) {
    if (!density.IsEmpty()) mean_ = density.SumOfValues() / density.NumActiveVoxels();
  }
  double At(const Eigen::Vector3d& point) const {
    if (mean_ <= 0) return 1.0;
    const Eigen::Vector3i ijk = density_.IndexFromWorld(point).array().round().cast<int>();
    return std::min(max_factor_, density_.Value(ijk) / mean_);
  }
  double max() const { return mean_ > 0 ? max_factor_ : 1.0; }

 private:
  const DensityGrid& density_;
  double max_factor_;
  double mean_ = 0.0;
};

// Axes from which no other axis starts (their first node is a junction on
// the parent axis, so only the later nodes count).
std::vector<BranchAxis> TerminalAxes(const SkeletonGraph& skeleton) {
  const std::vector<BranchAxis> axes = skeleton.BranchAxes();
  std::vector<char> starts_axis(skeleton.NumNodes(), 0);
  for (size_t a = 1; a < axes.size(); ++a) starts_axis[axes[a][0]] = 1;
  std::vector<BranchAxis> terminal;
  for (const BranchAxis& axis : axes) {
    bool bears = false;
    for (size_t i = 1; i < axis.size(); ++i) bears = bears || starts_axis[axis[i]];
    if (!bears && axis.size() >= 2) terminal.push_back(axis);
  }
  return terminal;
}

// A unit vector perpendicular to `t` at `azimuth` (radians) about it (0 = world up).
Eigen::Vector3d Radial(const Eigen::Vector3d& t, double azimuth) {
  return RadialDirection(t, azimuth / kDegree);
}

// Where a twig starts: on the edge into `child` at fraction s from its parent.
struct Site {
  int child = 0;
  double s = 0.0;
  double azimuth = 0.0;
  double length = 0.0;
};

class TwigGrower {
 public:
  TwigGrower(const TwigOptions& options, int twig_order, SkeletonGraph* skeleton,
             TwigSummary* summary)
      : options_(options), order_(twig_order), skeleton_(skeleton), summary_(summary) {}

  // A twig from node `base` leaving the unit direction `parent_dir`.
  void Grow(int base, const Eigen::Vector3d& parent_dir, const Site& site, double base_radius) {
    const Eigen::Vector3d dir =
        std::cos(options_.branching_angle_deg * kDegree) * parent_dir +
        std::sin(options_.branching_angle_deg * kDegree) * Radial(parent_dir, site.azimuth);
    ++summary_->twigs;
    if (options_.pattern == "sympodial") {
      GrowSympodial(base, dir, Radial(parent_dir, site.azimuth + 0.5 * M_PI), site.length,
                    base_radius);
    } else {
      GrowMonopodial(base, dir, site.length, base_radius);
    }
  }

 private:
  // Direction of segment i of n after tropism.
  Eigen::Vector3d Bend(const Eigen::Vector3d& dir, int i, int n) const {
    const double pull = options_.tropism * (1.0 - options_.stiffness) * (i + 1.0) / n;
    const Eigen::Vector3d bent = dir + pull * Eigen::Vector3d::UnitZ();
    return bent.norm() > 1e-9 ? Eigen::Vector3d(bent.normalized()) : dir;
  }
  int Add(int parent, const Eigen::Vector3d& step, double radius, int order) {
    summary_->total_length += step.norm();
    ++summary_->nodes_added;
    return skeleton_->AddNode(skeleton_->nodes[parent].position + step, radius, parent, order);
  }
  // A straight-ish chain of `n` segments; returns its node indices (base first).
  std::vector<int> Chain(int base, Eigen::Vector3d dir, double length, double r0, int n,
                         int order) {
    std::vector<int> nodes = {base};
    for (int i = 0; i < n; ++i) {
      dir = Bend(dir, i, n);
      const double radius = r0 * (1.0 - (1.0 - options_.tip_taper) * (i + 1.0) / n);
      nodes.push_back(Add(nodes.back(), dir * (length / n), radius, order));
    }
    return nodes;
  }
  void GrowMonopodial(int base, const Eigen::Vector3d& dir, double length, double r0) {
    const int n = options_.segments;
    const std::vector<int> axis = Chain(base, dir, length, r0, n, order_);
    for (int k = 0; k < options_.laterals; ++k) {
      // Laterals spread over the axis' inner nodes, alternating sides.
      const int at = axis[1 + (k * (n - 1)) / std::max(1, options_.laterals) % n];
      const Eigen::Vector3d parent_dir =
          (skeleton_->nodes[at].position -
           skeleton_->nodes[skeleton_->nodes[at].parent_idx].position)
              .normalized();
      const Eigen::Vector3d lateral =
          std::cos(options_.branching_angle_deg * kDegree) * parent_dir +
          std::sin(options_.branching_angle_deg * kDegree) * Radial(parent_dir, M_PI * (0.5 + k));
      Chain(at, lateral, kLateralLength * length, skeleton_->nodes[at].radius, std::max(1, n / 2),
            order_ + 1);
    }
  }
  void GrowSympodial(int base, Eigen::Vector3d dir, const Eigen::Vector3d& side, double length,
                     double r0) {
    const int n = options_.segments;
    const double unit = length / n;
    const Eigen::Vector3d plane_normal = dir.cross(side).normalized();
    int node = base;
    for (int i = 0; i < n; ++i) {
      if (i > 0) {
        // The spent apex stays as a stub; a lateral bud takes over, turned
        // alternately to either side.
        Add(node, dir * (kSpentApexLength * unit),
            skeleton_->nodes[node].radius * options_.tip_taper, order_ + 1);
        const double turn = (i % 2 ? 1.0 : -1.0) * options_.sympodial_angle_deg * kDegree;
        dir = Eigen::AngleAxisd(turn, plane_normal) * dir;
      }
      dir = Bend(dir, i, n);
      const double radius = r0 * (1.0 - (1.0 - options_.tip_taper) * (i + 1.0) / n);
      node = Add(node, dir * unit, radius, order_);
    }
  }

  const TwigOptions& options_;
  int order_;
  SkeletonGraph* skeleton_;
  TwigSummary* summary_;
};

// Draws twig sites along the terminal axes: candidates every `spacing` of
// arc length, each kept with probability DensityFactor / max.
std::vector<Site> DrawSites(const SkeletonGraph& skeleton, const std::vector<BranchAxis>& axes,
                            const DensityFactor& density, const TwigOptions& options,
                            double twig_length, RandomEngine* rng) {
  const double spacing = twig_length / (options.twigs_per_length * density.max());
  std::vector<Site> sites;
  for (const BranchAxis& axis : axes) {
    double azimuth = 2.0 * M_PI * rng->Uniform();
    for (size_t i = 1; i < axis.size(); ++i) {
      const Eigen::Vector3d& from = skeleton.nodes[axis[i - 1]].position;
      const Eigen::Vector3d& to = skeleton.nodes[axis[i]].position;
      const int candidates =
          static_cast<int>(std::floor((to - from).norm() / spacing + rng->Uniform()));
      for (int c = 0; c < candidates; ++c) {
        Site site;
        site.child = axis[i];
        site.s = (c + rng->Uniform()) / candidates;
        site.length = twig_length *
                      rng->Uniform(1.0 - options.length_variation, 1.0 + options.length_variation);
        const double keep = density.At(from + site.s * (to - from)) / density.max();
        if (rng->Uniform() >= keep) continue;
        azimuth += kGoldenAngle;
        site.azimuth = azimuth;
        sites.push_back(site);
      }
    }
  }
  return sites;
}

bool IsTwigNode(const SkeletonGraph& grown, const TwigSummary& summary, int node) {
  return node >= summary.first_added_node && grown.nodes[node].order >= summary.twig_order;
}

// The part of `axis` made of twig nodes, with the node it leaves from
// first; empty if it has none.
BranchAxis TwigPart(const SkeletonGraph& grown, const TwigSummary& summary,
                    const BranchAxis& axis) {
  for (size_t k = 1; k < axis.size(); ++k) {
    if (IsTwigNode(grown, summary, axis[k])) return BranchAxis(axis.begin() + (k - 1), axis.end());
  }
  return {};
}

void CheckGrown(const SkeletonGraph& grown, const TwigSummary& summary) {
  SYLVA_CHECK_INPUT(summary.first_added_node >= 0 && summary.first_added_node <= grown.NumNodes(),
                    "skeleton")
      << "the twig summary's first added node " << summary.first_added_node
      << " is not a node of the grown skeleton (" << grown.NumNodes() << " nodes)";
}

}  // namespace

bool TwigMeshOptions::Separate(int twigs) const {
  return mode == "separate" || (mode == "auto" && twigs > separate_above);
}

std::string TwigTubesSummary::BriefReport() const {
  std::ostringstream out;
  out << "Twig tubes: " << tubes << " closed tubes, " << triangles << " triangles in " << seconds
      << " s (beside the bark, overlapping it at their bases).";
  return out.str();
}

SkeletonGraph RemoveTwigs(const SkeletonGraph& grown, const TwigSummary& summary) {
  CheckGrown(grown, summary);
  std::vector<int> new_index(grown.NumNodes(), -1);
  int kept = 0;
  for (int i = 0; i < grown.NumNodes(); ++i) {
    if (!IsTwigNode(grown, summary, i)) new_index[i] = kept++;
  }
  SkeletonGraph branches;
  branches.radius_source = grown.radius_source;
  branches.nodes.reserve(kept);
  for (int i = 0; i < grown.NumNodes(); ++i) {
    if (new_index[i] < 0) continue;
    SkeletonNode node = grown.nodes[i];
    if (node.parent_idx >= 0) {
      node.parent_idx = new_index[node.parent_idx];
      SYLVA_CHECK_INPUT(node.parent_idx >= 0, "skeleton")
          << "node " << i << " is no twig but its parent is one";
    }
    branches.nodes.push_back(node);
  }
  return branches;
}

TriangleMesh MeshTwigTubes(const SkeletonGraph& grown, const TwigSummary& twigs,
                           const BranchMeshOptions& tube, const TwigMeshOptions& options,
                           TwigTubesSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  tube.Check();
  options.Check();
  CheckGrown(grown, twigs);
  CheckSkeletonInput(grown);
  TwigTubesSummary local;
  if (summary == nullptr) summary = &local;
  *summary = TwigTubesSummary();
  TriangleMesh mesh;
  const int material = mesh.AddMaterial(options.material);
  double max_radius = 0.0;
  for (const SkeletonNode& node : grown.nodes) max_radius = std::max(max_radius, node.radius);
  SYLVA_CHECK_INPUT(max_radius > 0, "skeleton")
      << "all radii are zero; assign radii first (e.g. AssignPipeModelRadii)";
  for (const BranchAxis& axis : grown.BranchAxes()) {
    const BranchAxis twig = TwigPart(grown, twigs, axis);
    if (twig.empty()) continue;
    const BranchTube planned = PlanAxisTube(grown, twig, /*is_trunk=*/false, max_radius, tube);
    if (planned.sides == 0) continue;
    AppendTube(SampleTubeRings(planned), planned.sides, material, &mesh);
    ++summary->tubes;
  }
  summary->triangles = mesh.NumTriangles();
  summary->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return mesh;
}

std::string TwigSummary::BriefReport() const {
  std::ostringstream out;
  out << "Twigs: " << twigs << " on " << terminal_branches << " terminal branches, " << nodes_added
      << " nodes added (order " << twig_order << "+), length " << twig_length << " each, "
      << total_length << " in all.";
  return out.str();
}

SkeletonGraph GrowTwigs(const SkeletonGraph& skeleton, const DensityGrid& density,
                        const TwigOptions& options, TwigSummary* summary) {
  options.Check();
  skeleton.Check();
  TwigSummary local;
  if (summary == nullptr) summary = &local;
  *summary = TwigSummary();
  SkeletonGraph out = skeleton;
  summary->first_added_node = out.NumNodes();
  int max_order = 0;
  for (const SkeletonNode& node : skeleton.nodes) max_order = std::max(max_order, node.order);
  summary->twig_order = max_order + 1;
  if (skeleton.NumNodes() < 2 || options.twigs_per_length == 0) return out;

  const double height = skeleton.Height();
  summary->twig_length = options.length > 0 ? options.length : options.length_fraction * height;
  if (summary->twig_length <= 0) return out;
  const std::vector<BranchAxis> axes = TerminalAxes(skeleton);
  summary->terminal_branches = static_cast<int>(axes.size());
  RandomEngine rng(options.seed, /*stream=*/0x7a19);
  const DensityFactor factor(density, options.max_density_factor);
  std::vector<Site> sites = DrawSites(skeleton, axes, factor, options, summary->twig_length, &rng);
  // Per edge, split at the sites from the parent end up, growing a twig at each.
  std::map<int, std::vector<Site>> sites_of_edge;
  for (const Site& site : sites) sites_of_edge[site.child].push_back(site);
  std::map<int, double> tip_radius;  // of each terminal axis' child nodes
  for (const BranchAxis& axis : axes) {
    for (size_t i = 1; i < axis.size(); ++i)
      tip_radius[axis[i]] = skeleton.nodes[axis.back()].radius;
  }
  TwigGrower grower(options, summary->twig_order, &out, summary);
  for (auto& [child, edge_sites] : sites_of_edge) {
    std::sort(edge_sites.begin(), edge_sites.end(),
              [](const Site& a, const Site& b) { return a.s < b.s; });
    const SkeletonNode lower = skeleton.nodes[skeleton.nodes[child].parent_idx];
    const SkeletonNode upper = skeleton.nodes[child];
    const Eigen::Vector3d dir = (upper.position - lower.position).normalized();
    const double twig_radius =
        tip_radius[child] * std::pow(options.strand_fraction, 1.0 / options.diameter_exponent);
    int previous = upper.parent_idx;
    for (const Site& site : edge_sites) {
      const int split =
          out.AddNode(lower.position + site.s * (upper.position - lower.position),
                      lower.radius + site.s * (upper.radius - lower.radius), previous, upper.order);
      out.nodes[split].strands = upper.strands;
      ++summary->nodes_added;
      grower.Grow(split, dir, site, twig_radius);
      previous = split;
    }
    out.nodes[child].parent_idx = previous;
  }
  return out;
}

}  // namespace sylva
