#include "mesh/leaves.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/geometry/point_grid.h"
#include "core/util/check.h"
#include "core/util/random.h"
#include "mesh/phyllotaxis.h"

namespace sylva {
namespace {

const Material kLeafMaterial = {"leaves", Eigen::Vector3f(0.22f, 0.46f, 0.13f), true};

// Random streams of RandomEngine(options.seed, stream).
constexpr uint64_t kDensityLeafStream = 0x1eaf;
constexpr uint64_t kSkeletonLeafStream = 0x1eaf5;

// Points every `spacing` along the edges whose radius is thin enough.
std::vector<Eigen::Vector3d> ThinBranchPoints(const SkeletonGraph& skeleton, double max_radius,
                                              double spacing) {
  std::vector<Eigen::Vector3d> points;
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.parent_idx < 0 || node.radius > max_radius) continue;
    const Eigen::Vector3d& parent = skeleton.nodes[node.parent_idx].position;
    const int steps =
        std::max(1, static_cast<int>(std::ceil((node.position - parent).norm() / spacing)));
    for (int s = 0; s <= steps; ++s)
      points.push_back(parent + (node.position - parent) * (double(s) / steps));
  }
  return points;
}

// Beer-Lambert projection factor of randomly oriented leaves (mean |cos|).
constexpr double kLeafProjection = 0.5;
// Opacities are capped below 1 before taking -log(1 - alpha).
constexpr double kMaxOpacity = 0.999;
// The matte test (SeenInMattes) averages the matte over a square around
// the leaf's projected centre of half-width this fraction of the leaf's
// length: the leaf's central half whatever its orientation (its tip may
// overhang the silhouette's edge).
constexpr double kFootprintHalfWidth = 0.25;

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
    const Eigen::Vector3d jitter(rng->Uniform(-0.5, 0.5), rng->Uniform(-0.5, 0.5),
                                 rng->Uniform(-0.5, 0.5));
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
    double half =
        kFootprintHalfWidth * length * 0.5 * (camera.FocalLengthX() + camera.FocalLengthY());
    if (!camera.IsOrthographic()) half /= in_cam.z();
    half = std::max(half, 0.5);
    const double mean =
        tables[v].BoxMean(pixel.x() - half, pixel.y() - half, pixel.x() + half, pixel.y() + half);
    if (mean >= 0.0 && mean < threshold) return false;
  }
  return true;
}

// The leaf's base at the origin of its frame: X = axis, Y = normal x axis, Z = normal.
LeafInstance ToInstance(const Leaf& leaf, double length) {
  Eigen::Matrix3d rotation;
  rotation.col(0) = leaf.axis;
  rotation.col(1) = leaf.normal.cross(leaf.axis);
  rotation.col(2) = leaf.normal;
  LeafInstance instance;
  instance.translation = (leaf.center - 0.5 * length * leaf.axis).cast<float>();
  instance.rotation = Eigen::Quaterniond(rotation).normalized().cast<float>();
  instance.scale = static_cast<float>(length);
  return instance;
}

// Half-width profile x^p (1 - x)^q scaled to a maximum of 1 (at p / (p + q)).
double Profile(double x, double p, double q) {
  const double peak = p / (p + q);
  return std::pow(x, p) * std::pow(1.0 - x, q) / (std::pow(peak, p) * std::pow(1.0 - peak, q));
}

// A polygon from base to tip along -Y, back along +Y (counter-clockwise seen
// from +Z), fanned from a point on the midrib.
LeafShape OutlineShape(const std::string& name, double aspect, double p, double q) {
  constexpr int kSamplesPerSide = 6;
  LeafShape shape;
  shape.name = name;
  shape.points.emplace_back(0.0f, 0.0f);
  for (int i = 1; i <= kSamplesPerSide; ++i) {
    const double x = double(i) / (kSamplesPerSide + 1);
    shape.points.emplace_back(x, -0.5 * aspect * Profile(x, p, q));
  }
  shape.points.emplace_back(1.0f, 0.0f);
  for (int i = kSamplesPerSide; i >= 1; --i) {
    const double x = double(i) / (kSamplesPerSide + 1);
    shape.points.emplace_back(x, 0.5 * aspect * Profile(x, p, q));
  }
  const int outline = static_cast<int>(shape.points.size());
  shape.points.emplace_back(p / (p + q), 0.0f);
  for (int i = 0; i < outline; ++i) shape.triangles.emplace_back(outline, i, (i + 1) % outline);
  return shape;
}

