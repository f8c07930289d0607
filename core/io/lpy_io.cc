#include "core/io/lpy_io.h"

#include <Eigen/Geometry>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;
// PlantGL's defaults: rotations without an argument turn 60 degrees, `_`
// (`!`) without one adds (subtracts) 1 to the width, F without one moves 1.
constexpr double kDefaultAngle = 60.0;
constexpr double kDefaultWidthIncrement = 1.0;
constexpr double kDefaultLength = 1.0;
// PlantGL's initial width.
constexpr double kInitialWidth = 0.1;

std::string DoubleText(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string Call(const std::string& name, std::initializer_list<double> args) {
  std::string text = name + "(";
  bool first = true;
  for (double arg : args) {
    text += (first ? "" : ",") + DoubleText(arg);
    first = false;
  }
  return text + ")";
}

// The turtle's position and frame (PlantGL: heading, left, up).
struct Turtle {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d heading = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d left = -Eigen::Vector3d::UnitY();
  Eigen::Vector3d up = Eigen::Vector3d::UnitX();
  double width = kInitialWidth;

  // The axis is normalised: a frame rotated about its own slightly
  // non-unit vectors would shrink geometrically over thousands of rotations.
  static Eigen::Vector3d Rotate(const Eigen::Vector3d& v, const Eigen::Vector3d& axis,
                                double degrees) {
    return Eigen::AngleAxisd(degrees * kDegree, axis.normalized()) * v;
  }
  // `+`: about U, H towards L.
  void Turn(double degrees) {
    const Eigen::Vector3d axis = up;
    heading = Rotate(heading, axis, degrees);
    left = Rotate(left, axis, degrees);
  }
  // `&`: about L, H towards -U.
  void Pitch(double degrees) {
    const Eigen::Vector3d axis = left;
    heading = Rotate(heading, axis, degrees);
    up = Rotate(up, axis, degrees);
  }
  // `/`: about H, L towards U.
  void Roll(double degrees) {
    const Eigen::Vector3d axis = heading;
    left = Rotate(left, axis, degrees);
    up = Rotate(up, axis, degrees);
  }
};

// ---------------------------------------------------------------------------
// Writing

class AxiomWriter {
 public:
  AxiomWriter(const SkeletonGraph& skeleton, LpyForm form, std::string* out,
              std::vector<int>* order)
      : skeleton_(skeleton), form_(form), out_(out), order_(order) {
    axes_ = skeleton.BranchAxes(nullptr);
    laterals_.resize(skeleton.nodes.size());
    for (size_t a = 1; a < axes_.size(); ++a) laterals_[axes_[a][0]].push_back(static_cast<int>(a));
  }

  void Write() {
    if (axes_.empty()) return;
    const SkeletonNode& root = skeleton_.nodes[axes_[0][0]];
    Turtle turtle;
    turtle.position = root.position;
    *out_ += "[" + Call("@M", {root.position.x(), root.position.y(), root.position.z()}) + " " +
             Call("_", {root.radius});
    order_->push_back(axes_[0][0]);
    Laterals(axes_[0][0], turtle);
    Axis(0, turtle);
    *out_ += "]";
  }

 private:
  // Draws axis a's nodes after its first from `turtle`, with the branches leaving each.
  void Axis(int a, Turtle turtle) {
    const BranchAxis& axis = axes_[a];
    for (size_t k = 1; k < axis.size(); ++k) {
      Segment(skeleton_.nodes[axis[k]], &turtle);
      order_->push_back(axis[k]);
      Laterals(axis[k], turtle);
    }
  }

  // The branches leaving `node`, each in brackets. A branch starts with
  // its first node's width, except at the root: there the root is drawn
  // first by the branch, and the width it starts with is the root's radius.
  void Laterals(int node, const Turtle& turtle) {
    for (int b : laterals_[node]) {
      const Eigen::Vector3d& at = skeleton_.nodes[node].position;
      *out_ += " [";
      if (form_ == LpyForm::kAbsolute) *out_ += Call("@M", {at.x(), at.y(), at.z()});
      if (node != axes_[0][0]) {
        *out_ += (form_ == LpyForm::kAbsolute ? " " : "") +
                 Call("_", {skeleton_.nodes[axes_[b][1]].radius});
      }
      Axis(b, turtle);
      *out_ += "]";
    }
  }

  void Segment(const SkeletonNode& node, Turtle* turtle) {
    const Eigen::Vector3d& p = node.position;
    if (form_ == LpyForm::kAbsolute) {
      *out_ += " " + Call("LineTo", {p.x(), p.y(), p.z(), node.radius});
      return;
    }
    // Aim from where the interpreter's turtle will be (no drift builds up).
    const Eigen::Vector3d d = p - turtle->position;
    const double length = d.norm();
    if (length > 0) {
      const double dh = d.dot(turtle->heading), dl = d.dot(turtle->left), du = d.dot(turtle->up);
      const double roll = std::atan2(du, dl) / kDegree;
      const double turn = std::atan2(std::hypot(dl, du), dh) / kDegree;
      if (turn != 0 && roll != 0) {
        *out_ += " " + Call("/", {roll});
        turtle->Roll(roll);
      }
      if (turn != 0) {
        *out_ += " " + Call("+", {turn});
        turtle->Turn(turn);
      }
    }
    *out_ += " " + Call("F", {length, node.radius});
    turtle->position += turtle->heading * length;
  }

  const SkeletonGraph& skeleton_;
  LpyForm form_;
  std::string* out_;
  std::vector<int>* order_;
  std::vector<BranchAxis> axes_;
  std::vector<std::vector<int>> laterals_;
};

const char kLpyTail[] =
    "\n"
    "derivation length: 0\n"
    "production:\n"
    "\n"
    "interpretation:\n"
    "\n"
    "endlsystem\n";

}  // namespace

