#include "core/io/mtg_io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <set>
#include <sstream>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

// ---------------------------------------------------------------------------
// Text helpers

std::string Trim(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  const size_t end = text.find_last_not_of(" \t\r");
  return text.substr(begin, end - begin + 1);
}

std::vector<std::string> SplitWhitespace(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  std::string word;
  while (in >> word) words.push_back(word);
  return words;
}

std::vector<std::string> SplitTabs(const std::string& text) {
  std::vector<std::string> cells(1);
  for (char ch : text) {
    if (ch == '\t') {
      cells.emplace_back();
    } else {
      cells.back() += ch;
    }
  }
  return cells;
}

bool StartsWith(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

// Shortest text that reads back as the same double.
std::string DoubleText(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

// A line of the file that is neither blank nor a comment, with its number.
struct SourceLine {
  int number = 0;
  std::string text;  // without the line end
};

std::vector<SourceLine> SignificantLines(const std::string& text) {
  std::vector<SourceLine> lines;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number == 1 && StartsWith(line, "\xEF\xBB\xBF")) line.erase(0, 3);
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    lines.push_back({number, line});
  }
  return lines;
}

// ---------------------------------------------------------------------------
// Header

// Walks the significant lines of one file, naming the current one in errors.
class MtgLines {
 public:
  MtgLines(std::vector<SourceLine> lines, std::string source)
      : lines_(std::move(lines)), source_(std::move(source)) {}

  bool AtEnd() const { return next_ >= lines_.size(); }
  // The next line; an InputError at the end of the file (`expected` says what was due).
  const SourceLine& Take(const std::string& expected) {
    SYLVA_CHECK_INPUT(!AtEnd(), source_) << "the file ends before " << expected;
    current_ = next_++;
    return lines_[current_];
  }
  // The next line's trimmed text starts with `word` (not consumed).
  bool NextStartsWith(const std::string& word) const {
    return !AtEnd() && StartsWith(Trim(lines_[next_].text), word);
  }
  std::string Where() const { return source_ + ":" + std::to_string(lines_[current_].number); }
  const std::string& source() const { return source_; }

 private:
  std::vector<SourceLine> lines_;
  std::string source_;
  size_t next_ = 0;
  size_t current_ = 0;
};

// The words of a section's column header must be `expected`.
void TakeColumnHeader(MtgLines* lines, const std::vector<std::string>& expected,
                      const std::string& section) {
  const std::vector<std::string> words =
      SplitWhitespace(lines->Take("the " + section + " column header").text);
  std::string want;
  for (const std::string& word : expected) want += (want.empty() ? "" : " ") + word;
  SYLVA_CHECK_INPUT(words == expected, lines->Where())
      << "expected the " << section << " column header '" << want << "'";
}

void TakeSection(MtgLines* lines, const std::string& name) {
  const SourceLine& line = lines->Take("the " + name + " section");
  SYLVA_CHECK_INPUT(StartsWith(Trim(line.text), name), lines->Where())
      << "expected the section '" << name << ":'";
}

void ParseCode(MtgLines* lines) {
  const SourceLine& line = lines->Take("'CODE: FORM-A'");
  const std::string text = Trim(line.text);
  const size_t colon = text.find(':');
  SYLVA_CHECK_INPUT(StartsWith(text, "CODE") && colon != std::string::npos, lines->Where())
      << "an MTG file starts with 'CODE: FORM-A'";
  const std::string form = Trim(text.substr(colon + 1));
  SYLVA_CHECK_INPUT(form != "FORM-B", lines->Where())
      << "FORM-B coding is not supported (only FORM-A)";
  SYLVA_CHECK_INPUT(form == "FORM-A", lines->Where()) << "unknown code form '" << form << "'";
}

