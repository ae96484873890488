#include "common/log.h"

#include <cstdio>

namespace ttz {
namespace {
int g_level = 2;
std::string g_tool = "ttz";
}  // namespace

void SetLogLevel(int level) { g_level = level; }
int LogLevel() { return g_level; }
void SetLogTool(const std::string& tool_name) { g_tool = tool_name; }

void Log(LogKind kind, const std::string& message) {
  if (static_cast<int>(kind) > g_level) return;
  const char* prefix = kind == LogKind::kError ? "error: " : kind == LogKind::kWarning ? "warning: " : "";
  std::fprintf(stderr, "%s: %s%s\n", g_tool.c_str(), prefix, message.c_str());
}

Progress::Progress(std::string label)
    : label_(std::move(label)), start_(std::chrono::steady_clock::now()), last_print_(start_) {}

double Progress::ElapsedSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::Update(int iteration, double cost) {
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_print_).count() < 1.0) return;
  last_print_ = now;
  char line[200];
  std::snprintf(line, sizeof line, "%s: iteration %d, cost %.6g, elapsed %.1f s", label_.c_str(),
                iteration, cost, ElapsedSeconds());
  Log(LogKind::kInfo, line);
}

}  // namespace ttz
