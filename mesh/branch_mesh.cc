#include "mesh/branch_mesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/util/check.h"
#include "mesh/bspline.h"

namespace sylva {
namespace {

// Consecutive axis nodes closer than this fraction of their distance from
// the origin (plus one world unit's fraction) count as coincident.
constexpr double kCoincidentFraction = 1e-9;
// A spline derivative shorter than this fraction of the segment's chord
// counts as zero; the chord direction is used instead.
constexpr double kDegenerateDerivative = 1e-9;

double MaxRadius(const SkeletonGraph& skeleton) {
  double max_radius = 0.0;
  for (const SkeletonNode& node : skeleton.nodes) max_radius = std::max(max_radius, node.radius);
  return max_radius;
}

bool Coincident(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).norm() <= kCoincidentFraction * (1.0 + b.norm());
}

// Unit tangent of the tube's spline at u, or the segment's chord direction
// where the derivative vanishes (control points doubling back).
Eigen::Vector3d TangentAt(const CubicBSpline& spline, double u) {
  int segment;
  double t;
  spline.Locate(u, &segment, &t);
  const Eigen::Vector3d chord = spline.ControlPoint(segment + 1) - spline.ControlPoint(segment);
  const Eigen::Vector3d derivative = spline.Derivative(u);
  if (derivative.norm() <= kDegenerateDerivative * chord.norm()) return chord.normalized();
  return derivative.normalized();
}

// PlanBranchTubes, also counting the axes without length in `skipped` (may be null).
std::vector<BranchTube> PlanTubes(const SkeletonGraph& skeleton, const BranchMeshOptions& options,
                                  int* skipped) {
  options.Check();
  CheckSkeletonInput(skeleton);
  std::vector<BranchTube> tubes;
  if (skeleton.NumNodes() < 2) return tubes;
  const double max_radius = MaxRadius(skeleton);
  SYLVA_CHECK_INPUT(max_radius > 0, "skeleton")
      << "all radii are zero; assign radii first (e.g. AssignPipeModelRadii)";
  const std::vector<BranchAxis> axes = skeleton.BranchAxes();
  for (size_t a = 0; a < axes.size(); ++a) {
    BranchTube tube = PlanAxisTube(skeleton, axes[a], a == 0, max_radius, options);
    if (tube.sides > 0) {
      tubes.push_back(std::move(tube));
    } else if (skipped != nullptr) {
      ++*skipped;
    }
  }
  return tubes;
}

}  // namespace

std::string BranchMeshSummary::BriefReport() const {
  std::ostringstream out;
  out << "Branch mesh: " << axes << " tubes";
  if (skipped_axes > 0) out << " (" << skipped_axes << " zero-length axes skipped)";
  out << ", " << rings << " rings, " << triangles << " triangles in " << seconds
      << " s; radii: " << radius_source << ".";
  return out.str();
}

void CheckSkeletonInput(const SkeletonGraph& skeleton) {
  try {
    skeleton.Check();
  } catch (const InputError&) {
    throw;
  } catch (const Error& error) {
    SYLVA_INPUT_ERROR("skeleton") << error.what();
  }
}

int TubeSides(double axis_radius, double max_radius, const BranchMeshOptions& options) {
  const int sides = static_cast<int>(std::ceil(options.max_sides * axis_radius / max_radius));
  return std::clamp(sides, options.min_sides, options.max_sides);
}

int TubeRingsPerSegment(double edge_length, const BranchMeshOptions& options) {
  const double by_length = std::ceil(options.rings_per_unit_length * edge_length);
  const double rings = std::max(static_cast<double>(options.rings_per_segment), by_length);
  return static_cast<int>(std::min(rings, static_cast<double>(kMaxBranchRingsPerSegment)));
}

int BranchTube::NumRings() const {
  int rings = 1;
  for (int r : rings_per_segment) rings += r;
  return rings;
}

int BranchTube::NumVertices() const { return sides * NumRings() + 2; }

int BranchTube::NumTriangles() const { return 2 * sides * (NumRings() - 1) + 2 * sides; }

BranchTube PlanAxisTube(const SkeletonGraph& skeleton, const BranchAxis& axis, bool is_trunk,
                        double max_radius, const BranchMeshOptions& options) {
  BranchTube tube;
  if (axis.size() < 2) return tube;
  for (size_t k = 0; k < axis.size(); ++k) {
    const SkeletonNode& node = skeleton.nodes[axis[k]];
    // A lateral's junction ring takes the lateral's first edge radius.
    const double radius = (k == 0 && !is_trunk) ? skeleton.nodes[axis[1]].radius : node.radius;
    if (!tube.control_points.empty() && Coincident(node.position, tube.control_points.back())) {
      tube.radii.back() = radius;
      continue;
    }
    tube.control_points.push_back(node.position);
    tube.radii.push_back(radius);
  }
  if (tube.control_points.size() < 2) return BranchTube();
  for (size_t k = 0; k + 1 < tube.control_points.size(); ++k) {
    const double length = (tube.control_points[k + 1] - tube.control_points[k]).norm();
    tube.rings_per_segment.push_back(TubeRingsPerSegment(length, options));
  }
  const double axis_radius = *std::max_element(tube.radii.begin(), tube.radii.end());
  tube.sides = TubeSides(axis_radius, max_radius, options);
  tube.circle_area = options.circle_area;
  return tube;
}

std::vector<BranchTube> PlanBranchTubes(const SkeletonGraph& skeleton,
                                        const BranchMeshOptions& options) {
  return PlanTubes(skeleton, options, nullptr);
}

