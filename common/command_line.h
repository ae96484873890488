// The main() of every command-line tool: parse the arguments with CLI11, run, and turn what goes
// wrong into one line on stderr and the exit codes of common/error.h.
#pragma once

#include <CLI/CLI.hpp>

#include <exception>
#include <string>

#include "common/error.h"
#include "common/log.h"

namespace ttz {

// `run()` returns the exit code; an InputError it throws exits kExitBadInput, any other
// exception kExitOther, each after one line on stderr.
template <typename Run>
int RunCommandLine(const std::string& tool, CLI::App& app, int argc, char** argv, Run&& run) {
  SetLogTool(tool);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    Log(LogKind::kError, std::string(e.what()) + " (see " + tool + " --help)");
    return kExitBadInput;
  }
  try {
    return run();
  } catch (const InputError& e) {
    Log(LogKind::kError, e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    Log(LogKind::kError, e.what());
    return kExitOther;
  }
}

}  // namespace ttz
