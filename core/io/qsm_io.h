// Quantitative structure models (QSM): a tree as a table of cylinders, the
// format TreeQSM, rTwig, aRchi and ITSMe read and write, and its conversion
// to and from sylva's skeleton.
//
// The CSV cylinder table (one header line, then one row per cylinder):
//
//   id,parent_id,start_x,start_y,start_z,axis_x,axis_y,axis_z,length,radius,branch,branch_order,radius_source,position_source,branching_source,units
//   1,0,22.25206,112.20287,-11.652903,-0.04426492,-0.008478129,0.99898386,0.37862566,0.08678285,1,0,ground
//   truth,ground truth,ground truth,m
//
//   id            stable cylinder id, an integer > 0 (TreeQSM: the 1-based row)
//   parent_id     id of the parent cylinder; 0 = none (a root: several allowed,
//                 TreeQSM leaves detached fragments unattached)
//   start_x,y,z   centre of the cylinder's base disc
//   axis_x,y,z    unit direction from the base to the top
//   length        > 0; the top centre is start + length * axis
//   radius        > 0
//   branch        branch id (TreeQSM: 1-based, 1 = trunk)
//   branch_order  0 = trunk, 1 = a branch on the trunk, ...
//   radius_source optional: what the radii are ("ground truth", "allometric
//                 prior", "measured", ...); the same on every row
//   position_source  optional: what start, axis and length are ("measured":
//                 sylva's reconstructions follow the density from the photos;
//                 "ground truth"; ...); the same on every row
//   branching_source optional: what parent_id, branch and branch_order are
//                 ("prior": in sylva's reconstructions the particle count and
//                 merging decide how many branches there are; ...); the same
//                 on every row. Tables without these columns read "unknown".
//   units         optional: unit of lengths ("m" if absent, as in TreeQSM)
//
// These are TreeQSM's cylinder fields (cylinder.start/axis/length/radius/
// parent/branch/BranchOrder) under the column names of the ITSMe CSV
// conversion (datasets/itsme-qsm). Columns are found by header name, in any
// order; other columns are ignored; fields may be "quoted" (as R writes them);
// CRLF line ends, blank lines and a UTF-8 byte-order mark are accepted.
#ifndef SYLVA_CORE_IO_QSM_IO_H_
#define SYLVA_CORE_IO_QSM_IO_H_

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/types/skeleton_graph.h"

namespace sylva {

struct QsmCylinder {
  int64_t id = 0;                                   // > 0
  int64_t parent_id = 0;                            // 0 = root
  Eigen::Vector3d start = Eigen::Vector3d::Zero();  // base centre, world units
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit vector, base to top
  double length = 0.0;                              // world units, > 0
  double radius = 0.0;                              // world units, > 0
  int64_t branch = 0;
  int branch_order = 0;

  Eigen::Vector3d End() const { return start + length * axis; }
};

// Invariants (Check()): ids > 0 and unique; every parent id is 0 or an id in
// the table; no cycles; finite values; length, radius > 0; |axis| = 1 within
// 1e-9; branch_order >= 0.
struct QsmModel {
  std::vector<QsmCylinder> cylinders;
  std::string radius_source = "unknown";     // see SkeletonGraph::radius_source
  std::string position_source = "unknown";   // see the file comment
  std::string branching_source = "unknown";  // see the file comment
  std::string units = "m";                   // unit of start, length and radius

