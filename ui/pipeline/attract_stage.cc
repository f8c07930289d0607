// The attract stage (thesis 3.2.2): one 2D attractor graph per input view,
// the trunk and main branches the particle flow is steered by. For each
// photo, the first that exists:
//   1. edits/<photo>.attractors.json: a whole graph a person made (same
//      format as the output), used as it is;
//   2. edits/<photo>.strokes.svg or .strokes.json: strokes a person drew,
//      joined into a graph (sketch/stroke_graph.h) and, with
//      Attractors.snap_strokes, snapped onto the photo by livewire;
//   3. with Attractors.mode=auto: a graph traced by livewire on the photo
//      from automatic seeds to the tree base (Skeleton.base, or estimated
//      from the density as the skeleton stage does) projected into it.
// Attractors.mode=edits uses only 1 and 2; off writes no graph. Outputs:
// out/attractors/<photo>.json and <photo>.png (the graph drawn on the photo),
// and the index out/attractors/attractors.json naming every input view's
// graph file and source ("edited", "strokes", "livewire" or "none"), which
// the skeleton stage reads.
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>

#include "core/io/attractor_io.h"
#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "core/io/vdb_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/random.h"
#include "core/util/threading.h"
#include "reconstruct/attractors/livewire.h"
#include "reconstruct/attractors/overlay.h"
#include "simulate/particle_flow.h"
#include "sketch/stroke_graph.h"
#include "sketch/strokes.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {
namespace {

// Stream id for DeriveSeed(General.seed, stream) (tree_building.cc uses 1, 2).
constexpr uint64_t kLivewireSeedStream = 3;

struct ViewAttractors {
  AttractorGraph2D graph;
  std::string source = "none";
  std::string note;  // why the graph differs from the usual, if it does
};

// The centre of the foreground pixel (matte >= threshold) nearest to `point`
// (ties: the first in row order). InputError if the matte has none.
Eigen::Vector2d NearestForeground(const FloatImage& matte, const Eigen::Vector2d& point,
                                  double threshold) {
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d nearest = point;
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      if (matte.at(x, y, 0) < threshold) continue;
      const Eigen::Vector2d centre(x + 0.5, y + 0.5);
      const double d2 = (centre - point).squaredNorm();
      if (d2 < best) best = d2, nearest = centre;
    }
  }
  SYLVA_CHECK_INPUT(std::isfinite(best), "matte") << "the matte has no foreground pixel";
  return nearest;
}

}  // namespace

