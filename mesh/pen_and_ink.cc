#include "mesh/pen_and_ink.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "mesh/embree_util.h"

namespace sylva {
namespace {

using Polyline = PenAndInkDrawing::Polyline;

constexpr double kDegrees = M_PI / 180.0;
// Outline samples count as visible within this depth of the first hit, in
// pixels (the paper's small offset of strokes towards the viewer).
constexpr double kVisibilityTolerancePx = 1.5;
// A hatching line breaks where the surface under it jumps this far in depth, pixels.
constexpr double kHatchDepthJumpPx = 3.0;
// Hatching samples along a line, pixels apart.
constexpr double kHatchStepPx = 1.0;
// Hatching strokes shorter than this are dropped, pixels.
constexpr double kMinHatchPx = 3.0;
// Angles of the two hatching families in the picture, degrees.
constexpr double kHatchAngleDeg = 55.0, kCrossHatchAngleDeg = 125.0;
// Chained endpoints match when they agree to 1 / kEndpointGrid pixels.
constexpr double kEndpointGrid = 64.0;
// Grey of the construction lines' ink (0 = no ink, 1 = black).
constexpr float kConstructionInk = 0.5f;

// The picture's frame: pixel = (p . right - x0, y1 - p . up) * scale + margin.
struct Frame {
  Eigen::Vector3d right, up, forward;
  double x0 = 0, y1 = 0, scale = 1, margin = 0, depth0 = 0;

  Eigen::Vector2d Project(const Eigen::Vector3d& p) const {
    return Eigen::Vector2d((p.dot(right) - x0) * scale + margin, (y1 - p.dot(up)) * scale + margin);
  }
  // The world point at pixel `q` on the plane of depth `depth0`.
  Eigen::Vector3d Unproject(const Eigen::Vector2d& q) const {
    return right * ((q.x() - margin) / scale + x0) + up * (y1 - (q.y() - margin) / scale) +
           forward * depth0;
  }
};

Frame MakeFrame(const std::vector<Eigen::Vector3d>& points, const PenAndInkView& view,
                const PenAndInkOptions& options, int* width, int* height) {
  Frame frame;
  frame.forward = view.view_direction.normalized();
  Eigen::Vector3d up = view.up - view.up.dot(frame.forward) * frame.forward;
  if (up.norm() < 1e-9) up = Eigen::Vector3d::UnitY() - frame.forward.y() * frame.forward;
  frame.up = up.normalized();
  frame.right = frame.forward.cross(frame.up);
  double x1 = -INFINITY, y0 = INFINITY, depth1 = -INFINITY;
  frame.x0 = frame.depth0 = INFINITY;
  frame.y1 = -INFINITY;
  for (const Eigen::Vector3d& p : points) {
    frame.x0 = std::min(frame.x0, p.dot(frame.right));
    x1 = std::max(x1, p.dot(frame.right));
    y0 = std::min(y0, p.dot(frame.up));
    frame.y1 = std::max(frame.y1, p.dot(frame.up));
    frame.depth0 = std::min(frame.depth0, p.dot(frame.forward));
    depth1 = std::max(depth1, p.dot(frame.forward));
  }
  const double extent = std::max({x1 - frame.x0, frame.y1 - y0, 1e-9});
  frame.margin = options.margin * options.image_size;
  frame.scale = (options.image_size - 2 * frame.margin) / extent;
  frame.depth0 -= 0.01 * (depth1 - frame.depth0) + 1e-6;  // rays start in front of everything
  *width = static_cast<int>(std::ceil((x1 - frame.x0) * frame.scale + 2 * frame.margin));
  *height = static_cast<int>(std::ceil((frame.y1 - y0) * frame.scale + 2 * frame.margin));
  return frame;
}

// The mesh in Embree, for first hits along the view direction.
class ViewRays {
 public:
  explicit ViewRays(const TriangleMesh& mesh) {
    device_ = rtcNewDevice("threads=1");
    CheckEmbreeDevice(device_, "rtcNewDevice");
    scene_ = rtcNewScene(device_);
    if (mesh.NumTriangles() > 0) {
      RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* vertices = static_cast<float*>(
          rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                  3 * sizeof(float), mesh.vertices.size()));
      for (size_t i = 0; i < mesh.vertices.size(); ++i) {
        for (int c = 0; c < 3; ++c) vertices[3 * i + c] = mesh.vertices[i][c];
      }
      auto* indices = static_cast<unsigned*>(
          rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                  3 * sizeof(unsigned), mesh.triangles.size()));
      for (size_t i = 0; i < mesh.triangles.size(); ++i) {
        for (int c = 0; c < 3; ++c) indices[3 * i + c] = mesh.triangles[i][c];
      }
      rtcCommitGeometry(geometry);
      rtcAttachGeometry(scene_, geometry);
      rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(scene_);
    CheckEmbreeDevice(device_, "building the pen-and-ink scene");
  }
  ~ViewRays() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  ViewRays(const ViewRays&) = delete;
  ViewRays& operator=(const ViewRays&) = delete;

