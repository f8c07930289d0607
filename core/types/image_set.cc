#include "core/types/image_set.h"

#include <set>

#include "core/util/check.h"

namespace sylva {

const Camera& ImageSet::CameraOf(const View& view) const {
  const auto it = cameras.find(view.camera_id);
  SYLVA_CHECK(it != cameras.end())
      << "view " << view.name << " has unknown camera " << view.camera_id;
  return it->second;
}

int ImageSet::FindView(const std::string& name) const {
  for (int i = 0; i < NumViews(); ++i) {
    if (views[i].name == name) return i;
  }
  return -1;
}

bool ImageSet::Project(int view_idx, const Eigen::Vector3d& point_in_world,
                       Eigen::Vector2d* point_in_image) const {
  const View& view = views.at(view_idx);
  const Camera& camera = CameraOf(view);
  const Eigen::Vector3d point_in_cam = view.cam_from_world * point_in_world;
  if (!camera.IsInFront(point_in_cam)) return false;
  *point_in_image = camera.ImgFromCam(point_in_cam);
  return true;
}

Ray3d ImageSet::RayThroughPixel(int view_idx, const Eigen::Vector2d& point_in_image) const {
  const View& view = views.at(view_idx);
  const Ray3d ray_in_cam = CameraOf(view).CamRayFromImg(point_in_image);
  const Rigid3d world_from_cam = view.cam_from_world.Inverse();
  Ray3d ray;
  ray.origin = world_from_cam * ray_in_cam.origin;
  ray.direction = world_from_cam.rotation * ray_in_cam.direction;
  ray.t_min = ray_in_cam.t_min;
  return ray;
}

void ImageSet::Check(const std::string& source) const {
  SYLVA_CHECK_INPUT(!views.empty(), source) << "the model has no images";
  for (const auto& [camera_id, camera] : cameras) {
    camera.Check(source + " (camera " + std::to_string(camera_id) + ")");
  }
  std::set<std::string> names;
  std::set<int> ids;
  for (const View& view : views) {
    SYLVA_CHECK_INPUT(!view.name.empty(), source) << "image " << view.image_id << " has no name";
    SYLVA_CHECK_INPUT(names.insert(view.name).second, source)
        << "image name '" << view.name << "' appears twice";
    SYLVA_CHECK_INPUT(ids.insert(view.image_id).second, source)
        << "image id " << view.image_id << " appears twice";
    SYLVA_CHECK_INPUT(cameras.count(view.camera_id) == 1, source)
        << "image '" << view.name << "' refers to camera " << view.camera_id
        << ", which is not in the model";
    const bool finite = view.cam_from_world.rotation.coeffs().allFinite() &&
                        view.cam_from_world.translation.allFinite();
    SYLVA_CHECK_INPUT(finite, source) << "image '" << view.name << "' has a non-finite pose";
  }
}

}  // namespace sylva
