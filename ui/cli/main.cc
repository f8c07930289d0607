// The one sylva binary: sylva <command> [arguments]. See 'sylva help'.
#include "core/util/memory.h"
#include "ui/cli/commands.h"

int main(int argc, char** argv) {
  sylva::KeepFreedMemoryForReuse();
  return sylva::RunCommandLine(argc, argv);
}
