// One registry of options for every front end (COLMAP's OptionManager idea).
//
// Each field of each stage's options struct is registered once, as
// "Section.field", with its unit and a help line. The CLI's --Section.field=
// flags, the project's sylva.json, the saved effective options and the
// desktop app's panels all go through this registry. The registry holds
// pointers into the options structs it was built over: keep them alive.
#ifndef SYLVA_UI_PIPELINE_OPTION_REGISTRY_H_
#define SYLVA_UI_PIPELINE_OPTION_REGISTRY_H_

#include <cstdint>
#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/geometry/box.h"

namespace sylva {

class OptionRegistry {
 public:
  struct Entry {
    std::string key;           // "Density.resolution"
    std::string type;          // "int", "float", "bool", "string", "box", "uint64"
    std::string unit;          // "voxels", "world units", "" ...
    std::string help;          // one line
    std::string default_text;  // value at registration time
    std::function<std::string()> get;
    std::function<void(const std::string&)> set;  // throws std::invalid_argument
  };

  void AddInt(const std::string& key, int* value, const std::string& unit, const std::string& help);
  void AddUint64(const std::string& key, uint64_t* value, const std::string& unit,
                 const std::string& help);
  void AddDouble(const std::string& key, double* value, const std::string& unit,
                 const std::string& help);
  void AddBool(const std::string& key, bool* value, const std::string& help);
  void AddString(const std::string& key, std::string* value, const std::string& help);
  // A box given as "x0,y0,z0,x1,y1,z1", or "auto" for an empty box.
  void AddBox(const std::string& key, Box3d* value, const std::string& unit,
              const std::string& help);
  // A point given as "x,y,z", or "auto" for a point with NaN coordinates.
  void AddPoint(const std::string& key, Eigen::Vector3d* value, const std::string& unit,
                const std::string& help);

  bool Has(const std::string& key) const { return Find(key) != nullptr; }
  const std::vector<Entry>& entries() const { return entries_; }
  std::string Get(const std::string& key) const;

  // Sets from text. Throws InputError(source, "...") for an unknown key or an
  // unparsable value; `source` names where the value came from
  // ("--Density.resolution", "project/sylva.json").
  void Set(const std::string& key, const std::string& text, const std::string& source);

  // {"Density": {"resolution": 64}, ...}; unknown sections/keys are errors.
  void SetFromJson(const nlohmann::json& options, const std::string& source);
  // All options, or only those that differ from their defaults.
  nlohmann::json ToJson(bool only_changed) const;

  // Every option with its type, default, unit and help, grouped by section;
  // only sections in `sections` if not empty.
  std::string Help(const std::vector<std::string>& sections = {}) const;

 private:
  void Add(Entry entry);
  const Entry* Find(const std::string& key) const;

  std::vector<Entry> entries_;
};

// Shortest text that parses back to the same double ("0.1", not "0.10000000000000001").
std::string FormatDouble(double value);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_OPTION_REGISTRY_H_