LeafShape Rhombus(const std::string& name, double aspect) {
  LeafShape shape;
  shape.name = name;
  const float half = static_cast<float>(0.5 * aspect);
  shape.points = {{0.0f, 0.0f}, {0.5f, -half}, {1.0f, 0.0f}, {0.5f, half}};
  shape.triangles = {{0, 1, 2}, {0, 2, 3}};
  return shape;
}

// Sample point of leaf-sized neighbourhoods: the opacity of the voxel holding p.
double OpacityAt(const DensityGrid& density, const Eigen::Vector3d& p) {
  return density.Value(density.IndexFromWorld(p).array().round().cast<int>());
}

// A run of consecutive branch-axis edges whose child radius is at most
// some maximum, as a polyline with each edge's radius (its child node's).
struct ThinAxis {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> radii;  // radii[k]: the edge from points[k] to points[k + 1]

  // The radius of the edge holding arc length s (world units from points[0]).
  double RadiusAt(double s) const {
    double arc = 0.0;
    for (size_t k = 0; k + 1 < points.size(); ++k) {
      arc += (points[k + 1] - points[k]).norm();
      if (s <= arc) return radii[k];
    }
    return radii.back();
  }
};

std::vector<ThinAxis> ThinAxes(const SkeletonGraph& skeleton, double max_radius) {
  std::vector<ThinAxis> runs;
  for (const BranchAxis& axis : skeleton.BranchAxes()) {
    ThinAxis run;
    for (size_t i = 1; i < axis.size(); ++i) {
      const SkeletonNode& node = skeleton.nodes[axis[i]];
      if (node.radius > max_radius) {
        if (run.points.size() >= 2) runs.push_back(run);
        run = ThinAxis();
        continue;
      }
      if (run.points.empty()) run.points.push_back(skeleton.nodes[axis[i - 1]].position);
      run.points.push_back(node.position);
      run.radii.push_back(node.radius);
    }
    if (run.points.size() >= 2) runs.push_back(run);
  }
  return runs;
}

PhyllotaxisOptions ToPhyllotaxis(const LeafOptions& options, double length) {
  PhyllotaxisOptions out;
  out.pattern = ParsePhyllotaxisPattern(options.phyllotaxis, "Leaves.phyllotaxis");
  out.divergence_deg = options.divergence_deg;
  out.leaves_per_whorl = options.leaves_per_whorl;
  out.internode = options.internode * length;
  out.insertion_deg = options.insertion_deg;
  return out;
}

// The leaf at a phyllotactic site, its normal turned towards n_opt (away
// from `centroid`) by phototropism, as the free leaves' random one is.
Leaf PhyllotacticLeaf(const LeafAttachment& a, const Eigen::Vector3d& centroid, double phototropism,
                      double length) {
  Leaf leaf;
  leaf.axis = a.petiole_direction;
  leaf.center = a.position + 0.5 * length * leaf.axis;
  const Eigen::Vector3d best = Perpendicular((leaf.center - centroid).normalized(), leaf.axis);
  const Eigen::Vector3d n = phototropism * best + (1.0 - phototropism) * a.normal;
  leaf.normal = n.norm() > 1e-9 ? Eigen::Vector3d(n.normalized()) : a.normal;
  return leaf;
}

