#include "ui/pipeline/qsm_meshing.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/io/image_io.h"
#include "core/io/lpy_io.h"
#include "core/io/mesh_io.h"
#include "core/util/check.h"
#include "core/util/random.h"
#include "mesh/allometry.h"
#include "mesh/gltf_export.h"
#include "mesh/mesh_checks.h"
#include "mesh/tree_metrics.h"
#include "mesh/wood.h"
#include "ui/pipeline/report.h"
#include "ui/pipeline/tree_building.h"

namespace sylva {
namespace {

// Monte Carlo samples per cylinder for the union volume: about 0.1 %
// standard error on tables of thousands of cylinders.
constexpr int kUnionSamplesPerCylinder = 64;

double RootRadius(const SkeletonGraph& skeleton) {
  return skeleton.nodes.empty() ? 0.0 : skeleton.nodes[skeleton.RootIdx()].radius;
}

}  // namespace

QsmMeshing MeshQsm(const QsmModel& qsm, const PipelineOptions& options, double merge_fraction) {
  QsmToSkeletonOptions convert;
  convert.merge_fraction = merge_fraction;
  convert.merge_inside_parent = true;
  QsmMeshing meshing;
  meshing.parts = SkeletonsFromQsm(qsm, convert);
  WoodOptions wood = WoodOptionsOf(options);
  wood.twigs = false;  // the table is the whole tree
  // Thousands of thin cylinders get 4-6 sided tubes: inscribed polygons
  // would hold 64-83 % of their volume. (The watertight bark's; the
  // overlapping tubes of BranchMesh.watertight=false are meshed, and left
  // out of the brief, as they always were.)
  if (wood.watertight_bark) wood.bark.tube.circle_area = true;
  std::ostringstream brief;
  brief << qsm.cylinders.size() << " cylinders in " << meshing.parts.size() << " part(s).";
  for (const QsmSkeleton& part : meshing.parts) {
    const Wood part_wood = MeshWood(part.skeleton, DensityGrid(), wood);
    meshing.bark.Append(part_wood.bark);
    if (wood.watertight_bark) brief << " " << part_wood.brief;
  }
  // A safety net for what the mesher still gets wrong on tables unlike the
  // tested ones: a closed piece inside out is turned, and counted.
  meshing.turned_components = TurnInsideOutComponents(&meshing.bark);
  SubdivideBark(options.geometry, &meshing.bark, &brief);
  // What a closed bark should be: outward solids, one per part plus one per
  // lateral left unattached (mesh/bark_mesh.h), enclosing about the
  // cylinders' union (their sum counts TreeQSM's overlaps twice).
  const MeshCheck check = CheckMesh(meshing.bark, "", false);
  meshing.components = check.components;
  meshing.inside_out_components = check.inside_out_components;
  meshing.cylinder_union_volume = QsmUnionVolume(qsm, kUnionSamplesPerCylinder, 1);
  meshing.volume_ratio = check.volume / meshing.cylinder_union_volume;
  brief << " Bark: " << check.components << " components (" << check.inside_out_components
        << " inside out, " << meshing.turned_components << " turned right side out before), volume "
        << check.volume << " = " << meshing.volume_ratio << " x the cylinders' union ("
        << check.volume / QsmCylinderVolumeSum(qsm) << " x their sum).";
  meshing.brief = brief.str();
  return meshing;
}

void AddSkeletonLeaves(const PipelineOptions& options, QsmMeshing* meshing) {
  LeafOptions leaves = LeafOptionsOf(options);
  meshing->leaves = LeafInstances();
  meshing->leaf_summary = LeafSummary();
  if (leaves.num_leaves < 0) {
    meshing->brief += " No leaves (Leaves.num_leaves=-1).";
    return;
  }
  double height = 0.0, trunk_radius = 0.0;
  for (const QsmSkeleton& part : meshing->parts) {
    height = std::max(height, part.skeleton.Height());
    trunk_radius = std::max(trunk_radius, RootRadius(part.skeleton));
  }
  if (leaves.leaf_length <= 0) leaves.leaf_length = leaves.leaf_length_fraction * height;
  const double thin_radius = leaves.thin_branch_radius_fraction * trunk_radius;
  // Leaves.image: relative to the working directory (no project here).
  LeafShape image_leaf;
  const std::string& image = options.geometry.leaf_image;
  if (!image.empty()) image_leaf = LeafShapeFromImage(ReadImage(image), image);
  const uint64_t seed = leaves.seed;
  for (size_t k = 0; k < meshing->parts.size(); ++k) {
    const SkeletonGraph& skeleton = meshing->parts[k].skeleton;
    leaves.seed = k == 0 ? seed : DeriveSeed(seed, k);
    // Thin as a fraction of the tree's trunk, not of a detached part's root.
    const double root_radius = RootRadius(skeleton);
    leaves.thin_branch_radius_fraction =
        root_radius > thin_radius ? thin_radius / root_radius : 1.0;
    LeafSummary summary;
    const LeafInstances part = GenerateSkeletonLeafInstances(skeleton, leaves, &summary,
                                                             image.empty() ? nullptr : &image_leaf);
    meshing->leaves.shape = part.shape;
    meshing->leaves.material = part.material;
    std::vector<LeafInstance>& all = meshing->leaves.instances;
    all.insert(all.end(), part.instances.begin(), part.instances.end());
    meshing->leaf_summary.Add(summary);
  }
  meshing->brief += " " + meshing->leaf_summary.BriefReport();
}

QsmMeshing MeshSkeletonTree(const SkeletonGraph& skeleton, const std::string& units,
                            double merge_fraction, const PipelineOptions& options, QsmModel* qsm) {
  *qsm = QsmFromSkeletonParts({skeleton}, units);
  QsmMeshing meshing = MeshQsm(*qsm, options, merge_fraction);
  AddSkeletonLeaves(options, &meshing);
  return meshing;
}

void UseSkeletonTreeDefaults(PipelineOptions* options) {
  options->leaves.phyllotaxis = kSkeletonTreePhyllotaxis;
}

void UseQsmMeshingDefaults(PipelineOptions* options) {
  UseSkeletonTreeDefaults(options);
  options->leaves.num_leaves = -1;
}

std::vector<std::filesystem::path> WriteQsmMeshing(const QsmMeshing& meshing, const QsmModel& qsm,
                                                   const std::filesystem::path& out_dir,
                                                   const PipelineOptions& options) {
  SYLVA_CHECK(!meshing.parts.empty()) << "nothing to write";
  std::filesystem::create_directories(out_dir);
  size_t largest = 0;
  for (size_t k = 1; k < meshing.parts.size(); ++k) {
    if (meshing.parts[k].skeleton.NumNodes() > meshing.parts[largest].skeleton.NumNodes()) {
      largest = k;
    }
  }
  GltfExportOptions gltf;
  gltf.extras["units"] = qsm.units;
  gltf.extras["branch_radii"] = "from the QSM (" + qsm.radius_source + ")";
  std::vector<std::filesystem::path> paths = {out_dir / "bark.obj", out_dir / "tree.obj",
                                              out_dir / "tree.glb", out_dir / "qsm.csv",
                                              out_dir / "metrics.json"};
  const bool leafy = !meshing.leaves.instances.empty();
  WriteObj(paths[0], meshing.bark);
  if (leafy) {
    TriangleMesh tree = meshing.bark;
    tree.Append(meshing.leaves.Bake());
    WriteObj(paths[1], tree);
    gltf.instance_leaves = options.geometry.instance_leaves;
    WriteGlb(paths[2], meshing.bark, meshing.leaves, gltf);
  } else {
    WriteObj(paths[1], meshing.bark);
    WriteGlb(paths[2], meshing.bark, gltf);
  }
  // The table as read (merged connectors move starts slightly; the exact
  // skeleton round trip is SkeletonsFromQsm with merge_fraction 0).
  WriteQsmCsv(paths[3], qsm);
  // Labelled with the table's own sources ("unknown" when it has none).
  FidelityReport report;
  report.units = qsm.units;
  report.has_metrics = true;
  report.metrics =
      ComputeTreeMetrics(meshing.parts[largest].skeleton, nullptr, qsm.units, options.tree_metrics,
                         {qsm.position_source, qsm.branching_source});
  WriteTreeMetricsJson(paths[4], report.metrics);
  // For plant modellers: the table's exact skeletons (no merged connectors).
  std::vector<SkeletonGraph> skeletons;
  for (const QsmSkeleton& part : SkeletonsFromQsm(qsm)) skeletons.push_back(part.skeleton);
  for (const char* name : {"tree.lpy", "tree_turtle.lpy", "tree.mtg"}) {
    paths.push_back(out_dir / name);
  }
  WriteLpy(paths[5], skeletons, LpyForm::kAbsolute, qsm.units);
  WriteLpy(paths[6], skeletons, LpyForm::kTurtle, qsm.units);
  WriteMtg(paths[7], skeletons, qsm.units);
  // Previews beside the other outputs, and the report of the tree's figures.
  report.previews =
      RenderReportPreviews(meshing.bark, leafy ? &meshing.leaves : nullptr, options.report);
  report.preview_dir = "";
  for (const std::filesystem::path& path :
       WriteFidelityReport(report, {{"mesh", meshing.brief}}, options.report, out_dir)) {
    paths.push_back(path);
  }
  return paths;
}

QsmModel QsmFromSkeletonParts(const std::vector<SkeletonGraph>& parts, const std::string& units) {
  QsmModel qsm;
  qsm.units = units;
  if (!parts.empty()) qsm.radius_source = parts.front().radius_source;
  for (const SkeletonGraph& part : parts) {
    const int64_t id_offset = static_cast<int64_t>(qsm.cylinders.size());
    int64_t branch_offset = 0;
    for (const QsmCylinder& c : qsm.cylinders) branch_offset = std::max(branch_offset, c.branch);
    for (QsmCylinder c : QsmFromSkeleton(part, units).cylinders) {
      c.id += id_offset;
      if (c.parent_id != 0) c.parent_id += id_offset;
      c.branch += branch_offset;
      qsm.cylinders.push_back(c);
    }
  }
  qsm.Check();
  return qsm;
}

void MtgMeshingOptions::Check() const {
  read.Check();
  SYLVA_CHECK_INPUT(scale > 0 && std::isfinite(scale), "--scale") << "must be > 0, got " << scale;
  SYLVA_CHECK_INPUT(trunk_radius >= 0 && std::isfinite(trunk_radius), "--trunk-radius")
      << "must be >= 0, got " << trunk_radius;
}

namespace {

// Pipe-model radii for a part read without any.
void AssignRadii(const MtgMeshingOptions& options, SkeletonGraph* part) {
  AllometryOptions allometry;
  allometry.trunk_radius = options.trunk_radius > 0
                               ? options.trunk_radius
                               : kDefaultTrunkRadiusFraction * std::max(part->Height(), 1e-9);
  allometry.min_radius = allometry.trunk_radius * kMinRadiusOfTrunk;
  AssignPipeModelRadii(allometry, part);
}

// Raises radius-0 nodes to the part's smallest positive radius; returns how many.
int RaiseZeroRadii(SkeletonGraph* part) {
  double smallest = INFINITY;
  for (const SkeletonNode& node : part->nodes) {
    if (node.radius > 0) smallest = std::min(smallest, node.radius);
  }
  int raised = 0;
  for (SkeletonNode& node : part->nodes) {
    if (node.radius <= 0) {
      node.radius = smallest;
      ++raised;
    }
  }
  return raised;
}

}  // namespace

MtgTable MtgTableForMeshing(const Mtg& mtg, const std::string& source,
                            const MtgMeshingOptions& options) {
  options.Check();
  MtgTable table;
  table.read = SkeletonsFromMtg(mtg, source, options.read);
  for (SkeletonGraph part : table.read.parts) {
    for (SkeletonNode& node : part.nodes) {
      node.position *= options.scale;
      node.radius *= options.scale;
    }
    const bool any_radius = std::any_of(part.nodes.begin(), part.nodes.end(),
                                        [](const SkeletonNode& n) { return n.radius > 0; });
    if (table.read.radius_feature.empty() || !any_radius) {
      AssignRadii(options, &part);
      ++table.pipe_model_parts;
    } else {
      table.raised_radii += RaiseZeroRadii(&part);
    }
    table.parts.push_back(std::move(part));
  }
  table.qsm = QsmFromSkeletonParts(table.parts, options.units);
  std::ostringstream brief;
  brief << "MTG " << source << ": " << table.read.BriefReport() << " " << table.pipe_model_parts
        << " part(s) given pipe-model radii, " << table.raised_radii
        << " zero radii raised; scaled by " << options.scale << " to " << options.units << ".";
  table.brief = brief.str();
  return table;
}

}  // namespace sylva
