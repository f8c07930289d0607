// Branch geometry as generalized cylinders (thesis 5.2).
//
// Every branch axis of SkeletonGraph::BranchAxes() becomes one closed tube:
//   1. its node positions are the control points of an open uniform cubic
//      B-spline (mesh/bspline.h), so the axis is smooth and starts exactly
//      at its first node (for a lateral, the junction on its parent axis);
//   2. the spline is sampled at rings_per_segment rings per skeleton edge;
//   3. parallel-transport frames (mesh/frames.h) orient the rings without
//      flips or needless twist;
//   4. a regular polygon of `sides` vertices, radius interpolated linearly
//      between the nodes' radii, is swept along (eq. 5.24), consecutive rings
//      are joined by two triangles per side, and both ends are closed by a
//      flat cap (a fan around a centre vertex).
// Each tube is a closed, consistently oriented 2-manifold (outward normals,
// counter-clockwise seen from outside). Tubes of laterals start at the
// junction and overlap their parent there: bifurcations are not yet stitched
// watertight (thesis 5.3), which renders fine and leaves every tube closed.
//
// Radius along an axis: the ring at node k has the radius of the edge that
// arrives at node k (SkeletonNode::radius); the ring at a lateral's junction
// node takes the radius of the lateral's first edge, not the parent's.
//
// Sides: a tube has ceil(max_sides * r_axis / r_max) sides, clamped to
// [min_sides, max_sides], where r_axis is the largest ring radius of the axis
// and r_max the largest radius in the skeleton: the trunk gets max_sides and
// the count falls with the radius, independent of the world unit.
#ifndef SYLVA_MESH_BRANCH_MESH_H_
#define SYLVA_MESH_BRANCH_MESH_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"
#include "mesh/frames.h"

namespace sylva {

// Upper bounds of BranchMeshOptions that keep a typo from asking for
// billions of triangles.
inline constexpr int kMaxBranchRingsPerSegment = 256;
inline constexpr int kMaxBranchSides = 256;

struct BranchMeshOptions {
  // Rings sampled on each spline segment (one per skeleton edge), at least;
  // in [1, 256]. The tip adds one ring per axis.
  int rings_per_segment = 3;
  // Additionally at least this many rings per world unit of edge length, so
  // long edges bend smoothly (>= 0; 0 = off). Capped at 256 per segment.
  double rings_per_unit_length = 0.0;
  // Sides of the cross-section polygon, see the header comment;
  // 3 <= min_sides <= max_sides <= 256.
  int min_sides = 4;
  int max_sides = 24;
  // Ring polygons with the circle's area (PolygonAreaRadiusScale), so a tube
  // holds the volume of the cylinders it stands for (an inscribed square
  // holds 64 % of it, a hexagon 83 %). Off by default: the bark mesher's
  // attachments of thin laterals on sparse (4-6 sided) parents fail more
  // often with the larger polygons (a twig-pruned synthetic tree: 41 of
  // ~500 laterals left overlapping). mesh-qsm turns it on.
  bool circle_area = false;
  // The material of every branch triangle (single-sided: tubes are closed).
  Material bark = {"bark", Eigen::Vector3f(0.36f, 0.26f, 0.18f), false};

  // Throws InputError("BranchMesh.<field>", ...) naming the violated constraint.
  void Check() const;
};

struct BranchMeshSummary {
  int axes = 0;          // branch axes meshed (one closed tube each)
  int skipped_axes = 0;  // axes of coincident nodes only (no length)
  int rings = 0;         // cross-sections swept, over all tubes
  int triangles = 0;
  double seconds = 0.0;
  // The skeleton's radius_source ("allometric prior" for reconstructions):
  // the tube radii are that, not a measurement.
  std::string radius_source;

