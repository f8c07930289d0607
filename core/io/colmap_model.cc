#include "core/io/colmap_model.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <set>
#include <string_view>
#include <unordered_set>
#include <utility>
#include <vector>

#include "core/util/check.h"
#include "core/util/file_util.h"

// File layouts (COLMAP 3.8, src/base/reconstruction.cc). Text files: one
// record per line, fields separated by spaces, '#' starts a comment line.
//   cameras.txt   CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]
//   images.txt    IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME
//                 POINTS2D[] as (X Y POINT3D_ID), on the next line (may be empty)
//   points3D.txt  POINT3D_ID X Y Z R G B ERROR TRACK[] as (IMAGE_ID POINT2D_IDX)
// Binary files are little-endian, each a uint64 record count then records:
//   cameras.bin   uint32 camera_id, int32 model_id, uint64 width, uint64 height,
//                 double params[num_params(model_id)]
//   images.bin    uint32 image_id, double qw qx qy qz tx ty tz, uint32 camera_id,
//                 NUL-terminated name, uint64 num_points2D,
//                 num_points2D x (double x, double y, uint64 point3D_id)
//   points3D.bin  uint64 point3D_id, double x y z, uint8 r g b, double error,
//                 uint64 track_length, track_length x (uint32 image_id, uint32 point2D_idx)

namespace sylva {
namespace {

constexpr char kCamerasText[] = "cameras.txt";
constexpr char kImagesText[] = "images.txt";
constexpr char kPointsText[] = "points3D.txt";
constexpr char kCamerasBinary[] = "cameras.bin";
constexpr char kImagesBinary[] = "images.bin";
constexpr char kPointsBinary[] = "points3D.bin";

// COLMAP's camera and image ids are uint32 and point ids uint64; sylva holds
// them as int and int64_t, so larger ids are rejected.
constexpr int64_t kMaxId = std::numeric_limits<int>::max();
constexpr int64_t kMaxPointId = std::numeric_limits<int64_t>::max();
constexpr int64_t kMaxUint32 = std::numeric_limits<uint32_t>::max();
// Image sizes are held as int.
constexpr int64_t kMaxImageSize = std::numeric_limits<int>::max();
// A quaternion shorter than this is not a rotation.
constexpr double kMinQuaternionNorm = 1e-12;

// Smallest size in bytes of one binary record, to reject absurd counts
// before allocating or looping.
constexpr size_t kMinCameraRecordBytes = 4 + 4 + 8 + 8 + 3 * 8;
constexpr size_t kMinImageRecordBytes = 4 + 7 * 8 + 4 + 1 + 8;
constexpr size_t kPoint2DBytes = 8 + 8 + 8;
constexpr size_t kMinPointRecordBytes = 8 + 3 * 8 + 3 + 8 + 8;
constexpr size_t kTrackElementBytes = 4 + 4;

// ---------------------------------------------------------------------------
// Model assembly, shared by the text and binary readers.

// Collects a model's records and checks each as it is added. Add* return why
// a record was rejected, or "" if it was added, so that each reader can report
// the problem at its own location (line or record).
class ModelBuilder {
 public:
  std::string AddCamera(int camera_id, const Camera& camera);
  std::string AddView(int image_id, const std::string& name, int camera_id,
                      const Eigen::Quaterniond& rotation, const Eigen::Vector3d& translation);
  std::string AddPoint(const Point3D& point);

  // The model with views and points sorted by id; `images_source` names the
  // images file for ImageSet::Check.
  ImageSet Finish(const std::string& images_source);