// Every phyllotactic site along `axes`, axis by axis, node by node; the
// leaves' bases on the axes, or `on_bark` the edge's radius out from them
// (across the axis, towards the petiole).
std::vector<Leaf> PhyllotaxisSites(const std::vector<ThinAxis>& axes, const LeafOptions& options,
                                   double length, const Eigen::Vector3d& centroid, bool on_bark) {
  const PhyllotaxisOptions phyllotaxis = ToPhyllotaxis(options, length);
  std::vector<Leaf> sites;
  for (const ThinAxis& axis : axes) {
    for (LeafAttachment a : PlaceLeavesAlongAxis(axis.points, phyllotaxis)) {
      if (on_bark) {
        a.position += axis.RadiusAt(a.arc_length) *
                      Perpendicular(a.petiole_direction, a.axis_tangent.normalized());
      }
      sites.push_back(PhyllotacticLeaf(a, centroid, options.phototropism, length));
    }
  }
  return sites;
}

// The branches that carry leaves: those of radius at most `fraction` of
// the trunk's (all of them if none is that thin), and points every
// `spacing` along them.
struct ThinBranches {
  double max_radius = 0.0;
  std::vector<Eigen::Vector3d> points;
};
ThinBranches FindThinBranches(const SkeletonGraph& skeleton, double fraction, double spacing) {
  const double trunk_radius = skeleton.nodes[skeleton.RootIdx()].radius;
  ThinBranches thin;
  thin.max_radius = fraction * trunk_radius;
  thin.points = ThinBranchPoints(skeleton, thin.max_radius, spacing);
  if (thin.points.empty()) {
    thin.max_radius = trunk_radius;
    thin.points = ThinBranchPoints(skeleton, thin.max_radius, spacing);
  }
  return thin;
}

// Leaf length in world units (LeafOptions::leaf_length).
double LeafLength(const SkeletonGraph& skeleton, const LeafOptions& options) {
  return options.leaf_length > 0 ? options.leaf_length
                                 : options.leaf_length_fraction * skeleton.Height();
}

// No leaves yet, with the material and the leaf shape (`shape` or the
// options' built-in one).
LeafInstances NoLeaves(const LeafOptions& options, const LeafShape* shape) {
  LeafInstances out;
  out.material = kLeafMaterial;
  out.shape = shape != nullptr ? *shape : BuiltinLeafShape(options.shape, options.leaf_aspect);
  out.shape.Check();
  return out;
}

}  // namespace

std::string LeafSummary::BriefReport() const {
  std::ostringstream out;
  if (!placement.empty()) {
    out << "Leaves: " << kept << " (target " << target << "), " << placement;
    if (phyllotaxis_sites > 0) out << ", " << phyllotaxis_sites << " sites";
    out << ", length " << leaf_length << ".";
    return out.str();
  }
  out << "Leaves: " << kept << " (target " << target << ") of " << drawn << " drawn ("
      << far_from_branches << " too far from a thin branch, " << outside_mattes
      << " outside the mattes), length " << leaf_length << ".";
  if (phyllotaxis_sites > 0) out << " Phyllotaxis offered " << phyllotaxis_sites << " sites.";
  return out.str();
}

void LeafSummary::Add(const LeafSummary& other) {
  target += other.target;
  drawn += other.drawn;
  kept += other.kept;
  far_from_branches += other.far_from_branches;
  outside_mattes += other.outside_mattes;
  phyllotaxis_sites += other.phyllotaxis_sites;
  leaf_length = std::max(leaf_length, other.leaf_length);
  if (placement.empty()) placement = other.placement;
}

void LeafShape::Check() const {
  const int n = static_cast<int>(points.size());
  for (const Eigen::Vector3i& t : triangles) {
    SYLVA_CHECK(t.minCoeff() >= 0 && t.maxCoeff() < n) << "leaf shape " << name << ": bad triangle";
  }
  SYLVA_CHECK(uvs.empty() || static_cast<int>(uvs.size()) == n)
      << "leaf shape " << name << ": " << uvs.size() << " UVs for " << n << " points";
  SYLVA_CHECK(texture.empty() || texture.channels() == 4)
      << "leaf shape " << name << ": the texture must be RGBA";
}

