// Ceres refinement of loosely registered cameras from clicked points (see
// loose_registration.h for the model, the unknowns and the gauge).
#include <ceres/ceres.h>

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include "core/util/check.h"
#include "reconstruct/registration/loose_angles.h"
#include "reconstruct/registration/loose_registration.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;
// Scales and focal lengths may not shrink below this fraction of their
// initial value (keeps them positive while the solver explores).
constexpr double kMinScaleFraction = 0.05;
// Triangulation: Tikhonov weight relative to the normal matrix' trace, so
// that (nearly) parallel rays still give a point (pulled to the origin).
constexpr double kTriangulationRegularizer = 1e-9;
// Solver tolerances (relative), tight: the problem is tiny.
constexpr double kFunctionTolerance = 1e-12;
constexpr double kParameterTolerance = 1e-12;
// Fewer clicked points than this leave an orthographic camera's 6 unknowns
// to the priors.
constexpr int kMinPointsPerCamera = 3;
// Directions fixed only by the priors that every problem has: the world's
// tilt about the two horizontal axes.
constexpr int kTiltDirections = 2;

using Point = std::array<double, 3>;

// ---- Cost functions --------------------------------------------------------

// Camera-frame coordinates R(angles) X + t (t of size 2 or 3; `z` only if 3).
template <typename T>
void CamFromWorld(const T* angles, const T* translation, bool has_z, const T* point, T* out) {
  T r[9];
  LooseRotationFromAngles(angles, r);
  for (int row = 0; row < 3; ++row) {
    out[row] = r[3 * row] * point[0] + r[3 * row + 1] * point[1] + r[3 * row + 2] * point[2];
  }
  out[0] += translation[0];
  out[1] += translation[1];
  if (has_z) out[2] += translation[2];
}

// Reprojection error of a clicked point, in units of the click sigma, for an
// orthographic camera (translation of size 2, scale in pixels per unit) or a
// perspective one (translation of size 3, focal length in pixels).
template <bool kPerspective>
struct Reprojection {
  Eigen::Vector2d observed, principal_point;
  double inverse_sigma;

  template <typename T>
  bool operator()(const T* angles, const T* translation, const T* scale, const T* point,
                  T* residual) const {
    T p[3];
    CamFromWorld(angles, translation, kPerspective, point, p);
    if constexpr (kPerspective) {
      if (!(p[2] > T(0))) return false;  // behind the camera: reject the step
      p[0] /= p[2];
      p[1] /= p[2];
    }
    residual[0] = (scale[0] * p[0] + principal_point.x() - observed.x()) * inverse_sigma;
    residual[1] = (scale[0] * p[1] + principal_point.y() - observed.y()) * inverse_sigma;
    return true;
  }
};

// The angles near the user's: 2 sin(difference / 2) / sigma is the
// difference for small angles and has no jump at +-180 degrees.
struct AnglePrior {
  Eigen::Vector3d prior, inverse_sigma;

  template <typename T>
  bool operator()(const T* angles, T* residual) const {
    using std::sin;
    for (int k = 0; k < 3; ++k) {
      residual[k] = T(2.0 * inverse_sigma[k]) * sin((angles[k] - T(prior[k])) * T(0.5));
    }
    return true;
  }
};

struct LogScalePrior {
  double prior, inverse_sigma;

  template <typename T>
  bool operator()(const T* scale, T* residual) const {
    using std::log;
    residual[0] = log(scale[0] / T(prior)) * inverse_sigma;
    return true;
  }
};

// ---- Problem state -----------------------------------------------------------

struct CameraState {
  std::string name;
  int view_idx = 0;  // in the initial ImageSet
  bool orthographic = false;
  bool free = false;  // sees clicked points, so it is refined
  int num_points = 0;
  double angles[3] = {0, 0, 0};       // azimuth, elevation, roll in radians
  double translation[3] = {0, 0, 0};  // of cam_from_world
  double scale[1] = {0};              // pixels per unit, or focal length in pixels
  Eigen::Vector2d principal_point = Eigen::Vector2d::Zero();
  Eigen::Vector3d given_angles = Eigen::Vector3d::Zero();  // the user's, radians
  double initial_scale = 0.0;
  double scale_sigma = 0.0;
};

