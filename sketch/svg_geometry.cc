#include "sketch/svg_geometry.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>

#include "core/util/check.h"

namespace sylva {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegrees = kPi / 180;
// Upper bound on the pieces of one flattened curve, so that absurd
// coordinates (1e300) cannot exhaust memory. A cubic spanning 1e6 pixels
// needs ~1700 pieces for a quarter pixel, an arc of radius 1e5 pixels ~5000.
constexpr int kMaxPiecesPerCurve = 10000;

bool IsSvgSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
bool IsDigit(char c) { return c >= '0' && c <= '9'; }

// Reads numbers, flags and letters from an attribute value and reports
// errors with the character offset.
class SvgScanner {
 public:
  explicit SvgScanner(std::string_view text) : text_(text) {}

  void SkipSpaces() {
    while (pos_ < text_.size() && IsSvgSpace(text_[pos_])) ++pos_;
  }
  // Whitespace and commas.
  void SkipSeparators() {
    while (pos_ < text_.size() && (IsSvgSpace(text_[pos_]) || text_[pos_] == ',')) ++pos_;
  }
  bool AtEnd() {
    SkipSeparators();
    return pos_ >= text_.size();
  }
  char Peek() const { return pos_ < text_.size() ? text_[pos_] : '\0'; }
  char Take() { return text_[pos_++]; }
  size_t position() const { return pos_; }
  std::string_view Rest() const { return text_.substr(pos_); }
  void Advance(size_t count) { pos_ += count; }

  // A number in SVG syntax after optional separators.
  double Number() {
    SkipSeparators();
    const size_t start = pos_;
    const size_t end = NumberEnd(start);
    if (end == start) Fail("expected a number");
    const size_t first = text_[start] == '+' ? start + 1 : start;  // from_chars rejects '+'
    double value = 0;
    const auto result = std::from_chars(text_.data() + first, text_.data() + end, value);
    if (result.ec != std::errc() || !std::isfinite(value)) Fail("number out of range");
    pos_ = end;
    return value;
  }
  Eigen::Vector2d Point() {
    const double x = Number();
    return {x, Number()};
  }
  // An arc flag: a single '0' or '1' (which may be followed directly by the
  // next number).
  bool Flag() {
    SkipSeparators();
    if (Peek() != '0' && Peek() != '1') Fail("expected an arc flag (0 or 1)");
    return Take() == '1';
  }
  // Whether a number starts here (after separators).
  bool AtNumber() {
    SkipSeparators();
    return NumberEnd(pos_) > pos_;
  }

  [[noreturn]] void Fail(const std::string& message) const {
    const std::string near(text_.substr(pos_, 12));
    throw InputError("", message + " at character " + std::to_string(pos_ + 1) +
                             (near.empty() ? " (the end)" : " ('" + near + "')"));
  }

 private:
  // End of the longest number in SVG syntax starting at `start` (== start if
  // none): sign? (digits ('.' digits?)? | '.' digits) (e sign? digits)?.
  size_t NumberEnd(size_t start) const {
    size_t i = start;
    if (i < text_.size() && (text_[i] == '+' || text_[i] == '-')) ++i;
    const size_t mantissa = i;
    while (i < text_.size() && IsDigit(text_[i])) ++i;
    bool digits = i > mantissa;
    if (i < text_.size() && text_[i] == '.') {
      const size_t fraction = ++i;
      while (i < text_.size() && IsDigit(text_[i])) ++i;
      digits = digits || i > fraction;
    }
    if (!digits) return start;
    if (i < text_.size() && (text_[i] == 'e' || text_[i] == 'E')) {
      size_t j = i + 1;
      if (j < text_.size() && (text_[j] == '+' || text_[j] == '-')) ++j;
      if (j < text_.size() && IsDigit(text_[j])) {
        while (j < text_.size() && IsDigit(text_[j])) ++j;
        i = j;
      }
    }
    return i;
  }

  std::string_view text_;
  size_t pos_ = 0;
};

// The largest factor by which `transform` stretches a length.
double MaxStretch(const Eigen::Affine2d& transform) {
  return Eigen::JacobiSVD<Eigen::Matrix2d>(transform.linear()).singularValues()(0);
}

// Pieces so that a curve whose second derivative is bounded by
// `max_second_derivative` stays within `tolerance` of its chords: the chord
// error over a parameter step h is at most h^2 / 8 * max |B''|.
int CurvePieces(double max_second_derivative, double tolerance) {
  const double pieces = std::ceil(std::sqrt(max_second_derivative / (8 * tolerance)));
  return static_cast<int>(std::clamp(pieces, 1.0, static_cast<double>(kMaxPiecesPerCurve)));
}

// Builds the polylines of one path in the target space.
class PathFlattener {
 public:
  PathFlattener(const Eigen::Affine2d& target_from_user, double tolerance)
      : target_from_user_(target_from_user), tolerance_(tolerance) {}

