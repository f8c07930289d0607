#include "reconstruct/density/density_reconstruction.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "reconstruct/density/ray_system.h"
#include "reconstruct/density/thin_structure.h"
#include "reconstruct/density/view_consensus.h"
#include "reconstruct/density/view_sampling.h"
#include "reconstruct/density/visual_hull.h"

namespace sylva {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void CheckMattes(const ImageSet& image_set, const std::vector<FloatImage>& mattes) {
  SYLVA_CHECK(static_cast<int>(mattes.size()) == image_set.NumViews())
      << mattes.size() << " mattes for " << image_set.NumViews() << " views";
  for (int v = 0; v < image_set.NumViews(); ++v) {
    const Camera& camera = image_set.CameraOf(v);
    const FloatImage& matte = mattes[v];
    SYLVA_CHECK_INPUT(matte.channels() == 1, image_set.views[v].name)
        << "matte must have one channel";
    SYLVA_CHECK_INPUT(matte.width() == camera.width() && matte.height() == camera.height(),
                      image_set.views[v].name)
        << "matte is " << matte.width() << "x" << matte.height() << " but the camera is "
        << camera.width() << "x" << camera.height();
  }
}

// The dense voxel block over `bounds` with `resolution` voxels on its longest side.
VoxelBlock GridBlock(const Box3d& bounds, int resolution) {
  VoxelBlock block;
  block.voxel_size = bounds.sizes().maxCoeff() / resolution;
  block.lower_corner = bounds.min();
  for (int a = 0; a < 3; ++a) {
    block.dims[a] =
        std::max(1, static_cast<int>(std::ceil(bounds.sizes()[a] / block.voxel_size - 1e-9)));
  }
  return block;
}

Box3d WithMargin(Box3d bounds, const DensityOptions& options) {
  const double margin =
      options.bounds_margin_voxels * bounds.sizes().maxCoeff() / options.resolution;
  bounds.min().array() -= margin;
  bounds.max().array() += margin;
  return bounds;
}

// The views listed in `views` with their cameras, in order.
ImageSet SubsetOf(const ImageSet& image_set, const std::vector<int>& views) {
  ImageSet subset;
  subset.cameras = image_set.cameras;
  for (int v : views) subset.views.push_back(image_set.views[v]);
  return subset;
}

template <typename T>
std::vector<T> Pick(const std::vector<T>& items, const std::vector<int>& indices) {
  std::vector<T> picked;
  for (int i : indices) picked.push_back(items[i]);
  return picked;
}

// The views the reconstruction uses: those whose mattes agree with the
// others (view_consensus.h), and those with painted density whatever they
// show; the others are named in the summary. Fills `trusted` with their
// indices.
void ChooseTrustedViews(const ImageSet& image_set, const std::vector<FloatImage>& masks,
                        const DensityOptions& options, const ProgressTask& progress,
                        std::vector<int>* trusted, DensitySummary* summary) {
  const std::vector<std::string> screened = ScreenForegroundMasks(masks);
  std::vector<int> plausible;
  for (int v = 0; v < image_set.NumViews(); ++v) {
    if (screened[v].empty()) plausible.push_back(v);
  }
  SYLVA_CHECK_INPUT(!plausible.empty(), "mattes") << "every matte is empty (no foreground)";
  // The frusta of the plausible views bound the consensus test (a wrong but
  // non-empty matte only loosens them), those of photos that cut the tree
  // not, as for the bounds (else the views that frame it whole would
  // disagree with the cut ones).
  FrameCuts cuts;
  const Box3d frustum_bounds =
      options.bounds.isEmpty()
          ? FrustumIntersectionBounds(SubsetOf(image_set, plausible), Pick(masks, plausible),
                                      options.open_frame_cuts ? &cuts : nullptr)
          : options.bounds;
  const ViewConsensus consensus =
      AssessViewConsensus(image_set, masks, frustum_bounds, options, screened, progress);
  summary->allowed_dissent = consensus.allowed_dissent;
  summary->median_carved_share = consensus.median_carved_share;
  for (int v = 0; v < image_set.NumViews(); ++v) {
    const std::string& name = image_set.views[v].name;
    const std::vector<std::string>& edited = options.edited_views;
    if (!consensus.trusted[v] && std::count(edited.begin(), edited.end(), name) > 0) {
      summary->warnings.push_back({"edited-view-kept",
                                   name + ": kept in the density although " + consensus.reasons[v] +
                                       ", because density is painted on it",
                                   name});
    } else if (!consensus.trusted[v]) {
      summary->distrusted_views.push_back(name);
      summary->warnings.push_back(
          {"distrusted-view", name + ": left out of the density, " + consensus.reasons[v], name});
      continue;
    }
    trusted->push_back(v);
  }
  SYLVA_CHECK_INPUT(!trusted->empty(), "mattes") << "no view agrees with the others";
}

// How many views implicit carving lets disagree (DensityOptions::carve_dissent
// and carve_min_views).
int CarveRank(int num_views, const DensityOptions& options) {
  const int dissent = static_cast<int>(std::floor(options.carve_dissent * num_views));
  return std::min(dissent, std::max(0, num_views - options.carve_min_views));
}

// Views whose mattes are looked at for thin structure (evenly spread).
constexpr int kThinStructureViews = 6;
// Fewer views than this do not pin thin structure down in depth: a finer grid
// only adds unknowns (two orthographic views of synthetic trees: held-out IoU
// 0.74-0.80 at 192 voxels against 0.75-0.81 at 128), so it is not refined.
constexpr int kMinViewsToRefine = 4;

// Density.resolution, refined by steps of 1.5x up to Density.max_resolution
// while too much of the mattes is thinner than a voxel (thin_structure.h)
// and the photos can show structure as fine as the next step's voxels.
void ChooseResolution(const ImageSet& image_set, const std::vector<FloatImage>& mattes,
                      const DensityOptions& options, DensitySummary* summary) {
  const Eigen::Vector3d center = summary->bounds.center();
  const double longest = summary->bounds.sizes().maxCoeff();
  const ThinStructureProbe probe(image_set, mattes, kThinStructureViews);
  const auto next = [&](int resolution) {
    return std::min(options.max_resolution, (3 * resolution + 1) / 2);
  };
  int resolution = options.resolution;
  double thin = probe.ThinShare(center, longest / resolution);
  bool capped = thin > options.max_thin_share && image_set.NumViews() < kMinViewsToRefine;
  while (!capped && thin > options.max_thin_share) {
    if (!probe.Resolvable(center, longest / next(resolution))) break;  // the photos' limit
    if (next(resolution) <= resolution) {
      capped = true;
      break;
    }
    resolution = next(resolution);
    thin = probe.ThinShare(center, longest / resolution);
  }
  summary->resolution = resolution;
  summary->thin_share = thin;
  if (!capped) return;
  std::ostringstream message;
  message << std::setprecision(3) << 100.0 * thin << " % of the mattes' centre lines are in "
          << "structure thinner than a voxel (" << longest / resolution << " world units, grid "
          << resolution << "); thin branches may be lost or faint ("
          << (image_set.NumViews() < kMinViewsToRefine ? "too few views to refine the grid"
                                                       : "raise Density.max_resolution")
          << ")";
  summary->warnings.push_back({"thin-structure", message.str()});
}

// Dense voxel index -> column of the unknown, -1 for carved voxels.
std::vector<int32_t> ColumnsOfKeptVoxels(const std::vector<float>& initial, double threshold,
                                         std::vector<int64_t>* voxel_of_column) {
  std::vector<int32_t> column_of_voxel(initial.size(), -1);
  for (size_t i = 0; i < initial.size(); ++i) {
    if (initial[i] > 0.0f && initial[i] >= threshold) {
      SYLVA_CHECK(voxel_of_column->size() < static_cast<size_t>(INT32_MAX))
          << "too many voxels; lower Density.resolution";
      column_of_voxel[i] = static_cast<int32_t>(voxel_of_column->size());
      voxel_of_column->push_back(static_cast<int64_t>(i));
    }
  }
  return column_of_voxel;
}

double OpticalDepth(double alpha, double max_opacity) {
  return -std::log(1.0 - std::min(alpha, max_opacity));
}

// The initial optical depths, scaled by the s minimising |s A x0 - b|.
std::vector<double> InitialSolution(const RaySystem& system, const std::vector<float>& initial,
                                    const std::vector<int64_t>& voxel_of_column, double max_opacity,
                                    double* scale) {
  std::vector<double> x(voxel_of_column.size());
  for (size_t j = 0; j < x.size(); ++j)
    x[j] = OpticalDepth(initial[voxel_of_column[j]], max_opacity);
  std::vector<double> ax;
  system.matrix.Multiply(x, &ax);
  double ab = 0.0, aa = 0.0;
  for (size_t i = 0; i < ax.size(); ++i) {
    ab += ax[i] * system.rhs[i];
    aa += ax[i] * ax[i];
  }
  *scale = aa > 0 ? ab / aa : 1.0;
  for (double& value : x) value *= *scale;
  return x;
}

// Non-negative least squares, or (thesis) CGLS, clamping of negatives, and
// re-solves with the clamped voxels fixed.
void SolveNonNegative(const RaySystem& system, const DensityOptions& options,
                      double absolute_tolerance, const ProgressTask& progress,
                      std::vector<double>* x, DensitySummary* summary) {
  const CglsOptions cgls{options.max_iterations, options.tolerance, absolute_tolerance,
                         options.cauchy_every};
  if (options.solver == "projected") {
    ProgressTask task = progress.SubTask("density: least squares", 0.0, 1.0);
    // A warm start (absolute_tolerance > 0) may need no step: the solve then
    // builds A's transpose only if it takes one.
    const bool warm = absolute_tolerance > 0;
    const SparseRows transposed = warm ? SparseRows() : system.matrix.Transposed();
    summary->solves.push_back(SolveProjectedGradient(system.matrix, warm ? nullptr : &transposed,
                                                     system.rhs, cgls, x, &task));
    return;
  }
  const SparseRows transposed = system.matrix.Transposed();
  std::vector<char> free(x->size(), 1);
  const int passes = 1 + options.nonnegative_passes;
  for (int pass = 0; pass < passes; ++pass) {
    ProgressTask task = progress.SubTask("density: least squares", double(pass) / passes,
                                         double(pass + 1) / passes);
    summary->solves.push_back(SolveCgls(system.matrix, transposed, system.rhs, cgls,
                                        pass > 0 ? &free : nullptr, x, &task));
    int64_t clamped = 0;
    for (size_t j = 0; j < x->size(); ++j) {
      if ((*x)[j] < 0.0) {
        (*x)[j] = 0.0;
        free[j] = 0;
        ++clamped;
      }
    }
    summary->num_clamped_voxels += clamped;
    if (clamped == 0) break;
  }
}

// The warm start's key: the caller's context and the grid's block, exactly.
std::string WarmStartKey(const std::string& context, const VoxelBlock& block) {
  std::ostringstream text;
  text << context << ";block" << std::hexfloat;
  for (int a = 0; a < 3; ++a) text << " " << block.dims[a] << " " << block.lower_corner[a];
  text << " " << block.voxel_size;
  return HexString(Fnv1a64(text.str()));
}

// Replaces the unknowns `warm` covers by its depths (both lists of voxels
// ascending); returns how many.
int64_t ApplyWarmStart(const DensityWarmStart& warm, const std::vector<int64_t>& voxel_of_column,
                       std::vector<double>* x) {
  if (warm.voxels.size() != warm.depths.size()) return 0;
  int64_t applied = 0;
  size_t k = 0;
  for (size_t j = 0; j < voxel_of_column.size(); ++j) {
    while (k < warm.voxels.size() && warm.voxels[k] < voxel_of_column[j]) ++k;
    if (k < warm.voxels.size() && warm.voxels[k] == voxel_of_column[j]) {
      (*x)[j] = warm.depths[k];
      ++applied;
    }
  }
  return applied;
}

// Step 4: least squares from the (rescaled) initialisation, or from the warm
// start where it matches; leaves this solve's state in `warm_start`.
std::vector<double> SolveDensity(const RaySystem& system, const std::vector<float>& initial,
                                 const VoxelBlock& block,
                                 const std::vector<int64_t>& voxel_of_column,
                                 const DensityOptions& options, const ProgressTask& progress,
                                 DensityWarmStart* warm_start, DensitySummary* summary) {
  std::vector<double> x = InitialSolution(system, initial, voxel_of_column,
                                          options.max_pixel_opacity, &summary->initial_scale);
  double stop_gradient = 0.0;
  const std::string key =
      warm_start != nullptr ? WarmStartKey(warm_start->context, block) : std::string();
  if (warm_start != nullptr && warm_start->key == key) {
    summary->num_warm_voxels = ApplyWarmStart(*warm_start, voxel_of_column, &x);
    if (summary->num_warm_voxels > 0) stop_gradient = warm_start->stop_gradient;
  }
  SolveNonNegative(system, options, stop_gradient, progress, &x, summary);
  if (warm_start == nullptr) return x;
  const CglsSummary& last = summary->solves.back();
  warm_start->key = key;
  warm_start->voxels = voxel_of_column;
  warm_start->depths.assign(x.begin(), x.end());
  warm_start->stop_gradient = std::max(
      {stop_gradient, options.tolerance * last.initial_gradient_norm, last.final_gradient_norm});
  return x;
}

DensityGrid MakeGrid(const VoxelBlock& block, const std::vector<int64_t>& voxel_of_column,
                     const std::vector<double>& x, double min_output_opacity) {
  const Eigen::Vector3d origin =
      block.lower_corner + Eigen::Vector3d::Constant(0.5 * block.voxel_size);
  DensityGrid grid(block.voxel_size, origin);
  for (size_t j = 0; j < x.size(); ++j) {
    const double alpha = 1.0 - std::exp(-x[j]);
    if (alpha > 0 && alpha >= min_output_opacity) {
      grid.SetValue(block.VoxelFromLinear(voxel_of_column[j]), static_cast<float>(alpha));
    }
  }
  return grid;
}

}  // namespace

