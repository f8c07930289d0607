// Initial cameras of loose registration (see loose_registration.h); the
// Ceres refinement is in loose_refinement.cc.
#include "reconstruct/registration/loose_registration.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/util/check.h"
#include "reconstruct/registration/loose_angles.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;

// A photo's base and top pixels and where they came from.
struct Anchors {
  Eigen::Vector2d base = Eigen::Vector2d::Zero();
  Eigen::Vector2d top = Eigen::Vector2d::Zero();
  LooseAnchorSource base_source = LooseAnchorSource::kGuess;
  LooseAnchorSource top_source = LooseAnchorSource::kGuess;
};

// Foreground pixel count per row of a matte.
std::vector<int> ForegroundPerRow(const FloatImage& matte, float threshold) {
  std::vector<int> counts(matte.height(), 0);
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) counts[y] += matte.at(x, y) >= threshold;
  }
  return counts;
}

// Mean x (pixel centres) of the foreground in rows [y0, y1].
double ForegroundCentroidX(const FloatImage& matte, float threshold, int y0, int y1) {
  double sum = 0.0;
  int count = 0;
  for (int y = y0; y <= y1; ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      if (matte.at(x, y) >= threshold) {
        sum += x + 0.5;
        ++count;
      }
    }
  }
  return count > 0 ? sum / count : 0.5 * matte.width();
}

// The base (bottom edge of the lowest tree row, at the foreground centroid of
// the lowest band of rows) and the top (top edge of the highest tree row, at
// its centroid) of the tree in a matte; false if the matte has no tree rows.
bool MatteAnchors(const FloatImage& matte, const LooseInitOptions& options, Anchors* anchors) {
  const float threshold = static_cast<float>(options.matte_threshold);
  const std::vector<int> counts = ForegroundPerRow(matte, threshold);
  const int min_count =
      std::max(1, static_cast<int>(std::ceil(options.min_row_fraction * matte.width())));
  int top_row = -1, bottom_row = -1;
  for (int y = 0; y < matte.height(); ++y) {
    if (counts[y] < min_count) continue;
    if (top_row < 0) top_row = y;
    bottom_row = y;
  }
  if (top_row < 0) return false;
  const int band = std::max(
      1, static_cast<int>(std::lround(options.base_band_fraction * (bottom_row + 1 - top_row))));
  anchors->base = Eigen::Vector2d(
      ForegroundCentroidX(matte, threshold, std::max(top_row, bottom_row - band + 1), bottom_row),
      bottom_row + 1.0);
  anchors->top = Eigen::Vector2d(ForegroundCentroidX(matte, threshold, top_row, top_row), top_row);
  anchors->base_source = anchors->top_source = LooseAnchorSource::kMatte;
  return true;
}

// Clicked base / top of photo `photo_idx`, overriding `anchors`.
void ClickedAnchors(const LooseSetup& setup, int photo_idx, Anchors* anchors) {
  const int base_idx = setup.FindPoint(kLooseBasePoint);
  const int top_idx = setup.FindPoint(kLooseTopPoint);
  if (base_idx >= 0) {
    if (const LooseObservation* base = setup.points[base_idx].Find(photo_idx)) {
      anchors->base = base->point_in_image;
      anchors->base_source = LooseAnchorSource::kClicked;
    }
  }
  if (top_idx >= 0) {
    if (const LooseObservation* top = setup.points[top_idx].Find(photo_idx)) {
      anchors->top = top->point_in_image;
      anchors->top_source = LooseAnchorSource::kClicked;
    }
  }
}

Anchors FindAnchors(const LooseSetup& setup, int photo_idx, const Eigen::Vector2i& size,
                    const FloatImage* matte, const LooseInitOptions& options) {
  Anchors anchors;
  const double half_span = 0.5 * options.fallback_fill * size.y();
  anchors.base = Eigen::Vector2d(0.5 * size.x(), 0.5 * size.y() + half_span);
  anchors.top = Eigen::Vector2d(0.5 * size.x(), 0.5 * size.y() - half_span);
  if (matte != nullptr) MatteAnchors(*matte, options, &anchors);
  ClickedAnchors(setup, photo_idx, &anchors);
  return anchors;
}

