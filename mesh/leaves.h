// Leaves (thesis 5.4): leaves on the thin branches (and twigs, mesh/twigs.h),
// as many as the density's leaf area implies and placed in proportion to it,
// either drawn freely near the branches or at phyllotactic nodes along them
// (mesh/phyllotaxis.h), turned towards the light by phototropism, and dropped
// where they project outside the mattes. Every leaf is one copy of a leaf
// shape (a built-in polygon or a textured quad from a user's image) under
// its own rigid transform + scale, so exporters can instance it
// (GenerateLeafInstances); GenerateLeaves bakes the copies into triangles.
// Trees without photos (gestures, MRF sketches, QSMs) have no density: their
// leaves follow the thin branches alone (GenerateSkeletonLeafInstances).
#ifndef SYLVA_MESH_LEAVES_H_
#define SYLVA_MESH_LEAVES_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types/density_grid.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"

namespace sylva {

struct LeafOptions {
  // Leaves to place; -1 = none (leafless plants). 0 (the default) = as many
  // as the density's leaf area
  // implies: by Beer-Lambert with randomly oriented leaves (projection
  // factor G = 0.5), a voxel of side s and optical depth x (per voxel length)
  // holds a leaf area of x s^2 / G. Leaves are drawn in proportion to the
  // density until this many pass the branch-reach and matte tests (or
  // max_draws_factor times as many were drawn).
  int num_leaves = 0;
  // Upper bound on the automatic count.
  int max_leaves = 200000;
  double max_draws_factor = 3.0;
  // Leaf length in world units; 0 = leaf_length_fraction x tree height.
  double leaf_length = 0.0;
  double leaf_length_fraction = 0.012;
  // Leaf width / length.
  double leaf_aspect = 0.6;
  // A leaf must be within this many leaf lengths of a thin branch (the twig
  // that carries it); farther draws are dropped.
  double twig_reach = 4.0;
  // Branches at most this fraction of the trunk radius carry leaves.
  double thin_branch_radius_fraction = 0.35;
  // 0: random orientation about the leaf's axis; 1: the leaf's normal turned
  // as close as possible to the outward direction from the crown centre
  // (thesis: n_opt = (a - z) / |a - z|). Halfway by default: fully turned
  // leaves are seen edge-on at the crown's silhouette, and the leaf count
  // from the leaf area assumes orientations near random (G = 0.5); at 0.8
  // the synthetic trees' silhouettes lost 2-4 % IoU.
  double phototropism = 0.5;
  // A leaf whose projected footprint has a mean matte value below this in
  // any view that sees it is dropped (thesis: "projected to empty or very
  // sparse regions"); alpha.
  double matte_threshold = 0.1;
  // Built-in leaf shape (BuiltinLeafShape): "quad" (a rhombus, the first
  // version's leaf), "ovate", "lanceolate", "needle". A user's image replaces
  // it through GenerateLeafInstances' `shape` argument.
  std::string shape = "quad";
  // "none": leaves drawn freely in proportion to the density near thin
  // branches (the first version). A pattern of ParsePhyllotaxisPattern
  // ("alternate", "opposite_decussate", "whorled", "spiral"): leaves sit at
  // phyllotactic nodes along the thin branches, and of those nodes' leaves a
  // density-weighted choice is kept, as many as the leaf area implies (at
  // most all of them).
  std::string phyllotaxis = "none";
  // Phyllotaxis: distance between nodes along a branch, in leaf lengths.
  double internode = 0.6;
  // Phyllotaxis: see PhyllotaxisOptions (0 = the pattern's divergence).
  double divergence_deg = 0.0;
  int leaves_per_whorl = 3;
  double insertion_deg = 60.0;
  uint64_t seed = 1;

  // Throws InputError("Leaves.<field>", ...).
  void Check() const;
};

struct LeafSummary {
  int64_t target = 0;  // leaves wanted (num_leaves or from the leaf area)
  int64_t drawn = 0;
  int64_t kept = 0;
  int64_t far_from_branches = 0;
  int64_t outside_mattes = 0;
  int64_t phyllotaxis_sites = 0;  // leaf positions offered by the pattern
  double leaf_length = 0.0;       // world units
  // How GenerateSkeletonLeafInstances placed the leaves ("spiral
  // phyllotaxis", ...); empty for GenerateLeafInstances, whose draws and
  // tests the brief reports instead.
  std::string placement;
  std::string BriefReport() const;
  // Adds `other`'s counts (the leaves of another part of one tree).
  void Add(const LeafSummary& other);
};

// One leaf in its own frame, in units of leaf length: +X along the midrib
// from the base (x = 0, where the petiole meets the branch) to the tip
// (x = 1), +Y across, +Z the normal of the upper face; triangles are
// counter-clockwise seen from +Z.
struct LeafShape {
  std::string name;
  std::vector<Eigen::Vector2f> points;     // (x, y)
  std::vector<Eigen::Vector3i> triangles;  // into points
  // Texture coordinates per point (glTF convention: (0, 0) = the image's
  // top-left corner), and the RGBA texture whose alpha masks the leaf; both
  // empty for untextured shapes.
  std::vector<Eigen::Vector2f> uvs;
  FloatImage texture;