StageRun RunAttractStage(const StageContext& context) {
  const Project& project = context.project;
  AttractStageOptions options = context.options.attract;
  options.livewire.seed = DeriveSeed(context.options.general.seed, kLivewireSeedStream);
  const ImageSet views = context.InputViews();
  const int n = views.NumViews();
  std::vector<ViewAttractors> results(n);
  StageRun run;
  if (options.mode != "off") {
    // The tree base, as the skeleton stage finds it.
    const Eigen::Vector3d base =
        context.options.skeleton.base.allFinite()
            ? context.options.skeleton.base
            : EstimateTreeBase(ReadDensityGrid(context.RequireOutput("density.vdb", "density")),
                               context.options.tree_base);
    ProgressTask task(context.progress, "attract: attractor graphs");
    std::mutex mutex;
    int done = 0;
    // One view's graph (results[v]).
    const auto attract_view = [&](int v) {
      const std::string& name = views.views[v].name;
      const Camera& camera = views.CameraOf(v);
      ViewAttractors& result = results[v];
      const fs::path edit = project.AttractorEditPath(name);
      const fs::path strokes_path = project.StrokesPath(name);
      if (!edit.empty()) {
        result.graph = ReadAttractorGraphJson(edit);
        const double aspect_error =
            std::abs(result.graph.width * static_cast<double>(camera.height()) -
                     result.graph.height * static_cast<double>(camera.width()));
        SYLVA_CHECK_INPUT(aspect_error <= 0.01 * result.graph.width * camera.height(),
                          edit.string())
            << "the graph is for a " << result.graph.width << "x" << result.graph.height
            << " image, the photo is " << camera.width() << "x" << camera.height();
        result.source = "edited";
      } else if (!strokes_path.empty()) {
        const StrokeSet strokes = ReadStrokes(strokes_path, camera.width(), camera.height());
        result.graph = GraphFromStrokes(strokes, options.strokes);
        result.source = "strokes";
      } else if (options.mode == "auto") {
        result.source = "livewire";
      }
      if (result.source == "none") return;
      const bool needs_photo =
          result.source == "livewire" || (result.source == "strokes" && options.snap_strokes);
      if (!needs_photo) return;
      const FloatImage photo = ReadImage(project.PhotoPath(name));
      const FloatImage matte = project.LoadMatte(views, v);
      SYLVA_CHECK_INPUT(photo.width() == camera.width() && photo.height() == camera.height(),
                        project.PhotoPath(name).string())
          << "the photo is " << photo.width() << "x" << photo.height() << " but its camera is "
          << camera.width() << "x" << camera.height();
      if (result.source == "livewire") {
        Eigen::Vector2d target;
        if (!views.Project(v, base, &target)) {
          result.source = "none";  // the base is behind the camera
          result.note = "tree base behind the camera";
          return;
        }
        if (!(target.x() >= 0 && target.y() >= 0 && target.x() <= camera.width() &&
              target.y() <= camera.height())) {
          // The base is out of frame (a close-up): the paths end where the
          // tree leaves the photo nearest to it.
          target = NearestForeground(matte, target, options.livewire.matte_threshold);
          result.note = "tree base outside the photo; target moved to the matte's nearest point";
        }
        result.graph = TraceAttractorGraph(photo, matte, target, {}, options.livewire);
      } else if (result.source == "strokes" && options.snap_strokes) {
        result.graph = SnapGraphToImage(result.graph, photo, matte, options.livewire);
        result.source = "strokes+livewire";
      }
    };
    ParallelForFirstError(n, [&](int v) {
      task.CheckCancelled();
      attract_view(v);
      std::lock_guard<std::mutex> lock(mutex);
      task.Update(static_cast<double>(++done) / n);
    });
    // Every graph is known: now the overlays (photos decoded again rather
    // than all held, so a failure above leaves the old outputs untouched).
    if (options.write_overlays) {
      ParallelForFirstError(n, [&](int v) {
        task.CheckCancelled();
        if (results[v].source == "none") return;
        const std::string& name = views.views[v].name;
        WriteImage(project.AttractorOverlayPath(name),
                   DrawAttractorOverlay(ReadImage(project.PhotoPath(name)), results[v].graph));
      });
    }
  }
  // Graphs, then the index (so the index never names a graph not written).
  Json index = {{"format", "sylva-attractor-index"}, {"version", 1}, {"mode", options.mode}};
  Json entries = Json::object();
  std::map<std::string, int> counts;
  for (int v = 0; v < n; ++v) {
    const std::string& name = views.views[v].name;
    ++counts[results[v].source];
    Json entry = {{"source", results[v].source}};
    if (!results[v].note.empty()) {
      entry["note"] = results[v].note;
      ++counts["noted (see attractors.json)"];
    }
    if (results[v].source != "none") {
      const fs::path path = project.AttractorGraphPath(name);
      WriteAttractorGraphJson(path, results[v].graph, name);
      entry["graph"] =
          fs::relative(path, project.AttractorIndexPath().parent_path()).generic_string();
      entry["nodes"] = results[v].graph.NumNodes();
      entry["length_px"] = results[v].graph.TotalLength();
      run.outputs.push_back(path);
      if (options.write_overlays) run.outputs.push_back(project.AttractorOverlayPath(name));
    }
    entries[name] = entry;
  }
  index["views"] = entries;
  WriteJsonFile(project.AttractorIndexPath(), index);
  run.outputs.push_back(project.AttractorIndexPath());
  std::ostringstream brief;
  brief << "Attractor graphs (mode " << options.mode << ") for " << n << " input views:";
  for (const auto& [source, count] : counts) brief << " " << count << " " << source << ";";
  brief << " written to out/attractors/.";
  run.brief = brief.str();
  return run;
}

std::vector<AttractorGraph2D> LoadAttractorGraphs(const Project& project, const ImageSet& views) {
  std::vector<AttractorGraph2D> graphs(views.NumViews());
  const fs::path index_path = project.AttractorIndexPath();
  const Json index = ReadJsonFile(index_path);
  SYLVA_CHECK_INPUT(index.is_object() && index.value("format", "") == "sylva-attractor-index" &&
                        index.contains("views") && index["views"].is_object(),
                    index_path.string())
      << "not a sylva attractor index; re-run 'sylva attract'";
  for (int v = 0; v < views.NumViews(); ++v) {
    const std::string& name = views.views[v].name;
    if (!index["views"].contains(name)) continue;
    const Json& entry = index["views"][name];
    if (!entry.is_object() || !entry.contains("graph") || !entry["graph"].is_string()) continue;
    graphs[v] =
        ReadAttractorGraphJson(index_path.parent_path() / entry["graph"].get<std::string>());
  }
  return graphs;
}

}  // namespace sylva
