// Logging to stderr and a throttled progress line for long solves.
#pragma once

#include <chrono>
#include <string>

namespace ttz {

// Verbosity threshold for Log(): 0 errors only, 1 warnings, 2 info (default), 3 debug.
void SetLogLevel(int level);
int LogLevel();

enum class LogKind { kError = 0, kWarning = 1, kInfo = 2, kDebug = 3 };

// Writes "tool: [warning: ]message" on one line of stderr when `kind` passes the threshold.
void Log(LogKind kind, const std::string& message);
void SetLogTool(const std::string& tool_name);

// Prints "label: iteration K, cost C, elapsed T s" at most once a second, and only after the first
// second, so short solves stay quiet and long ones show that they are alive.
class Progress {
 public:
  explicit Progress(std::string label);
  void Update(int iteration, double cost);
  double ElapsedSeconds() const;

 private:
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
};

}  // namespace ttz
