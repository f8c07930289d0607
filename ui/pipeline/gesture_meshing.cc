#include "ui/pipeline/gesture_meshing.h"

#include <nlohmann/json.hpp>
#include <sstream>

#include "core/io/skeleton_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "ui/pipeline/staged_output.h"

namespace sylva {
namespace {

constexpr char kUnits[] = "m";
// QsmToSkeletonOptions::merge_fraction for the grown skeleton, as for the
// MRF sketch trees (sketch_mrf.cc).
constexpr double kMergeFraction = 0.1;

std::string RoiJson(const GestureTree& tree) {
  const Supertoroid& r = tree.roi;
  const nlohmann::json json = {
      {"units", kUnits},
      {"shape", "supertoroid (Murakami et al. eq. 3; sketch/gesture_tree.h)"},
      {"fitted_to", tree.roi_from_strokes ? "roi strokes" : "the gestures"},
      {"center", {r.center.x(), r.center.y(), r.center.z()}},
      {"axis_slope", {r.slope.x(), r.slope.y()}},
      {"radii", {r.ax, r.ay, r.az}},
      {"n", r.n},
      {"e", r.e},
      {"alpha", r.alpha}};
  return json.dump(1) + "\n";
}

}  // namespace

GestureMeshing MeshGestures(const GestureSet& gestures, const PipelineOptions& options) {
  options.Check();
  GestureMeshing meshing;
  GestureTreeOptions tree_options = options.gesture;
  tree_options.seed = options.general.seed;
  const LsystemGrammar grammar = LoadGestureGrammar(tree_options);
  meshing.grammar_source = grammar.source();
  meshing.tree = GrowGestureTree(gestures, grammar, tree_options);
  meshing.meshing =
      MeshSkeletonTree(meshing.tree.skeleton, kUnits, kMergeFraction, options, &meshing.qsm);
  // What the figures in qsm.csv, metrics.json and the report come from.
  meshing.qsm.position_source = "gestures (trunks) and L-system (branches)";
  meshing.qsm.branching_source = "L-system";
  std::ostringstream brief;
  brief << "Gestures " << gestures.source << " (" << gestures.strokes.size()
        << " strokes), grammar " << meshing.grammar_source << ", " << tree_options.iterations
        << " derivation steps, seed " << tree_options.seed << ".\n"
        << meshing.tree.brief << "\n"
        << meshing.meshing.brief;
  meshing.brief = brief.str();
  return meshing;
}

std::vector<std::filesystem::path> WriteGestureMeshing(const GestureMeshing& meshing,
                                                       const std::filesystem::path& out_dir,
                                                       const PipelineOptions& options) {
  std::vector<std::filesystem::path> paths =
      WriteQsmMeshing(meshing.meshing, meshing.qsm, out_dir, options);
  paths.push_back(out_dir / "skeleton.json");
  WriteSkeletonJson(paths.back(), meshing.tree.skeleton, kUnits);
  paths.push_back(out_dir / "lstring.txt");
  AtomicWriteString(paths.back(), meshing.tree.lstring_text + "\n");
  paths.push_back(out_dir / "roi.json");
  AtomicWriteString(paths.back(), RoiJson(meshing.tree));
  return paths;
}

GestureMeshing RunGesture(const std::filesystem::path& gesture_path,
                          const std::filesystem::path& out_dir, const PipelineOptions& options,
                          const OptionRegistry& registry,
                          std::vector<std::filesystem::path>* written) {
  CheckOutDirIsFree(out_dir);
  const GestureMeshing meshing = MeshGestures(ReadGesture(gesture_path), options);
  std::vector<std::filesystem::path> paths =
      WriteStagedOutDir(out_dir, registry, [&](const std::filesystem::path& staging) {
        return WriteGestureMeshing(meshing, staging, options);
      });
  if (written != nullptr) *written = std::move(paths);
  return meshing;
}

}  // namespace sylva