LeafShape BuiltinLeafShape(const std::string& name, double aspect) {
  // Outline exponents x^p (1 - x)^q: widest at p / (p + q).
  if (name == "quad") return Rhombus(name, aspect);
  if (name == "ovate") return OutlineShape(name, aspect, 0.6, 1.0);
  if (name == "lanceolate") return OutlineShape(name, aspect, 0.5, 1.5);
  if (name == "needle") return Rhombus(name, std::min(aspect, 0.05));
  CheckBuiltinLeafShapeName(name);  // throws
  return LeafShape();
}

LeafShape LeafShapeFromImage(const FloatImage& rgba, const std::string& source,
                             float alpha_threshold) {
  SYLVA_CHECK_INPUT(rgba.channels() == 4 && !rgba.empty(), source)
      << "a leaf image needs 4 channels (RGBA), got " << rgba.channels();
  int x0 = rgba.width(), y0 = rgba.height(), x1 = -1, y1 = -1;
  for (int y = 0; y < rgba.height(); ++y) {
    for (int x = 0; x < rgba.width(); ++x) {
      if (rgba.at(x, y, 3) <= alpha_threshold) continue;
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
  }
  SYLVA_CHECK_INPUT(x1 >= 0, source) << "no pixel has alpha above " << alpha_threshold;
  // Box edges in UV (pixel edges), and the leaf's width / length.
  const float u0 = float(x0) / rgba.width(), u1 = float(x1 + 1) / rgba.width();
  const float v0 = float(y0) / rgba.height(), v1 = float(y1 + 1) / rgba.height();
  const float half = 0.5f * float(x1 + 1 - x0) / float(y1 + 1 - y0);
  LeafShape shape;
  shape.name = "image";
  // Seen from +Z with the tip (+X) up, +Y points left (u0).
  shape.points = {{0.0f, -half}, {1.0f, -half}, {1.0f, half}, {0.0f, half}};
  shape.uvs = {{u1, v1}, {u1, v0}, {u0, v0}, {u0, v1}};
  shape.triangles = {{0, 1, 2}, {0, 2, 3}};
  shape.texture = rgba;
  return shape;
}

TriangleMesh LeafInstances::Bake() const {
  TriangleMesh mesh;
  const int material_idx = mesh.AddMaterial(material);
  mesh.vertices.reserve(instances.size() * shape.points.size());
  mesh.triangles.reserve(instances.size() * shape.triangles.size());
  for (const LeafInstance& leaf : instances) {
    const Eigen::Matrix3f rotation = leaf.rotation.toRotationMatrix();
    const int first = mesh.NumVertices();
    for (const Eigen::Vector2f& p : shape.points) {
      mesh.AddVertex(leaf.translation +
                     leaf.scale * (rotation.col(0) * p.x() + rotation.col(1) * p.y()));
    }
    for (const Eigen::Vector3i& t : shape.triangles) {
      mesh.AddTriangle(first + t[0], first + t[1], first + t[2], material_idx);
    }
  }
  return mesh;
}

namespace {

// Leaves drawn freely in proportion to the density near the thin branches
// (the first version), in batches until the target is met or the draw
// budget is spent. Matte tests are left to the caller.
std::vector<Leaf> DrawFreeLeaves(const PointGrid& twigs, const DensityGrid& density,
                                 const DensitySampler& sampler, const LeafOptions& options,
                                 double length, RandomEngine* rng, LeafSummary* summary) {
  std::vector<Leaf> leaves;
  for (int64_t i = 0; i < summary->target; ++i) {
    ++summary->drawn;
    const Eigen::Vector3d center = sampler.Draw(density, rng);
    const int twig = twigs.Nearest(center, options.twig_reach * length);
    if (twig < 0) {
      ++summary->far_from_branches;
      continue;
    }
    Leaf leaf;
    leaf.center = center;
    const Eigen::Vector3d away = center - twigs.points()[twig];
    leaf.axis =
        away.norm() > 1e-9 * length ? Eigen::Vector3d(away.normalized()) : RandomUnitVector(rng);
    leaf.normal =
        LeafNormal(leaf.axis, (center - sampler.centroid).normalized(), options.phototropism, rng);
    leaves.push_back(leaf);
  }
  return leaves;
}

// Leaves at the phyllotactic sites along the thin branches, each kept with
// probability target x opacity / (sum of opacities over all sites), so the
// kept count follows the density like the free draw. The phyllotactic
// normal is turned towards n_opt by phototropism, as the random one is.
std::vector<Leaf> PhyllotacticLeaves(const std::vector<ThinAxis>& axes, const DensityGrid& density,
                                     const DensitySampler& sampler, const LeafOptions& options,
                                     double length, RandomEngine* rng, LeafSummary* summary) {
  const std::vector<Leaf> sites =
      PhyllotaxisSites(axes, options, length, sampler.centroid, /*on_bark=*/false);
  std::vector<double> weights;
  double total = 0.0;
  for (const Leaf& leaf : sites) {
    weights.push_back(OpacityAt(density, leaf.center));
    total += weights.back();
  }
  summary->phyllotaxis_sites = static_cast<int64_t>(sites.size());
  std::vector<Leaf> leaves;
  for (size_t i = 0; i < sites.size(); ++i) {
    ++summary->drawn;
    const double keep = total > 0 ? summary->target * weights[i] / total : 0.0;
    if (rng->Uniform() < keep) leaves.push_back(sites[i]);
  }
  return leaves;
}

// Leaves whose footprint lies inside the mattes (all of them without mattes).
std::vector<char> MatteTest(const std::vector<Leaf>& leaves, double length, const ImageSet& views,
                            const std::vector<SummedAreaTable>& tables, double threshold) {
  std::vector<char> keep(leaves.size(), 1);
  if (tables.empty()) return keep;
  tbb::parallel_for(size_t{0}, leaves.size(), [&](size_t i) {
    keep[i] = SeenInMattes(leaves[i], length, views, tables, threshold);
  });
  return keep;
}

}  // namespace

LeafInstances GenerateLeafInstances(const SkeletonGraph& skeleton, const DensityGrid& density,
                                    const ImageSet& views, const std::vector<FloatImage>& mattes,
                                    const LeafOptions& options, LeafSummary* summary,
                                    const LeafShape* shape) {
  options.Check();
  skeleton.Check();
  SYLVA_CHECK(mattes.empty() || static_cast<int>(mattes.size()) == views.NumViews());
  LeafSummary local;
  if (summary == nullptr) summary = &local;
  *summary = LeafSummary();
  LeafInstances out = NoLeaves(options, shape);
  if (skeleton.NumNodes() < 2 || density.IsEmpty() || options.num_leaves < 0) return out;

  const double length = LeafLength(skeleton, options);
  summary->leaf_length = length;
  ThinBranches thin = FindThinBranches(skeleton, options.thin_branch_radius_fraction, 0.5 * length);
  const DensitySampler sampler(density);
  const double leaf_area = 0.5 * length * options.leaf_aspect * length;
  summary->target =
      options.num_leaves > 0
          ? options.num_leaves
          : std::min<int64_t>(options.max_leaves, std::llround(sampler.leaf_area / leaf_area));
  std::vector<SummedAreaTable> tables;
  for (const FloatImage& matte : mattes) tables.emplace_back(matte);

  // Draw serially (one random stream), test against the mattes in parallel
  // (one flag per leaf: deterministic). Free draws repeat until the target
  // is met or max_draws_factor x target were drawn.
  RandomEngine rng(options.seed, kDensityLeafStream);
  const bool free_draws = options.phyllotaxis == "none";
  const PointGrid twigs(free_draws ? std::move(thin.points) : std::vector<Eigen::Vector3d>());
  const std::vector<ThinAxis> axes =
      free_draws ? std::vector<ThinAxis>() : ThinAxes(skeleton, thin.max_radius);
  const int64_t max_draws = static_cast<int64_t>(options.max_draws_factor * summary->target);
  const LeafSummary wanted = *summary;
  do {
    LeafSummary batch = wanted;
    batch.target = std::min(summary->target - summary->kept, max_draws - summary->drawn);
    const std::vector<Leaf> leaves =
        free_draws ? DrawFreeLeaves(twigs, density, sampler, options, length, &rng, &batch)
                   : PhyllotacticLeaves(axes, density, sampler, options, length, &rng, &batch);
    summary->drawn += batch.drawn;
    summary->far_from_branches += batch.far_from_branches;
    summary->phyllotaxis_sites += batch.phyllotaxis_sites;
    const std::vector<char> keep =
        MatteTest(leaves, length, views, tables, options.matte_threshold);
    for (size_t i = 0; i < leaves.size(); ++i) {
      if (!keep[i]) {
        ++summary->outside_mattes;
        continue;
      }
      out.instances.push_back(ToInstance(leaves[i], length));
      ++summary->kept;
    }
  } while (free_draws && summary->kept < summary->target && summary->drawn < max_draws);
  return out;
}

namespace {

Eigen::Vector3d Mean(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) sum += p;
  return points.empty() ? sum : Eigen::Vector3d(sum / double(points.size()));
}

// `target` of `sites` chosen uniformly without replacement (partial
// Fisher-Yates), in the sites' order; all of them if there are fewer.
std::vector<Leaf> ChooseSites(const std::vector<Leaf>& sites, int64_t target, RandomEngine* rng) {
  const int64_t n = static_cast<int64_t>(sites.size());
  if (target >= n) return sites;
  std::vector<int64_t> order(n);
  for (int64_t i = 0; i < n; ++i) order[i] = i;
  for (int64_t i = 0; i < target; ++i) {
    std::swap(order[i], order[i + rng->UniformInt(static_cast<uint32_t>(n - i))]);
  }
  order.resize(target);
  std::sort(order.begin(), order.end());
  std::vector<Leaf> chosen;
  for (int64_t i : order) chosen.push_back(sites[i]);
  return chosen;
}

// Thin edges (child node indices) and their cumulative length, for points
// drawn uniformly by length.
struct ThinEdges {
  std::vector<int> child;
  std::vector<double> cumulative;
  double Total() const { return cumulative.empty() ? 0.0 : cumulative.back(); }
};
ThinEdges FindThinEdges(const SkeletonGraph& skeleton, double max_radius) {
  ThinEdges edges;
  double total = 0.0;
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    const SkeletonNode& node = skeleton.nodes[i];
    if (node.parent_idx < 0 || node.radius > max_radius) continue;
    const double length = (node.position - skeleton.nodes[node.parent_idx].position).norm();
    if (length <= 0) continue;
    total += length;
    edges.child.push_back(i);
    edges.cumulative.push_back(total);
  }
  return edges;
}

