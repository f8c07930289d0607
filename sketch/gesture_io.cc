#include "sketch/gesture_io.h"

#include <tinyxml2.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <sstream>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

constexpr char kFormatName[] = "sylva-gesture";
constexpr int kFormatVersion = 1;
// InkML's prefixes of first and second differences and of omitted values.
constexpr char kDifferenceEncodings[] = "'\"!?";

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool StartsWithRoi(const char* text) { return text != nullptr && Lower(text).rfind("roi", 0) == 0; }

// Samples timed by arc length (files without time: constant speed).
void TimeByArcLength(GestureStroke* stroke) {
  double t = 0.0;
  for (size_t k = 0; k < stroke->samples.size(); ++k) {
    if (k > 0) t += (stroke->samples[k].position - stroke->samples[k - 1].position).norm();
    stroke->samples[k].t = t;
  }
}

// Drops samples repeating the previous position (a tracker at rest), so
// arc-length time stays strictly increasing.
void DropRepeats(GestureStroke* stroke) {
  std::vector<GestureSample> kept;
  for (const GestureSample& s : stroke->samples) {
    if (kept.empty() || (s.position - kept.back().position).norm() > 0) kept.push_back(s);
  }
  stroke->samples = std::move(kept);
}

// --- sylva-gesture JSON ---------------------------------------------------

GestureKind JsonKind(const JsonCursor& kind) {
  const std::string name = kind.AsString();
  if (name == "trunk") return GestureKind::kTrunk;
  if (name == "roi") return GestureKind::kRoi;
  kind.Fail("unknown stroke kind '" + name + "' (expected trunk or roi)");
}

GestureSample JsonSample(const JsonCursor& sample) {
  const std::vector<double> v = sample.AsDoubles();
  if (v.size() != 4 && v.size() != 5) {
    sample.Fail("a sample is [t, x, y, z] or [t, x, y, z, pressure]");
  }
  GestureSample s;
  s.t = v[0];
  s.position = Eigen::Vector3d(v[1], v[2], v[3]);
  if (v.size() == 5) {
    if (!(v[4] >= 0 && v[4] <= 1)) sample.Fail("pressure must lie in [0, 1]");
    s.pressure = v[4];
  }
  return s;
}

// --- InkML ------------------------------------------------------------------

using tinyxml2::XMLElement;

std::string LocalName(const XMLElement& element) {
  const std::string name = element.Name();
  const size_t colon = name.find(':');
  return colon == std::string::npos ? name : name.substr(colon + 1);
}

// The first descendant named `name` (without namespace prefix), depth first.
const XMLElement* FindDescendant(const XMLElement& parent, const std::string& name) {
  for (const XMLElement* child = parent.FirstChildElement(); child != nullptr;
       child = child->NextSiblingElement()) {
    if (LocalName(*child) == name) return child;
    if (const XMLElement* found = FindDescendant(*child, name)) return found;
  }
  return nullptr;
}

// Channel name -> column, from the document's <traceFormat>.
std::map<std::string, int> InkmlChannels(const XMLElement& ink, const std::string& source) {
  const XMLElement* format = FindDescendant(ink, "traceFormat");
  SYLVA_CHECK_INPUT(format != nullptr, source) << "no <traceFormat> declaring the channels";
  std::map<std::string, int> channels;
  int column = 0;
  for (const XMLElement* c = format->FirstChildElement(); c != nullptr;
       c = c->NextSiblingElement()) {
    if (LocalName(*c) != "channel") continue;
    const char* name = c->Attribute("name");
    SYLVA_CHECK_INPUT(name != nullptr, source)
        << "line " << c->GetLineNum() << ": <channel> without a name";
    // A repeated name would leave a column no channel reads (and the
    // samples' count check short of the columns).
    SYLVA_CHECK_INPUT(channels.emplace(name, column++).second, source)
        << "line " << c->GetLineNum() << ": channel '" << name << "' is declared twice";
  }
  for (const char* required : {"X", "Y", "Z"}) {
    SYLVA_CHECK_INPUT(channels.count(required), source)
        << "line " << format->GetLineNum() << ": the <traceFormat> has no " << required
        << " channel (3D gestures need X, Y and Z)";
  }
  return channels;
}

