// Errors: ps::Exception for broken invariants, ps::InputError for bad user input.
//
// The library never calls exit(); only apps turn exceptions into exit codes:
//   ps::InputError  -> exit 2 (the message names the file, the key or line, and what was expected)
//   anything else   -> exit 1
//
// Example:
//   PS_Assert(mask.type() == CV_8UC1);
//   PS_CheckEQ(photo.size(), segments.size(), "segments must have the photo's size");
//   throw ps::InputError(path, "views[0].camera.fx", "a positive number, got -3");
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace ps {

/// An invariant of the program failed (a bug or an unexpected state), with the source location.
class Exception : public std::runtime_error {
 public:
  Exception(const std::string& message, const char* file, int line, const char* func);
  /// The message without the source location.
  const std::string& message() const { return message_; }
  const std::string& sourceFile() const { return file_; }
  int sourceLine() const { return line_; }

 private:
  std::string message_;
  std::string file_;
  int line_ = 0;
};

/// Bad input from the user: a missing or malformed file, a wrong key, an inconsistent value.
/// what() is "<file>: <where>: <expected>", e.g.
/// "scene.json: views[0].camera.world_to_camera: expected a rigid transform (R^T R = I, det R = 1)".
class InputError : public std::runtime_error {
 public:
  /// @param file      the file at fault (as the user named it, or absolute)
  /// @param where     the key path ("views[0].camera.fx"), "line 12", or empty
  /// @param expected  what was expected and what was found
  InputError(const std::string& file, const std::string& where, const std::string& expected);
  const std::string& file() const { return file_; }
  const std::string& where() const { return where_; }
  const std::string& expected() const { return expected_; }

 private:
  std::string file_, where_, expected_;
};

namespace detail {
[[noreturn]] void throwCheckFailure(const std::string& message, const char* file, int line,
                                    const char* func);

template <typename A, typename B>
[[noreturn]] void throwCheckBinary(const char* exprA, const char* op, const char* exprB, const A& a,
                                   const B& b, const std::string& msg, const char* file, int line,
                                   const char* func) {
  std::ostringstream os;
  os << "check failed: " << exprA << " " << op << " " << exprB << " (" << a << " vs " << b << ")";
  if (!msg.empty()) os << ": " << msg;
  throwCheckFailure(os.str(), file, line, func);
}
}  // namespace detail

}  // namespace ps

/// Throws ps::Exception with the expression text and the source location when expr is false.
#define PS_Assert(expr)                                                                     \
  do {                                                                                      \
    if (!(expr))                                                                            \
      ::ps::detail::throwCheckFailure("assertion failed: " #expr, __FILE__, __LINE__,      \
                                      __func__);                                            \
  } while (0)

/// Throws ps::Exception when expr is false, with a message.
#define PS_Check(expr, msg)                                                                 \
  do {                                                                                      \
    if (!(expr)) {                                                                          \
      std::ostringstream ps_check_os_;                                                      \
      ps_check_os_ << "check failed: " #expr ": " << msg;                                   \
      ::ps::detail::throwCheckFailure(ps_check_os_.str(), __FILE__, __LINE__, __func__);    \
    }                                                                                       \
  } while (0)

#define PS_CHECK_BINARY_(a, op, b, msg)                                                     \
  do {                                                                                      \
    const auto& ps_a_ = (a);                                                                \
    const auto& ps_b_ = (b);                                                                \
    if (!(ps_a_ op ps_b_)) {                                                                \
      std::ostringstream ps_msg_os_;                                                        \
      ps_msg_os_ << msg;                                                                    \
      ::ps::detail::throwCheckBinary(#a, #op, #b, ps_a_, ps_b_, ps_msg_os_.str(), __FILE__, \
                                     __LINE__, __func__);                                   \
    }                                                                                       \
  } while (0)

/// Binary checks that print both values on failure: "check failed: a == b (3 vs 4): msg".
#define PS_CheckEQ(a, b, msg) PS_CHECK_BINARY_(a, ==, b, msg)
#define PS_CheckNE(a, b, msg) PS_CHECK_BINARY_(a, !=, b, msg)
#define PS_CheckLT(a, b, msg) PS_CHECK_BINARY_(a, <, b, msg)
#define PS_CheckLE(a, b, msg) PS_CHECK_BINARY_(a, <=, b, msg)
#define PS_CheckGT(a, b, msg) PS_CHECK_BINARY_(a, >, b, msg)
#define PS_CheckGE(a, b, msg) PS_CHECK_BINARY_(a, >=, b, msg)