// Leaves without phyllotaxis: uniform by length along the thin edges, each
// petiole leaning insertion_deg from its edge at a random azimuth.
std::vector<Leaf> LeavesAlongBranches(const SkeletonGraph& skeleton, const ThinEdges& edges,
                                      const Eigen::Vector3d& centroid, const LeafOptions& options,
                                      double length, RandomEngine* rng, LeafSummary* summary) {
  constexpr double kDegree = M_PI / 180.0;
  summary->target =
      options.num_leaves > 0
          ? options.num_leaves
          : std::min<int64_t>(options.max_leaves,
                              std::llround(edges.Total() / (options.internode * length)));
  std::vector<Leaf> leaves;
  if (edges.child.empty()) return leaves;
  for (int64_t k = 0; k < summary->target; ++k) {
    const double u = rng->Uniform() * edges.Total();
    const size_t e =
        std::min<size_t>(std::upper_bound(edges.cumulative.begin(), edges.cumulative.end(), u) -
                             edges.cumulative.begin(),
                         edges.child.size() - 1);
    const SkeletonNode& child = skeleton.nodes[edges.child[e]];
    const Eigen::Vector3d& parent = skeleton.nodes[child.parent_idx].position;
    const Eigen::Vector3d tangent = (child.position - parent).normalized();
    const Eigen::Vector3d on_axis = parent + rng->Uniform() * (child.position - parent);
    const Eigen::Vector3d radial = RadialDirection(tangent, rng->Uniform(0.0, 360.0));
    const Eigen::Vector3d base = on_axis + child.radius * radial;  // on the bark
    Leaf leaf;
    leaf.axis = (std::cos(options.insertion_deg * kDegree) * tangent +
                 std::sin(options.insertion_deg * kDegree) * radial)
                    .normalized();
    leaf.center = base + 0.5 * length * leaf.axis;
    leaf.normal =
        LeafNormal(leaf.axis, (leaf.center - centroid).normalized(), options.phototropism, rng);
    leaves.push_back(leaf);
  }
  summary->drawn = summary->target;
  return leaves;
}

