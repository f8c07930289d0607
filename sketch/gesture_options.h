// The options of trees grown from 3D gestures (sketch/gesture_tree.h), in
// a header of their own so that the pipeline's options can hold them
// without the growth's types. Registered as Gesture.* (the seed is
// General.seed).
#ifndef SYLVA_SKETCH_GESTURE_OPTIONS_H_
#define SYLVA_SKETCH_GESTURE_OPTIONS_H_

#include <cstdint>
#include <string>

namespace sylva {

struct GestureTreeOptions {
  // Grammar file (.lsys, sketch/lsystem.h); empty = kDefaultGestureGrammar.
  std::string grammar;
  // The grammar's parameters: "NAME=VALUE,NAME=VALUE" replaces the values
  // of its #define constants (each NAME must be defined in it).
  std::string defines;
  // Derivation steps of the L-system. >= 0.
  int iterations = 6;
  uint64_t seed = 1;
  // F modules per trunk stroke (the resampled point set, 4.1.1). >= 2.
  int trunk_segments = 60;
  // Smoothing passes over the resampled trunk (each moves a point half-way
  // to its neighbours' mean; the ends stay). >= 0.
  int smoothing_passes = 2;
  // Trunk radius at the stroke's mean speed, as a fraction of the first
  // trunk's length. > 0.
  double trunk_radius = 0.02;
  // The radius follows mean speed / speed (5.2), clamped to
  // [1 / max_speed_ratio, max_speed_ratio]. >= 1.
  double max_speed_ratio = 3.0;
  // Growth points: none below this fraction of a trunk's length ...
  double crown_base = 0.3;
  // ... then one every this fraction of it, each rolled by the divergence
  // from the previous one (golden angle by default). (0, 1].
  double growth_spacing = 0.07;
  double divergence_deg = 137.5;
  // A growth point's l is this fraction of its trunk's length, and its r
  // this fraction of the trunk's radius there (so is a later trunk
  // stroke's radius at mean speed, of the trunk it joins). > 0.
  double branch_length = 0.3;
  double branch_radius_ratio = 0.5;
  // The region of interest (supertoroid, eq. 3): exponents n (vertical
  // profile) and e (horizontal section); n <= 0 = fitted to the strokes.
  // alpha > 0 gives the torus its hole (in units of the radii).
  double roi_n = 0.0;
  double roi_e = 1.0;
  double roi_alpha = 0.0;
  // Without ROI strokes the region encloses the gestures, its horizontal
  // radii at least this fraction of its height. > 0.
  double roi_min_width = 0.45;
  // ... its radii this many times the gestures' half-extent (room for the
  // crown to grow around them), > 0.5; and its centre this fraction of the
  // gestures' height above theirs (crowns grow up), >= 0.
  double roi_margin = 1.2;
  double roi_lift = 0.1;
  // Turns tried (each this many degrees more) to avoid a collision. >= 0.
  int avoid_turns = 4;
  double avoid_turn_deg = 15.0;
  // Shortened segments below this fraction of their length are pruned.
  // (0, 1).
  double min_segment_fraction = 0.25;

  void Check() const;  // throws InputError naming "Gesture.<field>"
};

}  // namespace sylva

#endif  // SYLVA_SKETCH_GESTURE_OPTIONS_H_