struct ObservationRef {
  int camera = 0;
  int point = 0;
  Eigen::Vector2d observed = Eigen::Vector2d::Zero();
  ceres::ResidualBlockId block = nullptr;
};

// The camera of a view as refinement state; InputError if it cannot be.
CameraState StateFromView(const LooseSetup& setup, int photo_idx, const ImageSet& initial,
                          const LooseRefineOptions& options) {
  const LoosePhoto& photo = setup.photos[photo_idx];
  CameraState state;
  state.name = photo.name;
  state.view_idx = initial.FindView(photo.name);
  SYLVA_CHECK_INPUT(state.view_idx >= 0, setup.source)
      << "photo '" << photo.name << "' has no initial camera";
  const View& view = initial.views[state.view_idx];
  const Camera& camera = initial.CameraOf(view);
  state.orthographic = camera.IsOrthographic();
  SYLVA_CHECK_INPUT(state.orthographic == (photo.projection == LooseProjection::kOrthographic),
                    setup.source)
      << "photo '" << photo.name << "' is " << LooseProjectionName(photo.projection)
      << " but its initial camera is " << CameraModelName(camera.model());
  SYLVA_CHECK_INPUT(state.orthographic || ((camera.model() == CameraModel::kPinhole ||
                                            camera.model() == CameraModel::kSimplePinhole) &&
                                           camera.FocalLengthX() == camera.FocalLengthY()),
                    setup.source)
      << "photo '" << photo.name << "': loose refinement needs an ORTHOGRAPHIC or PINHOLE "
      << "camera with fx = fy, got " << CameraModelName(camera.model());
  const Eigen::Vector3d angles = LooseAnglesDeg(view.cam_from_world.rotation) * kDegree;
  std::copy(angles.data(), angles.data() + 3, state.angles);
  std::copy(view.cam_from_world.translation.data(), view.cam_from_world.translation.data() + 3,
            state.translation);
  state.scale[0] = state.initial_scale = camera.FocalLengthX();
  state.principal_point = camera.PrincipalPoint();
  state.given_angles =
      Eigen::Vector3d(photo.azimuth_deg, photo.elevation_deg, photo.roll_deg) * kDegree;
  state.scale_sigma =
      photo.HasFocalLength() ? options.known_focal_sigma : options.unknown_focal_sigma;
  return state;
}

Rigid3d PoseOf(const CameraState& state) {
  const Eigen::Vector3d angles_deg = Eigen::Map<const Eigen::Vector3d>(state.angles) / kDegree;
  return Rigid3d(LooseCamFromWorld(angles_deg.x(), angles_deg.y(), angles_deg.z()),
                 Eigen::Map<const Eigen::Vector3d>(state.translation));
}

ImageSet ImageSetOf(const ImageSet& initial, const std::vector<CameraState>& cameras) {
  ImageSet result = initial;
  for (const CameraState& state : cameras) {
    View& view = result.views[state.view_idx];
    view.cam_from_world = PoseOf(state);
    const Camera& old = initial.CameraOf(view);
    std::vector<double> params = {state.scale[0], state.scale[0], state.principal_point.x(),
                                  state.principal_point.y()};
    const CameraModel model =
        state.orthographic ? CameraModel::kOrthographic : CameraModel::kPinhole;
    result.cameras[view.camera_id] = Camera(model, old.width(), old.height(), std::move(params));
  }
  return result;
}

// Least-squares intersection of the rays of a point's observations.
Eigen::Vector3d Triangulate(const LoosePoint& point, const std::vector<CameraState>& cameras,
                            const ImageSet& image_set) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const LooseObservation& observation : point.observations) {
    const Ray3d ray = image_set.RayThroughPixel(cameras[observation.photo_idx].view_idx,
                                                observation.point_in_image);
    const Eigen::Matrix3d across =
        Eigen::Matrix3d::Identity() - ray.direction * ray.direction.transpose();
    normal += across;
    rhs += across * ray.origin;
  }
  normal += kTriangulationRegularizer * normal.trace() * Eigen::Matrix3d::Identity();
  return normal.ldlt().solve(rhs);
}

bool InFrontOfAll(const Eigen::Vector3d& point, const ImageSet& image_set) {
  for (const View& view : image_set.views) {
    if (!image_set.CameraOf(view).IsInFront(view.cam_from_world * point)) return false;
  }
  return true;
}