// Leaves at the phyllotactic sites of the thin branches: all of them, or
// num_leaves chosen uniformly.
std::vector<Leaf> PhyllotacticSkeletonLeaves(const SkeletonGraph& skeleton, double max_radius,
                                             const Eigen::Vector3d& centroid,
                                             const LeafOptions& options, double length,
                                             RandomEngine* rng, LeafSummary* summary) {
  const std::vector<Leaf> sites =
      PhyllotaxisSites(ThinAxes(skeleton, max_radius), options, length, centroid, /*on_bark=*/true);
  summary->phyllotaxis_sites = static_cast<int64_t>(sites.size());
  summary->drawn = summary->phyllotaxis_sites;
  summary->target = options.num_leaves > 0
                        ? options.num_leaves
                        : std::min<int64_t>(options.max_leaves, summary->phyllotaxis_sites);
  return ChooseSites(sites, summary->target, rng);
}

std::string SkeletonPlacement(const LeafOptions& options) {
  if (options.phyllotaxis == "none") return "spread along the thin branches (no phyllotaxis)";
  const PhyllotaxisOptions phyllotaxis = ToPhyllotaxis(options, 1.0);
  std::ostringstream text;
  text << PhyllotaxisPatternName(phyllotaxis.pattern) << " phyllotaxis (divergence "
       << phyllotaxis.DivergenceDeg() << " degrees) on the thin branches";
  return text.str();
}

}  // namespace

