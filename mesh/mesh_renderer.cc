#include "mesh/mesh_renderer.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "core/geometry/box.h"
#include "core/util/check.h"
#include "mesh/embree_util.h"
#include "mesh/mesh_rasterizer.h"

namespace sylva {
namespace {

// Rays start where they enter the mesh bounds padded by this fraction of
// their diagonal (plus this much in world units), so float rounding of the
// moved origin cannot lose a hit.
constexpr double kBoundsPadding = 1e-3;

struct Hit {
  double t = 0.0;  // along the ray, from its original origin
  int triangle_idx = -1;
  Eigen::Vector3f normal;  // geometric normal, not normalized
};

// The image positions of the S x S stratified samples of pixel (col, row).
Eigen::Vector2d SampleInPixel(int col, int row, int s, int t, int samples_per_axis) {
  const double step = 1.0 / samples_per_axis;
  return Eigen::Vector2d(col + (s + 0.5) * step, row + (t + 0.5) * step);
}

// The undistorted points (Camera::CamFromImg) of every sample of every
// pixel of a camera with lens distortion, whose Newton iterations cost more
// than the rest of a sample's ray. Views that share the camera (usually
// every view of a photo set, in both of the report's renders) share it.
struct SampleTable {
  Camera camera;
  int samples_per_axis = 0;
  std::vector<Eigen::Vector2d> points;  // (row * width + col) * S^2 + t * S + s

