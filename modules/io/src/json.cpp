#include "photoscene/io/json.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "photoscene/core/error.hpp"
#include "photoscene/io/files.hpp"

namespace ps::io {

nlohmann::json parseJson(const std::string& text, const std::string& file) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // Translate the byte offset into a line and column.
    size_t line = 1, column = 1;
    const size_t end = std::min(e.byte == 0 ? 0 : e.byte - 1, text.size());
    for (size_t i = 0; i < end; ++i) {
      if (text[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    std::string what = e.what();
    const auto pos = what.find("syntax error");
    if (pos != std::string::npos) what = what.substr(pos);
    throw InputError(file, "line " + std::to_string(line) + ", column " + std::to_string(column),
                     "JSON " + what);
  } catch (const nlohmann::json::exception& e) {
    // e.g. "number overflow parsing '1e999'": locate the token for the line number
    std::string what = e.what();
    const auto close = what.find("] ");
    if (close != std::string::npos) what = what.substr(close + 2);
    std::string where;
    const auto q0 = what.find('\''), q1 = what.rfind('\'');
    if (q0 != std::string::npos && q1 > q0) {
      const auto at = text.find(what.substr(q0 + 1, q1 - q0 - 1));
      if (at != std::string::npos) {
        const size_t line = 1 + std::count(text.begin(), text.begin() + at, '\n');
        const size_t lineStart = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
        where = "line " + std::to_string(line) + ", column " + std::to_string(at - lineStart + 1);
      }
    }
    throw InputError(file, where, "JSON " + what);
  }
}

nlohmann::json readJsonFile(const fs::path& path) {
  return parseJson(readTextFile(path), path.string());
}

void writeJsonFile(const fs::path& path, const nlohmann::json& value) {
  writeTextFile(path, value.dump(1) + "\n");
}

JsonValue::JsonValue(const nlohmann::json& value, std::string file, std::string path)
    : value_(&value), file_(std::move(file)), path_(std::move(path)) {}

std::string JsonValue::describe() const {
  const auto& v = *value_;
  if (v.is_string()) return "string \"" + v.get<std::string>().substr(0, 40) + "\"";
  if (v.is_number()) {
    std::ostringstream os;
    os << "number " << v.get<double>();
    return os.str();
  }
  return v.type_name();
}

void JsonValue::fail(const std::string& what) const {
  throw InputError(file_, path_.empty() ? "(root)" : path_, "expected " + what + ", got " + describe());
}

void JsonValue::failMessage(const std::string& message) const {
  throw InputError(file_, path_.empty() ? "(root)" : path_, message);
}

bool JsonValue::has(const std::string& key) const {
  return value_->is_object() && value_->contains(key) && !(*value_)[key].is_null();
}

JsonValue JsonValue::operator[](const std::string& key) const {
  if (!value_->is_object()) fail("an object");
  const std::string childPath = path_.empty() ? key : path_ + "." + key;
  auto it = value_->find(key);
  if (it == value_->end() || it->is_null())
    throw InputError(file_, childPath, "missing required key");
  return JsonValue(*it, file_, childPath);
}

std::optional<JsonValue> JsonValue::get(const std::string& key) const {
  if (!value_->is_object()) fail("an object");
  auto it = value_->find(key);
  if (it == value_->end() || it->is_null()) return std::nullopt;
  return JsonValue(*it, file_, path_.empty() ? key : path_ + "." + key);
}

JsonValue JsonValue::operator[](size_t index) const {
  if (!value_->is_array()) fail("an array");
  const std::string childPath = path_ + "[" + std::to_string(index) + "]";
  if (index >= value_->size()) throw InputError(file_, childPath, "missing array element");
  return JsonValue((*value_)[index], file_, childPath);
}

size_t JsonValue::size() const {
  if (!value_->is_array()) fail("an array");
  return value_->size();
}

std::vector<std::string> JsonValue::keys() const {
  if (!value_->is_object()) fail("an object");
  std::vector<std::string> out;
  for (auto it = value_->begin(); it != value_->end(); ++it) out.push_back(it.key());
  return out;
}

double JsonValue::number() const {
  if (!value_->is_number()) fail("a number");
  const double v = value_->get<double>();
  if (!std::isfinite(v)) fail("a finite number");
  return v;
}

double JsonValue::number(double lo, double hi) const {
  const double v = number();
  if (v < lo || v > hi) {
    std::ostringstream os;
    os << "a number in [" << lo << ", " << hi << "]";
    fail(os.str());
  }
  return v;
}

int64_t JsonValue::integer(int64_t lo, int64_t hi) const {
  if (!value_->is_number()) fail("an integer");
  const double d = value_->get<double>();
  if (!std::isfinite(d) || std::floor(d) != d) fail("an integer");
  const int64_t v = value_->is_number_integer() ? value_->get<int64_t>() : static_cast<int64_t>(d);
  if (v < lo || v > hi) {
    std::ostringstream os;
    os << "an integer in [" << lo << ", " << hi << "]";
    fail(os.str());
  }
  return v;
}

std::string JsonValue::string() const {
  if (!value_->is_string()) fail("a string");
  return value_->get<std::string>();
}

bool JsonValue::boolean() const {
  if (!value_->is_boolean()) fail("true or false");
  return value_->get<bool>();
}

std::vector<double> JsonValue::numbers(size_t n) const {
  if (!value_->is_array() || value_->size() != n) fail("an array of " + std::to_string(n) + " numbers");
  std::vector<double> out(n);
  for (size_t i = 0; i < n; ++i) out[i] = (*this)[i].number();
  return out;
}

Vec3d JsonValue::vec3() const {
  const auto v = numbers(3);
  return Vec3d(v[0], v[1], v[2]);
}

Vec2d JsonValue::vec2() const {
  const auto v = numbers(2);
  return Vec2d(v[0], v[1]);
}

Mat4d JsonValue::matrix4() const {
  if (!value_->is_array() || value_->size() != 4) fail("a 4x4 matrix (4 rows of 4 numbers)");
  Mat4d m;
  for (int r = 0; r < 4; ++r) {
    JsonValue row = (*this)[r];
    if (!row.raw().is_array() || row.raw().size() != 4) row.fail("a row of 4 numbers");
    for (int c = 0; c < 4; ++c) m(r, c) = row[c].number();
  }
  return m;
}

}  // namespace ps::io
