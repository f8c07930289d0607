#include "mesh/mesh_rasterizer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace sylva {
namespace {

// The picture's sample rows are cut into bands drawn in parallel, each
// writing its own rows only: this many per thread, of at least this many rows.
constexpr int kBandsPerThread = 4;
constexpr int kMinBandRows = 16;
// Triangles fewer samples across than this have no row spans computed.
constexpr int kNarrowSamples = 4;
// Beyond this many pixels from the picture a projected vertex would cost the
// edge functions too much precision to agree with the rays: cast rays.
constexpr double kMaxOffPicture = 1e6;

// A vertex in image coordinates (pixels) and its depth key: a smaller key
// is nearer. Perspective: -1/z, linear in the picture; orthographic: z.
struct Projected {
  double x = 0.0, y = 0.0, key = 0.0;
};

// One edge of a triangle, evaluated as (q - p) x (sample - p) with p, q its
// ends in lexicographic order, times `sign` for the triangle's direction:
// both triangles sharing an edge compute the same value, so a sample on it
// is inside one of them at least.
struct Edge {
  double px, py, dx, dy, sign;

  Edge(const Projected& from, const Projected& to) {
    const bool swap = to.x < from.x || (to.x == from.x && to.y < from.y);
    const Projected& p = swap ? to : from;
    const Projected& q = swap ? from : to;
    px = p.x;
    py = p.y;
    dx = q.x - p.x;
    dy = q.y - p.y;
    sign = swap ? -1.0 : 1.0;
  }
  double At(double x, double y) const { return sign * (dx * (y - py) - dy * (x - px)); }
};

// Samples of the picture, in image coordinates.
struct SampleGrid {
  int width = 0, height = 0, samples_per_axis = 1;
  double step = 1.0;  // 1 / samples_per_axis: a product per sample, not a quotient
  double X(int a) const { return (a + 0.5) * step; }
  double Y(int b) const { return (b + 0.5) * step; }
};

// floor and ceil of a double well within int's range, without the library
// calls (the build targets baseline x86-64, which has no rounding opcode).
int Floor(double x) {
  const int i = static_cast<int>(x);
  return i > x ? i - 1 : i;
}
int Ceil(double x) {
  const int i = static_cast<int>(x);
  return i < x ? i + 1 : i;
}

// Where a row of samples crosses one edge's line (x = px + run (y - py)),
// and which side of it is inside: x >= the crossing (bound +1), x <= it
// (-1), or no bound from a horizontal edge (0).
struct EdgeSpan {
  double px = 0.0, py = 0.0, run = 0.0;
  int bound = 0;

  EdgeSpan() = default;
  EdgeSpan(const Edge& edge, double orientation) : px(edge.px), py(edge.py) {
    // The inside's edge function grows with x by -orientation * sign * dy.
    const double growth = -orientation * edge.sign * edge.dy;
    bound = growth > 0.0 ? 1 : growth < 0.0 ? -1 : 0;
    run = edge.dy != 0.0 ? edge.dx / edge.dy : 0.0;
  }
  double CrossingX(double y) const { return px + run * (y - py); }
};

// Rasterizes triangle `t` into the sample rows [row_begin, row_end).
void RasterizeTriangle(const std::vector<Projected>& projected, const Eigen::Vector3i& triangle,
                       int t, const SampleGrid& grid, int row_begin, int row_end, bool nearest,
                       std::vector<double>* keys, std::vector<int>* sample_triangles) {
  const Projected& v0 = projected[triangle[0]];
  const Projected& v1 = projected[triangle[1]];
  const Projected& v2 = projected[triangle[2]];
  const double s = grid.samples_per_axis;
  // Sample rows and columns within the triangle's bounds.
  const int b0 = std::max(row_begin, Ceil(std::min({v0.y, v1.y, v2.y}) * s - 0.5));
  const int b1 = std::min(row_end - 1, Floor(std::max({v0.y, v1.y, v2.y}) * s - 0.5));
  const int a0 = std::max(0, Ceil(std::min({v0.x, v1.x, v2.x}) * s - 0.5));
  const int a1 = std::min(grid.width - 1, Floor(std::max({v0.x, v1.x, v2.x}) * s - 0.5));
  if (b0 > b1 || a0 > a1) return;
  // Weights of v0, v1, v2 at a sample: the edges opposite them.
  const Edge e0(v1, v2), e1(v2, v0), e2(v0, v1);
  const double area = e0.At(v0.x, v0.y);
  if (area == 0.0 || !std::isfinite(area)) return;  // edge-on: no ray hits it
  const bool positive = area > 0.0;
  const double inverse_area = 1.0 / area;
  const double orientation = positive ? 1.0 : -1.0;
  // Most triangles of a tree (leaves, twigs) are a few samples across: test
  // their bounds' samples directly; wider ones find each row's span first.
  const bool narrow = a1 - a0 < kNarrowSamples;
  EdgeSpan spans[3];
  if (!narrow) {
    const Edge* edges[3] = {&e0, &e1, &e2};
    for (int e = 0; e < 3; ++e) spans[e] = EdgeSpan(*edges[e], orientation);
  }
  for (int b = b0; b <= b1; ++b) {
    const double y = grid.Y(b);
    const size_t row = static_cast<size_t>(b) * grid.width;
    // The row's span from each edge, widened by a sample on either side for
    // rounding; the exact test below decides.
    double low = a0, high = a1;
    for (int e = 0; e < 3 && !narrow; ++e) {
      const EdgeSpan& span = spans[e];
      if (span.bound > 0) {
        low = std::max(low, span.CrossingX(y) * s - 1.5);
      } else if (span.bound < 0) {
        high = std::min(high, span.CrossingX(y) * s + 0.5);
      }
    }
    if (!(low <= high)) continue;
    // Branch-free: a tree's small triangles leave the inside test to chance.
    // The edge functions times the orientation (+-1, exact) are all >= 0
    // inside (the vertices are finite, so no NaN).
    int* triangles = sample_triangles->data() + row;
    double* row_keys = nearest ? keys->data() + row : nullptr;
    for (int a = Ceil(low), end = Floor(high); a <= end; ++a) {
      const double x = grid.X(a);
      const double w0 = e0.At(x, y), w1 = e1.At(x, y), w2 = e2.At(x, y);
      const bool inside = std::min({orientation * w0, orientation * w1, orientation * w2}) >= 0.0;
      if (!nearest) {
        triangles[a] = inside && triangles[a] < 0 ? t : triangles[a];
        continue;
      }
      const double key = (w0 * v0.key + w1 * v1.key + w2 * v2.key) * inverse_area;
      const bool nearer = inside && key < row_keys[a];
      row_keys[a] = nearer ? key : row_keys[a];
      triangles[a] = nearer ? t : triangles[a];
    }
  }
}

}  // namespace

