#include "sketch/drawing.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

constexpr StrokeRole kRoles[] = {StrokeRole::kBranch, StrokeRole::kCrown, StrokeRole::kConstruction,
                                 StrokeRole::kOrgan};

bool Finite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

}  // namespace

const char* StrokeRoleName(StrokeRole role) {
  switch (role) {
    case StrokeRole::kBranch:
      return "branch";
    case StrokeRole::kCrown:
      return "crown";
    case StrokeRole::kConstruction:
      return "construction";
    case StrokeRole::kOrgan:
      return "organ";
  }
  return "branch";
}

std::optional<StrokeRole> StrokeRoleFromName(const std::string& name) {
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (StrokeRole role : kRoles) {
    if (lower == StrokeRoleName(role)) return role;
  }
  return std::nullopt;
}

int SketchDrawing::CountRole(StrokeRole role) const {
  return static_cast<int>(std::count_if(strokes.begin(), strokes.end(),
                                        [role](const SketchStroke& s) { return s.role == role; }));
}

void SketchDrawing::Check() const {
  SYLVA_CHECK_INPUT(std::isfinite(width) && std::isfinite(height) && width > 0 && height > 0,
                    source)
      << "the canvas size must be positive, got " << width << " x " << height;
  SYLVA_CHECK_INPUT(!strokes.empty(), source) << "the drawing has no strokes";
  // Points farther out than the canvas' own size mean a broken file or
  // coordinates in another unit.
  const auto near_canvas = [this](const Eigen::Vector2d& p) {
    return Finite(p) && p.x() >= -width && p.x() <= 2 * width && p.y() >= -height &&
           p.y() <= 2 * height;
  };
  for (size_t s = 0; s < strokes.size(); ++s) {
    const SketchStroke& stroke = strokes[s];
    const size_t needed = stroke.closed ? 3 : 2;
    SYLVA_CHECK_INPUT(stroke.points.size() >= needed, source)
        << "stroke " << s << " (" << StrokeRoleName(stroke.role) << ") has " << stroke.points.size()
        << " points, needs at least " << needed;
    SYLVA_CHECK_INPUT(std::isfinite(stroke.width) && stroke.width >= 0, source)
        << "stroke " << s << " has width " << stroke.width;
    for (const Eigen::Vector2d& p : stroke.points) {
      SYLVA_CHECK_INPUT(near_canvas(p), source)
          << "stroke " << s << " has the point (" << p.x() << ", " << p.y() << ") far outside the "
          << width << " x " << height << " canvas";
    }
  }
  if (root) {
    SYLVA_CHECK_INPUT(near_canvas(*root), source)
        << "the root (" << root->x() << ", " << root->y() << ") lies far outside the canvas";
  }
}

}  // namespace sylva
