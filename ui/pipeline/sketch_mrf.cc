#include "ui/pipeline/sketch_mrf.h"

#include <algorithm>
#include <limits>
#include <queue>
#include <sstream>

#include "core/io/camera_file.h"
#include "core/io/mtg_io.h"
#include "core/io/qsm_io.h"
#include "core/io/skeleton_io.h"
#include "core/util/check.h"
#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/allometry.h"
#include "mesh/mesh_renderer.h"
#include "sketch/stroke_graph.h"
#include "ui/pipeline/pipeline_options.h"
#include "ui/pipeline/qsm_meshing.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// The drawn graph is simplified to this fraction of the view's size before
// its chains between forks are set aside (they keep the strokes' shape).
constexpr double kGraphTolerance = 0.01;
// Skeleton edges are at most this fraction of the tree's height.
constexpr double kMaxEdge = 0.02;
// A pixel is crown where the matte reaches this fraction of
// Sketch.crown_opacity.
constexpr double kCrownMatte = 0.5;
constexpr float kLineMatte = 0.99f;
// A crown is made at most this much deeper than wide to hold the drawn
// branches.
constexpr double kMaxCrownDepthScale = 2.0;
// QsmToSkeletonOptions::merge_fraction for meshing the skeleton.
constexpr double kMergeFraction = 0.1;

// The largest (by length) of `parts`.
const SkeletonGraph& Largest(const std::vector<SkeletonGraph>& parts, const std::string& source) {
  SYLVA_CHECK_INPUT(!parts.empty(), source) << "no tree in the file";
  return *std::max_element(parts.begin(), parts.end(), [](const auto& a, const auto& b) {
    return a.TotalLength() < b.TotalLength();
  });
}

SkeletonGraph ReadExemplarSkeleton(const fs::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".mtg")
    return Largest(SkeletonsFromMtg(ReadMtg(path), path.string()).parts, path.string());
  if (ext == ".json") return ReadSkeletonJson(path);
  SYLVA_CHECK_INPUT(ext == ".csv", path.string())
      << "an exemplar is an .mtg, a QSM .csv or a skeleton .json";
  std::vector<SkeletonGraph> parts;
  for (QsmSkeleton& part : SkeletonsFromQsm(ReadQsmCsv(path))) parts.push_back(part.skeleton);
  return Largest(parts, path.string());
}

// The drawn strokes between forks: the MRF's segments run from fork to fork
// (Chen 2008); the points drawn between them (`chains[i]` for segment i, on
// the drawing's plane, with their arc-length fraction) come back after the
// depths are known.
struct DrawnTree {
  SegmentTree segments;
  std::vector<std::vector<std::pair<Eigen::Vector3d, double>>> chains;
  Eigen::Vector3d view;
};

// The drawn graph's main component on the plane through the world origin
// across view 0's line of sight.
DrawnTree DrawnSegments(const AttractorGraph2D& graph, const ImageSet& cameras) {
  DrawnTree drawn;
  drawn.view = cameras.RayThroughPixel(0, graph.nodes[graph.root].position).direction;
  auto on_plane = [&](int node) {
    const Eigen::Vector3d o = cameras.RayThroughPixel(0, graph.nodes[node].position).origin;
    return Eigen::Vector3d(o - o.dot(drawn.view) * drawn.view);
  };
  const std::vector<std::vector<int>> children = graph.Children();
  std::queue<std::pair<int, int>> queue;  // (graph node, segment index)
  queue.push({graph.root, drawn.segments.AddPoint(on_plane(graph.root), -1)});
  drawn.chains.emplace_back();
  while (!queue.empty()) {
    const auto [node, idx] = queue.front();
    queue.pop();
    for (int child : children[node]) {
      std::vector<int> chain = {child};
      while (children[chain.back()].size() == 1) chain.push_back(children[chain.back()][0]);
      std::vector<double> arc = {0.0};
      Eigen::Vector3d last = on_plane(node);
      for (int c : chain)
        arc.push_back(arc.back() + (on_plane(c) - last).norm()), last = on_plane(c);
      std::vector<std::pair<Eigen::Vector3d, double>> inner;
      for (size_t k = 0; k + 1 < chain.size(); ++k) {
        inner.emplace_back(on_plane(chain[k]), arc[k + 1] / std::max(arc.back(), 1e-12));
      }
      queue.push({chain.back(), drawn.segments.AddPoint(on_plane(chain.back()), idx)});
      drawn.chains.push_back(std::move(inner));
    }
  }
  return drawn;
}