std::string DensitySummary::BriefReport() const {
  std::ostringstream out;
  out << "Density: " << num_views << " views";
  if (!distrusted_views.empty()) {
    out << " (" << distrusted_views.size() << " left out: their mattes disagree with the others)";
  }
  out << ", grid " << grid_dims.x() << "x" << grid_dims.y() << "x" << grid_dims.z() << " (voxel "
      << voxel_size << "; " << std::lround(100.0 * thin_share)
      << " % of the mattes' centre lines thinner), " << (automatic_bounds ? "visual-hull" : "given")
      << " bounds";
  if (!frame_cut_views.empty()) {
    out << " (" << frame_cut_views.size() << " views cut the tree at the frame's edge"
        << (cut_by_every_frame ? ", and no view frames it whole: bounded by the frames)"
                               : ": bounded by the others)");
  }
  out << "; " << num_carved_voxels << " voxels after carving, " << num_rows << " pixel rays, "
      << num_nonzeros << " non-zeros";
  if (num_unexplained_pixels > 0) out << ", " << num_unexplained_pixels << " unexplained fg pixels";
  out << ". Least squares";
  if (num_warm_voxels > 0) out << " (warm start: " << num_warm_voxels << " voxels)";
  out << ": ";
  for (size_t i = 0; i < solves.size(); ++i) {
    out << (i ? "; " : "") << solves[i].iterations << " it, |r| " << solves[i].initial_residual_norm
        << " -> " << solves[i].final_residual_norm << (solves[i].converged ? " (converged)" : "");
  }
  out << "; " << num_clamped_voxels << " negatives clamped; " << num_output_voxels
      << " voxels stored. Time " << seconds_total << " s (bounds " << seconds_bounds << ", init "
      << seconds_init << ", system " << seconds_system << ", solve " << seconds_solve << ").";
  return out.str();
}