void ParseClasses(MtgLines* lines, Mtg* mtg) {
  static const std::set<std::string> kDecompositions = {
      "NONE", "FREE", "CONNECTED", "NOTCONNECTED", "LINEAR", "PURELINEAR", "<-LINEAR", "+-LINEAR"};
  TakeSection(lines, "CLASSES");
  TakeColumnHeader(lines, {"SYMBOL", "SCALE", "DECOMPOSITION", "INDEXATION", "DEFINITION"},
                   "CLASSES");
  while (!lines->NextStartsWith("DESCRIPTION")) {
    const std::vector<std::string> fields =
        SplitWhitespace(lines->Take("the DESCRIPTION section").text);
    SYLVA_CHECK_INPUT(fields.size() == 5, lines->Where())
        << "a class line has 5 columns (SYMBOL SCALE DECOMPOSITION INDEXATION DEFINITION), this "
           "one "
        << fields.size();
    const std::string& symbol = fields[0];
    SYLVA_CHECK_INPUT(symbol == "$" || std::all_of(symbol.begin(), symbol.end(),
                                                   [](char c) { return std::isalpha(c); }),
                      lines->Where())
        << "bad class symbol '" << symbol << "' (letters, or $)";
    int scale = -1;
    const auto [end, error] =
        std::from_chars(fields[1].data(), fields[1].data() + fields[1].size(), scale);
    SYLVA_CHECK_INPUT(
        error == std::errc() && end == fields[1].data() + fields[1].size() && scale >= 0,
        lines->Where())
        << "bad scale '" << fields[1] << "' of class " << symbol;
    SYLVA_CHECK_INPUT(kDecompositions.count(fields[2]) > 0, lines->Where())
        << "bad decomposition '" << fields[2] << "' of class " << symbol;
    SYLVA_CHECK_INPUT(fields[4] == "IMPLICIT" || fields[4] == "EXPLICIT", lines->Where())
        << "bad definition '" << fields[4] << "' of class " << symbol << " (IMPLICIT or EXPLICIT)";
    if (symbol == "$") continue;
    SYLVA_CHECK_INPUT(mtg->class_scales.emplace(symbol, scale).second, lines->Where())
        << "class " << symbol << " is declared twice";
  }
  SYLVA_CHECK_INPUT(!mtg->class_scales.empty(), lines->source()) << "no class is declared";
}

void ParseDescription(MtgLines* lines, const Mtg& mtg) {
  TakeSection(lines, "DESCRIPTION");
  TakeColumnHeader(lines, {"LEFT", "RIGHT", "RELTYPE", "MAX"}, "DESCRIPTION");
  while (!lines->NextStartsWith("FEATURES")) {
    const std::vector<std::string> fields =
        SplitWhitespace(lines->Take("the FEATURES section").text);
    SYLVA_CHECK_INPUT(fields.size() >= 4, lines->Where())
        << "a description line has 4 columns (LEFT RIGHT RELTYPE MAX)";
    SYLVA_CHECK_INPUT(mtg.class_scales.count(fields[0]) > 0, lines->Where())
        << "unknown class '" << fields[0] << "'";
    std::string rights;
    for (size_t k = 1; k + 2 < fields.size(); ++k) rights += fields[k];
    std::istringstream in(rights);
    std::string right;
    while (std::getline(in, right, ',')) {
      SYLVA_CHECK_INPUT(mtg.class_scales.count(Trim(right)) > 0, lines->Where())
          << "unknown class '" << right << "'";
    }
    const std::string& reltype = fields[fields.size() - 2];
    SYLVA_CHECK_INPUT(reltype == "+" || reltype == "<", lines->Where())
        << "relation type '" << reltype << "' is neither '+' nor '<'";
  }
}

void ParseFeatures(MtgLines* lines, Mtg* mtg) {
  TakeSection(lines, "FEATURES");
  TakeColumnHeader(lines, {"NAME", "TYPE"}, "FEATURES");
  while (!lines->NextStartsWith("MTG")) {
    const std::vector<std::string> fields = SplitWhitespace(lines->Take("the MTG section").text);
    SYLVA_CHECK_INPUT(fields.size() >= 2, lines->Where()) << "a feature line is 'NAME TYPE'";
    SYLVA_CHECK_INPUT(mtg->feature_types.emplace(fields[0], fields[1]).second, lines->Where())
        << "feature " << fields[0] << " is declared twice";
    mtg->feature_names.push_back(fields[0]);
  }
  TakeSection(lines, "MTG");
}