// `result.tree` with the drawn points between forks put back, each at the
// depth interpolated along its segment; propagated points keep theirs.
void PutBackChains(const DrawnTree& drawn, MrfResult* result) {
  const SegmentTree& tree = result->tree;
  auto depth = [&](int i) { return (tree.points[i] - drawn.segments.points[i]).dot(drawn.view); };
  SegmentTree full;
  std::vector<int> index(tree.points.size(), -1);
  for (int i = 0; i < tree.Size(); ++i) {
    int parent = tree.parent[i] >= 0 ? index[tree.parent[i]] : -1;
    if (i < result->drawn && tree.parent[i] >= 0) {
      const double a = depth(tree.parent[i]), b = depth(i);
      for (const auto& [point, t] : drawn.chains[i]) {
        parent = full.AddPoint(point + ((1 - t) * a + t * b) * drawn.view, parent);
      }
    }
    index[i] = full.AddPoint(tree.points[i], parent);
  }
  result->tree = std::move(full);
}

// The drawing's footprint: positions across the line of sight and up.
Footprint DrawnFootprint(const SegmentTree& tree, const Eigen::Vector3d& view) {
  const Eigen::Vector3d across = Eigen::Vector3d::UnitZ().cross(view).normalized();
  std::vector<Eigen::Vector2d> points;
  for (const Eigen::Vector3d& p : tree.points) points.emplace_back(across.dot(p), p.z());
  return FootprintOf(points, tree.parent);
}

// The crown of local revolution of view 0's matte (rows where the crown
// covers something), deepened to hold the drawn branches' tips; none if the
// drawing has no crown.
CrownTest CrownOf(const SketchDrawing& drawing, const SketchView& front, const ImageSet& cameras,
                  const Eigen::Vector3d& view, double crown_opacity, const SegmentTree& drawn) {
  if (drawing.CountRole(StrokeRole::kCrown) == 0) return nullptr;
  CrownOfRevolution crown;
  crown.up = Eigen::Vector3d::UnitZ();
  crown.across = crown.up.cross(view).normalized();
  const FloatImage& matte = front.matte;
  auto world = [&](double x, double y) {
    return cameras.RayThroughPixel(0, Eigen::Vector2d(x, y)).origin;
  };
  const double pixel = (world(1.5, 0.5) - world(0.5, 0.5)).norm();
  crown.step = pixel;
  crown.bottom = world(0.5, matte.height() - 0.5).dot(crown.up) - 0.5 * pixel;
  for (int y = matte.height() - 1; y >= 0; --y) {
    int lo = -1, hi = -1;
    for (int x = 0; x < matte.width(); ++x) {
      // The crown's fill, not the drawn lines (opaque: trunk, ground).
      const float value = matte.at(x, y);
      if (value < kCrownMatte * crown_opacity || value >= kLineMatte) continue;
      if (lo < 0) lo = x;
      hi = x;
    }
    if (lo < 0) {
      crown.spans.push_back({1.0, -1.0});
      continue;
    }
    const double a = world(lo, y + 0.5).dot(crown.across);
    const double b = world(hi + 1.0, y + 0.5).dot(crown.across);
    crown.spans.push_back({std::min(a, b), std::max(a, b)});
  }
  crown.DeepenToHold(drawn.points, kMaxCrownDepthScale);
  return [crown](const Eigen::Vector3d& p) { return crown.Contains(p); };
}

// Pipe-model radii scaled as for radius-less MTGs (qsm_meshing.h).
void AssignSketchRadii(const PipelineOptions& options, SkeletonGraph* skeleton) {
  AllometryOptions allometry = options.allometry;
  allometry.trunk_radius = kDefaultTrunkRadiusFraction * options.sketch.tree_height;
  allometry.min_radius = allometry.trunk_radius * kMinRadiusOfTrunk;
  AssignPipeModelRadii(allometry, skeleton);
}