 private:
  ImageSet image_set_;
  std::set<int> image_ids_;
  std::set<std::string> names_;
  std::unordered_set<int64_t> point_ids_;
};

std::string ModelBuilder::AddCamera(int camera_id, const Camera& camera) {
  try {
    camera.Check("");
  } catch (const InputError& error) {
    return error.message();
  }
  if (!image_set_.cameras.emplace(camera_id, camera).second) {
    return "duplicate CAMERA_ID " + std::to_string(camera_id);
  }
  return "";
}

std::string ModelBuilder::AddView(int image_id, const std::string& name, int camera_id,
                                  const Eigen::Quaterniond& rotation,
                                  const Eigen::Vector3d& translation) {
  if (!rotation.coeffs().allFinite() || !translation.allFinite()) return "pose is not finite";
  if (rotation.norm() < kMinQuaternionNorm) return "quaternion QW QX QY QZ has zero length";
  if (name.empty()) return "image has no NAME";
  if (image_set_.cameras.count(camera_id) == 0) {
    return "CAMERA_ID " + std::to_string(camera_id) + " is not in the cameras file";
  }
  if (!image_ids_.insert(image_id).second) return "duplicate IMAGE_ID " + std::to_string(image_id);
  if (!names_.insert(name).second) return "duplicate image NAME '" + name + "'";
  View view;
  view.image_id = image_id;
  view.name = name;
  view.camera_id = camera_id;
  view.cam_from_world = Rigid3d(rotation, translation);
  image_set_.views.push_back(std::move(view));
  return "";
}

std::string ModelBuilder::AddPoint(const Point3D& point) {
  if (!point.position.allFinite()) return "point position is not finite";
  if (!std::isfinite(point.error)) return "point ERROR is not finite";
  if (!point_ids_.insert(point.point3d_id).second) {
    return "duplicate POINT3D_ID " + std::to_string(point.point3d_id);
  }
  image_set_.points.push_back(point);
  return "";
}

ImageSet ModelBuilder::Finish(const std::string& images_source) {
  std::sort(image_set_.views.begin(), image_set_.views.end(),
            [](const View& a, const View& b) { return a.image_id < b.image_id; });
  std::sort(image_set_.points.begin(), image_set_.points.end(),
            [](const Point3D& a, const Point3D& b) { return a.point3d_id < b.point3d_id; });
  image_set_.Check(images_source);
  return std::move(image_set_);
}

// ---------------------------------------------------------------------------
// Text reading.

// One line of a text file: where it is, and its whitespace-separated fields
// (views into the reader's buffer). Parse errors name "path:line".
struct TextLine {
  const std::string* path = nullptr;
  int number = 0;  // 1-based
  std::vector<std::string_view> fields;

  std::string Source() const { return *path + ":" + std::to_string(number); }
  // Field `i` as an integer in [min, max], or as a finite number.
  int64_t Integer(size_t i, const char* what, int64_t min, int64_t max) const;
  double Number(size_t i, const char* what) const;
  // Throws InputError at this line unless `problem` is empty.
  void Expect(const std::string& problem) const {
    SYLVA_CHECK_INPUT(problem.empty(), Source()) << problem;
  }
};

// `field` in quotes for an error message, control bytes escaped as \xNN.
std::string Quoted(std::string_view field) {
  std::string quoted = "'";
  for (const char c : field) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte != 0x7f) {
      quoted += c;
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      quoted += {'\\', 'x', kHex[byte >> 4], kHex[byte & 15]};
    }
  }
  return quoted + "'";
}

int64_t TextLine::Integer(size_t i, const char* what, int64_t min, int64_t max) const {
  const std::string_view field = fields.at(i);
  int64_t value = 0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  SYLVA_CHECK_INPUT(error != std::errc::invalid_argument && end == field.data() + field.size(),
                    Source())
      << what << " must be an integer, got " << Quoted(field);
  SYLVA_CHECK_INPUT(error == std::errc() && value >= min && value <= max, Source())
      << what << " must be in [" << min << ", " << max << "], got " << field;
  return value;
}

double TextLine::Number(size_t i, const char* what) const {
  const std::string_view field = fields.at(i);
  double value = 0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  SYLVA_CHECK_INPUT(
      error == std::errc() && end == field.data() + field.size() && std::isfinite(value), Source())
      << what << " must be a finite number, got " << Quoted(field);
  return value;
}

