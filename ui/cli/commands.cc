#include "ui/cli/commands.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/logging.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "datasets/synthetic/synthetic_qsm.h"
#include "mesh/subdivision.h"
#include "sketch/drawing_io.h"
#include "ui/batch/batch_runner.h"
#include "ui/batch/batch_summary.h"
#include "ui/batch/manifest.h"
#include "ui/batch/tree_run.h"
#include "ui/batch/workflow_engine.h"
#include "ui/cli/arguments.h"
#include "ui/cli/terminal_progress.h"
#include "ui/pipeline/concept_meshing.h"
#include "ui/pipeline/gesture_meshing.h"
#include "ui/pipeline/pipeline.h"
#include "ui/pipeline/qsm_meshing.h"
#include "ui/pipeline/sketch_mrf.h"
#include "ui/pipeline/sketch_project.h"

namespace sylva {
namespace {

const FlagSpec kLogLevelFlag = {"log-level", "LEVEL",
                                "debug, info (default), warning, error or silent"};

CommandSpec InitSpec() {
  return {
      "init",
      "sylva init PROJECT --photos DIR (--colmap MODEL_DIR | --cameras FILE.json | "
      "--register colmap | --register manual --loose-cameras FILE.json) [--mattes DIR] "
      "[--held-out NAMES] [--copy] [--units UNITS]",
      "Creates a project folder for one tree from its photos. The cameras are given (a\n"
      "COLMAP sparse model, text or binary, or a sylva camera file for orthographic or\n"
      "hand-placed views) or registered by the register stage: '--register colmap' runs\n"
      "COLMAP's structure from motion on every photo of --photos (sub-folders included);\n"
      "'--register manual' places 2-4 photos from their viewing azimuths and refines them\n"
      "from clicked correspondences (see reconstruct/registration/loose_registration.h).\n"
      "Mattes come from --mattes (same relative name, any image format), else from the\n"
      "photos' alpha channels, else the matte stage computes them (painted trimaps in\n"
      "PROJECT/edits/trimaps/<photo>.png override it). Every photo is decoded now, so a\n"
      "corrupt file is reported before any work. Photos and mattes are referenced where\n"
      "they are, or copied with --copy.\n"
      "With --sketch the project is made from drawings instead of photos (see 'sylva\n"
      "sketch -h'); Sketch.* options then say how.",
      {{"photos", "DIR", "folder of the photos (names as in the camera model)"},
       {"colmap", "MODEL_DIR", "given COLMAP sparse model folder (cameras/images .txt or .bin)"},
       {"cameras", "FILE.json", "given sylva camera file (see core/io/camera_file.h)"},
       {"register", "METHOD",
        "register the photos: colmap (structure from motion) or "
        "manual (with --loose-cameras)"},
       {"loose-cameras", "FILE.json",
        "azimuth (and optional elevation, focal length, "
        "correspondences) of each photo, for --register manual"},
       {"mattes", "DIR",
        "folder of alpha mattes; default: the photos' alpha channels, "
        "else computed"},
       {"held-out", "NAMES",
        "views kept out of the reconstruction and reported separately: "
        "comma-separated names, or @FILE with one name per line"},
       {"copy", "", "copy the photos and mattes into the project"},
       {"units", "UNITS",
        "world units of the cameras (default: from the camera file, "
        "else 'arbitrary'; with WorldFrame.known_height, the unit of "
        "that height)"},
       {"sketch", "DRAWINGS",
        "make the project from 1-4 drawings instead (comma-separated: front, side, "
        "back, other side)"},
       {"index", "N", "with --sketch: the drawing of a Quick, Draw! .ndjson file (default 0)"},
       kLogLevelFlag},
      1,
      1,
      true};
}

CommandSpec SketchSpec() {
  return {"sketch",
          "sylva sketch DRAWING [DRAWING2 ...] OUT_DIR [--index N] [--Section.field=value ...]",
          "Makes a tree from drawings alone (1-4 views of one tree: front, side, back, other\n"
          "side): Inkscape SVG (stroke roles from layer labels or classes: crown, branch),\n"
          "scanned or photographed pencil drawings (.png, .jpg, .tif) and Quick, Draw! .ndjson.\n"
          "Each drawing becomes a view of an ordinary project, OUT_DIR/project: an orthographic\n"
          "camera, the drawing's silhouette with its enclosed regions filled as the matte (the\n"
          "crown becomes density) and its branch strokes as attractor strokes (the particle\n"
          "flow follows them). One drawing does not say how deep the crown is: a virtual side\n"
          "view assumes a crown of revolution about the trunk (sketch/sketch_views.h). The\n"
          "tree is scaled to Sketch.tree_height. Writes to OUT_DIR: tree.glb, tree.obj,\n"
          "bark.obj (with their .mtl), skeleton.json, qsm.csv, metrics.json, tree.lpy,\n"
          "tree_turtle.lpy and tree.mtg (L-Py and OpenAlea), the previews and\n"
          "sketch_cameras.json (the drawings' cameras at their canvas sizes, to project the\n"
          "tree back onto them); the report is OUT_DIR/project/out/report.html. Edit and\n"
          "re-run with 'sylva run OUT_DIR/project'.\n"
          "With --Sketch.method=mrf the branches come from the first drawing by Chen et al.\n"
          "2008 instead: the drawn branches' depths by a Markov random field with the tree\n"
          "parameters of the nearest exemplar (Sketch.exemplars), then self-similar\n"
          "propagation inside the drawn crown; the tree is meshed directly into OUT_DIR (no\n"
          "project, no report), with leaves at the spiral phyllotaxis nodes of its thin\n"
          "branches (Leaves.phyllotaxis=spiral by default; Leaves.num_leaves=-1: none).\n"
          "With --Sketch.method=silhouette they come from the first drawing's crown outline by\n"
          "Wither et al. 2009: a branch into each bump of the outline, leaving its parent at\n"
          "the branching angle function's angle; smaller closed crown strokes are\n"
          "sub-silhouettes whose branching is copied to their siblings; branches drawn over\n"
          "the crown replace the inferred ones and lend them their shape; the branches are\n"
          "placed around their parents by a Gibbs process (Sketch.silhouette_phyllotaxis);\n"
          "meshed into OUT_DIR like mrf.",
          {{"index", "N", "the drawing of a Quick, Draw! .ndjson file (0-based line, default 0)"},
           kLogLevelFlag},
          2,
          5,
          true};
}

CommandSpec GestureSpec() {
  return {"gesture",
          "sylva gesture FILE OUT_DIR [--Gesture.grammar=FILE.lsys] [--Section.field=value ...]",
          "Grows a tree from 3D gestures (Murakami et al.): strokes of a tracked stylus in a\n"
          "sylva-gesture .json (timed samples [t, x, y, z, pressure?], kinds 'trunk' and 'roi'),\n"
          "W3C .inkml (X, Y, Z, T channels), .obj ('l' polylines; groups named roi* are ROI\n"
          "strokes) or ASCII .ply (edges; vertex property roi); see README 'Trees from 3D\n"
          "gestures'. Trunk strokes become trunk L-strings (radius inversely proportional to\n"
          "the stroke's speed) carrying growth points; the L-system of Gesture.grammar (sylva's\n"
          "grammar format, README) grows them for Gesture.iterations steps, rewriting only\n"
          "modules inside the region of interest (a supertoroid fitted to the ROI strokes, or\n"
          "around the gestures), every new segment kept in the region and clear of the others\n"
          "(turned, shortened or pruned). Without a trunk stroke the tree grows from the\n"
          "region's base (silhouette-based modelling). The seed is General.seed. Leaves grow\n"
          "at the phyllotactic nodes of the thin branches (Leaves.phyllotaxis=spiral by\n"
          "default for this command; Leaves.num_leaves=N picks N of them, -1 none).\n"
          "Writes to OUT_DIR (made only when everything succeeded): tree.glb, tree.obj,\n"
          "bark.obj (with their .mtl), skeleton.json, qsm.csv, metrics.json, tree.lpy,\n"
          "tree_turtle.lpy, tree.mtg, lstring.txt (the grown L-string), roi.json (the region),\n"
          "options.json, preview_0..3.png (Report.previews), report.html and report.json.",
          {kLogLevelFlag},
          2,
          2,
          true};
}

CommandSpec ConceptSpec() {
  return {"concept",
          "sylva concept DRAWING OUT_DIR [--index N] [--Concept.phyllotaxis=spiral|monostichous|"
          "distichous|tristichous|tetrastichous] [--Section.field=value ...]",
          "Makes a 3D plant from a concept sketch (Anastacio et al. 2006): construction lines\n"
          "(role 'construction': the stem, boundary lines beside it giving the organs' extent,\n"
          "inclination lines across it giving their angle; told apart by their names 'stem',\n"
          "'boundary', 'inclination' or by their shape, see sketch/concept_sketch.h) and organ\n"
          "strokes (role 'organ': closed outlines of blades, or lines for needles and\n"
          "branches). Organs are placed at nodes along the stem in a phyllotactic pattern\n"
          "(Concept.phyllotaxis, or written in the drawing as a <text>), sized to lie within\n"
          "the boundary lines revolved about the stem, inclined by the inclination lines.\n"
          "Writes to OUT_DIR (made only when everything succeeded): tree.glb, tree.obj,\n"
          "bark.obj (with their .mtl), skeleton.json, qsm.csv, tree.lpy, tree_turtle.lpy,\n"
          "tree.mtg, organs.json (each organ's node, azimuth and divergence), options.json\n"
          "(the effective options), pen-and-ink drawings pen_front, pen_oblique, pen_top\n"
          "(.svg with Inkscape layers hatching, outline, construction; and .png),\n"
          "preview_0..3.png (Report.previews), metrics.json, report.html and report.json.",
          {{"index", "N", "the drawing of a Quick, Draw! .ndjson file (0-based line, default 0)"},
           kLogLevelFlag},
          2,
          2,
          true};
}

CommandSpec RunSpec() {
  return {"run",
          "sylva run PROJECT [--until STAGE] [--force] [--Section.field=value ...]",
          "Runs the pipeline stages that are out of date (their inputs or options changed) and\n"
          "writes the outputs under PROJECT/out/. Options given here apply to this run (and\n"
          "are saved in the project's sylva.json with --save); the effective options of every\n"
          "run are written to PROJECT/out/run.json.",
          {{"until", "STAGE",
            "stop after this stage (matte, register, density, attract, skeleton, mesh, "
            "report)"},
           {"force", "", "re-run stages even if up to date"},
           {"save", "", "save the options given here in the project's sylva.json"},
           kLogLevelFlag},
          1,
          1,
          true};
}

CommandSpec StageSpec(const StageInfo& stage) {
  return {stage.name,
          std::string("sylva ") + stage.name + " PROJECT [--Section.field=value ...]",
          std::string("Runs the '") + stage.name + "' stage now: " + stage.description +
              ".\n"
              "Its inputs from earlier stages must exist. Options as for 'sylva run'.",
          {{"save", "", "save the options given here in the project's sylva.json"}, kLogLevelFlag},
          1,
          1,
          true};
}

CommandSpec SynthSpec() {
  return {"synth",
          "sylva synth OUT [--seed N] [--views K] [--held-out H] [--camera pinhole|ortho] "
          "[--size PX] [--qsm]",
          "Generates a synthetic ground-truth dataset: a procedural tree (skeleton with radii,\n"
          "branch cylinders, leaf clusters) rendered with Embree into RGBA photos and exact\n"
          "mattes from K cameras plus H held-out cameras, with a COLMAP text model (pinhole\n"
          "only), a sylva camera file, held_out.txt and the ground truth (skeleton, mesh).\n"
          "Deterministic by seed. Use it with:\n"
          "  sylva init P --photos OUT/photos --mattes OUT/mattes --cameras OUT/cameras.json "
          "--held-out @OUT/held_out.txt\n"
          "With --qsm it writes OUT/qsm.csv instead: the tree (thinning to 1 mm radius) as a\n"
          "laser-scan-like TreeQSM cylinder table of thousands of short, noisy cylinders with a\n"
          "few detached fragments as extra roots, for 'sylva mesh-qsm'.",
          {{"seed", "N", "seed of the tree (default 1)"},
           {"qsm", "", "write OUT/qsm.csv, a TreeQSM-like cylinder table, and no photos"},
           {"views", "K", "input views (default 8; orthographic: 2 at right angles)"},
           {"held-out", "H", "extra held-out views (default 2)"},
           {"camera", "KIND", "pinhole (default) or ortho"},
           {"size", "PX", "image width and height in pixels (default 512)"},
           {"samples", "S", "S x S rays per pixel for anti-aliased mattes (default 4)"},
           {"elevation", "DEG", "elevation of the pinhole input views (default 10)"},
           {"radial", "K", "radial distortion k of a SIMPLE_RADIAL camera (default 0)"},
           kLogLevelFlag},
          1,
          1,
          false};
}

CommandSpec MeshQsmSpec() {
  return {
      "mesh-qsm",
      "sylva mesh-qsm QSM.csv OUT_DIR [--merge F] [--subdivide N] [--no-previews] "
      "[--Section.field=value ...]",
      "Meshes a QSM cylinder table (TreeQSM's columns: id, parent_id, start_x..z,\n"
      "axis_x..z, length, radius, branch, branch_order; e.g. from a laser scan) without a\n"
      "project: one sylva skeleton per root cylinder, the watertight bark of the mesh\n"
      "stage (BranchMesh.* options). Writes OUT_DIR/bark.obj (closed solid), tree.obj,\n"
      "tree.glb, qsm.csv (the table as read), metrics.json and preview pictures of the\n"
      "bark from 4 sides, preview_0.png .. preview_3.png (Report.preview_* options),\n"
      "report.html and report.json (the tree's figures and previews).\n"
      "Prints the bark's figures: components, how many are inside out, and its volume\n"
      "over the union of the cylinders (and over their sum, which counts overlaps twice).\n"
      "Leafless by default (Leaves.num_leaves=-1); --Leaves.num_leaves=0 puts a leaf at\n"
      "every spiral phyllotaxis node of the thin branches, =N at N of them.\n"
      "Try it on a generated table: sylva synth T --qsm; sylva mesh-qsm T/qsm.csv OUT",
      {{"merge", "F",
        "children starting within F x their radius of the parent's axis hang from it "
        "directly (default 0.1); children starting inside their parent cylinder always do"},
       {"subdivide", "N",
        "N levels of Loop subdivision of the bark, 0-3 (default 0; same as "
        "--BranchMesh.subdivision=N)"},
       {"no-previews", "", "do not render the preview pictures (same as --Report.previews=false)"},
       kLogLevelFlag},
      2,
      2,
      true};
}

CommandSpec BatchSpec() {
  return {"batch",
          "sylva batch MANIFEST OUT_DIR [--jobs N | --engine snakemake [--profile P]] "
          "[--Section.field=value ...] | sylva batch --scan DIR [--output MANIFEST]",
          "Runs many trees, each a row of MANIFEST (CSV: name, photos, and colmap, cameras or\n"
          "register (+ loose_cameras); optional mattes, held_out, units and Section.field option\n"
          "columns; paths relative to the manifest; see ui/batch/manifest.h and the README). Each\n"
          "tree becomes the project OUT_DIR/<name>/, made and run as 'sylva init' and 'sylva run'\n"
          "would, in a child process of its own: a tree that fails or crashes is recorded with\n"
          "its stage, message and log (OUT_DIR/logs/<name>.log) and the others go on. Trees that\n"
          "finished before and are up to date are skipped, and a killed batch resumes where it\n"
          "stopped (the stage cache). Progress on stderr; OUT_DIR/summary.csv and summary.html\n"
          "sum up every tree. A bad manifest is refused before anything runs.\n"
          "Exit codes: 0 every tree finished, 3 some failed (the others finished), 2 bad\n"
          "manifest or options (nothing run), 130 interrupted, 1 internal error.\n"
          "With --engine snakemake the same trees run as jobs of Snakemake 7 (workflow/Snakefile;\n"
          "--profile slurm submits them to a Slurm cluster; see the README).\n"
          "--scan DIR writes a manifest of the tree folders in DIR (each with photos/ or images/,\n"
          "cameras.json, a COLMAP model in colmap/ or sparse/0/, or loose_cameras.json; mattes/\n"
          "and held_out.txt when present).",
          {{"jobs", "N", "trees run at once (default 1); each gets its share of the cores"},
           {"scan", "DIR", "write a manifest of the tree folders in DIR (to stdout, or --output)"},
           {"output", "MANIFEST", "with --scan: write the manifest to this new file"},
           {"only", "NAME",
            "run only this tree, in this process (what each child process does; for workflow "
            "engines)"},
           {"summary", "", "only rewrite OUT_DIR/summary.csv and summary.html from what exists"},
           {"engine", "ENGINE",
            "sylva (default: child processes here) or snakemake (workflow/Snakefile, one job per "
            "tree; locally or on Slurm by --profile)"},
           {"profile", "PROFILE",
            "with --engine snakemake: local (default), slurm, or a profile folder"},
           kLogLevelFlag},
          0,
          2,
          true};
}

std::atomic<bool> g_batch_interrupted{false};

void OnBatchInterrupt(int) {
  g_batch_interrupted.store(true);
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C stops at once
}

int ScanTrees(const ParsedArguments& args) {
  SYLVA_CHECK_INPUT(args.positional.empty(), args.positional.empty() ? "" : args.positional[0])
      << "unexpected argument with --scan; usage: sylva batch --scan DIR [--output MANIFEST]";
  const std::vector<ManifestTree> trees = ScanTreeFolders(args.Get("scan"));
  if (!args.Has("output")) {
    std::cout << ManifestText(trees, fs::current_path());
    return kExitOk;
  }
  const fs::path output = args.Get("output");
  std::error_code ec;
  SYLVA_CHECK_INPUT(!fs::exists(output, ec), output.string())
      << "already exists; choose a new manifest file";
  AtomicWriteString(output, ManifestText(trees, fs::absolute(output).parent_path()));
  std::cout << "Wrote a manifest of " << trees.size() << " trees to " << output.string()
            << "\nUse it: sylva batch " << output.string() << " OUT_DIR\n";
  return kExitOk;
}

int RunOneTree(const Manifest& manifest, const fs::path& out_dir, const ParsedArguments& args) {
  const ManifestTree* tree = manifest.Find(args.Get("only"));
  SYLVA_CHECK_INPUT(tree != nullptr, "--only")
      << "no tree named '" << args.Get("only") << "' in " << manifest.path.string();
  fs::create_directories(BatchLogDir(out_dir));
  TerminalProgress progress;
  TerminalProgress::InstallInterruptHandler(&progress);
  const TreeStatus status = RunTree(manifest, *tree, out_dir, args.options, &progress);
  progress.Finish();
  return status.exit_code;
}

int CmdBatch(const ParsedArguments& args) {
  if (args.Has("scan")) return ScanTrees(args);
  SYLVA_CHECK_INPUT(args.positional.size() == 2, "sylva batch")
      << "expected MANIFEST and OUT_DIR; usage: " << BatchSpec().usage;
  const Manifest manifest = ReadManifest(args.positional[0]);
  const fs::path out_dir = fs::absolute(args.positional[1]).lexically_normal();
  if (args.Has("only")) return RunOneTree(manifest, out_dir, args);
  CheckBatchOptions(args.options);
  if (args.Has("summary")) {
    WriteBatchSummary(manifest, out_dir);
    std::cout << "Wrote " << (out_dir / "summary.csv").string() << " and "
              << (out_dir / "summary.html").string() << "\n";
    return kExitOk;
  }
  BatchOptions options;
  options.jobs = args.GetInt("jobs", 1, 1, 1024);
  options.options = args.options;
  options.log_level = args.Get("log-level");
  const std::string engine = args.Get("engine", "sylva");
  SYLVA_CHECK_INPUT(engine == "sylva" || engine == "snakemake", "--engine")
      << "expected sylva or snakemake, got '" << engine << "'";
  SYLVA_CHECK_INPUT(engine == "snakemake" || !args.Has("profile"), "--profile")
      << "only with --engine snakemake";
  if (engine == "snakemake") {
    const int code =
        RunSnakemakeBatch(manifest, out_dir, ResolveProfile(args.Get("profile", "local")), options);
    std::cout << "Summary: " << (out_dir / "summary.csv").string() << ", "
              << (out_dir / "summary.html").string() << "\n";
    return code;
  }
  std::signal(SIGINT, OnBatchInterrupt);
  const BatchResult result = RunBatch(manifest, out_dir, options, &g_batch_interrupted);
  std::cout << result.BriefReport() << "\nSummary: " << (out_dir / "summary.csv").string() << ", "
            << (out_dir / "summary.html").string() << "\n";
  return result.ExitCode();
}

// The pipeline options of mesh-qsm and mesh-mtg: --Section.field=value,
// --subdivide, --no-previews.
PipelineOptions MeshingOptions(const ParsedArguments& args) {
  PipelineOptions options;
  UseQsmMeshingDefaults(&options);  // leafless unless --Leaves.num_leaves >= 0
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  for (const auto& [key, value] : args.options) registry.Set(key, value, "--" + key);
  if (args.Has("subdivide")) {
    options.geometry.bark_subdivision = args.GetInt("subdivide", 0, 0, kMaxLoopLevels);
  }
  options.Check();
  return options;
}

double MergeFraction(const ParsedArguments& args) {
  const double merge = args.Has("merge") ? args.GetDouble("merge", 0.1) : 0.1;
  SYLVA_CHECK_INPUT(merge >= 0 && merge < 1, "--merge") << "must be in [0, 1), got " << merge;
  return merge;
}

// Meshes `qsm` and writes the outputs to OUT_DIR (positional[1]).
int MeshAndWrite(const ParsedArguments& args, const QsmModel& qsm, PipelineOptions options) {
  QsmMeshing meshing = MeshQsm(qsm, options, MergeFraction(args));
  AddSkeletonLeaves(options, &meshing);
  std::cout << meshing.brief << "\n";
  if (args.Has("no-previews")) options.report.previews = false;
  for (const fs::path& path : WriteQsmMeshing(meshing, qsm, args.positional[1], options)) {
    std::cout << "  " << path.string() << "\n";
  }
  return kExitOk;
}

int CmdMeshQsm(const ParsedArguments& args) {
  const PipelineOptions options = MeshingOptions(args);
  MergeFraction(args);  // checked before reading
  return MeshAndWrite(args, ReadQsmCsv(args.positional[0]), options);
}

CommandSpec MeshMtgSpec() {
  return {
      "mesh-mtg",
      "sylva mesh-mtg TREE.mtg OUT_DIR [--diameter-unit K] [--scale S] [--units U] "
      "[--trunk-radius R] [--merge F] [--subdivide N] [--no-previews] [--Section.field=value ...]",
      "Meshes a tree coded in OpenAlea's MTG format (FORM-A, TAB-separated; e.g. a\n"
      "digitised tree, or sylva's own tree.mtg): the entities of the finest scale with\n"
      "XX YY ZZ features become skeleton nodes (radii from a 'radius' feature, else\n"
      "TopDia / TopDiameter, else the pipe model), the skeletons a cylinder table, which is\n"
      "meshed and written as by 'sylva mesh-qsm' (bark.obj, tree.obj, tree.glb, qsm.csv,\n"
      "metrics.json, tree.lpy, tree_turtle.lpy, tree.mtg, previews); leafless unless\n"
      "--Leaves.num_leaves=0 (every phyllotactic node of the thin branches) or N.\n"
      "Try it: sylva mesh-mtg datasets/openalea-mtg/boutdenoylum2.mtg OUT --diameter-unit 10 "
      "--scale 0.01 --units m",
      {{"diameter-unit", "K",
        "TopDia values are diameters in units K times smaller than the coordinates' "
        "(OpenAlea's DiameterUnit; default 1)"},
       {"scale", "S", "multiply positions and radii by S, e.g. 0.01 from cm to m (default 1)"},
       {"units", "U", "unit of the scaled positions, for the outputs (default 'unknown')"},
       {"trunk-radius", "R",
        "trunk radius (scaled units) of the pipe-model radii of files without radii "
        "(default 1.5 % of the tree's height)"},
       {"merge", "F", "as for mesh-qsm (default 0.1)"},
       {"subdivide", "N", "N levels of Loop subdivision of the bark, 0-3 (default 0)"},
       {"no-previews", "", "do not render the preview pictures"},
       kLogLevelFlag},
      2,
      2,
      true};
}

int CmdMeshMtg(const ParsedArguments& args) {
  const PipelineOptions options = MeshingOptions(args);
  MergeFraction(args);
  MtgMeshingOptions mtg_options;
  if (args.Has("diameter-unit")) {
    mtg_options.read.diameter_unit = args.GetDouble("diameter-unit", 1.0);
  }
  if (args.Has("scale")) mtg_options.scale = args.GetDouble("scale", 1.0);
  if (args.Has("units")) mtg_options.units = args.Get("units", "unknown");
  if (args.Has("trunk-radius")) mtg_options.trunk_radius = args.GetDouble("trunk-radius", 0.0);
  mtg_options.Check();
  const fs::path path = args.positional[0];
  const MtgTable table = MtgTableForMeshing(ReadMtg(path), path.string(), mtg_options);
  std::cout << table.brief << "\n";
  return MeshAndWrite(args, table.qsm, options);
}

std::vector<CommandSpec> AllSpecs() {
  std::vector<CommandSpec> specs = {InitSpec(), RunSpec()};
  for (const StageInfo& stage : AllStages()) specs.push_back(StageSpec(stage));
  specs.push_back(SynthSpec());
  specs.push_back(MeshQsmSpec());
  specs.push_back(BatchSpec());
  specs.push_back(SketchSpec());
  specs.push_back(MeshMtgSpec());
  specs.push_back(ConceptSpec());
  specs.push_back(GestureSpec());
  return specs;
}

std::string OptionsHelp() {
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  return registry.Help();
}

std::string GeneralHelp() {
  std::ostringstream out;
  out << "sylva: plausible, editable 3D trees from a few photographs.\n\ncommands:\n";
  for (const CommandSpec& spec : AllSpecs()) out << "  " << spec.usage << "\n";
  out << "  sylva help [COMMAND | options]\n"
         "\n'sylva COMMAND -h' explains a command; 'sylva help options' lists every option\n"
         "with its default and unit. Exit codes: 0 ok, 1 internal error, 2 bad input,\n"
         "130 interrupted; 'sylva batch': 3 when some trees failed.\n";
  return out.str();
}

void ApplyLogLevel(const ParsedArguments& args) {
  if (args.Has("log-level")) SetLogLevel(ParseLogLevel(args.Get("log-level")));
}

// The registry over `options`: a sketch project's defaults, then `args`'
// options.
void SketchOptions(const ParsedArguments& args, PipelineOptions* options,
                   OptionRegistry* registry) {
  RegisterPipelineOptions(options, registry);
  SetSketchDefaults(registry);
  for (const auto& [key, value] : args.options) registry->Set(key, value, "--" + key);
  options->Check();
}

Project InitSketchProject(const fs::path& root, const std::vector<fs::path>& drawings,
                          const ParsedArguments& args) {
  SketchSetup setup;
  setup.root = root;
  setup.drawings = drawings;
  setup.ndjson_index = args.GetInt("index", 0, 0, std::numeric_limits<int>::max());
  PipelineOptions options;
  OptionRegistry registry;
  SketchOptions(args, &options, &registry);
  return CreateSketchProject(setup, options.sketch, registry);
}

int CmdInitSketch(const ParsedArguments& args) {
  std::vector<fs::path> drawings;
  std::stringstream list(args.Get("sketch"));
  for (std::string item; std::getline(list, item, ',');) {
    if (!item.empty()) drawings.emplace_back(item);
  }
  const Project project = InitSketchProject(args.positional[0], drawings, args);
  std::cout << "Created project " << project.root().string() << " from " << drawings.size()
            << " drawing(s): " << project.photo_names().size()
            << " views; branch strokes in edits/, drawn cameras in "
            << SketchCamerasPath(project).string() << ".\nNext: sylva run "
            << project.root().string() << "\n";
  return kExitOk;
}

int CmdInit(const ParsedArguments& args) {
  if (args.Has("sketch")) return CmdInitSketch(args);
  SYLVA_CHECK_INPUT(args.options.empty(), "--" + args.options.front().first)
      << "options are given to 'sylva run' (or to 'sylva init --sketch')";
  ProjectSetup setup;
  setup.root = args.positional[0];
  SYLVA_CHECK_INPUT(args.Has("photos"), "sylva init") << "--photos DIR is required";
  setup.photos_dir = args.Get("photos");
  setup.colmap_model_dir = args.Get("colmap");
  setup.camera_file = args.Get("cameras");
  setup.register_method = args.Get("register");
  setup.loose_cameras_file = args.Get("loose-cameras");
  SYLVA_CHECK_INPUT(!args.Has("register") || !setup.register_method.empty(), "--register")
      << "expected 'colmap' or 'manual'";
  setup.mattes_dir = args.Get("mattes");
  if (args.Has("held-out")) setup.held_out = ParseViewNames(args.Get("held-out"));
  setup.copy_inputs = args.Has("copy");
  setup.units = args.Get("units");
  const Project project = Project::Create(setup);
  const std::string cameras = project.RegistersWithColmap() ? "registered by COLMAP"
                              : project.RegistersManually() ? "placed from loose azimuths"
                                                            : "given";
  const std::string mattes = project.ComputesMattes()   ? "computed by the matte stage"
                             : setup.mattes_dir.empty() ? "the photos' alpha channels"
                                                        : "given";
  std::cout << "Created project " << project.root().string() << ": " << project.photo_names().size()
            << " photos (" << project.held_out().size() << " held out); cameras " << cameras
            << "; mattes " << mattes << "; units " << project.units() << ".\nNext: sylva run "
            << setup.root.string() << "\n";
  return kExitOk;
}

// The project's saved options, then the command line's overrides; checked.
PipelineOptions ResolveOptions(Project* project, const ParsedArguments& args) {
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  project->ApplySavedOptions(&registry);
  for (const auto& [key, value] : args.options) registry.Set(key, value, "--" + key);
  options.Check();
  if (args.Has("save")) project->SaveOptions(registry);
  return options;
}

void PrintOutputs(const Project& project) {
  std::cout << "Outputs in " << project.OutDir().string() << "/:\n";
  for (const char* name : {"mattes", "cameras", "density.vdb", "skeleton.json", "skeleton.ply",
                           "tree.glb", "tree.obj", "report.json", "report.html", "run.json"}) {
    std::error_code ec;
    if (fs::is_regular_file(project.OutDir() / name, ec)) std::cout << "  " << name << "\n";
    if (fs::is_directory(project.OutDir() / name, ec)) std::cout << "  " << name << "/\n";
  }
}

int RunPipeline(const ParsedArguments& args, const Stage* single_stage) {
  Project project = Project::Open(args.positional[0]);
  const PipelineOptions options = ResolveOptions(&project, args);
  std::unique_ptr<tbb::global_control> threads;
  if (options.general.num_threads > 0) {
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    options.general.num_threads);
  }
  TerminalProgress progress;
  TerminalProgress::InstallInterruptHandler(&progress);
  Pipeline pipeline(project, options, &progress);
  RunSummary summary;
  if (single_stage != nullptr) {
    summary.stages.push_back(pipeline.RunStage(*single_stage));
  } else {
    const Stage until =
        args.Has("until") ? ParseStage(args.Get("until"), "--until") : AllStages().back().stage;
    summary = pipeline.Run(until, args.Has("force"));
  }
  progress.Finish();
  std::cout << summary.BriefReport();
  PrintOutputs(project);
  return kExitOk;
}

// `sylva sketch DRAWING... OUT_DIR`: a project of the drawings in
// OUT_DIR/project, run, and its main outputs copied to OUT_DIR.
// `sylva sketch ... --Sketch.method=mrf|silhouette`: the tree is written to
// a staging folder beside OUT_DIR, which becomes OUT_DIR only when complete.
int SketchWithoutProject(const ParsedArguments& args, const std::vector<fs::path>& paths,
                         const PipelineOptions& options) {
  const fs::path out = fs::absolute(args.positional.back());
  std::vector<SketchDrawing> drawings;
  const int index = args.GetInt("index", 0, 0, std::numeric_limits<int>::max());
  for (const fs::path& path : paths) drawings.push_back(ReadSketch(path, index));
  SketchTree tree;
  if (options.sketch_mrf.method == "mrf") {
    const std::vector<TreeExemplar> exemplars = options.sketch_mrf.exemplars.empty()
                                                    ? BuiltinExemplars()
                                                    : LoadExemplars(options.sketch_mrf.exemplars);
    tree = MakeMrfSketchTree(drawings, options, exemplars);
  } else {
    tree = MakeSilhouetteSketchTree(drawings, options);
  }
  QsmModel qsm;
  const QsmMeshing meshing = MeshSketchTree(tree, options, &qsm);
  const SilhouetteScores fit = FrontViewFit(tree, meshing, options);
  std::ostringstream fit_line;
  fit_line << std::fixed << std::setprecision(3) << "Front view: the tree covers the drawing "
           << "(enclosed regions filled) at IoU " << fit.iou << " (precision " << fit.precision
           << ", recall " << fit.recall << ").";
  std::cout << tree.brief << "\n" << meshing.brief << "\n" << fit_line.str() << "\n";
  const fs::path staging = TempPathBeside(out);
  std::vector<fs::path> written;
  try {
    written = WriteSketchTree(tree, qsm, meshing, options, staging);
    std::error_code ec;
    fs::remove(out, ec);  // empty, checked before
    fs::rename(staging, out);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(staging, ec);
    throw;
  }
  std::cout << "Outputs in " << out.string() << "/:\n";
  for (const fs::path& path : written) std::cout << "  " << path.filename().string() << "\n";
  return kExitOk;
}

int CmdSketch(const ParsedArguments& args) {
  const fs::path out = args.positional.back();
  std::error_code ec;
  SYLVA_CHECK_INPUT(!fs::exists(out, ec) || fs::is_empty(out, ec), out.string())
      << "already exists and is not empty";
  const std::vector<fs::path> drawings(args.positional.begin(), args.positional.end() - 1);
  {
    PipelineOptions options;
    UseSkeletonTreeDefaults(
        &options);  // mrf's and silhouette's trees; the flow's are the project's
    OptionRegistry registry;
    SketchOptions(args, &options, &registry);
    const bool leaf_length_given = std::any_of(
        args.options.begin(), args.options.end(),
        [](const auto& option) { return option.first.rfind("Leaves.leaf_length", 0) == 0; });
    if (options.sketch_mrf.method == "silhouette" && !leaf_length_given) {
      options.leaves.leaf_length_fraction = kSilhouetteLeafLengthFraction;
    }
    if (options.sketch_mrf.method != "flow") return SketchWithoutProject(args, drawings, options);
  }
  Project project = InitSketchProject(out / "project", drawings, args);
  const PipelineOptions options = ResolveOptions(&project, args);
  TerminalProgress progress;
  TerminalProgress::InstallInterruptHandler(&progress);
  const RunSummary summary =
      Pipeline(project, options, &progress).Run(AllStages().back().stage, false);
  progress.Finish();
  std::cout << summary.BriefReport() << "Outputs in " << out.string() << "/:\n";
  std::vector<fs::path> outputs = {SketchCamerasPath(project)};
  for (const char* name :
       {"tree.glb", "tree.obj", "tree.mtl", "bark.obj", "bark.mtl", "skeleton.json", "qsm.csv",
        "metrics.json", "tree.lpy", "tree_turtle.lpy", "tree.mtg"}) {
    outputs.push_back(project.OutDir() / name);
  }
  for (int k = 0; k < 4; ++k) {
    outputs.push_back(project.OutDir() / "report" / ("preview_" + std::to_string(k) + ".png"));
  }
  for (const fs::path& file : outputs) {
    if (!fs::is_regular_file(file, ec)) continue;
    AtomicWriteWith(out / file.filename(), [&](const fs::path& temp) {
      fs::copy_file(file, temp, fs::copy_options::overwrite_existing);
    });
    std::cout << "  " << file.filename().string() << "\n";
  }
  std::cout << "Report: " << (project.OutDir() / "report.html").string()
            << "\nEdit and re-run: sylva run " << project.root().string() << "\n";
  return kExitOk;
}

// The options of a command without a project: the defaults, then the
// --Section.field=value flags, checked. `registry` points into `options`.
void ApplyCommandOptions(const ParsedArguments& args, PipelineOptions* options,
                         OptionRegistry* registry) {
  RegisterPipelineOptions(options, registry);
  for (const auto& [key, value] : args.options) registry->Set(key, value, "--" + key);
  options->Check();
}

// What a one-shot command made: its brief and the files written in `out`.
int PrintOutputs(const std::string& brief, const fs::path& out,
                 const std::vector<fs::path>& written) {
  std::cout << brief << "\nOutputs in " << out.string() << "/:\n";
  for (const fs::path& file : written) std::cout << "  " << file.filename().string() << "\n";
  return kExitOk;
}

// `sylva concept DRAWING OUT_DIR`: a concept sketch's plant and its drawings.
int CmdConcept(const ParsedArguments& args) {
  PipelineOptions options;
  OptionRegistry registry;
  ApplyCommandOptions(args, &options, &registry);
  const fs::path out = args.positional[1];
  std::vector<fs::path> written;
  const ConceptMeshing meshing =
      RunConcept(args.positional[0], args.GetInt("index", 0, 0, std::numeric_limits<int>::max()),
                 out, options, registry, &written);
  return PrintOutputs(meshing.brief, out, written);
}

// `sylva gesture FILE OUT_DIR`: a tree grown from 3D gestures.
int CmdGesture(const ParsedArguments& args) {
  PipelineOptions options;
  UseSkeletonTreeDefaults(&options);
  OptionRegistry registry;
  ApplyCommandOptions(args, &options, &registry);
  const fs::path out = args.positional[1];
  std::vector<fs::path> written;
  const GestureMeshing meshing = RunGesture(args.positional[0], out, options, registry, &written);
  return PrintOutputs(meshing.brief, out, written);
}

// `sylva synth OUT --qsm`: the tree of `seed` as a TreeQSM-like table.
int WriteSynthQsm(const fs::path& out, uint64_t seed) {
  std::error_code ec;
  SYLVA_CHECK_INPUT(!fs::exists(out, ec) || fs::is_empty(out, ec), out.string())
      << "already exists and is not empty";
  const QsmModel qsm = GenerateSyntheticQsm(SyntheticQsmOptions(), seed);
  fs::create_directories(out);
  WriteQsmCsv(out / "qsm.csv", qsm);
  int roots = 0;
  for (const QsmCylinder& c : qsm.cylinders) roots += c.parent_id == 0 ? 1 : 0;
  std::cout << "Wrote a synthetic QSM (seed " << seed << ", " << qsm.cylinders.size()
            << " cylinders, " << roots << " roots) to " << (out / "qsm.csv").string()
            << "\nUse it: sylva mesh-qsm " << (out / "qsm.csv").string() << " OUT_DIR\n";
  return kExitOk;
}

int CmdSynth(const ParsedArguments& args) {
  SyntheticDatasetOptions options;
  if (args.Has("seed")) {
    options.seed = static_cast<uint64_t>(args.GetInt("seed", 1, 0, 2147483647));
  }
  if (args.Has("qsm")) return WriteSynthQsm(args.positional[0], options.seed);
  const std::string camera = args.Get("camera", "pinhole");
  SYLVA_CHECK_INPUT(camera == "pinhole" || camera == "ortho", "--camera")
      << "expected pinhole or ortho, got '" << camera << "'";
  options.camera =
      camera == "ortho" ? SyntheticCameraKind::kOrthographic : SyntheticCameraKind::kPinhole;
  options.num_views = args.GetInt("views", camera == "ortho" ? 2 : 8, 1, 1000);
  options.num_held_out = args.GetInt("held-out", 2, 0, 1000);
  options.image_size = args.GetInt("size", options.image_size, 8, 16384);
  options.samples_per_axis = args.GetInt("samples", options.samples_per_axis, 1, 16);
  options.elevation_deg = args.GetDouble("elevation", options.elevation_deg);
  options.radial_distortion = args.GetDouble("radial", options.radial_distortion);
  options.Check();
  const fs::path out = args.positional[0];
  std::error_code ec;
  SYLVA_CHECK_INPUT(!fs::exists(out, ec) || fs::is_empty(out, ec), out.string())
      << "already exists and is not empty";
  TerminalProgress progress;
  TerminalProgress::InstallInterruptHandler(&progress);
  const SyntheticDataset dataset = MakeSyntheticDataset(options, &progress);
  progress.Finish();
  WriteSyntheticDataset(dataset, options, out);
  std::cout << "Wrote a synthetic tree (seed " << options.seed << ", "
            << dataset.image_set.NumViews() << " views, " << dataset.held_out.size()
            << " held out) to " << out.string() << "\nUse it: sylva init PROJECT --photos "
            << (out / "photos").string() << " --mattes " << (out / "mattes").string()
            << " --cameras " << (out / "cameras.json").string() << " --held-out @"
            << (out / "held_out.txt").string() << "\n";
  return kExitOk;
}

int PrintCommandHelp(const CommandSpec& spec) {
  std::cout << CommandHelp(spec);
  if (spec.takes_pipeline_options) std::cout << "\n" << OptionsHelp();
  return kExitOk;
}

int CmdHelp(int argc, const char* const* argv) {
  if (argc < 3) {
    std::cout << GeneralHelp();
    return kExitOk;
  }
  const std::string topic = argv[2];
  if (topic == "options") {
    std::cout << OptionsHelp();
    return kExitOk;
  }
  for (const CommandSpec& spec : AllSpecs()) {
    if (spec.name == topic) return PrintCommandHelp(spec);
  }
  SYLVA_INPUT_ERROR(topic) << "no such command or help topic (see 'sylva help')";
  return kExitBadInput;
}

int Dispatch(int argc, const char* const* argv) {
  if (argc < 2) {
    std::cerr << GeneralHelp();
    return kExitBadInput;
  }
  const std::string command = argv[1];
  if (command == "help" || command == "-h" || command == "--help") return CmdHelp(argc, argv);
  if (command == "version" || command == "--version") {
    std::cout << "sylva 0.1.0\n";
    return kExitOk;
  }
  for (const CommandSpec& spec : AllSpecs()) {
    if (spec.name != command) continue;
    const ParsedArguments args = ParseArguments(spec, argc, argv, 2);
    if (args.help) return PrintCommandHelp(spec);
    ApplyLogLevel(args);
    if (command == "init") return CmdInit(args);
    if (command == "run") return RunPipeline(args, nullptr);
    if (command == "synth") return CmdSynth(args);
    if (command == "mesh-qsm") return CmdMeshQsm(args);
    if (command == "batch") return CmdBatch(args);
    if (command == "sketch") return CmdSketch(args);
    if (command == "mesh-mtg") return CmdMeshMtg(args);
    if (command == "concept") return CmdConcept(args);
    if (command == "gesture") return CmdGesture(args);
    const Stage stage = ParseStage(command, command);
    return RunPipeline(args, &stage);
  }
  SYLVA_INPUT_ERROR(command) << "unknown command (see 'sylva help')";
  return kExitBadInput;
}

}  // namespace

int RunCommandLine(int argc, const char* const* argv) {
  try {
    return Dispatch(argc, argv);
  } catch (const InputError& error) {
    std::cerr << "\nsylva: error: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const Cancelled&) {
    std::cerr << "\nsylva: interrupted; no output was changed by the unfinished stage\n";
    return kExitCancelled;
  } catch (const std::exception& error) {
    std::cerr << "\nsylva: internal error: " << error.what() << "\n";
    return kExitError;
  }
}

}  // namespace sylva
