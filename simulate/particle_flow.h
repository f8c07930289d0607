// The particle flow (Neubert, Franken, Deussen 2007; Neubert's thesis 3.4):
// particles seeded in proportion to the density flow down to the tree base,
// attracted by their nearest neighbours and steered by an external direction
// field; particles that come close merge, and the traces they leave are the
// tree skeleton.
//
// The model, per particle i (position x, velocity v, mass m = number of
// seeded particles it carries), in the frame of the density grid's voxels
// (lengths in voxels, so every option is independent of the tree's size):
//
//   x' = v
//   v' = base_pull * unit(t(x) - x)                  (towards the base b)
//      + neighbor_pull * s(d) * 2 m_j / (m_i + m_j) * unit(x_j - x)
//      + field_weight * field.Direction(x)
//      - damping * v
//
// with j the nearest other particle, d = |x_j - x| and the falloff
// s(d) = (1 - (d / neighbor_radius)^2)^2 for d < neighbor_radius, else 0.
// The base pull heads for t(x), a point on the vertical axis through the base
// (the trunk), descent_angle_deg below the horizontal from x, at least
// axis_lookahead below x and never below b: traces converge on the axis and
// run down it as one trunk. (The thesis pulls straight at b,
// descent_angle_deg = 90, which gathers the traces in a cone; the direction
// field of traced or drawn attractors is the thesis' way to shape the trunk,
// this axis is sylva's default when there is none.)
// The neighbour term is the thesis' attraction written as an acceleration:
// light particles are drawn to heavy bundles, heavy bundles barely move
// towards single particles, equal masses meet halfway. The drag makes the
// motion smooth and bounds the speed: alone, a particle approaches the base at
// the terminal speed base_pull / damping voxels per time unit.
//
// Each iteration (one accepted step):
//   1. particles within base_radius of the base stop; their traces end at the
//      base (the root) and are "finished";
//   2. particles within merge_distance of a finished trace join it there
//      (join_finished_traces; a sylva refinement): bundles that follow the
//      same path at different times, typically down the trunk, make one
//      trace that carries all of them, not several side by side. With
//      join_flowing_traces, so do particles that come upon the trace of a
//      bundle still flowing ahead of them (never their own) and move along
//      it (within flowing_join_angle_deg): that bundle carries them from
//      then on;
//   3. one nearest-neighbour query per particle (options.neighbor_search);
//   4. pairs closer than merge_distance merge (from the second iteration on,
//      so every trace starts with an edge): candidate pairs are taken in order
//      of distance, then of particle ids, each particle in at most one merge
//      per iteration. The heavier particle (equal masses: the lower id)
//      survives where it is, carrying the summed mass and momentum; the
//      absorbed particle's trace ends at the survivor's trace there;
//   5. all particles advance by one RK4 step of a common adaptive size h
//      (thesis eq. 3.6), with neighbours frozen during the step: step
//      doubling estimates each particle's position error, the step is
//      rejected and shrunk if the largest error exceeds error_tolerance, and
//      grown after an accepted step (Numerical Recipes' controller, with
//      local extrapolation);
//   6. traces record a node whenever the path leaves the straight line from
//      the last node by more than trace_tolerance.
// Particles that have not reached the base after max_iterations are joined to
// the root by a straight edge (counted in the summary), so the result is
// always one rooted tree. The traces then become the skeleton: chains between
// junctions are simplified (Douglas-Peucker, simplify_tolerance).
//
// Deterministic: the same density, base, field, options and seed give the
// same skeleton, whatever the number of threads (per-particle work is
// independent, merges are resolved in a fixed order, nodes are numbered in
// particle order).
#ifndef SYLVA_SIMULATE_PARTICLE_FLOW_H_
#define SYLVA_SIMULATE_PARTICLE_FLOW_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "core/types/density_grid.h"
#include "core/types/skeleton_graph.h"
#include "core/util/progress.h"
#include "simulate/direction_field.h"

namespace sylva {

struct ParticleFlowOptions {
  // --- Particles ---
  // Particles seeded, each uniformly inside a voxel drawn with probability
  // proportional to its opacity. The thesis used 500-1000 for medium and
  // 1000-2000 for large trees.
  int num_particles = 1000;
  // Seed of the particles' positions (RandomEngine).
  uint64_t seed = 1;
  // Voxels are drawn with probability proportional to opacity^seed_exponent
  // (1: the thesis). Opacity grows with a branch's width, so the thesis'
  // seeding gives the trunk and limbs most particles and the thin branches
  // few. 0.5 on tests/bench/skeleton_probe.cc's trees: ITSMe buttressed
  // tree 1's recall 0.68 -> 0.94 (length 0.70 -> 1.00 x, Chamfer 1.35 ->
  // 0.67 %), the 4 ITSMe trees' recall 0.81 -> 0.91, leafless trees' 0.53 ->
  // 0.57 (Chamfer 2.00 -> 1.93 %); but ITSMe tree 2 1.03 -> 1.66 x (39 % of it
  // traced twice) and, steered by the true main branches
  // (sylva_attractor_probe --graphs=truth), their 2D Chamfer 2.36 -> 2.60 px
  // (3D 1.92 -> 1.97 %): the unsteered skeleton is closer, the steered one
  // farther. Not the default for that.
  double seed_exponent = 1.0;