std::string LpyText(const std::vector<SkeletonGraph>& parts, LpyForm form, const std::string& units,
                    std::vector<std::vector<int>>* node_order) {
  std::string out = "# A tree skeleton written by sylva as an L-Py axiom (";
  out += form == LpyForm::kAbsolute ? "absolute form: @M and LineTo(x,y,z,width)"
                                    : "turtle form: F(length,width), / roll, + turn";
  out += ").\n# Units: " + units + "; widths are branch radii (" +
         (parts.empty() ? std::string("none") : parts[0].radius_source) + ").\n";
  if (form == LpyForm::kTurtle) {
    out += "# PlantGL's initial frame: heading +Z, left -Y, up +X; angles in degrees.\n";
  }
  out += "Axiom: ";
  std::vector<std::vector<int>> orders(parts.size());
  for (size_t p = 0; p < parts.size(); ++p) {
    parts[p].Check();
    if (p > 0) out += " ";
    AxiomWriter(parts[p], form, &out, &orders[p]).Write();
  }
  out += "\n";
  out += kLpyTail;
  if (node_order != nullptr) *node_order = std::move(orders);
  return out;
}

void WriteLpy(const std::filesystem::path& path, const std::vector<SkeletonGraph>& parts,
              LpyForm form, const std::string& units) {
  AtomicWriteString(path, LpyText(parts, form, units));
}

// ---------------------------------------------------------------------------
// Interpreting

namespace {

// Reads the modules of one axiom line and draws them.
class AxiomInterpreter {
 public:
  AxiomInterpreter(const std::string& axiom, std::string where_prefix, size_t column_offset)
      : text_(axiom), where_prefix_(std::move(where_prefix)), column_offset_(column_offset) {}

  LpyTree Run() {
    while (SkipBlanks()) Module();
    SYLVA_CHECK_INPUT(stack_.empty(), Where(text_.size()))
        << stack_.size() << " '[' not closed by ']'";
    return std::move(tree_);
  }

 private:
  struct State {
    Turtle turtle;
    int part = -1;  // -1: the turtle stands on no node
    int node = -1;
  };

  std::string Where(size_t at) const {
    return where_prefix_ + ":" + std::to_string(at + column_offset_ + 1);
  }

  bool SkipBlanks() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return pos_ < text_.size();
  }

