#include "photoscene/core/log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>

#include "photoscene/core/error.hpp"

namespace ps {

namespace {
spdlog::level::level_enum toSpd(LogLevel l) {
  switch (l) {
    case LogLevel::Trace: return spdlog::level::trace;
    case LogLevel::Debug: return spdlog::level::debug;
    case LogLevel::Info: return spdlog::level::info;
    case LogLevel::Warn: return spdlog::level::warn;
    case LogLevel::Error: return spdlog::level::err;
    case LogLevel::Off: return spdlog::level::off;
  }
  return spdlog::level::info;
}
}  // namespace

void initLogging(LogLevel level) {
  auto existing = spdlog::get("photoscene");
  if (!existing) {
    auto logger = spdlog::stderr_color_mt("photoscene");
    logger->set_pattern("[photoscene] [%^%l%$] %v");
    spdlog::set_default_logger(logger);
  }
  spdlog::set_level(toSpd(level));
}

void setLogLevel(LogLevel level) { spdlog::set_level(toSpd(level)); }

LogLevel parseLogLevel(const std::string& name) {
  if (name == "trace") return LogLevel::Trace;
  if (name == "debug") return LogLevel::Debug;
  if (name == "info") return LogLevel::Info;
  if (name == "warn") return LogLevel::Warn;
  if (name == "error") return LogLevel::Error;
  if (name == "off") return LogLevel::Off;
  PS_Check(false, "unknown log level '" << name << "'");
  return LogLevel::Info;
}

}  // namespace ps
