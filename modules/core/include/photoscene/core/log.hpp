// Logging through spdlog. Library code includes this header (not spdlog's) and logs with
// spdlog::info / warn / debug directly; apps call initLogging once. Messages go to stderr so
// stdout stays free for command output.
#pragma once

#include <spdlog/spdlog.h>
#include <string>

// Build time: every spdlog call with arguments formats through fmt's detail::vformat_to<char>,
// which fmt 9's headers define without an explicit-instantiation declaration, so each
// translation unit that logs compiled the whole formatting engine again (about 5 s at -O3 per
// file; 15 s for a unity batch of the pipeline's stages). libfmt compiles and exports that
// instantiation (format.cc); declaring it extern here makes every caller link to it instead.
// Same code, same output. GCC only: clang mangles this signature's dependent
// `std::is_same<...>::value` differently from the GCC that built libfmt, so a clang build (the
// sanitizers) would not find the symbol; it instantiates as before.
#if defined(FMT_VERSION) && FMT_VERSION >= 90000 && FMT_VERSION < 100000 && \
    !defined(FMT_HEADER_ONLY) && defined(__GNUC__) && !defined(__clang__)
namespace fmt {
FMT_BEGIN_DETAIL_NAMESPACE
extern template FMT_API void vformat_to<char>(
    buffer<char>&, basic_string_view<char>,
    basic_format_args<FMT_BUFFER_CONTEXT(type_identity_t<char>)>, locale_ref);
FMT_END_DETAIL_NAMESPACE
}  // namespace fmt
#endif

namespace ps {

enum class LogLevel { Trace, Debug, Info, Warn, Error, Off };

/// Installs a stderr logger ("[photoscene] [info] message") as spdlog's default. Idempotent.
void initLogging(LogLevel level = LogLevel::Info);
void setLogLevel(LogLevel level);
/// Parses "trace|debug|info|warn|error|off"; throws ps::Exception otherwise.
LogLevel parseLogLevel(const std::string& name);

}  // namespace ps
