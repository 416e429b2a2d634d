#include "photoscene/io/uri.hpp"

#include <cctype>
#include <cstdio>
#include <cstring>

namespace ps::io {

namespace fs = std::filesystem;

std::string relativeUri(const fs::path& path, const fs::path& base) {
  std::error_code ec;
  fs::path rel = fs::relative(fs::absolute(path), fs::absolute(base), ec);
  if (ec || rel.empty()) rel = fs::absolute(path);
  std::string out;
  for (unsigned char c : rel.generic_string()) {
    if (std::isalnum(c) || std::strchr("-._~/!$&'()*+,;=:@", c)) {
      out += static_cast<char>(c);
    } else {
      char buf[4];
      std::snprintf(buf, sizeof(buf), "%%%02X", c);
      out += buf;
    }
  }
  return out;
}

}  // namespace ps::io
