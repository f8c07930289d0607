#include "reconstruct/matting/matte_set.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

#include "core/util/check.h"
#include "reconstruct/matting/cv_image.h"

namespace sylva {
namespace {

// Matte values at or above this are foreground.
constexpr float kForegroundAlpha = 0.5f;
// For the static test, a pixel is foreground from this alpha: a rig's
// structure often fades out in the mattes (lit walls, glowing edges), and
// its faint parts must go with it.
constexpr float kStaticAlpha = 0.25f;
// Static structure is cleaned of specks up to this radius (analysis pixels).
constexpr int kStaticSpeckRadius = 1;
// Pieces of the moving foreground smaller than this share of the largest
// piece are flicker, not the subject.
constexpr double kSubjectPieceShare = 0.05;
// Static structure covering less than this share of the image is left alone:
// a few pixels of a trunk's base or of flicker, not a rig.
constexpr double kMinStructureShare = 0.001;

std::string Percent(double share) {
  std::ostringstream out;
  out << std::setprecision(3) << 100.0 * share << " %";
  return out.str();
}

// Photos of one size, by index.
std::map<std::pair<int, int>, std::vector<int>> GroupBySize(const std::vector<FloatImage>& photos) {
  std::map<std::pair<int, int>, std::vector<int>> groups;
  for (size_t i = 0; i < photos.size(); ++i) {
    groups[{photos[i].width(), photos[i].height()}].push_back(static_cast<int>(i));
  }
  return groups;
}

// Per pixel of a group of photos: in how many the matte is foreground, and
// in how many it is foreground and the photo matches the per-pixel median of
// the group's photos in every channel.
struct StaticCounts {
  cv::Mat foreground;  // CV_32S
  cv::Mat unchanged;   // CV_32S
};

StaticCounts CountStaticForeground(const std::vector<FloatImage>& photos,
                                   const std::vector<FloatImage>& mattes,
                                   const std::vector<int>& group, double tolerance) {
  const int width = photos[group[0]].width(), height = photos[group[0]].height();
  StaticCounts counts{cv::Mat(height, width, CV_32S, cv::Scalar(0)),
                      cv::Mat(height, width, CV_32S, cv::Scalar(0))};
  std::vector<float> samples(group.size());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      std::array<float, 3> median{};
      for (int c = 0; c < 3; ++c) {
        for (size_t k = 0; k < group.size(); ++k) samples[k] = photos[group[k]].at(x, y, c);
        std::nth_element(samples.begin(), samples.begin() + samples.size() / 2, samples.end());
        median[c] = samples[samples.size() / 2];
      }
      for (int i : group) {
        if (mattes[i].at(x, y) < kStaticAlpha) continue;
        ++counts.foreground.at<int>(y, x);
        bool same = true;
        for (int c = 0; c < 3; ++c) {
          same = same && std::abs(photos[i].at(x, y, c) - median[c]) <= tolerance;
        }
        counts.unchanged.at<int>(y, x) += same;
      }
    }
  }
  return counts;
}

// Pixels foreground in at least `needed` photos ("persistent"), and those of
// them that belong to a piece anchored by pixels also unchanged in colour in
// that many photos: the core grown into the persistent pixels around it
// (the structure's edges, where JPEG noise and blending change the colour).
struct StaticPixels {
  cv::Mat persistent;
  cv::Mat anchored;
};

StaticPixels FindStaticPixels(const StaticCounts& counts, int needed) {
  StaticPixels pixels;
  pixels.persistent = counts.foreground >= needed;
  cv::Mat core = counts.unchanged >= needed;
  cv::morphologyEx(core, core, cv::MORPH_OPEN, Disk(kStaticSpeckRadius));
  // Morphological reconstruction of the core inside the persistent pixels.
  cv::Mat grown = core & pixels.persistent, previous;
  do {
    previous = grown.clone();
    cv::dilate(grown, grown, Disk(1));
    grown &= pixels.persistent;
  } while (cv::countNonZero(grown != previous) > 0);
  pixels.anchored = grown | core;
  return pixels;
}

// The union over the group's photos of foreground outside `fixed`.
cv::Mat MovingUnion(const std::vector<FloatImage>& mattes, const std::vector<int>& group,
                    const cv::Mat& fixed) {
  cv::Mat moving(fixed.size(), CV_8U, cv::Scalar(0));
  for (int i : group) {
    for (int y = 0; y < fixed.rows; ++y) {
      for (int x = 0; x < fixed.cols; ++x) {
        if (mattes[i].at(x, y) >= kForegroundAlpha && fixed.at<uchar>(y, x) == 0) {
          moving.at<uchar>(y, x) = 255;
        }
      }
    }
  }
  return moving;
}

