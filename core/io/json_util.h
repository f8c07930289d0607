// Reading JSON files with errors that name the file and the JSON location.
// Include only in .cc files (nlohmann/json is a heavy header).
#ifndef SYLVA_CORE_IO_JSON_UTIL_H_
#define SYLVA_CORE_IO_JSON_UTIL_H_

#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sylva {

using Json = nlohmann::json;

// Parses a JSON file; throws InputError("FILE: invalid JSON at line L, column
// C: ...") on syntax errors.
Json ReadJsonFile(const std::filesystem::path& path);
Json ParseJson(const std::string& text, const std::string& source);

// Writes pretty-printed JSON atomically.
void WriteJsonFile(const std::filesystem::path& path, const Json& json);

// A read-only view of a JSON value with its location, for validated access:
//   JsonCursor root(json, "cameras.json");
//   int width = root["cameras"][0]["width"].AsInt();
// Any type error or missing key throws InputError("cameras.json: at
// /cameras/0/width: expected an integer").
class JsonCursor {
 public:
  JsonCursor(const Json& value, std::string source, std::string pointer = "")
      : value_(&value), source_(std::move(source)), pointer_(std::move(pointer)) {}

  const Json& value() const { return *value_; }
  const std::string& source() const { return source_; }
  std::string Location() const { return pointer_.empty() ? "/" : pointer_; }

  bool Has(const std::string& key) const;
  JsonCursor operator[](const std::string& key) const;  // required key
  JsonCursor operator[](size_t index) const;            // array element
  size_t Size() const;                                  // array length
  bool IsObject() const { return value_->is_object(); }
  bool IsArray() const { return value_->is_array(); }

  int AsInt() const;
  int64_t AsInt64() const;
  double AsDouble() const;  // finite numbers only
  bool AsBool() const;
  std::string AsString() const;
  std::vector<double> AsDoubles(size_t expected_size = 0) const;  // 0: any size
  Eigen::Vector3d AsVector3() const;

  // Throws InputError at this location with `message`.
  [[noreturn]] void Fail(const std::string& message) const;

 private:
  const Json* value_;
  std::string source_;
  std::string pointer_;
};

// Checks the header of a sylva JSON file: `root` is an object whose
// "format" is `format` and whose "version" is `version`; throws InputError at
// the offending key otherwise.
void CheckJsonFormat(const JsonCursor& root, const std::string& format, int version);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_JSON_UTIL_H_
