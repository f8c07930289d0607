// Outputs of the one-shot commands (sylva concept, sylva gesture) written
// into OUT_DIR all at once: a killed or failed run leaves no partial folder.
#ifndef SYLVA_UI_PIPELINE_STAGED_OUTPUT_H_
#define SYLVA_UI_PIPELINE_STAGED_OUTPUT_H_

#include <filesystem>
#include <functional>
#include <vector>

namespace sylva {

class OptionRegistry;

// Throws InputError naming `out_dir` if it exists and is not empty (checked
// before the work, so a mistake costs nothing).
void CheckOutDirIsFree(const std::filesystem::path& out_dir);

// Calls write(staging) on a new folder beside `out_dir`, adds options.json
// (every option of `registry`), then renames the folder to `out_dir` (which
// may exist if empty). Returns the written files' paths under `out_dir`. On
// any error the staging folder is removed and the error rethrown.
using WriteOutputs =
    std::function<std::vector<std::filesystem::path>(const std::filesystem::path& staging)>;
std::vector<std::filesystem::path> WriteStagedOutDir(const std::filesystem::path& out_dir,
                                                     const OptionRegistry& registry,
                                                     const WriteOutputs& write);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_STAGED_OUTPUT_H_