// Reads a text file line by line, as COLMAP does: leading and trailing
// whitespace (including a Windows '\r') is ignored.
class TextReader {
 public:
  explicit TextReader(const fs::path& path) : path_(path.string()), text_(ReadFileToString(path)) {
    constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
    if (std::string_view(text_).substr(0, kUtf8Bom.size()) == kUtf8Bom) pos_ = kUtf8Bom.size();
  }

  // The next line, whatever it holds; false at the end of the file.
  bool NextLine(TextLine* line);
  // The next line that is neither blank nor a comment.
  bool NextDataLine(TextLine* line);

 private:
  std::string path_;
  std::string text_;
  size_t pos_ = 0;
  int line_number_ = 0;
};

bool TextReader::NextLine(TextLine* line) {
  if (pos_ >= text_.size()) return false;
  size_t end = text_.find('\n', pos_);
  if (end == std::string::npos) end = text_.size();
  const std::string_view text(text_.data() + pos_, end - pos_);
  pos_ = end + 1;
  line->path = &path_;
  line->number = ++line_number_;
  line->fields.clear();
  constexpr std::string_view kSpace = " \t\r\v\f";
  size_t start = text.find_first_not_of(kSpace);
  while (start != std::string_view::npos) {
    const size_t stop = std::min(text.find_first_of(kSpace, start), text.size());
    line->fields.push_back(text.substr(start, stop - start));
    start = text.find_first_not_of(kSpace, stop);
  }
  return true;
}

bool TextReader::NextDataLine(TextLine* line) {
  while (NextLine(line)) {
    if (!line->fields.empty() && line->fields[0][0] != '#') return true;
  }
  return false;
}

CameraModel ColmapModelFromName(const TextLine& line) {
  const std::string name(line.fields[1]);
  SYLVA_CHECK_INPUT(name != CameraModelName(CameraModel::kOrthographic), line.Source())
      << "ORTHOGRAPHIC is sylva's own camera model; COLMAP models cannot hold it";
  return ParseCameraModel(name, line.Source());
}

void ReadCamerasText(const fs::path& path, ModelBuilder* builder) {
  TextReader reader(path);
  TextLine line;
  while (reader.NextDataLine(&line)) {
    SYLVA_CHECK_INPUT(line.fields.size() >= 4, line.Source())
        << "expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[], got " << line.fields.size()
        << " fields";
    const int camera_id = static_cast<int>(line.Integer(0, "CAMERA_ID", 0, kMaxId));
    const CameraModel model = ColmapModelFromName(line);
    const int width = static_cast<int>(line.Integer(2, "WIDTH", 1, kMaxImageSize));
    const int height = static_cast<int>(line.Integer(3, "HEIGHT", 1, kMaxImageSize));
    std::vector<double> params;
    for (size_t i = 4; i < line.fields.size(); ++i) params.push_back(line.Number(i, "PARAMS"));
    SYLVA_CHECK_INPUT(static_cast<int>(params.size()) == CameraModelNumParams(model), line.Source())
        << CameraModelName(model) << " camera needs " << CameraModelNumParams(model)
        << " parameters, got " << params.size();
    line.Expect(builder->AddCamera(camera_id, Camera(model, width, height, std::move(params))));
  }
}

// Checks the syntax of a POINTS2D line; sylva does not keep observations.
void CheckPoints2DLine(const TextLine& line) {
  SYLVA_CHECK_INPUT(line.fields.size() % 3 == 0, line.Source())
      << "expected the POINTS2D line, X Y POINT3D_ID triples, got " << line.fields.size()
      << " fields (images.txt has two lines per image, the second may be empty)";
  for (size_t i = 0; i < line.fields.size(); i += 3) {
    line.Number(i, "POINTS2D X");
    line.Number(i + 1, "POINTS2D Y");
    line.Integer(i + 2, "POINTS2D POINT3D_ID", -1, kMaxPointId);
  }
}

