// Benchmark of the L-system behind `sylva gesture` (sketch/lsystem.h,
// issue 17): derivation speed in modules per second of sylva's compiled
// parametric L-system beside a naive string-rewriting reference in the
// same process (the L-string kept as text, every module and every
// expression re-parsed from text at every step, results printed back to
// text), on the same grammar; the two final strings must agree (module
// count, every parameter within 1e-9 relative). Also the whole gesture
// growth (interpretation, region and collision avoidance) on a trunk
// gesture made in code, for scale.
//
// usage: sylva_gesture_benchmark [--quick]   (--quick: fewer steps)
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "core/util/random.h"
#include "sketch/gesture_tree.h"
#include "sketch/lsystem.h"
#include "tests/bench/agreement.h"

namespace sylva {
namespace {

// Deterministic (no uniform(): the reference has no random numbers).
constexpr char kGrammar[] = R"(#define LR 0.9
axiom: A(1, 0.1)
A(l, r) : l > 0.01 -> F(l, r) [ +(30) A(l * LR, r * 0.7) ] [ -(30) /(137.5) A(l * LR, r * 0.7) ] A(l * 0.95, r * 0.9)
F(l, r) -> F(l * 1.02, r * 1.05)
)";

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// --- the naive reference ----------------------------------------------------

struct NaiveProduction {
  std::string name;
  std::vector<std::string> formals;
  std::string condition;  // "" = none
  std::string successor;  // text, re-parsed at every application
};

const std::vector<NaiveProduction> kNaiveProductions = {
    {"A",
     {"l", "r"},
     "l > 0.01",
     "F(l, r)[+(30)A(l * 0.9, r * 0.7)][-(30)/(137.5)A(l * 0.9, r * 0.7)]A(l * 0.95, r * 0.9)"},
    {"F", {"l", "r"}, "", "F(l * 1.02, r * 1.05)"}};

// A recursive-descent evaluator over expression text with a map of names.
class NaiveExpression {
 public:
  NaiveExpression(const std::string& text, const std::map<std::string, double>& vars)
      : text_(text), vars_(vars) {}
  double Evaluate() { return Comparison(); }