LeafInstances GenerateSkeletonLeafInstances(const SkeletonGraph& skeleton,
                                            const LeafOptions& options, LeafSummary* summary,
                                            const LeafShape* shape) {
  options.Check();
  skeleton.Check();
  LeafSummary local;
  if (summary == nullptr) summary = &local;
  *summary = LeafSummary();
  LeafInstances out = NoLeaves(options, shape);
  if (skeleton.NumNodes() < 2 || options.num_leaves < 0) return out;
  const double length = LeafLength(skeleton, options);
  summary->leaf_length = length;
  summary->placement = SkeletonPlacement(options);
  const ThinBranches thin =
      FindThinBranches(skeleton, options.thin_branch_radius_fraction, 0.5 * length);
  const Eigen::Vector3d centroid = Mean(thin.points);
  RandomEngine rng(options.seed, kSkeletonLeafStream);
  const std::vector<Leaf> leaves =
      options.phyllotaxis == "none"
          ? LeavesAlongBranches(skeleton, FindThinEdges(skeleton, thin.max_radius), centroid,
                                options, length, &rng, summary)
          : PhyllotacticSkeletonLeaves(skeleton, thin.max_radius, centroid, options, length, &rng,
                                       summary);
  for (const Leaf& leaf : leaves) out.instances.push_back(ToInstance(leaf, length));
  summary->kept = static_cast<int64_t>(out.instances.size());
  return out;
}

TriangleMesh GenerateLeaves(const SkeletonGraph& skeleton, const DensityGrid& density,
                            const ImageSet& views, const std::vector<FloatImage>& mattes,
                            const LeafOptions& options, LeafSummary* summary) {
  return GenerateLeafInstances(skeleton, density, views, mattes, options, summary).Bake();
}

}  // namespace sylva
