#include "mesh/leaves.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/geometry/point_grid.h"
#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

const Material kLeafMaterial = {"leaves", Eigen::Vector3f(0.22f, 0.46f, 0.13f), true};

// Points every `spacing` along the edges whose radius is thin enough.
std::vector<Eigen::Vector3d> ThinBranchPoints(const SkeletonGraph& skeleton, double max_radius,
                                              double spacing) {
  std::vector<Eigen::Vector3d> points;
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.parent_idx < 0 || node.radius > max_radius) continue;
    const Eigen::Vector3d& parent = skeleton.nodes[node.parent_idx].position;
    const int steps = std::max(1, static_cast<int>(std::ceil((node.position - parent).norm() / spacing)));
    for (int s = 0; s <= steps; ++s) points.push_back(parent + (node.position - parent) * (double(s) / steps));
  }
  return points;
}

double TreeHeight(const SkeletonGraph& skeleton) {
  double top = -std::numeric_limits<double>::infinity();
  for (const SkeletonNode& node : skeleton.nodes) top = std::max(top, node.position.z());
  return top - skeleton.nodes[skeleton.RootIdx()].position.z();
}

// Beer-Lambert projection factor of randomly oriented leaves (mean |cos|).
constexpr double kLeafProjection = 0.5;
// Opacities are capped below 1 before taking -log(1 - alpha).
constexpr double kMaxOpacity = 0.999;

// Active voxels and the cumulative opacity over them, for drawing ∝ density.
struct DensitySampler {
  std::vector<Eigen::Vector3i> voxels;
  std::vector<double> cumulative;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double leaf_area = 0.0;  // world units^2, see LeafOptions::num_leaves

  explicit DensitySampler(const DensityGrid& density) {
    double total = 0.0, optical_depth = 0.0;
    density.ForEachActive([&](const Eigen::Vector3i& ijk, float alpha) {
      voxels.push_back(ijk);
      total += alpha;
      cumulative.push_back(total);
      centroid += alpha * density.WorldFromIndex(ijk.cast<double>());
      optical_depth -= std::log(1.0 - std::min<double>(alpha, kMaxOpacity));
    });
    if (total > 0) centroid /= total;
    leaf_area = optical_depth * density.voxel_size() * density.voxel_size() / kLeafProjection;
  }
  Eigen::Vector3d Draw(const DensityGrid& density, RandomEngine* rng) const {
    const double u = rng->Uniform() * cumulative.back();
    const size_t i = std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin();
    const Eigen::Vector3d jitter(rng->Uniform(-0.5, 0.5), rng->Uniform(-0.5, 0.5), rng->Uniform(-0.5, 0.5));
    return density.WorldFromIndex(voxels[std::min(i, voxels.size() - 1)].cast<double>() + jitter);
  }
};

Eigen::Vector3d RandomUnitVector(RandomEngine* rng) {
  Eigen::Vector3d v(rng->Normal(), rng->Normal(), rng->Normal());
  return v.norm() > 1e-12 ? Eigen::Vector3d(v.normalized()) : Eigen::Vector3d::UnitX();
}

// The component of v perpendicular to the unit axis a, normalised (or zero).
Eigen::Vector3d Perpendicular(const Eigen::Vector3d& v, const Eigen::Vector3d& a) {
  const Eigen::Vector3d p = v - v.dot(a) * a;
  return p.norm() > 1e-9 ? Eigen::Vector3d(p.normalized()) : Eigen::Vector3d::Zero();
}

struct Leaf {
  Eigen::Vector3d center, axis, normal;
};

// Thesis 5.4: the normal is the direction perpendicular to the leaf's axis
// closest to n_opt, blended with a random one by (1 - phototropism).
Eigen::Vector3d LeafNormal(const Eigen::Vector3d& axis, const Eigen::Vector3d& outward,
                           double phototropism, RandomEngine* rng) {
  const Eigen::Vector3d random = Perpendicular(RandomUnitVector(rng), axis);
  const Eigen::Vector3d best = Perpendicular(outward, axis);
  Eigen::Vector3d n = phototropism * best + (1.0 - phototropism) * random;
  if (n.norm() < 1e-9) n = random.norm() > 0 ? random : axis.unitOrthogonal();
  return n.normalized();
}