// The MTG column header: the feature names, in consecutive TAB cells from
// `*first_cell` on.
std::vector<std::string> ParseColumnHeader(MtgLines* lines, const Mtg& mtg, size_t* first_cell) {
  const SourceLine& line = lines->Take("the MTG column header");
  const std::vector<std::string> cells = SplitTabs(line.text);
  const std::string head = Trim(cells[0]);
  SYLVA_CHECK_INPUT(StartsWith(head, "ENTITY-CODE") || StartsWith(head, "TOPO"), lines->Where())
      << "expected the column header 'ENTITY-CODE' (or 'TOPO') and the feature names";
  std::vector<std::string> names;
  *first_cell = 0;
  for (size_t k = 1; k < cells.size(); ++k) {
    const std::string name = Trim(cells[k]);
    if (name.empty()) {
      SYLVA_CHECK_INPUT(names.empty(), lines->Where())
          << "feature columns must be consecutive TAB cells (an empty cell after '" << names.back()
          << "')";
      continue;
    }
    SYLVA_CHECK_INPUT(mtg.feature_types.count(name) > 0, lines->Where())
        << "feature '" << name << "' is not declared under FEATURES";
    if (names.empty()) *first_cell = k;
    names.push_back(name);
  }
  return names;
}

// ---------------------------------------------------------------------------
// Code: OpenAlea's Reader.preprocess_line (indentation -> brackets)

// The state of OpenAlea's preprocessing: the indentation of each open
// column and the edge each one opened with.
struct Indentation {
  std::vector<int> indent = {0};
  std::vector<char> edges;
};

bool OpensBranch(char edge) { return edge == '+' || edge == '/'; }

// A line at the current column without '^': a '+' or '/' code closes the
// previous sibling's branch and opens its own.
std::string SameColumn(const std::string& code, Indentation* state) {
  if (state->edges.empty()) return code;
  const std::string close = OpensBranch(state->edges.back()) ? "]" : "";
  if (!OpensBranch(code[0])) return code;
  if (!close.empty()) state->edges.pop_back();
  state->edges.push_back(code[0]);
  return close + "[" + code;
}

std::string Preprocess(const std::string& code, int tabs, Indentation* state,
                       const std::string& where) {
  const int diff = tabs - state->indent.back();
  const bool caret = code[0] == '^';
  if (diff == 0) {
    if (caret) return code.substr(1);
    if (!state->edges.empty()) return SameColumn(code, state);
    if (code[0] == '+') state->edges.push_back('+');
    return code;
  }
  if (diff > 0) {
    SYLVA_CHECK_INPUT(!caret, where)
        << "'^' continues the code above in the same column, but this line is indented further";
    state->indent.push_back(tabs);
    state->edges.push_back(code[0]);
    return OpensBranch(code[0]) ? "[" + code : code;
  }
  std::string brackets;
  while (tabs < state->indent.back()) {
    state->indent.pop_back();
    if (!state->edges.empty()) {
      if (OpensBranch(state->edges.back())) brackets += "]";
      state->edges.pop_back();
    }
  }
  SYLVA_CHECK_INPUT(tabs == state->indent.back(), where)
      << "the code's column (" << tabs << " TABs) matches no column above it";
  return brackets + (caret ? code.substr(1) : SameColumn(code, state));
}

// One step of the code: a bracket or an entity with its relation.
struct CodeToken {
  std::string tag;   // "[", "]", "/", "+", "<", "<<"
  std::string name;  // entity label, e.g. "S12"
  int line = 0;
  const std::map<std::string, std::string>* features = nullptr;  // the line's last entity only
};

void Tokenize(const std::string& code, int line, const std::string& where,
              std::vector<CodeToken>* tokens) {
  size_t p = 0;
  while (p < code.size() && (code[p] == '[' || code[p] == ']')) {
    tokens->push_back({std::string(1, code[p]), "", line});
    ++p;
  }
  SYLVA_CHECK_INPUT(p < code.size(), where) << "empty topological code";
  while (p < code.size()) {
    std::string tag;
    if (code.compare(p, 2, "<<") == 0) {
      tag = "<<";
    } else if (code[p] == '/' || code[p] == '+' || code[p] == '<') {
      tag = std::string(1, code[p]);
    }
    SYLVA_CHECK_INPUT(!tag.empty(), where)
        << "expected '/', '<' or '+' before '" << code.substr(p) << "' in code '" << code << "'";
    p += tag.size();
    const size_t end = code.find_first_of("/+<", p);
    const std::string name = code.substr(p, end == std::string::npos ? end : end - p);
    SYLVA_CHECK_INPUT(!name.empty(), where) << "an entity name is missing in code '" << code << "'";
    SYLVA_CHECK_INPUT(name != "." && name.find('.') == std::string::npos, where)
        << "the abbreviations '<.<' and '+.+' are not supported";
    tokens->push_back({tag, name, line});
    p = end == std::string::npos ? code.size() : end;
  }
}

