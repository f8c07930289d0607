// Compares the branch divergence (phyllotaxis) angles of a reconstructed
// skeleton with ROMI's hand measurements (metadata.json -> measures):
//
//   sylva_branch_angle_probe SKELETON.json METADATA.json [--stem=strands|highest]
//       [--tolerance=MM] [--probe=MM] [--min_organ=MM] [--scale=S] [--seed=N]
//
// Method.
// - Main stem: from the root, the chain that at every node follows the child
//   carrying the most strands (then the thickest): SkeletonGraph::BranchAxes'
//   trunk. --stem=highest takes the path from the root to the highest tip
//   instead. Positions are scaled to mm (units "m" -> 1000, else --scale or 1).
// - Organs: every other child of a stem node (a junction) whose own axis
//   (same continuation rule) is at least --min_organ mm long. Its arc length is
//   the junction's along the stem; its direction is the point --probe mm along
//   its axis minus the junction, projected onto the plane perpendicular to the
//   local stem tangent (mean of the two adjacent edge directions). The azimuth
//   is measured in a frame parallel-transported along the stem (minimal
//   rotation from node to node), counter-clockwise about the upward tangent.
// - Measured organs: 1 + internodes.size() of them, at heights offset +
//   cumulative internodes; angles[i] is the divergence from organ i to i+1.
//   The offset (the first organ's arc length) is chosen on a grid over
//   [-tolerance, stem length] (the first organ is above the stem's base) to
//   minimise sum_i min(distance to the nearest organ, tolerance); first
//   minimum wins.
//   Organs are then paired one-to-one, closest pairs first, within tolerance,
//   skipping a pair that would cross one already made (order is kept).
// - A measured divergence counts when both of its organs are paired; ours is
//   (azimuth(j(i+1)) - azimuth(j(i))) mod 360. Errors are wrapped to [0, 180]
//   and reported for ours and for 360 - ours (the other handedness), beside
//   two controls: uniform random angles (fixed seed) and a constant 137.5 deg.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "core/io/json_util.h"
#include "core/io/skeleton_io.h"
#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

constexpr double kDegPerRad = 180.0 / M_PI;
constexpr double kGoldenAngleDeg = 137.5;
constexpr double kOffsetStepMm = 0.5;  // grid step of the offset search
constexpr int kBaselineDraws = 1000;   // random angles per measured divergence

struct ProbeOptions {
  std::string stem = "strands";  // "strands" (BranchAxes trunk) or "highest"
  double tolerance_mm = 10.0;    // largest arc-length gap of a pair
  double probe_mm = 5.0;         // distance along an organ to its direction point
  double min_organ_mm = 5.0;     // shorter organs (stubs, noise) are ignored
  double scale = 0.0;            // skeleton units -> mm; 0: from the file's units
  uint64_t seed = 1;             // of the random baseline
};

struct Organ {
  double arc_mm;       // junction's arc length along the stem
  double azimuth_deg;  // in [0, 360)
};

double Mod360(double deg) { return deg - 360.0 * std::floor(deg / 360.0); }
double AngleError(double a_deg, double b_deg) {
  return std::abs(Mod360(a_deg - b_deg + 180) - 180);
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? NAN : 0.5 * (v[(n - 1) / 2] + v[n / 2]);
}