bool SeenInMattes(const Leaf& leaf, double length, const ImageSet& views,
                  const std::vector<SummedAreaTable>& tables, double threshold) {
  for (int v = 0; v < views.NumViews(); ++v) {
    const View& view = views.views[v];
    const Camera& camera = views.CameraOf(view);
    const Eigen::Vector3d in_cam = view.cam_from_world * leaf.center;
    if (!camera.IsInFront(in_cam)) continue;
    const Eigen::Vector2d pixel = camera.ImgFromCam(in_cam);
    double half = 0.25 * length * 0.5 * (camera.FocalLengthX() + camera.FocalLengthY());
    if (!camera.IsOrthographic()) half /= in_cam.z();
    half = std::max(half, 0.5);
    const double mean = tables[v].BoxMean(pixel.x() - half, pixel.y() - half, pixel.x() + half,
                                          pixel.y() + half);
    if (mean >= 0.0 && mean < threshold) return false;
  }
  return true;
}

void AddLeafQuad(const Leaf& leaf, double length, double width, int material, TriangleMesh* mesh) {
  const Eigen::Vector3d side = leaf.normal.cross(leaf.axis);
  const Eigen::Vector3d corners[4] = {
      leaf.center - 0.5 * length * leaf.axis, leaf.center + 0.5 * width * side,
      leaf.center + 0.5 * length * leaf.axis, leaf.center - 0.5 * width * side};
  const int first = mesh->NumVertices();
  for (const Eigen::Vector3d& c : corners) mesh->AddVertex(c.cast<float>());
  // (base, right, tip) and (base, tip, left) face along the leaf's normal.
  mesh->AddTriangle(first, first + 1, first + 2, material);
  mesh->AddTriangle(first, first + 2, first + 3, material);
}

}  // namespace

void LeafOptions::Check() const {
  SYLVA_CHECK_INPUT(num_leaves >= -1 && num_leaves <= 10000000, "Leaves.num_leaves")
      << "must be -1 (no leaves), 0 (from the leaf area) or up to 10^7, got " << num_leaves;
  SYLVA_CHECK_INPUT(max_leaves >= 1 && max_leaves <= 10000000, "Leaves.max_leaves")
      << "must be between 1 and 10^7, got " << max_leaves;
  SYLVA_CHECK_INPUT(max_draws_factor >= 1, "Leaves.max_draws_factor")
      << "must be >= 1, got " << max_draws_factor;
  SYLVA_CHECK_INPUT(leaf_length >= 0, "Leaves.leaf_length") << "must be >= 0, got " << leaf_length;
  SYLVA_CHECK_INPUT(leaf_length_fraction > 0 && leaf_length_fraction < 1,
                    "Leaves.leaf_length_fraction")
      << "must be in (0, 1), got " << leaf_length_fraction;
  SYLVA_CHECK_INPUT(leaf_aspect > 0 && leaf_aspect <= 10, "Leaves.leaf_aspect")
      << "must be in (0, 10], got " << leaf_aspect;
  SYLVA_CHECK_INPUT(twig_reach > 0, "Leaves.twig_reach") << "must be > 0, got " << twig_reach;
  SYLVA_CHECK_INPUT(thin_branch_radius_fraction > 0 && thin_branch_radius_fraction <= 1,
                    "Leaves.thin_branch_radius_fraction")
      << "must be in (0, 1], got " << thin_branch_radius_fraction;
  SYLVA_CHECK_INPUT(phototropism >= 0 && phototropism <= 1, "Leaves.phototropism")
      << "must be in [0, 1], got " << phototropism;
  SYLVA_CHECK_INPUT(matte_threshold >= 0 && matte_threshold < 1, "Leaves.matte_threshold")
      << "must be in [0, 1), got " << matte_threshold;
}

