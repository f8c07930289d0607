// The sylva commands. Each returns the process exit code; errors are thrown
// and turned into exit codes by main().
#ifndef SYLVA_UI_CLI_COMMANDS_H_
#define SYLVA_UI_CLI_COMMANDS_H_

namespace sylva {

// Exit codes.
constexpr int kExitOk = 0;
constexpr int kExitError = 1;        // a failure inside sylva
constexpr int kExitBadInput = 2;     // bad files, options or arguments
constexpr int kExitCancelled = 130;  // interrupted (as shells report SIGINT)

// Dispatches argv[1] to a command.
int RunCommandLine(int argc, const char* const* argv);

}  // namespace sylva

#endif  // SYLVA_UI_CLI_COMMANDS_H_
