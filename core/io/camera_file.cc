#include "core/io/camera_file.h"

#include <algorithm>

#include "core/io/json_util.h"
#include "core/util/check.h"

namespace sylva {
namespace {

constexpr char kFormatName[] = "sylva-cameras";
constexpr int kFormatVersion = 1;

Camera ParseCamera(const JsonCursor& json) {
  // Errors from the camera's own checks are re-raised at this JSON location.
  try {
    const CameraModel model = ParseCameraModel(json["model"].AsString(), "");
    Camera camera(model, json["width"].AsInt(), json["height"].AsInt(), json["params"].AsDoubles());
    camera.Check("");
    return camera;
  } catch (const InputError& error) {
    if (!error.source().empty()) throw;
    json.Fail(error.message());
  }
}

Rigid3d ParsePose(const JsonCursor& json) {
  if (json.Has("cam_from_world")) {
    const JsonCursor pose = json["cam_from_world"];
    const std::vector<double> q = pose["qvec"].AsDoubles(4);
    const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
    if (rotation.norm() < 1e-12) pose["qvec"].Fail("quaternion has zero length");
    return Rigid3d(rotation, pose["tvec"].AsVector3());
  }
  if (json.Has("look_at")) {
    const JsonCursor look_at = json["look_at"];
    const Eigen::Vector3d center = look_at["center"].AsVector3();
    const Eigen::Vector3d target = look_at["target"].AsVector3();
    const Eigen::Vector3d up =
        look_at.Has("up") ? look_at["up"].AsVector3() : Eigen::Vector3d::UnitZ();
    if ((target - center).norm() < 1e-12) look_at.Fail("center and target coincide");
    if ((target - center).normalized().cross(up.normalized()).norm() < 1e-9) {
      look_at.Fail("viewing direction is parallel to 'up'");
    }
    return LookAt(center, target, up);
  }
  json.Fail("image needs 'cam_from_world' or 'look_at'");
}

}  // namespace

ImageSet ReadCameraFile(const std::filesystem::path& path, std::string* units) {
  const Json json = ReadJsonFile(path);
  const JsonCursor root(json, path.string());
  if (!root.IsObject()) root.Fail("expected an object");
  if (root["format"].AsString() != kFormatName) root["format"].Fail("expected 'sylva-cameras'");
  const int version = root["version"].AsInt();
  if (version != kFormatVersion) root["version"].Fail("unsupported version");
  if (units != nullptr) *units = root.Has("units") ? root["units"].AsString() : "arbitrary";

  ImageSet image_set;
  const JsonCursor cameras = root["cameras"];
  for (size_t i = 0; i < cameras.Size(); ++i) {
    const int camera_id = cameras[i]["camera_id"].AsInt();
    if (!image_set.cameras.emplace(camera_id, ParseCamera(cameras[i])).second) {
      cameras[i].Fail("duplicate camera_id " + std::to_string(camera_id));
    }
  }
  const JsonCursor images = root["images"];
  for (size_t i = 0; i < images.Size(); ++i) {
    View view;
    view.image_id = images[i]["image_id"].AsInt();
    view.name = images[i]["name"].AsString();
    view.camera_id = images[i]["camera_id"].AsInt();
    view.cam_from_world = ParsePose(images[i]);
    image_set.views.push_back(view);
  }
  std::sort(image_set.views.begin(), image_set.views.end(),
            [](const View& a, const View& b) { return a.image_id < b.image_id; });
  image_set.Check(path.string());
  return image_set;
}

void WriteCameraFile(const std::filesystem::path& path, const ImageSet& image_set,
                     const std::string& units) {
  Json json;
  json["format"] = kFormatName;
  json["version"] = kFormatVersion;
  json["units"] = units;
  json["cameras"] = Json::array();
  for (const auto& [camera_id, camera] : image_set.cameras) {
    json["cameras"].push_back({{"camera_id", camera_id},
                               {"model", CameraModelName(camera.model())},
                               {"width", camera.width()},
                               {"height", camera.height()},
                               {"params", camera.params()}});
  }
  json["images"] = Json::array();
  for (const View& view : image_set.views) {
    const Eigen::Quaterniond& q = view.cam_from_world.rotation;
    const Eigen::Vector3d& t = view.cam_from_world.translation;
    json["images"].push_back(
        {{"image_id", view.image_id},
         {"name", view.name},
         {"camera_id", view.camera_id},
         {"cam_from_world",
          {{"qvec", {q.w(), q.x(), q.y(), q.z()}}, {"tvec", {t.x(), t.y(), t.z()}}}}});
  }
  WriteJsonFile(path, json);
}

}  // namespace sylva