// Pixel distance between a point's projection and its click (infinite
// behind a camera).
double PixelError(const ImageSet& image_set, const CameraState& camera, const Point& point,
                  const Eigen::Vector2d& observed) {
  Eigen::Vector2d projected;
  if (!image_set.Project(camera.view_idx, Eigen::Vector3d(point[0], point[1], point[2]),
                         &projected)) {
    return std::numeric_limits<double>::infinity();
  }
  return (projected - observed).norm();
}

// ---- The problem ---------------------------------------------------------

class LooseProblem {
 public:
  LooseProblem(const LooseSetup& setup, const ImageSet& initial, const LooseRefineOptions& options)
      : setup_(setup),
        initial_(initial),
        options_(options),
        robust_scale_(options.robust_loss_px / options.click_sigma_px),
        loss_(new ceres::HuberLoss(robust_scale_), ceres::TAKE_OWNERSHIP),
        problem_(ProblemOptions()) {
    std::set<int> camera_ids;
    for (size_t i = 0; i < setup.photos.size(); ++i) {
      cameras_.push_back(StateFromView(setup, static_cast<int>(i), initial, options));
      const View& view = initial.views[cameras_.back().view_idx];
      SYLVA_CHECK_INPUT(camera_ids.insert(view.camera_id).second, setup.source)
          << "photo '" << view.name << "' shares camera " << view.camera_id
          << " with another photo; loose refinement needs one camera per photo";
    }
    for (const LoosePoint& point : setup.points) {
      for (const LooseObservation& observation : point.observations) {
        ++cameras_[observation.photo_idx].num_points;
      }
    }
    for (CameraState& camera : cameras_) camera.free = camera.num_points > 0;
    for (const LoosePoint& point : setup.points) {
      Eigen::Vector3d p = Triangulate(point, cameras_, initial);
      // A start behind a camera would stop the solver at once; the origin
      // (the base, in front of every initial camera) is a safe one.
      if (!InFrontOfAll(p, initial)) p.setZero();
      points_.push_back({p.x(), p.y(), p.z()});
    }
    Build();
  }

  // Solves for the points with the cameras held, then for everything with
  // the Huber loss (convex, so far-off starts converge), then with the
  // Cauchy loss (a mis-click then barely pulls).
  void Solve(LooseRefineSummary* summary) {
    SetCamerasConstant(true);
    ceres::Solver::Summary points_only;
    ceres::Solve(SolverOptions(), &problem_, &points_only);
    summary->rms_before_px = RmsError(ImageSetOf(initial_, cameras_), &rms_before_);
    SetCamerasConstant(false);
    ceres::Solver::Summary huber, cauchy;
    ceres::Solve(SolverOptions(), &problem_, &huber);
    loss_.Reset(new ceres::CauchyLoss(robust_scale_), ceres::TAKE_OWNERSHIP);
    ceres::Solve(SolverOptions(), &problem_, &cauchy);
    summary->termination = ceres::TerminationTypeToString(cauchy.termination_type);
    summary->iterations = static_cast<int>(huber.iterations.size() + cauchy.iterations.size()) - 2;
    summary->num_weak_directions = CountWeakDirections();
    summary->num_unknowns = NumUnknowns();
  }

  const std::vector<CameraState>& cameras() const { return cameras_; }
  const std::vector<Point>& points() const { return points_; }
  const std::vector<ObservationRef>& observations() const { return observations_; }
  // Per-camera RMS error with the initial cameras (after Solve).
  const std::vector<double>& rms_before() const { return rms_before_; }

  // RMS pixel error over all observations for `image_set` (the current
  // cameras); optionally per camera.
  double RmsError(const ImageSet& image_set, std::vector<double>* per_camera) const {
    std::vector<double> sums(cameras_.size(), 0.0);
    std::vector<int> counts(cameras_.size(), 0);
    double total = 0.0;
    for (const ObservationRef& ref : observations_) {
      const double error =
          PixelError(image_set, cameras_[ref.camera], points_[ref.point], ref.observed);
      sums[ref.camera] += error * error;
      ++counts[ref.camera];
      total += error * error;
    }
    if (per_camera != nullptr) {
      per_camera->assign(cameras_.size(), 0.0);
      for (size_t c = 0; c < cameras_.size(); ++c) {
        if (counts[c] > 0) (*per_camera)[c] = std::sqrt(sums[c] / counts[c]);
      }
    }
    return observations_.empty() ? 0.0 : std::sqrt(total / observations_.size());
  }

