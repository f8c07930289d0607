#include "sketch/scan_interpret.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <opencv2/imgproc.hpp>

namespace sylva::scan {
namespace {

// ---- Trunk outline pairs ----

// A point every `spacing` along a stroke, with its arc length and unit
// tangent.
struct Sample {
  int stroke = 0;
  double arc = 0;
  Eigen::Vector2d point, tangent;
};

std::vector<double> ArcLengths(const std::vector<Eigen::Vector2d>& points) {
  std::vector<double> arcs(points.size(), 0.0);
  for (size_t i = 1; i < points.size(); ++i) {
    arcs[i] = arcs[i - 1] + (points[i] - points[i - 1]).norm();
  }
  return arcs;
}

std::vector<Sample> SampleStroke(const TracedStroke& stroke, int index, double spacing) {
  const std::vector<Eigen::Vector2d>& points = stroke.edge.points;
  const std::vector<double> arcs = ArcLengths(points);
  std::vector<Sample> samples;
  for (size_t i = 0, j = 0; i < points.size(); ++i) {
    if (!samples.empty() && arcs[i] - samples.back().arc < spacing) continue;
    // The tangent over about one spacing on either side.
    while (j + 1 < points.size() && arcs[j + 1] < arcs[i] - spacing) ++j;
    size_t k = i;
    while (k + 1 < points.size() && arcs[k] < arcs[i] + spacing) ++k;
    const Eigen::Vector2d along = points[k] - points[j];
    if (along.norm() == 0) continue;
    samples.push_back({index, arcs[i], points[i], along.normalized()});
  }
  return samples;
}

// Whether sample b lies across from sample a like the other outline of a
// trunk: at a trunk's separation, along a's normal, running parallel, and
// (on the same stroke) not just a neighbour along it.
bool Opposite(const Sample& a, const Sample& b, const TrunkPairOptions& options, double sin_max,
              double* distance) {
  const Eigen::Vector2d ab = b.point - a.point;
  const double d = ab.norm();
  if (d < options.min_separation_px || d > options.max_separation_px) return false;
  if (a.stroke == b.stroke && std::abs(a.arc - b.arc) < 2 * d) return false;
  const double cos_max = std::sqrt(1 - sin_max * sin_max);
  if (std::abs(a.tangent.dot(b.tangent)) < cos_max) return false;
  if (std::abs(a.tangent.dot(ab)) > sin_max * d) return false;
  *distance = d;
  return true;
}

// Whether the paper shows midway between a and b (a trunk's inside is not
// inked; two branches with a third between them are no trunk).
bool PaperBetween(const cv::Mat& ink, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d middle = 0.5 * (a + b);
  return !ink.at<uchar>(static_cast<int>(std::lround(middle.y())),
                        static_cast<int>(std::lround(middle.x())));
}

// For each sample, the nearest opposite sample (-1 if none), by a grid of
// cells as large as the greatest separation.
std::vector<int> MatchSamples(const cv::Mat& ink, const std::vector<Sample>& samples,
                              const TrunkPairOptions& options) {
  const double cell = options.max_separation_px;
  std::map<std::pair<int, int>, std::vector<int>> grid;
  const auto cell_of = [cell](const Eigen::Vector2d& p) {
    return std::make_pair(static_cast<int>(std::floor(p.x() / cell)),
                          static_cast<int>(std::floor(p.y() / cell)));
  };
  for (size_t i = 0; i < samples.size(); ++i) {
    grid[cell_of(samples[i].point)].push_back(static_cast<int>(i));
  }
  const double sin_max = std::sin(options.max_angle_rad);
  std::vector<int> partner(samples.size(), -1);
  for (size_t i = 0; i < samples.size(); ++i) {
    const auto [cx, cy] = cell_of(samples[i].point);
    double best = options.max_separation_px + 1;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const auto it = grid.find({cx + dx, cy + dy});
        if (it == grid.end()) continue;
        for (int j : it->second) {
          double d = 0;
          if (Opposite(samples[i], samples[j], options, sin_max, &d) && d < best &&
              PaperBetween(ink, samples[i].point, samples[j].point)) {
            best = d;
            partner[i] = j;
          }
        }
      }
    }
  }
  return partner;
}

constexpr int kMaxRunGap = 3;

// A stretch of one stroke's samples [first, last] matched to one partner
// stroke.
struct Run {
  int first = 0, last = 0;
  int partner_stroke = -1;
};

