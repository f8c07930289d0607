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
#include "reconstruct/attractors/livewire_target.h"
#include "reconstruct/attractors/overlay.h"
#include "simulate/particle_flow.h"
#include "sketch/stroke_graph.h"
#include "sketch/strokes.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {
namespace {

// Stream id for DeriveSeed(General.seed, stream) (tree_building.cc uses 1, 2).
constexpr uint64_t kLivewireSeedStream = 3;

// The summary's figures: views by graph source, and the views with a note.
const std::pair<const char*, const char*> kSourceFigures[] = {
    {"edited", "edited"},     {"strokes", "strokes"}, {"strokes+livewire", "strokes_livewire"},
    {"livewire", "livewire"}, {"none", "none"},       {"noted (see attractors.json)", "noted"}};

struct ViewAttractors {
  AttractorGraph2D graph;
  std::string source = "none";
  std::string note;  // why the graph differs from the usual, if it does
  // A graph traced on the photo: what it was traced from (TraceKey), and
  // whether it came from the cache rather than a trace.
  std::string trace_key;
  bool cached = false;
};

// The graphs traced on photos, per view, in cache/attractors/ (<photo>.json
// the graph, <photo>.key its key, source and note): a view whose photo,
// edited matte, strokes, livewire target and options have not changed keeps
// its graph and overlay, so after a stroke or density edit on one view only
// that view is traced again. Not read in a cold run (StageContext::cold).
struct TraceCache {
  fs::path dir;
  std::string options_text;  // the Attractors options and the seed
  bool read = true;
};

// Livewire targets are keyed to this fraction of a pixel, so that a base
// estimate that moves by a rounding error after a density edit elsewhere
// (the density changes a little everywhere) keeps the views' graphs; a kept
// graph's root is moved to the exact target.
constexpr double kTargetKeyPixels = 1.0 / 16.0;

// What a view's traced graph depends on: the options, the photo (path and
// stamp), the edited matte's values, the strokes drawn (path and stamp) and
// the livewire target.
std::string TraceKey(const TraceCache& cache, const Project& project, const std::string& name,
                     const FloatImage& matte, const Eigen::Vector2d& target) {
  std::ostringstream text;
  text << cache.options_text << ";" << FileKey(project, project.PhotoPath(name)) << ";"
       << FileKey(project, project.StrokesPath(name)) << ";"
       << HexString(Fnv1a64(matte.data(), matte.NumPixels() * matte.channels() * sizeof(float)))
       << ";" << std::llround(target.x() / kTargetKeyPixels) << ","
       << std::llround(target.y() / kTargetKeyPixels);
  return HexString(Fnv1a64(text.str()));
}

fs::path TraceCachePath(const TraceCache& cache, const std::string& name,
                        const std::string& extension) {
  return cache.dir / fs::path(name).replace_extension(extension).filename();
}

// The cached graph of view `name` if its key is `result->trace_key`.
bool ReadCachedTrace(const TraceCache& cache, const std::string& name, ViewAttractors* result) {
  const fs::path key_path = TraceCachePath(cache, name, ".key");
  const fs::path graph_path = TraceCachePath(cache, name, ".json");
  std::error_code ec;
  if (!cache.read || !fs::is_regular_file(key_path, ec) || !fs::is_regular_file(graph_path, ec)) {
    return false;
  }
  std::istringstream record(ReadFileToString(key_path));
  std::string key, source, note;
  if (!std::getline(record, key) || key != result->trace_key || !std::getline(record, source)) {
    return false;
  }
  std::getline(record, note);
  try {
    result->graph = ReadAttractorGraphJson(graph_path);
  } catch (const InputError&) {
    return false;  // a damaged cache only means tracing again
  }
  result->source = source;
  result->note = note;
  result->cached = true;
  return true;
}

// Keeps every freshly traced graph in the cache (the graph before its key).
void WriteTraceCache(const TraceCache& cache, const ImageSet& views,
                     const std::vector<ViewAttractors>& results) {
  for (int v = 0; v < views.NumViews(); ++v) {
    const ViewAttractors& result = results[v];
    if (result.trace_key.empty() || result.cached) continue;
    const std::string& name = views.views[v].name;
    fs::create_directories(cache.dir);
    WriteAttractorGraphJson(TraceCachePath(cache, name, ".json"), result.graph, name);
    AtomicWriteString(TraceCachePath(cache, name, ".key"),
                      result.trace_key + "\n" + result.source + "\n" + result.note + "\n");
  }
}

// The tree base, as the skeleton stage finds it.
Eigen::Vector3d TreeBaseInWorld(const StageContext& context) {
  if (context.options.skeleton.base.allFinite()) return context.options.skeleton.base;
  return EstimateTreeBase(ReadDensityGrid(context.RequireOutput("density.vdb", "density")),
                          context.options.tree_base);
}

// Step 1: the view's graph as a person made it (a whole graph, or strokes
// joined into one), else source "livewire" (mode auto: to be traced) or
// "none".
ViewAttractors ReadViewEdits(const Project& project, const std::string& name, const Camera& camera,
                             const AttractStageOptions& options) {
  ViewAttractors result;
  const fs::path edit = project.AttractorEditPath(name);
  const fs::path strokes_path = project.StrokesPath(name);
  if (!edit.empty()) {
    result.graph = ReadAttractorGraphJson(edit);
    SYLVA_CHECK_INPUT(result.graph.FitsAspectOf(camera.width(), camera.height()), edit.string())
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
  return result;
}

// Step 2: traces the graph of a "livewire" view on its photo from the tree
// base, or snaps drawn strokes onto it (Attractors.snap_strokes); or takes
// the graph from the cache when none of what it depends on changed.
void TraceOnPhoto(const Project& project, const ImageSet& views, int v,
                  const Eigen::Vector3d& base_in_world, const AttractStageOptions& options,
                  const TraceCache& cache, ViewAttractors* result) {
  const bool needs_photo =
      result->source == "livewire" || (result->source == "strokes" && options.snap_strokes);
  if (!needs_photo) return;
  const std::string& name = views.views[v].name;
  const Camera& camera = views.CameraOf(v);
  const FloatImage matte = project.LoadEditedMatte(views, v);
  LivewireTarget target;
  if (result->source == "livewire") {
    target = ChooseLivewireTarget(views, v, base_in_world, matte, options.livewire.matte_threshold);
    result->note = target.note;
    if (!target.found) {
      result->source = "none";
      return;
    }
  }
  result->trace_key = TraceKey(cache, project, name, matte, target.point_in_image);
  if (ReadCachedTrace(cache, name, result)) {
    if (result->source == "livewire")
      result->graph.nodes[result->graph.root].position = target.point_in_image;
    return;
  }
  const FloatImage photo = ReadImage(project.PhotoPath(name));
  SYLVA_CHECK_INPUT(photo.width() == camera.width() && photo.height() == camera.height(),
                    project.PhotoPath(name).string())
      << "the photo is " << photo.width() << "x" << photo.height() << " but its camera is "
      << camera.width() << "x" << camera.height();
  if (result->source == "strokes") {
    result->graph = SnapGraphToImage(result->graph, photo, matte, options.livewire);
    result->source = "strokes+livewire";
    return;
  }
  result->graph = TraceAttractorGraph(photo, matte, target.point_in_image, {}, options.livewire);
}

// Every view's graph (steps 1 and 2), in parallel.
std::vector<ViewAttractors> AttractViews(const Project& project, const ImageSet& views,
                                         const Eigen::Vector3d& base_in_world,
                                         const AttractStageOptions& options,
                                         const TraceCache& cache, ProgressTask* task) {
  const int n = views.NumViews();
  std::vector<ViewAttractors> results(n);
  std::mutex mutex;
  int done = 0;
  ParallelForFirstError(n, [&](int v) {
    task->CheckCancelled();
    results[v] = ReadViewEdits(project, views.views[v].name, views.CameraOf(v), options);
    TraceOnPhoto(project, views, v, base_in_world, options, cache, &results[v]);
    std::lock_guard<std::mutex> lock(mutex);
    task->Update(static_cast<double>(++done) / n);
  });
  return results;
}

// Every graph drawn on its photo (photos decoded again rather than all held,
// so a failure while attracting leaves the old outputs untouched); a graph
// from the cache keeps the overlay drawn when it was traced.
void WriteOverlays(const Project& project, const ImageSet& views,
                   const std::vector<ViewAttractors>& results, const ProgressTask& task) {
  ParallelForFirstError(views.NumViews(), [&](int v) {
    task.CheckCancelled();
    if (results[v].source == "none") return;
    const std::string& name = views.views[v].name;
    std::error_code ec;
    if (results[v].cached && fs::is_regular_file(project.AttractorOverlayPath(name), ec)) return;
    WriteImage(project.AttractorOverlayPath(name),
               DrawAttractorOverlay(ReadImage(project.PhotoPath(name)), results[v].graph));
  });
}

// Writes the graphs, then the index (so the index never names a graph not
// written), adding the files to `run`; returns the number of views by
// source (and of noted views).
std::map<std::string, int> WriteGraphsAndIndex(const Project& project, const ImageSet& views,
                                               const std::vector<ViewAttractors>& results,
                                               const AttractStageOptions& options, StageRun* run) {
  Json entries = Json::object();
  std::map<std::string, int> counts;
  for (int v = 0; v < views.NumViews(); ++v) {
    const std::string& name = views.views[v].name;
    const ViewAttractors& result = results[v];
    ++counts[result.source];
    Json entry = {{"source", result.source}};
    if (!result.note.empty()) {
      entry["note"] = result.note;
      ++counts["noted (see attractors.json)"];
    }
    if (result.source != "none") {
      const fs::path path = project.AttractorGraphPath(name);
      WriteAttractorGraphJson(path, result.graph, name);
      entry["graph"] =
          fs::relative(path, project.AttractorIndexPath().parent_path()).generic_string();
      entry["nodes"] = result.graph.NumNodes();
      entry["length_px"] = result.graph.TotalLength();
      run->outputs.push_back(path);
      if (options.write_overlays) run->outputs.push_back(project.AttractorOverlayPath(name));
    }
    entries[name] = entry;
  }
  WriteJsonFile(project.AttractorIndexPath(), {{"format", "sylva-attractor-index"},
                                               {"version", 1},
                                               {"mode", options.mode},
                                               {"views", entries}});
  run->outputs.push_back(project.AttractorIndexPath());
  return counts;
}

// The brief and the figures from the number of views by source.
void SummariseAttract(const std::string& mode, int num_views,
                      const std::map<std::string, int>& counts, StageRun* run) {
  std::ostringstream brief;
  brief << "Attractor graphs (mode " << mode << ") for " << num_views << " input views:";
  for (const auto& [source, count] : counts) brief << " " << count << " " << source << ";";
  brief << " written to out/attractors/.";
  run->brief = brief.str();
  run->AddFigure("views", num_views, "views");
  for (const auto& [source, key] : kSourceFigures) {
    const auto found = counts.find(source);
    run->AddFigure(key, found == counts.end() ? 0 : found->second, "views");
  }
}

}  // namespace

StageRun RunAttractStage(const StageContext& context) {
  AttractStageOptions options = context.options.attract;
  options.livewire.seed = DeriveSeed(context.options.general.seed, kLivewireSeedStream);
  StageRun run;
  StepClock clock(&run.profile);
  const ImageSet views = context.InputViews();
  std::vector<ViewAttractors> results(views.NumViews());
  if (options.mode != "off") {
    const Eigen::Vector3d base_in_world = TreeBaseInWorld(context);
    clock.Lap("tree_base");
    ProgressTask task(context.progress, "attract: attractor graphs");
    const TraceCache cache{context.project.CacheDir() / "attractors",
                           OptionsText(context.options, {"Attractors.", "General.seed"}),
                           !context.cold};
    results = AttractViews(context.project, views, base_in_world, options, cache, &task);
    clock.Lap("graphs");
    if (options.write_overlays) {
      WriteOverlays(context.project, views, results, task);
      clock.Lap("write_overlays");
    }
  }
  const std::map<std::string, int> counts =
      WriteGraphsAndIndex(context.project, views, results, options, &run);
  WriteTraceCache({context.project.CacheDir() / "attractors", "", false}, views, results);
  clock.Lap("write");
  SummariseAttract(options.mode, views.NumViews(), counts, &run);
  int traced = 0;
  for (const ViewAttractors& result : results)
    traced += !result.trace_key.empty() && !result.cached;
  run.AddFigure("traced", traced, "views");
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
