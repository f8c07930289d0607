// Which triangle of a mesh each sample of a picture sees, by rasterization:
// the same samples MeshRenderer's rays take (S x S per pixel, at image
// positions (i + (s + 0.5) / S, j + (t + 0.5) / S)), found by projecting the
// triangles instead of casting a ray per sample. For a camera without lens
// distortion a ray through a sample hits a triangle exactly when the sample
// lies in the triangle's projection, so the answer is the ray caster's up to
// samples lying on an edge (rasterization counts them inside; edges are
// evaluated the same way from both triangles that share them, so no sample
// falls between two). Nearest means: smallest depth along a perspective ray
// (geometry behind the camera is not seen), smallest z along an orthographic
// full line (geometry behind the image plane is seen).
//
// An implementation detail of MeshRenderer (mesh_renderer.cc), which falls
// back to Embree's rays where rasterization would not be exact.
#ifndef SYLVA_MESH_MESH_RASTERIZER_H_
#define SYLVA_MESH_MESH_RASTERIZER_H_

#include <Eigen/Core>
#include <vector>

#include "core/geometry/rigid3.h"
#include "core/types/camera.h"

namespace sylva {

struct RasterMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;
};

// Fills `sample_triangles` (camera.width() * S by camera.height() * S
// samples, row-major, sample (a, b) of pixel (a / S, b / S)) with the index
// of the nearest triangle each sample sees, or -1. With `nearest` false any
// triangle that covers the sample will do (coverage alone, cheaper).
// Returns false, leaving the output empty, when rasterization would not
// match the rays: a camera with lens distortion, a perspective camera with
// a triangle vertex not in front of it, or a vertex projecting too far off
// the picture for double precision.
bool RasterizeSamples(const RasterMesh& mesh, const Camera& camera, const Rigid3d& cam_from_world,
                      int samples_per_axis, bool nearest, std::vector<int>* sample_triangles);

}  // namespace sylva

#endif  // SYLVA_MESH_MESH_RASTERIZER_H_