 private:
  // The problem does not own the shared loss function (a member).
  static ceres::Problem::Options ProblemOptions() {
    ceres::Problem::Options problem;
    problem.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return problem;
  }

  ceres::Solver::Options SolverOptions() const {
    ceres::Solver::Options solver;
    solver.linear_solver_type = ceres::DENSE_QR;
    solver.max_num_iterations = options_.max_iterations;
    solver.function_tolerance = kFunctionTolerance;
    solver.parameter_tolerance = kParameterTolerance;
    solver.num_threads = 1;  // deterministic
    solver.logging_type = ceres::SILENT;
    return solver;
  }

  void Build() {
    for (size_t p = 0; p < setup_.points.size(); ++p) {
      for (const LooseObservation& observation : setup_.points[p].observations) {
        AddObservation(observation.photo_idx, static_cast<int>(p), observation.point_in_image);
      }
    }
    for (CameraState& camera : cameras_) {
      if (camera.free) AddPriors(&camera);
    }
    FixGauge();
  }

  void AddObservation(int camera_idx, int point_idx, const Eigen::Vector2d& observed) {
    CameraState& camera = cameras_[camera_idx];
    const double inverse_sigma = 1.0 / options_.click_sigma_px;
    ceres::CostFunction* cost = nullptr;
    if (camera.orthographic) {
      cost = new ceres::AutoDiffCostFunction<Reprojection<false>, 2, 3, 2, 1, 3>(
          new Reprojection<false>{observed, camera.principal_point, inverse_sigma});
    } else {
      cost = new ceres::AutoDiffCostFunction<Reprojection<true>, 2, 3, 3, 1, 3>(
          new Reprojection<true>{observed, camera.principal_point, inverse_sigma});
    }
    const ceres::ResidualBlockId block = problem_.AddResidualBlock(
        cost, &loss_, camera.angles, camera.translation, camera.scale, points_[point_idx].data());
    observations_.push_back({camera_idx, point_idx, observed, block});
    problem_.SetParameterLowerBound(camera.scale, 0, kMinScaleFraction * camera.initial_scale);
  }

  void AddPriors(CameraState* camera) {
    const Eigen::Vector3d sigma_deg(options_.azimuth_sigma_deg, options_.elevation_sigma_deg,
                                    options_.roll_sigma_deg);
    const Eigen::Vector3d inverse_sigma = (sigma_deg * kDegree).cwiseInverse();
    problem_.AddResidualBlock(new ceres::AutoDiffCostFunction<AnglePrior, 3, 3>(
                                  new AnglePrior{camera->given_angles, inverse_sigma}),
                              nullptr, camera->angles);
    problem_.AddResidualBlock(
        new ceres::AutoDiffCostFunction<LogScalePrior, 1, 1>(
            new LogScalePrior{camera->initial_scale, 1.0 / camera->scale_sigma}),
        nullptr, camera->scale);
  }

  // Base at the origin, the first refined photo's azimuth, and the scale
  // (the top's height, else that photo's scale or depth of the origin).
  void FixGauge() {
    const int base_idx = setup_.FindPoint(kLooseBasePoint);
    if (base_idx < 0) return;  // no points at all (Check requires "base" otherwise)
    points_[base_idx] = {0.0, 0.0, 0.0};
    problem_.SetParameterBlockConstant(points_[base_idx].data());
    const int top_idx = setup_.FindPoint(kLooseTopPoint);
    const bool height_gauge = setup_.tree_height > 0 && top_idx >= 0;
    if (height_gauge) {
      points_[top_idx][2] = setup_.tree_height;
      problem_.SetManifold(points_[top_idx].data(), new ceres::SubsetManifold(3, {2}));
    }
    const auto gauge =
        std::find_if(cameras_.begin(), cameras_.end(), [](const CameraState& c) { return c.free; });
    problem_.SetManifold(gauge->angles, new ceres::SubsetManifold(3, {0}));
    if (!height_gauge && gauge->orthographic) {
      scale_fixed_ = gauge->scale;
    } else if (!height_gauge) {
      problem_.SetManifold(gauge->translation, new ceres::SubsetManifold(3, {2}));
    }
  }