  // One line for humans.
  std::string BriefReport() const;
};

// Bark tubes for every branch axis of `skeleton`, with one material
// (options.bark). `summary` may be null. Throws InputError("skeleton", ...)
// for a skeleton failing SkeletonGraph::Check() (negative or non-finite radii,
// non-finite positions, cycles), or one whose radii are all zero (assign
// radii first, e.g. AssignPipeModelRadii); InputError for bad options.
// Deterministic.
TriangleMesh MeshBranches(const SkeletonGraph& skeleton, const BranchMeshOptions& options,
                          BranchMeshSummary* summary);

// ---- The pieces, for tests and benchmarks ----

// One branch axis prepared for sweeping: everything MeshBranches decides
// before it builds geometry.
struct BranchTube {
  // The axis' node positions in world units, consecutive coincident nodes
  // merged (the later one's radius kept); at least 2.
  std::vector<Eigen::Vector3d> control_points;
  // Ring radius at each control point, world units (>= 0).
  std::vector<double> radii;
  // Rings sampled on each spline segment (control_points.size() - 1 of them).
  std::vector<int> rings_per_segment;
  int sides = 0;
  // Ring polygons with the circle's area (BranchMeshOptions::circle_area).
  bool circle_area = false;

  int NumRings() const;      // all segments' rings plus the tip ring
  int NumVertices() const;   // sides per ring plus the two cap centres
  int NumTriangles() const;  // 2 sides per ring gap plus sides per cap
};

// The tubes MeshBranches sweeps, in BranchAxes() order, without the
// skipped axes. Validates like MeshBranches.
std::vector<BranchTube> PlanBranchTubes(const SkeletonGraph& skeleton,
                                        const BranchMeshOptions& options);

// The tube of one `axis` (node indices of `skeleton`, as BranchAxes() lists
// them), planned as PlanBranchTubes plans it: `is_trunk` for the root axis,
// else the first ring takes the radius of the axis' first edge; sides from
// TubeSides(axis radius, `max_radius`). An axis whose nodes all coincide
// gives an empty tube (sides == 0). No validation (callers check).
BranchTube PlanAxisTube(const SkeletonGraph& skeleton, const BranchAxis& axis, bool is_trunk,
                        double max_radius, const BranchMeshOptions& options);

// A cross-section of a tube: centre on the spline, frame, radius.
struct TubeRing {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // world units
  CurveFrame frame;
  double radius = 0.0;  // world units
};

// The tube's rings: spline samples at u = k + s / rings_per_segment[k]
// (s = 0..rings-1, for every segment k) and u = last, framed by parallel
// transport, radii interpolated linearly in u between the control points (and
// scaled by PolygonAreaRadiusScale(sides) if tube.circle_area).
std::vector<TubeRing> SampleTubeRings(const BranchTube& tube);
// Its first `max_rings` rings (at least one), the same as the whole tube's.
std::vector<TubeRing> SampleTubeRings(const BranchTube& tube, int max_rings);

// Appends the closed tube through `rings` (at least 2) with `sides` sides:
// ring vertex j at center + radius (cos(2 pi j / sides) N + sin(...) B),
// two triangles per side between consecutive rings, a cap fan at each end.
// Vertex j of ring i gets index mesh->NumVertices() (before the call) +
// i * sides + j; the cap centres follow. Without a cap the tube is open at
// that end: its side triangles use the directed ring edges j -> j + 1 on the
// first ring and j + 1 -> j on the last one.
void AppendTube(const std::vector<TubeRing>& rings, int sides, int material, TriangleMesh* mesh,
                bool base_cap = true, bool tip_cap = true);

// SkeletonGraph::Check() as an input error (the skeleton is the user's
// data): throws InputError("skeleton", ...) naming the broken invariant.
void CheckSkeletonInput(const SkeletonGraph& skeleton);

// Sides of a tube whose largest radius is `axis_radius` in a skeleton whose
// largest radius is `max_radius` (> 0): see the header comment.
int TubeSides(double axis_radius, double max_radius, const BranchMeshOptions& options);
// The circumradius of a regular polygon of `sides` (>= 3) sides with the
// area of the unit circle: sqrt(2 pi / (sides sin(2 pi / sides))), 1.253 for
// 4 sides, 1.0057 for 24 (BranchMeshOptions::circle_area).
double PolygonAreaRadiusScale(int sides);
// Rings on a spline segment (skeleton edge) of length `edge_length`.
int TubeRingsPerSegment(double edge_length, const BranchMeshOptions& options);

}  // namespace sylva

#endif  // SYLVA_MESH_BRANCH_MESH_H_