  // The first hit from `origin` along `direction`: distance (inf if none)
  // and the geometric normal.
  double Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
              Eigen::Vector3d* normal = nullptr) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit ray_hit = EmbreeRayHit(origin.cast<float>(), direction.cast<float>(), 0.0f,
                                     std::numeric_limits<float>::infinity());
    rtcIntersect1(scene_, &context, &ray_hit);
    if (ray_hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return INFINITY;
    if (normal != nullptr) {
      *normal = Eigen::Vector3d(ray_hit.hit.Ng_x, ray_hit.hit.Ng_y, ray_hit.hit.Ng_z).normalized();
    }
    return ray_hit.ray.tfar;
  }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

// ------------------------------------------------- outlines

// Edges drawn as outlines (header): vertex pairs.
std::vector<std::pair<int, int>> OutlineEdges(const TriangleMesh& mesh, const Frame& frame,
                                              double crease_deg) {
  std::map<std::pair<int, int>, std::vector<int>> faces_of_edge;
  std::vector<Eigen::Vector3d> normals(mesh.triangles.size());
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Eigen::Vector3i& t = mesh.triangles[f];
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
    normals[f] = (mesh.vertices[t[1]].cast<double>() - a)
                     .cross(mesh.vertices[t[2]].cast<double>() - a)
                     .normalized();
    for (int c = 0; c < 3; ++c) {
      const int u = t[c], v = t[(c + 1) % 3];
      faces_of_edge[{std::min(u, v), std::max(u, v)}].push_back(static_cast<int>(f));
    }
  }
  const double crease_cos = std::cos(crease_deg * kDegrees);
  std::vector<std::pair<int, int>> edges;
  for (const auto& [edge, faces] : faces_of_edge) {
    bool drawn = faces.size() != 2;
    if (!drawn) {
      const Eigen::Vector3d& n0 = normals[faces[0]];
      const Eigen::Vector3d& n1 = normals[faces[1]];
      drawn = n0.dot(frame.forward) * n1.dot(frame.forward) < 0 || n0.dot(n1) < crease_cos;
    }
    if (drawn) edges.push_back(edge);
  }
  return edges;
}

// Joins segments that share endpoints into polylines.
std::vector<Polyline> Chain(const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& segs) {
  const auto key = [](const Eigen::Vector2d& p) {
    return std::make_pair(std::llround(p.x() * kEndpointGrid), std::llround(p.y() * kEndpointGrid));
  };
  std::multimap<std::pair<long long, long long>, int> at_point;
  for (size_t i = 0; i < segs.size(); ++i) {
    at_point.emplace(key(segs[i].first), static_cast<int>(i));
    at_point.emplace(key(segs[i].second), static_cast<int>(i));
  }
  std::vector<bool> used(segs.size(), false);
  // The other end of an unused segment at `p`, marking it used.
  const auto next = [&](const Eigen::Vector2d& p, Eigen::Vector2d* other) {
    const auto range = at_point.equal_range(key(p));
    for (auto it = range.first; it != range.second; ++it) {
      if (used[it->second]) continue;
      used[it->second] = true;
      const auto& s = segs[it->second];
      *other = key(s.first) == key(p) ? s.second : s.first;
      return true;
    }
    return false;
  };
  std::vector<Polyline> lines;
  for (size_t i = 0; i < segs.size(); ++i) {
    if (used[i]) continue;
    used[i] = true;
    Polyline line = {segs[i].first, segs[i].second};
    Eigen::Vector2d p;
    while (next(line.back(), &p)) line.push_back(p);
    while (next(line.front(), &p)) line.insert(line.begin(), p);
    lines.push_back(std::move(line));
  }
  return lines;
}