std::string LeafSummary::BriefReport() const {
  std::ostringstream out;
  out << "Leaves: " << kept << " (target " << target << ") of " << drawn << " drawn ("
      << far_from_branches
      << " too far from a thin branch, " << outside_mattes << " outside the mattes), length "
      << leaf_length << ".";
  return out.str();
}

TriangleMesh GenerateLeaves(const SkeletonGraph& skeleton, const DensityGrid& density,
                            const ImageSet& views, const std::vector<FloatImage>& mattes,
                            const LeafOptions& options, LeafSummary* summary) {
  options.Check();
  skeleton.Check();
  SYLVA_CHECK(mattes.empty() || static_cast<int>(mattes.size()) == views.NumViews());
  LeafSummary local;
  if (summary == nullptr) summary = &local;
  *summary = LeafSummary();
  TriangleMesh mesh;
  const int material = mesh.AddMaterial(kLeafMaterial);
  if (skeleton.NumNodes() < 2 || density.IsEmpty()) return mesh;

  const double length = options.leaf_length > 0 ? options.leaf_length
                                                : options.leaf_length_fraction * TreeHeight(skeleton);
  summary->leaf_length = length;
  const double trunk_radius = skeleton.nodes[skeleton.RootIdx()].radius;
  std::vector<Eigen::Vector3d> twig_points =
      ThinBranchPoints(skeleton, options.thin_branch_radius_fraction * trunk_radius, 0.5 * length);
  if (twig_points.empty()) twig_points = ThinBranchPoints(skeleton, trunk_radius, 0.5 * length);
  const PointGrid twigs(std::move(twig_points));
  const DensitySampler sampler(density);

  const double width = options.leaf_aspect * length;
  summary->target = options.num_leaves > 0
                        ? options.num_leaves
                        : std::min<int64_t>(options.max_leaves,
                                            std::llround(sampler.leaf_area / (0.5 * length * width)));
  std::vector<SummedAreaTable> tables;
  for (const FloatImage& matte : mattes) tables.emplace_back(matte);

  // Draw in batches (serially: one random stream), test the batch against
  // the mattes in parallel (one flag per leaf: deterministic), until the
  // target is met or the draw budget is spent.
  RandomEngine rng(options.seed, /*stream=*/0x1eaf);
  const int64_t max_draws = static_cast<int64_t>(options.max_draws_factor * summary->target);
  while (summary->kept < summary->target && summary->drawn < max_draws) {
    const int64_t batch = std::min(summary->target - summary->kept, max_draws - summary->drawn);
    std::vector<Leaf> leaves;
    for (int64_t i = 0; i < batch; ++i) {
      ++summary->drawn;
      const Eigen::Vector3d center = sampler.Draw(density, &rng);
      const int twig = twigs.Nearest(center, options.twig_reach * length);
      if (twig < 0) {
        ++summary->far_from_branches;
        continue;
      }
      Leaf leaf;
      leaf.center = center;
      const Eigen::Vector3d away = center - twigs.points()[twig];
      leaf.axis = away.norm() > 1e-9 * length ? Eigen::Vector3d(away.normalized())
                                               : RandomUnitVector(&rng);
      leaf.normal = LeafNormal(leaf.axis, (center - sampler.centroid).normalized(),
                               options.phototropism, &rng);
      leaves.push_back(leaf);
    }
    std::vector<char> keep(leaves.size(), 1);
    if (!tables.empty()) {
      tbb::parallel_for(size_t{0}, leaves.size(), [&](size_t i) {
        keep[i] = SeenInMattes(leaves[i], length, views, tables, options.matte_threshold);
      });
    }
    for (size_t i = 0; i < leaves.size(); ++i) {
      if (!keep[i]) {
        ++summary->outside_mattes;
        continue;
      }
      AddLeafQuad(leaves[i], length, width, material, &mesh);
      ++summary->kept;
    }
  }
  return mesh;
}

}  // namespace sylva
