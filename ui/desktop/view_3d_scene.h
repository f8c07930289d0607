// What the 3D views show of a project: the mesh (out/tree.obj), the
// density's voxels (out/density.vdb) as points and the skeleton
// (out/skeleton.json) as segments, read once and shared by the Embree view
// (view_3d.h) and the OpenGL view (view_3d_gl.h).
#ifndef SYLVA_UI_DESKTOP_VIEW_3D_SCENE_H_
#define SYLVA_UI_DESKTOP_VIEW_3D_SCENE_H_

#include <Eigen/Core>
#include <QColor>
#include <QString>
#include <memory>
#include <utility>
#include <vector>

#include "core/geometry/box.h"
#include "core/types/triangle_mesh.h"

namespace sylva {

class Project;

struct View3dScene {
  TriangleMesh mesh;                    // empty if there is none
  std::vector<Eigen::Vector3f> points;  // density voxels at least kPointOpacityMin opaque (world)
  std::vector<float> point_values;      // their opacities
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> skeleton;  // segments
  Box3d bounds;                                                       // of everything above
  QString status;  // what was read, and what could not be

  bool empty() const { return bounds.isEmpty(); }
};

// Reads whichever of the three files exist; a file that cannot be read is
// skipped and named in `status`. At most 40,000 voxels (evenly thinned).
std::shared_ptr<const View3dScene> LoadView3dScene(const Project& project);

// The colours both views draw the points and the skeleton in.
QColor View3dPointColor(float opacity);
QColor View3dSkeletonColor();

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_VIEW_3D_SCENE_H_