// Appends the visible runs of segment a-b (world) as picture segments.
void AddVisibleRuns(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Frame& frame,
                    const ViewRays& rays, const PenAndInkOptions& options,
                    PenAndInkDrawing* drawing,
                    std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>* segments) {
  const double tolerance = kVisibilityTolerancePx / frame.scale;
  const Eigen::Vector2d pa = frame.Project(a), pb = frame.Project(b);
  const int n =
      std::max(1, static_cast<int>(std::ceil((pb - pa).norm() / options.sample_spacing_px)));
  int run_start = -1;
  for (int i = 0; i <= n; ++i) {
    bool visible = false;
    if (i < n) {
      const Eigen::Vector3d q = a + (i + 0.5) / n * (b - a);
      const Eigen::Vector3d origin = frame.Unproject(frame.Project(q));
      const double depth = (q - origin).dot(frame.forward);
      visible = rays.Cast(origin, frame.forward) >= depth - tolerance;
      ++drawing->outline_samples;
      drawing->hidden_outline_samples += visible ? 0 : 1;
    }
    if (visible && run_start < 0) run_start = i;
    if (!visible && run_start >= 0) {
      segments->emplace_back(pa + (pb - pa) * run_start / n, pa + (pb - pa) * i / n);
      run_start = -1;
    }
  }
}

void DrawOutlines(const TriangleMesh& mesh,
                  const std::vector<std::vector<Eigen::Vector3d>>& feature_lines,
                  const Frame& frame, const ViewRays& rays, const PenAndInkOptions& options,
                  PenAndInkDrawing* drawing) {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segments;
  for (const auto& [u, v] : OutlineEdges(mesh, frame, options.crease_deg)) {
    AddVisibleRuns(mesh.vertices[u].cast<double>(), mesh.vertices[v].cast<double>(), frame, rays,
                   options, drawing, &segments);
  }
  for (const auto& line : feature_lines) {
    for (size_t i = 1; i < line.size(); ++i) {
      AddVisibleRuns(line[i - 1], line[i], frame, rays, options, drawing, &segments);
    }
  }
  drawing->outline = Chain(segments);
}

// ------------------------------------------------- hatching

