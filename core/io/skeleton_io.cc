#include "core/io/skeleton_io.h"

#include <cstdio>
#include <sstream>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

constexpr char kFormatName[] = "sylva-skeleton";
constexpr int kFormatVersion = 1;

SkeletonNode ParseNode(const JsonCursor& json, int num_nodes) {
  SkeletonNode node;
  node.position = json["position"].AsVector3();
  node.radius = json["radius"].AsDouble();
  if (node.radius < 0) json["radius"].Fail("radius must be >= 0");
  node.parent_idx = json["parent"].AsInt();
  if (node.parent_idx < -1 || node.parent_idx >= num_nodes) {
    json["parent"].Fail("parent must be -1 or a node index below " + std::to_string(num_nodes));
  }
  node.order = json["order"].AsInt();
  if (node.order < 0) json["order"].Fail("order must be >= 0");
  if (json.Has("strands")) {
    node.strands = json["strands"].AsInt();
    if (node.strands < 0) json["strands"].Fail("strands must be >= 0");
  }
  return node;
}

}  // namespace

void WriteSkeletonJson(const std::filesystem::path& path, const SkeletonGraph& skeleton,
                       const std::string& units) {
  skeleton.Check();
  Json json;
  json["format"] = kFormatName;
  json["version"] = kFormatVersion;
  json["units"] = units;
  json["radius_source"] = skeleton.radius_source;
  json["nodes"] = Json::array();
  for (const SkeletonNode& node : skeleton.nodes) {
    json["nodes"].push_back(
        {{"position", {node.position.x(), node.position.y(), node.position.z()}},
         {"radius", node.radius},
         {"parent", node.parent_idx},
         {"order", node.order},
         {"strands", node.strands}});
  }
  WriteJsonFile(path, json);
}

SkeletonGraph ReadSkeletonJson(const std::filesystem::path& path, std::string* units) {
  const Json json = ReadJsonFile(path);
  const JsonCursor root(json, path.string());
  if (!root.IsObject()) root.Fail("expected an object");
  if (root["format"].AsString() != kFormatName) root["format"].Fail("expected 'sylva-skeleton'");
  if (root["version"].AsInt() != kFormatVersion) root["version"].Fail("unsupported version");
  if (units != nullptr) *units = root.Has("units") ? root["units"].AsString() : "arbitrary";

  SkeletonGraph skeleton;
  if (root.Has("radius_source")) skeleton.radius_source = root["radius_source"].AsString();
  const JsonCursor nodes = root["nodes"];
  const int num_nodes = static_cast<int>(nodes.Size());
  for (int i = 0; i < num_nodes; ++i) skeleton.nodes.push_back(ParseNode(nodes[i], num_nodes));
  try {
    skeleton.Check();
  } catch (const Error& error) {
    nodes.Fail(error.what());
  }
  return skeleton;
}

namespace {

constexpr char kPlyHeaderTemplate[] =
    "ply\n"
    "format ascii 1.0\n"
    "comment sylva skeleton; units: %s; radius: %s\n"
    "element vertex %d\n"
    "property float x\n"
    "property float y\n"
    "property float z\n"
    "property float radius\n"
    "property int strands\n"
    "property int order\n"
    "element edge %d\n"
    "property list uchar int vertex_indices\n"
    "end_header\n";

// Reads the next non-empty line; InputError at end of file.
std::string NextLine(std::istream& in, const std::string& source, int* line_number) {
  std::string line;
  while (std::getline(in, line)) {
    ++*line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty()) return line;
  }
  SYLVA_INPUT_ERROR(source) << "unexpected end of file after line " << *line_number;
  return line;
}

// Parses the header; returns the vertex and edge counts.
std::pair<int, int> ReadPlyHeader(std::istream& in, const std::string& source, int* line_number,
                                  std::string* radius_source) {
  int vertices = -1, edges = -1;
  SYLVA_CHECK_INPUT(NextLine(in, source, line_number) == "ply", source + ":1") << "not a PLY file";
  for (;;) {
    const std::string line = NextLine(in, source, line_number);
    const std::string where = source + ":" + std::to_string(*line_number);
    if (line == "end_header") break;
    std::istringstream words(line);
    std::string keyword, name;
    words >> keyword;
    if (keyword == "format") {
      words >> name;
      SYLVA_CHECK_INPUT(name == "ascii", where) << "only ASCII skeleton PLY files are read";
    } else if (keyword == "element") {
      int count = -1;
      words >> name >> count;
      SYLVA_CHECK_INPUT(count >= 0, where) << "bad element count";
      if (name == "vertex") vertices = count;
      if (name == "edge") edges = count;
    } else if (keyword == "comment") {
      const size_t at = line.find("radius: ");
      if (at != std::string::npos) *radius_source = line.substr(at + 8);
    }
  }
  SYLVA_CHECK_INPUT(vertices >= 0 && edges >= 0, source) << "needs vertex and edge elements";
  return {vertices, edges};
}

}  // namespace

void WriteSkeletonPly(const std::filesystem::path& path, const SkeletonGraph& skeleton,
                      const std::string& units) {
  skeleton.Check();
  const int num_edges = skeleton.NumNodes() - (skeleton.NumNodes() > 0 ? 1 : 0);
  char header[1024];
  std::snprintf(header, sizeof(header), kPlyHeaderTemplate, units.c_str(),
                skeleton.radius_source.c_str(), skeleton.NumNodes(), num_edges);
  std::ostringstream out;
  out << header;
  char line[256];
  for (const SkeletonNode& node : skeleton.nodes) {
    std::snprintf(line, sizeof(line), "%.9g %.9g %.9g %.9g %d %d\n", node.position.x(),
                  node.position.y(), node.position.z(), node.radius, node.strands, node.order);
    out << line;
  }
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    if (skeleton.nodes[i].parent_idx >= 0)
      out << "2 " << i << " " << skeleton.nodes[i].parent_idx << "\n";
  }
  AtomicWriteString(path, out.str());
}

SkeletonGraph ReadSkeletonPly(const std::filesystem::path& path) {
  const std::string source = path.string();
  std::istringstream in(ReadFileToString(path));
  int line_number = 0;
  SkeletonGraph skeleton;
  const auto [num_vertices, num_edges] =
      ReadPlyHeader(in, source, &line_number, &skeleton.radius_source);
  for (int i = 0; i < num_vertices; ++i) {
    std::istringstream words(NextLine(in, source, &line_number));
    SkeletonNode node;
    words >> node.position.x() >> node.position.y() >> node.position.z() >> node.radius >>
        node.strands >> node.order;
    SYLVA_CHECK_INPUT(!words.fail(), source + ":" + std::to_string(line_number))
        << "expected x y z radius strands order";
    skeleton.nodes.push_back(node);
  }
  for (int e = 0; e < num_edges; ++e) {
    std::istringstream words(NextLine(in, source, &line_number));
    int count = 0, child = -1, parent = -1;
    words >> count >> child >> parent;
    const std::string where = source + ":" + std::to_string(line_number);
    SYLVA_CHECK_INPUT(!words.fail() && count == 2, where) << "expected '2 child parent'";
    SYLVA_CHECK_INPUT(child >= 0 && child < num_vertices && parent >= 0 && parent < num_vertices,
                      where)
        << "vertex index out of range";
    skeleton.nodes[child].parent_idx = parent;
  }
  try {
    skeleton.Check();
  } catch (const Error& error) {
    SYLVA_INPUT_ERROR(source) << "not a rooted tree: " << error.what();
  }
  return skeleton;
}

}  // namespace sylva