double PolygonAreaRadiusScale(int sides) {
  SYLVA_CHECK(sides >= 3);
  return std::sqrt(2 * M_PI / (sides * std::sin(2 * M_PI / sides)));
}

std::vector<TubeRing> SampleTubeRings(const BranchTube& tube) {
  return SampleTubeRings(tube, std::numeric_limits<int>::max());
}

std::vector<TubeRing> SampleTubeRings(const BranchTube& tube, int max_rings) {
  const CubicBSpline spline(tube.control_points);
  std::vector<double> parameters;
  parameters.reserve(tube.NumRings());
  for (size_t k = 0; k < tube.rings_per_segment.size(); ++k) {
    const int rings = tube.rings_per_segment[k];
    for (int s = 0; s < rings; ++s) parameters.push_back(k + static_cast<double>(s) / rings);
  }
  parameters.push_back(spline.NumSegments());
  std::vector<Eigen::Vector3d> tangents;
  tangents.reserve(parameters.size());
  for (double u : parameters) tangents.push_back(TangentAt(spline, u));
  // The first frame's normal looks at every tangent, the others at those
  // before them.
  const Eigen::Vector3d initial_normal = InitialNormal(tangents);
  if (tangents.size() > static_cast<size_t>(std::max(max_rings, 1))) {
    tangents.resize(std::max(max_rings, 1));
  }
  const std::vector<CurveFrame> frames = ParallelTransportFrames(tangents, initial_normal);
  const double area_scale =
      tube.circle_area && tube.sides >= 3 ? PolygonAreaRadiusScale(tube.sides) : 1.0;
  std::vector<TubeRing> rings(frames.size());
  for (size_t i = 0; i < rings.size(); ++i) {
    int k;
    double t;
    spline.Locate(parameters[i], &k, &t);
    rings[i].center = spline.Evaluate(parameters[i]);
    rings[i].frame = frames[i];
    rings[i].radius = area_scale * ((1 - t) * tube.radii[k] + t * tube.radii[k + 1]);
  }
  return rings;
}

void AppendTube(const std::vector<TubeRing>& rings, int sides, int material, TriangleMesh* mesh,
                bool base_cap, bool tip_cap) {
  SYLVA_CHECK(rings.size() >= 2 && sides >= 3);
  std::vector<double> cosines(sides), sines(sides);
  for (int j = 0; j < sides; ++j) {
    cosines[j] = std::cos(2 * M_PI * j / sides);
    sines[j] = std::sin(2 * M_PI * j / sides);
  }
  // Ring vertices, eq. 5.24; vertex j of ring i is first + i * sides + j.
  const int first = mesh->NumVertices();
  for (const TubeRing& ring : rings) {
    const Eigen::Vector3d n = ring.radius * ring.frame.normal;
    const Eigen::Vector3d b = ring.radius * ring.frame.binormal;
    for (int j = 0; j < sides; ++j) {
      mesh->AddVertex((ring.center + cosines[j] * n + sines[j] * b).cast<float>());
    }
  }
  // Sides: (i, j), (i, j+1), (i+1, j+1) and (i, j), (i+1, j+1), (i+1, j)
  // turn counter-clockwise seen from outside, since B = T x N.
  const int num_rings = static_cast<int>(rings.size());
  for (int i = 0; i + 1 < num_rings; ++i) {
    const int ring = first + i * sides, next = ring + sides;
    for (int j = 0; j < sides; ++j) {
      const int j1 = (j + 1) % sides;
      mesh->AddTriangle(ring + j, ring + j1, next + j1, material);
      mesh->AddTriangle(ring + j, next + j1, next + j, material);
    }
  }
  // Caps: the base faces -T, the tip +T.
  const int last = first + (num_rings - 1) * sides;
  const int base = base_cap ? mesh->AddVertex(rings.front().center.cast<float>()) : -1;
  const int tip = tip_cap ? mesh->AddVertex(rings.back().center.cast<float>()) : -1;
  for (int j = 0; j < sides; ++j) {
    const int j1 = (j + 1) % sides;
    if (base_cap) mesh->AddTriangle(base, first + j1, first + j, material);
    if (tip_cap) mesh->AddTriangle(tip, last + j, last + j1, material);
  }
}

TriangleMesh MeshBranches(const SkeletonGraph& skeleton, const BranchMeshOptions& options,
                          BranchMeshSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  BranchMeshSummary local;
  if (summary == nullptr) summary = &local;
  *summary = BranchMeshSummary();
  summary->radius_source = skeleton.radius_source;
  const std::vector<BranchTube> tubes = PlanTubes(skeleton, options, &summary->skipped_axes);
  TriangleMesh mesh;
  const int material = mesh.AddMaterial(options.bark);
  int64_t num_vertices = 0, num_triangles = 0;
  for (const BranchTube& tube : tubes) {
    num_vertices += tube.NumVertices();
    num_triangles += tube.NumTriangles();
  }
  mesh.vertices.reserve(num_vertices);
  mesh.triangles.reserve(num_triangles);
  mesh.triangle_materials.reserve(num_triangles);
  for (const BranchTube& tube : tubes) {
    AppendTube(SampleTubeRings(tube), tube.sides, material, &mesh);
    summary->rings += tube.NumRings();
  }
  summary->axes = static_cast<int>(tubes.size());
  summary->triangles = mesh.NumTriangles();
  summary->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return mesh;
}

}  // namespace sylva
