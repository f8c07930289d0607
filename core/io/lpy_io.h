// A tree skeleton as an L-Py L-system (OpenAlea L-Py, PlantGL's turtle), and
// a small turtle interpreter for the subset written, to check what is written.
//
// The file is a loadable L-Py model whose axiom draws the tree and whose
// productions are empty (`derivation length: 0`):
//
//   Axiom: [@M(0,0,0) _(0.16) LineTo(0,0,1,0.12) [@M(0,0,1) _(0.05) LineTo(0.4,0,1.3,0.05)] ...]
//   derivation length: 0
//   production:
//   interpretation:
//   endlsystem
//
// Two forms (LpyForm):
// - absolute: `@M(x,y,z)` (MoveTo) to the start of every branch axis, then
//   `LineTo(x,y,z,r)` to each node: a cylinder from the turtle to the node,
//   r the node's radius (LineTo's 4th argument, the top width; `_(r)` sets
//   the width the first one starts with: the root's radius, or a branch's
//   first node's; a branch leaving the root starts with the root's radius).
//   LineTo keeps the turtle's orientation; rotations play no part.
// - turtle (relative): `@M(x,y,z)` once per skeleton, to its root, then per
//   node a roll `/(a)` and a turn `+(b)` (degrees) that point the heading at
//   the node, and `F(length,r)`. The initial frame is PlantGL's: heading H =
//   +Z, left L = -Y, up U = +X; `+(a)` turns H towards L about U, `/(a)`
//   rolls L towards U about H. L-Py maps `+` to PlantGL's Turtle::left
//   (a rotation of +a about U) and `/` to Turtle::rollL (+a about H; L-Py's
//   predefinedmodules.cpp, PlantGL's turtle.cpp). Caution: old PlantGL
//   versions (before the turtle's reflection support) rotated rollL by -a,
//   where this form would draw mirrored branches; the absolute form does not
//   depend on it.
//
// In both, `[` `]` enclose each skeleton and every branch axis
// (SkeletonGraph::BranchAxes(); a branch is written where it leaves its
// parent axis, so brackets nest by branch order). Widths are radii in the
// skeleton's world units (PlantGL's width is a cylinder's radius). Numbers
// are doubles in their shortest exact text.
#ifndef SYLVA_CORE_IO_LPY_IO_H_
#define SYLVA_CORE_IO_LPY_IO_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/types/skeleton_graph.h"

namespace sylva {

enum class LpyForm {
  kAbsolute,  // @M / LineTo
  kTurtle,    // F and rotations
};

// The .lpy text of `parts` in `form`; comment lines at the top give `units`
// and the radius source. `node_order` (optional) receives, per part, the
// skeleton node each drawn node is (InterpretLpy's node order; the root
// first). Throws Error if a part fails Check().
std::string LpyText(const std::vector<SkeletonGraph>& parts, LpyForm form, const std::string& units,
                    std::vector<std::vector<int>>* node_order = nullptr);
// Writes LpyText atomically.
void WriteLpy(const std::filesystem::path& path, const std::vector<SkeletonGraph>& parts,
              LpyForm form, const std::string& units);

// What a turtle draws from an axiom.
struct LpyTree {
  // One per connected piece: a segment starts a new skeleton when the turtle
  // was moved (@M) away from every drawn node (a segment drawn from where a
  // node is continues from the first node drawn there); nodes in drawing
  // order.
  std::vector<SkeletonGraph> parts;
  int modules = 0;  // modules interpreted
};

// Interprets the `Axiom:` line of an L-Py file with PlantGL's turtle:
// `[` `]`, `@M`/`MoveTo(x,y,z)`, `LineTo(x,y,z[,r])`, `F[(length[,r])]`
// (length 1 by default), `_(r)`/`!(r)`/`SetWidth(r)` (without an argument
// `_` adds 1 and `!` subtracts 1, as PlantGL's IncWidth/DecWidth),
// `+ - & ^ / \` with an angle in degrees (60 without),
// and blanks between modules. Every segment drawn adds a node (radius: its
// top width, or the width before it) whose parent is the node the turtle
// stands on; the width at the first segment of a piece is its root's
// radius; node.order = bracket depth - 1 (each skeleton is in brackets).
// -0 and +0 coordinates are different points here (exact text round trip).
// Throws InputError naming `source`, the line and column, for anything
// else: another module, a bad number, unbalanced brackets, no axiom.
LpyTree InterpretLpy(const std::string& text, const std::string& source);
LpyTree ReadLpy(const std::filesystem::path& path);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_LPY_IO_H_
