#include "sketch/lsystem.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/random.h"

namespace sylva {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;
// The deepest evaluation stack an expression may need.
constexpr int kMaxStack = 64;
// The deepest nesting of parentheses and unary operators parsed.
constexpr int kMaxNesting = 200;
constexpr char kTurtleCharacters[] = "+-&^/\\|![]";

enum Code {
  kNumber,
  kParam,
  kAdd,
  kSub,
  kMul,
  kDiv,
  kPow,
  kNeg,
  kNot,
  kLt,
  kLe,
  kGt,
  kGe,
  kEq,
  kNe,
  kAnd,
  kOr,
  kSin,
  kCos,
  kTan,
  kSqrt,
  kAbs,
  kExp,
  kLog,
  kFloor,
  kMin,
  kMax,
  kUniform,
};

struct Function {
  const char* name;
  Code code;
  int arity;
};
constexpr Function kFunctions[] = {
    {"sin", kSin, 1}, {"cos", kCos, 1}, {"tan", kTan, 1},         {"sqrt", kSqrt, 1},
    {"abs", kAbs, 1}, {"exp", kExp, 1}, {"log", kLog, 1},         {"floor", kFloor, 1},
    {"min", kMin, 2}, {"max", kMax, 2}, {"uniform", kUniform, 2},
};

double Binary(int code, double a, double b) {
  switch (code) {
    case kAdd:
      return a + b;
    case kSub:
      return a - b;
    case kMul:
      return a * b;
    case kDiv:
      return a / b;
    case kPow:
      return std::pow(a, b);
    case kLt:
      return a < b;
    case kLe:
      return a <= b;
    case kGt:
      return a > b;
    case kGe:
      return a >= b;
    case kEq:
      return a == b;
    case kNe:
      return a != b;
    case kAnd:
      return a != 0 && b != 0;
    case kOr:
      return a != 0 || b != 0;
    case kMin:
      return std::min(a, b);
    default:
      return std::max(a, b);
  }
}

double Unary(int code, double a) {
  switch (code) {
    case kNeg:
      return -a;
    case kNot:
      return a == 0;
    case kSin:
      return std::sin(a * kDegree);
    case kCos:
      return std::cos(a * kDegree);
    case kTan:
      return std::tan(a * kDegree);
    case kSqrt:
      return std::sqrt(a);
    case kAbs:
      return std::abs(a);
    case kExp:
      return std::exp(a);
    case kLog:
      return std::log(a);
    default:
      return std::floor(a);
  }
}

bool IsUnaryCode(int code) {
  return code == kNeg || code == kNot || (code >= kSin && code <= kFloor);
}

}  // namespace

double LsystemExpression::Evaluate(const double* params, RandomEngine* random) const {
  double stack[kMaxStack];
  int top = 0;
  for (const Op& op : ops) {
    if (op.code == kNumber) {
      stack[top++] = op.value;
    } else if (op.code == kParam) {
      stack[top++] = params[static_cast<int>(op.value)];
    } else if (IsUnaryCode(op.code)) {
      stack[top - 1] = Unary(op.code, stack[top - 1]);
    } else if (op.code == kUniform) {
      --top;
      stack[top - 1] = random->Uniform(stack[top - 1], stack[top]);
    } else {
      --top;
      stack[top - 1] = Binary(op.code, stack[top - 1], stack[top]);
    }
  }
  return top > 0 ? stack[top - 1] : 0.0;
}

void LsystemString::Add(int symbol, std::initializer_list<double> values) {
  modules.push_back({symbol, static_cast<int>(params.size()), static_cast<int>(values.size())});
  params.insert(params.end(), values.begin(), values.end());
}

void LsystemString::Append(const LsystemString& other, int module) {
  const LsystemModule& m = other.modules[module];
  modules.push_back({m.symbol, static_cast<int>(params.size()), m.count});
  params.insert(params.end(), other.params.begin() + m.first,
                other.params.begin() + m.first + m.count);
}

