// Ray-cast rendering of triangle meshes through sylva's camera models:
// coverage (silhouette) images and simply shaded RGBA images.
//
// Every pixel is sampled by S x S stratified rays, at the image positions
// (i + (s + 0.5) / S, j + (t + 0.5) / S) for pixel (col i, row j) and
// s, t = 0..S-1 (COLMAP's convention: the pixel centre is (i + 0.5, j + 0.5)).
// Rays come from Camera::CamRayFromImg, so distortion is honoured exactly;
// orthographic rays are full lines (geometry behind the image plane is seen).
// A pixel's coverage is the fraction of its rays that hit the mesh, so the
// rendered mattes are exact up to the sampling resolution of 1 / S^2.
//
// For a camera without lens distortion the samples are found by rasterizing
// the triangles (mesh_rasterizer.h), which gives what the rays would (up to
// samples exactly on an edge) at a fraction of their cost; with distortion,
// or a perspective camera with geometry beside or behind it, rays are cast.
//
// Used to render the synthetic ground-truth photos and mattes, and to render
// reconstructed meshes for silhouette fidelity reports. Embree does the ray
// casting; it stays an implementation detail of mesh_renderer.cc.
#ifndef SYLVA_MESH_MESH_RENDERER_H_
#define SYLVA_MESH_MESH_RENDERER_H_

#include <Eigen/Core>
#include <memory>

#include "core/geometry/rigid3.h"
#include "core/types/camera.h"
#include "core/types/float_image.h"
#include "core/types/triangle_mesh.h"

namespace sylva {

// How the samples are found: kAuto rasterizes where that is exact (see
// above) and casts rays elsewhere; kRayCast always casts rays (tests and
// benchmarks compare the two).
enum class MeshRenderMethod { kAuto, kRayCast };

struct MeshRenderOptions {
  // Rays per pixel along each image axis (S); S x S rays per pixel. >= 1.
  int samples_per_axis = 4;
  // Direction towards the (directional) light, in world coordinates; need not
  // be unit length but must be non-zero. Default: from above, slightly front.
  Eigen::Vector3f light_direction = Eigen::Vector3f(0.4f, -0.3f, 0.85f);
  // Fraction of the diffuse colour seen on faces turned away from the light,
  // in [0, 1]. Shading is ambient + (1 - ambient) |n . l| (double-sided).
  float ambient = 0.35f;
  MeshRenderMethod method = MeshRenderMethod::kAuto;

  // Throws InputError naming the violated constraint.
  void Check() const;
};

class MeshRenderer {
 public:
  using Options = MeshRenderOptions;

  // Builds the acceleration structure once (copies the mesh's geometry and
  // materials). Throws Error if the mesh fails TriangleMesh::Check().
  explicit MeshRenderer(const TriangleMesh& mesh);
  ~MeshRenderer();
  MeshRenderer(MeshRenderer&&) noexcept;
  MeshRenderer& operator=(MeshRenderer&&) noexcept;
  MeshRenderer(const MeshRenderer&) = delete;
  MeshRenderer& operator=(const MeshRenderer&) = delete;

  // Straight-alpha RGBA image of camera.width() x camera.height() pixels:
  // colour = mean shaded colour of the pixel's rays that hit (Lambert on the
  // triangle material's diffuse colour, lit from both sides), 0 where no ray
  // hits; alpha = fraction of the rays that hit. Parallel over rows (TBB);
  // the output is deterministic. Const and thread-safe.
  FloatImage RenderRgba(const Camera& camera, const Rigid3d& cam_from_world,
                        const Options& options) const;

  // One-channel coverage (alpha) image with the same sampling as RenderRgba.
  FloatImage RenderCoverage(const Camera& camera, const Rigid3d& cam_from_world,
                            int samples_per_axis,
                            MeshRenderMethod method = MeshRenderMethod::kAuto) const;

  // The coverage image of RenderCoverage(camera, cam_from_world, S) and, from
  // the same samples, a shaded picture `picture_scale` times as large per
  // axis with S / picture_scale rays per pixel per axis: RenderRgba through
  // the camera scaled by picture_scale (its samples are the coverage's).
  // picture_scale must divide S; 0 = no picture. One pass where the mesh is
  // rasterized; shading options' samples_per_axis is not used.
  struct CoverageAndRgba {
    FloatImage coverage, rgba;
  };
  CoverageAndRgba RenderCoverageAndRgba(const Camera& camera, const Rigid3d& cam_from_world,
                                        int samples_per_axis, int picture_scale,
                                        const Options& shading) const;

  // Distance along a world ray to the first hit at t >= ray.t_min (for a
  // full line, t_min = -inf, the hit nearest to its far-behind end), or +inf
  // if there is none. For point queries and tests; thread-safe.
  double CastRay(const Ray3d& ray_in_world) const;

  int NumTriangles() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sylva

#endif  // SYLVA_MESH_MESH_RENDERER_H_
