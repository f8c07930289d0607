#include "ui/pipeline/staged_output.h"

#include <nlohmann/json.hpp>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "ui/pipeline/option_registry.h"

namespace sylva {

namespace fs = std::filesystem;

void CheckOutDirIsFree(const fs::path& out_dir) {
  std::error_code ec;
  SYLVA_CHECK_INPUT(!fs::exists(out_dir, ec) || fs::is_empty(out_dir, ec), out_dir.string())
      << "already exists and is not empty";
}

std::vector<fs::path> WriteStagedOutDir(const fs::path& out_dir, const OptionRegistry& registry,
                                        const WriteOutputs& write) {
  const fs::path target = fs::absolute(out_dir);
  const fs::path staging = TempPathBeside(target);
  std::error_code ec;
  try {
    std::vector<fs::path> paths = write(staging);
    paths.push_back(staging / "options.json");
    AtomicWriteString(paths.back(), registry.ToJson(/*only_changed=*/false).dump(2) + "\n");
    if (fs::exists(target, ec)) fs::remove(target);
    fs::rename(staging, target);
    for (fs::path& path : paths) path = target / path.filename();
    return paths;
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
}

}  // namespace sylva