// A point of view 0 of `cameras` on the plane through the world origin
// across its line of sight, as (across, up): (x, z) for the front view.
Eigen::Vector2d OnFrontPlane(const ImageSet& cameras, const Eigen::Vector2d& pixel) {
  const Ray3d ray = cameras.RayThroughPixel(0, pixel);
  const Eigen::Vector3d p = ray.origin - ray.origin.dot(ray.direction) * ray.direction;
  return {p.x(), p.z()};
}

// The silhouette method's inputs from view 0: the trunk (from the base up,
// taken up to kLeaderShare of the crown's height), the drawn branches.
constexpr double kLeaderShare = 0.8;
// A branch stroke with an end this near the base (share of the drawn
// height) stands on the ground: the trunk.
constexpr double kTrunkFootShare = 0.03;
// Closed crown strokes smaller than this share of the crown, with this
// share of their perimeter inside it (kPerimeterSamples points), are
// sub-silhouettes.
constexpr double kSubSilhouetteShare = 0.6;
constexpr double kSubSilhouetteInside = 0.7;
constexpr int kPerimeterSamples = 100;
// The drawn trunk's width is measured at these shares of the way from the
// base to the crown, looking this many pixels aside for it. Wider than
// kOutlinedTrunkLines lines, the trunk was drawn as outlines.
constexpr double kTrunkWidthHeights[] = {0.2, 0.4, 0.6};
constexpr int kTrunkSearchPixels = 3;
constexpr double kOutlinedTrunkLines = 2.5;
// A drawing encloses a crown if at least this share of its view is filled
// at the crown's opacity.
constexpr double kMinCrownShare = 0.01;
// The crown is the widest band of rows of a drawing's silhouette: rows at
// least this share of the widest row's width.
constexpr double kCrownBandShare = 0.35;

// The matte without what hangs below the crown: the trunk and the ground
// drawn with it. The crown is the band of wide rows (kCrownBandShare of
// the widest) with the most silhouette; rows below it are cleared.
FloatImage WithoutTrunk(const FloatImage& matte, double crown_opacity) {
  std::vector<int> width(matte.height(), 0);
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) width[y] += matte.at(x, y) >= 0.5 * crown_opacity;
  }
  const int widest = *std::max_element(width.begin(), width.end());
  int best_bottom = matte.height() - 1;
  long best_area = -1;
  for (int y = 0; y < matte.height();) {
    if (width[y] < kCrownBandShare * widest) {
      ++y;
      continue;
    }
    long area = 0;
    int end = y;
    while (end < matte.height() && width[end] >= kCrownBandShare * widest) area += width[end++];
    if (area > best_area) best_area = area, best_bottom = end - 1;
    y = end;
  }
  FloatImage crown = matte;
  for (int y = best_bottom + 1; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) crown.at(x, y) = 0.0f;
  }
  return crown;
}

}  // namespace

std::vector<TreeExemplar> BuiltinExemplars() {
  struct Species {
    const char* name;
    double angle_min, angle_max, crown_base;
    std::array<int, 3> children;
    std::array<double, 3> ratio;
  };
  const Species species[] = {{"broadleaf", 30, 60, 0.3, {13, 7, 5}, {0.6, 0.45, 0.5}},
                             {"columnar", 12, 28, 0.2, {14, 6, 4}, {0.45, 0.45, 0.5}},
                             {"spreading", 55, 80, 0.25, {9, 7, 5}, {0.75, 0.55, 0.5}},
                             {"excurrent", 70, 90, 0.1, {26, 4, 2}, {0.3, 0.4, 0.4}}};
  std::vector<TreeExemplar> exemplars;
  for (const Species& s : species) {
    SyntheticTreeOptions options;
    options.branch_angle_min_deg = s.angle_min;
    options.branch_angle_max_deg = s.angle_max;
    options.crown_base = s.crown_base;
    options.num_children = s.children;
    options.length_ratio = s.ratio;
    exemplars.push_back(MakeExemplar(s.name, GenerateSyntheticSkeleton(options, 1)));
  }
  return exemplars;
}