// The subject: the large pieces of what moves, pieces of at least
// kSubjectPieceShare of the largest one (specks of flicker are not), grown
// by a pixel so that what touches them is next to them.
cv::Mat NearSubject(const cv::Mat& moving) {
  cv::Mat labels, stats, centroids;
  const int num_labels =
      cv::connectedComponentsWithStats(moving, labels, stats, centroids, 8, CV_32S);
  int largest = 0;
  for (int label = 1; label < num_labels; ++label) {
    largest = std::max(largest, stats.at<int>(label, cv::CC_STAT_AREA));
  }
  cv::Mat subject(moving.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < labels.rows; ++y) {
    for (int x = 0; x < labels.cols; ++x) {
      const int label = labels.at<int>(y, x);
      if (label > 0 && stats.at<int>(label, cv::CC_STAT_AREA) >= kSubjectPieceShare * largest) {
        subject.at<uchar>(y, x) = 255;
      }
    }
  }
  cv::dilate(subject, subject, Disk(1));
  return subject;
}

// The connected pieces of `pixels` that are the rig's: those that do not
// touch the subject, and, if `border_is_rig`, those that reach the image
// border (a rig's frame, rails and walls do; a trunk carrying the crown does
// not).
cv::Mat RigPieces(const cv::Mat& pixels, const cv::Mat& near_subject, bool border_is_rig) {
  cv::Mat labels;
  const int num_labels = cv::connectedComponents(pixels, labels, 8, CV_32S);
  std::vector<char> touches_border(num_labels, 0), touches_subject(num_labels, 0);
  for (int y = 0; y < labels.rows; ++y) {
    for (int x = 0; x < labels.cols; ++x) {
      const int label = labels.at<int>(y, x);
      if (label == 0) continue;
      if (x == 0 || y == 0 || x == labels.cols - 1 || y == labels.rows - 1) {
        touches_border[label] = 1;
      }
      if (near_subject.at<uchar>(y, x)) touches_subject[label] = 1;
    }
  }
  cv::Mat rig(pixels.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < labels.rows; ++y) {
    for (int x = 0; x < labels.cols; ++x) {
      const int label = labels.at<int>(y, x);
      if (label != 0 && ((border_is_rig && touches_border[label]) || !touches_subject[label])) {
        rig.at<uchar>(y, x) = 255;
      }
    }
  }
  return rig;
}

// The rig: anchored static pieces that reach the border or do not touch the
// subject (a trunk or stem on the rotation axis, which looks the same from
// every side and carries the moving crown, stays), and persistent pieces
// without a colour anchor that do not touch the subject (a rig's thin edges,
// whose colour JPEG noise changes). Persistent pieces touching the subject
// stay even at the border: the middle of a crown that overflows the frame in
// every photo of a camera ring.
cv::Mat RigStructure(const StaticPixels& pixels, const std::vector<FloatImage>& mattes,
                     const std::vector<int>& group) {
  const cv::Mat near_subject = NearSubject(MovingUnion(mattes, group, pixels.persistent));
  const cv::Mat loose = pixels.persistent & ~pixels.anchored;
  return RigPieces(pixels.anchored, near_subject, true) | RigPieces(loose, near_subject, false);
}

// Foreground pixels of the group's mattes in total, and those outside `structure`.
void CountMoving(const std::vector<FloatImage>& mattes, const std::vector<int>& group,
                 const cv::Mat& structure, int64_t* foreground, int64_t* moving) {
  *foreground = *moving = 0;
  for (int i : group) {
    for (int y = 0; y < structure.rows; ++y) {
      for (int x = 0; x < structure.cols; ++x) {
        if (mattes[i].at(x, y) < kForegroundAlpha) continue;
        ++*foreground;
        *moving += structure.at<uchar>(y, x) == 0;
      }
    }
  }
}

FloatImage StructureImage(const cv::Mat& structure) {
  cv::Mat values;
  structure.convertTo(values, CV_32F, 1.0 / 255.0);
  return MatToImage(values);
}

}  // namespace

int MatteSetFactor(int width, int height, const MatteSetOptions& options) {
  return std::max(1, (std::max(width, height) + options.analysis_size - 1) / options.analysis_size);
}

FloatImage SmallMatte(const FloatImage& matte, int factor) {
  SYLVA_CHECK(factor >= 1 && matte.channels() == 1);
  FloatImage small((matte.width() + factor - 1) / factor, (matte.height() + factor - 1) / factor,
                   1);
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      float& value = small.at(x / factor, y / factor);
      value = std::max(value, matte.at(x, y));
    }
  }
  return small;
}