  const Eigen::Vector2d& current() const { return current_; }
  bool started() const { return !polylines_.empty(); }
  std::vector<std::vector<Eigen::Vector2d>> TakePolylines() { return std::move(polylines_); }

  void MoveTo(const Eigen::Vector2d& p) {
    current_ = start_ = p;
    polylines_.push_back({target_from_user_ * p});
    open_ = true;
  }
  void LineTo(const Eigen::Vector2d& p) {
    Append(target_from_user_ * p);
    current_ = p;
  }
  void Close() {
    if (open_) Append(target_from_user_ * start_);
    current_ = start_;
    open_ = false;
  }

  void CubicTo(const Eigen::Vector2d& c1, const Eigen::Vector2d& c2, const Eigen::Vector2d& p) {
    const Eigen::Vector2d q0 = target_from_user_ * current_, q1 = target_from_user_ * c1,
                          q2 = target_from_user_ * c2, q3 = target_from_user_ * p;
    // |B''(t)| <= 6 max(|q0 - 2 q1 + q2|, |q1 - 2 q2 + q3|).
    const double bound = 6 * std::max((q0 - 2 * q1 + q2).norm(), (q1 - 2 * q2 + q3).norm());
    const int pieces = CurvePieces(bound, tolerance_);
    for (int k = 1; k < pieces; ++k) {
      const double t = static_cast<double>(k) / pieces, s = 1 - t;
      Append(s * s * s * q0 + 3 * s * s * t * q1 + 3 * s * t * t * q2 + t * t * t * q3);
    }
    LineTo(p);
  }

  void QuadTo(const Eigen::Vector2d& c, const Eigen::Vector2d& p) {
    const Eigen::Vector2d q0 = target_from_user_ * current_, q1 = target_from_user_ * c,
                          q2 = target_from_user_ * p;
    const int pieces = CurvePieces(2 * (q0 - 2 * q1 + q2).norm(), tolerance_);  // |B''| = 2|...|
    for (int k = 1; k < pieces; ++k) {
      const double t = static_cast<double>(k) / pieces, s = 1 - t;
      Append(s * s * q0 + 2 * s * t * q1 + t * t * q2);
    }
    LineTo(p);
  }

  // SVG's elliptical arc from the current point to p (SVG 1.1 F.6.5, F.6.6).
  void ArcTo(double rx, double ry, double angle_degrees, bool large_arc, bool sweep,
             const Eigen::Vector2d& p) {
    if (p == current_) return;  // the spec omits such an arc entirely
    rx = std::abs(rx), ry = std::abs(ry);
    if (rx == 0 || ry == 0) return LineTo(p);
    const Eigen::Rotation2Dd axes(angle_degrees * kDegrees);
    // Step 1: the midpoint-relative start point in the ellipse's axes.
    const Eigen::Vector2d start_prime = axes.inverse() * ((current_ - p) / 2);
    // F.6.6: scale radii up until the ellipse reaches both points.
    const double lambda = start_prime.x() * start_prime.x() / (rx * rx) +
                          start_prime.y() * start_prime.y() / (ry * ry);
    if (lambda > 1) rx *= std::sqrt(lambda), ry *= std::sqrt(lambda);
    // Step 2: the centre in the ellipse's axes.
    const double x2 = start_prime.x() * start_prime.x(), y2 = start_prime.y() * start_prime.y();
    const double numerator = rx * rx * ry * ry - rx * rx * y2 - ry * ry * x2;
    double factor = std::sqrt(std::max(0.0, numerator / (rx * rx * y2 + ry * ry * x2)));
    if (large_arc == sweep) factor = -factor;
    const Eigen::Vector2d centre_prime(factor * rx * start_prime.y() / ry,
                                       -factor * ry * start_prime.x() / rx);
    // Step 3: the centre, the start angle and the swept angle.
    const Eigen::Vector2d centre = axes * centre_prime + (current_ + p) / 2;
    const Eigen::Vector2d u((start_prime.x() - centre_prime.x()) / rx,
                            (start_prime.y() - centre_prime.y()) / ry);
    const Eigen::Vector2d v((-start_prime.x() - centre_prime.x()) / rx,
                            (-start_prime.y() - centre_prime.y()) / ry);
    const double theta1 = std::atan2(u.y(), u.x());
    double delta = std::atan2(v.y(), v.x()) - theta1;
    if (sweep && delta < 0) delta += 2 * kPi;
    if (!sweep && delta > 0) delta -= 2 * kPi;
    // The affine image of a circle step d has chord error r (1 - cos(d / 2)).
    const double radius = std::max(rx, ry) * MaxStretch(target_from_user_);
    const double step = tolerance_ < radius ? 2 * std::acos(1 - tolerance_ / radius) : kPi / 2;
    const int pieces = static_cast<int>(
        std::clamp(std::ceil(std::abs(delta) / step), 1.0, double{kMaxPiecesPerCurve}));
    for (int k = 1; k < pieces; ++k) {
      const double theta = theta1 + delta * k / pieces;
      const Eigen::Vector2d on_ellipse(rx * std::cos(theta), ry * std::sin(theta));
      Append(target_from_user_ * (centre + axes * on_ellipse));
    }
    LineTo(p);
  }

