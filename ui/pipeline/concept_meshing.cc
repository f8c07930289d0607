#include "ui/pipeline/concept_meshing.h"

#include <nlohmann/json.hpp>
#include <sstream>

#include "core/io/image_io.h"
#include "core/io/lpy_io.h"
#include "core/io/mesh_io.h"
#include "core/io/mtg_io.h"
#include "core/io/qsm_io.h"
#include "core/io/skeleton_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "mesh/gltf_export.h"
#include "mesh/tree_metrics.h"
#include "mesh/wood.h"
#include "sketch/drawing_io.h"
#include "ui/pipeline/report.h"
#include "ui/pipeline/staged_output.h"
#include "ui/pipeline/tree_building.h"

namespace sylva {
namespace {

constexpr char kUnits[] = "m";

struct NamedView {
  const char* name;
  double azimuth_deg, elevation_deg;
};
// The drawing's own view, a three-quarter view from above, and the top view
// (the paper's figures 10, 12 and 16).
constexpr NamedView kViews[] = {{"front", 0, 0}, {"oblique", 35, 25}, {"top", 0, 90}};

nlohmann::json Vector(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

std::string OrgansJson(const ConceptPlant& plant) {
  nlohmann::json organs = nlohmann::json::array();
  for (size_t k = 0; k < plant.organs.size(); ++k) {
    const ConceptOrgan& organ = plant.organs[k];
    nlohmann::json entry = {{"node", organ.node},
                            {"layer", organ.layer},
                            {"azimuth_deg", organ.azimuth_deg},
                            {"branching_deg", organ.branching_deg},
                            {"base", Vector(organ.base)},
                            {"tip", Vector(organ.tip)},
                            {"reference_tip", Vector(organ.reference_tip)},
                            {"length", organ.length},
                            {"fit", organ.fit},
                            {"template_t", organ.template_t}};
    if (k > 0) entry["divergence_deg"] = MeasuredDivergenceDeg(plant.organs[k - 1], organ);
    organs.push_back(entry);
  }
  const nlohmann::json json = {{"units", kUnits},
                               {"phyllotaxis", ConceptPatternName(plant.pattern)},
                               {"divergence_deg", plant.divergence_deg},
                               {"organs", organs}};
  return json.dump(1) + "\n";
}

}  // namespace

TriangleMesh ConceptMeshing::Tree() const {
  TriangleMesh mesh = bark;
  mesh.Append(plant.blades);
  return mesh;
}

ConceptMeshing MeshConceptDrawing(const SketchDrawing& drawing, const PipelineOptions& options) {
  options.Check();
  ConceptMeshing meshing;
  meshing.structure = InterpretConceptDrawing(drawing);
  ConceptPlantOptions plant_options = options.concept_plant;
  plant_options.seed = options.general.seed;
  meshing.plant = BuildConceptPlant(meshing.structure, plant_options);
  WoodOptions wood = WoodOptionsOf(options);
  wood.twigs = false;  // the drawing is the whole plant
  const Wood meshed = MeshWood(meshing.plant.wood_skeleton, DensityGrid(), wood);
  meshing.bark = meshed.bark;
  std::ostringstream brief;
  brief << meshing.structure.BriefReport() << "\n" << meshing.plant.brief << "\n" << meshed.brief;
  const TriangleMesh tree = meshing.Tree();
  for (const NamedView& view : kViews) {
    meshing.drawings.push_back(DrawPenAndInk(
        tree, meshing.plant.veins, meshing.plant.construction,
        PenAndInkView::FromAngles(view.azimuth_deg, view.elevation_deg), options.pen_and_ink));
    meshing.view_names.push_back(view.name);
    brief << "\nPen and ink, " << view.name << ": " << meshing.drawings.back().BriefReport();
  }
  meshing.brief = brief.str();
  return meshing;
}

std::vector<std::filesystem::path> WriteConceptMeshing(const ConceptMeshing& meshing,
                                                       const std::filesystem::path& out_dir,
                                                       const PipelineOptions& options) {
  std::filesystem::create_directories(out_dir);
  const SkeletonGraph& skeleton = meshing.plant.skeleton;
  const TriangleMesh tree = meshing.Tree();
  std::vector<std::filesystem::path> paths;
  const auto out = [&](const std::string& name) {
    paths.push_back(out_dir / name);
    return paths.back();
  };
  GltfExportOptions gltf;
  gltf.extras["units"] = kUnits;
  gltf.extras["source"] = "concept sketch " + meshing.structure.source;
  gltf.extras["phyllotaxis"] = ConceptPatternName(meshing.plant.pattern);
  WriteGlb(out("tree.glb"), tree, gltf);
  WriteObj(out("tree.obj"), tree);
  WriteObj(out("bark.obj"), meshing.bark);
  WriteSkeletonJson(out("skeleton.json"), skeleton, kUnits);
  WriteQsmCsv(out("qsm.csv"), QsmFromSkeleton(skeleton, kUnits));
  WriteLpy(out("tree.lpy"), {skeleton}, LpyForm::kAbsolute, kUnits);
  WriteLpy(out("tree_turtle.lpy"), {skeleton}, LpyForm::kTurtle, kUnits);
  WriteMtg(out("tree.mtg"), {skeleton}, kUnits);
  AtomicWriteString(out("organs.json"), OrgansJson(meshing.plant));
  for (size_t k = 0; k < meshing.drawings.size(); ++k) {
    const std::string stem = "pen_" + meshing.view_names[k];
    WritePenAndInkSvg(out(stem + ".svg"), meshing.drawings[k]);
    WriteImage(out(stem + ".png"), RasterizePenAndInk(meshing.drawings[k]), PixelFormat::kUint8);
  }
  // The plant's figures, and the report of a plant made without photos:
  // the figures, the previews beside it and the summary.
  FidelityReport report;
  report.units = kUnits;
  report.has_metrics = true;
  report.metrics = ComputeTreeMetrics(skeleton, nullptr, kUnits, options.tree_metrics,
                                      {"concept sketch", "concept sketch (phyllotaxis)"});
  WriteTreeMetricsJson(out("metrics.json"), report.metrics);
  report.previews = RenderReportPreviews(tree, nullptr, options.report);
  report.preview_dir = "";
  for (const std::filesystem::path& path :
       WriteFidelityReport(report, {{"concept", meshing.brief}}, options.report, out_dir)) {
    paths.push_back(path);
  }
  return paths;
}

ConceptMeshing RunConcept(const std::filesystem::path& drawing_path, int ndjson_index,
                          const std::filesystem::path& out_dir, const PipelineOptions& options,
                          const OptionRegistry& registry,
                          std::vector<std::filesystem::path>* written) {
  CheckOutDirIsFree(out_dir);
  const ConceptMeshing meshing =
      MeshConceptDrawing(ReadSketch(drawing_path, ndjson_index), options);
  std::vector<std::filesystem::path> paths =
      WriteStagedOutDir(out_dir, registry, [&](const std::filesystem::path& staging) {
        return WriteConceptMeshing(meshing, staging, options);
      });
  if (written != nullptr) *written = std::move(paths);
  return meshing;
}

}  // namespace sylva