// The image direction in which the world's +Z points (unit), and the length
// of +Z's image-plane projection (cos of the elevation).
Eigen::Vector2d ImageUp(const Eigen::Matrix3d& cam_from_world, double* length) {
  const Eigen::Vector2d up = cam_from_world.col(2).head<2>();
  *length = up.norm();
  return up / *length;
}

struct InitialPose {
  Rigid3d cam_from_world;
  Camera camera;
  double scale = 0.0;
  double distance = 0.0;
};

InitialPose OrthographicPose(const LoosePhoto& photo, const Eigen::Vector2i& size,
                             const Anchors& anchors, const Eigen::Quaterniond& rotation,
                             double height, const LooseInitOptions& options, double pixel_height) {
  double up_length = 0.0;
  ImageUp(rotation.toRotationMatrix(), &up_length);
  InitialPose pose;
  pose.scale = pixel_height / (height * up_length);
  const Eigen::Vector2d center = 0.5 * size.cast<double>();
  const Eigen::Vector2d offset = (anchors.base - center) / pose.scale;
  pose.distance =
      photo.distance > 0 ? photo.distance : options.orthographic_distance_heights * height;
  pose.cam_from_world = Rigid3d(rotation, Eigen::Vector3d(offset.x(), offset.y(), pose.distance));
  pose.camera = Camera::Orthographic(size.x(), size.y(), pose.scale);
  return pose;
}

// Depth d of the base such that a vertical tree of `height` standing on it
// has its top's image position along the image's up direction where it was
// found: with the base at d b (b = normalised base ray) and top at
// d b + height R e_z, solve for d along the up direction (linear in d).
double PerspectiveBaseDepth(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& base_ray,
                            const Eigen::Vector2d& top_normalized, double height) {
  double up_length = 0.0;
  const Eigen::Vector2d up = ImageUp(rotation, &up_length);
  const Eigen::Vector3d top_offset = height * rotation.col(2);
  const double numerator = (top_normalized * top_offset.z() - top_offset.head<2>()).dot(up);
  const double denominator = (base_ray.head<2>() - top_normalized).dot(up);
  return numerator / denominator;
}

InitialPose PerspectivePose(const LoosePhoto& photo, const Eigen::Vector2i& size,
                            const Anchors& anchors, const Eigen::Quaterniond& rotation,
                            double height, const LooseInitOptions& options, double pixel_height,
                            std::vector<std::string>* warnings) {
  const Eigen::Matrix3d r = rotation.toRotationMatrix();
  double up_length = 0.0;
  ImageUp(r, &up_length);
  InitialPose pose;
  pose.scale = photo.FocalLengthPx(size.x(), size.y());
  if (pose.scale <= 0 && photo.distance > 0) {
    // A tree of height H at horizontal distance D spans about f H cos(e) / D pixels.
    pose.scale = photo.distance * pixel_height / (height * up_length);
  }
  if (pose.scale <= 0) pose.scale = options.default_focal_factor * std::max(size.x(), size.y());
  const Eigen::Vector2d center = 0.5 * size.cast<double>();
  const Eigen::Vector3d base_ray(((anchors.base - center) / pose.scale).homogeneous());
  const Eigen::Vector2d top_normalized = (anchors.top - center) / pose.scale;
  double depth = PerspectiveBaseDepth(r, base_ray, top_normalized, height);
  if (!(depth > 0 && depth + height * r(2, 2) > 0 && std::isfinite(depth))) {
    // The top's pixel is unreachable with this focal length (the tree would
    // have to stand behind the camera): use the far-away approximation.
    depth = pose.scale * height * up_length / pixel_height;
    warnings->push_back("photo '" + photo.name +
                        "': base and top are inconsistent with the focal length; the camera "
                        "distance is a rough guess");
  }
  pose.distance = depth;
  pose.cam_from_world = Rigid3d(rotation, depth * base_ray);
  pose.camera = Camera::Pinhole(size.x(), size.y(), pose.scale);
  return pose;
}