  // The module's name: `@` and letters, one of the symbols, or a bracket.
  std::string Name() {
    const size_t start = pos_;
    if (text_[pos_] == '@') ++pos_;
    while (pos_ < text_.size() && std::isalpha(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    if (pos_ == start) ++pos_;  // a one-character symbol
    return text_.substr(start, pos_ - start);
  }

  std::vector<double> Arguments() {
    std::vector<double> args;
    if (pos_ >= text_.size() || text_[pos_] != '(') return args;
    const size_t close = text_.find(')', pos_);
    SYLVA_CHECK_INPUT(close != std::string::npos, Where(pos_)) << "'(' not closed";
    std::istringstream in(text_.substr(pos_ + 1, close - pos_ - 1));
    std::string field;
    size_t at = pos_ + 1;
    while (std::getline(in, field, ',')) {
      const size_t begin = field.find_first_not_of(" \t");
      const size_t end = field.find_last_not_of(" \t");
      const std::string number =
          begin == std::string::npos ? "" : field.substr(begin, end - begin + 1);
      double value = 0.0;
      const auto [ptr, error] =
          std::from_chars(number.data(), number.data() + number.size(), value);
      SYLVA_CHECK_INPUT(!number.empty() && error == std::errc() &&
                            ptr == number.data() + number.size() && std::isfinite(value),
                        Where(at))
          << "'" << field << "' is not a number";
      args.push_back(value);
      at += field.size() + 1;
    }
    pos_ = close + 1;
    return args;
  }

  void Module() {
    const size_t at = pos_;
    const std::string name = Name();
    const std::vector<double> args = Arguments();
    ++tree_.modules;
    auto need = [&](size_t low, size_t high) {
      SYLVA_CHECK_INPUT(args.size() >= low && args.size() <= high, Where(at))
          << name << " takes " << low << (high > low ? "-" + std::to_string(high) : "")
          << " arguments, got " << args.size();
    };
    auto angle = [&]() {
      need(0, 1);
      return args.empty() ? kDefaultAngle : args[0];
    };
    Turtle& turtle = state_.turtle;
    const double width_before = turtle.width;
    if (name == "[") {
      need(0, 0);
      stack_.push_back(state_);
    } else if (name == "]") {
      need(0, 0);
      SYLVA_CHECK_INPUT(!stack_.empty(), Where(at)) << "']' without '['";
      state_ = stack_.back();
      stack_.pop_back();
    } else if (name == "@M" || name == "MoveTo") {
      need(3, 3);
      MoveTo({args[0], args[1], args[2]});
    } else if (name == "LineTo") {
      need(3, 4);
      if (args.size() == 4) turtle.width = args[3];
      Draw({args[0], args[1], args[2]}, width_before, at);
    } else if (name == "F") {
      need(0, 2);
      const double length = args.empty() ? kDefaultLength : args[0];
      if (args.size() == 2) turtle.width = args[1];
      Draw(turtle.position + length * turtle.heading, width_before, at);
    } else if (name == "_" || name == "!" || name == "SetWidth") {
      need(name == "SetWidth" ? 1 : 0, 1);
      const double step = name == "!" ? -kDefaultWidthIncrement : kDefaultWidthIncrement;
      turtle.width = args.empty() ? turtle.width + step : args[0];
    } else if (name == "+" || name == "-") {
      turtle.Turn(name == "+" ? angle() : -angle());
    } else if (name == "&" || name == "^") {
      turtle.Pitch(name == "&" ? angle() : -angle());
    } else if (name == "/" || name == "\\") {
      turtle.Roll(name == "/" ? angle() : -angle());
    } else {
      SYLVA_CHECK_INPUT(false, Where(at))
          << "module '" << name << "' is not in the subset sylva interprets "
          << "([ ] @M MoveTo LineTo F _ ! SetWidth + - & ^ / \\)";
    }
  }

  // Stays on the current node if the point is its position, else leaves the tree.
  void MoveTo(const Eigen::Vector3d& point) {
    state_.turtle.position = point;
    if (state_.part >= 0 && tree_.parts[state_.part].nodes[state_.node].position == point) return;
    state_.part = state_.node = -1;
  }

  // A segment to `point`: a new node. Off the tree, the segment starts at
  // the node drawn first at the turtle's position (branches written at a
  // root before its first segment), else at a new root of radius
  // `root_width` (the width the segment starts with).
  void Draw(const Eigen::Vector3d& point, double root_width, size_t at) {
    Turtle& turtle = state_.turtle;
    SYLVA_CHECK_INPUT(turtle.width >= 0, Where(at)) << "negative width " << turtle.width;
    const int order = std::max(static_cast<int>(stack_.size()) - 1, 0);
    if (state_.part < 0) {
      const auto found = node_at_.find(Key(turtle.position));
      if (found != node_at_.end()) {
        std::tie(state_.part, state_.node) = found->second;
      } else {
        state_.part = static_cast<int>(tree_.parts.size());
        tree_.parts.emplace_back();
        Add(turtle.position, root_width, -1, order);
      }
    }
    Add(point, turtle.width, state_.node, order);
    turtle.position = point;
  }

  void Add(const Eigen::Vector3d& position, double radius, int parent, int order) {
    state_.node = tree_.parts[state_.part].AddNode(position, radius, parent, order);
    node_at_.emplace(Key(position), std::make_pair(state_.part, state_.node));
  }

  static std::string Key(const Eigen::Vector3d& p) {
    return std::string(reinterpret_cast<const char*>(p.data()), 3 * sizeof(double));
  }

  const std::string& text_;
  std::string where_prefix_;
  size_t column_offset_;
  size_t pos_ = 0;
  State state_;
  std::vector<State> stack_;
  LpyTree tree_;
  std::map<std::string, std::pair<int, int>>
      node_at_;  // position -> (part, node) drawn first there
};

}  // namespace

LpyTree InterpretLpy(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.rfind("Axiom:", 0) != 0) continue;
    const std::string axiom = line.substr(6);
    SYLVA_CHECK_INPUT(axiom.find_first_not_of(" \t") != std::string::npos,
                      source + ":" + std::to_string(number))
        << "the axiom is empty (a procedural axiom on the next lines is not interpreted)";
    return AxiomInterpreter(axiom, source + ":" + std::to_string(number), 6).Run();
  }
  SYLVA_CHECK_INPUT(false, source) << "no 'Axiom:' line";
  return {};
}

LpyTree ReadLpy(const std::filesystem::path& path) {
  return InterpretLpy(ReadFileToString(path), path.string());
}

}  // namespace sylva