// ---------------------------------------------------------------------------
// Code: OpenAlea's multiscale_edit (brackets -> entities)

// Splits an entity label such as "S12" into its class symbol and index.
void ParseLabel(const std::string& name, const std::string& where, std::string* symbol,
                int* index) {
  size_t letters = 0;
  while (letters < name.size() && std::isalpha(static_cast<unsigned char>(name[letters]))) {
    ++letters;
  }
  *symbol = name.substr(0, letters);
  const std::string number = name.substr(letters);
  SYLVA_CHECK_INPUT(
      !symbol->empty() && number.size() < 10 &&
          std::all_of(number.begin(), number.end(), [](char c) { return std::isdigit(c); }),
      where)
      << "bad entity name '" << name << "' (a class symbol and an index, e.g. S12)";
  *index = number.empty() ? 0 : std::stoi(number);
}

class MtgBuilder {
 public:
  MtgBuilder(Mtg* mtg, std::string source) : mtg_(mtg), source_(std::move(source)) {
    mtg_->entities.assign(1, MtgEntity());
    mtg_->entities[0].label = "$";
  }

  void Apply(const CodeToken& token) {
    where_ = source_ + ":" + std::to_string(token.line);
    if (token.tag == "[") {
      stack_.push_back(vid_);
    } else if (token.tag == "]") {
      SYLVA_CHECK_INPUT(!stack_.empty(), where_) << "a branch closes that was never opened";
      vid_ = current_ = stack_.back();
      stack_.pop_back();
      scale_ = Scale(vid_);
    } else {
      const int created = Entity(token);
      if (token.features != nullptr) mtg_->entities[created].features = *token.features;
    }
  }

 private:
  int Scale(int v) const { return mtg_->entities[v].scale; }

  int Complex(int v) const {
    const int complex = mtg_->entities[v].complex_idx;
    SYLVA_CHECK_INPUT(complex >= 0, where_) << "the code climbs above the plants' scale";
    return complex;
  }

  int New(const std::string& name, int scale, int complex, int line) {
    MtgEntity entity;
    entity.label = name;
    ParseLabel(name, where_, &entity.symbol, &entity.index);
    entity.scale = scale;
    entity.complex_idx = complex;
    entity.line = line;
    mtg_->entities.push_back(entity);
    return static_cast<int>(mtg_->entities.size()) - 1;
  }

  int AddComponent(int complex, const CodeToken& token) {
    return New(token.name, Scale(complex) + 1, complex, token.line);
  }

  int AddChild(int parent, char edge, const std::string& name, int line) {
    const int child = New(name, Scale(parent), mtg_->entities[parent].complex_idx, line);
    Link(parent, child, edge);
    return child;
  }

  void Link(int parent, int child, char edge) {
    mtg_->entities[child].parent_idx = parent;
    mtg_->entities[child].edge = edge == 0 ? '<' : edge;
  }

  int Entity(const CodeToken& token) {
    std::string symbol;
    int index = 0;
    ParseLabel(token.name, where_, &symbol, &index);
    const auto it = mtg_->class_scales.find(symbol);
    SYLVA_CHECK_INPUT(it != mtg_->class_scales.end(), where_)
        << "entity '" << token.name << "' is of class '" << symbol
        << "', not declared under CLASSES";
    int new_scale = it->second;
    if (token.tag == "/" && new_scale <= scale_) {
      new_scale -= 1;
      pending_ = '/';
    }
    while (new_scale < scale_) {
      --scale_;
      current_ = Complex(current_);
    }
    if (token.tag == "+" || token.tag == "<") return Relation(token);
    if (token.tag == "<<") return Range(token);
    return Decomposition(token);
  }

  int Relation(const CodeToken& token) {
    if (Scale(vid_) == scale_) {
      vid_ = current_ = AddChild(vid_, token.tag[0], token.name, token.line);
      pending_ = 0;
    } else {
      current_ = AddComponent(Complex(current_), token);
      pending_ = token.tag[0];
    }
    return current_;
  }