namespace {

// Step 1: the views whose mattes agree with the others (their indices in
// `all_views`) and the bounds, the visual hull of those views
// (summary->bounds, num_views, automatic_bounds).
std::vector<int> ChooseViewsAndBounds(const ImageSet& all_views,
                                      const std::vector<FloatImage>& all_mattes,
                                      const DensityOptions& options, const ProgressTask& progress,
                                      DensitySummary* summary) {
  std::vector<FloatImage> masks(all_mattes.size());
  tbb::parallel_for(size_t{0}, all_mattes.size(), [&](size_t v) {
    masks[v] = ForegroundMask(all_mattes[v], options.hull_alpha_threshold);
  });
  std::vector<int> trusted_views;
  ChooseTrustedViews(all_views, masks, options, progress.SubTask("density: views", 0.0, 0.03),
                     &trusted_views, summary);
  if (trusted_views.size() != masks.size()) masks = Pick(masks, trusted_views);
  summary->num_views = static_cast<int>(trusted_views.size());
  summary->automatic_bounds = options.bounds.isEmpty();
  if (!summary->automatic_bounds) {
    summary->bounds = options.bounds;
    return trusted_views;
  }
  const ImageSet trusted = SubsetOf(all_views, trusted_views);
  FrameCuts cuts;
  summary->bounds = WithMargin(VisualHullBounds(trusted, masks, options.hull_resolution,
                                                CarveRank(trusted.NumViews(), options),
                                                progress.SubTask("density: bounds", 0.03, 0.05),
                                                options.open_frame_cuts ? &cuts : nullptr),
                               options);
  for (int v : cuts.views) summary->frame_cut_views.push_back(trusted.views[v].name);
  summary->cut_by_every_frame = cuts.beyond_every_frame;
  if (cuts.beyond_every_frame) {
    std::ostringstream message;
    message << "the tree reaches the edge of the frame in " << cuts.views.size() << " of "
            << trusted.NumViews()
            << " views and no view frames it whole: the frames bound the reconstruction, and "
               "what lies beyond them is left out (step back, or add a view that frames the "
               "whole tree)";
    summary->warnings.push_back({"frame-cut", message.str()});
  }
  return trusted_views;
}

// Step 3: the pixel-ray equations over the kept voxels, from the mattes
// downsampled so a voxel covers about Density.pixels_per_voxel pixels.
RaySystem BuildPixelEquations(const ImageSet& image_set, const std::vector<FloatImage>& mattes,
                              const VoxelBlock& block, const std::vector<int32_t>& column_of_voxel,
                              int64_t num_columns, const DensityOptions& options,
                              const ProgressTask& progress, DensitySummary* summary) {
  const Eigen::Vector3d center =
      block.lower_corner + 0.5 * block.voxel_size * block.dims.cast<double>();
  std::vector<ViewSampling> sampling;
  std::vector<FloatImage> downsampled(image_set.NumViews());
  for (int v = 0; v < image_set.NumViews(); ++v) {
    sampling.push_back(MakeViewSampling(image_set, v, center, block.voxel_size,
                                        options.pixels_per_voxel, options.rays_per_axis));
    summary->downsample_factors.push_back(sampling.back().factor);
  }
  tbb::parallel_for(0, image_set.NumViews(),
                    [&](int v) { downsampled[v] = DownsampleBox(mattes[v], sampling[v].factor); });
  RaySystem system = BuildRaySystem(image_set, sampling, downsampled, block, column_of_voxel,
                                    num_columns, options.max_pixel_opacity,
                                    options.hull_alpha_threshold, options.min_row_weight, progress);
  summary->num_rows = system.matrix.NumRows();
  summary->num_nonzeros = system.matrix.NumNonZeros();
  summary->num_unexplained_pixels = system.num_unexplained_pixels;
  return system;
}

}  // namespace