  bool Serves(const Camera& other, int samples) const {
    return samples == samples_per_axis && other.model() == camera.model() &&
           other.width() == camera.width() && other.height() == camera.height() &&
           other.params() == camera.params();
  }
};

// Tables hold at most this many samples (16 bytes each), and a renderer
// keeps this many; a larger image traces its samples directly.
constexpr int64_t kMaxTableSamples = int64_t{1} << 21;
constexpr size_t kMaxTables = 2;
// Cameras (keys alone) remembered from a single render, the oldest forgotten.
constexpr size_t kMaxSeenOnce = 8;

// Pixels [x0, x1) x [y0, y1).
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// Samples along each edge of a distorted camera's rectangle (and per axis
// inside it) whose images bound the rectangle's image.
constexpr int kOutlineSamples = 64;
constexpr int kInsideSamples = 16;

// The pixels whose sample rays may meet `box`; all others miss it. A ray
// meets the box only through the box's projection onto the camera's z = 1
// plane (an orthographic camera's xy plane), which lies in the rectangle Q
// around its corners' projections, all in front of the camera (else every
// pixel may see it). Without distortion Q's image is a rectangle; with
// distortion, a sample whose undistorted point lies outside Q lies outside
// Q's distorted image, whose bounds are taken from its outline (and a grid
// inside, should the distortion fold) sampled densely, widened by the
// largest step between outline samples and a pixel.
PixelRect ReachablePixels(const Camera& camera, const Rigid3d& cam_from_world, const Box3d& box) {
  const PixelRect whole{0, 0, camera.width(), camera.height()};
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d p = cam_from_world * box.corner(static_cast<Box3d::CornerType>(corner));
    if (!camera.IsOrthographic() && !(p.z() > 0)) return whole;
    const Eigen::Vector2d q =
        camera.IsOrthographic() ? p.head<2>() : Eigen::Vector2d(p.head<2>() / p.z());
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  if (!lo.allFinite() || !hi.allFinite()) return whole;
  // The image of a point of the plane (ImgFromCam divides by z = 1, or
  // ignores it for an orthographic camera).
  const auto image_of = [&camera](double u, double v) {
    return camera.ImgFromCam(Eigen::Vector3d(u, v, 1.0));
  };
  Eigen::Vector2d image_lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d image_hi = -image_lo;
  const auto add = [&](const Eigen::Vector2d& point) {
    image_lo = image_lo.cwiseMin(point);
    image_hi = image_hi.cwiseMax(point);
  };
  double margin = 1.0;
  if (camera.IsOrthographic() || !camera.HasDistortion()) {
    add(image_of(lo.x(), lo.y()));
    add(image_of(hi.x(), hi.y()));
  } else {
    const std::array<Eigen::Vector2d, 5> outline = {lo, Eigen::Vector2d(hi.x(), lo.y()), hi,
                                                    Eigen::Vector2d(lo.x(), hi.y()), lo};
    for (int edge = 0; edge < 4; ++edge) {
      Eigen::Vector2d previous = image_of(outline[edge].x(), outline[edge].y());
      for (int k = 1; k <= kOutlineSamples; ++k) {
        const Eigen::Vector2d q =
            outline[edge] + (outline[edge + 1] - outline[edge]) * k / kOutlineSamples;
        const Eigen::Vector2d point = image_of(q.x(), q.y());
        add(point);
        margin = std::max(margin, 1.0 + (point - previous).norm());
        previous = point;
      }
    }
    for (int j = 0; j <= kInsideSamples; ++j) {
      for (int i = 0; i <= kInsideSamples; ++i) {
        add(image_of(lo.x() + (hi.x() - lo.x()) * i / kInsideSamples,
                     lo.y() + (hi.y() - lo.y()) * j / kInsideSamples));
      }
    }
  }
  if (!image_lo.allFinite() || !image_hi.allFinite()) return whole;
  const auto clamp = [](double value, int size) {
    return static_cast<int>(std::clamp(value, 0.0, static_cast<double>(size)));
  };
  PixelRect rect;
  rect.x0 = clamp(std::floor(image_lo.x() - margin), camera.width());
  rect.y0 = clamp(std::floor(image_lo.y() - margin), camera.height());
  rect.x1 = clamp(std::floor(image_hi.x() + margin) + 1, camera.width());
  rect.y1 = clamp(std::floor(image_hi.y() + margin) + 1, camera.height());
  return rect;
}

bool HitFromRayHit(const RTCRayHit& ray_hit, double t_start, Hit* hit) {
  if (ray_hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit->t = t_start + ray_hit.ray.tfar;
  hit->triangle_idx = static_cast<int>(ray_hit.hit.primID);
  hit->normal = Eigen::Vector3f(ray_hit.hit.Ng_x, ray_hit.hit.Ng_y, ray_hit.hit.Ng_z);
  return true;
}

}  // namespace

void MeshRenderOptions::Check() const {
  SYLVA_CHECK_INPUT(samples_per_axis >= 1, "MeshRenderOptions.samples_per_axis")
      << "must be >= 1, got " << samples_per_axis;
  SYLVA_CHECK_INPUT(light_direction.allFinite() && light_direction.norm() > 0,
                    "MeshRenderOptions.light_direction")
      << "must be a finite, non-zero vector";
  SYLVA_CHECK_INPUT(ambient >= 0 && ambient <= 1, "MeshRenderOptions.ambient")
      << "must be in [0, 1], got " << ambient;
}

class MeshRenderer::Impl {
 public:
  explicit Impl(const TriangleMesh& mesh);
  ~Impl();
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  // First hit of a world ray at t >= ray.t_min; false if none.
  bool Intersect(const Ray3d& ray, Hit* hit) const;
  // The Embree ray for a world ray, and the offset of its origin along it.
  RTCRayHit MakeRayHit(const Ray3d& ray, double* t_start) const;

  // Renders `channels` channels; `shade(hit, pixel)` adds one hit's colour to
  // the pixel's first channels - 1 values, the last channel is coverage. One
  // channel (coverage alone) needs no hit's place: any hit will do, which
  // Embree finds sooner than the first (rtcOccluded, as for shadow rays).
  using ShadeFn = std::function<void(const Hit&, float*)>;
  FloatImage Render(const Camera& camera, const Rigid3d& cam_from_world, int samples_per_axis,
                    int channels, MeshRenderMethod method, const ShadeFn& shade) const;