  // E1<<E5: E2, E3, E4, E5 after the current entity; the last one is `token`.
  int Range(const CodeToken& token) {
    const int from_index = mtg_->entities[current_].index;
    const std::string from_label = mtg_->entities[current_].label;
    std::string symbol;
    int to_index = 0;
    ParseLabel(token.name, where_, &symbol, &to_index);
    SYLVA_CHECK_INPUT(to_index > from_index, where_)
        << "'" << from_label << "<<" << token.name << "' does not count up";
    for (int i = from_index + 1; i <= to_index; ++i) {
      vid_ = current_ = AddChild(vid_, '<', symbol + std::to_string(i), token.line);
    }
    pending_ = 0;
    return current_;
  }

  int Decomposition(const CodeToken& token) {
    if (Scale(vid_) == scale_) {
      vid_ = current_ = AddComponent(vid_, token);
      ++scale_;
    } else if (Scale(vid_) > scale_) {
      ++scale_;
      const int component = AddComponent(current_, token);
      if (Scale(vid_) == scale_ && pending_ != '/') {
        Link(vid_, component, pending_);
        vid_ = current_ = component;
      } else {
        current_ = component;
        if (pending_ == '/') {
          vid_ = current_;
          scale_ = Scale(vid_);
        }
      }
    } else {
      vid_ = current_ = AddComponent(current_, token);
    }
    return current_;
  }

  Mtg* mtg_;
  std::string source_;
  std::string where_;
  int vid_ = 0;      // OpenAlea's `vid`: the entity of the finest scale reached
  int current_ = 0;  // OpenAlea's `current_vertex`
  int scale_ = 0;
  char pending_ = 0;  // the relation for the next entity of vid_'s scale
  std::vector<int> stack_;
};

// Reads the code lines into tokens (features attached to each line's last entity).
std::vector<CodeToken> TokenizeCode(MtgLines* lines, const std::vector<std::string>& names,
                                    size_t first_cell,
                                    std::vector<std::map<std::string, std::string>>* features) {
  std::vector<CodeToken> tokens;
  Indentation state;
  std::vector<std::pair<size_t, size_t>> attach;  // token index -> features index
  while (!lines->AtEnd()) {
    const SourceLine& line = lines->Take("");
    const std::string where = lines->Where();
    const std::string code = SplitWhitespace(line.text)[0];
    SYLVA_CHECK_INPUT(code[0] != '(', where) << "aliases '(name)' are not supported";
    SYLVA_CHECK_INPUT(code[0] != '*', where) << "dated observations '*' are not supported";
    SYLVA_CHECK_INPUT(code.find("++") == std::string::npos, where)
        << "the abbreviation '++' is not supported";
    const std::vector<std::string> cells = SplitTabs(line.text);
    std::map<std::string, std::string> values;
    for (size_t k = 0; k < names.size(); ++k) {
      const size_t cell = first_cell + k;
      if (cell < cells.size() && !Trim(cells[cell]).empty()) values[names[k]] = Trim(cells[cell]);
    }
    const int tabs = static_cast<int>(line.text.find_first_not_of('\t'));
    Tokenize(Preprocess(code, tabs, &state, where), line.number, where, &tokens);
    SYLVA_CHECK_INPUT(tokens.back().tag != "[" && tokens.back().tag != "]", where)
        << "no entity in code '" << code << "'";
    if (!values.empty()) {
      features->push_back(std::move(values));
      attach.emplace_back(tokens.size() - 1, features->size() - 1);
    }
  }
  for (const auto& [token, index] : attach) tokens[token].features = &(*features)[index];
  while (!state.edges.empty()) {
    if (OpensBranch(state.edges.back())) tokens.push_back({"]", "", 0});
    state.edges.pop_back();
  }
  return tokens;
}

}  // namespace

Mtg ParseMtg(const std::string& text, const std::string& source) {
  MtgLines lines(SignificantLines(text), source);
  Mtg mtg;
  ParseCode(&lines);
  ParseClasses(&lines, &mtg);
  ParseDescription(&lines, mtg);
  ParseFeatures(&lines, &mtg);
  size_t first_cell = 0;
  const std::vector<std::string> names = ParseColumnHeader(&lines, mtg, &first_cell);
  std::vector<std::map<std::string, std::string>> features;
  const std::vector<CodeToken> tokens = TokenizeCode(&lines, names, first_cell, &features);
  SYLVA_CHECK_INPUT(!tokens.empty(), source) << "the MTG section codes no entity";
  MtgBuilder builder(&mtg, source);
  for (const CodeToken& token : tokens) builder.Apply(token);
  return mtg;
}