 private:
  void Skip() {
    while (pos_ < text_.size() && text_[pos_] == ' ') ++pos_;
  }
  double Comparison() {
    const double a = Sum();
    Skip();
    if (pos_ < text_.size() && text_[pos_] == '>') return ++pos_, a > Sum();
    if (pos_ < text_.size() && text_[pos_] == '<') return ++pos_, a < Sum();
    return a;
  }
  double Sum() {
    double a = Product();
    for (Skip(); pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-'); Skip()) {
      const char op = text_[pos_++];
      const double b = Product();
      a = op == '+' ? a + b : a - b;
    }
    return a;
  }
  double Product() {
    double a = Primary();
    for (Skip(); pos_ < text_.size() && (text_[pos_] == '*' || text_[pos_] == '/'); Skip()) {
      const char op = text_[pos_++];
      const double b = Primary();
      a = op == '*' ? a * b : a / b;
    }
    return a;
  }
  double Primary() {
    Skip();
    if (text_[pos_] == '(') {
      ++pos_;
      const double a = Comparison();
      Skip();
      ++pos_;
      return a;
    }
    if (std::isdigit(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '.') {
      char* end = nullptr;
      const double a = std::strtod(text_.c_str() + pos_, &end);
      pos_ = end - text_.c_str();
      return a;
    }
    const size_t start = pos_;
    while (pos_ < text_.size() && std::isalnum(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return vars_.at(text_.substr(start, pos_ - start));
  }

  const std::string& text_;
  const std::map<std::string, double>& vars_;
  size_t pos_ = 0;
};

// Splits "F(1,2)" modules of `text` starting at `pos`: name and parameter texts.
bool NextModule(const std::string& text, size_t* pos, std::string* name,
                std::vector<std::string>* params) {
  while (*pos < text.size() && text[*pos] == ' ') ++*pos;
  if (*pos >= text.size()) return false;
  name->assign(1, text[(*pos)++]);
  params->clear();
  if (*pos < text.size() && text[*pos] == '(') {
    int depth = 0;
    std::string current;
    for (++*pos; *pos < text.size(); ++*pos) {
      const char c = text[*pos];
      if (c == '(') ++depth;
      if ((c == ',' || c == ')') && depth == 0) {
        params->push_back(current);
        current.clear();
        if (c == ')') break;
        continue;
      }
      if (c == ')') --depth;
      current += c;
    }
    ++*pos;
  }
  return true;
}

void AppendModule(const std::string& name, const std::vector<double>& values, std::string* out) {
  *out += name;
  char number[32];
  for (size_t k = 0; k < values.size(); ++k) {
    std::snprintf(number, sizeof(number), "%.17g", values[k]);
    *out += (k == 0 ? "(" : ",");
    *out += number;
  }
  if (!values.empty()) *out += ')';
}

std::string NaiveStep(const std::string& string, int* modules) {
  std::string out;
  size_t pos = 0;
  std::string name, succ_name;
  std::vector<std::string> params, succ_params;
  while (NextModule(string, &pos, &name, &params)) {
    std::map<std::string, double> vars;
    const NaiveProduction* applied = nullptr;
    for (const NaiveProduction& p : kNaiveProductions) {
      if (p.name != name || p.formals.size() != params.size()) continue;
      vars.clear();
      for (size_t k = 0; k < params.size(); ++k)
        vars[p.formals[k]] = std::strtod(params[k].c_str(), nullptr);
      if (p.condition.empty() || NaiveExpression(p.condition, vars).Evaluate() != 0) {
        applied = &p;
        break;
      }
    }
    if (applied == nullptr) {
      std::vector<double> values;
      for (const std::string& p : params) values.push_back(std::strtod(p.c_str(), nullptr));
      AppendModule(name, values, &out);
      ++*modules;
      continue;
    }
    size_t succ_pos = 0;
    while (NextModule(applied->successor, &succ_pos, &succ_name, &succ_params)) {
      std::vector<double> values;
      for (const std::string& e : succ_params)
        values.push_back(NaiveExpression(e, vars).Evaluate());
      AppendModule(succ_name, values, &out);
      ++*modules;
    }
  }
  return out;
}

// --- comparison -----------------------------------------------------------------

// The largest relative parameter difference of two texts with the same
// modules, or infinity if the modules differ.
double TextDifference(const std::string& a, const std::string& b) {
  size_t pa = 0, pb = 0;
  std::string na, nb;
  std::vector<std::string> va, vb;
  double worst = 0;
  for (;;) {
    const bool more_a = NextModule(a, &pa, &na, &va), more_b = NextModule(b, &pb, &nb, &vb);
    if (more_a != more_b || (more_a && (na != nb || va.size() != vb.size()))) return INFINITY;
    if (!more_a) return worst;
    for (size_t k = 0; k < va.size(); ++k) {
      const double x = std::strtod(va[k].c_str(), nullptr), y = std::strtod(vb[k].c_str(), nullptr);
      worst = std::max(worst, std::abs(x - y) / std::max(std::abs(x), 1e-300));
    }
  }
}

int Main(bool quick) {
  const int steps = quick ? 7 : 10;
  const LsystemGrammar grammar = LsystemGrammar::Parse(kGrammar, "benchmark grammar");
  RandomEngine random(1);
  auto start = std::chrono::steady_clock::now();
  LsystemString fast = grammar.axiom();
  long fast_modules = 0;
  for (int k = 0; k < steps; ++k) {
    fast = DeriveStep(grammar, fast, nullptr, &random);
    fast_modules += fast.Size();
  }
  const double fast_seconds = Seconds(start);
  start = std::chrono::steady_clock::now();
  std::string naive = "A(1,0.10000000000000001)";
  int naive_modules = 0;
  for (int k = 0; k < steps; ++k) naive = NaiveStep(naive, &naive_modules);
  const double naive_seconds = Seconds(start);
  std::printf("L-system derivation, %d steps -> %d modules (%ld produced in all)\n", steps,
              fast.Size(), fast_modules);
  std::printf("  sylva (compiled productions, flat parameters): %.4f s, %.3g modules/s\n",
              fast_seconds, fast_modules / fast_seconds);
  std::printf("  naive string rewriting (text re-parsed):        %.4f s, %.3g modules/s\n",
              naive_seconds, naive_modules / naive_seconds);
  std::printf("  speed-up %.1fx\n", naive_seconds / fast_seconds);
  Agreement agreement("the naive string rewriting");
  agreement.AtMost("module count difference", std::abs(naive_modules - fast_modules), 0);
  agreement.AtMost("largest relative parameter difference",
                   TextDifference(grammar.ToText(fast), naive), 1e-9);
  // The whole growth, for scale: a 6 m trunk drawn straight up.
  GestureSet gestures;
  gestures.source = "benchmark gesture";
  GestureStroke trunk;
  for (int k = 0; k <= 20; ++k) trunk.samples.push_back({0.1 * k, {0.0, 0.0, 0.3 * k}, 1.0});
  gestures.strokes = {trunk};
  gestures.timed = true;
  GestureTreeOptions options;
  options.iterations = quick ? 5 : 7;
  start = std::chrono::steady_clock::now();
  const GestureTree tree = GrowGestureTree(gestures, LoadGestureGrammar(options), options);
  const double grow_seconds = Seconds(start);
  std::printf(
      "gesture growth (%d steps, region and collision avoidance): %d modules, %d nodes in "
      "%.3f s, %.3g modules/s; smallest capsule gap %.3g m\n",
      options.iterations, tree.modules, tree.skeleton.NumNodes(), grow_seconds,
      tree.modules / grow_seconds, tree.min_capsule_distance);
  agreement.AtLeast("smallest capsule gap (m)", tree.min_capsule_distance, 0.0);
  return agreement.ExitCode();
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  return sylva::Main(quick);
}