std::vector<FloatImage> FindStaticStructure(const std::vector<FloatImage>& small_photos,
                                            const std::vector<FloatImage>& small_mattes,
                                            const MatteSetOptions& options,
                                            std::vector<Warning>* warnings) {
  SYLVA_CHECK(small_photos.size() == small_mattes.size());
  std::vector<FloatImage> structures(small_photos.size());
  if (!options.remove_static) return structures;
  for (const auto& [size, group] : GroupBySize(small_photos)) {
    if (static_cast<int>(group.size()) < options.static_min_photos) continue;
    const int needed = static_cast<int>(std::ceil(options.static_photo_fraction * group.size()));
    const StaticPixels pixels = FindStaticPixels(
        CountStaticForeground(small_photos, small_mattes, group, options.static_color_tolerance),
        needed);
    cv::Mat structure = RigStructure(pixels, small_mattes, group);
    if (cv::countNonZero(structure) < kMinStructureShare * structure.total()) continue;
    if (options.static_margin_px > 0)
      cv::dilate(structure, structure, Disk(options.static_margin_px));
    int64_t foreground = 0, moving = 0;
    CountMoving(small_mattes, group, structure, &foreground, &moving);
    const double moving_share = foreground > 0 ? static_cast<double>(moving) / foreground : 0.0;
    const std::string photos = std::to_string(group.size()) + " photos of " +
                               std::to_string(size.first) + "x" + std::to_string(size.second) +
                               " (analysed size)";
    if (moving_share < options.static_min_moving_share) {
      warnings->push_back({"static-scene", photos + ": only " + Percent(moving_share) +
                                               " of the foreground changes between them; no "
                                               "static structure removed"});
      continue;
    }
    const double structure_share = static_cast<double>(cv::countNonZero(structure)) /
                                   (static_cast<double>(structure.rows) * structure.cols);
    warnings->push_back(
        {"static-structure", photos + ": " + Percent(structure_share) +
                                 " of the image is foreground at the same pixels in every photo "
                                 "(a fixed camera's rig: frame, rails, pot holder) and was made "
                                 "background (MatteSet.remove_static=false keeps it)"});
    const FloatImage image = StructureImage(structure);
    for (int i : group) structures[i] = image;
  }
  return structures;
}

MatteShape MeasureMatte(const FloatImage& matte) {
  MatteShape shape;
  const int w = matte.width(), h = matte.height();
  if (w == 0 || h == 0) return shape;
  int64_t foreground = 0, border = 0, border_foreground = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const bool is_foreground = matte.at(x, y) >= kForegroundAlpha;
      foreground += is_foreground;
      if (x == 0 || y == 0 || x == w - 1 || y == h - 1) {
        ++border;
        border_foreground += is_foreground;
      }
    }
  }
  shape.foreground_share = static_cast<double>(foreground) / (static_cast<double>(w) * h);
  shape.border_share = static_cast<double>(border_foreground) / border;
  return shape;
}

FloatImage RepairMatte(const FloatImage& photo, const FloatImage& hint, const FloatImage& own,
                       const std::array<double, 3>& backdrop_rgb, const MattingOptions& options) {
  SYLVA_CHECK(own.width() == photo.width() && own.height() == photo.height());
  MattingOptions keyed = options;
  keyed.trimap = "backdrop";
  std::ostringstream color;
  color << backdrop_rgb[0] * 255 << "," << backdrop_rgb[1] * 255 << "," << backdrop_rgb[2] * 255;
  keyed.backdrop_color = color.str();
  FloatImage matte = ComputeMatte(photo, hint, FloatImage(), keyed);
  for (size_t p = 0; p < matte.NumPixels(); ++p) {
    matte.data()[p] = std::min(matte.data()[p], own.data()[p]);
  }
  return matte;
}

std::string ImplausibleMatteReason(const MatteShape& shape, double median_foreground_share,
                                   const MatteSetOptions& options) {
  if (shape.border_share > options.max_border_share) {
    return "its foreground covers " + Percent(shape.border_share) + " of the image border";
  }
  if (median_foreground_share <= 0) return "";
  const double ratio = shape.foreground_share / median_foreground_share;
  if (ratio > options.max_foreground_ratio || ratio * options.max_foreground_ratio < 1) {
    return "its foreground is " + Percent(shape.foreground_share) + " of the image, the median " +
           "photo's " + Percent(median_foreground_share);
  }
  return "";
}

}  // namespace sylva