std::vector<TreeExemplar> LoadExemplars(const std::string& list) {
  std::vector<TreeExemplar> exemplars;
  std::stringstream stream(list);
  for (std::string item; std::getline(stream, item, ',');) {
    if (item.empty()) continue;
    const fs::path path(item);
    std::error_code ec;
    SYLVA_CHECK_INPUT(fs::is_regular_file(path, ec), item)
        << "no such exemplar file (Sketch.exemplars)";
    exemplars.push_back(MakeExemplar(path.filename().string(), ReadExemplarSkeleton(path)));
  }
  return exemplars;
}

MrfSketchTree MakeMrfSketchTree(const std::vector<SketchDrawing>& drawings,
                                const PipelineOptions& options,
                                const std::vector<TreeExemplar>& exemplars) {
  SYLVA_CHECK(!drawings.empty() && !exemplars.empty()) << "needs a drawing and exemplars";
  const SketchViews views = MakeSketchViews({drawings[0]}, options.sketch);
  const SketchView& front = views.views[0];
  SYLVA_CHECK_INPUT(!front.strokes.strokes.empty(), drawings[0].source)
      << "no branch strokes, and no crown to infer major branches from";
  StrokeGraphOptions graph_options;
  graph_options.resample_spacing = std::numeric_limits<double>::infinity();
  const AttractorGraph2D graph = GraphFromStrokes(front.strokes, graph_options)
                                     .Simplified(kGraphTolerance * options.sketch.image_size);
  MrfSketchTree tree;
  const DrawnTree drawn_tree = DrawnSegments(graph, views.cameras);
  const SegmentTree& drawn = drawn_tree.segments;
  const Eigen::Vector3d& view = drawn_tree.view;
  SYLVA_CHECK_INPUT(drawn.Size() >= 2, drawings[0].source) << "the branch strokes have no length";
  const int chosen = SelectTemplate(exemplars, DrawnFootprint(drawn, view));
  const TreeExemplar& exemplar = exemplars[chosen];
  tree.template_name = exemplar.name;
  MrfOptions mrf = options.sketch_mrf.mrf;
  mrf.seed = options.general.seed;
  tree.result = InferBranchDepths(drawn, view, exemplar.parameters, mrf);
  PropagateBranches(exemplar.tree,
                    CrownOf(drawings[0], front, views.cameras, view, options.sketch.crown_opacity,
                            tree.result.tree),
                    mrf, &tree.result);
  const int drawn_segments = tree.result.drawn - 1;
  const int propagated = tree.result.tree.Size() - tree.result.drawn;
  PutBackChains(drawn_tree, &tree.result);
  const double height = options.sketch.tree_height;
  tree.skeleton = SkeletonOfSegments(tree.result.tree, kMaxEdge * height);
  AssignSketchRadii(options, &tree.skeleton);
  tree.drawing_cameras = views.drawing_cameras;
  tree.front_view = views.cameras;
  tree.front_matte = front.matte;
  std::ostringstream brief;
  brief << "Branches by MRF (Chen 2008): " << drawn_segments << " drawn segments, template '"
        << exemplar.name << "', " << tree.result.icm_sweeps << " ICM sweeps, "
        << tree.result.em_iterations << " EM rounds, " << tree.result.interpenetrations
        << " interpenetrations pushed apart; " << propagated << " segments propagated; "
        << tree.skeleton.NumNodes() << " skeleton nodes.";
  tree.brief = brief.str();
  tree.position_source = "drawing (MRF depths, self-similar propagation)";
  tree.branching_source = "drawing and self-similar propagation";
  return tree;
}

