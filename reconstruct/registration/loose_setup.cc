#include "reconstruct/registration/loose_setup.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/util/check.h"

namespace sylva {
namespace {

// A 35-mm frame is 36 mm across its longer side.
constexpr double kFullFrameLongSideMm = 36.0;

std::string PhotoLabel(const LoosePhoto& photo) { return "photo '" + photo.name + "'"; }

void CheckPhoto(const LoosePhoto& photo, const std::string& source) {
  SYLVA_CHECK_INPUT(!photo.name.empty(), source) << "a photo has an empty name";
  const std::string label = PhotoLabel(photo);
  SYLVA_CHECK_INPUT(std::isfinite(photo.azimuth_deg), source)
      << label << ": azimuth_deg must be a finite number of degrees";
  SYLVA_CHECK_INPUT(std::abs(photo.elevation_deg) < 90, source)
      << label << ": elevation_deg must be in (-90, 90) degrees, got " << photo.elevation_deg;
  SYLVA_CHECK_INPUT(std::abs(photo.roll_deg) <= 180, source)
      << label << ": roll_deg must be in [-180, 180] degrees, got " << photo.roll_deg;
  SYLVA_CHECK_INPUT(photo.focal_length_px >= 0 && std::isfinite(photo.focal_length_px), source)
      << label << ": focal_length_px must be a positive number of pixels, got "
      << photo.focal_length_px;
  SYLVA_CHECK_INPUT(photo.focal_length_35mm >= 0 && std::isfinite(photo.focal_length_35mm), source)
      << label << ": focal_length_35mm must be a positive number of millimetres, got "
      << photo.focal_length_35mm;
  SYLVA_CHECK_INPUT(photo.focal_length_px == 0 || photo.focal_length_35mm == 0, source)
      << label << ": give focal_length_px or focal_length_35mm, not both";
  SYLVA_CHECK_INPUT(!photo.HasFocalLength() || photo.projection == LooseProjection::kPerspective,
                    source)
      << label << ": an orthographic photo has no focal length";
  SYLVA_CHECK_INPUT(photo.distance >= 0 && std::isfinite(photo.distance), source)
      << label << ": distance must be positive, got " << photo.distance;
}

void CheckPoint(const LooseSetup& setup, const LoosePoint& point) {
  const std::string& source = setup.source;
  SYLVA_CHECK_INPUT(!point.name.empty(), source) << "a point has an empty name";
  const std::string label = "point '" + point.name + "'";
  std::set<int> photos;
  for (const LooseObservation& observation : point.observations) {
    SYLVA_CHECK_INPUT(
        observation.photo_idx >= 0 && observation.photo_idx < static_cast<int>(setup.photos.size()),
        source)
        << label << ": refers to photo index " << observation.photo_idx << " of "
        << setup.photos.size();
    const std::string& photo = setup.photos[observation.photo_idx].name;
    SYLVA_CHECK_INPUT(photos.insert(observation.photo_idx).second, source)
        << label << ": seen twice in photo '" << photo << "'";
    const Eigen::Vector2d& p = observation.point_in_image;
    SYLVA_CHECK_INPUT(p.allFinite() && (p.array() >= 0).all(), source)
        << label << " in photo '" << photo << "': pixel position (" << p.x() << ", " << p.y()
        << ") must be finite and non-negative";
  }
  SYLVA_CHECK_INPUT(photos.size() >= 2, source)
      << label << ": is seen in " << photos.size()
      << " photo(s); a point must be clicked in at least 2 photos";
}

}  // namespace

std::string LooseProjectionName(LooseProjection projection) {
  return projection == LooseProjection::kOrthographic ? "orthographic" : "perspective";
}

LooseProjection ParseLooseProjection(const std::string& name, const std::string& source) {
  if (name == "orthographic") return LooseProjection::kOrthographic;
  if (name == "perspective") return LooseProjection::kPerspective;
  SYLVA_INPUT_ERROR(source) << "projection must be 'orthographic' or 'perspective', got '" << name
                            << "'";
  return LooseProjection::kPerspective;
}

double LoosePhoto::FocalLengthPx(int width, int height) const {
  if (focal_length_px > 0) return focal_length_px;
  if (focal_length_35mm > 0) {
    return focal_length_35mm * std::max(width, height) / kFullFrameLongSideMm;
  }
  return 0.0;
}

const LooseObservation* LoosePoint::Find(int photo_idx) const {
  for (const LooseObservation& observation : observations) {
    if (observation.photo_idx == photo_idx) return &observation;
  }
  return nullptr;
}

int LooseSetup::FindPhoto(const std::string& name) const {
  for (size_t i = 0; i < photos.size(); ++i) {
    if (photos[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int LooseSetup::FindPoint(const std::string& name) const {
  for (size_t i = 0; i < points.size(); ++i) {
    if (points[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int LooseSetup::NumObservations() const {
  int count = 0;
  for (const LoosePoint& point : points) count += static_cast<int>(point.observations.size());
  return count;
}

void LooseSetup::Check() const {
  SYLVA_CHECK_INPUT(photos.size() >= 2, source)
      << "loose registration needs at least 2 photos, got " << photos.size();
  SYLVA_CHECK_INPUT(tree_height >= 0 && std::isfinite(tree_height), source)
      << "tree_height must be positive, got " << tree_height;
  std::set<std::string> photo_names;
  for (const LoosePhoto& photo : photos) {
    CheckPhoto(photo, source);
    SYLVA_CHECK_INPUT(photo_names.insert(photo.name).second, source)
        << "photo '" << photo.name << "' is listed twice";
  }
  std::set<std::string> point_names;
  for (const LoosePoint& point : points) {
    CheckPoint(*this, point);
    SYLVA_CHECK_INPUT(point_names.insert(point.name).second, source)
        << "point '" << point.name << "' is listed twice";
  }
  SYLVA_CHECK_INPUT(points.empty() || FindPoint(kLooseBasePoint) >= 0, source)
      << "the points must include '" << kLooseBasePoint
      << "' (the foot of the trunk), which fixes the world origin";
}

void LooseSetup::CheckPixels(const std::vector<Eigen::Vector2i>& image_sizes) const {
  SYLVA_CHECK(image_sizes.size() == photos.size()) << "one image size per photo";
  for (const LoosePoint& point : points) {
    for (const LooseObservation& observation : point.observations) {
      const Eigen::Vector2i& size = image_sizes.at(observation.photo_idx);
      const Eigen::Vector2d& p = observation.point_in_image;
      SYLVA_CHECK_INPUT(p.x() <= size.x() && p.y() <= size.y(), source)
          << "point '" << point.name << "' in photo '" << photos[observation.photo_idx].name
          << "': pixel position (" << p.x() << ", " << p.y() << ") is outside the " << size.x()
          << "x" << size.y() << " image";
    }
  }
}

}  // namespace sylva