// Parses one line at a time with a cursor; errors carry line and column.
class LsystemParser {
 public:
  LsystemParser(LsystemGrammar* grammar, std::string line, int line_number)
      : grammar_(grammar), text_(std::move(line)), line_(line_number) {}

  void ParseLine() {
    SkipSpace();
    if (AtEnd()) return;
    if (Consume("#define")) return ParseDefine();
    if (Consume("axiom")) {
      SkipSpace();
      Expect(":");
      grammar_->axiom_ = ParseModules(nullptr);
      grammar_->has_axiom_ = true;
      return;
    }
    ParseProduction();
  }

 private:
  [[noreturn]] void Fail(const std::string& message) const {
    std::ostringstream where;
    where << "line " << line_ << ", column " << pos_ + 1 << ": " << message;
    throw InputError(grammar_->source_, where.str());
  }
  bool AtEnd() const { return pos_ >= text_.size(); }
  char Peek(size_t ahead = 0) const {
    return pos_ + ahead < text_.size() ? text_[pos_ + ahead] : '\0';
  }
  void SkipSpace() {
    while (!AtEnd() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool Consume(const std::string& token) {
    if (text_.compare(pos_, token.size(), token) != 0) return false;
    pos_ += token.size();
    return true;
  }
  void Expect(const std::string& token) {
    if (!Consume(token)) Fail("expected '" + token + "'");
  }
  bool AtArrow() const { return Peek() == '-' && Peek(1) == '>'; }

  // Constants, #defines and the arithmetic of them only.
  void RequireConstant(const LsystemExpression& expression, const std::string& what) {
    for (const LsystemExpression::Op& op : expression.ops) {
      if (op.code == kUniform || op.code == kParam) {
        Fail(what + " must be fixed: no parameters, no uniform()");
      }
    }
  }

  // Guards the recursion of nested parentheses and unary operators.
  void Enter() {
    if (++nesting_ > kMaxNesting) Fail("expression nested too deeply");
  }

  std::string Identifier() {
    const size_t start = pos_;
    if (!std::isalpha(static_cast<unsigned char>(Peek()))) return "";
    while (std::isalnum(static_cast<unsigned char>(Peek())) || Peek() == '_') ++pos_;
    return text_.substr(start, pos_ - start);
  }

  void ParseDefine() {
    SkipSpace();
    const std::string name = Identifier();
    if (name.empty()) Fail("expected a constant's name after #define");
    LsystemExpression expression = ParseExpressionAt();
    RequireConstant(expression, "a #define");
    SkipSpace();
    if (!AtEnd()) Fail("unexpected text after the constant's value");
    const auto* overrides = grammar_->overrides_;
    const bool overridden = overrides != nullptr && overrides->count(name) != 0;
    grammar_->constants_[name] =
        overridden ? overrides->at(name) : expression.Evaluate(nullptr, nullptr);
  }

  void ParseProduction() {
    LsystemProduction production;
    production.line = line_;
    const std::string name = ModuleName();
    if (name.empty()) Fail("expected 'axiom:', '#define' or a production 'A(x) -> ...'");
    production.symbol = grammar_->Symbol(name);
    formals_.clear();
    if (Consume("(")) ParseFormals();
    production.num_params = static_cast<int>(formals_.size());
    SkipSpace();
    if (Consume(":")) {
      production.has_condition = true;
      production.condition = ParseExpressionAt();
      SkipSpace();
    }
    if (!Consume("->")) Fail("expected '->' after the predecessor");
    if (Consume("(")) {
      LsystemExpression weight = ParseExpressionAt();
      RequireConstant(weight, "a production's weight");
      SkipSpace();
      Expect(")");
      production.weight = weight.Evaluate(nullptr, nullptr);
      if (!(production.weight > 0)) Fail("a production's weight must be > 0");
    }
    for (Successor& s : ParseSuccessors()) production.successor.push_back(std::move(s));
    grammar_->productions_.push_back(std::move(production));
  }

  void ParseFormals() {
    for (;;) {
      SkipSpace();
      const std::string formal = Identifier();
      if (formal.empty()) Fail("expected a parameter name");
      if (std::find(formals_.begin(), formals_.end(), formal) != formals_.end())
        Fail("parameter '" + formal + "' named twice");
      formals_.push_back(formal);
      SkipSpace();
      if (Consume(")")) return;
      Expect(",");
    }
  }

  std::string ModuleName() {
    SkipSpace();
    if (Peek() != '\0' && std::string(kTurtleCharacters).find(Peek()) != std::string::npos) {
      return std::string(1, text_[pos_++]);
    }
    return Identifier();
  }

  using Successor = LsystemProduction::Successor;

  std::vector<Successor> ParseSuccessors() {
    std::vector<Successor> successors;
    for (;;) {
      SkipSpace();
      if (AtEnd()) return successors;
      const std::string name = ModuleName();
      if (name.empty()) Fail(std::string("expected a module, got '") + Peek() + "'");
      Successor s;
      s.symbol = grammar_->Symbol(name);
      if (Consume("(")) {
        for (;;) {
          s.params.push_back(ParseExpressionAt());
          SkipSpace();
          if (Consume(")")) break;
          Expect(",");
        }
      }
      successors.push_back(std::move(s));
    }
  }

  // A successor list evaluated now (the axiom: constants only).
  LsystemString ParseModules(RandomEngine* random) {
    formals_.clear();
    LsystemString string;
    for (const Successor& s : ParseSuccessors()) {
      string.modules.push_back(
          {s.symbol, static_cast<int>(string.params.size()), static_cast<int>(s.params.size())});
      for (const LsystemExpression& e : s.params) {
        RequireConstant(e, "the axiom");
        string.params.push_back(e.Evaluate(nullptr, random));
      }
    }
    return string;
  }

  // --- expressions (precedence climbing into postfix) ---

  LsystemExpression ParseExpressionAt() {
    LsystemExpression expression;
    ops_ = &expression.ops;
    depth_ = max_depth_ = 0;
    ParseOr();
    if (max_depth_ > kMaxStack) Fail("expression too deep");
    return expression;
  }
  void Emit(int code, double value = 0.0) {
    ops_->push_back({code, value});
    if (code == kNumber || code == kParam) {
      max_depth_ = std::max(max_depth_, ++depth_);
    } else if (!IsUnaryCode(code)) {
      --depth_;
    }
  }
  void ParseOr() {
    ParseAnd();
    while (SkipSpace(), Consume("||")) ParseAnd(), Emit(kOr);
  }
  void ParseAnd() {
    ParseComparison();
    while (SkipSpace(), Consume("&&")) ParseComparison(), Emit(kAnd);
  }
  void ParseComparison() {
    ParseSum();
    SkipSpace();
    static const std::pair<const char*, Code> kComparisons[] = {
        {"<=", kLe}, {">=", kGe}, {"==", kEq}, {"!=", kNe}, {"<", kLt}, {">", kGt}};
    for (const auto& [token, code] : kComparisons) {
      if (Consume(token)) {
        ParseSum();
        Emit(code);
        return;
      }
    }
  }
  void ParseSum() {
    ParseProduct();
    for (;;) {
      SkipSpace();
      if (AtArrow()) return;
      if (Consume("+")) {
        ParseProduct(), Emit(kAdd);
      } else if (Consume("-")) {
        ParseProduct(), Emit(kSub);
      } else {
        return;
      }
    }
  }
  void ParseProduct() {
    ParseUnary();
    for (;;) {
      SkipSpace();
      if (Consume("*")) {
        ParseUnary(), Emit(kMul);
      } else if (Consume("/")) {
        ParseUnary(), Emit(kDiv);
      } else {
        return;
      }
    }
  }
  void ParseUnary() {
    Enter();
    SkipSpace();
    if (!AtArrow() && Consume("-")) {
      ParseUnary(), Emit(kNeg);
    } else if (Peek() == '!' && Peek(1) != '=' && Consume("!")) {
      ParseUnary(), Emit(kNot);
    } else {
      ParsePrimary();
      SkipSpace();
      if (Consume("^")) ParseUnary(), Emit(kPow);
    }
    --nesting_;
  }
  void ParsePrimary() {
    SkipSpace();
    if (Consume("(")) {
      ParseOr();
      SkipSpace();
      Expect(")");
      return;
    }
    if (std::isdigit(static_cast<unsigned char>(Peek())) || Peek() == '.') {
      const char* begin = text_.c_str() + pos_;
      char* end = nullptr;
      const double value = std::strtod(begin, &end);
      if (end == begin) Fail("expected a number");
      pos_ += end - begin;
      return Emit(kNumber, value);
    }
    const size_t start = pos_;
    const std::string name = Identifier();
    if (name.empty())
      Fail(AtEnd() ? "expected a value at the end of the line"
                   : std::string("expected a value, got '") + Peek() + "'");
    SkipSpace();
    if (Peek() == '(') return ParseCall(name, start);
    const auto formal = std::find(formals_.begin(), formals_.end(), name);
    if (formal != formals_.end())
      return Emit(kParam, static_cast<double>(formal - formals_.begin()));
    const auto constant = grammar_->constants_.find(name);
    if (constant == grammar_->constants_.end()) {
      pos_ = start;
      Fail("unknown name '" + name + "' (not a parameter of the predecessor nor a #define)");
    }
    Emit(kNumber, constant->second);
  }
  void ParseCall(const std::string& name, size_t start) {
    const Function* function = nullptr;
    for (const Function& f : kFunctions) function = name == f.name ? &f : function;
    if (function == nullptr) {
      pos_ = start;
      Fail("unknown function '" + name + "'");
    }
    Expect("(");
    for (int k = 0; k < function->arity; ++k) {
      if (k > 0) SkipSpace(), Expect(",");
      ParseOr();
    }
    SkipSpace();
    Expect(")");
    Emit(function->code);
  }

  LsystemGrammar* grammar_;
  std::string text_;
  int line_;
  size_t pos_ = 0;
  std::vector<std::string> formals_;
  std::vector<LsystemExpression::Op>* ops_ = nullptr;
  int depth_ = 0, max_depth_ = 0;
  int nesting_ = 0;
};

LsystemGrammar LsystemGrammar::Parse(const std::string& text, const std::string& source,
                                     const std::map<std::string, double>* overrides) {
  LsystemGrammar grammar;
  grammar.source_ = source;
  grammar.overrides_ = overrides;
  for (const char* c = kTurtleCharacters; *c != '\0'; ++c) grammar.Symbol(std::string(1, *c));
  std::istringstream lines(text);
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    // A comment runs from a '#' that does not start "#define".
    for (size_t hash = line.find('#'); hash != std::string::npos; hash = line.find('#', hash + 1)) {
      if (line.compare(hash, 7, "#define") != 0) {
        line.resize(hash);
        break;
      }
    }
    LsystemParser(&grammar, line, number).ParseLine();
  }
  grammar.overrides_ = nullptr;
  if (overrides != nullptr) {
    for (const auto& [name, value] : *overrides) {
      if (grammar.constants_.count(name) == 0) grammar.unused_overrides_.push_back(name);
    }
  }
  grammar.by_symbol_.assign(grammar.names_.size(), {});
  for (size_t p = 0; p < grammar.productions_.size(); ++p) {
    grammar.by_symbol_[grammar.productions_[p].symbol].push_back(static_cast<int>(p));
  }
  return grammar;
}

LsystemGrammar LsystemGrammar::Read(const std::filesystem::path& path,
                                    const std::map<std::string, double>* overrides) {
  std::error_code ec;
  SYLVA_CHECK_INPUT(std::filesystem::is_regular_file(path, ec), path.string())
      << "no such grammar file";
  return Parse(ReadFileToString(path), path.string(), overrides);
}

int LsystemGrammar::Symbol(const std::string& name) {
  const auto it = index_.find(name);
  if (it != index_.end()) return it->second;
  names_.push_back(name);
  by_symbol_.emplace_back();
  return index_[name] = static_cast<int>(names_.size()) - 1;
}

int LsystemGrammar::FindSymbol(const std::string& name) const {
  const auto it = index_.find(name);
  return it == index_.end() ? -1 : it->second;
}

double LsystemGrammar::Constant(const std::string& name, double fallback) const {
  const auto it = constants_.find(name);
  return it == constants_.end() ? fallback : it->second;
}

const std::vector<int>& LsystemGrammar::ProductionsOf(int symbol) const {
  static const std::vector<int> kNone;
  return symbol < static_cast<int>(by_symbol_.size()) ? by_symbol_[symbol] : kNone;
}

std::string LsystemGrammar::ToText(const LsystemString& string) const {
  std::string text;
  char number[32];
  for (const LsystemModule& m : string.modules) {
    const std::string& name = names_[m.symbol];
    if (!text.empty() && std::isalnum(static_cast<unsigned char>(name[0])) &&
        std::isalnum(static_cast<unsigned char>(text.back())))
      text += ' ';
    text += name;
    if (m.count == 0) continue;
    for (int k = 0; k < m.count; ++k) {
      std::snprintf(number, sizeof(number), "%.17g", string.params[m.first + k]);
      text += (k == 0 ? "(" : ",");
      text += number;
    }
    text += ')';
  }
  return text;
}

namespace {

// The production applying to module `m` (-1: none).
int ChooseProduction(const LsystemGrammar& grammar, const double* frame, const LsystemModule& m,
                     RandomEngine* random) {
  double total = 0.0;
  int stochastic[16];
  int num_stochastic = 0;
  for (int p : grammar.ProductionsOf(m.symbol)) {
    const LsystemProduction& production = grammar.productions()[p];
    if (production.num_params != m.count) continue;
    if (production.has_condition && production.condition.Evaluate(frame, random) == 0) continue;
    if (production.weight == 0) return p;
    if (num_stochastic < 16) stochastic[num_stochastic++] = p, total += production.weight;
  }
  if (num_stochastic == 0) return -1;
  if (num_stochastic == 1) return stochastic[0];
  double pick = random->Uniform() * total;
  for (int k = 0; k < num_stochastic; ++k) {
    pick -= grammar.productions()[stochastic[k]].weight;
    if (pick < 0) return stochastic[k];
  }
  return stochastic[num_stochastic - 1];
}

}  // namespace

LsystemString DeriveStep(const LsystemGrammar& grammar, const LsystemString& string,
                         const std::vector<char>* rewritable, RandomEngine* random,
                         LsystemDeriveSummary* summary, std::vector<char>* fresh) {
  LsystemString result;
  if (fresh != nullptr) fresh->clear();
  result.modules.reserve(string.modules.size() * 2);
  result.params.reserve(string.params.size() * 2);
  int rewritten = 0;
  for (int i = 0; i < string.Size(); ++i) {
    const LsystemModule& m = string.modules[i];
    const double* frame = string.params.data() + m.first;
    const int p = (rewritable != nullptr && !(*rewritable)[i])
                      ? -1
                      : ChooseProduction(grammar, frame, m, random);
    if (p < 0) {
      result.Append(string, i);
      if (fresh != nullptr) fresh->push_back(0);
      continue;
    }
    ++rewritten;
    for (const LsystemProduction::Successor& s : grammar.productions()[p].successor) {
      result.modules.push_back(
          {s.symbol, static_cast<int>(result.params.size()), static_cast<int>(s.params.size())});
      for (const LsystemExpression& e : s.params)
        result.params.push_back(e.Evaluate(frame, random));
      if (fresh != nullptr) fresh->push_back(1);
    }
  }
  if (summary != nullptr) {
    summary->rewritten = rewritten;
    summary->modules = result.Size();
  }
  return result;
}

}  // namespace sylva