  void SetCamerasConstant(bool constant) {
    for (CameraState& camera : cameras_) {
      if (!camera.free) continue;
      for (double* block : {camera.angles, camera.translation, camera.scale}) {
        if (constant || block == scale_fixed_) {
          problem_.SetParameterBlockConstant(block);
        } else {
          problem_.SetParameterBlockVariable(block);
        }
      }
    }
  }

  std::vector<double*> VariableBlocks() const {
    std::vector<double*> blocks;
    std::vector<double*> all;
    problem_.GetParameterBlocks(&all);
    for (double* block : all) {
      if (!problem_.IsParameterBlockConstant(block)) blocks.push_back(block);
    }
    return blocks;
  }

  int NumUnknowns() const {
    int count = 0;
    for (double* block : VariableBlocks()) count += problem_.ParameterBlockTangentSize(block);
    return count;
  }

  // Rank deficiency of the reprojection residuals' Jacobian (columns scaled
  // to unit length): directions only the priors determine.
  int CountWeakDirections() {
    ceres::Problem::EvaluateOptions evaluate;
    evaluate.parameter_blocks = VariableBlocks();
    for (const ObservationRef& ref : observations_) evaluate.residual_blocks.push_back(ref.block);
    evaluate.apply_loss_function = false;
    ceres::CRSMatrix crs;
    problem_.Evaluate(evaluate, nullptr, nullptr, nullptr, &crs);
    Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
    for (int row = 0; row < crs.num_rows; ++row) {
      for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) {
        jacobian(row, crs.cols[k]) = crs.values[k];
      }
    }
    for (int col = 0; col < jacobian.cols(); ++col) {
      const double norm = jacobian.col(col).norm();
      if (norm > 0) jacobian.col(col) /= norm;
    }
    const Eigen::VectorXd singular = Eigen::JacobiSVD<Eigen::MatrixXd>(jacobian).singularValues();
    int weak = static_cast<int>(jacobian.cols()) - static_cast<int>(singular.size());
    for (int k = 0; k < singular.size(); ++k) {
      weak += singular[k] < options_.weak_direction_threshold * singular[0];
    }
    return weak;
  }

  const LooseSetup& setup_;
  const ImageSet& initial_;
  const LooseRefineOptions& options_;
  std::vector<CameraState> cameras_;
  std::vector<Point> points_;
  std::vector<ObservationRef> observations_;
  std::vector<double> rms_before_;
  double* scale_fixed_ = nullptr;    // a scale block held constant for the gauge
  double robust_scale_;              // of the losses, in click sigmas
  ceres::LossFunctionWrapper loss_;  // of every reprojection residual
  ceres::Problem problem_;
};

// ---- Summary ---------------------------------------------------------------

LooseCameraChange CameraChange(const CameraState& before, const CameraState& after,
                               double rms_before, double rms_after) {
  LooseCameraChange change;
  change.name = after.name;
  change.num_points = after.num_points;
  change.angles_given_deg = after.given_angles / kDegree;
  change.angles_initial_deg = Eigen::Map<const Eigen::Vector3d>(before.angles) / kDegree;
  change.angles_refined_deg = Eigen::Map<const Eigen::Vector3d>(after.angles) / kDegree;
  change.relative_scale_change = after.scale[0] / before.scale[0] - 1.0;
  if (after.orthographic) {
    change.translation_change = std::hypot(after.translation[0] - before.translation[0],
                                           after.translation[1] - before.translation[1]);
  } else {
    change.translation_change =
        (PoseOf(after).Inverse().translation - PoseOf(before).Inverse().translation).norm();
  }
  change.rms_before_px = rms_before;
  change.rms_after_px = rms_after;
  return change;
}

