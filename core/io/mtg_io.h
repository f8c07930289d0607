// OpenAlea's MTG (multiscale tree graph) text format: reading any FORM-A
// coding file into sylva skeletons, and writing a sylva skeleton as one.
//
// An MTG file (OpenAlea `openalea.mtg`, doc/user/syntax.rst; AMAPmod's
// coding files) is TAB-separated text: a header of sections
//
//   CODE:        FORM-A
//   CLASSES:     SYMBOL SCALE DECOMPOSITION INDEXATION DEFINITION, one line per class
//   DESCRIPTION: LEFT RIGHT RELTYPE MAX, the allowed '<' / '+' relations
//   FEATURES:    NAME TYPE, one line per feature (INT, REAL, STRING, ALPHA, dates)
//   MTG:         a column header `ENTITY-CODE` (or `TOPO`) followed by the
//                feature names, then one line per coded entity
//
// In the code, '/' decomposes an entity into the next scale, '<' follows on
// the same axis, '+' branches, `E1<<E5` abbreviates E1<E2<...<E5; a code in
// column c continues the last code of column c-1 above it, and a leading '^'
// continues the last code written in its own column. Feature values start
// at the TAB cell of the first feature name in the column header; they
// belong to the last entity of their line. '#' starts a comment line.
//
// ReadMtg follows OpenAlea's own reader (io.py: Reader.preprocess_code, then
// multiscale_edit) so that a file means what it means in OpenAlea. Not
// supported (an InputError names the line): FORM-B, aliases `(name)`, dated
// observations `*`, and the `<.<` / `+.+` / `++` abbreviations.
//
// What sylva writes (WriteMtg): classes P (plant, scale 1), A (axis, scale 2)
// and S (scale 3), one S per skeleton node, the node's position in features
// XX YY ZZ and its radius in `radius` (world units) on every S line:
//
//   /P1
//   	/A1
//   		/S1	...	0	0	0	0.16      the root node
//   		^<S2	...	0	0	1	0.12
//   		^+A2                          a branch leaving node S2
//   			/S1	...	0.4	0	1.3	0.05
//   		^<S3	...	0	0	2	0.08
//
// An axis is a SkeletonGraph::BranchAxes() axis; its first S is the first
// node after its junction, '+'-linked to the junction's S (OpenAlea's
// reader links it so). Several skeletons become plants P1, P2, ...
#ifndef SYLVA_CORE_IO_MTG_IO_H_
#define SYLVA_CORE_IO_MTG_IO_H_

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/types/skeleton_graph.h"

namespace sylva {

// One entity (vertex) of an MTG at one scale.
struct MtgEntity {
  std::string label;     // e.g. "S12": class symbol + index
  std::string symbol;    // the class, e.g. "S"
  int index = 0;         // the label's number (0 if none)
  int scale = 0;         // 0 = the whole file ($), 1 = plants, ...
  int complex_idx = -1;  // the entity at scale - 1 it is part of; -1 for $
  int parent_idx = -1;   // the entity at the same scale it follows or branches from
  char edge = 0;         // '<' or '+' to its parent; 0 without a parent
  int line = 0;          // 1-based line of the file that coded it (0 for $)
  std::map<std::string, std::string> features;  // name -> text, only those given
};

struct Mtg {
  std::map<std::string, int> class_scales;  // symbol -> scale
  std::vector<std::string> feature_names;   // as declared under FEATURES
  std::map<std::string, std::string> feature_types;
  std::vector<MtgEntity> entities;  // entities[0] is the scale-0 root $
};

// Parses an MTG text; `source` names it in errors. Throws InputError naming
// the source and line of the first problem: a missing or misplaced section,
// a malformed class or feature line, an entity of an undeclared class, an
// indentation that matches no enclosing column, an unbalanced branch.
Mtg ParseMtg(const std::string& text, const std::string& source);
Mtg ReadMtg(const std::filesystem::path& path);

struct MtgToSkeletonOptions {
  // TopDia / TopDiameter values are diameters in units `diameter_unit` times
  // smaller than those of XX YY ZZ (OpenAlea dressing files' DiameterUnit:
  // 10 for the walnut's mm diameters with cm coordinates). > 0. A `radius`
  // feature is taken as it is, in the coordinates' unit.
  double diameter_unit = 1.0;

  void Check() const;  // throws InputError naming the option
};

// The skeletons of an MTG and how they were found.
struct MtgSkeletons {
  // One per root of the geometry scale's tree; nodes parents first.
  std::vector<SkeletonGraph> parts;
  // The entity each node came from (entity index into Mtg::entities).
  std::vector<std::vector<int>> entity_of_node;
  int geometry_scale = 0;      // the finest scale whose entities carry XX YY ZZ
  std::string radius_feature;  // "radius", "TopDia", "TopDiameter" or "" (none)
  int placed_entities = 0;     // entities of that scale with coordinates
  int unplaced_entities = 0;   // of that scale without (skipped; children hang on)
  int merged_nodes = 0;        // entities at their parent's position, merged
  int base_nodes = 0;          // roots placed from a coarser entity's coordinates
  int radii_filled = 0;        // nodes without a radius value, given a neighbour's

  std::string BriefReport() const;
};

// The tree of the finest scale whose entities have XX, YY and ZZ: every
// such entity becomes a node at (XX, YY, ZZ), its parent the nearest entity
// up its parent chain ('<' or '+') that has coordinates. Entities without
// coordinates are skipped (children hang on their nearest placed
// ancestor); an entity at its parent's exact position is merged into it. A
// root whose enclosing entity (its axis, its plant) has coordinates elsewhere
// gets that point as a base node below it (OpenAlea's digitised trees put
// an axis' base point on the axis). Radius = `radius`, else TopDia or
// TopDiameter / 2 / diameter_unit; nodes without a value take their
// parent's (a root its first child's); without any radius feature every
// radius is 0 and radius_source "unknown" (the caller assigns radii).
// node.order from SkeletonGraph::AssignOrders(). Throws InputError (naming
// `source` and the line) for a coordinate or radius that is not a finite
// number, and when no entity has all of XX, YY and ZZ.
MtgSkeletons SkeletonsFromMtg(const Mtg& mtg, const std::string& source,
                              const MtgToSkeletonOptions& options = MtgToSkeletonOptions());

// The MTG text of `parts` (layout in the file comment; doubles in their
// shortest exact text, so reading gives back the same numbers). A comment
// line at the top gives `units` and the radius source. `node_order`
// (optional) receives, per part, the skeleton node of each S entity in file
// order (SkeletonsFromMtg's node order). Throws Error if a part fails Check().
std::string MtgText(const std::vector<SkeletonGraph>& parts, const std::string& units,
                    std::vector<std::vector<int>>* node_order = nullptr);
// Writes MtgText atomically.
void WriteMtg(const std::filesystem::path& path, const std::vector<SkeletonGraph>& parts,
              const std::string& units);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_MTG_IO_H_
