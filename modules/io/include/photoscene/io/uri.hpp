// Relative URIs of files (glTF buffer and image URIs, the report's links).
#pragma once

#include <filesystem>
#include <string>

namespace ps::io {

/// `path` relative to the folder `base`, '/'-separated, with every byte that RFC 3986 does not
/// allow in a path segment percent-encoded (a space as %20); the absolute path when the two
/// share no root.
std::string relativeUri(const std::filesystem::path& path, const std::filesystem::path& base);

}  // namespace ps::io