void AddWarnings(const LooseProblem& problem, LooseRefineSummary* summary) {
  int num_free = 0, num_free_orthographic = 0;
  for (const CameraState& camera : problem.cameras()) {
    num_free += camera.free;
    num_free_orthographic += camera.free && camera.orthographic;
    if (!camera.free) {
      summary->warnings.push_back("photo '" + camera.name +
                                  "' has no clicked points; its camera is kept as initialised");
    } else if (camera.num_points < kMinPointsPerCamera) {
      summary->warnings.push_back("photo '" + camera.name + "' sees only " +
                                  std::to_string(camera.num_points) +
                                  " clicked point(s); its pose leans on the priors");
    }
  }
  if (num_free == 2 && num_free_orthographic == 2) {
    summary->warnings.push_back(
        "two orthographic views cannot fix the angle between them; their azimuths stay near "
        "the given values");
  }
  if (summary->num_equations < summary->num_unknowns) {
    summary->warnings.push_back("fewer equations (" + std::to_string(summary->num_equations) +
                                ") than unknowns (" + std::to_string(summary->num_unknowns) +
                                "); click more points");
  }
  if (summary->termination != "CONVERGENCE") {
    summary->warnings.push_back("the solver stopped without converging (" + summary->termination +
                                ")");
  }
  if (summary->num_weak_directions > kTiltDirections) {
    summary->warnings.push_back(std::to_string(summary->num_weak_directions - kTiltDirections) +
                                " combination(s) of the unknowns are fixed only by the priors "
                                "(beyond the world's tilt); click more points");
  }
}

// Largest error and where.
void FindWorst(const LooseSetup& setup, const LooseProblem& problem, const ImageSet& image_set,
               LooseRefineSummary* summary) {
  for (const ObservationRef& ref : problem.observations()) {
    const CameraState& camera = problem.cameras()[ref.camera];
    const double error = PixelError(image_set, camera, problem.points()[ref.point], ref.observed);
    if (error > summary->max_after_px) {
      summary->max_after_px = error;
      summary->worst_observation =
          "point '" + setup.points[ref.point].name + "' in photo '" + camera.name + "'";
    }
  }
}

}  // namespace

std::string LooseRefineSummary::BriefReport() const {
  std::ostringstream out;
  out.precision(3);
  out << "Loose refinement: ";
  if (!refined) {
    out << "not run.";
  } else {
    out << num_points << " points, " << num_observations << " clicks, " << num_unknowns
        << " unknowns; reprojection RMS " << rms_before_px << " px -> " << rms_after_px
        << " px (max " << max_after_px << " px, " << worst_observation << "); " << iterations
        << " iterations, " << termination << ", " << seconds << " s.";
    for (const LooseCameraChange& camera : cameras) {
      const Eigen::Vector3d delta = camera.angles_refined_deg - camera.angles_initial_deg;
      out << " " << camera.name << ": azimuth " << camera.angles_refined_deg.x() << " (moved "
          << delta.x() << "), elevation " << camera.angles_refined_deg.y() << " (" << delta.y()
          << "), roll " << camera.angles_refined_deg.z() << " (" << delta.z() << ") deg, scale "
          << 100.0 * camera.relative_scale_change << " %, RMS " << camera.rms_after_px << " px.";
    }
  }
  for (const std::string& warning : warnings) out << " Warning: " << warning << ".";
  return out.str();
}

LooseRefinement RefineLooseCameras(const LooseSetup& setup, const ImageSet& initial,
                                   const LooseRefineOptions& options) {
  options.Check();
  setup.Check();
  const auto start = std::chrono::steady_clock::now();
  LooseRefinement result;
  LooseRefineSummary& summary = result.summary;
  if (setup.points.empty()) {
    result.image_set = initial;
    summary.warnings.push_back("no clicked points: the cameras are the initial guess");
    return result;
  }
  LooseProblem problem(setup, initial, options);
  const std::vector<CameraState> before = problem.cameras();
  problem.Solve(&summary);
  result.image_set = ImageSetOf(initial, problem.cameras());

  summary.refined = true;
  summary.num_points = static_cast<int>(setup.points.size());
  summary.num_observations = setup.NumObservations();
  summary.num_equations = 2 * summary.num_observations;
  std::vector<double> rms_after;
  summary.rms_after_px = problem.RmsError(result.image_set, &rms_after);
  for (size_t c = 0; c < before.size(); ++c) {
    summary.cameras.push_back(
        CameraChange(before[c], problem.cameras()[c], problem.rms_before()[c], rms_after[c]));
  }
  for (size_t p = 0; p < setup.points.size(); ++p) {
    const Point& point = problem.points()[p];
    summary.points_in_world[setup.points[p].name] = Eigen::Vector3d(point[0], point[1], point[2]);
  }
  FindWorst(setup, problem, result.image_set, &summary);
  AddWarnings(problem, &summary);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace sylva