  // RasterizeSamples on this mesh (false where it would not be exact).
  bool Rasterize(const Camera& camera, const Rigid3d& cam_from_world, int samples_per_axis,
                 bool nearest, std::vector<int>* sample_triangles) const {
    return RasterizeSamples(raster_mesh_, camera, cam_from_world, samples_per_axis, nearest,
                            sample_triangles);
  }
  // The pixels from rasterized samples (RasterizeSamples' layout), S x S
  // samples per pixel; the image's width times S is the samples' width.
  void ResolveSamples(const std::vector<int>& sample_triangles, int samples_per_axis,
                      const ShadeFn& shade, FloatImage* image) const;

  // Lambert on the triangle's diffuse colour, lit from both sides.
  ShadeFn Lambert(const MeshRenderOptions& options) const;

  const Eigen::Vector3f& ColorOf(int triangle_idx) const {
    return material_colors_[triangle_materials_[triangle_idx]];
  }
  int NumTriangles() const { return static_cast<int>(triangle_materials_.size()); }

 private:
  // The Embree scene of the mesh, built once on first use (thread-safe).
  RTCScene Scene() const;
  void AddGeometry() const;
  // The rays of one image row and where each starts along its world ray;
  // reused from row to row.
  struct RowBuffers {
    std::vector<RTCRayHit> ray_hits;
    std::vector<double> t_starts;
    std::vector<RTCRay> rays;  // coverage alone
  };
  // The pixels of row `row` in columns [x0, x1).
  void RenderRow(const Camera& camera, const SampleTable* table, const Rigid3d& world_from_cam,
                 int samples_per_axis, int row, int x0, int x1, const ShadeFn& shade,
                 RowBuffers* buffers, FloatImage* image) const;
  // Averages the traced rays of one row's columns [x0, x1) (`samples`
  // consecutive rays per pixel).
  static void CoverRow(const RowBuffers& buffers, int samples, int row, int x0, int x1,
                       FloatImage* image);
  static void ShadeRow(const RowBuffers& buffers, int samples, int row, int x0, int x1,
                       const ShadeFn& shade, FloatImage* image);

  // The sample table for a camera with lens distortion, or null: built at
  // the second render with that camera and samples (a renderer used once
  // does not pay for the pixels its view does not reach), kept for the
  // next ones. Thread-safe.
  std::shared_ptr<const SampleTable> TableFor(const Camera& camera, int samples_per_axis) const;

  mutable std::mutex tables_mutex_;
  mutable std::vector<std::shared_ptr<const SampleTable>> tables_;  // newest last
  mutable std::vector<SampleTable> seen_once_;                      // keys only (no points)
  mutable std::once_flag scene_built_;
  mutable RTCDevice device_ = nullptr;
  mutable RTCScene scene_ = nullptr;
  std::vector<int> triangle_materials_;
  std::vector<Eigen::Vector3f> material_colors_;
  RasterMesh raster_mesh_;
  std::vector<Eigen::Vector3f> triangle_normals_;  // geometric, as Embree's
  Box3d padded_bounds_;                            // mesh bounds, padded (empty for an empty mesh)
};

MeshRenderer::Impl::Impl(const TriangleMesh& mesh) {
  mesh.Check();
  triangle_materials_ = mesh.triangle_materials;
  for (const Material& material : mesh.materials)
    material_colors_.push_back(material.diffuse_color);
  raster_mesh_.vertices = mesh.vertices;
  raster_mesh_.triangles = mesh.triangles;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3f& v0 = mesh.vertices[t[0]];
    triangle_normals_.push_back((v0 - mesh.vertices[t[1]]).cross(mesh.vertices[t[2]] - v0));
  }
  if (mesh.NumVertices() > 0) {
    const Box3d bounds = mesh.Bounds();
    const double pad = kBoundsPadding * bounds.diagonal().norm() + kBoundsPadding;
    padded_bounds_ = Box3d(bounds.min().array() - pad, bounds.max().array() + pad);
  }
}

RTCScene MeshRenderer::Impl::Scene() const {
  // Built at the first ray: rasterized pictures need none.
  std::call_once(scene_built_, [this] {
    device_ = rtcNewDevice(nullptr);
    SYLVA_CHECK(device_ != nullptr) << "cannot create an Embree device";
    scene_ = rtcNewScene(device_);
    // Robust traversal: no cracks between triangles sharing an edge, so a
    // tessellated surface's coverage is exact.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    if (NumTriangles() > 0) AddGeometry();
    rtcCommitScene(scene_);
    CheckEmbreeDevice(device_, "building the scene");
  });
  return scene_;
}

MeshRenderer::Impl::~Impl() {
  if (scene_ != nullptr) rtcReleaseScene(scene_);
  if (device_ != nullptr) rtcReleaseDevice(device_);
}

void MeshRenderer::Impl::AddGeometry() const {
  const RasterMesh& mesh = raster_mesh_;
  RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               mesh.vertices.size()));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), mesh.triangles.size()));
  CheckEmbreeDevice(device_, "allocating geometry buffers");
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    for (int k = 0; k < 3; ++k) vertices[3 * v + k] = mesh.vertices[v][k];
  }
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_, geometry);
  rtcReleaseGeometry(geometry);
}

