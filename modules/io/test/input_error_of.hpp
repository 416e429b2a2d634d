// What the tests of bad input share (io and scene): run a call, return the message of the
// ps::InputError it throws, and search it.
#pragma once

#include <exception>
#include <string>

#include "photoscene/core/error.hpp"

namespace ps::test {

/// Runs f, expects ps::InputError, returns its message ("NO EXCEPTION" or "WRONG EXCEPTION
/// TYPE: ..." otherwise, so that a check on the message fails and shows why).
template <typename F>
std::string inputErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("WRONG EXCEPTION TYPE: ") + e.what();
  }
  return "NO EXCEPTION";
}

inline bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace ps::test
