#include "ui/pipeline/option_registry.h"

#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "core/util/check.h"

namespace sylva {
namespace {

std::string Trim(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t") - begin + 1);
}

double ParseDouble(const std::string& text) {
  const std::string t = Trim(text);
  double value = 0;
  const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (error != std::errc() || end != t.data() + t.size() || t.empty() || !std::isfinite(value)) {
    throw std::invalid_argument("expected a number, got '" + text + "'");
  }
  return value;
}

template <typename Integer>
Integer ParseInteger(const std::string& text) {
  const std::string t = Trim(text);
  Integer value = 0;
  const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (error != std::errc() || end != t.data() + t.size() || t.empty()) {
    throw std::invalid_argument("expected an integer, got '" + text + "'");
  }
  return value;
}

bool ParseBool(const std::string& text) {
  const std::string t = Trim(text);
  if (t == "true" || t == "1" || t == "yes" || t == "on") return true;
  if (t == "false" || t == "0" || t == "no" || t == "off") return false;
  throw std::invalid_argument("expected true or false, got '" + text + "'");
}

std::vector<double> ParseNumberList(const std::string& text) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) values.push_back(ParseDouble(item));
  return values;
}

Box3d ParseBox(const std::string& text) {
  if (Trim(text) == "auto" || Trim(text).empty()) return Box3d();
  const std::vector<double> values = ParseNumberList(text);
  if (values.size() != 6) {
    throw std::invalid_argument("expected 'auto' or six numbers x0,y0,z0,x1,y1,z1, got '" + text +
                                "'");
  }
  const Box3d box(Eigen::Vector3d(values[0], values[1], values[2]),
                  Eigen::Vector3d(values[3], values[4], values[5]));
  if (!((box.max() - box.min()).array() > 0).all()) {
    throw std::invalid_argument("box maximum must exceed its minimum on every axis");
  }
  return box;
}

Eigen::Vector3d ParsePoint(const std::string& text) {
  if (Trim(text) == "auto" || Trim(text).empty()) return Eigen::Vector3d::Constant(NAN);
  const std::vector<double> values = ParseNumberList(text);
  if (values.size() != 3) {
    throw std::invalid_argument("expected 'auto' or three numbers x,y,z, got '" + text + "'");
  }
  return Eigen::Vector3d(values[0], values[1], values[2]);
}

std::string FormatPoint(const Eigen::Vector3d& point) {
  if (!point.allFinite()) return "auto";
  return FormatDouble(point.x()) + "," + FormatDouble(point.y()) + "," + FormatDouble(point.z());
}

std::string FormatBox(const Box3d& box) {
  if (box.isEmpty()) return "auto";
  std::string text;
  for (int i = 0; i < 6; ++i) {
    text += (i ? "," : "") + FormatDouble(i < 3 ? box.min()[i] : box.max()[i - 3]);
  }
  return text;
}

std::pair<std::string, std::string> SplitKey(const std::string& key) {
  const size_t dot = key.find('.');
  return {key.substr(0, dot), dot == std::string::npos ? "" : key.substr(dot + 1)};
}

}  // namespace

std::string FormatDouble(double value) {
  char buffer[64];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  SYLVA_CHECK(error == std::errc());
  return std::string(buffer, end);
}

void OptionRegistry::Add(Entry entry) {
  SYLVA_CHECK(!Has(entry.key)) << "option " << entry.key << " registered twice";
  SYLVA_CHECK(!SplitKey(entry.key).second.empty()) << "option key needs a section: " << entry.key;
  entry.default_text = entry.get();
  entries_.push_back(std::move(entry));
}

void OptionRegistry::AddInt(const std::string& key, int* value, const std::string& unit,
                            const std::string& help) {
  Add({key, "int", unit, help, "", [value] { return std::to_string(*value); },
       [value](const std::string& t) { *value = ParseInteger<int>(t); }});
}

void OptionRegistry::AddUint64(const std::string& key, uint64_t* value, const std::string& unit,
                               const std::string& help) {
  Add({key, "uint64", unit, help, "", [value] { return std::to_string(*value); },
       [value](const std::string& t) { *value = ParseInteger<uint64_t>(t); }});
}