// One family of hatching lines at `angle_deg`, where the tone exceeds `tone`.
void Hatch(const Frame& frame, const ViewRays& rays, const PenAndInkOptions& options,
           double angle_deg, double tone, PenAndInkDrawing* drawing) {
  const Eigen::Vector2d along(std::cos(angle_deg * kDegrees), std::sin(angle_deg * kDegrees));
  const Eigen::Vector2d across(-along.y(), along.x());
  const Eigen::Vector3d light = options.light_direction.normalized();
  const double w = drawing->width, h = drawing->height;
  double lo = INFINITY, hi = -INFINITY, s_lo = INFINITY, s_hi = -INFINITY;
  for (const Eigen::Vector2d& corner : {Eigen::Vector2d(0, 0), Eigen::Vector2d(w, 0),
                                        Eigen::Vector2d(0, h), Eigen::Vector2d(w, h)}) {
    lo = std::min(lo, corner.dot(across));
    hi = std::max(hi, corner.dot(across));
    s_lo = std::min(s_lo, corner.dot(along));
    s_hi = std::max(s_hi, corner.dot(along));
  }
  const int num_lines = static_cast<int>((hi - lo) / options.hatch_spacing_px);
  const double jump = kHatchDepthJumpPx / frame.scale;
  std::vector<std::vector<Polyline>> per_line(num_lines);
  tbb::parallel_for(0, num_lines, [&](int k) {
    const double offset = lo + (k + 0.5) * options.hatch_spacing_px;
    Polyline stroke;
    double last_depth = INFINITY;
    const auto finish = [&] {
      if (stroke.size() >= 2 && (stroke.back() - stroke.front()).norm() >= kMinHatchPx) {
        per_line[k].push_back({stroke.front(), stroke.back()});
      }
      stroke.clear();
    };
    for (double s = s_lo; s <= s_hi; s += kHatchStepPx) {
      const Eigen::Vector2d p = offset * across + s * along;
      if (p.x() < 0 || p.y() < 0 || p.x() > w || p.y() > h) {
        finish();
        continue;
      }
      Eigen::Vector3d normal;
      const double depth = rays.Cast(frame.Unproject(p), frame.forward, &normal);
      if (!std::isfinite(depth)) {
        finish();
        continue;
      }
      if (normal.dot(frame.forward) > 0) normal = -normal;  // the side seen
      const bool dark = 1 - std::max(0.0, normal.dot(light)) > tone;
      if (!dark || std::abs(depth - last_depth) > jump) finish();
      if (dark) stroke.push_back(p);
      last_depth = depth;
    }
    finish();
  });
  for (auto& lines : per_line) {
    for (Polyline& line : lines) drawing->hatching.push_back(std::move(line));
  }
}

// ------------------------------------------------- output

void Splat(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double width, float ink,
           FloatImage* image) {
  const double reach = width / 2 + 1;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min(a.x(), b.x()) - reach)));
  const int x1 =
      std::min(image->width() - 1, static_cast<int>(std::ceil(std::max(a.x(), b.x()) + reach)));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min(a.y(), b.y()) - reach)));
  const int y1 =
      std::min(image->height() - 1, static_cast<int>(std::ceil(std::max(a.y(), b.y()) + reach)));
  const Eigen::Vector2d d = b - a;
  const double length2 = std::max(d.squaredNorm(), 1e-12);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      const double t = std::clamp((p - a).dot(d) / length2, 0.0, 1.0);
      const double distance = (a + t * d - p).norm();
      const double coverage = std::clamp(width / 2 + 0.5 - distance, 0.0, 1.0);
      if (coverage <= 0) continue;
      const float value = 1.0f - static_cast<float>(coverage) * ink;
      for (int c = 0; c < 3; ++c) image->at(x, y, c) = std::min(image->at(x, y, c), value);
    }
  }
}

void AppendLayer(const char* name, const std::vector<Polyline>& lines, const char* style,
                 std::ostringstream* svg) {
  *svg << "  <g inkscape:groupmode=\"layer\" inkscape:label=\"" << name << "\" id=\"" << name
       << "\" style=\"" << style << "\">\n";
  char number[64];
  for (const Polyline& line : lines) {
    *svg << "    <polyline points=\"";
    for (size_t i = 0; i < line.size(); ++i) {
      std::snprintf(number, sizeof(number), "%s%.2f,%.2f", i == 0 ? "" : " ", line[i].x(),
                    line[i].y());
      *svg << number;
    }
    *svg << "\"/>\n";
  }
  *svg << "  </g>\n";
}

}  // namespace

PenAndInkView PenAndInkView::FromAngles(double azimuth_deg, double elevation_deg) {
  const double az = azimuth_deg * kDegrees, el = elevation_deg * kDegrees;
  PenAndInkView view;
  view.view_direction =
      Eigen::Vector3d(-std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), -std::sin(el));
  // Looking straight down, the picture's up is the front's far side (+y).
  view.up = std::abs(elevation_deg) > 89.9 ? Eigen::Vector3d(-std::sin(az), std::cos(az), 0)
                                           : Eigen::Vector3d::UnitZ();
  return view;
}