namespace {

// What the silhouette method reads from a drawing, on the front view's
// plane (x across, z up).
struct SilhouetteInputs {
  Outline2 trunk, crown;
  double crown_low = 0.0, crown_high = 0.0;  // the crown's lowest and highest z
  std::vector<Outline2> drawn, sub_silhouettes;
};

// The trunk: the branch stroke with an end at the base, from there up
// (vertical without one), taken up to kLeaderShare of the crown's height;
// the other branch strokes are drawn branches. A drawing without branch
// strokes gets its views' inferred branches, which this method infers its
// own way: they are not read.
void ReadSilhouetteStrokes(const SketchDrawing& drawing, const SketchViews& views,
                           SilhouetteInputs* inputs) {
  const SketchView& front = views.views[0];
  const double crown_low = inputs->crown_low, crown_high = inputs->crown_high;
  const Eigen::Vector2d base = OnFrontPlane(views.cameras, *front.strokes.root);
  int trunk_stroke = -1;
  double nearest = kTrunkFootShare * (crown_high - base.y());
  std::vector<Outline2> strokes;
  for (const Stroke& stroke : front.strokes.strokes) {
    Outline2 line;
    for (const Eigen::Vector2d& p : stroke.points) line.push_back(OnFrontPlane(views.cameras, p));
    if (line.size() < 2) continue;
    if ((line.back() - base).norm() < (line.front() - base).norm()) {
      std::reverse(line.begin(), line.end());
    }
    if ((line.front() - base).norm() <= nearest) {
      nearest = (line.front() - base).norm();
      trunk_stroke = static_cast<int>(strokes.size());
    }
    strokes.push_back(std::move(line));
  }
  const int drawn_branch_strokes = static_cast<int>(
      std::count_if(drawing.strokes.begin(), drawing.strokes.end(),
                    [](const SketchStroke& s) { return s.role == StrokeRole::kBranch; }));
  if (drawn_branch_strokes == 0) trunk_stroke = -1;
  inputs->trunk = trunk_stroke >= 0 ? strokes[trunk_stroke] : Outline2{base};
  const double leader = crown_low + kLeaderShare * (crown_high - crown_low);
  if (inputs->trunk.back().y() < leader)
    inputs->trunk.emplace_back(inputs->trunk.back().x(), leader);
  if (drawn_branch_strokes >= 2 && front.strokes.strokes.size() >= 2) {
    for (size_t k = 0; k < strokes.size(); ++k) {
      if (static_cast<int>(k) != trunk_stroke) inputs->drawn.push_back(strokes[k]);
    }
  }
}

// Sub-silhouettes: closed crown strokes well inside the crown's size.
std::vector<Outline2> SubSilhouettesOf(const SketchDrawing& drawing, const SketchViews& views,
                                       const Outline2& crown) {
  std::vector<Outline2> sub_silhouettes;
  const double crown_area = OutlineArea(crown);
  for (const SketchStroke& stroke : drawing.strokes) {
    if (stroke.role != StrokeRole::kCrown || stroke.points.size() < 3) continue;
    Outline2 outline;
    for (const Eigen::Vector2d& p : stroke.points) {
      outline.push_back(OnFrontPlane(views.drawing_cameras, p));
    }
    // The share of its perimeter inside the crown, from points evenly
    // spaced along it (its vertices alone may be few: a rectangle).
    Outline2 closed = outline;
    closed.push_back(outline.front());
    double perimeter = 0.0;
    for (size_t i = 1; i < closed.size(); ++i) perimeter += (closed[i] - closed[i - 1]).norm();
    int inside = 0;
    for (int k = 0; k < kPerimeterSamples; ++k) {
      double walk = perimeter * (k + 0.5) / kPerimeterSamples;
      size_t i = 1;
      while (i + 1 < closed.size() && walk > (closed[i] - closed[i - 1]).norm()) {
        walk -= (closed[i] - closed[i - 1]).norm();
        ++i;
      }
      const Eigen::Vector2d edge = closed[i] - closed[i - 1];
      const double t = edge.norm() > 0 ? std::min(1.0, walk / edge.norm()) : 0.0;
      inside += InsideOutline(crown, closed[i - 1] + t * edge);
    }
    if (OutlineArea(outline) < kSubSilhouetteShare * crown_area &&
        inside >= kSubSilhouetteInside * kPerimeterSamples) {
      sub_silhouettes.push_back(outline);
    }
  }
  return sub_silhouettes;
}

// The trunk's radius as drawn, in world units: the median width of the
// drawing's silhouette (its matte at half the crown's opacity or more:
// lines, wood between outlines, enclosed regions) across the trunk at
// kTrunkWidthHeights of the way from the base to the crown; 0 if no wider
// than kOutlinedTrunkLines drawn lines (a trunk drawn as one line says
// nothing of its width; outlines do).
double DrawnTrunkRadius(const SketchView& front, const ImageSet& cameras, const Outline2& trunk,
                        double crown_low, double line_width_px, double crown_opacity) {
  const FloatImage& matte = front.matte;
  auto opaque = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < matte.width() && y < matte.height() &&
           matte.at(x, y) >= 0.5 * crown_opacity;
  };
  const double pixel = (OnFrontPlane(cameras, Eigen::Vector2d(1.5, 0.5)) -
                        OnFrontPlane(cameras, Eigen::Vector2d(0.5, 0.5)))
                           .norm();
  std::vector<double> widths;
  for (double share : kTrunkWidthHeights) {
    const double z = trunk.front().y() + share * (crown_low - trunk.front().y());
    // The trunk's point at height z (its first one at or above it).
    Eigen::Vector2d at = trunk.back();
    for (const Eigen::Vector2d& p : trunk) {
      if (p.y() >= z) {
        at = p;
        break;
      }
    }
    Eigen::Vector2d px;
    if (!cameras.Project(0, Eigen::Vector3d(at.x(), 0.0, z), &px)) continue;
    const int y = static_cast<int>(px.y());
    int x = static_cast<int>(px.x());
    for (int d = 0; d <= kTrunkSearchPixels && !opaque(x, y); ++d) {
      if (opaque(x - d, y))
        x -= d;
      else if (opaque(x + d, y))
        x += d;
    }
    if (!opaque(x, y)) continue;
    int left = x, right = x;
    while (opaque(left - 1, y)) --left;
    while (opaque(right + 1, y)) ++right;
    widths.push_back(right - left + 1);
  }
  if (widths.empty()) return 0.0;
  std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
  const double width = widths[widths.size() / 2];
  return width > kOutlinedTrunkLines * line_width_px ? 0.5 * width * pixel : 0.0;
}