bool RasterizeSamples(const RasterMesh& mesh, const Camera& camera, const Rigid3d& cam_from_world,
                      int samples_per_axis, bool nearest, std::vector<int>* sample_triangles) {
  sample_triangles->clear();
  if (camera.HasDistortion()) return false;
  const bool orthographic = camera.IsOrthographic();
  const Eigen::Matrix3d rotation = cam_from_world.rotation.toRotationMatrix();
  const double reach = kMaxOffPicture + std::max(camera.width(), camera.height());
  std::vector<Projected> projected(mesh.vertices.size());
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    for (int k = 0; k < 3; ++k) used[triangle[k]] = 1;
  }
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!used[v]) continue;
    const Eigen::Vector3d in_cam =
        rotation * mesh.vertices[v].cast<double>() + cam_from_world.translation;
    if (!orthographic && !(in_cam.z() > 0.0)) return false;
    const Eigen::Vector2d xy = camera.ImgFromCam(in_cam);
    if (!(std::abs(xy.x()) < reach && std::abs(xy.y()) < reach)) return false;
    projected[v] = {xy.x(), xy.y(), orthographic ? in_cam.z() : -1.0 / in_cam.z()};
  }

  SampleGrid grid;
  grid.samples_per_axis = samples_per_axis;
  grid.step = 1.0 / samples_per_axis;
  grid.width = camera.width() * samples_per_axis;
  grid.height = camera.height() * samples_per_axis;
  // Each triangle's sample rows (empty where it misses the picture).
  std::vector<std::pair<int, int>> triangle_rows(mesh.triangles.size(), {0, -1});
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (int k = 0; k < 3; ++k) {
      low = std::min(low, projected[mesh.triangles[t][k]].y);
      high = std::max(high, projected[mesh.triangles[t][k]].y);
    }
    triangle_rows[t] = {std::max(0, Ceil(low * samples_per_axis - 0.5)),
                        std::min(grid.height - 1, Floor(high * samples_per_axis - 0.5))};
  }
  const size_t num_samples = static_cast<size_t>(grid.width) * grid.height;
  sample_triangles->assign(num_samples, -1);
  std::vector<double> keys;
  if (nearest) keys.assign(num_samples, std::numeric_limits<double>::infinity());
  // A few bands per thread, each walking all triangles in index order (the
  // mesh's order keeps neighbours together in memory; ties keep the lowest
  // index) and drawing those that reach it.
  const int num_bands = std::clamp(grid.height / kMinBandRows, 1,
                                   kBandsPerThread * tbb::this_task_arena::max_concurrency());
  tbb::parallel_for(tbb::blocked_range<int>(0, num_bands), [&](const tbb::blocked_range<int>& r) {
    for (int band = r.begin(); band < r.end(); ++band) {
      const int row_begin = static_cast<int>(static_cast<int64_t>(grid.height) * band / num_bands);
      const int row_end =
          static_cast<int>(static_cast<int64_t>(grid.height) * (band + 1) / num_bands);
      for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto [first_row, last_row] = triangle_rows[t];
        if (first_row >= row_end || last_row < row_begin) continue;
        RasterizeTriangle(projected, mesh.triangles[t], static_cast<int>(t), grid, row_begin,
                          row_end, nearest, &keys, sample_triangles);
      }
    }
  });
  return true;
}

}  // namespace sylva