void ParseImageLine(const TextLine& line, ModelBuilder* builder) {
  SYLVA_CHECK_INPUT(line.fields.size() >= 10, line.Source())
      << "expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME, got " << line.fields.size()
      << " fields";
  SYLVA_CHECK_INPUT(line.fields.size() == 10, line.Source())
      << "expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME, got " << line.fields.size()
      << " fields (COLMAP's text format cannot hold image names with spaces)";
  const int image_id = static_cast<int>(line.Integer(0, "IMAGE_ID", 0, kMaxId));
  const Eigen::Quaterniond rotation(line.Number(1, "QW"), line.Number(2, "QX"),
                                    line.Number(3, "QY"), line.Number(4, "QZ"));
  const Eigen::Vector3d translation(line.Number(5, "TX"), line.Number(6, "TY"),
                                    line.Number(7, "TZ"));
  const int camera_id = static_cast<int>(line.Integer(8, "CAMERA_ID", 0, kMaxId));
  line.Expect(
      builder->AddView(image_id, std::string(line.fields[9]), camera_id, rotation, translation));
}

void ReadImagesText(const fs::path& path, ModelBuilder* builder) {
  TextReader reader(path);
  TextLine line;
  while (reader.NextDataLine(&line)) {
    ParseImageLine(line, builder);
    // The POINTS2D line follows unconditionally; like COLMAP, accept its
    // absence at the very end of the file.
    TextLine points_line;
    if (reader.NextLine(&points_line)) CheckPoints2DLine(points_line);
  }
}

Point3D ParsePointLine(const TextLine& line) {
  SYLVA_CHECK_INPUT(line.fields.size() >= 8 && line.fields.size() % 2 == 0, line.Source())
      << "expected POINT3D_ID X Y Z R G B ERROR then (IMAGE_ID POINT2D_IDX) pairs, got "
      << line.fields.size() << " fields";
  Point3D point;
  point.point3d_id = line.Integer(0, "POINT3D_ID", 0, kMaxPointId);
  point.position = Eigen::Vector3d(line.Number(1, "X"), line.Number(2, "Y"), line.Number(3, "Z"));
  point.color = Eigen::Vector3i(static_cast<int>(line.Integer(4, "R", 0, 255)),
                                static_cast<int>(line.Integer(5, "G", 0, 255)),
                                static_cast<int>(line.Integer(6, "B", 0, 255)));
  point.error = line.Number(7, "ERROR");
  // Tracks are checked for syntax only: sylva does not keep them.
  for (size_t i = 8; i < line.fields.size(); i += 2) {
    line.Integer(i, "TRACK IMAGE_ID", 0, kMaxUint32);
    line.Integer(i + 1, "TRACK POINT2D_IDX", 0, kMaxUint32);
  }
  return point;
}

void ReadPointsText(const fs::path& path, ModelBuilder* builder) {
  TextReader reader(path);
  TextLine line;
  while (reader.NextDataLine(&line)) line.Expect(builder->AddPoint(ParsePointLine(line)));
}

// ---------------------------------------------------------------------------
// Binary reading.

// Reads little-endian values from a whole file held in memory. Every read is
// bounds-checked; errors name the file, the record being read and the offset.
class BinaryReader {
 public:
  explicit BinaryReader(const fs::path& path)
      : source_(path.string()), data_(ReadFileToString(path)) {}

  // Names the record being read in error messages ("image #3").
  void SetRecord(const char* kind, uint64_t index) {
    record_kind_ = kind;
    record_index_ = index;
  }

  uint8_t U8(const char* what) { return static_cast<uint8_t>(LittleEndian(1, what)); }
  uint32_t U32(const char* what) { return static_cast<uint32_t>(LittleEndian(4, what)); }
  int32_t I32(const char* what);
  uint64_t U64(const char* what) { return LittleEndian(8, what); }
  double F64(const char* what);
  // A COLMAP uint32 id that must fit sylva's int.
  int Id(const char* what);
  std::string NulTerminatedString(const char* what);
  // A count of items of at least `min_item_bytes` each, checked against the
  // bytes left in the file.
  uint64_t Count(const char* what, size_t min_item_bytes);
  void Skip(uint64_t num_bytes, const char* what);
  // Throws unless the whole file was read.
  void ExpectEnd();

  // Throws InputError naming the file, the current record and `message`.
  [[noreturn]] void Fail(const std::string& message) const;
  void Expect(const std::string& problem) const {
    if (!problem.empty()) Fail(problem);
  }

