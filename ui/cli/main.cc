// The one sylva binary: sylva <command> [arguments]. See 'sylva help'.
#include "ui/cli/commands.h"

int main(int argc, char** argv) { return sylva::RunCommandLine(argc, argv); }