void OptionRegistry::AddDouble(const std::string& key, double* value, const std::string& unit,
                               const std::string& help) {
  Add({key, "float", unit, help, "", [value] { return FormatDouble(*value); },
       [value](const std::string& t) { *value = ParseDouble(t); }});
}

void OptionRegistry::AddBool(const std::string& key, bool* value, const std::string& help) {
  Add({key, "bool", "", help, "", [value] { return std::string(*value ? "true" : "false"); },
       [value](const std::string& t) { *value = ParseBool(t); }});
}

void OptionRegistry::AddString(const std::string& key, std::string* value,
                               const std::string& help) {
  Add({key, "string", "", help, "", [value] { return *value; },
       [value](const std::string& t) { *value = t; }});
}

void OptionRegistry::AddBox(const std::string& key, Box3d* value, const std::string& unit,
                            const std::string& help) {
  Add({key, "box", unit, help, "", [value] { return FormatBox(*value); },
       [value](const std::string& t) { *value = ParseBox(t); }});
}

void OptionRegistry::AddPoint(const std::string& key, Eigen::Vector3d* value,
                              const std::string& unit, const std::string& help) {
  Add({key, "point", unit, help, "", [value] { return FormatPoint(*value); },
       [value](const std::string& t) { *value = ParsePoint(t); }});
}

const OptionRegistry::Entry* OptionRegistry::Find(const std::string& key) const {
  for (const Entry& entry : entries_) {
    if (entry.key == key) return &entry;
  }
  return nullptr;
}

std::string OptionRegistry::Get(const std::string& key) const {
  const Entry* entry = Find(key);
  SYLVA_CHECK(entry != nullptr) << "unknown option " << key;
  return entry->get();
}

void OptionRegistry::Set(const std::string& key, const std::string& text,
                         const std::string& source) {
  const Entry* entry = Find(key);
  SYLVA_CHECK_INPUT(entry != nullptr, source)
      << "unknown option '" << key << "' (see 'sylva help options')";
  try {
    entry->set(text);
  } catch (const std::invalid_argument& error) {
    SYLVA_INPUT_ERROR(source) << "option " << key << ": " << error.what();
  } catch (const std::out_of_range&) {
    SYLVA_INPUT_ERROR(source) << "option " << key << ": value out of range";
  }
}

void OptionRegistry::SetFromJson(const nlohmann::json& options, const std::string& source) {
  SYLVA_CHECK_INPUT(options.is_object(), source) << "'options' must be an object";
  for (const auto& [section, fields] : options.items()) {
    SYLVA_CHECK_INPUT(fields.is_object(), source)
        << "options section '" << section << "' must be an object";
    for (const auto& [field, value] : fields.items()) {
      const std::string key = section + "." + field;
      Set(key, value.is_string() ? value.get<std::string>() : value.dump(), source);
    }
  }
}

nlohmann::json OptionRegistry::ToJson(bool only_changed) const {
  nlohmann::json json = nlohmann::json::object();
  for (const Entry& entry : entries_) {
    const std::string text = entry.get();
    if (only_changed && text == entry.default_text) continue;
    const auto [section, field] = SplitKey(entry.key);
    nlohmann::json& slot = json[section][field];
    if (entry.type == "int" || entry.type == "uint64") {
      slot = nlohmann::json::parse(text);
    } else if (entry.type == "float") {
      slot = std::stod(text);
    } else if (entry.type == "bool") {
      slot = text == "true";
    } else {
      slot = text;
    }
  }
  return json;
}

std::string OptionRegistry::Help(const std::vector<std::string>& sections) const {
  std::ostringstream out;
  std::string current_section;
  for (const Entry& entry : entries_) {
    const std::string section = SplitKey(entry.key).first;
    if (!sections.empty() &&
        std::find(sections.begin(), sections.end(), section) == sections.end()) {
      continue;
    }
    if (section != current_section) {
      out << (current_section.empty() ? "" : "\n") << section << ":\n";
      current_section = section;
    }
    out << "  --" << entry.key << "=<" << entry.type << ">  (default " << entry.default_text;
    if (!entry.unit.empty()) out << ", " << entry.unit;
    out << ")\n      " << entry.help << "\n";
  }
  return out.str();
}

}  // namespace sylva