// Maximal runs of matched samples with the same partner stroke along each
// stroke (samples are in stroke order), bridging up to kMaxRunGap
// unmatched samples (where a hand-drawn outline wobbles out of parallel).
std::vector<Run> FindRuns(const std::vector<Sample>& samples, const std::vector<int>& partner) {
  std::vector<Run> runs;
  for (int i = 0; i < static_cast<int>(samples.size()); ++i) {
    if (partner[i] < 0) continue;
    const int other = samples[partner[i]].stroke;
    const bool continues = !runs.empty() && runs.back().partner_stroke == other &&
                           samples[runs.back().last].stroke == samples[i].stroke &&
                           i - runs.back().last <= kMaxRunGap + 1;
    if (continues) {
      runs.back().last = i;
    } else {
      runs.push_back({i, i, other});
    }
  }
  return runs;
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

// Arc-length intervals of a stroke that a trunk pair used up.
using Cuts = std::vector<std::pair<double, double>>;

// The pieces of `stroke` outside `cuts` that are at least `min_length` long.
std::vector<TracedStroke> CutStroke(const TracedStroke& stroke, const Cuts& cuts,
                                    double min_length) {
  const std::vector<Eigen::Vector2d>& points = stroke.edge.points;
  const std::vector<double> arcs = ArcLengths(points);
  const auto is_cut = [&](double arc) {
    return std::any_of(cuts.begin(), cuts.end(),
                       [arc](const auto& c) { return arc >= c.first && arc <= c.second; });
  };
  std::vector<TracedStroke> pieces;
  TracedStroke piece = stroke;
  piece.edge = SkeletonEdge{};
  const auto flush = [&]() {
    if (piece.edge.points.size() >= 2 && EdgeLength(piece.edge) >= min_length) {
      pieces.push_back(piece);
    }
    piece.edge.points.clear();
  };
  for (size_t i = 0; i < points.size(); ++i) {
    if (is_cut(arcs[i])) {
      flush();
    } else {
      piece.edge.points.push_back(points[i]);
    }
  }
  flush();
  return pieces;
}

// ---- Crown outlines ----

// Labels of the paper regions the ink encloses (not reaching the page's
// edge), and whether each is large enough to be the inside of a crown.
cv::Mat EnclosedRegions(const cv::Mat& ink, double min_area, std::vector<uchar>& enclosed,
                        std::vector<uchar>& large) {
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(ink == 0, labels, stats, centroids, 4);
  enclosed.assign(count, 0);
  large.assign(count, 0);
  for (int c = 1; c < count; ++c) {
    const int x = stats.at<int>(c, cv::CC_STAT_LEFT), y = stats.at<int>(c, cv::CC_STAT_TOP);
    const int w = stats.at<int>(c, cv::CC_STAT_WIDTH), h = stats.at<int>(c, cv::CC_STAT_HEIGHT);
    enclosed[c] = x > 0 && y > 0 && x + w < ink.cols && y + h < ink.rows;
    large[c] = enclosed[c] && stats.at<int>(c, cv::CC_STAT_AREA) >= min_area;
  }
  return labels;
}

cv::Mat RegionMask(const cv::Mat& labels, const std::vector<uchar>& chosen) {
  cv::Mat mask(labels.size(), CV_8U);
  for (int y = 0; y < labels.rows; ++y) {
    const int* label = labels.ptr<int>(y);
    uchar* out = mask.ptr<uchar>(y);
    for (int x = 0; x < labels.cols; ++x) out[x] = chosen[label[x]] ? 255 : 0;
  }
  return mask;
}

// Morphology by a disc of `radius_px` through the distance transform: O(pixels)
// whatever the radius, where cv::dilate with a disc of 2 line widths costs
// as many operations per pixel as the disc has pixels.
cv::Mat Grow(const cv::Mat& mask, double radius_px) {
  cv::Mat distance;
  cv::distanceTransform(mask == 0, distance, cv::DIST_L2, cv::DIST_MASK_5);
  return distance <= radius_px;
}
cv::Mat Shrink(const cv::Mat& mask, double radius_px) {
  cv::Mat distance;
  cv::distanceTransform(mask, distance, cv::DIST_L2, cv::DIST_MASK_5);
  return distance > radius_px;
}

// The crown's inside: the large enclosed regions, with the small ones that
// lie more next to them than next to the open paper outside (the pockets
// between the outline and a branch touching it, but not the gap between
// two branches forking below the crown), and the strokes between them;
// without the inside of trunk outline pairs.
cv::Mat CrownMask(const cv::Mat& ink, const CrownOptions& options,
                  const std::vector<TracedStroke>& strokes) {
  const double min_area = options.min_area_fraction * cv::boundingRect(ink).area();
  std::vector<uchar> enclosed, large;
  const cv::Mat labels = EnclosedRegions(ink, min_area, enclosed, large);
  cv::Mat mask = RegionMask(labels, large);
  std::vector<uchar> outside(enclosed.size());
  for (size_t c = 1; c < enclosed.size(); ++c) outside[c] = !enclosed[c];
  const cv::Mat near_crown = Grow(mask, 2 * options.line_width_px);
  const cv::Mat near_outside = Grow(RegionMask(labels, outside), 2 * options.line_width_px);
  std::vector<int> crown_side(enclosed.size(), 0), outside_side(enclosed.size(), 0);
  for (int y = 0; y < labels.rows; ++y) {
    for (int x = 0; x < labels.cols; ++x) {
      crown_side[labels.at<int>(y, x)] += near_crown.at<uchar>(y, x) != 0;
      outside_side[labels.at<int>(y, x)] += near_outside.at<uchar>(y, x) != 0;
    }
  }
  std::vector<uchar> chosen = large;
  for (size_t c = 1; c < enclosed.size(); ++c) {
    chosen[c] |= enclosed[c] && crown_side[c] > 0 && crown_side[c] >= outside_side[c];
  }
  mask = RegionMask(labels, chosen);
  mask = Shrink(Grow(mask, 2 * options.line_width_px), 2 * options.line_width_px);
  for (const TracedStroke& stroke : strokes) {
    if (!stroke.trunk_pair) continue;
    std::vector<cv::Point> line;
    for (const Eigen::Vector2d& p : stroke.edge.points) line.emplace_back(p.x(), p.y());
    const int thickness = static_cast<int>(std::ceil(stroke.width + 2 * options.line_width_px));
    cv::polylines(mask, line, false, cv::Scalar(0), thickness);
  }
  return mask;
}

// The crown outlines: the outer boundaries of the crown mask's large parts,
// grown by half a line width to run along the drawn outline's centre.
std::vector<std::vector<cv::Point>> CrownOutlines(const cv::Mat& ink, const CrownOptions& options,
                                                  const std::vector<TracedStroke>& strokes) {
  cv::Mat mask = CrownMask(ink, options, strokes);
  mask = Grow(mask, 0.5 * (options.line_width_px - 1));
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  const double min_area = options.min_area_fraction * cv::boundingRect(ink).area();
  contours.erase(std::remove_if(contours.begin(), contours.end(),
                                [&](const auto& c) { return cv::contourArea(c) < min_area; }),
                 contours.end());
  return contours;
}

// Distances (pixels) to one outline over its bounding box grown by
// `margin_px`: a point near the outline is looked up, not searched for.
struct OutlineDistance {
  cv::Rect box;
  cv::Mat distance;  // CV_32F over `box`

  OutlineDistance(const std::vector<cv::Point>& outline, const cv::Size& page, int margin_px) {
    box = cv::boundingRect(outline);
    box -= cv::Point(margin_px, margin_px);
    box += cv::Size(2 * margin_px, 2 * margin_px);
    box &= cv::Rect(cv::Point(0, 0), page);
    cv::Mat shifted(box.size(), CV_8U, cv::Scalar(255));
    std::vector<cv::Point> local;
    for (const cv::Point& p : outline) local.push_back(p - box.tl());
    cv::polylines(shifted, local, true, cv::Scalar(0), 1, cv::LINE_8);
    cv::distanceTransform(shifted, distance, cv::DIST_L2, cv::DIST_MASK_3);
  }

  bool Near(const Eigen::Vector2d& p, double near_px) const {
    const cv::Point q(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
    return box.contains(q) && distance.at<float>(q - box.tl()) <= near_px;
  }
};

// The outline most of the stroke lies on, or -1.
int OutlineOf(const TracedStroke& stroke, const std::vector<OutlineDistance>& outlines,
              const CrownOptions& options) {
  const double near_px = options.line_width_px + 1;
  const std::vector<Eigen::Vector2d>& points = stroke.edge.points;
  for (size_t o = 0; o < outlines.size(); ++o) {
    const auto on = std::count_if(points.begin(), points.end(), [&](const Eigen::Vector2d& p) {
      return outlines[o].Near(p, near_px);
    });
    if (on >= options.on_outline_fraction * points.size()) return static_cast<int>(o);
  }
  return -1;
}

}  // namespace

int MergeTrunkPairs(const cv::Mat& ink, const TrunkPairOptions& options,
                    std::vector<TracedStroke>& strokes) {
  const double spacing = std::max(2.0, options.line_width_px);
  std::vector<Sample> samples;
  for (size_t s = 0; s < strokes.size(); ++s) {
    const std::vector<Sample> more = SampleStroke(strokes[s], static_cast<int>(s), spacing);
    samples.insert(samples.end(), more.begin(), more.end());
  }
  const std::vector<int> partner = MatchSamples(ink, samples, options);
  std::vector<Cuts> cuts(strokes.size());
  std::vector<TracedStroke> trunks;
  for (const Run& run : FindRuns(samples, partner)) {
    const int stroke = samples[run.first].stroke;
    // Each pair once: from its lower-numbered stroke, or on a U-shaped
    // stroke from the arm that comes first.
    if (run.partner_stroke < stroke) continue;
    if (run.partner_stroke == stroke && samples[partner[run.first]].arc < samples[run.first].arc) {
      continue;
    }
    TracedStroke trunk;
    trunk.trunk_pair = true;
    std::vector<double> separations;
    double partner_min = 1e300, partner_max = -1e300;
    for (int i = run.first; i <= run.last; ++i) {
      if (partner[i] < 0) continue;
      const Sample& other = samples[partner[i]];
      trunk.edge.points.push_back(0.5 * (samples[i].point + other.point));
      separations.push_back((other.point - samples[i].point).norm());
      partner_min = std::min(partner_min, other.arc);
      partner_max = std::max(partner_max, other.arc);
    }
    trunk.width = Median(separations);
    const double length = samples[run.last].arc - samples[run.first].arc;
    if (length < options.min_length_separations * trunk.width) continue;
    double base_y = -1e300;
    for (const Eigen::Vector2d& p : trunk.edge.points) base_y = std::max(base_y, p.y());
    if (base_y < options.min_base_y_px) continue;
    cuts[stroke].push_back({samples[run.first].arc - spacing, samples[run.last].arc + spacing});
    cuts[run.partner_stroke].push_back({partner_min - spacing, partner_max + spacing});
    trunks.push_back(std::move(trunk));
  }
  if (trunks.empty()) return 0;
  std::vector<TracedStroke> result;
  for (size_t s = 0; s < strokes.size(); ++s) {
    if (cuts[s].empty()) {
      result.push_back(std::move(strokes[s]));
      continue;
    }
    // Leftovers shorter than twice the widest pair through them: caps.
    double cap = 0;
    for (const TracedStroke& t : trunks) cap = std::max(cap, 2 * t.width);
    for (TracedStroke& piece : CutStroke(strokes[s], cuts[s], cap)) result.push_back(piece);
  }
  const int pairs = static_cast<int>(trunks.size());
  for (TracedStroke& trunk : trunks) result.push_back(std::move(trunk));
  strokes = std::move(result);
  return pairs;
}

void MarkCrownStrokes(const cv::Mat& ink, const CrownOptions& options,
                      std::vector<TracedStroke>& strokes) {
  const std::vector<std::vector<cv::Point>> outlines = CrownOutlines(ink, options, strokes);
  std::vector<OutlineDistance> distances;
  const int margin_px = static_cast<int>(std::ceil(options.line_width_px)) + 3;
  for (const auto& outline : outlines) distances.emplace_back(outline, ink.size(), margin_px);
  std::vector<double> width_sum(outlines.size(), 0.0);
  std::vector<int> on_outline(outlines.size(), 0);
  std::vector<TracedStroke> result;
  for (TracedStroke& stroke : strokes) {
    const int outline = stroke.trunk_pair ? -1 : OutlineOf(stroke, distances, options);
    if (outline < 0) {
      result.push_back(std::move(stroke));
    } else {
      width_sum[outline] += stroke.width;
      ++on_outline[outline];
    }
  }
  // One closed stroke per outline that drawn strokes lie on.
  for (size_t o = 0; o < outlines.size(); ++o) {
    if (on_outline[o] == 0) continue;
    TracedStroke crown;
    for (const cv::Point& p : outlines[o]) crown.edge.points.emplace_back(p.x, p.y);
    crown.edge.closed = true;
    crown.role = StrokeRole::kCrown;
    crown.width = width_sum[o] / on_outline[o];
    result.push_back(std::move(crown));
  }
  strokes = std::move(result);
}

}  // namespace sylva::scan