Mtg ReadMtg(const std::filesystem::path& path) {
  return ParseMtg(ReadFileToString(path), path.string());
}

// ---------------------------------------------------------------------------
// MTG -> skeletons

void MtgToSkeletonOptions::Check() const {
  SYLVA_CHECK_INPUT(diameter_unit > 0 && std::isfinite(diameter_unit), "diameter_unit")
      << "must be > 0, got " << diameter_unit;
}

std::string MtgSkeletons::BriefReport() const {
  std::ostringstream out;
  int nodes = 0;
  for (const SkeletonGraph& part : parts) nodes += part.NumNodes();
  out << parts.size() << " part(s), " << nodes << " nodes from the " << placed_entities
      << " entities with XX YY ZZ at scale " << geometry_scale << " (" << unplaced_entities
      << " without coordinates skipped, " << merged_nodes << " at their parent's position merged, "
      << base_nodes << " base points from an axis or plant); radii from "
      << (radius_feature.empty() ? "no feature (none given)" : radius_feature) << " ("
      << radii_filled << " filled from a neighbour).";
  return out.str();
}

namespace {

double FeatureNumber(const MtgEntity& entity, const std::string& name, const std::string& source) {
  const std::string& text = entity.features.at(name);
  // Python's float(), which OpenAlea uses, also takes a leading '+'.
  const char* begin = text.data() + (text.size() > 1 && text[0] == '+' ? 1 : 0);
  double value = 0.0;
  const auto [end, error] = std::from_chars(begin, text.data() + text.size(), value);
  SYLVA_CHECK_INPUT(
      error == std::errc() && end == text.data() + text.size() && std::isfinite(value),
      source + ":" + std::to_string(entity.line))
      << "feature " << name << " of " << entity.label << " is '" << text
      << "', not a finite number";
  return value;
}

bool HasPosition(const MtgEntity& entity) {
  return entity.features.count("XX") > 0 && entity.features.count("YY") > 0 &&
         entity.features.count("ZZ") > 0;
}

Eigen::Vector3d Position(const MtgEntity& entity, const std::string& source) {
  return {FeatureNumber(entity, "XX", source), FeatureNumber(entity, "YY", source),
          FeatureNumber(entity, "ZZ", source)};
}

std::string RadiusFeature(const Mtg& mtg) {
  for (const char* name : {"radius", "TopDia", "TopDiameter"}) {
    if (mtg.feature_types.count(name) > 0) return name;
  }
  return "";
}

// Gives nodes without a radius (-1) their parent's, a root its first child's.
int FillRadii(SkeletonGraph* skeleton) {
  int filled = 0;
  std::vector<SkeletonNode>& nodes = skeleton->nodes;
  for (SkeletonNode& node : nodes) {
    if (node.radius < 0 && node.parent_idx >= 0 && nodes[node.parent_idx].radius >= 0) {
      node.radius = nodes[node.parent_idx].radius;
      ++filled;
    }
  }
  const std::vector<std::vector<int>> children = skeleton->Children();
  for (int i = static_cast<int>(nodes.size()) - 1; i >= 0; --i) {
    if (nodes[i].radius >= 0) continue;
    for (int child : children[i]) {
      if (nodes[child].radius >= 0) {
        nodes[i].radius = nodes[child].radius;
        ++filled;
        break;
      }
    }
  }
  for (SkeletonNode& node : nodes) node.radius = std::max(node.radius, 0.0);
  return filled;
}

// Builds the skeletons of MtgSkeletons: see SkeletonsFromMtg.
class SkeletonBuilder {
 public:
  SkeletonBuilder(const Mtg& mtg, const std::string& source, const MtgToSkeletonOptions& options,
                  MtgSkeletons* out)
      : mtg_(mtg), source_(source), options_(options), out_(out) {
    out_->radius_feature = RadiusFeature(mtg);
    node_.assign(mtg.entities.size(), -1);
    part_.assign(mtg.entities.size(), -1);
  }

  void Build() {
    for (int e = 0; e < static_cast<int>(mtg_.entities.size()); ++e) {
      if (mtg_.entities[e].scale == out_->geometry_scale) Add(e);
    }
  }