// The trunk at least `radius` thick below the crown (height `crown_low`),
// tapering from there to its tip: the drawing shows the trunk's width, the
// pipe model keeps the branches' (a whole pipe model scaled to a thick
// drawn trunk made its laterals overlap: up to 1,851 bark components on
// the bundled doodles instead of 97).
void ThickenTrunk(double radius, double crown_low, SkeletonGraph* skeleton) {
  if (radius <= 0) return;
  const BranchAxis trunk = skeleton->BranchAxes().front();
  const double top = skeleton->nodes[trunk.back()].position.z();
  for (int node : trunk) {
    const double z = skeleton->nodes[node].position.z();
    const double share = z <= crown_low ? 1.0 : std::max(0.0, (top - z) / (top - crown_low));
    skeleton->nodes[node].radius = std::max(skeleton->nodes[node].radius, share * radius);
  }
}

}  // namespace

SketchTree MakeSilhouetteSketchTree(const std::vector<SketchDrawing>& drawings,
                                    const PipelineOptions& options) {
  SYLVA_CHECK(!drawings.empty()) << "needs a drawing";
  const SketchDrawing& drawing = drawings[0];
  const SketchViews views = MakeSketchViews({drawing}, options.sketch);
  const SketchView& front = views.views[0];
  SilhouetteInputs inputs;
  for (const Eigen::Vector2d& p : CrownOutlineOf(
           WithoutTrunk(front.matte, options.sketch.crown_opacity), options.sketch.crown_opacity)) {
    inputs.crown.push_back(OnFrontPlane(views.cameras, p));
  }
  // The crown is an enclosed region (filled at the crown's opacity), not
  // the drawn lines alone (opaque; their anti-aliased edges are a sliver).
  const float crown_opacity = static_cast<float>(options.sketch.crown_opacity);
  int enclosed = 0;
  for (int y = 0; y < front.matte.height(); ++y) {
    for (int x = 0; x < front.matte.width(); ++x) {
      const float v = front.matte.at(x, y);
      enclosed += v >= 0.5f * crown_opacity && v <= crown_opacity + 1e-3f;
    }
  }
  SYLVA_CHECK_INPUT(inputs.crown.size() >= 8 &&
                        enclosed >= kMinCrownShare * front.matte.width() * front.matte.height(),
                    drawing.source)
      << "encloses no crown for the silhouette method (Sketch.method=silhouette needs a closed "
         "outline of the crown; Sketch.method=flow makes a tree of branch strokes alone)";
  inputs.crown_low = inputs.crown_high = inputs.crown[0].y();
  for (const Eigen::Vector2d& p : inputs.crown) {
    inputs.crown_low = std::min(inputs.crown_low, p.y());
    inputs.crown_high = std::max(inputs.crown_high, p.y());
  }
  ReadSilhouetteStrokes(drawing, views, &inputs);
  inputs.sub_silhouettes = SubSilhouettesOf(drawing, views, inputs.crown);
  SilhouetteTreeOptions silhouette = options.sketch_mrf.silhouette;
  silhouette.seed = options.general.seed;
  const SilhouetteStructure structure = InferSilhouetteStructure(
      inputs.trunk, inputs.crown, inputs.sub_silhouettes, inputs.drawn, silhouette);
  const SilhouetteTree placed =
      PlaceSilhouetteTree(structure, kMaxEdge * options.sketch.tree_height, silhouette);
  SketchTree tree;
  tree.skeleton = placed.skeleton;
  AssignSketchRadii(options, &tree.skeleton);
  const double line_width_px = options.sketch.line_width * options.sketch.image_size;
  ThickenTrunk(DrawnTrunkRadius(front, views.cameras, inputs.trunk, inputs.crown_low, line_width_px,
                                options.sketch.crown_opacity),
               inputs.crown_low, &tree.skeleton);
  tree.drawing_cameras = views.drawing_cameras;
  tree.front_view = views.cameras;
  tree.front_matte = front.matte;
  std::ostringstream brief;
  brief << "Branches from silhouettes (Wither 2009): " << structure.branches.size() - 1
        << " branches in the drawing's plane over " << silhouette.levels << " levels ("
        << structure.drawn_branches << " drawn, " << structure.drawn_crowns
        << " drawn sub-silhouettes, " << structure.coverage_branches << " added for coverage, "
        << structure.copied_styles << " styles copied); " << placed.extra_branches
        << " more placed in depth; phyllotaxis " << silhouette.phyllotaxis << "; "
        << tree.skeleton.NumNodes() << " skeleton nodes.";
  tree.brief = brief.str();
  tree.position_source = "drawing (crown silhouettes; depth by a Gibbs process)";
  tree.branching_source = "crown silhouettes and botanical rules (Wither 2009)";
  return tree;
}

