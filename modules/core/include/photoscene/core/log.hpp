// Logging through spdlog. Library code logs with spdlog::info / warn / debug directly; apps call
// initLogging once. Messages go to stderr so stdout stays free for command output.
#pragma once

#include <spdlog/spdlog.h>
#include <string>

namespace ps {

enum class LogLevel { Trace, Debug, Info, Warn, Error, Off };

/// Installs a stderr logger ("[photoscene] [info] message") as spdlog's default. Idempotent.
void initLogging(LogLevel level = LogLevel::Info);
void setLogLevel(LogLevel level);
/// Parses "trace|debug|info|warn|error|off"; throws ps::Exception otherwise.
LogLevel parseLogLevel(const std::string& name);

}  // namespace ps