RTCRayHit MeshRenderer::Impl::MakeRayHit(const Ray3d& ray, double* t_start) const {
  // Embree needs tnear >= 0, and a full line (t_min = -inf) has no start:
  // clip the ray to the (padded) mesh bounds and start it there. Rays that
  // miss the bounds are made inactive (tnear > tfar), which Embree skips.
  double t_enter = 0.0, t_exit = 0.0;
  const bool inside = ClipRayToBox(ray, padded_bounds_, &t_enter, &t_exit);
  *t_start = inside ? t_enter : 0.0;
  const Eigen::Vector3d origin = ray.origin + *t_start * ray.direction;
  return EmbreeRayHit(origin.cast<float>(), ray.direction.cast<float>(), inside ? 0.0f : 1.0f,
                      inside ? std::numeric_limits<float>::infinity() : 0.0f);
}

bool MeshRenderer::Impl::Intersect(const Ray3d& ray, Hit* hit) const {
  double t_start = 0.0;
  RTCRayHit ray_hit = MakeRayHit(ray, &t_start);
  if (ray_hit.ray.tnear > ray_hit.ray.tfar) return false;  // misses the bounds
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(Scene(), &context, &ray_hit);
  return HitFromRayHit(ray_hit, t_start, hit);
}

std::shared_ptr<const SampleTable> MeshRenderer::Impl::TableFor(const Camera& camera,
                                                                int samples_per_axis) const {
  const int64_t num_samples =
      int64_t{camera.width()} * camera.height() * samples_per_axis * samples_per_axis;
  if (camera.IsOrthographic() || !camera.HasDistortion() || num_samples > kMaxTableSamples) {
    return nullptr;
  }
  std::lock_guard<std::mutex> lock(tables_mutex_);
  for (const auto& table : tables_) {
    if (table->Serves(camera, samples_per_axis)) return table;
  }
  const auto seen = std::find_if(seen_once_.begin(), seen_once_.end(), [&](const SampleTable& key) {
    return key.Serves(camera, samples_per_axis);
  });
  if (seen == seen_once_.end()) {
    if (seen_once_.size() == kMaxSeenOnce) seen_once_.erase(seen_once_.begin());
    seen_once_.push_back(SampleTable{camera, samples_per_axis, {}});
    return nullptr;
  }
  auto table = std::make_shared<SampleTable>(SampleTable{camera, samples_per_axis, {}});
  table->points.resize(static_cast<size_t>(num_samples));
  const int per_pixel = samples_per_axis * samples_per_axis;
  tbb::parallel_for(0, camera.height(), [&](int row) {
    size_t k = static_cast<size_t>(row) * camera.width() * per_pixel;
    for (int col = 0; col < camera.width(); ++col) {
      for (int t = 0; t < samples_per_axis; ++t) {
        for (int s = 0; s < samples_per_axis; ++s, ++k) {
          table->points[k] = camera.CamFromImg(SampleInPixel(col, row, s, t, samples_per_axis));
        }
      }
    }
  });
  if (tables_.size() == kMaxTables) tables_.erase(tables_.begin());
  tables_.push_back(table);
  return table;
}