  // --- Forces (accelerations; lengths in voxels of the density grid, time in
  // the simulation's own time unit) ---
  // Pull towards the tree base, in voxels / time^2.
  double base_pull = 2.0;
  // The base pull heads for the vertical axis through the base (the trunk)
  // at this angle below the horizontal, in degrees, in (0, 90]: a particle at
  // horizontal distance r from the axis aims at the axis point r * tan(angle)
  // below it (never below the base), so traces converge on the axis, then
  // run down it as a trunk. 90 aims straight at the base (the thesis' pull),
  // which gathers the traces in a cone. 30 gave the closest skeletons on
  // synthetic trees (branches leave their parents at 30-60 degrees there).
  double descent_angle_deg = 30.0;
  // Near the axis the pull aims at least this far below the particle, in
  // voxels, so particles settle onto the axis rather than cross it.
  double axis_lookahead = 4.0;
  // Largest attraction towards the nearest neighbour (between equal masses,
  // at distance 0), in voxels / time^2.
  double neighbor_pull = 2.0;
  // The attraction falls smoothly to zero at this distance, in voxels; it is
  // also the radius of the nearest-neighbour search.
  double neighbor_radius = 16.0;
  // Weight of the external direction field (directions of length <= 1), in
  // voxels / time^2; 0 ignores the field. With the attractor graphs' field
  // (simulate/attractor_field.h), 10 cut the 2D distance between projected
  // main branches and the truth the most on synthetic trees (1: -13 %, 3:
  // -18 %, 6: -26 %, 10: -30 %, 20: -25 %; tests/bench/attractor_probe.cc);
  // it outweighs the base and neighbour pulls wherever the field is non-zero.
  double field_weight = 10.0;
  // Linear drag, in 1 / time: velocities relax towards force / damping with
  // time constant 1 / damping.
  double damping = 1.0;

  // --- Merging and stopping ---
  // Particles whose nearest neighbour is closer than this merge, in voxels.
  double merge_distance = 1.0;
  // Particles closer than this to the base stop there, in voxels.
  double base_radius = 2.0;
  // A particle that comes within merge_distance of a finished trace (one
  // already joined to the root) joins it there, and its particles follow
  // that trace to the root, instead of flowing beside it as a second trace
  // (which happens when bundles take the same path at different times, e.g.
  // down the trunk). A sylva refinement; false gives the thesis' merging of
  // live particles only.
  bool join_finished_traces = true;
  // The same for the traces of particles still flowing (a particle's own
  // trace, and those leading to it, excepted) that the particle moves along,
  // its velocity within flowing_join_angle_deg of the trace's direction:
  // it joins the trace, and the bundle at its end carries it from then on,
  // as if they had merged there. Without it, a bundle that passes where
  // another passed earlier, while that one still flows, lays a second trace
  // beside the first. On tests/bench/skeleton_probe.cc's trees (livewire
  // graphs, joins within 18 degrees, momentum conserved): leafless trees
  // traced twice 41-44 % -> 24-28 % of the length, 0.96 -> 0.80 x the
  // truth (0.55 -> 0.59 x once), precision 0.817 -> 0.792 (less padding),
  // Chamfer 2.00 -> 2.06 %; ITSMe recall 0.81 -> 0.82, Chamfer 1.03 ->
  // 0.78 %, but tree 2 1.03 -> 1.35 x. Joining at any angle sends bundles
  // along other paths (the steered trunk follows the attractors less, the
  // sketch oracle's first-order angle 44 -> 51-56 degrees against 39);
  // without the momentum, lone leaders' paths carry the bundles (first-order
  // stubs 36 -> 49 on leafless tree 1). Not the default: leafless
  // precision under 0.8 and ITSMe tree 2 beyond 1.3 x.
  bool join_flowing_traces = false;
  // Traces crossed at a wider angle are not the same path: the particle
  // flows on (joining them would send its particles where it was not
  // going). In degrees, [0, 180].
  double flowing_join_angle_deg = 18.0;
  // Accepted steps at most (the thesis used about 200).
  int max_iterations = 200;

  // --- Adaptive RK4 (step sizes in time units) ---
  // Largest position error per step allowed by step doubling, in voxels.
  double error_tolerance = 0.05;
  double initial_step = 0.5;
  double min_step = 0.01;
  // Speeds stay below (base_pull + 2 neighbor_pull + |field_weight|) /
  // damping (16 voxels per time unit with the defaults and a field, 6
  // without; typically ~2), so a step moves a particle a few voxels at most.
  double max_step = 1.0;