  // Throws Error naming the first broken invariant.
  void Check() const;
};

// Reads a cylinder table. Numbers must parse completely and be finite; axes
// whose length is within 1e-3 of 1 are normalised (TreeQSM stores float32),
// others are an error. Throws InputError naming the file and line for any
// problem: a missing column, a bad number, a duplicate id, a missing parent, a
// cycle, differing radius_source or units values.
QsmModel ReadQsmCsv(const std::filesystem::path& path);

// Writes every column above (the sources and units included) atomically,
// doubles in their shortest exact text, so ReadQsmCsv gives back the same
// numbers. Throws Error if the model fails Check().
void WriteQsmCsv(const std::filesystem::path& path, const QsmModel& qsm);

// One connected part of a QSM (a root cylinder and its descendants) as a
// skeleton, with the cylinder each skeleton edge came from.
//
// Representation (SkeletonsFromQsm):
// - The root cylinder's start is the skeleton's root node. Every cylinder
//   gives its end node, and a "split" node on its axis where children leave
//   part-way along it (TreeQSM: a branch's first cylinder starts inside its
//   parent cylinder), so the cylinder is a chain of collinear edges from its
//   start node over its split nodes to its end node.
// - A child continuing its parent's branch (same `branch`) attaches at the
//   parent's end node (TreeQSM's successive cylinders overlap by a few mm).
//   A child starting a new branch attaches at parameter t = (start -
//   parent.start) . parent.axis / parent.length along its parent: t > 0.95
//   (or a start within 1e-9 relative of the parent's end) at the end node,
//   smaller t at a split node at max(t, 0.05); equal t share a split node.
// - A child whose start coincides with its parent's end (within 1e-9 of the
//   larger of the parent's length and the end's largest coordinate) starts at
//   the parent's end node. Otherwise (TreeQSM: always, by a few mm to cm) a
//   "connector" node is added at the child's exact start, as a child of the
//   node it attaches to; the connector edge is no cylinder.
// - Node radius = the radius of the cylinder the edge to its parent belongs
//   to; a root or connector node takes the radius of the cylinder starting
//   there, so a mesher sees a continuous tube.
// - node.order = the cylinder's branch_order; strands = 0 (unknown).
// - cylinder_ids[i] / branch_ids[i]: the id and branch of the cylinder the
//   edge from node i to its parent belongs to (end and split nodes); 0 for a
//   root or connector node.
// QsmFromSkeletons() inverts this exactly (same ids, parents, branches and
// orders; start/axis/length/radius within 1e-10 relative: lengths come back as
// |end - start|, which loses digits when coordinates are far larger than lengths).
struct QsmSkeleton {
  SkeletonGraph skeleton;
  std::vector<int64_t> cylinder_ids;  // per node
  std::vector<int64_t> branch_ids;    // per node
};

struct QsmToSkeletonOptions {
  // A child cylinder whose start lies within merge_fraction x its radius of
  // the node it attaches to starts at that node, without a connector. TreeQSM
  // tables hold float32 values, so some children start ~1e-6 m off their
  // parent's end: the default 0 keeps those micro-connectors (and the round
  // trip exact); a mesher may prefer e.g. 0.1, at the price of moving those
  // children's starts (and axes and lengths) by up to that distance. >= 0.
  double merge_fraction = 0.0;
  // A child cylinder whose start lies inside its parent cylinder (within the
  // parent's radius of its axis segment) starts at the node it attaches to,
  // without a connector. TreeQSM starts a branch inside its parent and each
  // next cylinder of a branch a few mm back inside the previous one: those
  // connectors lie inside the parent's solid and point anywhere (sideways
  // off the parent's axis, or back along the branch), so a tube swept along
  // them folds or turns inside out. A mesher wants them gone (mesh-qsm:
  // on); the child's start then moves by at most the parent's radius.
  bool merge_inside_parent = false;

  void Check() const;  // throws InputError naming the option
};

// One QsmSkeleton per root cylinder, in the order of the roots in the table;
// nodes in depth-first order (parents before children), children in table
// order. Every skeleton passes SkeletonGraph::Check(). Throws Error if `qsm`
// fails Check().
std::vector<QsmSkeleton> SkeletonsFromQsm(
    const QsmModel& qsm, const QsmToSkeletonOptions& options = QsmToSkeletonOptions());

// The exact inverse of SkeletonsFromQsm: one cylinder per chain of edges with
// the same cylinder id, from the node before the chain to its last node;
// connector edges dropped (a cylinder starting at a connector gets the
// cylinder the connector's parent lies on as parent).
// Cylinders are listed by id. radius_source from the first skeleton.
QsmModel QsmFromSkeletons(const std::vector<QsmSkeleton>& parts, const std::string& units);

// A QSM from any skeleton (radii must be > 0 for WriteQsmCsv): one cylinder per edge, start =
// parent node, axis = unit(child - parent), length = the edge length, radius = the child node's
// radius. Cylinders are numbered 1, 2, ... branch axis by branch axis
// (SkeletonGraph::BranchAxes(): trunk first, then breadth-first), so parents
// precede children as in TreeQSM; branch = the axis' 1-based index,
// branch_order = the axis' order. radius_source from the skeleton. Edges of
// zero length are skipped (their child's cylinders attach to the cylinder
// ending at the parent). Throws Error if the skeleton fails Check().
QsmModel QsmFromSkeleton(const SkeletonGraph& skeleton, const std::string& units);

// Volumes of a table's solids, world units cubed. The cylinders of a
// TreeQSM table overlap (successive ones by a few mm, a branch's first
// cylinder starts inside its parent), so their sum pi r^2 L counts those
// overlaps twice; a closed bark around them encloses about their union.
double QsmCylinderVolumeSum(const QsmModel& qsm);
// The volume of the union of the cylinders, by Monte Carlo:
// `samples_per_cylinder` points uniform in each cylinder count when no
// earlier cylinder of the table holds them. Relative standard error about
// sqrt(overlapped fraction / (samples_per_cylinder x cylinders)); the same
// seed gives the same value. Throws Error if `qsm` fails Check().
double QsmUnionVolume(const QsmModel& qsm, int samples_per_cylinder, uint64_t seed);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_QSM_IO_H_