QsmMeshing MeshSketchTree(const SketchTree& tree, const PipelineOptions& options, QsmModel* qsm) {
  QsmMeshing meshing = MeshSkeletonTree(tree.skeleton, "m", kMergeFraction, options, qsm);
  // What the figures in qsm.csv, metrics.json and the report come from.
  qsm->position_source = tree.position_source;
  qsm->branching_source = tree.branching_source;
  return meshing;
}

SilhouetteScores FrontViewFit(const SketchTree& tree, const QsmMeshing& meshing,
                              const PipelineOptions& options) {
  TriangleMesh mesh = meshing.bark;
  mesh.Append(meshing.leaves.Bake());
  constexpr int kSamples = 2;
  const FloatImage coverage = MeshRenderer(mesh).RenderCoverage(
      tree.front_view.CameraOf(0), tree.front_view.views[0].cam_from_world, kSamples);
  return CompareSilhouettes(coverage, tree.front_matte, 0.5f,
                            0.5f * static_cast<float>(options.sketch.crown_opacity));
}

std::vector<fs::path> WriteSketchTree(const SketchTree& tree, const QsmModel& qsm,
                                      const QsmMeshing& meshing, const PipelineOptions& options,
                                      const fs::path& out_dir) {
  std::vector<fs::path> paths = WriteQsmMeshing(meshing, qsm, out_dir, options);
  WriteSkeletonJson(out_dir / "skeleton.json", tree.skeleton, "m");
  paths.push_back(out_dir / "skeleton.json");
  WriteCameraFile(out_dir / "sketch_cameras.json", tree.drawing_cameras, "m");
  paths.push_back(out_dir / "sketch_cameras.json");
  return paths;
}

}  // namespace sylva
