#include "reconstruct/registration/loose_setup_io.h"

#include <set>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

constexpr const char* kFormat = "sylva-loose-cameras";
constexpr int kVersion = 1;

// Refuses keys outside `allowed` (a misspelt optional key would otherwise be
// silently ignored).
void CheckKeys(const JsonCursor& object, const std::set<std::string>& allowed) {
  if (!object.IsObject()) object.Fail("expected an object");
  for (const auto& item : object.value().items()) {
    if (allowed.count(item.key()) == 0) {
      std::string list;
      for (const std::string& key : allowed) list += (list.empty() ? "" : ", ") + key;
      object.Fail("unknown key '" + item.key() + "' (allowed: " + list + ")");
    }
  }
}

double OptionalDouble(const JsonCursor& object, const std::string& key, double fallback) {
  return object.Has(key) ? object[key].AsDouble() : fallback;
}

// A value that must be > 0 when given.
double OptionalPositive(const JsonCursor& object, const std::string& key) {
  if (!object.Has(key)) return 0.0;
  const double value = object[key].AsDouble();
  if (!(value > 0)) object[key].Fail(key + " must be positive, got " + std::to_string(value));
  return value;
}

LoosePhoto ParsePhoto(const JsonCursor& json) {
  CheckKeys(json, {"name", "azimuth_deg", "elevation_deg", "roll_deg", "projection",
                   "focal_length_px", "focal_length_35mm", "distance"});
  LoosePhoto photo;
  photo.name = json["name"].AsString();
  if (photo.name.empty()) json["name"].Fail("a photo name must not be empty");
  photo.azimuth_deg = json["azimuth_deg"].AsDouble();
  photo.elevation_deg = OptionalDouble(json, "elevation_deg", 0.0);
  photo.roll_deg = OptionalDouble(json, "roll_deg", 0.0);
  const JsonCursor projection = json["projection"];
  const std::string projection_name = projection.AsString();
  if (projection_name != "orthographic" && projection_name != "perspective") {
    projection.Fail("projection must be 'orthographic' or 'perspective', got '" + projection_name +
                    "'");
  }
  photo.projection = ParseLooseProjection(projection_name, json.source());
  photo.focal_length_px = OptionalPositive(json, "focal_length_px");
  photo.focal_length_35mm = OptionalPositive(json, "focal_length_35mm");
  photo.distance = OptionalPositive(json, "distance");
  return photo;
}

LoosePoint ParsePoint(const JsonCursor& json, const LooseSetup& setup) {
  CheckKeys(json, {"name", "seen"});
  LoosePoint point;
  point.name = json["name"].AsString();
  const JsonCursor seen = json["seen"];
  if (!seen.IsObject()) seen.Fail("expected an object {photo name: [x, y], ...}");
  for (const auto& item : seen.value().items()) {
    const JsonCursor position = seen[item.key()];
    const int photo_idx = setup.FindPhoto(item.key());
    if (photo_idx < 0) {
      position.Fail("point '" + point.name + "' is seen in photo '" + item.key() +
                    "', which is not among the photos");
    }
    const std::vector<double> xy = position.AsDoubles(2);
    point.observations.push_back({photo_idx, Eigen::Vector2d(xy[0], xy[1])});
  }
  return point;
}

LooseSetup ParseSetup(const JsonCursor& root) {
  CheckKeys(root, {"format", "version", "tree_height", "units", "photos", "points"});
  if (root.Has("format") && root["format"].AsString() != kFormat) {
    root["format"].Fail(std::string("expected \"") + kFormat + "\"");
  }
  if (root.Has("version") && root["version"].AsInt() != kVersion) {
    root["version"].Fail("unsupported version (this sylva reads version 1)");
  }
  LooseSetup setup;
  setup.source = root.source();
  setup.tree_height = OptionalPositive(root, "tree_height");
  if (root.Has("units")) setup.units = root["units"].AsString();
  const JsonCursor photos = root["photos"];
  for (size_t i = 0; i < photos.Size(); ++i) setup.photos.push_back(ParsePhoto(photos[i]));
  if (root.Has("points")) {
    const JsonCursor points = root["points"];
    for (size_t i = 0; i < points.Size(); ++i) {
      setup.points.push_back(ParsePoint(points[i], setup));
    }
  }
  return setup;
}

}  // namespace

LooseSetup ParseLooseSetup(const std::string& text, const std::string& source) {
  const Json json = ParseJson(text, source);
  LooseSetup setup = ParseSetup(JsonCursor(json, source));
  setup.Check();
  return setup;
}

LooseSetup ReadLooseSetup(const std::filesystem::path& path) {
  return ParseLooseSetup(ReadFileToString(path), path.string());
}

void WriteLooseSetup(const std::filesystem::path& path, const LooseSetup& setup) {
  Json json = {{"format", kFormat}, {"version", kVersion}, {"units", setup.units}};
  if (setup.tree_height > 0) json["tree_height"] = setup.tree_height;
  json["photos"] = Json::array();
  for (const LoosePhoto& photo : setup.photos) {
    Json entry = {{"name", photo.name},
                  {"azimuth_deg", photo.azimuth_deg},
                  {"elevation_deg", photo.elevation_deg},
                  {"roll_deg", photo.roll_deg},
                  {"projection", LooseProjectionName(photo.projection)}};
    if (photo.focal_length_px > 0) entry["focal_length_px"] = photo.focal_length_px;
    if (photo.focal_length_35mm > 0) entry["focal_length_35mm"] = photo.focal_length_35mm;
    if (photo.distance > 0) entry["distance"] = photo.distance;
    json["photos"].push_back(entry);
  }
  json["points"] = Json::array();
  for (const LoosePoint& point : setup.points) {
    Json seen = Json::object();
    for (const LooseObservation& observation : point.observations) {
      const Eigen::Vector2d& p = observation.point_in_image;
      seen[setup.photos.at(observation.photo_idx).name] = {p.x(), p.y()};
    }
    json["points"].push_back({{"name", point.name}, {"seen", seen}});
  }
  WriteJsonFile(path, json);
}

}  // namespace sylva