std::string PenAndInkDrawing::BriefReport() const {
  std::ostringstream out;
  out << width << " x " << height << " px: " << outline.size() << " outline strokes ("
      << hidden_outline_samples << " of " << outline_samples << " edge samples hidden), "
      << hatching.size() << " hatching strokes, " << construction.size() << " construction lines.";
  return out.str();
}

PenAndInkDrawing DrawPenAndInk(const TriangleMesh& mesh,
                               const std::vector<std::vector<Eigen::Vector3d>>& feature_lines,
                               const std::vector<std::vector<Eigen::Vector3d>>& construction,
                               const PenAndInkView& view, const PenAndInkOptions& options) {
  options.Check();
  mesh.Check();
  SYLVA_CHECK(view.view_direction.allFinite() && view.view_direction.norm() > 0)
      << "the view direction must be non-zero";
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3f& v : mesh.vertices) points.push_back(v.cast<double>());
  for (const auto& line : construction) points.insert(points.end(), line.begin(), line.end());
  for (const auto& line : feature_lines) points.insert(points.end(), line.begin(), line.end());
  SYLVA_CHECK(!points.empty()) << "nothing to draw";
  PenAndInkDrawing drawing;
  const Frame frame = MakeFrame(points, view, options, &drawing.width, &drawing.height);
  drawing.line_width[0] = options.outline_width_px;
  drawing.line_width[1] = options.hatch_width_px;
  drawing.line_width[2] = options.construction_width_px;
  const ViewRays rays(mesh);
  DrawOutlines(mesh, feature_lines, frame, rays, options, &drawing);
  Hatch(frame, rays, options, kHatchAngleDeg, options.hatch_tone, &drawing);
  Hatch(frame, rays, options, kCrossHatchAngleDeg, options.cross_hatch_tone, &drawing);
  for (const auto& line : construction) {
    if (!options.construction) break;
    Polyline projected;
    for (const Eigen::Vector3d& p : line) projected.push_back(frame.Project(p));
    drawing.construction.push_back(std::move(projected));
  }
  return drawing;
}

std::string PenAndInkSvg(const PenAndInkDrawing& drawing) {
  std::ostringstream svg;
  svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" "
         "xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" width=\""
      << drawing.width << "\" height=\"" << drawing.height << "\" viewBox=\"0 0 " << drawing.width
      << " " << drawing.height << "\">\n"
      << "  <rect x=\"0\" y=\"0\" width=\"" << drawing.width << "\" height=\"" << drawing.height
      << "\" fill=\"white\"/>\n";
  const auto style = [](const char* colour, double width, const char* extra) {
    std::ostringstream s;
    s << "fill:none;stroke:" << colour << ";stroke-width:" << width
      << ";stroke-linecap:round;stroke-linejoin:round" << extra;
    return s.str();
  };
  AppendLayer("hatching", drawing.hatching, style("#000000", drawing.line_width[1], "").c_str(),
              &svg);
  AppendLayer("outline", drawing.outline, style("#000000", drawing.line_width[0], "").c_str(),
              &svg);
  AppendLayer("construction", drawing.construction,
              style("#808080", drawing.line_width[2], ";stroke-dasharray:4,3").c_str(), &svg);
  svg << "</svg>\n";
  return svg.str();
}

void WritePenAndInkSvg(const std::filesystem::path& path, const PenAndInkDrawing& drawing) {
  AtomicWriteString(path, PenAndInkSvg(drawing));
}

FloatImage RasterizePenAndInk(const PenAndInkDrawing& drawing) {
  FloatImage image(drawing.width, drawing.height, 3, 1.0f);
  const auto draw = [&](const std::vector<Polyline>& lines, double width, float ink) {
    for (const Polyline& line : lines) {
      for (size_t i = 1; i < line.size(); ++i) Splat(line[i - 1], line[i], width, ink, &image);
    }
  };
  draw(drawing.construction, drawing.line_width[2], kConstructionInk);
  draw(drawing.hatching, drawing.line_width[1], 1.0f);
  draw(drawing.outline, drawing.line_width[0], 1.0f);
  return image;
}

}  // namespace sylva
