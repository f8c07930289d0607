// Fuzz target: a project's settings file, PROJECT/sylva.json
// (ui/pipeline/project.h), opened and its saved options applied to the
// option registry and checked, as `sylva run` does.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz/fuzz_util.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/pipeline_options.h"
#include "ui/pipeline/project.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sylva;
  const std::filesystem::path root = fuzz::WorkDir() / "project";
  std::filesystem::create_directories(root);
  fuzz::WriteBytes(root / "sylva.json",
                   std::string_view(reinterpret_cast<const char*>(data), size));
  try {
    const Project project = Project::Open(root);
    PipelineOptions options;
    OptionRegistry registry;
    RegisterPipelineOptions(&options, &registry);
    project.ApplySavedOptions(&registry);
    options.Check();
  } catch (const InputError&) {
  }
  return 0;
}
