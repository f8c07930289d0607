// A set of registered photos: cameras (intrinsics) and views (poses), in one
// world frame. This is what registration produces and every later stage reads.
// Pixels themselves are not held here (see FloatImage); views refer to their
// photo by a relative name, as COLMAP models do ("side/30.jpg").
#ifndef SYLVA_CORE_TYPES_IMAGE_SET_H_
#define SYLVA_CORE_TYPES_IMAGE_SET_H_

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "core/geometry/rigid3.h"
#include "core/types/camera.h"

namespace sylva {

// One registered photo.
struct View {
  int image_id = 0;   // stable id (COLMAP IMAGE_ID)
  std::string name;   // photo path relative to the photo folder
  int camera_id = 0;  // key into ImageSet::cameras
  Rigid3d cam_from_world;

  Eigen::Vector3d ProjectionCenter() const { return cam_from_world.Inverse().translation; }
  Eigen::Vector3d ViewingDirection() const {
    return cam_from_world.rotation.inverse() * Eigen::Vector3d::UnitZ();
  }
};

// A sparse 3D point of a COLMAP model (optional).
struct Point3D {
  int64_t point3d_id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3i color = Eigen::Vector3i::Zero();
  double error = 0.0;
};

class ImageSet {
 public:
  std::map<int, Camera> cameras;  // by camera id
  std::vector<View> views;        // in model order (sorted by image id)
  std::vector<Point3D> points;    // may be empty

  int NumViews() const { return static_cast<int>(views.size()); }
  const Camera& CameraOf(const View& view) const;
  const Camera& CameraOf(int view_idx) const { return CameraOf(views.at(view_idx)); }

  // Index of the view with this photo name, or -1.
  int FindView(const std::string& name) const;

  // Pixel position of a world point in a view; false if it is behind a
  // pinhole camera (the position is then undefined).
  bool Project(int view_idx, const Eigen::Vector3d& point_in_world,
               Eigen::Vector2d* point_in_image) const;

  // The world ray through a pixel of a view.
  Ray3d RayThroughPixel(int view_idx, const Eigen::Vector2d& point_in_image) const;

  // Checks that every view references an existing camera, names are unique
  // and non-empty, poses are finite. Throws InputError naming `source`.
  void Check(const std::string& source) const;
};

}  // namespace sylva

#endif  // SYLVA_CORE_TYPES_IMAGE_SET_H_