  // A drawing command right after Z starts a new subpath at the current point.
  void EnsureOpen() {
    if (!open_) MoveTo(current_);
  }

 private:
  void Append(const Eigen::Vector2d& q) {
    if (polylines_.back().back() != q) polylines_.back().push_back(q);
  }

  Eigen::Affine2d target_from_user_;
  double tolerance_;
  std::vector<std::vector<Eigen::Vector2d>> polylines_;
  Eigen::Vector2d current_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d start_ = Eigen::Vector2d::Zero();
  bool open_ = false;
};

bool IsPathCommand(char c) { return c != 0 && std::strchr("MmLlHhVvCcSsQqTtAaZz", c) != nullptr; }

// Runs one path command's arguments (one repeat); `command` may change from
// moveto to lineto. Updates the reflected control point for S and T.
void RunPathCommand(SvgScanner* scanner, char* command, PathFlattener* path,
                    Eigen::Vector2d* reflected_cubic, Eigen::Vector2d* reflected_quad) {
  const bool relative = std::islower(static_cast<unsigned char>(*command));
  const Eigen::Vector2d base = relative ? path->current() : Eigen::Vector2d::Zero();
  const char kind = static_cast<char>(std::toupper(static_cast<unsigned char>(*command)));
  const Eigen::Vector2d current = path->current();
  // The control point that a following S or T reflects: by default the end
  // of this command (set below), the mirrored last control point after a
  // cubic (C, S) or quadratic (Q, T) segment.
  std::optional<Eigen::Vector2d> last_cubic_control, last_quad_control;
  if (kind == 'M') {
    path->MoveTo(base + scanner->Point());
    *command = relative ? 'l' : 'L';  // further pairs are implicit linetos
  } else if (kind == 'Z') {
    path->Close();
  } else {
    path->EnsureOpen();
    if (kind == 'L') {
      path->LineTo(base + scanner->Point());
    } else if (kind == 'H') {
      path->LineTo({base.x() + scanner->Number(), current.y()});
    } else if (kind == 'V') {
      path->LineTo({current.x(), base.y() + scanner->Number()});
    } else if (kind == 'C' || kind == 'S') {
      const Eigen::Vector2d c1 = kind == 'C' ? base + scanner->Point() : *reflected_cubic;
      last_cubic_control = base + scanner->Point();
      path->CubicTo(c1, *last_cubic_control, base + scanner->Point());
    } else if (kind == 'Q' || kind == 'T') {
      last_quad_control = kind == 'Q' ? base + scanner->Point() : *reflected_quad;
      path->QuadTo(*last_quad_control, base + scanner->Point());
    } else {  // 'A'
      const double rx = scanner->Number(), ry = scanner->Number(), angle = scanner->Number();
      const bool large_arc = scanner->Flag(), sweep = scanner->Flag();
      path->ArcTo(rx, ry, angle, large_arc, sweep, base + scanner->Point());
    }
  }
  const Eigen::Vector2d& end = path->current();
  *reflected_cubic = last_cubic_control ? Eigen::Vector2d(2 * end - *last_cubic_control) : end;
  *reflected_quad = last_quad_control ? Eigen::Vector2d(2 * end - *last_quad_control) : end;
}

Eigen::Affine2d TransformFromFunction(const std::string& name, const std::vector<double>& args,
                                      const SvgScanner& scanner) {
  const auto need = [&](std::initializer_list<size_t> counts) {
    if (std::find(counts.begin(), counts.end(), args.size()) == counts.end()) {
      scanner.Fail(name + "() does not take " + std::to_string(args.size()) + " numbers");
    }
  };
  Eigen::Affine2d t = Eigen::Affine2d::Identity();
  if (name == "matrix") {
    need({6});
    t.matrix() << args[0], args[2], args[4], args[1], args[3], args[5], 0, 0, 1;
  } else if (name == "translate") {
    need({1, 2});
    t.translate(Eigen::Vector2d(args[0], args.size() > 1 ? args[1] : 0));
  } else if (name == "scale") {
    need({1, 2});
    t.scale(Eigen::Vector2d(args[0], args.size() > 1 ? args[1] : args[0]));
  } else if (name == "rotate") {
    need({1, 3});
    const Eigen::Vector2d pivot =
        args.size() > 1 ? Eigen::Vector2d(args[1], args[2]) : Eigen::Vector2d::Zero();
    t.translate(pivot).rotate(args[0] * kDegrees).translate(-pivot);
  } else if (name == "skewX" || name == "skewY") {
    need({1});
    t.linear()(name == "skewX" ? 0 : 1, name == "skewX" ? 1 : 0) = std::tan(args[0] * kDegrees);
  } else {
    scanner.Fail("unknown transform '" + name + "'");
  }
  return t;
}

}  // namespace

