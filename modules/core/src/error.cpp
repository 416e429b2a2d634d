#include "photoscene/core/error.hpp"

namespace ps {

namespace {
std::string withLocation(const std::string& message, const char* file, int line,
                         const char* func) {
  std::ostringstream os;
  os << message << " (" << (file ? file : "?") << ":" << line;
  if (func) os << " in " << func;
  os << ")";
  return os.str();
}

std::string inputMessage(const std::string& file, const std::string& where,
                         const std::string& expected) {
  std::string s = file;
  if (!where.empty()) s += ": " + where;
  s += ": " + expected;
  return s;
}
}  // namespace

Exception::Exception(const std::string& message, const char* file, int line, const char* func)
    : std::runtime_error(withLocation(message, file, line, func)),
      message_(message),
      file_(file ? file : ""),
      line_(line) {}

InputError::InputError(const std::string& file, const std::string& where,
                       const std::string& expected)
    : std::runtime_error(inputMessage(file, where, expected)),
      file_(file),
      where_(where),
      expected_(expected) {}

namespace detail {
void throwCheckFailure(const std::string& message, const char* file, int line, const char* func) {
  throw Exception(message, file, line, func);
}
}  // namespace detail

}  // namespace ps