// measures.angles (radians -> degrees) and measured organ heights relative to
// the first organ (cumulative measures.internodes, numbers or numeric strings).
void ReadMeasures(const std::string& path, std::vector<double>* angles_deg,
                  std::vector<double>* heights_mm) {
  const Json json = ReadJsonFile(path);
  const JsonCursor measures = JsonCursor(json, path)["measures"];
  for (double a : measures["angles"].AsDoubles()) angles_deg->push_back(a * kDegPerRad);
  const JsonCursor internodes = measures["internodes"];
  heights_mm->assign(1, 0.0);
  for (size_t i = 0; i < internodes.Size(); ++i) {
    const JsonCursor item = internodes[i];
    double length = 0;
    if (item.value().is_string()) {
      const std::string text = item.AsString();
      size_t used = 0;
      try {
        length = std::stod(text, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != text.size() || !std::isfinite(length)) item.Fail("not a number");
    } else {
      length = item.AsDouble();
    }
    if (length < 0) item.Fail("negative internode");
    heights_mm->push_back(heights_mm->back() + length);
  }
  SYLVA_CHECK_INPUT(!angles_deg->empty() && angles_deg->size() + 1 == heights_mm->size(), path)
      << "measures: " << angles_deg->size() << " angles but " << internodes.Size()
      << " internodes (expected equal, > 0)";
}

// From `start`, follows the child with the most strands, then the thickest.
std::vector<int> FollowAxis(const SkeletonGraph& g, const std::vector<std::vector<int>>& children,
                            int start) {
  std::vector<int> chain;
  for (int node = start; node >= 0;) {
    chain.push_back(node);
    int next = -1;
    for (int c : children[node]) {
      if (next < 0 || g.nodes[c].strands > g.nodes[next].strands ||
          (g.nodes[c].strands == g.nodes[next].strands && g.nodes[c].radius > g.nodes[next].radius))
        next = c;
    }
    node = next;
  }
  return chain;
}

std::vector<int> PathToHighestTip(const SkeletonGraph& g) {
  int tip = g.RootIdx();
  for (int i : g.Tips()) {
    if (g.nodes[i].position.z() > g.nodes[tip].position.z()) tip = i;
  }
  std::vector<int> path;
  for (int node = tip; node >= 0; node = g.nodes[node].parent_idx) path.push_back(node);
  std::reverse(path.begin(), path.end());
  return path;
}

double ChainLength(const SkeletonGraph& g, const std::vector<int>& chain) {
  double length = 0;
  for (size_t k = 1; k < chain.size(); ++k)
    length += (g.nodes[chain[k]].position - g.nodes[chain[k - 1]].position).norm();
  return length;
}

// The point `distance` along the chain (its end if the chain is shorter).
Eigen::Vector3d PointAlong(const SkeletonGraph& g, const std::vector<int>& chain, double distance) {
  for (size_t k = 1; k < chain.size(); ++k) {
    const Eigen::Vector3d& a = g.nodes[chain[k - 1]].position;
    const Eigen::Vector3d& b = g.nodes[chain[k]].position;
    const double length = (b - a).norm();
    if (length >= distance && length > 0) return a + (b - a) * (distance / length);
    distance -= length;
  }
  return g.nodes[chain.back()].position;
}

// Organs along the stem, in stem order; positions already in mm.
std::vector<Organ> FindOrgans(const SkeletonGraph& g, const std::vector<int>& stem,
                              const ProbeOptions& options, int* num_children) {
  const std::vector<std::vector<int>> children = g.Children();
  auto position = [&](size_t k) { return g.nodes[stem[k]].position; };
  // Reference direction u, perpendicular to the tangent, transported from (+Z, +X).
  Eigen::Vector3d tangent = Eigen::Vector3d::UnitZ(), u = Eigen::Vector3d::UnitX();
  std::vector<Organ> organs;
  *num_children = 0;
  double arc = 0;
  for (size_t k = 0; k + 1 < stem.size(); ++k) {
    const Eigen::Vector3d chord = position(k + 1) - position(k > 0 ? k - 1 : 0);
    if (chord.norm() > 1e-9) {  // else keep the previous frame
      const Eigen::Vector3d next_tangent = chord.normalized();
      u = Eigen::Quaterniond::FromTwoVectors(tangent, next_tangent) * u;
      tangent = next_tangent;
      u = (u - u.dot(tangent) * tangent).normalized();
    }
    const Eigen::Vector3d v = tangent.cross(u);
    const Eigen::Vector3d& junction = g.nodes[stem[k]].position;
    for (int child : children[stem[k]]) {
      if (child == stem[k + 1]) continue;
      ++*num_children;
      std::vector<int> axis = FollowAxis(g, children, child);
      axis.insert(axis.begin(), stem[k]);
      if (ChainLength(g, axis) < options.min_organ_mm) continue;
      Eigen::Vector3d d = PointAlong(g, axis, options.probe_mm) - junction;
      d -= d.dot(tangent) * tangent;
      if (d.norm() < 1e-9) continue;  // along the stem: no azimuth
      organs.push_back({arc, Mod360(std::atan2(d.dot(v), d.dot(u)) * kDegPerRad)});
    }
    arc += (position(k + 1) - junction).norm();
  }
  return organs;
}

// The offset minimising sum_i min(gap to the nearest organ, tolerance); then
// one-to-one pairs, closest first. Returns the organ index per measured organ (-1: none).
std::vector<int> MatchOrgans(const std::vector<double>& heights, const std::vector<Organ>& organs,
                             double stem_length, double tolerance, double* offset) {
  auto gap = [&](double h, const Organ& o) { return std::abs(o.arc_mm - h); };
  double best_cost = INFINITY;
  for (double off = -tolerance; off <= stem_length; off += kOffsetStepMm) {
    double cost = 0;
    for (double h : heights) {
      double nearest = tolerance;
      for (const Organ& o : organs) nearest = std::min(nearest, gap(h + off, o));
      cost += nearest;
    }
    if (cost < best_cost - 1e-9) best_cost = cost, *offset = off;
  }
  std::vector<std::pair<double, std::pair<int, int>>> candidates;
  for (size_t i = 0; i < heights.size(); ++i) {
    for (size_t j = 0; j < organs.size(); ++j) {
      const double d = gap(heights[i] + *offset, organs[j]);
      if (d <= tolerance) candidates.push_back({d, {static_cast<int>(i), static_cast<int>(j)}});
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<int> match(heights.size(), -1);
  std::vector<bool> used(organs.size(), false);
  for (const auto& [d, ij] : candidates) {
    if (match[ij.first] >= 0 || used[ij.second]) continue;
    bool crosses = false;
    for (size_t i = 0; i < match.size(); ++i)
      crosses |= match[i] >= 0 && (static_cast<int>(i) - ij.first) * (match[i] - ij.second) <= 0;
    if (crosses) continue;
    match[ij.first] = ij.second;
    used[ij.second] = true;
  }
  return match;
}

bool ParseFlag(const std::string& flag, ProbeOptions* o) {
  const size_t eq = flag.find('=');
  if (flag.rfind("--", 0) != 0 || eq == std::string::npos) return false;
  const std::string name = flag.substr(2, eq - 2), value = flag.substr(eq + 1);
  const std::map<std::string, double*> numbers = {{"tolerance", &o->tolerance_mm},
                                                  {"probe", &o->probe_mm},
                                                  {"min_organ", &o->min_organ_mm},
                                                  {"scale", &o->scale}};
  size_t used = 0;
  if (name == "stem" && (value == "strands" || value == "highest")) {
    o->stem = value;
    used = value.size();
  } else if (name == "seed") {
    o->seed = std::stoull(value, &used);
  } else if (numbers.count(name)) {
    *numbers.at(name) = std::stod(value, &used);
  }
  return used > 0 && used == value.size();
}

// "12.3 deg", or "n/a" when there was nothing to take a median of.
std::string Deg(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f deg", value);
  return std::isnan(value) ? "n/a" : text;
}

// The divergences whose two organs are both paired, with the errors of ours,
// of the other handedness and of the two controls.
struct Comparison {
  std::vector<double> measured, ours, err_ours, err_mirror, err_random, err_golden;
};

// Compares and prints one table row per measured divergence.
Comparison CompareDivergences(const std::vector<double>& measured_deg,
                              const std::vector<double>& heights, double offset,
                              const std::vector<int>& match, const std::vector<Organ>& organs,
                              uint64_t seed) {
  Comparison c;
  RandomEngine random(seed);
  std::printf("\n pair  meas.h  arc(i)  arc(i+1)  measured   ours  360-ours  err(ours)  %s\n",
              "err(360-ours)");
  for (size_t i = 0; i < measured_deg.size(); ++i) {
    const double measured = measured_deg[i];
    if (match[i] < 0 || match[i + 1] < 0) {
      std::printf("%5zu  %6.1f  (organ not matched)\n", i, heights[i] + offset);
      continue;
    }
    const Organ& a = organs[match[i]];
    const Organ& b = organs[match[i + 1]];
    const double ours = Mod360(b.azimuth_deg - a.azimuth_deg);
    c.measured.push_back(measured);
    c.ours.push_back(ours);
    c.err_ours.push_back(AngleError(ours, measured));
    c.err_mirror.push_back(AngleError(360 - ours, measured));
    c.err_golden.push_back(AngleError(kGoldenAngleDeg, measured));
    for (int d = 0; d < kBaselineDraws; ++d)
      c.err_random.push_back(AngleError(random.Uniform(0, 360), measured));
    std::printf("%5zu  %6.1f  %6.1f  %8.1f  %8.1f  %5.1f  %8.1f  %9.1f  %13.1f\n", i,
                heights[i] + offset, a.arc_mm, b.arc_mm, measured, ours, 360 - ours,
                c.err_ours.back(), c.err_mirror.back());
  }
  return c;
}

int Main(int argc, char** argv) {
  ProbeOptions options;
  for (int i = 3; i < argc; ++i) {
    bool ok = false;
    try {
      ok = ParseFlag(argv[i], &options);
    } catch (const std::exception&) {
    }
    SYLVA_CHECK_INPUT(ok, argv[i]) << "unknown flag or bad value";
  }
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s SKELETON.json METADATA.json [--stem=strands|highest] %s\n",
                 argv[0], "[--tolerance=MM] [--probe=MM] [--min_organ=MM] [--scale=S] [--seed=N]");
    return 2;
  }
  SYLVA_CHECK_INPUT(options.tolerance_mm > 0 && options.probe_mm > 0 && options.scale >= 0, "flags")
      << "tolerance and probe must be > 0, scale >= 0";
  std::string units;
  SkeletonGraph g = ReadSkeletonJson(argv[1], &units);
  SYLVA_CHECK_INPUT(g.NumNodes() >= 2, argv[1]) << "skeleton has fewer than 2 nodes";
  const double scale = options.scale > 0 ? options.scale : units == "m" ? 1000.0 : 1.0;
  for (SkeletonNode& node : g.nodes) node.position *= scale;
  std::vector<double> measured_deg, heights;
  ReadMeasures(argv[2], &measured_deg, &heights);

  // The main stem and its organs.
  const std::vector<int> stem = options.stem == "highest" ? PathToHighestTip(g) : g.BranchAxes()[0];
  const double stem_length = ChainLength(g, stem);
  const double base_z = g.nodes[stem[0]].position.z();
  const double rise = g.nodes[stem.back()].position.z() - base_z;
  double height = 0;
  for (const SkeletonNode& node : g.nodes) height = std::max(height, node.position.z() - base_z);
  std::printf(
      "skeleton %s (units \"%s\", x%g -> mm)\nstem \"%s\": %zu nodes, %.1f mm long, rises %.1f "
      "mm\n",
      argv[1], units.c_str(), scale, options.stem.c_str(), stem.size(), stem_length, rise);
  if (rise < 0.5 * height)
    std::printf("warning: the stem rises %.1f mm of the skeleton's %.1f mm; try --stem=highest\n",
                rise, height);
  int num_children = 0;
  const std::vector<Organ> organs = FindOrgans(g, stem, options, &num_children);
  SYLVA_CHECK_INPUT(!organs.empty(), argv[1])
      << "no branches leave the main stem (" << num_children
      << " side children, none >= " << options.min_organ_mm << " mm with a direction off the stem)";

  std::printf("organs at arc lengths (mm):");
  for (const Organ& o : organs) std::printf(" %.0f", o.arc_mm);
  std::printf("\n");
  // Pairing, comparison, summary.
  double offset = 0;
  const std::vector<int> match =
      MatchOrgans(heights, organs, stem_length, options.tolerance_mm, &offset);
  const Comparison c =
      CompareDivergences(measured_deg, heights, offset, match, organs, options.seed);
  const int matched =
      static_cast<int>(std::count_if(match.begin(), match.end(), [](int j) { return j >= 0; }));
  const double med_ours = Median(c.err_ours), med_mirror = Median(c.err_mirror);
  const char* better = c.ours.empty()           ? "n/a"
                       : med_ours <= med_mirror ? "ours (counter-clockwise about the stem)"
                                                : "360 - ours (clockwise about the stem)";
  std::printf("\nreconstructed organs on the main stem  %zu (of %d side children)\n", organs.size(),
              num_children);
  std::printf("measured organs matched                %d of %zu (offset %.1f mm)\n", matched,
              heights.size(), offset);
  std::printf("divergences compared                   %zu of %zu\n", c.ours.size(),
              measured_deg.size());
  std::printf("median |error|, ours                   %s\n", Deg(med_ours).c_str());
  std::printf("median |error|, 360 - ours             %s\n", Deg(med_mirror).c_str());
  std::printf("better convention                      %s\n", better);
  std::printf("median divergence, measured (compared) %s (all: %s)\n",
              Deg(Median(c.measured)).c_str(), Deg(Median(measured_deg)).c_str());
  std::printf("median divergence, ours / 360 - ours   %s / %s\n", Deg(Median(c.ours)).c_str(),
              Deg(360 - Median(c.ours)).c_str());
  std::printf("control: uniform random angles, error  %s\n", Deg(Median(c.err_random)).c_str());
  std::printf("control: constant 137.5 deg, error     %s\n", Deg(Median(c.err_golden)).c_str());
  return c.ours.empty() ? 1 : 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  try {
    return sylva::Main(argc, argv);
  } catch (const sylva::Error& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 2;
  }
}
