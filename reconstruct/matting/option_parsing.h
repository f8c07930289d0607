// Parsers for the MattingOptions fields that are strings (internal to
// reconstruct/matting). Each throws InputError naming "Matting.<field>".
#ifndef SYLVA_RECONSTRUCT_MATTING_OPTION_PARSING_H_
#define SYLVA_RECONSTRUCT_MATTING_OPTION_PARSING_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace sylva {

// A hue interval in degrees [0, 360]; lo > hi wraps through 0.
struct HueRange {
  double lo = 0.0;
  double hi = 0.0;
  bool Contains(double hue_degrees) const;
};

// "" -> no ranges; "lo-hi[,lo-hi...]".
std::vector<HueRange> ParseHueRanges(const std::string& text);

// "auto" -> nullopt; "R,G,B" in 0..255 -> colour in [0, 1].
std::optional<std::array<double, 3>> ParseBackdropColor(const std::string& text);

// A region of interest in fractions of the image: x0 < x1, y0 < y1 in [0, 1].
struct RegionFraction {
  double x0 = 0.0, y0 = 0.0, x1 = 1.0, y1 = 1.0;
};

// "" -> nullopt (whole image); "x0,y0,x1,y1".
std::optional<RegionFraction> ParseRegion(const std::string& text);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MATTING_OPTION_PARSING_H_