bool InkmlIsRoi(const XMLElement& trace, const XMLElement* group) {
  if (StartsWithRoi(trace.Attribute("xml:id")) || StartsWithRoi(trace.Attribute("brushRef")))
    return true;
  if (group != nullptr && StartsWithRoi(group->Attribute("xml:id"))) return true;
  for (const XMLElement* a = trace.FirstChildElement(); a != nullptr; a = a->NextSiblingElement()) {
    const char* type = a->Attribute("type");
    if (LocalName(*a) == "annotation" && type != nullptr && std::string(type) == "kind" &&
        a->GetText() != nullptr && StartsWithRoi(a->GetText()))
      return true;
  }
  return false;
}

// The text of a <trace> (its own text nodes, not its annotations').
std::string TraceText(const XMLElement& trace) {
  std::string text;
  for (const tinyxml2::XMLNode* node = trace.FirstChild(); node != nullptr;
       node = node->NextSibling()) {
    if (const tinyxml2::XMLText* piece = node->ToText()) text += piece->Value();
  }
  return text;
}

GestureStroke InkmlStroke(const XMLElement& trace, const XMLElement* group,
                          const std::map<std::string, int>& channels, const std::string& source) {
  GestureStroke stroke;
  stroke.kind = InkmlIsRoi(trace, group) ? GestureKind::kRoi : GestureKind::kTrunk;
  std::stringstream samples(TraceText(trace));
  const std::string where = "line " + std::to_string(trace.GetLineNum()) + ", <trace> sample ";
  int index = 0;
  for (std::string item; std::getline(samples, item, ',');) {
    ++index;
    if (item.find_first_not_of(" \t\r\n") == std::string::npos) continue;
    SYLVA_CHECK_INPUT(item.find_first_of(kDifferenceEncodings) == std::string::npos, source)
        << where << index
        << ": InkML difference encodings are not supported (explicit values only)";
    std::istringstream values(item);
    std::vector<double> v;
    std::string token;
    while (values >> token) {
      char* end = nullptr;
      const double value = std::strtod(token.c_str(), &end);
      SYLVA_CHECK_INPUT(*end == '\0' && std::isfinite(value), source)
          << where << index << ": '" << token << "' is not a number";
      v.push_back(value);
    }
    SYLVA_CHECK_INPUT(v.size() == channels.size(), source)
        << where << index << ": " << v.size() << " values for " << channels.size() << " channels";
    GestureSample s;
    s.position = {v[channels.at("X")], v[channels.at("Y")], v[channels.at("Z")]};
    if (channels.count("T")) s.t = v[channels.at("T")];
    if (channels.count("F")) s.pressure = std::clamp(v[channels.at("F")], 0.0, 1.0);
    stroke.samples.push_back(s);
  }
  return stroke;
}

void CollectTraces(const XMLElement& parent, const XMLElement* group,
                   const std::map<std::string, int>& channels, const std::string& source,
                   GestureSet* set) {
  for (const XMLElement* child = parent.FirstChildElement(); child != nullptr;
       child = child->NextSiblingElement()) {
    const std::string name = LocalName(*child);
    if (name == "trace") set->strokes.push_back(InkmlStroke(*child, group, channels, source));
    if (name == "traceGroup") CollectTraces(*child, child, channels, source, set);
  }
}

// --- OBJ and PLY --------------------------------------------------------------

// `token` as a vertex index of an OBJ `l` line (1-based, or negative from
// the end) into `count` vertices.
int ObjIndex(const std::string& token, int count, const std::string& source, int line) {
  char* end = nullptr;
  const long value = std::strtol(token.c_str(), &end, 10);
  SYLVA_CHECK_INPUT(end != token.c_str() && (*end == '\0' || *end == '/'), source)
      << "line " << line << ": '" << token << "' is not a vertex index";
  const long index = value < 0 ? count + value : value - 1;
  SYLVA_CHECK_INPUT(value != 0 && index >= 0 && index < count, source)
      << "line " << line << ": vertex " << value << " does not exist (" << count
      << " vertices so far)";
  return static_cast<int>(index);
}

Eigen::Vector3d ParsePoint(std::istringstream& in, const std::string& source,
                           const std::string& where) {
  Eigen::Vector3d p;
  in >> p.x() >> p.y() >> p.z();
  SYLVA_CHECK_INPUT(!in.fail() && p.allFinite(), source) << where << ": expected x y z numbers";
  return p;
}

