// A parametric L-system (Prusinkiewicz and Lindenmayer 1990, ch. 1.10) with
// a small grammar format of sylva's own, the growth engine of the 3D
// gestures (Murakami et al., section 3: the "interactive L-system", whose
// productions apply only to modules inside a region of interest: the
// `rewritable` mask of Derive).
//
// Grammar files (.lsys), line by line:
//
//   # a comment, to the end of the line
//   #define NAME EXPR          a constant (EXPR may use earlier constants)
//   axiom: MODULES             the starting string (needed unless given in code)
//   PRED -> MODULES            a production
//   PRED : COND -> MODULES     applies only where COND is true (non-zero)
//   PRED ->(W) MODULES         a stochastic production of weight W > 0
//   PRED : COND ->(W) MODULES
//
// MODULES is a list of modules, each a name and an optional parameter list
// of expressions, `F(l, r)`; names are identifiers (letters, digits, `_`,
// starting with a letter) or one of the turtle characters + - & ^ / \ | ! [ ].
// Modules are separated by spaces or follow a closing parenthesis or a
// turtle character (`F(1)A(2)` is two modules, `FA` one named FA). PRED is
// one module whose parameters are names (its formal parameters, used in
// COND and in the successor's expressions). Expressions: numbers, constants,
// parameters, + - * / ^ (power), unary -, < <= > >= == !=, && || !,
// parentheses and the functions sin cos tan (degrees) sqrt abs exp log
// floor min max and uniform(a, b) (a pseudo-random number of the run's
// seed). Several productions for one module are tried in file order: the
// first deterministic one whose condition holds applies; otherwise, if
// stochastic ones hold, one is drawn by weight among them. A production
// matches modules with as many parameters as it has formal parameters.
//
// A module without a matching production is copied unchanged. Errors name
// the file, line and column.
#ifndef SYLVA_SKETCH_LSYSTEM_H_
#define SYLVA_SKETCH_LSYSTEM_H_

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace sylva {

class RandomEngine;

// One module of an L-string: its symbol (an index into the grammar's
// symbol table) and its parameters params[first, first + count) of the
// string's flat parameter array.
struct LsystemModule {
  int symbol = 0;
  int first = 0;
  int count = 0;
};

// An L-string with its parameters stored flat (no allocation per module).
struct LsystemString {
  std::vector<LsystemModule> modules;
  std::vector<double> params;

  int Size() const { return static_cast<int>(modules.size()); }
  double Param(int module, int k) const { return params[modules[module].first + k]; }
  void Add(int symbol, std::initializer_list<double> values);
  void Append(const LsystemString& other, int module);  // module `module` of `other`
};

// A compiled expression (postfix byte code); evaluated against a frame of
// formal parameter values.
struct LsystemExpression {
  struct Op {
    int code = 0;
    double value = 0.0;  // the number of a constant, the index of a parameter
  };
  std::vector<Op> ops;
  double Evaluate(const double* params, RandomEngine* random) const;
};

struct LsystemProduction {
  int symbol = 0;
  int num_params = 0;
  bool has_condition = false;
  LsystemExpression condition;
  double weight = 0.0;  // 0: deterministic
  struct Successor {
    int symbol = 0;
    std::vector<LsystemExpression> params;
  };
  std::vector<Successor> successor;
  int line = 0;  // in the grammar file
};

class LsystemGrammar {
 public:
  // Parses grammar text; `source` names it in errors ("FILE: line L,
  // column C: ..."). Throws InputError.
  // `overrides` (optional) replaces the values of #define constants by
  // name (the constants they are used in after it see the new value);
  // names not defined in the text are listed in unused_overrides().
  static LsystemGrammar Parse(const std::string& text, const std::string& source,
                              const std::map<std::string, double>* overrides = nullptr);
  static LsystemGrammar Read(const std::filesystem::path& path,
                             const std::map<std::string, double>* overrides = nullptr);
  const std::vector<std::string>& unused_overrides() const { return unused_overrides_; }

  // The symbol's index (added if new).
  int Symbol(const std::string& name);
  int FindSymbol(const std::string& name) const;  // -1 if absent
  const std::string& SymbolName(int symbol) const { return names_[symbol]; }
  int NumSymbols() const { return static_cast<int>(names_.size()); }
  // A constant's value (from #define), or `fallback`.
  double Constant(const std::string& name, double fallback) const;

  const LsystemString& axiom() const { return axiom_; }
  bool has_axiom() const { return has_axiom_; }
  const std::vector<LsystemProduction>& productions() const { return productions_; }
  const std::string& source() const { return source_; }

  // Productions of each symbol, in file order.
  const std::vector<int>& ProductionsOf(int symbol) const;

  // The string as text, parameters with %g ("F(1.5)A(2)" without spaces
  // after turtle characters), for messages, tests and the naive reference.
  std::string ToText(const LsystemString& string) const;

 private:
  friend class LsystemParser;
  std::string source_;
  std::vector<std::string> names_;
  std::map<std::string, int> index_;
  std::map<std::string, double> constants_;
  const std::map<std::string, double>* overrides_ = nullptr;
  std::vector<std::string> unused_overrides_;
  LsystemString axiom_;
  bool has_axiom_ = false;
  std::vector<LsystemProduction> productions_;
  std::vector<std::vector<int>> by_symbol_;
};

struct LsystemDeriveSummary {
  int rewritten = 0;  // modules a production applied to
  int modules = 0;    // modules of the result
};

// One derivation step: every module with rewritable[i] != 0 (all when
// `rewritable` is null) and a matching production is replaced by its
// successor; others are copied. `random` draws the stochastic productions
// and uniform(); modules are visited left to right, so a seed gives one
// result. `fresh` (optional) receives, per module of the result, 1 if it
// comes from a successor, 0 if copied.
LsystemString DeriveStep(const LsystemGrammar& grammar, const LsystemString& string,
                         const std::vector<char>* rewritable, RandomEngine* random,
                         LsystemDeriveSummary* summary = nullptr,
                         std::vector<char>* fresh = nullptr);

}  // namespace sylva

#endif  // SYLVA_SKETCH_LSYSTEM_H_