 private:
  uint64_t LittleEndian(size_t num_bytes, const char* what);
  void Need(uint64_t num_bytes, const char* what) const;

  std::string source_;
  std::string data_;
  size_t pos_ = 0;
  const char* record_kind_ = nullptr;
  uint64_t record_index_ = 0;
};

void BinaryReader::Fail(const std::string& message) const {
  std::string where;
  if (record_kind_ != nullptr) {
    where = std::string(record_kind_) + " #" + std::to_string(record_index_) + ": ";
  }
  throw InputError(source_, where + message);
}

void BinaryReader::Need(uint64_t num_bytes, const char* what) const {
  if (num_bytes <= data_.size() - pos_) return;
  Fail(std::string("file is truncated: ") + what + " needs " + std::to_string(num_bytes) +
       " bytes at offset " + std::to_string(pos_) + ", but the file has " +
       std::to_string(data_.size()) + " bytes");
}

uint64_t BinaryReader::LittleEndian(size_t num_bytes, const char* what) {
  Need(num_bytes, what);
  uint64_t value = 0;
  for (size_t i = 0; i < num_bytes; ++i) {
    value |= static_cast<uint64_t>(static_cast<unsigned char>(data_[pos_ + i])) << (8 * i);
  }
  pos_ += num_bytes;
  return value;
}

