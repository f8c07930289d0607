#include "mesh/tree_preview.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/util/check.h"
#include "mesh/embree_util.h"

namespace sylva {
namespace {

constexpr double kDegrees = M_PI / 180.0;
// A leaf texel keeps a hit at this alpha or more (glTF MASK's default cutoff).
constexpr float kAlphaCutoff = 0.5f;
// Shadow rays start this fraction of the scene's diagonal off the surface.
constexpr float kShadowOffset = 1e-5f;
// Sky light on a face: (1 - kSkyTilt) + kSkyTilt * n.z of the face's normal
// turned towards the viewer, so faces turned down (undersides of branches)
// are darker than faces turned up.
constexpr float kSkyTilt = 0.3f;
// Smooth shading interpolates vertex normals within this angle (cosine) of
// the face's normal (about 40 degrees).
constexpr float kCosCreaseAngle = 0.766f;
// Geometry id of the mesh; leaf instance k has id k + 1.
constexpr unsigned kMeshGeometryId = 0;
// Elevation of the views is limited to keep the up vector usable.
constexpr double kMaxElevationDeg = 89.0;
// Leaves are baked into the mesh when there are at least this many camera
// rays per baked triangle. sylva_preview_benchmark (10^5 leaves x 14
// triangles): baking and the BVH cost 0.54 s more than instancing, and each
// of the 14.7 M camera rays (with its shadow ray) is traced 0.078 us faster:
// about 5 rays per triangle break even.
constexpr double kRaysPerBakedTriangle = 5.0;

float SrgbFromLinear(float value) {
  const float v = std::clamp(value, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float LinearFromSrgb(float value) {
  const float v = std::clamp(value, 0.0f, 1.0f);
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

// Unit vector from the scene towards a camera at (azimuth, elevation).
Eigen::Vector3d TowardsCamera(double azimuth_deg, double elevation_deg) {
  const double azimuth = azimuth_deg * kDegrees, elevation = elevation_deg * kDegrees;
  return Eigen::Vector3d(std::sin(azimuth) * std::cos(elevation),
                         -std::cos(azimuth) * std::cos(elevation), std::sin(elevation));
}

std::string AzimuthName(double azimuth_deg) {
  std::string number = std::to_string(std::lround(azimuth_deg));
  return "azimuth_" + number;
}

// Orthographic camera framing the projections of the points that
// `for_each_point(visit)` visits, seen through `cam_from_world`: their
// bounding rectangle centred, scaled to leave the margin on the tighter side.
template <typename ForEachPoint>
Camera FramingCamera(const ForEachPoint& for_each_point, const Rigid3d& cam_from_world,
                     const TreePreviewOptions& options) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  const Eigen::Matrix<double, 2, 3> xy_from_world =
      cam_from_world.rotation.toRotationMatrix().topRows<2>();
  for_each_point([&](const Eigen::Vector3d& point_in_world) {
    const Eigen::Vector2d xy = xy_from_world * point_in_world;
    lo = lo.cwiseMin(xy);
    hi = hi.cwiseMax(xy);
  });
  const double border = 2.0 * options.margin * std::min(options.width, options.height);
  const Eigen::Vector2d extent = (hi - lo).cwiseMax(1e-12 * (hi - lo).maxCoeff());
  const double pixels_per_unit =
      std::min((options.width - border) / extent.x(), (options.height - border) / extent.y());
  const Eigen::Vector2d mid = 0.5 * (lo + hi) + cam_from_world.translation.head<2>();
  return Camera(CameraModel::kOrthographic, options.width, options.height,
                {pixels_per_unit, pixels_per_unit, 0.5 * options.width - pixels_per_unit * mid.x(),
                 0.5 * options.height - pixels_per_unit * mid.y()});
}

// The views of options around `bounds`, without their cameras.
std::vector<PreviewView> PosesAround(const Box3d& bounds, const TreePreviewOptions& options) {
  options.Check();
  SYLVA_CHECK_INPUT(!bounds.isEmpty() && bounds.diagonal().norm() > 0, "tree preview")
      << "nothing to frame: the scene is empty or a single point";
  const Eigen::Vector3d center = bounds.center();
  const double distance = bounds.diagonal().norm();  // puts the image plane outside the box
  std::vector<PreviewView> views;
  for (double azimuth : options.azimuths_deg) {
    PreviewView view;
    view.name = AzimuthName(azimuth);
    view.cam_from_world = LookAt(center + distance * TowardsCamera(azimuth, options.elevation_deg),
                                 center, Eigen::Vector3d::UnitZ());
    views.push_back(view);
  }
  if (options.top_view) {
    PreviewView view;
    view.name = "top";
    view.cam_from_world =
        LookAt(center + distance * Eigen::Vector3d::UnitZ(), center, Eigen::Vector3d::UnitY());
    views.push_back(view);
  }
  return views;
}

// Camera rays of `num_views` pictures of options' size and sampling.
double CameraRays(const TreePreviewOptions& options, size_t num_views) {
  return static_cast<double>(options.width) * options.height * options.samples_per_axis *
         options.samples_per_axis * num_views;
}

// What a ray sees where it hits, with normals turned towards the viewer.
struct SurfacePoint {
  Eigen::Vector3f position;
  Eigen::Vector3f geometric_normal;  // unit
  Eigen::Vector3f shading_normal;    // unit
  Eigen::Vector3f albedo;            // linear RGB
  bool double_sided = false;
};

}  // namespace

void TreePreviewOptions::Check() const {
  SYLVA_CHECK_INPUT(width >= 8 && width <= 16384, "TreePreview.width")
      << "must be in [8, 16384] pixels, got " << width;
  SYLVA_CHECK_INPUT(height >= 8 && height <= 16384, "TreePreview.height")
      << "must be in [8, 16384] pixels, got " << height;
  SYLVA_CHECK_INPUT(samples_per_axis >= 1 && samples_per_axis <= 16, "TreePreview.samples_per_axis")
      << "must be in [1, 16], got " << samples_per_axis;
  SYLVA_CHECK_INPUT(!azimuths_deg.empty() || top_view, "TreePreview.azimuths_deg")
      << "no views: give at least one azimuth or the top view";
  for (double azimuth : azimuths_deg) {
    SYLVA_CHECK_INPUT(std::isfinite(azimuth), "TreePreview.azimuths_deg") << "must be finite";
  }
  SYLVA_CHECK_INPUT(std::abs(elevation_deg) <= kMaxElevationDeg, "TreePreview.elevation_deg")
      << "must be in [-89, 89] degrees, got " << elevation_deg;
  SYLVA_CHECK_INPUT(margin >= 0 && margin < 0.4, "TreePreview.margin")
      << "must be in [0, 0.4), got " << margin;
  SYLVA_CHECK_INPUT(sun_direction.allFinite() && sun_direction.norm() > 0,
                    "TreePreview.sun_direction")
      << "must be a finite, non-zero vector";
  SYLVA_CHECK_INPUT(sun_intensity >= 0 && std::isfinite(sun_intensity), "TreePreview.sun_intensity")
      << "must be >= 0, got " << sun_intensity;
  SYLVA_CHECK_INPUT(sky_intensity >= 0 && std::isfinite(sky_intensity), "TreePreview.sky_intensity")
      << "must be >= 0, got " << sky_intensity;
  SYLVA_CHECK_INPUT(leaf_translucency >= 0 && leaf_translucency <= 1,
                    "TreePreview.leaf_translucency")
      << "must be in [0, 1], got " << leaf_translucency;
}

std::vector<PreviewView> FramedPreviewViews(const Box3d& bounds,
                                            const TreePreviewOptions& options) {
  std::vector<PreviewView> views = PosesAround(bounds, options);
  const auto corners = [&](const auto& visit) {
    for (int corner = 0; corner < 8; ++corner) {
      visit(bounds.corner(static_cast<Box3d::CornerType>(corner)));
    }
  };
  for (PreviewView& view : views)
    view.camera = FramingCamera(corners, view.cam_from_world, options);
  return views;
}

PreviewView CloseUpView(const Eigen::Vector3d& center, double radius, double azimuth_deg,
                        double elevation_deg, const TreePreviewOptions& options) {
  options.Check();
  SYLVA_CHECK_INPUT(center.allFinite() && std::isfinite(radius) && radius > 0, "close-up")
      << "needs a finite centre and a radius > 0, got radius " << radius;
  SYLVA_CHECK_INPUT(std::abs(elevation_deg) <= kMaxElevationDeg, "close-up elevation")
      << "must be in [-89, 89] degrees, got " << elevation_deg;
  PreviewView view;
  view.name = "close_up";
  view.cam_from_world = LookAt(center + radius * TowardsCamera(azimuth_deg, elevation_deg), center,
                               Eigen::Vector3d::UnitZ());
  const double usable = (1.0 - 2.0 * options.margin) * std::min(options.width, options.height);
  view.camera = Camera::Orthographic(options.width, options.height, usable / (2.0 * radius));
  return view;
}

// ---- The scene ----

class TreePreviewRenderer::Impl {
 public:
  Impl(const TriangleMesh& mesh, const LeafInstances* leaves, PreviewLeafGeometry leaf_geometry);
  ~Impl();
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  FloatImage Render(const PreviewView& view, const TreePreviewOptions& options) const;
  std::vector<PreviewView> FramedViews(const TreePreviewOptions& options) const;

  Box3d bounds;
  TreePreviewStats stats;

 private:
  struct Leaf {  // the one leaf geometry, in its own frame
    std::vector<Eigen::Vector3f> points;
    std::vector<Eigen::Vector3i> triangles;
    std::vector<Eigen::Vector2f> uvs;  // empty: untextured
    FloatImage texture;
    Eigen::Vector3f color;
  };
  // The scene (device_ exists): `leaves` (null: none) baked into the mesh or
  // instanced.
  void Build(const TriangleMesh& mesh, const LeafInstances* leaves, bool bake);
  // Releases what Embree holds (idempotent).
  void Release();
  void AddMesh(const TriangleMesh& mesh);
  void AddLeaves(const LeafInstances& leaves);
  // Leaf k (Embree geometry id k + 1) as an instance of the leaf scene.
  void AddLeafInstance(const LeafInstance& instance, size_t k);
  // The texel under the barycentric point (u, v) of leaf triangle `triangle_idx`.
  const float* LeafTexel(unsigned triangle_idx, float u, float v) const;
  static void LeafAlphaFilter(const RTCFilterFunctionNArguments* args);

  // The visible surface along a traced ray; false if it missed.
  bool Resolve(const RTCRayHit& ray_hit, bool smooth_normals, SurfacePoint* point) const;
  // A visible point's light before its shadow ray: the sun's share (0 if
  // none could arrive) and the sky's, and where a shadow ray would start.
  struct Lighting {
    Eigen::Vector3f albedo;
    float sun = 0.0f, sky = 0.0f;
    Eigen::Vector3f shadow_origin;
  };
  Lighting Light(const SurfacePoint& point, const TreePreviewOptions& options) const;
  // One row of the picture: its rays, then the shadow rays of the points
  // they hit, each as one coherent stream. `buffers` are reused.
  struct RowBuffers {
    std::vector<RTCRayHit> rays;
    std::vector<Lighting> lights;
    std::vector<char> hit;
    std::vector<RTCRay> shadow_rays;
    std::vector<int> shadowed_sample;
  };
  void RenderRow(const PreviewView& view, const Rigid3d& world_from_cam, int row,
                 const TreePreviewOptions& options, RowBuffers* buffers, FloatImage* image) const;

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  RTCScene leaf_scene_ = nullptr;
  // The mesh.
  std::vector<Eigen::Vector3f> vertices_;
  std::vector<Eigen::Vector3f> vertex_normals_;
  std::vector<Eigen::Vector3i> triangles_;
  std::vector<int> triangle_materials_;
  std::vector<Material> materials_;
  // The leaves.
  Leaf leaf_;
  std::vector<Eigen::Matrix3f> leaf_rotations_;  // world_from_leaf, per instance
  std::vector<LeafInstance> leaf_instances_;
  float shadow_offset_ = 0.0f;
};

TreePreviewRenderer::Impl::Impl(const TriangleMesh& mesh, const LeafInstances* leaves,
                                PreviewLeafGeometry leaf_geometry) {
  const auto start = std::chrono::steady_clock::now();
  mesh.Check();
  const bool has_leaves = leaves != nullptr && !leaves->instances.empty();
  const bool bake = has_leaves && leaf_geometry == PreviewLeafGeometry::kTriangles;
  if (has_leaves) leaves->shape.Check();
  SYLVA_CHECK(!bake || leaves->shape.texture.empty()) << "a textured leaf shape cannot be baked";
  device_ = rtcNewDevice(nullptr);
  SYLVA_CHECK(device_ != nullptr) << "cannot create an Embree device";
  // A throwing constructor runs no destructor: what Embree holds by then is
  // released here.
  try {
    Build(mesh, has_leaves ? leaves : nullptr, bake);
  } catch (...) {
    Release();
    throw;
  }
  shadow_offset_ = bounds.isEmpty()
                       ? 0.0f
                       : kShadowOffset * static_cast<float>(bounds.diagonal().norm()) + 1e-6f;
  stats.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void TreePreviewRenderer::Impl::Build(const TriangleMesh& mesh, const LeafInstances* leaves,
                                      bool bake) {
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  if (bake) {
    // Baked leaves are mesh triangles of the leaf material (double-sided,
    // its colour), shaded as the instanced leaf is: a flat leaf's vertex
    // normals are its face normal.
    TriangleMesh with_leaves = mesh;
    with_leaves.Append(leaves->Bake());
    AddMesh(with_leaves);
    stats.mesh_triangles = mesh.NumTriangles();
    stats.leaf_instances = static_cast<int>(leaves->instances.size());
    stats.leaf_triangles = static_cast<int>(leaves->shape.triangles.size());
    stats.leaves_as_triangles = true;
  } else {
    if (mesh.NumTriangles() > 0) AddMesh(mesh);
    if (leaves != nullptr) AddLeaves(*leaves);
  }
  rtcCommitScene(scene_);
  CheckEmbreeDevice(device_, "building the preview scene");
}

void TreePreviewRenderer::Impl::Release() {
  if (scene_ != nullptr) rtcReleaseScene(scene_);
  if (leaf_scene_ != nullptr) rtcReleaseScene(leaf_scene_);
  if (device_ != nullptr) rtcReleaseDevice(device_);
  scene_ = leaf_scene_ = nullptr;
  device_ = nullptr;
}

TreePreviewRenderer::Impl::~Impl() { Release(); }

void TreePreviewRenderer::Impl::AddMesh(const TriangleMesh& mesh) {
  vertices_ = mesh.vertices;
  vertex_normals_ = mesh.VertexNormals();
  triangles_ = mesh.triangles;
  triangle_materials_ = mesh.triangle_materials;
  materials_ = mesh.materials;
  stats.mesh_triangles = mesh.NumTriangles();
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    for (int k = 0; k < 3; ++k) bounds.extend(mesh.vertices[triangle[k]].cast<double>());
  }
  RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree reads vertices with 16-byte loads: one unused vertex of padding.
  vertices_.push_back(Eigen::Vector3f::Zero());
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                             vertices_.data(), 0, sizeof(Eigen::Vector3f), vertices_.size() - 1);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                             triangles_.data(), 0, sizeof(Eigen::Vector3i), triangles_.size());
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(scene_, geometry, kMeshGeometryId);
  rtcReleaseGeometry(geometry);
  CheckEmbreeDevice(device_, "adding the mesh");
}

void TreePreviewRenderer::Impl::AddLeaves(const LeafInstances& leaves) {
  for (const Eigen::Vector2f& p : leaves.shape.points) leaf_.points.emplace_back(p.x(), p.y(), 0.f);
  leaf_.triangles = leaves.shape.triangles;
  leaf_.uvs = leaves.shape.uvs;
  leaf_.texture = leaves.shape.texture;
  leaf_.color = leaves.material.diffuse_color;
  stats.leaf_triangles = static_cast<int>(leaf_.triangles.size());
  stats.leaf_instances = static_cast<int>(leaves.instances.size());
  if (leaf_.triangles.empty()) return;
  // The one leaf geometry in its own scene...
  leaf_scene_ = rtcNewScene(device_);
  RTCGeometry leaf = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  leaf_.points.push_back(Eigen::Vector3f::Zero());  // padding, as for the mesh
  rtcSetSharedGeometryBuffer(leaf, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                             leaf_.points.data(), 0, sizeof(Eigen::Vector3f),
                             leaf_.points.size() - 1);
  rtcSetSharedGeometryBuffer(leaf, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                             leaf_.triangles.data(), 0, sizeof(Eigen::Vector3i),
                             leaf_.triangles.size());
  if (!leaf_.uvs.empty() && !leaf_.texture.empty()) {
    rtcSetGeometryUserData(leaf, this);
    rtcSetGeometryIntersectFilterFunction(leaf, LeafAlphaFilter);
    rtcSetGeometryOccludedFilterFunction(leaf, LeafAlphaFilter);
  }
  rtcCommitGeometry(leaf);
  rtcAttachGeometry(leaf_scene_, leaf);
  rtcReleaseGeometry(leaf);
  rtcCommitScene(leaf_scene_);
  // ... drawn once per leaf under its transform (world = t + s R p).
  leaf_rotations_.reserve(leaves.instances.size());
  leaf_instances_ = leaves.instances;
  for (size_t k = 0; k < leaves.instances.size(); ++k) AddLeafInstance(leaves.instances[k], k);
  CheckEmbreeDevice(device_, "adding the leaf instances");
}

void TreePreviewRenderer::Impl::AddLeafInstance(const LeafInstance& instance, size_t k) {
  const Eigen::Matrix3f rotation = instance.rotation.normalized().toRotationMatrix();
  leaf_rotations_.push_back(rotation);
  Eigen::Matrix<float, 3, 4> world_from_leaf;  // column-major, as Embree wants it
  world_from_leaf.leftCols<3>() = instance.scale * rotation;
  world_from_leaf.col(3) = instance.translation;
  for (size_t p = 0; p + 1 < leaf_.points.size(); ++p) {  // the last point is padding
    bounds.extend(
        (world_from_leaf.leftCols<3>() * leaf_.points[p] + instance.translation).cast<double>());
  }
  RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(geometry, leaf_scene_);
  rtcSetGeometryTransform(geometry, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, world_from_leaf.data());
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(scene_, geometry, static_cast<unsigned>(k + 1));
  rtcReleaseGeometry(geometry);
}

const float* TreePreviewRenderer::Impl::LeafTexel(unsigned triangle_idx, float u, float v) const {
  const Eigen::Vector3i& triangle = leaf_.triangles[triangle_idx];
  const Eigen::Vector2f uv = (1.0f - u - v) * leaf_.uvs[triangle[0]] + u * leaf_.uvs[triangle[1]] +
                             v * leaf_.uvs[triangle[2]];
  const int x =
      std::clamp(static_cast<int>(uv.x() * leaf_.texture.width()), 0, leaf_.texture.width() - 1);
  const int y =
      std::clamp(static_cast<int>(uv.y() * leaf_.texture.height()), 0, leaf_.texture.height() - 1);
  const FloatImage& texture = leaf_.texture;
  return texture.data() + (static_cast<size_t>(y) * texture.width() + x) * texture.channels();
}

void TreePreviewRenderer::Impl::LeafAlphaFilter(const RTCFilterFunctionNArguments* args) {
  const Impl& impl = *static_cast<const Impl*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const float* texel =
        impl.LeafTexel(RTCHitN_primID(args->hit, args->N, i), RTCHitN_u(args->hit, args->N, i),
                       RTCHitN_v(args->hit, args->N, i));
    if (texel[3] < kAlphaCutoff) args->valid[i] = 0;
  }
}