// Checks the mattes given for the set-up's photos; returns one pointer per
// photo (nullptr: no matte).
std::vector<const FloatImage*> PhotoMattes(const LooseSetup& setup,
                                           const std::vector<Eigen::Vector2i>& sizes,
                                           const std::map<std::string, FloatImage>& mattes) {
  std::vector<const FloatImage*> result(setup.photos.size(), nullptr);
  for (size_t i = 0; i < setup.photos.size(); ++i) {
    const auto it = mattes.find(setup.photos[i].name);
    if (it == mattes.end() || it->second.empty()) continue;
    const FloatImage& matte = it->second;
    SYLVA_CHECK_INPUT(
        matte.channels() == 1 && matte.width() == sizes[i].x() && matte.height() == sizes[i].y(),
        setup.source)
        << "the matte of photo '" << setup.photos[i].name << "' is " << matte.width() << "x"
        << matte.height() << " with " << matte.channels() << " channel(s); expected "
        << sizes[i].x() << "x" << sizes[i].y() << " with 1";
    result[i] = &matte;
  }
  return result;
}

std::vector<Eigen::Vector2i> PhotoSizes(const LooseSetup& setup,
                                        const std::map<std::string, Eigen::Vector2i>& sizes) {
  std::vector<Eigen::Vector2i> result;
  for (const LoosePhoto& photo : setup.photos) {
    const auto it = sizes.find(photo.name);
    SYLVA_CHECK_INPUT(it != sizes.end(), setup.source)
        << "photo '" << photo.name << "' is not among the photos";
    SYLVA_CHECK_INPUT((it->second.array() > 0).all(), setup.source)
        << "photo '" << photo.name << "' has an empty image";
    result.push_back(it->second);
  }
  return result;
}

// The tree's extent in the photo along the image's up direction, in pixels;
// throws if the top is not above the base.
double PixelHeight(const LooseSetup& setup, const LoosePhoto& photo, const Anchors& anchors,
                   const Eigen::Quaterniond& rotation) {
  double up_length = 0.0;
  const Eigen::Vector2d up = ImageUp(rotation.toRotationMatrix(), &up_length);
  const double pixel_height = (anchors.top - anchors.base).dot(up);
  SYLVA_CHECK_INPUT(pixel_height > 0, setup.source)
      << "photo '" << photo.name << "': the top (" << anchors.top.x() << ", " << anchors.top.y()
      << ", " << LooseAnchorSourceName(anchors.top_source) << ") is not above the base ("
      << anchors.base.x() << ", " << anchors.base.y() << ", "
      << LooseAnchorSourceName(anchors.base_source) << ") for the given elevation and roll";
  return pixel_height;
}

}  // namespace

Eigen::Quaterniond LooseCamFromWorld(double azimuth_deg, double elevation_deg, double roll_deg) {
  const double angles[3] = {azimuth_deg * kDegree, elevation_deg * kDegree, roll_deg * kDegree};
  double r[9];
  LooseRotationFromAngles(angles, r);
  const Eigen::Matrix3d rotation =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r);
  return Eigen::Quaterniond(rotation).normalized();
}

Eigen::Vector3d LooseAnglesDeg(const Eigen::Quaterniond& cam_from_world) {
  const Eigen::Matrix3d r = cam_from_world.toRotationMatrix();
  const Eigen::Vector3d x = r.row(0), z = r.row(2);
  const double azimuth = std::atan2(-z.y(), -z.x());
  const double elevation = std::asin(std::clamp(-z.z(), -1.0, 1.0));
  const Eigen::Vector3d x0(-std::sin(azimuth), std::cos(azimuth), 0.0);
  const Eigen::Vector3d y0 = z.cross(x0);
  const double roll = std::atan2(x.dot(y0), x.dot(x0));
  return Eigen::Vector3d(azimuth, elevation, roll) / kDegree;
}