int32_t BinaryReader::I32(const char* what) {
  const uint32_t bits = U32(what);
  int32_t value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

double BinaryReader::F64(const char* what) {
  const uint64_t bits = U64(what);
  double value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

int BinaryReader::Id(const char* what) {
  const uint32_t id = U32(what);
  if (id > kMaxId) Fail(std::string(what) + " " + std::to_string(id) + " is too large");
  return static_cast<int>(id);
}

std::string BinaryReader::NulTerminatedString(const char* what) {
  const size_t end = data_.find('\0', pos_);
  if (end == std::string::npos) {
    Fail(std::string("file is truncated: ") + what + " at offset " + std::to_string(pos_) +
         " has no terminating NUL byte");
  }
  std::string text = data_.substr(pos_, end - pos_);
  pos_ = end + 1;
  return text;
}

uint64_t BinaryReader::Count(const char* what, size_t min_item_bytes) {
  const uint64_t count = U64(what);
  if (count > (data_.size() - pos_) / min_item_bytes) {
    Fail(std::string(what) + " is " + std::to_string(count) + ", but only " +
         std::to_string(data_.size() - pos_) + " bytes follow at offset " + std::to_string(pos_) +
         " (the file is truncated or corrupt)");
  }
  return count;
}

void BinaryReader::Skip(uint64_t num_bytes, const char* what) {
  Need(num_bytes, what);
  pos_ += num_bytes;
}

void BinaryReader::ExpectEnd() {
  record_kind_ = nullptr;
  if (pos_ != data_.size()) {
    Fail(std::to_string(data_.size() - pos_) +
         " unexpected bytes after the last record, at offset " + std::to_string(pos_));
  }
}

void ReadCameraRecord(BinaryReader* reader, ModelBuilder* builder) {
  const int camera_id = reader->Id("CAMERA_ID");
  const int32_t model_id = reader->I32("MODEL_ID");
  const uint64_t width = reader->U64("WIDTH");
  const uint64_t height = reader->U64("HEIGHT");
  CameraModel model = CameraModel::kPinhole;
  try {
    model = CameraModelFromColmapId(model_id, "");
  } catch (const InputError& error) {
    reader->Fail(error.message());
  }
  if (width > kMaxImageSize || height > kMaxImageSize) {
    reader->Fail("image size " + std::to_string(width) + "x" + std::to_string(height) +
                 " is too large");
  }
  std::vector<double> params(CameraModelNumParams(model));
  for (double& param : params) param = reader->F64("PARAMS");
  reader->Expect(builder->AddCamera(
      camera_id, Camera(model, static_cast<int>(width), static_cast<int>(height), params)));
}

void ReadCamerasBinary(const fs::path& path, ModelBuilder* builder) {
  BinaryReader reader(path);
  const uint64_t num_cameras = reader.Count("number of cameras", kMinCameraRecordBytes);
  for (uint64_t i = 0; i < num_cameras; ++i) {
    reader.SetRecord("camera", i);
    ReadCameraRecord(&reader, builder);
  }
  reader.ExpectEnd();
}

void ReadImageRecord(BinaryReader* reader, ModelBuilder* builder) {
  const int image_id = reader->Id("IMAGE_ID");
  double pose[7];
  for (double& value : pose) value = reader->F64("pose");
  const int camera_id = reader->Id("CAMERA_ID");
  const std::string name = reader->NulTerminatedString("NAME");
  const uint64_t num_points2d = reader->Count("number of 2D points", kPoint2DBytes);
  reader->Skip(num_points2d * kPoint2DBytes, "2D points");
  const Eigen::Quaterniond rotation(pose[0], pose[1], pose[2], pose[3]);
  const Eigen::Vector3d translation(pose[4], pose[5], pose[6]);
  reader->Expect(builder->AddView(image_id, name, camera_id, rotation, translation));
}

void ReadImagesBinary(const fs::path& path, ModelBuilder* builder) {
  BinaryReader reader(path);
  const uint64_t num_images = reader.Count("number of images", kMinImageRecordBytes);
  for (uint64_t i = 0; i < num_images; ++i) {
    reader.SetRecord("image", i);
    ReadImageRecord(&reader, builder);
  }
  reader.ExpectEnd();
}

void ReadPointRecord(BinaryReader* reader, ModelBuilder* builder) {
  Point3D point;
  const uint64_t point3d_id = reader->U64("POINT3D_ID");
  if (point3d_id > static_cast<uint64_t>(kMaxPointId)) {
    reader->Fail("POINT3D_ID " + std::to_string(point3d_id) + " is too large");
  }
  point.point3d_id = static_cast<int64_t>(point3d_id);
  for (int k = 0; k < 3; ++k) point.position[k] = reader->F64("XYZ");
  for (int k = 0; k < 3; ++k) point.color[k] = reader->U8("RGB");
  point.error = reader->F64("ERROR");
  const uint64_t track_length = reader->Count("track length", kTrackElementBytes);
  reader->Skip(track_length * kTrackElementBytes, "track");
  reader->Expect(builder->AddPoint(point));
}

void ReadPointsBinary(const fs::path& path, ModelBuilder* builder) {
  BinaryReader reader(path);
  const uint64_t num_points = reader.Count("number of points", kMinPointRecordBytes);
  for (uint64_t i = 0; i < num_points; ++i) {
    reader.SetRecord("point", i);
    ReadPointRecord(&reader, builder);
  }
  reader.ExpectEnd();
}

// ---------------------------------------------------------------------------
// Writing.

// Appends the shortest decimal form that reads back to exactly `value`.
void AppendNumber(double value, std::string* out) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  SYLVA_CHECK(result.ec == std::errc());
  out->append(buffer, result.ptr);
}

// COLMAP's text format splits fields at whitespace; its binary format ends
// names at a NUL byte.
bool CanStoreName(const std::string& name, bool text) {
  if (!text) return name.find('\0') == std::string::npos;
  return std::none_of(name.begin(), name.end(),
                      [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; });
}

// Throws InputError for anything COLMAP's format or our readers would reject,
// before any file is written.
void CheckWritable(const ImageSet& image_set, const fs::path& model_dir, bool text) {
  image_set.Check(model_dir.string());
  const std::string cameras_source = (model_dir / (text ? kCamerasText : kCamerasBinary)).string();
  for (const auto& [camera_id, camera] : image_set.cameras) {
    SYLVA_CHECK_INPUT(!camera.IsOrthographic(), cameras_source)
        << "camera " << camera_id << " is ORTHOGRAPHIC, which COLMAP models cannot hold";
    SYLVA_CHECK_INPUT(camera_id >= 0, cameras_source) << "negative CAMERA_ID " << camera_id;
  }
  const std::string images_source = (model_dir / (text ? kImagesText : kImagesBinary)).string();
  for (const View& view : image_set.views) {
    SYLVA_CHECK_INPUT(view.image_id >= 0, images_source) << "negative IMAGE_ID " << view.image_id;
    SYLVA_CHECK_INPUT(CanStoreName(view.name, text), images_source)
        << "image name '" << view.name << "' cannot be stored: COLMAP's "
        << (text ? "text format splits fields at whitespace" : "binary format ends names at NUL");
  }
  const std::string points_source = (model_dir / (text ? kPointsText : kPointsBinary)).string();
  for (const Point3D& point : image_set.points) {
    SYLVA_CHECK_INPUT(point.point3d_id >= 0, points_source)
        << "negative POINT3D_ID " << point.point3d_id;
    SYLVA_CHECK_INPUT(point.color.minCoeff() >= 0 && point.color.maxCoeff() <= 255, points_source)
        << "point " << point.point3d_id << " has a color outside [0, 255]";
    SYLVA_CHECK_INPUT(point.position.allFinite() && std::isfinite(point.error), points_source)
        << "point " << point.point3d_id << " is not finite";
  }
}

std::string CamerasText(const ImageSet& image_set) {
  std::string out =
      "# Camera list with one line of data per camera:\n"
      "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
      "# Number of cameras: " +
      std::to_string(image_set.cameras.size()) + "\n";
  for (const auto& [camera_id, camera] : image_set.cameras) {
    out += std::to_string(camera_id) + " " + CameraModelName(camera.model()) + " " +
           std::to_string(camera.width()) + " " + std::to_string(camera.height());
    for (double param : camera.params()) {
      out += ' ';
      AppendNumber(param, &out);
    }
    out += '\n';
  }
  return out;
}

std::string ImagesText(const ImageSet& image_set) {
  std::string out =
      "# Image list with two lines of data per image:\n"
      "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
      "# Number of images: " +
      std::to_string(image_set.views.size()) + ", mean observations per image: 0\n";
  for (const View& view : image_set.views) {
    const Eigen::Quaterniond& q = view.cam_from_world.rotation;
    const Eigen::Vector3d& t = view.cam_from_world.translation;
    out += std::to_string(view.image_id);
    for (double value : {q.w(), q.x(), q.y(), q.z(), t.x(), t.y(), t.z()}) {
      out += ' ';
      AppendNumber(value, &out);
    }
    out += " " + std::to_string(view.camera_id) + " " + view.name + "\n\n";  // empty POINTS2D
  }
  return out;
}

std::string PointsText(const ImageSet& image_set) {
  std::string out =
      "# 3D point list with one line of data per point:\n"
      "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
      "# Number of points: " +
      std::to_string(image_set.points.size()) + ", mean track length: 0\n";
  for (const Point3D& point : image_set.points) {
    out += std::to_string(point.point3d_id);
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      AppendNumber(point.position[k], &out);
    }
    for (int k = 0; k < 3; ++k) out += " " + std::to_string(point.color[k]);
    out += ' ';
    AppendNumber(point.error, &out);
    out += '\n';  // empty track
  }
  return out;
}