  // --- Traces and skeleton ---
  // A trace records a node when the path deviates from the straight line
  // from its last node by more than this, in voxels (0 records every step).
  double trace_tolerance = 0.25;
  // Chains between junctions are simplified until every dropped node lies
  // within this distance of the kept polyline, in voxels (0 keeps all).
  double simplify_tolerance = 0.5;

  // --- Nearest neighbours ---
  // "uniform_grid" (default, fastest), "embree" or "brute_force" (O(N^2),
  // reference only); see simulate/neighbor_search.h.
  std::string neighbor_search = "uniform_grid";

  // Throws InputError("ParticleFlow.<field>", ...) naming the first violated
  // constraint.
  void Check() const;
};

struct ParticleFlowSummary {
  int seeded = 0;                // particles seeded (= options.num_particles)
  int merges = 0;                // merge events
  int reached_base = 0;          // seeded particles that arrived within base_radius
                                 //   or by joining a finished trace
  int trace_joins = 0;           // bundles that joined a finished trace
  int flowing_joins = 0;         // bundles that joined the trace of a flowing one
  int unfinished = 0;            // seeded particles not arrived after max_iterations,
  int unfinished_bundles = 0;    //   in this many bundles, each joined to the root
                                 //   by a straight edge
  int iterations = 0;            // accepted steps of the whole system
  int64_t rejected_steps = 0;    // trials rejected by the error control
  int64_t particle_steps = 0;    // particle advances (summed over accepted steps)
  int64_t neighbor_queries = 0;  // nearest-neighbour queries (one per particle and step)
  std::string neighbor_search;   // structure used
  double final_step = 0.0;       // step size at the end, in time units
  double simulated_time = 0.0;   // in time units
  int raw_nodes = 0;             // nodes of the recorded traces
  int skeleton_nodes = 0;        // nodes after simplification
  // Wall-clock times: seeding; neighbour queries and merges; arrivals and
  // joins of finished traces; integration and trace recording; building the
  // skeleton; all.
  double seconds_seed = 0, seconds_neighbors = 0, seconds_join = 0, seconds_integrate = 0,
         seconds_skeleton = 0, seconds_total = 0;

  // One paragraph for humans (Ceres' BriefReport style).
  std::string BriefReport() const;
};

// Runs the particle flow on `density` towards `base_in_world` (world frame;
// see EstimateTreeBase) and returns the skeleton: root at the base, nodes in
// world units listed parents first, `strands` = seeded particles carried by
// each edge (the root: all of them; at every junction a node carries the sum
// of its children), branch orders assigned (SkeletonGraph::AssignOrders),
// radii 0 and radius_source "unknown" (radii are a later stage).
// `raw_traces` (optional) receives the traces as recorded, before
// simplification, in the same form. `progress` (may be null) reports progress
// and cancels (throws Cancelled); `summary` may be null.
// Throws InputError if the options are invalid, the density is empty
// ("density") or the base lies outside the density's active bounds grown by
// max(base_radius, 1) voxels ("base").
SkeletonGraph SimulateParticleFlow(const DensityGrid& density, const Eigen::Vector3d& base_in_world,
                                   const DirectionField& field, const ParticleFlowOptions& options,
                                   ProgressReporter* progress, ParticleFlowSummary* summary,
                                   SkeletonGraph* raw_traces = nullptr);

struct TreeBaseOptions {
  // Voxels below this opacity are ignored (alpha in [0, 1)).
  double min_opacity = 0.05;
  // The base layer is the lowest whose summed opacity reaches this fraction
  // of the largest layer sum among the lowest reference_voxels layers, so a
  // few stray voxels under the trunk (reconstruction blur) do not lower the
  // base. In (0, 1].
  double layer_fraction = 0.5;
  int reference_voxels = 8;
  // Layers from the base layer up whose opacity-weighted centre gives the
  // base's x and y (>= 1).
  int slab_voxels = 3;

  // Throws InputError("TreeBase.<field>", ...).
  void Check() const;
};

// The bottom of the trunk, from the density alone (+Z is up in the world
// frame). Among voxels with opacity >= min_opacity, with S(k) the summed
// opacity of layer k (voxels at height index k) and k_low the lowest
// non-empty layer: the base layer k0 is the lowest layer with
// S(k0) >= layer_fraction * max S over [k_low, k_low + reference_voxels);
// the base's z is the bottom face of layer k0, its x and y the
// opacity-weighted mean of the voxel centres in layers
// [k0, k0 + slab_voxels). Throws InputError("density", ...) if no voxel
// qualifies.
Eigen::Vector3d EstimateTreeBase(const DensityGrid& density,
                                 const TreeBaseOptions& options = TreeBaseOptions());

}  // namespace sylva

#endif  // SYLVA_SIMULATE_PARTICLE_FLOW_H_
