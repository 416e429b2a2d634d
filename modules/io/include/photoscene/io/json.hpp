// JSON reading with messages that name the file and the key path.
//
//   auto root = ps::io::readJsonFile("scene.json");
//   ps::io::JsonValue scene(root, "scene.json");
//   double fx = scene["views"][0]["camera"]["fx"].number();
//   // a string there throws ps::InputError:
//   //   "scene.json: views[0].camera.fx: expected a number, got string"
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "photoscene/core/math.hpp"

namespace ps::io {

namespace fs = std::filesystem;

/// Parses JSON text. A syntax error throws ps::InputError(file, "line L, column C", ...).
nlohmann::json parseJson(const std::string& text, const std::string& file);
/// Reads and parses a JSON file (missing file or syntax error: ps::InputError).
nlohmann::json readJsonFile(const fs::path& path);
/// Serializes with 1-space indentation and writes atomically.
void writeJsonFile(const fs::path& path, const nlohmann::json& value);

/// A read-only view of one JSON value that remembers its file and key path.
class JsonValue {
 public:
  JsonValue(const nlohmann::json& value, std::string file, std::string path = "");

  const std::string& file() const { return file_; }
  /// "views[0].camera.fx" (empty at the root).
  const std::string& path() const { return path_; }
  const nlohmann::json& raw() const { return *value_; }

  bool isObject() const { return value_->is_object(); }
  bool isArray() const { return value_->is_array(); }
  bool isNumber() const { return value_->is_number(); }
  bool isString() const { return value_->is_string(); }
  bool has(const std::string& key) const;

  /// Required member of an object (missing: "missing required key").
  JsonValue operator[](const std::string& key) const;
  /// Optional member (absent or null: nullopt).
  std::optional<JsonValue> get(const std::string& key) const;
  /// Array element.
  JsonValue operator[](size_t index) const;
  /// Array size (throws unless an array).
  size_t size() const;
  /// Object keys in document order.
  std::vector<std::string> keys() const;

  /// A finite number.
  double number() const;
  /// A finite number in [lo, hi].
  double number(double lo, double hi) const;
  /// An integer (a number with no fractional part) in [lo, hi].
  int64_t integer(int64_t lo = INT64_MIN, int64_t hi = INT64_MAX) const;
  std::string string() const;
  bool boolean() const;
  /// An array of exactly n finite numbers.
  std::vector<double> numbers(size_t n) const;
  Vec3d vec3() const;
  Vec2d vec2() const;
  /// A 4x4 matrix as 4 rows of 4 numbers.
  Mat4d matrix4() const;

  /// Throws ps::InputError(file, path, "expected " + what + ", got <type>").
  [[noreturn]] void fail(const std::string& what) const;
  /// Throws ps::InputError(file, path, message) with the message as given.
  [[noreturn]] void failMessage(const std::string& message) const;

 private:
  std::string describe() const;
  const nlohmann::json* value_;
  std::string file_, path_;
};

}  // namespace ps::io