// Appends little-endian values to a byte string.
class BinaryWriter {
 public:
  void U8(uint8_t value) { LittleEndian(value, 1); }
  void U32(uint32_t value) { LittleEndian(value, 4); }
  void I32(int32_t value) { LittleEndian(static_cast<uint32_t>(value), 4); }
  void U64(uint64_t value) { LittleEndian(value, 8); }
  void F64(double value) {
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof(bits));
    U64(bits);
  }
  void NulTerminatedString(const std::string& text) {
    bytes_.append(text.c_str(), text.size() + 1);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  void LittleEndian(uint64_t value, size_t num_bytes) {
    for (size_t i = 0; i < num_bytes; ++i) bytes_.push_back(static_cast<char>(value >> (8 * i)));
  }

  std::string bytes_;
};

std::string CamerasBinary(const ImageSet& image_set) {
  BinaryWriter out;
  out.U64(image_set.cameras.size());
  for (const auto& [camera_id, camera] : image_set.cameras) {
    out.U32(static_cast<uint32_t>(camera_id));
    out.I32(CameraModelColmapId(camera.model()));
    out.U64(static_cast<uint64_t>(camera.width()));
    out.U64(static_cast<uint64_t>(camera.height()));
    for (double param : camera.params()) out.F64(param);
  }
  return out.bytes();
}