std::string LooseAnchorSourceName(LooseAnchorSource source) {
  switch (source) {
    case LooseAnchorSource::kClicked:
      return "clicked";
    case LooseAnchorSource::kMatte:
      return "matte";
    default:
      return "guess";
  }
}

std::string LooseInitSummary::BriefReport() const {
  std::ostringstream out;
  out << "Loose cameras: " << views.size() << " photos, tree height " << tree_height << " " << units
      << (height_known ? "" : " (assumed)") << ".";
  for (const LooseInitView& view : views) {
    out << " " << view.name << ": base " << LooseAnchorSourceName(view.base_source) << ", top "
        << LooseAnchorSourceName(view.top_source) << ", "
        << (view.distance > 0 ? "focal " : "scale ") << view.scale;
    if (view.distance > 0) out << " px, distance " << view.distance;
    out << ".";
  }
  for (const std::string& warning : warnings) out << " Warning: " << warning << ".";
  return out.str();
}

ImageSet InitialLooseCameras(const LooseSetup& setup,
                             const std::map<std::string, Eigen::Vector2i>& image_sizes,
                             const std::map<std::string, FloatImage>& mattes,
                             const LooseInitOptions& options, LooseInitSummary* summary) {
  options.Check();
  setup.Check();
  const std::vector<Eigen::Vector2i> sizes = PhotoSizes(setup, image_sizes);
  setup.CheckPixels(sizes);
  const std::vector<const FloatImage*> photo_mattes = PhotoMattes(setup, sizes, mattes);
  LooseInitSummary local_summary;
  if (summary == nullptr) summary = &local_summary;
  *summary = LooseInitSummary();
  summary->height_known = setup.tree_height > 0;
  summary->tree_height = summary->height_known ? setup.tree_height : options.assumed_tree_height;
  summary->units = summary->height_known ? setup.units : "arbitrary";

  ImageSet image_set;
  for (size_t i = 0; i < setup.photos.size(); ++i) {
    const LoosePhoto& photo = setup.photos[i];
    const Anchors anchors =
        FindAnchors(setup, static_cast<int>(i), sizes[i], photo_mattes[i], options);
    for (const auto& [source, what] :
         {std::make_pair(anchors.base_source, "base"), std::make_pair(anchors.top_source, "top")}) {
      if (source != LooseAnchorSource::kGuess) continue;
      summary->warnings.push_back("photo '" + photo.name + "': the tree's " + what +
                                  " is neither clicked nor in a usable matte; guessed as if the "
                                  "tree filled the middle of the photo");
    }
    const Eigen::Quaterniond rotation =
        LooseCamFromWorld(photo.azimuth_deg, photo.elevation_deg, photo.roll_deg);
    const double pixel_height = PixelHeight(setup, photo, anchors, rotation);
    const InitialPose pose =
        photo.projection == LooseProjection::kOrthographic
            ? OrthographicPose(photo, sizes[i], anchors, rotation, summary->tree_height, options,
                               pixel_height)
            : PerspectivePose(photo, sizes[i], anchors, rotation, summary->tree_height, options,
                              pixel_height, &summary->warnings);
    const int id = static_cast<int>(i) + 1;
    image_set.cameras.emplace(id, pose.camera);
    View view;
    view.image_id = id;
    view.name = photo.name;
    view.camera_id = id;
    view.cam_from_world = pose.cam_from_world;
    image_set.views.push_back(view);
    const bool perspective = photo.projection == LooseProjection::kPerspective;
    summary->views.push_back({photo.name, anchors.base_source, anchors.top_source, anchors.base,
                              anchors.top, pose.scale, perspective ? pose.distance : 0.0});
  }
  return image_set;
}

}  // namespace sylva