std::vector<double> ParseSvgNumbers(std::string_view text) {
  SvgScanner scanner(text);
  std::vector<double> numbers;
  while (!scanner.AtEnd()) numbers.push_back(scanner.Number());
  return numbers;
}

double ParseSvgLength(std::string_view text) {
  SvgScanner scanner(text);
  const double value = scanner.Number();
  std::string unit(scanner.Rest());
  while (!unit.empty() && IsSvgSpace(unit.back())) unit.pop_back();
  const double pixels_per_unit = unit.empty() || unit == "px" ? 1.0
                                 : unit == "in"               ? 96.0
                                 : unit == "cm"               ? 96.0 / 2.54
                                 : unit == "mm"               ? 96.0 / 25.4
                                 : unit == "pt"               ? 96.0 / 72
                                 : unit == "pc"               ? 16.0
                                                              : 0.0;
  if (pixels_per_unit == 0) scanner.Fail("unsupported length unit '" + unit + "'");
  return value * pixels_per_unit;
}

Eigen::Affine2d ParseSvgTransform(std::string_view text) {
  SvgScanner scanner(text);
  Eigen::Affine2d parent_from_element = Eigen::Affine2d::Identity();
  while (!scanner.AtEnd()) {
    std::string name;
    while (std::isalpha(static_cast<unsigned char>(scanner.Peek()))) name += scanner.Take();
    if (name.empty()) scanner.Fail("expected a transform name");
    scanner.SkipSpaces();
    if (scanner.Peek() != '(') scanner.Fail("expected '(' after " + name);
    scanner.Take();
    std::vector<double> args;
    while (!scanner.AtEnd() && scanner.Peek() != ')') args.push_back(scanner.Number());
    if (scanner.Peek() != ')') scanner.Fail("expected ')' to close " + name + "(");
    scanner.Take();
    parent_from_element = parent_from_element * TransformFromFunction(name, args, scanner);
  }
  return parent_from_element;
}

std::vector<std::vector<Eigen::Vector2d>> FlattenSvgPath(std::string_view path_data,
                                                         const Eigen::Affine2d& target_from_user,
                                                         double tolerance) {
  SYLVA_CHECK(tolerance > 0);
  SvgScanner scanner(path_data);
  PathFlattener path(target_from_user, tolerance);
  Eigen::Vector2d reflected_cubic = Eigen::Vector2d::Zero(), reflected_quad = reflected_cubic;
  char command = 0;
  while (!scanner.AtEnd()) {
    if (IsPathCommand(scanner.Peek())) {
      command = scanner.Take();
    } else if (command == 0 || command == 'Z' || command == 'z' || !scanner.AtNumber()) {
      // Numbers repeat the last command, except after Z.
      scanner.Fail(std::isalpha(static_cast<unsigned char>(scanner.Peek()))
                       ? "unknown path command '" + std::string(1, scanner.Peek()) + "'"
                       : std::string("expected a path command"));
    }
    if (!path.started() && command != 'M' && command != 'm') {
      scanner.Fail("path data must start with a moveto (M or m)");
    }
    RunPathCommand(&scanner, &command, &path, &reflected_cubic, &reflected_quad);
  }
  return path.TakePolylines();
}

}  // namespace sylva