// Polylines of an edge list: chains through vertices of degree 2, each
// starting at a vertex of another degree (or anywhere on a closed loop).
std::vector<std::vector<int>> ChainEdges(int vertices,
                                         const std::vector<std::array<int, 2>>& edges) {
  std::vector<std::vector<int>> adjacent(vertices);
  for (size_t e = 0; e < edges.size(); ++e) {
    adjacent[edges[e][0]].push_back(static_cast<int>(e));
    adjacent[edges[e][1]].push_back(static_cast<int>(e));
  }
  std::vector<char> used(edges.size(), 0);
  std::vector<std::vector<int>> chains;
  auto walk = [&](int start, int edge) {
    std::vector<int> chain = {start};
    int at = start;
    while (edge >= 0 && !used[edge]) {
      used[edge] = 1;
      at = edges[edge][0] == at ? edges[edge][1] : edges[edge][0];
      chain.push_back(at);
      edge = -1;
      if (adjacent[at].size() == 2) {
        for (int next : adjacent[at]) edge = used[next] ? edge : next;
      }
    }
    chains.push_back(chain);
  };
  for (int pass = 0; pass < 2; ++pass) {  // open chains first, then loops
    for (int v = 0; v < vertices; ++v) {
      if (pass == 0 && adjacent[v].size() == 2) continue;
      for (int e : adjacent[v]) {
        if (!used[e]) walk(v, e);
      }
    }
  }
  return chains;
}

struct PlyHeader {
  int vertices = 0, edges = 0;
  std::vector<std::string> vertex_properties, edge_properties;
  int lines = 0;  // header lines, including end_header
};

PlyHeader ReadPlyHeader(std::istream& in, const std::string& source) {
  PlyHeader header;
  std::string line, element;
  while (std::getline(in, line)) {
    ++header.lines;
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (header.lines == 1) {
      SYLVA_CHECK_INPUT(word == "ply", source) << "line 1: not a PLY file (no 'ply' magic)";
    } else if (word == "format") {
      words >> word;
      SYLVA_CHECK_INPUT(word == "ascii", source)
          << "line " << header.lines << ": only ASCII PLY is read, not '" << word << "'";
    } else if (word == "element") {
      int count = -1;
      words >> element >> count;
      SYLVA_CHECK_INPUT(count >= 0, source) << "line " << header.lines << ": bad element count";
      SYLVA_CHECK_INPUT((element == "vertex" && header.edges == 0) || element == "edge", source)
          << "line " << header.lines << ": expected 'element vertex' then 'element edge', got '"
          << element << "'";
      (element == "vertex" ? header.vertices : header.edges) = count;
    } else if (word == "property") {
      std::string type, name;
      words >> type >> name;
      SYLVA_CHECK_INPUT(type != "list", source)
          << "line " << header.lines << ": list properties are not read (edges are "
          << "'property int vertex1' and 'vertex2')";
      if (element == "vertex") header.vertex_properties.push_back(name);
      if (element == "edge") header.edge_properties.push_back(name);
    } else if (word == "end_header") {
      return header;
    }
  }
  SYLVA_INPUT_ERROR(source) << "no end_header";
  return header;
}

int PropertyIndex(const std::vector<std::string>& properties, const std::string& name,
                  const std::string& source, bool required) {
  const auto it = std::find(properties.begin(), properties.end(), name);
  SYLVA_CHECK_INPUT(!required || it != properties.end(), source)
      << "the PLY header has no property '" << name << "'";
  return it == properties.end() ? -1 : static_cast<int>(it - properties.begin());
}

// One data line of `count` numbers.
std::vector<double> PlyValues(std::istream& in, size_t count, const std::string& source,
                              int* line_number) {
  std::string line;
  ++*line_number;
  SYLVA_CHECK_INPUT(static_cast<bool>(std::getline(in, line)), source)
      << "line " << *line_number << ": the file ends before its elements";
  std::istringstream words(line);
  std::vector<double> values(count);
  for (double& v : values) words >> v;
  SYLVA_CHECK_INPUT(!words.fail(), source)
      << "line " << *line_number << ": expected " << count << " numbers";
  return values;
}

}  // namespace

double GestureStroke::Length() const {
  double length = 0.0;
  for (size_t k = 1; k < samples.size(); ++k) {
    length += (samples[k].position - samples[k - 1].position).norm();
  }
  return length;
}