bool TreePreviewRenderer::Impl::Resolve(const RTCRayHit& ray_hit, bool smooth_normals,
                                        SurfacePoint* point) const {
  const RTCHit& hit = ray_hit.hit;
  if (hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  const Eigen::Vector3f direction(ray_hit.ray.dir_x, ray_hit.ray.dir_y, ray_hit.ray.dir_z);
  point->position = Eigen::Vector3f(ray_hit.ray.org_x, ray_hit.ray.org_y, ray_hit.ray.org_z) +
                    ray_hit.ray.tfar * direction;
  // Embree reports an instanced hit's normal in the instance's own frame.
  Eigen::Vector3f normal(hit.Ng_x, hit.Ng_y, hit.Ng_z);
  if (hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
    normal = leaf_rotations_[hit.instID[0] - 1] * normal;
    point->shading_normal = normal.normalized();
    point->double_sided = true;
    point->albedo = leaf_.color;
    if (!leaf_.uvs.empty() && !leaf_.texture.empty()) {
      const float* texel = LeafTexel(hit.primID, hit.u, hit.v);
      for (int c = 0; c < 3; ++c) point->albedo[c] = LinearFromSrgb(texel[c]);
    }
  } else {
    const Eigen::Vector3i& triangle = triangles_[hit.primID];
    const Material& material = materials_[triangle_materials_[hit.primID]];
    point->albedo = material.diffuse_color;
    point->double_sided = material.double_sided;
    point->shading_normal = normal.normalized();
    if (smooth_normals) {
      // A vertex normal farther than the crease angle from the face's stands
      // for a hard edge (a box's corner): the face keeps its own normal there.
      const float weights[3] = {1.0f - hit.u - hit.v, hit.u, hit.v};
      Eigen::Vector3f smooth = Eigen::Vector3f::Zero();
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3f& vertex_normal = vertex_normals_[triangle[k]];
        smooth += weights[k] * (vertex_normal.dot(point->shading_normal) >= kCosCreaseAngle
                                    ? vertex_normal
                                    : point->shading_normal);
      }
      if (smooth.norm() > 0) point->shading_normal = smooth.normalized();
    }
  }
  point->geometric_normal = normal.normalized();
  if (!point->geometric_normal.allFinite()) return false;  // degenerate triangle
  // Both normals towards the viewer (leaves and cut-open solids are seen from both sides).
  if (point->geometric_normal.dot(direction) > 0) {
    point->geometric_normal = -point->geometric_normal;
    point->shading_normal = -point->shading_normal;
  }
  return true;
}

