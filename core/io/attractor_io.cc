#include "core/io/attractor_io.h"

#include <sstream>
#include <vector>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

constexpr char kFormatName[] = "sylva-attractor-graph";
constexpr int kFormatVersion = 1;

// A JSON number as nlohmann writes it: the shortest text that reads back to
// the same double.
std::string JsonNumber(double value) { return Json(value).dump(); }

int ParsePositiveSize(const JsonCursor& json) {
  const int size = json.AsInt();
  if (size <= 0) json.Fail("must be a positive number of pixels, got " + std::to_string(size));
  return size;
}

std::vector<AttractorNode> ParseNodes(const JsonCursor& json) {
  std::vector<AttractorNode> nodes(json.Size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const std::vector<double> xy = json[i].AsDoubles(2);
    nodes[i].position = Eigen::Vector2d(xy[0], xy[1]);
  }
  return nodes;
}

// Sets the parents from [child, parent] pairs, rejecting indices out of
// range, self loops and a second parent for one node.
void ParseEdges(const JsonCursor& json, std::vector<AttractorNode>* nodes) {
  const int num_nodes = static_cast<int>(nodes->size());
  std::vector<int> edge_of_child(nodes->size(), -1);
  for (size_t e = 0; e < json.Size(); ++e) {
    const JsonCursor edge = json[e];
    if (edge.Size() != 2) edge.Fail("expected [child, parent]");
    const int child = edge[0].AsInt();
    const int parent = edge[1].AsInt();
    for (const int index : {child, parent}) {
      if (index < 0 || index >= num_nodes) {
        edge.Fail("node index " + std::to_string(index) + " out of range (" +
                  std::to_string(num_nodes) + " nodes)");
      }
    }
    if (child == parent) edge.Fail("node " + std::to_string(child) + " is its own parent");
    if (edge_of_child[child] >= 0) {
      edge.Fail("node " + std::to_string(child) + " has a second parent (first in edge " +
                std::to_string(edge_of_child[child]) + ")");
    }
    edge_of_child[child] = static_cast<int>(e);
    (*nodes)[child].parent_idx = parent;
  }
}

}  // namespace

void WriteAttractorGraphJson(const std::filesystem::path& path, const AttractorGraph2D& graph,
                             const std::string& image_name) {
  try {
    graph.Check(path.string());
  } catch (const InputError& error) {
    throw Error("refusing to write an invalid attractor graph: " + std::string(error.what()));
  }
  // Written by hand rather than with Json::dump(2) so that every node and
  // edge takes one line, which keeps the file easy to read and edit.
  std::ostringstream out;
  out << "{\n  \"format\": \"" << kFormatName << "\",\n  \"version\": " << kFormatVersion
      << ",\n  \"image\": " << Json(image_name).dump() << ",\n  \"width\": " << graph.width
      << ",\n  \"height\": " << graph.height << ",\n  \"source\": " << Json(graph.source).dump()
      << ",\n  \"root\": " << graph.root << ",\n  \"nodes\": [";
  for (int i = 0; i < graph.NumNodes(); ++i) {
    const Eigen::Vector2d& p = graph.nodes[i].position;
    out << (i > 0 ? ",\n    [" : "\n    [") << JsonNumber(p.x()) << ", " << JsonNumber(p.y())
        << "]";
  }
  out << (graph.IsEmpty() ? "],\n  \"edges\": [" : "\n  ],\n  \"edges\": [");
  bool first = true;
  for (int i = 0; i < graph.NumNodes(); ++i) {
    if (graph.nodes[i].parent_idx < 0) continue;
    out << (first ? "\n    [" : ",\n    [") << i << ", " << graph.nodes[i].parent_idx << "]";
    first = false;
  }
  out << (first ? "]\n}\n" : "\n  ]\n}\n");
  AtomicWriteString(path, out.str());
}

AttractorGraph2D ReadAttractorGraphJson(const std::filesystem::path& path,
                                        std::string* image_name) {
  const Json json = ReadJsonFile(path);
  const JsonCursor top(json, path.string());
  CheckJsonFormat(top, kFormatName, kFormatVersion);
  const std::string image = top["image"].AsString();
  if (image_name != nullptr) *image_name = image;

  AttractorGraph2D graph;
  graph.width = ParsePositiveSize(top["width"]);
  graph.height = ParsePositiveSize(top["height"]);
  graph.source = top.Has("source") ? top["source"].AsString() : "unknown";
  graph.nodes = ParseNodes(top["nodes"]);
  ParseEdges(top["edges"], &graph.nodes);
  graph.root = top["root"].AsInt();
  const bool root_ok = graph.IsEmpty() ? graph.root == -1
                                       : graph.root >= 0 && graph.root < graph.NumNodes() &&
                                             graph.nodes[graph.root].parent_idx < 0;
  if (!root_ok) {
    top["root"].Fail(graph.IsEmpty() ? "must be -1: there are no nodes"
                                     : "must be the index of a node without a parent, got " +
                                           std::to_string(graph.root));
  }
  try {
    graph.Check(path.string());
  } catch (const InputError& error) {
    top["edges"].Fail(error.message());  // the only problem left: a cycle
  }
  return graph;
}

}  // namespace sylva