int GestureSet::Count(GestureKind kind) const {
  return static_cast<int>(std::count_if(strokes.begin(), strokes.end(),
                                        [&](const GestureStroke& s) { return s.kind == kind; }));
}

void GestureSet::Check() const {
  SYLVA_CHECK_INPUT(!strokes.empty(), source) << "no gesture strokes";
  for (size_t k = 0; k < strokes.size(); ++k) {
    const std::vector<GestureSample>& samples = strokes[k].samples;
    SYLVA_CHECK_INPUT(samples.size() >= 2 && strokes[k].Length() > 0, source)
        << "stroke " << k << ": fewer than two distinct samples";
    for (size_t i = 0; i < samples.size(); ++i) {
      SYLVA_CHECK_INPUT(samples[i].position.allFinite() && std::isfinite(samples[i].t), source)
          << "stroke " << k << ", sample " << i << ": not finite";
      SYLVA_CHECK_INPUT(i == 0 || samples[i].t > samples[i - 1].t, source)
          << "stroke " << k << ", sample " << i << ": time " << samples[i].t
          << " does not increase (previous " << samples[i - 1].t << ")";
    }
  }
}

std::string GestureKindName(GestureKind kind) {
  return kind == GestureKind::kRoi ? "roi" : "trunk";
}

GestureSet ReadGestureJson(const std::filesystem::path& path) {
  const Json json = ReadJsonFile(path);
  const JsonCursor top(json, path.string());
  CheckJsonFormat(top, kFormatName, kFormatVersion);
  GestureSet set;
  set.source = path.string();
  set.timed = true;
  const JsonCursor strokes = top["strokes"];
  if (strokes.Size() == 0) strokes.Fail("no strokes");
  for (size_t k = 0; k < strokes.Size(); ++k) {
    GestureStroke stroke;
    stroke.kind = JsonKind(strokes[k]["kind"]);
    const JsonCursor samples = strokes[k]["samples"];
    for (size_t i = 0; i < samples.Size(); ++i) {
      stroke.samples.push_back(JsonSample(samples[i]));
      if (i > 0 && !(stroke.samples[i].t > stroke.samples[i - 1].t)) {
        samples[i].Fail("time does not increase");
      }
    }
    if (samples.Size() < 2) samples.Fail("a stroke needs at least two samples");
    set.strokes.push_back(std::move(stroke));
  }
  set.Check();
  return set;
}

GestureSet ReadGestureInkml(const std::filesystem::path& path) {
  const std::string source = path.string();
  const std::string text = ReadFileToString(path);
  tinyxml2::XMLDocument document;
  if (document.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
    SYLVA_INPUT_ERROR(source) << "not valid XML (line " << document.ErrorLineNum()
                              << "): " << document.ErrorStr();
  }
  const XMLElement* ink = document.RootElement();
  SYLVA_CHECK_INPUT(ink != nullptr && LocalName(*ink) == "ink", source)
      << "not an InkML file: the root element is not <ink>";
  const std::map<std::string, int> channels = InkmlChannels(*ink, source);
  GestureSet set;
  set.source = source;
  set.timed = channels.count("T") > 0;
  CollectTraces(*ink, nullptr, channels, source, &set);
  SYLVA_CHECK_INPUT(!set.strokes.empty(), source) << "no <trace>";
  for (GestureStroke& stroke : set.strokes) {
    if (!set.timed) DropRepeats(&stroke), TimeByArcLength(&stroke);
  }
  set.Check();
  return set;
}

GestureSet ReadGestureObj(const std::filesystem::path& path) {
  GestureSet set;
  set.source = path.string();
  std::istringstream lines(ReadFileToString(path));
  std::vector<Eigen::Vector3d> vertices;
  bool roi = false;
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "v") {
      vertices.push_back(ParsePoint(words, set.source, "line " + std::to_string(number)));
    } else if (word == "g" || word == "o") {
      std::string name;
      words >> name;
      roi = StartsWithRoi(name.c_str());
    } else if (word == "l") {
      GestureStroke stroke;
      stroke.kind = roi ? GestureKind::kRoi : GestureKind::kTrunk;
      for (std::string token; words >> token;) {
        const int index = ObjIndex(token, static_cast<int>(vertices.size()), set.source, number);
        stroke.samples.push_back({0.0, vertices[index], 1.0});
      }
      DropRepeats(&stroke);
      SYLVA_CHECK_INPUT(stroke.samples.size() >= 2, set.source)
          << "line " << number << ": a polyline needs two distinct vertices";
      TimeByArcLength(&stroke);
      set.strokes.push_back(std::move(stroke));
    }
  }
  SYLVA_CHECK_INPUT(!set.strokes.empty(), set.source) << "no 'l' polylines";
  set.Check();
  return set;
}

