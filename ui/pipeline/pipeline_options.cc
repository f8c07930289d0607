#include "ui/pipeline/pipeline_options.h"

#include <cmath>

#include "core/util/check.h"
#include "mesh/subdivision.h"

namespace sylva {

void GeneralOptions::Check() const {
  SYLVA_CHECK_INPUT(num_threads >= 0 && num_threads <= 1024, "General.num_threads")
      << "must be between 0 (all cores) and 1024, got " << num_threads;
}

void ReportOptions::Check() const {
  SYLVA_CHECK_INPUT(opacity_threshold > 0 && opacity_threshold < 1, "Report.opacity_threshold")
      << "must be in (0, 1), got " << opacity_threshold;
  SYLVA_CHECK_INPUT(matte_threshold > 0 && matte_threshold <= 1, "Report.matte_threshold")
      << "must be in (0, 1], got " << matte_threshold;
  SYLVA_CHECK_INPUT(pixels_per_voxel > 0 && pixels_per_voxel <= 64, "Report.pixels_per_voxel")
      << "must be in (0, 64], got " << pixels_per_voxel;
  SYLVA_CHECK_INPUT(mesh_samples_per_axis >= 1 && mesh_samples_per_axis <= 16,
                    "Report.mesh_samples_per_axis")
      << "must be between 1 and 16, got " << mesh_samples_per_axis;
  SYLVA_CHECK_INPUT(preview_size >= 64 && preview_size <= 4096, "Report.preview_size")
      << "must be between 64 and 4096 pixels, got " << preview_size;
  SYLVA_CHECK_INPUT(preview_samples_per_axis >= 1 && preview_samples_per_axis <= 8,
                    "Report.preview_samples_per_axis")
      << "must be between 1 and 8, got " << preview_samples_per_axis;
  SYLVA_CHECK_INPUT(poor_fit_iou >= 0 && poor_fit_iou <= 1, "Report.poor_fit_iou")
      << "must be in [0, 1], got " << poor_fit_iou;
}

void SkeletonOptions::Check() const {
  SYLVA_CHECK_INPUT(base.allFinite() || base.array().isNaN().all(), "Skeleton.base")
      << "must be 'auto' or three finite numbers";
  SYLVA_CHECK_INPUT(trunk_radius >= 0 && std::isfinite(trunk_radius), "Skeleton.trunk_radius")
      << "must be >= 0 (0 = measured in the mattes), got " << trunk_radius;
  SYLVA_CHECK_INPUT(trunk_radius_fraction > 0 && trunk_radius_fraction < 1,
                    "Skeleton.trunk_radius_fraction")
      << "must be in (0, 1), got " << trunk_radius_fraction;
  SYLVA_CHECK_INPUT(min_radius_fraction >= 0 && min_radius_fraction <= 1,
                    "Skeleton.min_radius_fraction")
      << "must be in [0, 1], got " << min_radius_fraction;
  pruning.Check();
  consolidation.Check();
}

void TreeGeometryOptions::Check() const {
  BarkMeshOptions bark_check = bark;
  bark_check.Check();
  SYLVA_CHECK_INPUT(bark_subdivision >= 0 && bark_subdivision <= kMaxLoopLevels,
                    "BranchMesh.subdivision")
      << "must be in [0, " << kMaxLoopLevels << "], got " << bark_subdivision;
  twig.Check();
  twig_mesh.Check();
}

void AttractStageOptions::Check() const {
  SYLVA_CHECK_INPUT(mode == "auto" || mode == "edits" || mode == "off", "Attractors.mode")
      << "must be auto, edits or off, got '" << mode << "'";
  strokes.Check();
  livewire.Check();
}

void SketchMrfOptions::Check() const {
  SYLVA_CHECK_INPUT(method == "flow" || method == "mrf" || method == "silhouette", "Sketch.method")
      << "expected flow, mrf or silhouette, got '" << method << "'";
  mrf.Check();
  silhouette.Check();
}

void PipelineOptions::Check() const {
  general.Check();
  matting.Check();
  matte_set.Check();
  colmap.Check();
  world_frame.Check();
  loose_init.Check();
  loose_refine.Check();
  density.Check();
  tree_base.Check();
  attract.Check();
  direction_field.Check();
  particle_flow.Check();
  skeleton.Check();
  // Allometry sizes are set by the skeleton stage; check the exponent here.
  AllometryOptions allometry_check = allometry;
  allometry_check.trunk_radius = 1.0;
  allometry_check.min_radius = 0.0;
  allometry_check.Check();
  branch_width.Check();
  branch_mesh.Check();
  leaves.Check();
  geometry.Check();
  tree_metrics.Check();
  report.Check();
  sketch.Check();
  sketch_mrf.Check();
  concept_plant.Check();
  pen_and_ink.Check();
  gesture.Check();
}

namespace {

void RegisterGeneral(GeneralOptions* o, OptionRegistry* r) {
  r->AddUint64("General.seed", &o->seed, "", "seed of every random choice; same seed, same tree");
  r->AddInt("General.num_threads", &o->num_threads, "threads", "worker threads; 0 = all cores");
}

void RegisterDensity(DensityOptions* o, OptionRegistry* r) {
  r->AddInt("Density.resolution", &o->resolution, "voxels",
            "voxels along the longest side of the bounds");
  r->AddInt("Density.max_resolution", &o->max_resolution, "voxels",
            "the grid is refined up to this when the mattes show structure thinner than a "
            "voxel (<= Density.resolution: never)");
  r->AddDouble("Density.max_thin_share", &o->max_thin_share, "share",
               "refine while more than this share of the mattes' foreground is thinner than a "
               "voxel");
  r->AddBox("Density.bounds", &o->bounds, "world units",
            "grid bounds x0,y0,z0,x1,y1,z1, or auto (visual hull of the mattes)");
  r->AddDouble("Density.bounds_margin_voxels", &o->bounds_margin_voxels, "voxels",
               "margin around automatic bounds");
  r->AddInt("Density.hull_resolution", &o->hull_resolution, "voxels",
            "coarse carving grid that finds automatic bounds (longest side)");
  r->AddDouble("Density.hull_alpha_threshold", &o->hull_alpha_threshold, "alpha",
               "matte value above which a pixel is foreground for the visual hull");
  r->AddBool("Density.open_frame_cuts", &o->open_frame_cuts,
             "a photo whose foreground reaches its edge (the tree goes on beyond the frame) "
             "does not bound the grid; the photos that frame the tree whole do (warning "
             "frame-cut where none does); false = every frame bounds the tree");
  r->AddDouble("Density.view_outlier_fraction", &o->view_outlier_fraction, "share of views",
               "at most this share of the mattes may be wrong: the consensus hull that tests "
               "every view tolerates that many dissenting views (0 = trust every view)");
  r->AddInt("Density.view_consensus_min_views", &o->view_consensus_min_views, "views",
            "fewer input views than this are not tested against the others");
  r->AddDouble("Density.view_max_carved_share", &o->view_max_carved_share, "share",
               "a view is left out when its matte carves away more than this share of what "
               "the other views agree on ...");
  r->AddDouble("Density.view_carved_share_ratio", &o->view_carved_share_ratio, "",
               "... and more than this many times the median view's share");
  r->AddDouble("Density.carve_threshold", &o->carve_threshold, "alpha",
               "voxels whose initial opacity (min over views of the mean matte over the "
               "footprint) is below this are carved (thesis 3.3)");
  r->AddDouble("Density.carve_dissent", &o->carve_dissent, "share of views",
               "implicit carving lets this share of the views see (nearly) nothing where a "
               "voxel is: thin structure missed by a view or two stays for the least squares "
               "to decide (floor(share x views) views; 0 = minimum over views, the thesis)");
  r->AddInt("Density.carve_min_views", &o->carve_min_views, "views",
            "... but never fewer views than this must see something where a voxel is "
            "(fewer agree on the visual hull's ghosts)");
  r->AddDouble("Density.pixels_per_voxel", &o->pixels_per_voxel, "pixels",
               "images are downsampled so a voxel covers about this many pixels across");
  r->AddInt("Density.rays_per_axis", &o->rays_per_axis, "rays",
            "rays per downsampled pixel along each axis (n x n)");
  r->AddDouble("Density.max_pixel_opacity", &o->max_pixel_opacity, "alpha",
               "matte values are clamped to this before -log(1 - alpha)");
  r->AddDouble("Density.min_row_weight", &o->min_row_weight, "",
               "pixel equations weighted by max(1 - alpha, this): fits opacity rather than "
               "depth; 1 = unweighted (thesis)");
  r->AddString("Density.solver", &o->solver,
               "projected (non-negative least squares) or cgls (thesis: least squares, then "
               "negatives clamped)");
  r->AddInt("Density.max_iterations", &o->max_iterations, "iterations",
            "iterations per least-squares solve");
  r->AddInt("Density.cauchy_every", &o->cauchy_every, "steps",
            "projected only: every this many steps one is a Cauchy step (exact length along "
            "the preconditioned gradient), which reaches the fit in fewer iterations; 0 = "
            "Barzilai-Borwein steps only");
  r->AddDouble("Density.tolerance", &o->tolerance, "relative",
               "stop when the (projected) gradient falls below tolerance times its start");
  r->AddInt("Density.nonnegative_passes", &o->nonnegative_passes, "passes",
            "cgls only: re-solves with clamped voxels fixed at zero (0 = clamp once, as the "
            "thesis)");
  r->AddDouble("Density.min_output_opacity", &o->min_output_opacity, "alpha",
               "voxels below this opacity are not stored");
  r->AddBool("Density.warm_start", &o->warm_start,
             "after an edit, re-solve from the last run's solve (faster; the grid then depends "
             "slightly on that run, so the same inputs may not give the same tree)");
}

void RegisterTreeBase(TreeBaseOptions* o, OptionRegistry* r) {
  r->AddDouble("TreeBase.min_opacity", &o->min_opacity, "alpha",
               "voxels below this opacity are ignored when finding the trunk's base");
  r->AddDouble("TreeBase.layer_fraction", &o->layer_fraction, "",
               "the base layer is the lowest holding this fraction of the densest low layer");
  r->AddInt("TreeBase.reference_voxels", &o->reference_voxels, "voxels",
            "low layers among which the densest is the reference");
  r->AddInt("TreeBase.slab_voxels", &o->slab_voxels, "voxels",
            "layers above the base whose centre gives the base's x and y");
}

void RegisterLivewire(LivewireOptions* o, OptionRegistry* r) {
  r->AddString("Attractors.seeds", &o->seeds,
               "automatic livewire seeds: silhouette (random outline points, the thesis), "
               "farthest_point or skeleton_tips");
  r->AddInt("Attractors.num_seeds", &o->num_seeds, "seeds", "automatic seeds per photo");
  r->AddInt("Attractors.max_image_size", &o->max_image_size, "pixels",
            "trace on a copy at most this large (longest side)");
  r->AddDouble("Attractors.matte_threshold", &o->matte_threshold, "alpha",
               "a pixel belongs to the tree at this matte value or more");
  r->AddDouble("Attractors.simplify_tolerance", &o->simplify_tolerance, "pixels",
               "Douglas-Peucker tolerance of the traced graphs");
  r->AddDouble("Attractors.min_twig_length", &o->min_twig_length, "fraction of the image size",
               "traced twigs shorter than this are removed");
  r->AddDouble("Attractors.weight_outside", &o->weight_outside, "",
               "livewire cost per step off the matte");
  r->AddDouble("Attractors.weight_direction", &o->weight_direction, "",
               "livewire cost of turning against the branch axis");
  r->AddDouble("Attractors.weight_centerline", &o->weight_centerline, "",
               "livewire cost of leaving the branches' centre lines");
  r->AddDouble("Attractors.photo_weight", &o->photo_weight, "",
               "share of the photo's luminance in the centre-line cost (0 = matte only)");
  r->AddDouble("Attractors.snap_radius", &o->snap_radius, "pixels",
               "snapped strokes: drawn nodes move to the best centre-line pixel this close");
}

void RegisterAttract(AttractStageOptions* o, OptionRegistry* r) {
  r->AddString("Attractors.mode", &o->mode,
               "auto (graphs a person drew in edits/, else traced by livewire), edits (only drawn "
               "ones) or off (no attractor graphs)");
  r->AddBool("Attractors.snap_strokes", &o->snap_strokes,
             "snap drawn strokes onto the photo's structures by livewire");
  r->AddBool("Attractors.write_overlays", &o->write_overlays,
             "draw each graph on its photo (out/attractors/<photo>.png)");
  r->AddDouble("Attractors.stroke_snap_distance", &o->strokes.snap_distance, "pixels",
               "a stroke's end this close to another stroke joins it");
  r->AddDouble("Attractors.stroke_simplify_tolerance", &o->strokes.simplify_tolerance, "pixels",
               "drawn points this close to the simplified stroke are dropped (0 keeps all)");
  r->AddDouble("Attractors.stroke_resample_spacing", &o->strokes.resample_spacing, "pixels",
               "a simplified stroke is resampled at most this far apart");
  RegisterLivewire(&o->livewire, r);
}

void RegisterDirectionField(AttractorFieldOptions* o, OptionRegistry* r) {
  r->AddInt("DirectionField.resolution", &o->resolution, "cells",
            "cells of each photo's 2D direction field along its longer side (thesis: 100)");
  r->AddString("DirectionField.blend", &o->blend,
               "blend h(d) of eq. 3.7: linear (towards the graph far, along it near) or "
               "constant (a fixed approach angle)");
  r->AddDouble("DirectionField.falloff", &o->falloff, "fraction of the image size",
               "linear blend: distance from the graph at which particles head straight for it");
  r->AddDouble("DirectionField.constant_h", &o->constant_h, "",
               "constant blend: h in (0, 1); approach angle atan(h / (1 - h))");
  r->AddString("DirectionField.combine", &o->combine,
               "how the views' lifted directions combine: average (least-squares mean, the "
               "thesis) or intersect (the direction whose projections agree with every view)");
  r->AddInt("DirectionField.resolution_3d", &o->resolution_3d, "cells",
            "samples of the 3D field along the longest side of the tree's box");
}

void RegisterParticleFlow(ParticleFlowOptions* o, OptionRegistry* r) {
  r->AddInt("ParticleFlow.num_particles", &o->num_particles, "particles",
            "particles seeded in proportion to density (thesis: 500-2000)");
  r->AddDouble("ParticleFlow.seed_exponent", &o->seed_exponent, "",
               "voxels are drawn in proportion to opacity to this power (1 = the thesis)");
  r->AddDouble("ParticleFlow.base_pull", &o->base_pull, "voxels/time^2", "pull towards the base");
  r->AddDouble("ParticleFlow.descent_angle_deg", &o->descent_angle_deg, "degrees",
               "the pull aims at the trunk axis this far below the horizontal (90 = at the base)");
  r->AddDouble("ParticleFlow.axis_lookahead", &o->axis_lookahead, "voxels",
               "near the axis the pull aims at least this far down");
  r->AddDouble("ParticleFlow.neighbor_pull", &o->neighbor_pull, "voxels/time^2",
               "largest attraction to the nearest neighbour");
  r->AddDouble("ParticleFlow.neighbor_radius", &o->neighbor_radius, "voxels",
               "the attraction fades to zero at this distance");
  r->AddDouble("ParticleFlow.field_weight", &o->field_weight, "voxels/time^2",
               "weight of the external direction field");
  r->AddDouble("ParticleFlow.damping", &o->damping, "1/time", "linear drag");
  r->AddDouble("ParticleFlow.merge_distance", &o->merge_distance, "voxels",
               "particles closer than this merge (masses add)");
  r->AddDouble("ParticleFlow.base_radius", &o->base_radius, "voxels",
               "particles this close to the base stop");
  r->AddBool("ParticleFlow.join_finished_traces", &o->join_finished_traces,
             "a particle passing a finished trace joins it (false = the thesis' behaviour)");
  r->AddBool("ParticleFlow.join_flowing_traces", &o->join_flowing_traces,
             "a particle moving along the trace of a bundle still flowing joins it (false = "
             "the thesis' behaviour)");
  r->AddDouble("ParticleFlow.flowing_join_angle_deg", &o->flowing_join_angle_deg, "degrees",
               "a flowing trace is joined only by particles moving within this angle of it");
  r->AddInt("ParticleFlow.max_iterations", &o->max_iterations, "steps",
            "accepted RK4 steps at most (thesis: ~200)");
  r->AddDouble("ParticleFlow.error_tolerance", &o->error_tolerance, "voxels",
               "largest position error per adaptive RK4 step");
  r->AddDouble("ParticleFlow.initial_step", &o->initial_step, "time", "first RK4 step");
  r->AddDouble("ParticleFlow.min_step", &o->min_step, "time", "smallest RK4 step");
  r->AddDouble("ParticleFlow.max_step", &o->max_step, "time", "largest RK4 step");
  r->AddDouble("ParticleFlow.trace_tolerance", &o->trace_tolerance, "voxels",
               "a trace records a node when the path deviates this much");
  r->AddDouble("ParticleFlow.simplify_tolerance", &o->simplify_tolerance, "voxels",
               "collinear chains are simplified within this distance");
  r->AddString("ParticleFlow.neighbor_search", &o->neighbor_search,
               "uniform_grid (fastest), embree or brute_force");
}

void RegisterSkeleton(SkeletonOptions* o, AllometryOptions* allometry, OptionRegistry* r) {
  r->AddPoint("Skeleton.base", &o->base, "world units",
              "bottom of the trunk x,y,z, or auto (estimated from the density)");
  r->AddDouble(
      "Skeleton.trunk_radius", &o->trunk_radius, "world units",
      "trunk radius at the base (an allometric prior's scale); 0 = measured in the mattes");
  r->AddDouble("Skeleton.trunk_radius_fraction", &o->trunk_radius_fraction, "",
               "trunk radius as a fraction of the tree height where the mattes cannot tell");
  r->AddDouble("Skeleton.min_radius_fraction", &o->min_radius_fraction, "",
               "thinnest branch radius as a fraction of the trunk radius");
  r->AddDouble("Skeleton.prune_max_strand_fraction", &o->pruning.max_strand_fraction, "",
               "branches carrying at most this fraction of all strands are checked against the "
               "mattes (0 = no pruning)");
  r->AddDouble("Skeleton.prune_max_outside_fraction", &o->pruning.max_outside_fraction, "",
               "a checked branch with more than this fraction of its length on matte background "
               "in some view is removed");
  r->AddDouble("Skeleton.prune_matte_threshold", &o->pruning.matte_threshold, "alpha",
               "matte value below which a branch sample is on background");
  r->AddDouble("Skeleton.prune_sample_spacing_fraction", &o->pruning.sample_spacing_fraction, "",
               "sample spacing along branches, as a fraction of the tree height");
  r->AddDouble("Skeleton.redundancy_fraction", &o->consolidation.redundancy_fraction, "",
               "twig stretches within this fraction of the height of other wood are trimmed "
               "(a branch traced twice keeps one trace; 0 = keep all)");
  r->AddDouble("Skeleton.zip_radius_voxels", &o->consolidation.zip_radius_voxels, "voxels",
               "a branch's first stretch within this distance of its parent (wood traced "
               "twice side by side) is zipped onto the parent (0 = keep)");
  r->AddDouble("Skeleton.duplicate_radius_voxels", &o->consolidation.duplicate_radius_voxels,
               "voxels",
               "a stretch within this distance of thicker wood elsewhere on the tree (a branch "
               "traced twice by bundles that passed at different times) joins it (0 = keep)");
  r->AddDouble("Skeleton.min_support", &o->consolidation.min_support, "",
               "twig stretches where less than this share of the voxels around reach "
               "Skeleton.support_opacity are trimmed (0 = keep)");
  r->AddInt("Skeleton.support_radius_voxels", &o->consolidation.support_radius_voxels, "voxels",
            "half-width of the cube of voxels the support is measured in");
  r->AddDouble("Skeleton.support_opacity", &o->consolidation.support_opacity, "alpha",
               "opacity from which a voxel counts as supporting wood");
  r->AddDouble("Skeleton.thin_strand_fraction", &o->consolidation.max_strand_fraction, "",
               "branches carrying at most this fraction of all strands must show density along "
               "them and may not leave the trunk's foot");
  r->AddDouble("Skeleton.max_empty_fraction", &o->consolidation.max_empty_fraction, "",
               "a thin branch with more than this fraction of its length in empty density is "
               "removed (1 = keep)");
  r->AddDouble("Skeleton.base_fraction", &o->consolidation.base_fraction, "",
               "thin branches leaving the trunk below this fraction of the height are removed");
  r->AddBool("Skeleton.remove_hidden_twigs", &o->consolidation.remove_hidden_twigs,
             "twigs lying wholly inside thicker wood (within its radius) are removed");
  r->AddDouble("Skeleton.consolidate_sample_spacing_fraction",
               &o->consolidation.sample_spacing_fraction, "",
               "sample spacing of the consolidation, as a fraction of the tree height");
  r->AddDouble("Allometry.diameter_exponent", &allometry->diameter_exponent, "",
               "pipe model d0^D = sum di^D: 2 = Leonardo, 2.49 = Murray");
}

void RegisterBranchWidth(BranchWidthOptions* o, OptionRegistry* r) {
  r->AddString("BranchWidth.mode", &o->mode,
               "scale the pipe-model radii to the branch widths the mattes show: auto (leafless "
               "plants, Leaves.num_leaves=-1), on, off");
  r->AddDouble("BranchWidth.matte_threshold", &o->matte_threshold, "alpha",
               "a matte pixel is foreground at this alpha or more");
  r->AddDouble("BranchWidth.view_quantile", &o->view_quantile, "",
               "quantile of an edge's widths over the views (0 = the narrowest)");
  r->AddInt("BranchWidth.min_views", &o->min_views, "views", "views needed to measure an edge");
  r->AddDouble("BranchWidth.min_side_on", &o->min_side_on, "",
               "an edge is measured in views seeing it at least this much side-on (0.5 = 30 deg)");
  r->AddDouble("BranchWidth.search_pixels", &o->search_pixels, "pixels",
               "how far across the projected edge its centre line is looked for");
  r->AddDouble("BranchWidth.min_measured_share", &o->min_measured_share, "",
               "share of an axis' edges measured for its own scale (else its parent's)");
}

void RegisterBranchMesh(BranchMeshOptions* o, OptionRegistry* r) {
  r->AddInt("BranchMesh.rings_per_segment", &o->rings_per_segment, "rings",
            "rings sampled per skeleton edge along the B-spline");
  r->AddDouble("BranchMesh.rings_per_unit_length", &o->rings_per_unit_length, "rings/world unit",
               "at least this many rings per unit of length (0 = off)");
  r->AddInt("BranchMesh.min_sides", &o->min_sides, "sides", "sides of the thinnest branches");
  r->AddInt("BranchMesh.max_sides", &o->max_sides, "sides", "sides of the trunk");
}

void RegisterLeaves(LeafOptions* o, OptionRegistry* r) {
  r->AddInt("Leaves.num_leaves", &o->num_leaves, "leaves",
            "leaves placed in proportion to density; 0 = from the density's leaf area "
            "(Beer-Lambert; trees without photos: every phyllotactic node of the thin "
            "branches); -1 = no leaves (leafless plants; mesh-qsm's default)");
  r->AddInt("Leaves.max_leaves", &o->max_leaves, "leaves", "upper bound on the automatic count");
  r->AddDouble("Leaves.leaf_length", &o->leaf_length, "world units",
               "leaf length; 0 = leaf_length_fraction x tree height");
  r->AddDouble("Leaves.leaf_length_fraction", &o->leaf_length_fraction, "",
               "leaf length as a fraction of the tree height");
  r->AddDouble("Leaves.leaf_aspect", &o->leaf_aspect, "", "leaf width / length");
  r->AddDouble("Leaves.twig_reach", &o->twig_reach, "leaf lengths",
               "leaves farther than this from a thin branch are dropped");
  r->AddDouble("Leaves.thin_branch_radius_fraction", &o->thin_branch_radius_fraction, "",
               "branches thinner than this fraction of the trunk radius carry leaves");
  r->AddDouble("Leaves.phototropism", &o->phototropism, "",
               "0 random orientation, 1 leaves turned outward from the crown (thesis 5.4)");
  r->AddDouble("Leaves.matte_threshold", &o->matte_threshold, "alpha",
               "leaves projecting onto mattes sparser than this are dropped");
  r->AddDouble("Leaves.max_draws_factor", &o->max_draws_factor, "",
               "leaf positions drawn at most this many times the leaves wanted");
}

// RegisterGeometry's parts, in registration order: bark, twigs, leaf shapes.
void RegisterBarkGeometry(TreeGeometryOptions* o, OptionRegistry* r) {
  r->AddBool("BranchMesh.watertight", &o->watertight_bark,
             "closed, outward 2-manifold bark with joints at junctions (thesis 5.3): one solid "
             "per root plus one per lateral left unattached (counted in the summary); false = "
             "overlapping tubes");
  r->AddDouble("BranchMesh.sphere_margin", &o->bark.sphere_margin, "",
               "junction spheres (eq. 5.25) enlarged by this fraction");
  r->AddInt("BranchMesh.repair_rounds", &o->bark.repair_rounds, "rounds",
            "junctions next to crossing triangles meshed again as convex joints; 0 = off");
  r->AddDouble("BranchMesh.max_cut_fraction", &o->bark.max_cut_fraction, "",
               "a joint's cut may use at most this fraction of its edge, in (0, 1)");
  r->AddDouble("BranchMesh.min_radius_fraction", &o->bark.min_radius_fraction, "",
               "ring radii are at least this fraction of the largest radius (tips of radius 0)");
  r->AddDouble("BranchMesh.attach_ratio", &o->bark.attach_ratio, "",
               "laterals at most this fraction of their parent's radius are attached to one quad "
               "of its tube instead of a convex joint; 0 = never");
  r->AddInt("BranchMesh.subdivision", &o->bark_subdivision, "levels",
            "Loop subdivision of the bark for smooth junctions: 0 = off, at most 3 (each level "
            "x4 triangles; thin branches shrink a little)");
}

void RegisterTwigs(TreeGeometryOptions* o, OptionRegistry* r) {
  r->AddBool("Twigs.enabled", &o->twigs, "grow twigs from the terminal branches (thesis 5.4)");
  r->AddString("Twigs.pattern", &o->twig.pattern, "monopodial or sympodial");
  r->AddDouble("Twigs.twigs_per_length", &o->twig.twigs_per_length, "per twig length",
               "twigs along a terminal branch where the density is average");
  r->AddDouble("Twigs.length_fraction", &o->twig.length_fraction, "",
               "twig length as a fraction of the tree height");
  r->AddDouble("Twigs.branching_angle_deg", &o->twig.branching_angle_deg, "degrees",
               "angle between a twig and its branch");
  r->AddDouble("Twigs.tropism", &o->twig.tropism, "", "> 0 bends twigs up, < 0 droops them");
  r->AddDouble("Twigs.stiffness", &o->twig.stiffness, "", "resistance to tropism, [0, 1]");
  r->AddString("Twigs.mesh", &o->twig_mesh.mode,
               "joined (part of the watertight bark), separate (closed tubes of their own beside "
               "the bark; bark.obj without them) or auto (separate above Twigs.separate_above)");
  r->AddInt("Twigs.separate_above", &o->twig_mesh.separate_above, "twigs",
            "Twigs.mesh=auto meshes the twigs separately when a tree has more than this");
  r->AddDouble("Twigs.max_density_factor", &o->twig.max_density_factor, "",
               "twigs per length at most this many times the average, in dense parts");
  r->AddDouble("Twigs.length", &o->twig.length, "world units",
               "twig length; 0 = Twigs.length_fraction x tree height");
  r->AddDouble("Twigs.length_variation", &o->twig.length_variation, "",
               "twig lengths vary uniformly by this fraction");
  r->AddDouble("Twigs.strand_fraction", &o->twig.strand_fraction, "",
               "a twig's strands as a fraction of its branch's (its radius by the pipe model)");
  r->AddDouble("Twigs.diameter_exponent", &o->twig.diameter_exponent, "",
               "pipe model exponent of the twigs' radii");
  r->AddDouble("Twigs.tip_taper", &o->twig.tip_taper, "",
               "a twig's radius at its tip as a fraction of its base radius");
  r->AddInt("Twigs.segments", &o->twig.segments, "segments", "skeleton edges per twig");
  r->AddInt("Twigs.laterals", &o->twig.laterals, "twigs",
            "monopodial: lateral shoots per twig, half as long");
  r->AddDouble("Twigs.sympodial_angle_deg", &o->twig.sympodial_angle_deg, "degrees",
               "sympodial: turn of each unit from the previous one");
}

void RegisterLeafGeometry(TreeGeometryOptions* o, LeafOptions* leaves, OptionRegistry* r) {
  r->AddString("Leaves.shape", &leaves->shape, "quad, ovate, lanceolate or needle");
  r->AddString("Leaves.image", &o->leaf_image,
               "a leaf picture (RGBA; alpha = outline) used as a textured leaf");
  r->AddString("Leaves.phyllotaxis", &leaves->phyllotaxis,
               "none (free, by density), alternate, opposite_decussate, whorled or spiral "
               "(the default of gesture, sketch --Sketch.method=mrf, mesh-qsm)");
  r->AddDouble("Leaves.internode", &leaves->internode, "leaf lengths",
               "phyllotaxis: distance between leaf nodes along a branch");
  r->AddDouble("Leaves.divergence_deg", &leaves->divergence_deg, "degrees",
               "phyllotaxis: angle between successive nodes; 0 = the pattern's own");
  r->AddInt("Leaves.leaves_per_whorl", &leaves->leaves_per_whorl, "leaves",
            "phyllotaxis whorled: leaves per node");
  r->AddDouble("Leaves.insertion_deg", &leaves->insertion_deg, "degrees",
               "phyllotaxis: angle between a leaf and its branch");
  r->AddBool("Export.instance_leaves", &o->instance_leaves,
             "tree.glb stores one leaf mesh + per-leaf transforms (EXT_mesh_gpu_instancing)");
}

void RegisterTreeMetrics(TreeMetricsOptions* o, OptionRegistry* r) {
  r->AddDouble("TreeMetrics.dbh_height_m", &o->dbh_height_m, "m",
               "height of the DBH above the base (metric units only)");
  r->AddDouble("TreeMetrics.major_branch_fraction", &o->major_branch_fraction, "",
               "a first-order branch starts the crown when it carries this fraction of the "
               "largest one's length");
  r->AddDouble("TreeMetrics.crown_scale_fraction", &o->crown_scale_fraction, "",
               "the density crown volume closes gaps about 2x this fraction of the height");
  r->AddDouble("TreeMetrics.density_support_fraction", &o->density_support_fraction, "",
               "density fainter than this fraction of the crown's typical value is noise");
  r->AddDouble("TreeMetrics.direction_fraction", &o->direction_fraction, "",
               "a branch's direction for its angle runs this fraction of its length");
}

void RegisterReport(ReportOptions* o, OptionRegistry* r) {
  r->AddDouble("Report.opacity_threshold", &o->opacity_threshold, "alpha",
               "projected density at or above this is foreground");
  r->AddDouble("Report.matte_threshold", &o->matte_threshold, "alpha",
               "matte at or above this is foreground");
  r->AddDouble("Report.pixels_per_voxel", &o->pixels_per_voxel, "pixels",
               "comparison resolution: images downsampled so a voxel covers about this many "
               "pixels");
  r->AddInt("Report.mesh_samples_per_axis", &o->mesh_samples_per_axis, "rays",
            "rays per compared pixel along each axis when rendering the mesh");
  r->AddBool("Report.write_images", &o->write_images,
             "write per-view comparison pictures, renders and report.html");
  r->AddBool("Report.previews", &o->previews,
             "preview pictures of the tree (bark + leaves, sun and shadows, 4 views) in "
             "report/preview_<k>.png");
  r->AddInt("Report.preview_size", &o->preview_size, "pixels",
            "width and height of the preview pictures");
  r->AddInt("Report.preview_samples_per_axis", &o->preview_samples_per_axis, "rays",
            "rays per preview pixel along each axis (anti-aliasing)");
  r->AddDouble("Report.poor_fit_iou", &o->poor_fit_iou, "IoU",
               "below this mean IoU over the input views the report warns poor-density-fit / "
               "poor-mesh-fit; 0 = never");
}

// RegisterMatting's parts, in registration order: the trimap, its refinement.
void RegisterTrimap(MattingOptions* o, MatteStageOptions* stage, OptionRegistry* r) {
  r->AddString("Matting.trimap", &o->trimap,
               "trimap source: auto (backdrop if the photo border is uniform, else grabcut), "
               "backdrop, difference (needs Matting.background_photo) or grabcut");
  r->AddString("Matting.background_photo", &stage->background_photo,
               "photo of the backdrop without the tree, for trimap=difference (path, absolute "
               "or relative to the project)");
  r->AddDouble("Matting.auto_backdrop_fraction", &o->auto_backdrop_fraction, "fraction",
               "trimap=auto uses the backdrop model when this share of the border agrees "
               "with its median colour");
  r->AddString("Matting.backdrop_color", &o->backdrop_color,
               "backdrop colour: auto (median of the photo border) or R,G,B in 0..255");
  r->AddDouble("Matting.border_fraction", &o->border_fraction, "fraction",
               "width of the border strip sampled for the backdrop, of the shorter side");
  r->AddDouble("Matting.chroma_tolerance", &o->chroma_tolerance, "sine",
               "chroma difference to the backdrop still counted as backdrop");
  r->AddDouble("Matting.luminance_tolerance", &o->luminance_tolerance, "luminance",
               "brightness difference to the backdrop still counted as backdrop (0..1)");
  r->AddDouble("Matting.dark_level", &o->dark_level, "luminance",
               "below this brightness a pixel's chroma is treated as noise");
  r->AddDouble("Matting.foreground_evidence", &o->foreground_evidence, "",
               "evidence (difference / tolerance) from which a pixel is sure foreground");
  r->AddDouble("Matting.backdrop_smoothness", &o->backdrop_smoothness, "fraction",
               "smoothness of the estimated backdrop (Gaussian sigma, of the longer side)");
  r->AddInt("Matting.band_px", &o->band_px, "pixels",
            "pixels this close to both foreground and background are unknown");
  r->AddString("Matting.reject_hues", &o->reject_hues,
               "hue ranges never foreground, lo-hi[,lo-hi] in degrees (e.g. 330-35 for "
               "orange calibration targets); empty = none");
  r->AddDouble("Matting.reject_min_saturation", &o->reject_min_saturation, "fraction",
               "minimum HSV saturation of a rejected hue");
  r->AddDouble("Matting.reject_min_value", &o->reject_min_value, "fraction",
               "minimum HSV value of a rejected hue");
  r->AddInt("Matting.reject_margin_px", &o->reject_margin_px, "pixels",
            "margin rejected around rejected objects");
  r->AddInt("Matting.reject_min_width_px", &o->reject_min_width_px, "pixels",
            "rejected-hue objects are at least this wide (thinner ones, e.g. tan stems, stay)");
  r->AddDouble("Matting.reject_below_value", &o->reject_below_value, "fraction",
               "pixels darker than this HSV value are never foreground; 0 = off");
  r->AddString("Matting.region", &o->region,
               "region of interest x0,y0,x1,y1 as fractions of the photo; outside is "
               "background; empty = whole photo");
  r->AddInt("Matting.grabcut_iterations", &o->grabcut_iterations, "iterations",
            "GrabCut iterations (trimap=grabcut)");
  r->AddDouble("Matting.grabcut_margin", &o->grabcut_margin, "fraction",
               "border strip GrabCut assumes background, of each side");
  r->AddDouble("Matting.grabcut_max_megapixels", &o->grabcut_max_megapixels, "MP",
               "GrabCut runs on the photo downsampled to at most this size");
}

void RegisterAlphaRefinement(MattingOptions* o, OptionRegistry* r) {
  r->AddString("Matting.refine", &o->refine,
               "alpha refinement of the unknown pixels: closed_form (Levin et al.), alphamat "
               "(OpenCV information flow) or none");
  r->AddDouble("Matting.max_megapixels", &o->max_megapixels, "MP",
               "refinement runs at most at this size, then alpha is upsampled guided by "
               "the photo");
  r->AddDouble("Matting.closed_form_prior_weight", &o->closed_form_prior_weight, "",
               "weak pull towards alpha 0.5 that keeps unknown regions without known "
               "neighbours well-posed");
  r->AddDouble("Matting.closed_form_epsilon", &o->closed_form_epsilon, "",
               "closed-form matting regulariser (colours in 0..1)");
  r->AddInt("Matting.closed_form_max_iterations", &o->closed_form_max_iterations, "iterations",
            "conjugate-gradient iterations of closed-form matting");
  r->AddDouble("Matting.closed_form_tolerance", &o->closed_form_tolerance, "",
               "conjugate-gradient relative tolerance");
  r->AddInt("Matting.upsample_radius", &o->upsample_radius, "pixels",
            "guided upsampling window radius (reduced image)");
  r->AddDouble("Matting.upsample_epsilon", &o->upsample_epsilon, "",
               "guided upsampling regulariser");
  r->AddInt("Matting.seed", &o->seed, "", "seed of GrabCut's k-means initialisation");
}

void RegisterMatteSet(MatteSetOptions* o, OptionRegistry* r) {
  r->AddBool("MatteSet.remove_static", &o->remove_static,
             "make background what is foreground at the same pixels in (nearly) every photo "
             "of a fixed camera: a cabin's frame, rails, pot holder");
  r->AddInt("MatteSet.static_min_photos", &o->static_min_photos, "photos",
            "photos of one size needed to call pixels static");
  r->AddDouble("MatteSet.static_photo_fraction", &o->static_photo_fraction, "share of photos",
               "static = foreground and unchanged in at least this share of the photos");
  r->AddDouble("MatteSet.static_color_tolerance", &o->static_color_tolerance, "RGB in [0, 1]",
               "unchanged = every channel within this of the per-pixel median photo");
  r->AddInt("MatteSet.static_margin_px", &o->static_margin_px, "analysis pixels",
            "static structure grown by this margin");
  r->AddDouble("MatteSet.static_min_moving_share", &o->static_min_moving_share, "share",
               "if less of the foreground moves between photos, nothing is removed");
  r->AddDouble("MatteSet.max_border_share", &o->max_border_share, "share",
               "a matte covering more of the image border is implausible (re-matted or named)");
  r->AddDouble("MatteSet.max_foreground_ratio", &o->max_foreground_ratio, "",
               "a matte with more than this many times the median photo's foreground (or less "
               "than its inverse) is implausible");
  r->AddInt("MatteSet.analysis_size", &o->analysis_size, "pixels",
            "the set checks run on copies at most this large");
}

void RegisterColmap(ColmapOptions* o, OptionRegistry* r) {
  r->AddString("Colmap.executable", &o->executable, "the COLMAP program (name on PATH or a path)");
  r->AddString("Colmap.matcher", &o->matcher,
               "exhaustive, sequential, or auto (exhaustive up to Colmap.exhaustive_max_photos)");
  r->AddInt("Colmap.exhaustive_max_photos", &o->exhaustive_max_photos, "photos",
            "matcher=auto matches exhaustively up to this many photos");
  r->AddInt("Colmap.sequential_overlap", &o->sequential_overlap, "photos",
            "sequential matcher: neighbours matched on each side");
  r->AddBool("Colmap.use_masks", &o->use_masks,
             "pass the mattes (dilated) as COLMAP masks: features only on the tree");
  r->AddInt("Colmap.max_image_size", &o->max_image_size, "pixels",
            "SIFT runs on photos downscaled to at most this size");
  r->AddInt("Colmap.max_num_features", &o->max_num_features, "features", "SIFT features per photo");
  r->AddString("Colmap.camera_model", &o->camera_model,
               "COLMAP camera model (SIMPLE_RADIAL, PINHOLE, OPENCV, ...)");
  r->AddBool("Colmap.single_camera", &o->single_camera,
             "one camera for all photos (forced off when photo sizes differ)");
  r->AddInt("Colmap.num_threads", &o->num_threads, "threads", "COLMAP threads; -1 = all cores");
  r->AddInt("Colmap.random_seed", &o->random_seed, "", "COLMAP's random seed");
  r->AddDouble("Colmap.stall_seconds", &o->stall_seconds, "s",
               "a COLMAP command silent and idle (no CPU time) this long has hung: it is stopped "
               "and run once more (0 = wait for ever)");
  r->AddInt("Colmap.mapper_attempts", &o->mapper_attempts, "runs",
            "mapper runs (next seed each, relaxed thresholds) while photos stay unregistered");
  r->AddDouble("Colmap.rematch_below", &o->rematch_below, "share",
               "match again (guided) when fewer than this share of the photos are registered");
}

void RegisterWorldFrame(WorldFrameOptions* o, OptionRegistry* r) {
  r->AddString("WorldFrame.up", &o->up,
               "the registration's axis that points up: auto (camera ring or the photos' "
               "vertical), +x, -x, +y, -y, +z, -z, or keep");
  r->AddString("WorldFrame.base", &o->base,
               "tree base at the origin: auto (lowest matte region, triangulated) or keep");
  r->AddDouble("WorldFrame.known_height", &o->known_height, "WorldFrame.units",
               "the tree's height, to scale the world; 0 = unknown (units arbitrary)");
  r->AddString("WorldFrame.units", &o->units, "units of WorldFrame.known_height");
  r->AddInt("WorldFrame.matte_working_size", &o->matte_working_size, "pixels",
            "mattes are analysed downsampled to at most this size");
  r->AddDouble("WorldFrame.min_part_fraction", &o->min_part_fraction, "",
               "matte parts smaller than this fraction of the largest are ignored");
  r->AddDouble("WorldFrame.band_fraction", &o->band_fraction, "",
               "the lowest band of a matte, as a fraction of its extent along up");
  r->AddDouble("WorldFrame.consensus", &o->consensus, "",
               "share of the views whose mattes must cover a point of the tree (1 = visual hull)");
  r->AddInt("WorldFrame.ring_min_views", &o->ring_min_views, "views",
            "camera centres form a ring with at least this many views");
  r->AddDouble("WorldFrame.ring_max_thickness", &o->ring_max_thickness, "",
               "a ring's spread across its plane, at most this fraction of its width");
  r->AddDouble("WorldFrame.ring_max_tilt_degrees", &o->ring_max_tilt_degrees, "degrees",
               "a ring leaning more than this from the cameras' upright is not horizontal");
  r->AddDouble("WorldFrame.matte_threshold", &o->matte_threshold, "alpha",
               "matte value from which a pixel is the tree");
}

void RegisterLoose(LooseInitOptions* init, LooseRefineOptions* refine, OptionRegistry* r) {
  r->AddDouble("LooseCameras.assumed_tree_height", &init->assumed_tree_height, "units",
               "tree height assumed when the loose-camera file gives none");
  r->AddDouble("LooseCameras.default_focal_factor", &init->default_focal_factor, "",
               "focal length of a perspective photo without one, times its longer side");
  r->AddDouble("LooseCameras.click_sigma_px", &refine->click_sigma_px, "pixels",
               "accuracy of a clicked correspondence");
  r->AddDouble("LooseCameras.robust_loss_px", &refine->robust_loss_px, "pixels",
               "reprojection error beyond which a click counts as an outlier (robust loss)");
  r->AddDouble("LooseCameras.azimuth_sigma_deg", &refine->azimuth_sigma_deg, "degrees",
               "how far the refinement may move a given azimuth (prior)");
  r->AddDouble("LooseCameras.elevation_sigma_deg", &refine->elevation_sigma_deg, "degrees",
               "prior on a given elevation");
  r->AddDouble("LooseCameras.roll_sigma_deg", &refine->roll_sigma_deg, "degrees",
               "prior on a given roll");
  r->AddInt("LooseCameras.max_iterations", &refine->max_iterations, "iterations",
            "Ceres iterations");
}

void RegisterSketch(SketchViewOptions* o, OptionRegistry* r) {
  r->AddInt("Sketch.image_size", &o->image_size, "pixels",
            "longest side of a drawing's view (the drawing is scaled to it)");
  r->AddDouble("Sketch.tree_height", &o->tree_height, "m",
               "height of a drawn tree (a prior: a drawing has no scale)");
  r->AddDouble("Sketch.crown_opacity", &o->crown_opacity, "alpha",
               "matte value of the regions a drawing encloses (the crown)");
  r->AddDouble("Sketch.line_width", &o->line_width, "fraction of the image size",
               "width of drawn lines in the matte where the drawing gives none");
  r->AddDouble("Sketch.gap_closing", &o->gap_closing, "fraction of the image size",
               "gaps in outlines narrower than this are closed before filling");
  r->AddDouble("Sketch.valley_depth", &o->valley_depth, "fraction of the crown's size",
               "concavities of a crown outline deeper than this split it into bumps, "
               "one inferred major branch each");
  r->AddDouble("Sketch.branch_reach", &o->branch_reach, "",
               "how far an inferred major branch reaches towards its bump's apex");
}

void RegisterSketchMrf(SketchMrfOptions* o, OptionRegistry* r) {
  r->AddString("Sketch.method", &o->method,
               "how 'sylva sketch' makes the branches: flow (the drawing as views of a project, "
               "the particle flow), mrf (Chen 2008: drawn branches' depths by a Markov random "
               "field, then self-similar propagation) or silhouette (Wither 2009: branches "
               "inferred from the crown's silhouette and sub-silhouettes, placed in depth by a "
               "Gibbs process)");
  r->AddString("Sketch.exemplars", &o->exemplars,
               "mrf: exemplar trees, comma-separated .mtg, QSM .csv or skeleton .json files; "
               "empty = four built-in species");
  r->AddDouble("Sketch.mrf_interaction", &o->mrf.interaction, "",
               "mrf: k_e, how strongly branches seek free space");
  r->AddInt("Sketch.mrf_em_iterations", &o->mrf.em_iterations, "rounds",
            "mrf: EM rounds over the tree parameters (0 keeps the template's)");
  r->AddDouble("Sketch.mrf_prior_weight", &o->mrf.prior_weight, "relations",
               "mrf: how many relations the template's parameters count as in EM");
  r->AddInt("Sketch.mrf_grid", &o->mrf.density_grid, "voxels",
            "mrf: cells per side of the branch density grid (paper: 25)");
  r->AddInt("Sketch.mrf_reach", &o->mrf.crowding_reach, "voxels",
            "mrf: the interaction is summed this many voxels around a point (0 = the whole grid)");
  r->AddInt("Sketch.mrf_candidates", &o->mrf.depth_candidates, "depths",
            "mrf: depths tried per segment and step");
  r->AddInt("Sketch.mrf_sweeps", &o->mrf.max_icm_sweeps, "sweeps", "mrf: most ICM sweeps");
  r->AddDouble("Sketch.mrf_epsilon", &o->mrf.icm_epsilon, "fraction of the tree's size",
               "mrf: ICM stops when the depths move less than this in a sweep");
  r->AddInt("Sketch.generations", &o->mrf.generations, "generations",
            "mrf: propagation generations when the drawing has no crown");
  r->AddInt("Sketch.max_segments", &o->mrf.max_segments, "segments",
            "mrf: propagation stops at this many segments");
  SilhouetteTreeOptions* w = &o->silhouette;
  r->AddDouble("Sketch.silhouette_baf_base_deg", &w->baf_base_deg, "degrees",
               "silhouette: branching angle to the parent at its base (the BAF's first value)");
  r->AddDouble("Sketch.silhouette_baf_tip_deg", &w->baf_tip_deg, "degrees",
               "silhouette: branching angle to the parent at its tip (the BAF's last value)");
  r->AddDouble("Sketch.silhouette_valley_depth", &w->valley_depth, "fraction of the outline's size",
               "silhouette: concavities deeper than this split an outline into bumps");
  r->AddDouble("Sketch.silhouette_cone_min_deg", &w->cone_min_deg, "degrees",
               "silhouette: sub-silhouette cone of a sharp bump");
  r->AddDouble("Sketch.silhouette_cone_max_deg", &w->cone_max_deg, "degrees",
               "silhouette: sub-silhouette cone of a round bump");
  r->AddInt("Sketch.silhouette_levels", &w->levels, "levels",
            "silhouette: levels of branches below the trunk");
  r->AddDouble(
      "Sketch.silhouette_max_overlap", &w->max_overlap, "fraction of its area",
      "silhouette: a branch added for coverage may overlap its siblings' crowns this much");
  r->AddDouble("Sketch.silhouette_drawn_spread_deg", &w->drawn_spread_deg, "degrees",
               "silhouette: branches from the drawing turn at most this far out of its plane");
  r->AddDouble("Sketch.silhouette_extra_branches", &w->extra_branches, "per drawn branch",
               "silhouette: branches added around each parent to fill the crown in depth");
  r->AddString("Sketch.silhouette_phyllotaxis", &w->phyllotaxis,
               "silhouette: none, spiral (144 degrees), decussate (2 per node, 90 degrees) or "
               "whorl3 (3 per node, 60 degrees)");
  r->AddDouble("Sketch.silhouette_gibbs_alpha", &w->gibbs_alpha, "",
               "silhouette: alpha of the closeness penalty 1 / (1 + alpha d)");
  r->AddInt("Sketch.silhouette_gibbs_iterations", &w->gibbs_iterations, "trials",
            "silhouette: depletion-replacement trials per parent");
  r->AddInt("Sketch.silhouette_max_branches", &w->max_branches, "branches",
            "silhouette: most branches (half of them in the drawing's plane)");
  r->AddDouble("Sketch.silhouette_min_branch_share", &w->min_branch_share,
               "fraction of the tree's height", "silhouette: shorter branches are not inferred");
}

void RegisterConcept(ConceptPlantOptions* o, OptionRegistry* r) {
  r->AddString("Concept.phyllotaxis", &o->phyllotaxis,
               "auto (as written in the drawing, else spiral), spiral (137.5 deg), monostichous "
               "(30), distichous (180), tristichous (120) or tetrastichous (90)");
  r->AddDouble("Concept.divergence_deg", &o->divergence_deg, "degrees",
               "angle between successive nodes; < 0 = the pattern's");
  r->AddInt("Concept.organs_per_layer", &o->organs_per_layer, "nodes",
            "nodes between two inclination lines (or on the whole stem)");
  r->AddInt("Concept.organs_per_node", &o->organs_per_node, "organs",
            "organs per node, evenly spread (2 with tetrastichous: decussate pairs)");
  r->AddDouble("Concept.first_azimuth_deg", &o->first_azimuth_deg, "degrees",
               "azimuth of the top organ (0 = the drawing's right, counter-clockwise from above)");
  r->AddDouble("Concept.default_branching_deg", &o->default_branching_deg, "degrees",
               "organs' angle from the stem's downward direction without inclination lines");
  r->AddDouble("Concept.stem_length", &o->stem_length, "m",
               "the stem's length (a drawing has no scale)");
  r->AddDouble("Concept.stem_radius_fraction", &o->stem_radius_fraction, "",
               "stem base radius over its length when the drawing gives no stroke width");
  r->AddDouble("Concept.stem_tip_fraction", &o->stem_tip_fraction, "",
               "stem radius at its tip over its base radius");
  r->AddDouble("Concept.organ_droop", &o->organ_droop, "organ lengths",
               "how far a blade's tip hangs below its reference line");
  r->AddDouble("Concept.organ_fold_deg", &o->organ_fold_deg, "degrees",
               "a blade rises from its midrib to its edges at this angle");
  r->AddBool("Concept.organ_axes", &o->organ_axes,
             "every organ is also a skeleton axis (midrib), so L-Py and MTG carry the "
             "arrangement");
  r->AddDouble("Concept.organ_axis_radius_fraction", &o->organ_axis_radius_fraction, "",
               "an organ axis' radius over the organ's length");
}

void RegisterPenAndInk(PenAndInkOptions* o, OptionRegistry* r) {
  r->AddInt("PenAndInk.image_size", &o->image_size, "pixels", "longer side of the drawings");
  r->AddDouble("PenAndInk.margin", &o->margin, "fraction of the image size", "empty border");
  r->AddDouble("PenAndInk.sample_spacing_px", &o->sample_spacing_px, "pixels",
               "outline edges are tested for visibility at this spacing");
  r->AddDouble("PenAndInk.crease_deg", &o->crease_deg, "degrees",
               "faces meeting at more than this angle draw a crease line");
  r->AddDouble("PenAndInk.hatch_spacing_px", &o->hatch_spacing_px, "pixels",
               "distance between hatching lines");
  r->AddDouble("PenAndInk.hatch_tone", &o->hatch_tone, "",
               "surfaces darker than this (0 white, 1 black) are hatched");
  r->AddDouble("PenAndInk.cross_hatch_tone", &o->cross_hatch_tone, "",
               "surfaces darker than this are cross-hatched");
  r->AddPoint("PenAndInk.light_direction", &o->light_direction, "",
              "direction towards the light (x,y,z; +z up, +y away from the drawing's viewer)");
  r->AddDouble("PenAndInk.outline_width_px", &o->outline_width_px, "pixels", "outline ink width");
  r->AddDouble("PenAndInk.hatch_width_px", &o->hatch_width_px, "pixels", "hatching ink width");
  r->AddDouble("PenAndInk.construction_width_px", &o->construction_width_px, "pixels",
               "construction line width");
  r->AddBool("PenAndInk.construction", &o->construction,
             "draw the construction lines (grey, dashed) in their own layer");
}

void RegisterGesture(GestureTreeOptions* o, OptionRegistry* r) {
  r->AddString("Gesture.grammar", &o->grammar,
               "L-system grammar file (.lsys, see README); empty = the built-in broadleaf "
               "(datasets/gesture/broadleaf.lsys)");
  r->AddString("Gesture.defines", &o->defines,
               "the grammar's parameters: NAME=VALUE,... replaces its #define constants");
  r->AddInt("Gesture.iterations", &o->iterations, "steps", "derivation steps of the L-system");
  r->AddInt("Gesture.trunk_segments", &o->trunk_segments, "segments",
            "F modules per trunk stroke (resampled by arc length)");
  r->AddInt("Gesture.smoothing_passes", &o->smoothing_passes, "passes",
            "smoothing of the resampled trunk strokes (ends fixed)");
  r->AddDouble("Gesture.trunk_radius", &o->trunk_radius, "fraction of the trunk's length",
               "trunk radius where the stroke moved at its mean speed");
  r->AddDouble("Gesture.max_speed_ratio", &o->max_speed_ratio, "",
               "radius = trunk_radius x mean speed / speed, clamped to [1/this, this]");
  r->AddDouble("Gesture.crown_base", &o->crown_base, "fraction of a trunk's length",
               "no growth points below this");
  r->AddDouble("Gesture.growth_spacing", &o->growth_spacing, "fraction of a trunk's length",
               "distance between growth points A(l, r, h)");
  r->AddDouble("Gesture.divergence_deg", &o->divergence_deg, "degrees",
               "roll between successive growth points");
  r->AddDouble("Gesture.branch_length", &o->branch_length, "fraction of the trunk's length",
               "l of the growth points");
  r->AddDouble("Gesture.branch_radius_ratio", &o->branch_radius_ratio, "",
               "r of the growth points over the trunk's radius there");
  r->AddDouble("Gesture.roi_n", &o->roi_n, "",
               "supertoroid exponent of the region's vertical profile; <= 0 = fitted");
  r->AddDouble("Gesture.roi_e", &o->roi_e, "", "supertoroid exponent of its horizontal section");
  r->AddDouble("Gesture.roi_alpha", &o->roi_alpha, "radii",
               "the supertoroid's hole (0: a superellipsoid)");
  r->AddDouble("Gesture.roi_min_width", &o->roi_min_width, "fraction of the height",
               "least horizontal radius of a region fitted around the gestures (no ROI strokes)");
  r->AddDouble("Gesture.roi_margin", &o->roi_margin, "times the gestures' extent",
               "size of a region fitted around the gestures (no ROI strokes)");
  r->AddDouble("Gesture.roi_lift", &o->roi_lift, "fraction of the height",
               "how far a region fitted around the gestures sits above them");
  r->AddInt("Gesture.avoid_turns", &o->avoid_turns, "turns",
            "turns tried away from an obstacle before shortening");
  r->AddDouble("Gesture.avoid_turn_deg", &o->avoid_turn_deg, "degrees", "each turn's step");
  r->AddDouble("Gesture.min_segment_fraction", &o->min_segment_fraction, "",
               "segments shortened below this fraction of their length are pruned");
}

}  // namespace

void RegisterPipelineOptions(PipelineOptions* options, OptionRegistry* registry) {
  RegisterGeneral(&options->general, registry);
  RegisterTrimap(&options->matting, &options->matte_stage, registry);
  RegisterAlphaRefinement(&options->matting, registry);
  RegisterMatteSet(&options->matte_set, registry);
  RegisterColmap(&options->colmap, registry);
  RegisterWorldFrame(&options->world_frame, registry);
  RegisterLoose(&options->loose_init, &options->loose_refine, registry);
  RegisterDensity(&options->density, registry);
  RegisterTreeBase(&options->tree_base, registry);
  RegisterAttract(&options->attract, registry);
  RegisterDirectionField(&options->direction_field, registry);
  RegisterParticleFlow(&options->particle_flow, registry);
  RegisterSkeleton(&options->skeleton, &options->allometry, registry);
  RegisterBranchWidth(&options->branch_width, registry);
  RegisterBranchMesh(&options->branch_mesh, registry);
  RegisterLeaves(&options->leaves, registry);
  RegisterBarkGeometry(&options->geometry, registry);
  RegisterTwigs(&options->geometry, registry);
  RegisterLeafGeometry(&options->geometry, &options->leaves, registry);
  RegisterTreeMetrics(&options->tree_metrics, registry);
  RegisterReport(&options->report, registry);
  RegisterSketch(&options->sketch, registry);
  RegisterSketchMrf(&options->sketch_mrf, registry);
  RegisterConcept(&options->concept_plant, registry);
  RegisterPenAndInk(&options->pen_and_ink, registry);
  RegisterGesture(&options->gesture, registry);
}

}  // namespace sylva
