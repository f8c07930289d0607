#include "core/io/json_util.h"

#include <cmath>
#include <limits>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {

Json ParseJson(const std::string& text, const std::string& source) {
  try {
    return Json::parse(text);
  } catch (const Json::exception& error) {
    // A syntax error (parse_error) or a number too large for a double
    // (out_of_range.406, "number overflow parsing '1e999'"). nlohmann's
    // message starts with "[json.exception.parse_error.101] ".
    std::string message = error.what();
    const size_t bracket = message.find("] ");
    if (bracket != std::string::npos) message = message.substr(bracket + 2);
    SYLVA_INPUT_ERROR(source) << "invalid JSON: " << message;
  }
  return Json();
}

Json ReadJsonFile(const std::filesystem::path& path) {
  return ParseJson(ReadFileToString(path), path.string());
}

void WriteJsonFile(const std::filesystem::path& path, const Json& json) {
  AtomicWriteString(path, json.dump(2) + "\n");
}

void JsonCursor::Fail(const std::string& message) const {
  throw InputError(source_, "at " + Location() + ": " + message);
}

bool JsonCursor::Has(const std::string& key) const {
  return value_->is_object() && value_->contains(key);
}

JsonCursor JsonCursor::operator[](const std::string& key) const {
  if (!value_->is_object()) Fail("expected an object");
  const auto it = value_->find(key);
  if (it == value_->end()) Fail("missing key '" + key + "'");
  return JsonCursor(*it, source_, pointer_ + "/" + key);
}

JsonCursor JsonCursor::operator[](size_t index) const {
  if (!value_->is_array()) Fail("expected an array");
  if (index >= value_->size()) Fail("index " + std::to_string(index) + " out of range");
  return JsonCursor((*value_)[index], source_, pointer_ + "/" + std::to_string(index));
}

size_t JsonCursor::Size() const {
  if (!value_->is_array()) Fail("expected an array");
  return value_->size();
}

int64_t JsonCursor::AsInt64() const {
  if (value_->is_number_integer()) return value_->get<int64_t>();
  if (value_->is_number_float()) {
    const double d = value_->get<double>();
    if (std::isfinite(d) && d == std::floor(d) && std::abs(d) < 9e15) {
      return static_cast<int64_t>(d);
    }
  }
  Fail("expected an integer");
}

int JsonCursor::AsInt() const {
  const int64_t v = AsInt64();
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) {
    Fail("integer out of range");
  }
  return static_cast<int>(v);
}

double JsonCursor::AsDouble() const {
  if (!value_->is_number()) Fail("expected a number");
  const double d = value_->get<double>();
  if (!std::isfinite(d)) Fail("expected a finite number");
  return d;
}

bool JsonCursor::AsBool() const {
  if (!value_->is_boolean()) Fail("expected true or false");
  return value_->get<bool>();
}

std::string JsonCursor::AsString() const {
  if (!value_->is_string()) Fail("expected a string");
  return value_->get<std::string>();
}

std::vector<double> JsonCursor::AsDoubles(size_t expected_size) const {
  const size_t n = Size();
  if (expected_size > 0 && n != expected_size) {
    Fail("expected " + std::to_string(expected_size) + " numbers, got " + std::to_string(n));
  }
  std::vector<double> values;
  for (size_t i = 0; i < n; ++i) values.push_back((*this)[i].AsDouble());
  return values;
}

Eigen::Vector3d JsonCursor::AsVector3() const {
  const std::vector<double> v = AsDoubles(3);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

void CheckJsonFormat(const JsonCursor& root, const std::string& format, int version) {
  if (!root.IsObject()) root.Fail("expected an object");
  if (root["format"].AsString() != format) root["format"].Fail("expected '" + format + "'");
  const int found = root["version"].AsInt();
  if (found != version) {
    root["version"].Fail("unsupported version " + std::to_string(found) + " (this sylva reads " +
                         std::to_string(version) + ")");
  }
}

}  // namespace sylva