void MeshRenderer::Impl::RenderRow(const Camera& camera, const SampleTable* table,
                                   const Rigid3d& world_from_cam, int samples_per_axis, int row,
                                   int x0, int x1, const ShadeFn& shade, RowBuffers* buffers,
                                   FloatImage* image) const {
  // All rays of the row, pixel by pixel, traced as one coherent stream.
  const int samples = samples_per_axis * samples_per_axis;
  const size_t num_rays = static_cast<size_t>(x1 - x0) * samples;
  buffers->ray_hits.resize(num_rays);
  buffers->t_starts.resize(num_rays);
  const Eigen::Matrix3d world_from_cam_rotation = world_from_cam.rotation.toRotationMatrix();
  size_t r = 0;
  for (int col = x0; col < x1; ++col) {
    for (int t = 0; t < samples_per_axis; ++t) {
      for (int s = 0; s < samples_per_axis; ++s, ++r) {
        // CamRayFromImg's ray, from the table's point where there is one.
        const Ray3d ray_in_cam =
            table == nullptr
                ? camera.CamRayFromImg(SampleInPixel(col, row, s, t, samples_per_axis))
                : Camera::PerspectiveRay(
                      table->points[(static_cast<size_t>(row) * camera.width() + col) * samples +
                                    t * samples_per_axis + s]);
        Ray3d ray_in_world = ray_in_cam;
        ray_in_world.origin =
            world_from_cam_rotation * ray_in_cam.origin + world_from_cam.translation;
        ray_in_world.direction = world_from_cam_rotation * ray_in_cam.direction;
        buffers->ray_hits[r] = MakeRayHit(ray_in_world, &buffers->t_starts[r]);
      }
    }
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  if (image->channels() == 1) {
    buffers->rays.resize(num_rays);
    for (size_t k = 0; k < num_rays; ++k) buffers->rays[k] = buffers->ray_hits[k].ray;
    rtcOccluded1M(Scene(), &context, buffers->rays.data(), static_cast<unsigned>(num_rays),
                  sizeof(RTCRay));
    CoverRow(*buffers, samples, row, x0, x1, image);
    return;
  }
  rtcIntersect1M(Scene(), &context, buffers->ray_hits.data(), static_cast<unsigned>(num_rays),
                 sizeof(RTCRayHit));
  ShadeRow(*buffers, samples, row, x0, x1, shade, image);
}

void MeshRenderer::Impl::CoverRow(const RowBuffers& buffers, int samples, int row, int x0, int x1,
                                  FloatImage* image) {
  for (int col = x0; col < x1; ++col) {
    int hits = 0;
    for (int k = 0; k < samples; ++k) {
      // Embree sets an occluded ray's tfar to -inf; the others keep theirs
      // (>= 0: infinity, or 0 for a ray made inactive by MakeRayHit).
      hits += buffers.rays[static_cast<size_t>(col - x0) * samples + k].tfar < 0.0f ? 1 : 0;
    }
    image->at(col, row, 0) = static_cast<float>(hits) / static_cast<float>(samples);
  }
}

void MeshRenderer::Impl::ShadeRow(const RowBuffers& buffers, int samples, int row, int x0, int x1,
                                  const ShadeFn& shade, FloatImage* image) {
  const int channels = image->channels();
  std::vector<float> sum(channels);
  for (int col = x0; col < x1; ++col) {
    std::fill(sum.begin(), sum.end(), 0.0f);
    int hits = 0;
    for (int k = 0; k < samples; ++k) {
      const size_t r = static_cast<size_t>(col - x0) * samples + k;
      Hit hit;
      if (!HitFromRayHit(buffers.ray_hits[r], buffers.t_starts[r], &hit)) continue;
      ++hits;
      shade(hit, sum.data());
    }
    float* pixel = &image->at(col, row, 0);
    for (int c = 0; c + 1 < channels; ++c) pixel[c] = hits > 0 ? sum[c] / hits : 0.0f;
    pixel[channels - 1] = static_cast<float>(hits) / static_cast<float>(samples);
  }
}

void MeshRenderer::Impl::ResolveSamples(const std::vector<int>& sample_triangles,
                                        int samples_per_axis, const ShadeFn& shade,
                                        FloatImage* image) const {
  const int channels = image->channels();
  const int samples = samples_per_axis * samples_per_axis;
  const size_t sample_width = static_cast<size_t>(image->width()) * samples_per_axis;
  tbb::parallel_for(
      tbb::blocked_range<int>(0, image->height()), [&](const tbb::blocked_range<int>& rows) {
        std::vector<float> sum(channels);
        for (int row = rows.begin(); row < rows.end(); ++row) {
          for (int col = 0; col < image->width(); ++col) {
            std::fill(sum.begin(), sum.end(), 0.0f);
            int hits = 0;
            // The rays' order within the pixel, so that sums round alike.
            for (int t = 0; t < samples_per_axis; ++t) {
              const size_t sample_row = static_cast<size_t>(row) * samples_per_axis + t;
              for (int s = 0; s < samples_per_axis; ++s) {
                const int triangle =
                    sample_triangles[sample_row * sample_width + col * samples_per_axis + s];
                if (triangle < 0) continue;
                ++hits;
                if (channels == 1) continue;
                Hit hit;
                hit.triangle_idx = triangle;
                hit.normal = triangle_normals_[triangle];
                shade(hit, sum.data());
              }
            }
            float* pixel = &image->at(col, row, 0);
            for (int c = 0; c + 1 < channels; ++c) pixel[c] = hits > 0 ? sum[c] / hits : 0.0f;
            pixel[channels - 1] = static_cast<float>(hits) / static_cast<float>(samples);
          }
        }
      });
}

FloatImage MeshRenderer::Impl::Render(const Camera& camera, const Rigid3d& cam_from_world,
                                      int samples_per_axis, int channels, MeshRenderMethod method,
                                      const ShadeFn& shade) const {
  camera.Check("MeshRenderer camera");
  SYLVA_CHECK_INPUT(samples_per_axis >= 1, "samples_per_axis")
      << "must be >= 1, got " << samples_per_axis;
  FloatImage image(camera.width(), camera.height(), channels);
  if (NumTriangles() == 0) return image;
  std::vector<int> sample_triangles;
  if (method == MeshRenderMethod::kAuto &&
      Rasterize(camera, cam_from_world, samples_per_axis, channels > 1, &sample_triangles)) {
    ResolveSamples(sample_triangles, samples_per_axis, shade, &image);
    return image;
  }
  // Pixels beyond the reach of the mesh's bounds stay empty, as their rays
  // would leave them.
  const PixelRect reach = ReachablePixels(camera, cam_from_world, padded_bounds_);
  if (reach.x0 >= reach.x1 || reach.y0 >= reach.y1) return image;
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const std::shared_ptr<const SampleTable> table = TableFor(camera, samples_per_axis);
  tbb::parallel_for(tbb::blocked_range<int>(reach.y0, reach.y1),
                    [&](const tbb::blocked_range<int>& rows) {
                      RowBuffers buffers;
                      for (int row = rows.begin(); row < rows.end(); ++row) {
                        RenderRow(camera, table.get(), world_from_cam, samples_per_axis, row,
                                  reach.x0, reach.x1, shade, &buffers, &image);
                      }
                    });
  return image;
}

MeshRenderer::MeshRenderer(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>(mesh)) {}
MeshRenderer::~MeshRenderer() = default;
MeshRenderer::MeshRenderer(MeshRenderer&&) noexcept = default;
MeshRenderer& MeshRenderer::operator=(MeshRenderer&&) noexcept = default;

int MeshRenderer::NumTriangles() const { return impl_->NumTriangles(); }

MeshRenderer::Impl::ShadeFn MeshRenderer::Impl::Lambert(const MeshRenderOptions& options) const {
  options.Check();
  const Eigen::Vector3f light = options.light_direction.normalized();
  const float ambient = options.ambient;
  return [this, light, ambient](const Hit& hit, float* rgb) {
    const float normal_norm = hit.normal.norm();
    const float cosine = normal_norm > 0 ? std::abs(hit.normal.dot(light)) / normal_norm : 1.0f;
    const float shading = ambient + (1.0f - ambient) * cosine;
    const Eigen::Vector3f& color = ColorOf(hit.triangle_idx);
    for (int c = 0; c < 3; ++c) rgb[c] += shading * color[c];
  };
}

FloatImage MeshRenderer::RenderRgba(const Camera& camera, const Rigid3d& cam_from_world,
                                    const Options& options) const {
  return impl_->Render(camera, cam_from_world, options.samples_per_axis, 4, options.method,
                       impl_->Lambert(options));
}

MeshRenderer::CoverageAndRgba MeshRenderer::RenderCoverageAndRgba(const Camera& camera,
                                                                  const Rigid3d& cam_from_world,
                                                                  int samples_per_axis,
                                                                  int picture_scale,
                                                                  const Options& shading) const {
  SYLVA_CHECK_INPUT(samples_per_axis >= 1, "samples_per_axis")
      << "must be >= 1, got " << samples_per_axis;
  SYLVA_CHECK_INPUT(
      picture_scale >= 0 && (picture_scale == 0 || samples_per_axis % picture_scale == 0),
      "picture_scale")
      << "must be 0 or divide samples_per_axis " << samples_per_axis << ", got " << picture_scale;
  const Impl::ShadeFn shade = impl_->Lambert(shading);
  CoverageAndRgba result;
  std::vector<int> sample_triangles;
  if (shading.method == MeshRenderMethod::kAuto &&
      impl_->Rasterize(camera, cam_from_world, samples_per_axis, picture_scale > 0,
                       &sample_triangles)) {
    result.coverage = FloatImage(camera.width(), camera.height(), 1);
    impl_->ResolveSamples(sample_triangles, samples_per_axis, shade, &result.coverage);
    if (picture_scale > 0) {
      result.rgba = FloatImage(camera.width() * picture_scale, camera.height() * picture_scale, 4);
      impl_->ResolveSamples(sample_triangles, samples_per_axis / picture_scale, shade,
                            &result.rgba);
    }
    return result;
  }
  // Rays: asked for, or where rasterizing would not be exact (not tried again).
  result.coverage =
      RenderCoverage(camera, cam_from_world, samples_per_axis, MeshRenderMethod::kRayCast);
  if (picture_scale > 0) {
    const Camera picture_camera = camera.Scaled(picture_scale, camera.width() * picture_scale,
                                                camera.height() * picture_scale);
    result.rgba = impl_->Render(picture_camera, cam_from_world, samples_per_axis / picture_scale, 4,
                                MeshRenderMethod::kRayCast, shade);
  }
  return result;
}

FloatImage MeshRenderer::RenderCoverage(const Camera& camera, const Rigid3d& cam_from_world,
                                        int samples_per_axis, MeshRenderMethod method) const {
  return impl_->Render(camera, cam_from_world, samples_per_axis, 1, method,
                       [](const Hit&, float*) {});
}

double MeshRenderer::CastRay(const Ray3d& ray_in_world) const {
  Hit hit;
  if (!impl_->Intersect(ray_in_world, &hit)) return std::numeric_limits<double>::infinity();
  return hit.t;
}

}  // namespace sylva
