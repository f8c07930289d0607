// Fuzz target: L-system grammar files (sketch/lsystem.h), parsed and
// derived for two steps when the string stays small.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "core/util/random.h"
#include "fuzz/fuzz_util.h"
#include "sketch/lsystem.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".lsys", [](const std::filesystem::path& path) {
    using namespace sylva;
    const LsystemGrammar grammar = LsystemGrammar::Read(path);
    RandomEngine random(1);
    LsystemString string = grammar.axiom();
    for (int step = 0; step < 2 && string.Size() < 10000; ++step) {
      string = DeriveStep(grammar, string, nullptr, &random);
    }
    (void)grammar.ToText(string);
  });
}
