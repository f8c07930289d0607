#include "core/io/skeleton_io.h"

#include "core/io/json_util.h"
#include "core/util/check.h"

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

}  // namespace sylva
