#include <cmath>
#include <cstdlib>

#include "core/util/check.h"
#include "reconstruct/matting/matting.h"
#include "reconstruct/matting/option_parsing.h"

namespace sylva {
namespace {

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts(1);
  for (char c : text) {
    if (c == separator) {
      parts.emplace_back();
    } else if (c != ' ') {
      parts.back() += c;
    }
  }
  return parts;
}

// A whole string as a finite number, or nullopt.
std::optional<double> ParseNumber(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

// Exactly `count` comma-separated numbers, or InputError naming `field`.
std::vector<double> ParseNumbers(const std::string& text, size_t count, const char* field,
                                 const char* format) {
  const std::vector<std::string> parts = Split(text, ',');
  std::vector<double> values;
  for (const std::string& part : parts) {
    const std::optional<double> value = ParseNumber(part);
    SYLVA_CHECK_INPUT(value.has_value() && parts.size() == count, field)
        << "must be " << format << ", got '" << text << "'";
    values.push_back(*value);
  }
  return values;
}

}  // namespace

bool HueRange::Contains(double hue_degrees) const {
  if (lo <= hi) return hue_degrees >= lo && hue_degrees <= hi;
  return hue_degrees >= lo || hue_degrees <= hi;
}

std::vector<HueRange> ParseHueRanges(const std::string& text) {
  std::vector<HueRange> ranges;
  if (text.empty()) return ranges;
  for (const std::string& part : Split(text, ',')) {
    const size_t dash = part.find('-', 1);
    std::optional<double> lo, hi;
    if (dash != std::string::npos) {
      lo = ParseNumber(part.substr(0, dash));
      hi = ParseNumber(part.substr(dash + 1));
    }
    SYLVA_CHECK_INPUT(lo && hi && *lo >= 0 && *lo <= 360 && *hi >= 0 && *hi <= 360,
                      "Matting.reject_hues")
        << "must be '' or 'lo-hi[,lo-hi...]' with degrees in [0, 360], got '" << text << "'";
    ranges.push_back({*lo, *hi});
  }
  return ranges;
}

std::optional<std::array<double, 3>> ParseBackdropColor(const std::string& text) {
  if (text == "auto") return std::nullopt;
  const std::vector<double> values =
      ParseNumbers(text, 3, "Matting.backdrop_color", "'auto' or 'R,G,B' in 0..255");
  std::array<double, 3> rgb{};
  for (int c = 0; c < 3; ++c) {
    SYLVA_CHECK_INPUT(values[c] >= 0 && values[c] <= 255, "Matting.backdrop_color")
        << "components must be in 0..255, got '" << text << "'";
    rgb[c] = values[c] / 255.0;
  }
  return rgb;
}

std::optional<RegionFraction> ParseRegion(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const std::vector<double> v =
      ParseNumbers(text, 4, "Matting.region", "'' or 'x0,y0,x1,y1' (fractions of the photo)");
  SYLVA_CHECK_INPUT(v[0] >= 0 && v[1] >= 0 && v[2] <= 1 && v[3] <= 1 && v[0] < v[2] && v[1] < v[3],
                    "Matting.region")
      << "needs 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1, got '" << text << "'";
  return RegionFraction{v[0], v[1], v[2], v[3]};
}

void MattingOptions::Check() const {
  SYLVA_CHECK_INPUT(
      trimap == "auto" || trimap == "backdrop" || trimap == "difference" || trimap == "grabcut",
      "Matting.trimap")
      << "must be 'auto', 'backdrop', 'difference' or 'grabcut', got '" << trimap << "'";
  SYLVA_CHECK_INPUT(auto_backdrop_fraction >= 0 && auto_backdrop_fraction <= 1,
                    "Matting.auto_backdrop_fraction")
      << "must be in [0, 1], got " << auto_backdrop_fraction;
  ParseBackdropColor(backdrop_color);
  SYLVA_CHECK_INPUT(border_fraction > 0 && border_fraction <= 0.25, "Matting.border_fraction")
      << "must be in (0, 0.25], got " << border_fraction;
  SYLVA_CHECK_INPUT(chroma_tolerance > 0 && chroma_tolerance <= 1, "Matting.chroma_tolerance")
      << "must be in (0, 1], got " << chroma_tolerance;
  SYLVA_CHECK_INPUT(luminance_tolerance > 0 && luminance_tolerance <= 1,
                    "Matting.luminance_tolerance")
      << "must be in (0, 1], got " << luminance_tolerance;
  SYLVA_CHECK_INPUT(dark_level > 0 && dark_level <= 1, "Matting.dark_level")
      << "must be in (0, 1], got " << dark_level;
  SYLVA_CHECK_INPUT(foreground_evidence > 1 && foreground_evidence <= 100,
                    "Matting.foreground_evidence")
      << "must be in (1, 100], got " << foreground_evidence;
  SYLVA_CHECK_INPUT(backdrop_smoothness > 0 && backdrop_smoothness <= 1,
                    "Matting.backdrop_smoothness")
      << "must be in (0, 1], got " << backdrop_smoothness;
  SYLVA_CHECK_INPUT(band_px >= 0 && band_px <= 100, "Matting.band_px")
      << "must be between 0 and 100 pixels, got " << band_px;
  ParseHueRanges(reject_hues);
  SYLVA_CHECK_INPUT(reject_min_saturation >= 0 && reject_min_saturation <= 1,
                    "Matting.reject_min_saturation")
      << "must be in [0, 1], got " << reject_min_saturation;
  SYLVA_CHECK_INPUT(reject_min_value >= 0 && reject_min_value <= 1, "Matting.reject_min_value")
      << "must be in [0, 1], got " << reject_min_value;
  SYLVA_CHECK_INPUT(reject_min_width_px >= 1 && reject_min_width_px <= 101,
                    "Matting.reject_min_width_px")
      << "must be between 1 and 101 pixels, got " << reject_min_width_px;
  SYLVA_CHECK_INPUT(reject_margin_px >= 0 && reject_margin_px <= 100, "Matting.reject_margin_px")
      << "must be between 0 and 100 pixels, got " << reject_margin_px;
  SYLVA_CHECK_INPUT(reject_below_value >= 0 && reject_below_value < 1, "Matting.reject_below_value")
      << "must be in [0, 1), got " << reject_below_value;
  ParseRegion(region);
  SYLVA_CHECK_INPUT(grabcut_iterations >= 1 && grabcut_iterations <= 100,
                    "Matting.grabcut_iterations")
      << "must be between 1 and 100, got " << grabcut_iterations;
  SYLVA_CHECK_INPUT(grabcut_margin > 0 && grabcut_margin < 0.5, "Matting.grabcut_margin")
      << "must be in (0, 0.5), got " << grabcut_margin;
  SYLVA_CHECK_INPUT(grabcut_max_megapixels >= 0.01 && grabcut_max_megapixels <= 100,
                    "Matting.grabcut_max_megapixels")
      << "must be in [0.01, 100], got " << grabcut_max_megapixels;
  SYLVA_CHECK_INPUT(refine == "closed_form" || refine == "alphamat" || refine == "none",
                    "Matting.refine")
      << "must be 'closed_form', 'alphamat' or 'none', got '" << refine << "'";
  SYLVA_CHECK_INPUT(max_megapixels >= 0.01 && max_megapixels <= 100, "Matting.max_megapixels")
      << "must be in [0.01, 100], got " << max_megapixels;
  SYLVA_CHECK_INPUT(closed_form_epsilon > 0 && closed_form_epsilon <= 1,
                    "Matting.closed_form_epsilon")
      << "must be in (0, 1], got " << closed_form_epsilon;
  SYLVA_CHECK_INPUT(closed_form_max_iterations >= 1 && closed_form_max_iterations <= 1000000,
                    "Matting.closed_form_max_iterations")
      << "must be between 1 and 1000000, got " << closed_form_max_iterations;
  SYLVA_CHECK_INPUT(closed_form_tolerance > 0 && closed_form_tolerance < 1,
                    "Matting.closed_form_tolerance")
      << "must be in (0, 1), got " << closed_form_tolerance;
  SYLVA_CHECK_INPUT(closed_form_prior_weight > 0 && closed_form_prior_weight <= 1,
                    "Matting.closed_form_prior_weight")
      << "must be in (0, 1], got " << closed_form_prior_weight;
  SYLVA_CHECK_INPUT(upsample_radius >= 1 && upsample_radius <= 50, "Matting.upsample_radius")
      << "must be between 1 and 50 pixels, got " << upsample_radius;
  SYLVA_CHECK_INPUT(upsample_epsilon > 0 && upsample_epsilon <= 1, "Matting.upsample_epsilon")
      << "must be in (0, 1], got " << upsample_epsilon;
  SYLVA_CHECK_INPUT(seed >= 0, "Matting.seed") << "must be >= 0, got " << seed;
}

}  // namespace sylva
