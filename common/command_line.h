// The main() of every command-line tool: parse the arguments with CLI11, run, and turn what goes
// wrong into one line on stderr and the exit codes of common/error.h.
#pragma once

#include <CLI/CLI.hpp>

#include <exception>
#include <string>

#include "common/error.h"
#include "common/log.h"

namespace ttz {

// Checks of a number option, in place of CLI::PositiveNumber and CLI::NonNegativeNumber, whose
// messages print the whole double range: these say what is expected ("--ds: value -1 is not a
// positive number").
inline CLI::Validator NumberCheck(bool positive) {
  const std::string what = positive ? "positive" : "non-negative";
  return CLI::Validator(
      [positive, what](std::string& text) {
        double x = 0.0;
        if (CLI::detail::lexical_cast(text, x) && (positive ? x > 0.0 : x >= 0.0)) return std::string();
        return "value " + text + " is not a " + what + " number";
      },
      positive ? "POSITIVE" : "NONNEGATIVE");
}
inline const CLI::Validator kPositiveNumber = NumberCheck(true);
inline const CLI::Validator kNonNegativeNumber = NumberCheck(false);

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