 private:
  // The entity's radius in world units, or -1 without a value.
  double Radius(const MtgEntity& entity) const {
    const std::string& name = out_->radius_feature;
    if (name.empty() || entity.features.count(name) == 0) return -1.0;
    const double value = FeatureNumber(entity, name, source_);
    SYLVA_CHECK_INPUT(value >= 0, source_ + ":" + std::to_string(entity.line))
        << name << " of " << entity.label << " is negative";
    return name == "radius" ? value : value / 2.0 / options_.diameter_unit;
  }

  // The nearest enclosing entity with coordinates, or -1.
  int PlacedComplex(int e) const {
    for (int c = mtg_.entities[e].complex_idx; c > 0; c = mtg_.entities[c].complex_idx) {
      if (HasPosition(mtg_.entities[c])) return c;
    }
    return -1;
  }

  int AddNode(int part, int e, const Eigen::Vector3d& position, double radius, int parent) {
    out_->entity_of_node[part].push_back(e);
    return out_->parts[part].AddNode(position, radius, parent, 0);
  }

  void Add(int e) {
    const MtgEntity& entity = mtg_.entities[e];
    const int parent = entity.parent_idx;
    const int anchor = parent >= 0 ? node_[parent] : -1;
    if (!HasPosition(entity)) {
      ++out_->unplaced_entities;
      node_[e] = anchor;
      part_[e] = parent >= 0 ? part_[parent] : -1;
      return;
    }
    ++out_->placed_entities;
    const Eigen::Vector3d position = Position(entity, source_);
    if (anchor < 0) {
      AddRoot(e, position);
      return;
    }
    const int part = part_[parent];
    part_[e] = part;
    if (out_->parts[part].nodes[anchor].position == position) {
      node_[e] = anchor;
      ++out_->merged_nodes;
      return;
    }
    node_[e] = AddNode(part, e, position, Radius(entity), anchor);
  }

  void AddRoot(int e, const Eigen::Vector3d& position) {
    const int part = static_cast<int>(out_->parts.size());
    out_->parts.emplace_back();
    out_->entity_of_node.emplace_back();
    part_[e] = part;
    int parent = -1;
    const int base = PlacedComplex(e);
    if (base >= 0 && Position(mtg_.entities[base], source_) != position) {
      parent = AddNode(part, base, Position(mtg_.entities[base], source_),
                       Radius(mtg_.entities[base]), -1);
      ++out_->base_nodes;
    }
    node_[e] = AddNode(part, e, position, Radius(mtg_.entities[e]), parent);
  }

  const Mtg& mtg_;
  const std::string& source_;
  const MtgToSkeletonOptions& options_;
  MtgSkeletons* out_;
  std::vector<int> node_;  // per entity: its node, or its nearest placed ancestor's
  std::vector<int> part_;  // per entity: the part of that node
};

}  // namespace

MtgSkeletons SkeletonsFromMtg(const Mtg& mtg, const std::string& source,
                              const MtgToSkeletonOptions& options) {
  options.Check();
  MtgSkeletons out;
  out.geometry_scale = -1;
  for (const MtgEntity& entity : mtg.entities) {
    if (HasPosition(entity)) out.geometry_scale = std::max(out.geometry_scale, entity.scale);
  }
  SYLVA_CHECK_INPUT(out.geometry_scale >= 0, source)
      << "no entity has all of the features XX, YY and ZZ: the tree cannot be placed (only "
         "files of digitised coordinates can be read)";
  SkeletonBuilder(mtg, source, options, &out).Build();
  for (SkeletonGraph& part : out.parts) {
    out.radii_filled += FillRadii(&part);
    part.radius_source =
        out.radius_feature.empty() ? "unknown" : "from the MTG feature " + out.radius_feature;
    part.AssignOrders();
    part.Check();
  }
  return out;
}

// ---------------------------------------------------------------------------
// Skeletons -> MTG text

namespace {

constexpr int kPlantColumn = 0;

// Writes one plant's lines: the code in its TAB column, the features from
// TAB cell `code_cells` on.
class MtgPlantWriter {
 public:
  MtgPlantWriter(const SkeletonGraph& skeleton, int code_cells, std::string* out,
                 std::vector<int>* order)
      : skeleton_(skeleton), code_cells_(code_cells), out_(out), order_(order) {
    axes_ = skeleton.BranchAxes(&orders_);
    laterals_.resize(skeleton.nodes.size());
    for (size_t a = 1; a < axes_.size(); ++a) laterals_[axes_[a][0]].push_back(static_cast<int>(a));
  }