TreePreviewRenderer::Impl::Lighting TreePreviewRenderer::Impl::Light(
    const SurfacePoint& point, const TreePreviewOptions& options) const {
  const Eigen::Vector3f sun = options.sun_direction.normalized().cast<float>();
  float cosine = point.shading_normal.dot(sun);
  float side = 1.0f;  // the side the sun light arrives from, along the geometric normal
  if (point.geometric_normal.dot(sun) <= 0.0f) {
    // Lit from behind: a leaf passes a fraction of it, a solid face none.
    cosine = point.double_sided ? static_cast<float>(options.leaf_translucency) *
                                      std::abs(point.geometric_normal.dot(sun))
                                : 0.0f;
    side = -1.0f;
  }
  Lighting lighting;
  lighting.albedo = point.albedo;
  lighting.sun = static_cast<float>(options.sun_intensity) * std::max(cosine, 0.0f);
  lighting.sky = static_cast<float>(options.sky_intensity) *
                 ((1.0f - kSkyTilt) + kSkyTilt * point.shading_normal.z());
  lighting.shadow_origin = point.position + side * shadow_offset_ * point.geometric_normal;
  return lighting;
}

void TreePreviewRenderer::Impl::RenderRow(const PreviewView& view, const Rigid3d& world_from_cam,
                                          int row, const TreePreviewOptions& options,
                                          RowBuffers* buffers, FloatImage* image) const {
  const int samples = options.samples_per_axis;
  const int per_pixel = samples * samples;
  const size_t num_rays = static_cast<size_t>(image->width()) * per_pixel;
  buffers->rays.resize(num_rays);
  size_t r = 0;
  for (int col = 0; col < image->width(); ++col) {
    for (int t = 0; t < samples; ++t) {
      for (int s = 0; s < samples; ++s, ++r) {
        const Eigen::Vector2d point_in_image(col + (s + 0.5) / samples, row + (t + 0.5) / samples);
        const Ray3d ray_in_cam = view.camera.CamRayFromImg(point_in_image);
        const Eigen::Vector3f origin = (world_from_cam * ray_in_cam.origin).cast<float>();
        const Eigen::Vector3f direction =
            (world_from_cam.rotation * ray_in_cam.direction).cast<float>();
        // Orthographic rays start on the image plane.
        buffers->rays[r] =
            EmbreeRayHit(origin, direction, 0.0f, std::numeric_limits<float>::infinity());
      }
    }
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcIntersect1M(scene_, &context, buffers->rays.data(), static_cast<unsigned>(num_rays),
                 sizeof(RTCRayHit));
  // Shade what the rays hit; a shadow ray for each point the sun can reach.
  const Eigen::Vector3f sun = options.sun_direction.normalized().cast<float>();
  buffers->lights.resize(num_rays);
  buffers->hit.assign(num_rays, 0);
  buffers->shadow_rays.clear();
  buffers->shadowed_sample.clear();
  for (size_t k = 0; k < num_rays; ++k) {
    SurfacePoint point;
    if (!Resolve(buffers->rays[k], options.smooth_normals, &point)) continue;
    buffers->hit[k] = 1;
    buffers->lights[k] = Light(point, options);
    if (buffers->lights[k].sun > 0.0f && options.shadows) {
      buffers->shadow_rays.push_back(EmbreeRay(buffers->lights[k].shadow_origin, sun, 0.0f,
                                               std::numeric_limits<float>::infinity()));
      buffers->shadowed_sample.push_back(static_cast<int>(k));
    }
  }
  rtcInitIntersectContext(&context);
  rtcOccluded1M(scene_, &context, buffers->shadow_rays.data(),
                static_cast<unsigned>(buffers->shadow_rays.size()), sizeof(RTCRay));
  for (size_t k = 0; k < buffers->shadow_rays.size(); ++k) {
    // Embree marks an occluded ray with tfar = -inf.
    if (buffers->shadow_rays[k].tfar < 0.0f) buffers->lights[buffers->shadowed_sample[k]].sun = 0;
  }
  // Each pixel: the mean colour of its rays that hit, and the share that hit.
  for (int col = 0; col < image->width(); ++col) {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    int hits = 0;
    for (int k = col * per_pixel; k < (col + 1) * per_pixel; ++k) {
      if (!buffers->hit[k]) continue;
      const Lighting& light = buffers->lights[k];
      sum += (light.sun + light.sky) * light.albedo;
      ++hits;
    }
    const float coverage = static_cast<float>(hits) / static_cast<float>(per_pixel);
    if (hits > 0) sum /= static_cast<float>(hits);
    Eigen::Vector4f pixel(sum.x(), sum.y(), sum.z(), coverage);
    if (options.white_background) {
      pixel.head<3>() = pixel.w() * pixel.head<3>() + Eigen::Vector3f::Constant(1.0f - pixel.w());
      pixel.w() = 1.0f;
    }
    for (int c = 0; c < 3; ++c) {
      image->at(col, row, c) = options.srgb ? SrgbFromLinear(pixel[c]) : pixel[c];
    }
    image->at(col, row, 3) = pixel.w();
  }
}

FloatImage TreePreviewRenderer::Impl::Render(const PreviewView& view,
                                             const TreePreviewOptions& options) const {
  options.Check();
  view.camera.Check("tree preview view '" + view.name + "'");
  FloatImage image(view.camera.width(), view.camera.height(), 4);
  const Rigid3d world_from_cam = view.cam_from_world.Inverse();
  tbb::parallel_for(tbb::blocked_range<int>(0, image.height()),
                    [&](const tbb::blocked_range<int>& rows) {
                      RowBuffers buffers;
                      for (int row = rows.begin(); row < rows.end(); ++row) {
                        RenderRow(view, world_from_cam, row, options, &buffers, &image);
                      }
                    });
  return image;
}

std::vector<PreviewView> TreePreviewRenderer::Impl::FramedViews(
    const TreePreviewOptions& options) const {
  std::vector<PreviewView> views = PosesAround(bounds, options);
  // Every vertex drawn (padding excluded): the silhouette's exact extent.
  const auto points = [&](const auto& visit) {
    for (const Eigen::Vector3i& triangle : triangles_) {
      for (int k = 0; k < 3; ++k) visit(vertices_[triangle[k]].cast<double>());
    }
    if (leaf_.triangles.empty()) return;
    for (size_t k = 0; k < leaf_instances_.size(); ++k) {
      const LeafInstance& leaf = leaf_instances_[k];
      for (size_t p = 0; p + 1 < leaf_.points.size(); ++p) {
        visit((leaf.translation + leaf.scale * (leaf_rotations_[k] * leaf_.points[p]))
                  .cast<double>());
      }
    }
  };
  for (PreviewView& view : views) view.camera = FramingCamera(points, view.cam_from_world, options);
  return views;
}

// ---- Public API ----

PreviewLeafGeometry ChoosePreviewLeafGeometry(const LeafInstances* leaves, double num_rays) {
  if (leaves == nullptr || !leaves->shape.texture.empty()) return PreviewLeafGeometry::kInstances;
  const double baked_triangles =
      static_cast<double>(leaves->instances.size()) * leaves->shape.triangles.size();
  return baked_triangles * kRaysPerBakedTriangle <= num_rays ? PreviewLeafGeometry::kTriangles
                                                             : PreviewLeafGeometry::kInstances;
}

TreePreviewRenderer::TreePreviewRenderer(const TriangleMesh& mesh, const LeafInstances* leaves,
                                         PreviewLeafGeometry leaf_geometry)
    : impl_(std::make_unique<Impl>(mesh, leaves, leaf_geometry)) {}
TreePreviewRenderer::~TreePreviewRenderer() = default;
TreePreviewRenderer::TreePreviewRenderer(TreePreviewRenderer&&) noexcept = default;
TreePreviewRenderer& TreePreviewRenderer::operator=(TreePreviewRenderer&&) noexcept = default;

Box3d TreePreviewRenderer::Bounds() const { return impl_->bounds; }
const TreePreviewStats& TreePreviewRenderer::Stats() const { return impl_->stats; }

std::vector<PreviewView> TreePreviewRenderer::FramedViews(const TreePreviewOptions& options) const {
  return impl_->FramedViews(options);
}

FloatImage TreePreviewRenderer::Render(const PreviewView& view,
                                       const TreePreviewOptions& options) const {
  return impl_->Render(view, options);
}

std::vector<FloatImage> RenderTreePreviews(const TriangleMesh& mesh, const LeafInstances* leaves,
                                           const TreePreviewOptions& options) {
  options.Check();
  const double num_rays =
      CameraRays(options, options.azimuths_deg.size() + (options.top_view ? 1 : 0));
  const TreePreviewRenderer renderer(mesh, leaves, ChoosePreviewLeafGeometry(leaves, num_rays));
  std::vector<FloatImage> pictures;
  for (const PreviewView& view : renderer.FramedViews(options)) {
    pictures.push_back(renderer.Render(view, options));
  }
  return pictures;
}

FloatImage RenderCloseUp(const TriangleMesh& mesh, const LeafInstances* leaves,
                         const Eigen::Vector3d& center, double radius, double azimuth_deg,
                         double elevation_deg, const TreePreviewOptions& options) {
  const PreviewView view = CloseUpView(center, radius, azimuth_deg, elevation_deg, options);
  return TreePreviewRenderer(mesh, leaves,
                             ChoosePreviewLeafGeometry(leaves, CameraRays(options, 1)))
      .Render(view, options);
}

}  // namespace sylva