DensityGrid ReconstructDensity(const ImageSet& image_set, const std::vector<FloatImage>& mattes,
                               const DensityOptions& options, ProgressReporter* progress,
                               DensitySummary* summary) {
  return ReconstructDensity(image_set, mattes, options, progress, summary, nullptr);
}

DensityGrid ReconstructDensity(const ImageSet& all_views, const std::vector<FloatImage>& all_mattes,
                               const DensityOptions& options, ProgressReporter* reporter,
                               DensitySummary* summary, DensityWarmStart* warm_start) {
  options.Check();
  all_views.Check("cameras");
  CheckMattes(all_views, all_mattes);
  DensitySummary local_summary;
  if (summary == nullptr) summary = &local_summary;
  *summary = DensitySummary();
  const Clock::time_point start = Clock::now();
  const ProgressTask progress(reporter, "density");

  // 1. Trusted views, bounds and the grid's resolution.
  Clock::time_point step = Clock::now();
  const std::vector<int> trusted_views =
      ChooseViewsAndBounds(all_views, all_mattes, options, progress, summary);
  const ImageSet image_set = SubsetOf(all_views, trusted_views);
  const bool all_trusted = image_set.NumViews() == all_views.NumViews();
  const std::vector<FloatImage> picked_mattes =
      all_trusted ? std::vector<FloatImage>() : Pick(all_mattes, trusted_views);
  const std::vector<FloatImage>& mattes = all_trusted ? all_mattes : picked_mattes;
  ChooseResolution(image_set, mattes, options, summary);
  const VoxelBlock block = GridBlock(summary->bounds, summary->resolution);
  summary->grid_dims = block.dims;
  summary->voxel_size = block.voxel_size;
  summary->seconds_bounds = SecondsSince(step);

  // 2. Initialisation and implicit carving.
  step = Clock::now();
  std::vector<SummedAreaTable> tables = MakeSummedAreaTables(mattes);
  const std::vector<float> initial =
      LowFootprintMeans(image_set, tables, block, CarveRank(image_set.NumViews(), options),
                        progress.SubTask("density: init", 0.05, 0.2));
  tables.clear();
  std::vector<int64_t> voxel_of_column;
  const std::vector<int32_t> column_of_voxel =
      ColumnsOfKeptVoxels(initial, options.carve_threshold, &voxel_of_column);
  summary->num_carved_voxels = static_cast<int64_t>(voxel_of_column.size());
  SYLVA_CHECK_INPUT(!voxel_of_column.empty(), "Density.carve_threshold")
      << "every voxel was carved away; lower the threshold or check cameras and mattes";
  summary->seconds_init = SecondsSince(step);

  // 3. The pixel-ray equations.
  step = Clock::now();
  const RaySystem system = BuildPixelEquations(
      image_set, mattes, block, column_of_voxel, static_cast<int64_t>(voxel_of_column.size()),
      options, progress.SubTask("density: rays", 0.2, 0.4), summary);
  summary->seconds_system = SecondsSince(step);

  // 4. Least squares.
  step = Clock::now();
  const std::vector<double> x =
      SolveDensity(system, initial, block, voxel_of_column, options,
                   progress.SubTask("density: solve", 0.4, 0.98), warm_start, summary);
  summary->seconds_solve = SecondsSince(step);

  // 5. The sparse grid.
  DensityGrid grid = MakeGrid(block, voxel_of_column, x, options.min_output_opacity);
  grid.SetMetadata("sylva_quantity", "opacity per voxel (alpha of a ray crossing one voxel)");
  summary->num_output_voxels = grid.NumActiveVoxels();
  summary->seconds_total = SecondsSince(start);
  return grid;
}

}  // namespace sylva