  // Throws Error on bad indices, UVs not matching points, or a texture that
  // is not RGBA.
  void Check() const;
};

// "quad": the rhombus base, (0.5, +-aspect/2), tip; "ovate" (widest at 3/8 of
// the length) and "lanceolate" (widest at 1/4, tapering to a long point):
// 14-point outlines fanned from a point on the midrib; "needle": a thin
// rhombus of width min(aspect, 0.05). `aspect` = width / length.
// Throws InputError("Leaves.shape", ...) for other names.
LeafShape BuiltinLeafShape(const std::string& name, double aspect);
// Throws InputError("Leaves.shape", ...) unless `name` is one of those shapes.
void CheckBuiltinLeafShapeName(const std::string& name);

// A textured quad from an RGBA image of one leaf (upright: petiole at the
// bottom row, tip at the top; alpha = 0 off the leaf): the quad spans the
// alpha > alpha_threshold bounding box, one leaf length high and as wide as
// the box's aspect implies. Throws InputError(`source`, ...) if the image is
// not 4-channel or holds no leaf.
LeafShape LeafShapeFromImage(const FloatImage& rgba, const std::string& source,
                             float alpha_threshold = 0.5f);

// One leaf: world_point = translation + scale * rotation * (x, y, 0) for a
// shape point (x, y); scale = the leaf length (world units).
struct LeafInstance {
  Eigen::Vector3f translation = Eigen::Vector3f::Zero();
  Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
  float scale = 1.0f;
};

struct LeafInstances {
  LeafShape shape;
  Material material;  // "leaves", double-sided
  std::vector<LeafInstance> instances;

  // The copies as triangles (shape points in order per leaf), material
  // `material`, no texture coordinates.
  TriangleMesh Bake() const;
};

// `skeleton` needs radii; `mattes` are one per view of `views` (may be empty
// to skip the matte test). `shape` (optional) replaces options.shape, e.g. a
// LeafShapeFromImage.
LeafInstances GenerateLeafInstances(const SkeletonGraph& skeleton, const DensityGrid& density,
                                    const ImageSet& views, const std::vector<FloatImage>& mattes,
                                    const LeafOptions& options, LeafSummary* summary,
                                    const LeafShape* shape = nullptr);

// Leaves of a tree known by its skeleton alone (grown from gestures, drawn
// by MRF, read from a QSM): there is no density and no photo, so the leaves
// follow the thin branches (thin_branch_radius_fraction) alone. `skeleton`
// needs radii.
// Their bases sit on the bark (the branch's radius off its axis, towards
// the petiole), so leaves of thick twigs are not buried in them.
// - With a phyllotaxis pattern they sit at the pattern's nodes along the
//   thin branches, as GenerateLeafInstances places them: every site for
//   num_leaves = 0 (at most max_leaves), else num_leaves sites chosen
//   uniformly (all of them if there are fewer), in the sites' order.
// - With "none" they spread uniformly over the thin branches' length, each
//   petiole leaning insertion_deg from its branch at a random azimuth:
//   num_leaves of them, or for 0 one per internode of thin branch (as many
//   as a single-leaf pattern would hold), at most max_leaves.
// Leaf normals turn towards the outward direction from the thin branches'
// centroid by phototropism. The leaf area, twig_reach, max_draws_factor and
// the matte test of GenerateLeafInstances do not apply. Deterministic for
// options.seed. `shape` (optional) replaces options.shape.
LeafInstances GenerateSkeletonLeafInstances(const SkeletonGraph& skeleton,
                                            const LeafOptions& options, LeafSummary* summary,
                                            const LeafShape* shape = nullptr);

// GenerateLeafInstances(...).Bake(). Material "leaves" (double-sided).
TriangleMesh GenerateLeaves(const SkeletonGraph& skeleton, const DensityGrid& density,
                            const ImageSet& views, const std::vector<FloatImage>& mattes,
                            const LeafOptions& options, LeafSummary* summary);

}  // namespace sylva

#endif  // SYLVA_MESH_LEAVES_H_