  void Write(int plant) {
    Line(kPlantColumn, "/P" + std::to_string(plant), -1);
    if (axes_.empty()) return;
    Line(kPlantColumn + 1, "/A1", -1);
    Axis(0, kPlantColumn + 2);
  }

 private:
  void Line(int column, const std::string& code, int node) {
    *out_ += std::string(column, '\t') + code;
    if (node >= 0) {
      const SkeletonNode& n = skeleton_.nodes[node];
      *out_ += std::string(code_cells_ - column, '\t') + DoubleText(n.position.x()) + "\t" +
               DoubleText(n.position.y()) + "\t" + DoubleText(n.position.z()) + "\t" +
               DoubleText(n.radius);
      order_->push_back(node);
    }
    *out_ += "\n";
  }

  // Axis a's nodes as S1, S2, ... in `column`, each followed by the axes branching there.
  void Axis(int a, int column) {
    const BranchAxis& axis = axes_[a];
    const size_t first = a == 0 ? 0 : 1;  // a lateral's junction belongs to its parent axis
    for (size_t k = first; k < axis.size(); ++k) {
      const std::string label = "S" + std::to_string(k - first + 1);
      Line(column, k == first ? "/" + label : "^<" + label, axis[k]);
      for (int b : laterals_[axis[k]]) {
        Line(column, "^+A" + std::to_string(b + 1), -1);
        Axis(b, column + 1);
      }
    }
  }

  const SkeletonGraph& skeleton_;
  int code_cells_;
  std::string* out_;
  std::vector<int>* order_;
  std::vector<BranchAxis> axes_;
  std::vector<int> orders_;
  std::vector<std::vector<int>> laterals_;  // per node: the axes branching there
};

const char kMtgHeader[] =
    "CODE:\tFORM-A\n"
    "\n"
    "CLASSES:\n"
    "SYMBOL\tSCALE\tDECOMPOSITION\tINDEXATION\tDEFINITION\n"
    "$\t0\tFREE\tFREE\tIMPLICIT\n"
    "P\t1\tCONNECTED\tFREE\tIMPLICIT\n"
    "A\t2\t<-LINEAR\tFREE\tIMPLICIT\n"
    "S\t3\tNONE\tFREE\tEXPLICIT\n"
    "\n"
    "DESCRIPTION:\n"
    "LEFT\tRIGHT\tRELTYPE\tMAX\n"
    "A\tA\t+\t?\n"
    "S\tS\t<\t1\n"
    "S\tS\t+\t?\n"
    "\n"
    "FEATURES:\n"
    "NAME\tTYPE\n"
    "XX\tREAL\n"
    "YY\tREAL\n"
    "ZZ\tREAL\n"
    "radius\tREAL\n"
    "\n"
    "MTG:\n";

}  // namespace

std::string MtgText(const std::vector<SkeletonGraph>& parts, const std::string& units,
                    std::vector<std::vector<int>>* node_order) {
  int max_order = 0;
  for (const SkeletonGraph& part : parts) {
    part.Check();
    std::vector<int> orders;
    part.BranchAxes(&orders);
    for (int order : orders) max_order = std::max(max_order, order);
  }
  // Columns: P in 0, the trunk A in 1, an axis of order k's S (and the
  // '+A' lines of its branches) in k + 2.
  const int code_cells = max_order + 3;
  std::string out =
      "# A tree skeleton written by sylva: one S entity per skeleton node, XX YY ZZ its\n";
  out += "# position and radius its radius, in " + units +
         " (radii: " + (parts.empty() ? std::string("none") : parts[0].radius_source) + ").\n";
  out += kMtgHeader;
  out += "ENTITY-CODE" + std::string(code_cells, '\t') + "XX\tYY\tZZ\tradius\n";
  std::vector<std::vector<int>> orders(parts.size());
  for (size_t p = 0; p < parts.size(); ++p) {
    MtgPlantWriter(parts[p], code_cells, &out, &orders[p]).Write(static_cast<int>(p) + 1);
  }
  if (node_order != nullptr) *node_order = std::move(orders);
  return out;
}

void WriteMtg(const std::filesystem::path& path, const std::vector<SkeletonGraph>& parts,
              const std::string& units) {
  AtomicWriteString(path, MtgText(parts, units));
}

}  // namespace sylva