GestureSet ReadGesturePly(const std::filesystem::path& path) {
  GestureSet set;
  set.source = path.string();
  std::istringstream in(ReadFileToString(path));
  const PlyHeader header = ReadPlyHeader(in, set.source);
  SYLVA_CHECK_INPUT(header.edges > 0, set.source) << "no 'element edge' (or no edges)";
  const int x = PropertyIndex(header.vertex_properties, "x", set.source, true);
  const int y = PropertyIndex(header.vertex_properties, "y", set.source, true);
  const int z = PropertyIndex(header.vertex_properties, "z", set.source, true);
  const int roi = PropertyIndex(header.vertex_properties, "roi", set.source, false);
  const int v1 = PropertyIndex(header.edge_properties, "vertex1", set.source, true);
  const int v2 = PropertyIndex(header.edge_properties, "vertex2", set.source, true);
  int line = header.lines;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<char> is_roi;
  for (int k = 0; k < header.vertices; ++k) {
    const std::vector<double> v = PlyValues(in, header.vertex_properties.size(), set.source, &line);
    vertices.emplace_back(v[x], v[y], v[z]);
    SYLVA_CHECK_INPUT(vertices.back().allFinite(), set.source) << "line " << line << ": not finite";
    is_roi.push_back(roi >= 0 && v[roi] != 0);
  }
  std::vector<std::array<int, 2>> edges;
  for (int k = 0; k < header.edges; ++k) {
    const std::vector<double> v = PlyValues(in, header.edge_properties.size(), set.source, &line);
    for (int end : {v1, v2}) {
      SYLVA_CHECK_INPUT(v[end] >= 0 && v[end] < header.vertices && v[end] == std::floor(v[end]),
                        set.source)
          << "line " << line << ": edge vertex " << v[end] << " does not exist";
    }
    edges.push_back({static_cast<int>(v[v1]), static_cast<int>(v[v2])});
  }
  for (const std::vector<int>& chain : ChainEdges(header.vertices, edges)) {
    GestureStroke stroke;
    stroke.kind = is_roi[chain[0]] ? GestureKind::kRoi : GestureKind::kTrunk;
    for (int v : chain) stroke.samples.push_back({0.0, vertices[v], 1.0});
    DropRepeats(&stroke);
    SYLVA_CHECK_INPUT(stroke.samples.size() >= 2, set.source)
        << "edge chain from vertex " << chain[0] << ": fewer than two distinct vertices";
    TimeByArcLength(&stroke);
    set.strokes.push_back(std::move(stroke));
  }
  set.Check();
  return set;
}

GestureSet ReadGesture(const std::filesystem::path& path) {
  const std::string extension = Lower(path.extension().string());
  if (extension == ".json") return ReadGestureJson(path);
  if (extension == ".inkml") return ReadGestureInkml(path);
  if (extension == ".obj") return ReadGestureObj(path);
  if (extension == ".ply") return ReadGesturePly(path);
  SYLVA_INPUT_ERROR(path.string()) << "unknown gesture file type '" << extension
                                   << "': expected .json (sylva-gesture), .inkml, .obj or .ply";
  return GestureSet();
}

void WriteGestureJson(const std::filesystem::path& path, const GestureSet& gestures) {
  Json strokes = Json::array();
  for (const GestureStroke& stroke : gestures.strokes) {
    Json samples = Json::array();
    for (const GestureSample& s : stroke.samples) {
      samples.push_back({s.t, s.position.x(), s.position.y(), s.position.z(), s.pressure});
    }
    strokes.push_back({{"kind", GestureKindName(stroke.kind)}, {"samples", samples}});
  }
  WriteJsonFile(path, {{"format", kFormatName}, {"version", kFormatVersion}, {"strokes", strokes}});
}

}  // namespace sylva