std::string ImagesBinary(const ImageSet& image_set) {
  BinaryWriter out;
  out.U64(image_set.views.size());
  for (const View& view : image_set.views) {
    const Eigen::Quaterniond& q = view.cam_from_world.rotation;
    const Eigen::Vector3d& t = view.cam_from_world.translation;
    out.U32(static_cast<uint32_t>(view.image_id));
    for (double value : {q.w(), q.x(), q.y(), q.z(), t.x(), t.y(), t.z()}) out.F64(value);
    out.U32(static_cast<uint32_t>(view.camera_id));
    out.NulTerminatedString(view.name);
    out.U64(0);  // no 2D points
  }
  return out.bytes();
}

std::string PointsBinary(const ImageSet& image_set) {
  BinaryWriter out;
  out.U64(image_set.points.size());
  for (const Point3D& point : image_set.points) {
    out.U64(static_cast<uint64_t>(point.point3d_id));
    for (int k = 0; k < 3; ++k) out.F64(point.position[k]);
    for (int k = 0; k < 3; ++k) out.U8(static_cast<uint8_t>(point.color[k]));
    out.F64(point.error);
    out.U64(0);  // empty track
  }
  return out.bytes();
}

}  // namespace

ImageSet ReadColmapModel(const fs::path& model_dir) {
  std::error_code ignored;
  if (fs::is_regular_file(model_dir / kCamerasBinary, ignored)) {
    return ReadColmapModelBinary(model_dir);
  }
  return ReadColmapModelText(model_dir);
}

ImageSet ReadColmapModelText(const fs::path& model_dir) {
  ModelBuilder builder;
  ReadCamerasText(model_dir / kCamerasText, &builder);
  ReadImagesText(model_dir / kImagesText, &builder);
  std::error_code ignored;
  if (fs::exists(model_dir / kPointsText, ignored)) {
    ReadPointsText(model_dir / kPointsText, &builder);
  }
  return builder.Finish((model_dir / kImagesText).string());
}

ImageSet ReadColmapModelBinary(const fs::path& model_dir) {
  ModelBuilder builder;
  ReadCamerasBinary(model_dir / kCamerasBinary, &builder);
  ReadImagesBinary(model_dir / kImagesBinary, &builder);
  std::error_code ignored;
  if (fs::exists(model_dir / kPointsBinary, ignored)) {
    ReadPointsBinary(model_dir / kPointsBinary, &builder);
  }
  return builder.Finish((model_dir / kImagesBinary).string());
}

bool IsColmapModelDir(const fs::path& model_dir) {
  std::error_code ignored;
  return fs::is_regular_file(model_dir / kCamerasText, ignored) ||
         fs::is_regular_file(model_dir / kCamerasBinary, ignored);
}

void WriteColmapModelText(const ImageSet& image_set, const fs::path& model_dir) {
  CheckWritable(image_set, model_dir, /*text=*/true);
  AtomicWriteString(model_dir / kCamerasText, CamerasText(image_set));
  AtomicWriteString(model_dir / kImagesText, ImagesText(image_set));
  AtomicWriteString(model_dir / kPointsText, PointsText(image_set));
}

void WriteColmapModelBinary(const ImageSet& image_set, const fs::path& model_dir) {
  CheckWritable(image_set, model_dir, /*text=*/false);
  AtomicWriteString(model_dir / kCamerasBinary, CamerasBinary(image_set));
  AtomicWriteString(model_dir / kImagesBinary, ImagesBinary(image_set));
  AtomicWriteString(model_dir / kPointsBinary, PointsBinary(image_set));
}

}  // namespace sylva
