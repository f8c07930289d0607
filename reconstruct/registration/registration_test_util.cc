#include "reconstruct/registration/registration_test_util.h"

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {

PoseErrors ComparePoses(const ImageSet& estimate, const ImageSet& truth) {
  std::vector<Eigen::Vector3d> estimated_centres, true_centres;
  std::vector<const View*> true_views;
  for (const View& view : estimate.views) {
    const int truth_idx = truth.FindView(view.name);
    SYLVA_CHECK(truth_idx >= 0) << "view '" << view.name << "' is not in the reference";
    true_views.push_back(&truth.views[truth_idx]);
    estimated_centres.push_back(view.ProjectionCenter());
    true_centres.push_back(true_views.back()->ProjectionCenter());
  }
  PoseErrors errors;
  errors.truth_from_estimate = EstimateSim3(estimated_centres, true_centres);
  for (size_t i = 0; i < estimate.views.size(); ++i) {
    const Rigid3d aligned =
        errors.truth_from_estimate.TransformPose(estimate.views[i].cam_from_world);
    errors.rotation_degrees.push_back(
        aligned.rotation.angularDistance(true_views[i]->cam_from_world.rotation) * 180 / M_PI);
    errors.position.push_back((aligned.Inverse().translation - true_centres[i]).norm());
  }
  return errors;
}

double Max(const std::vector<double>& values) {
  SYLVA_CHECK(!values.empty());
  return *std::max_element(values.begin(), values.end());
}

std::vector<std::string> SortedFileNames(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.is_regular_file()) names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

FloatImage RomiMatte(const FloatImage& photo) {
  constexpr float kMinBrightness = 95.0f / 255;
  constexpr float kMaxRedOverBlue = 60.0f / 255;
  SYLVA_CHECK(photo.channels() >= 3) << "an RGB photo is needed";
  FloatImage matte(photo.width(), photo.height(), 1);
  for (int y = 0; y < photo.height(); ++y) {
    for (int x = 0; x < photo.width(); ++x) {
      const float r = photo.at(x, y, 0), g = photo.at(x, y, 1), b = photo.at(x, y, 2);
      const bool bright = std::min({r, g, b}) > kMinBrightness;
      matte.at(x, y) = bright && r - b <= kMaxRedOverBlue ? 1.0f : 0.0f;
    }
  }
  return matte;
}

}  // namespace sylva
