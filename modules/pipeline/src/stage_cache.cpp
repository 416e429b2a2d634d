#include "photoscene/pipeline/stage_cache.hpp"

#include <cstring>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include "photoscene/core/log.hpp"

#include "photoscene/core/error.hpp"
#include "photoscene/io/files.hpp"

namespace ps {

namespace fs = std::filesystem;

namespace {
constexpr uint64_t kMagic = 0x31454843535050ULL;  // "PPSCHE1"
constexpr uint32_t kFormat = 1;
}  // namespace

void Archive::putString(const std::string& s) {
  put<uint64_t>(s.size());
  bytes_.insert(bytes_.end(), s.begin(), s.end());
}

void Archive::putMat(const cv::Mat& m) {
  const cv::Mat c = m.isContinuous() ? m : m.clone();
  put<int32_t>(c.rows);
  put<int32_t>(c.cols);
  put<int32_t>(c.type());
  const size_t n = c.total() * c.elemSize();
  const auto* p = reinterpret_cast<const char*>(c.data);
  if (n) bytes_.insert(bytes_.end(), p, p + n);
}

std::string Archive::getString() {
  const uint64_t n = get<uint64_t>();
  checkRemaining(n);
  std::string s(bytes_.data() + pos_, n);
  pos_ += n;
  return s;
}

cv::Mat Archive::getMat() {
  const int rows = get<int32_t>(), cols = get<int32_t>(), type = get<int32_t>();
  PS_Check(rows >= 0 && cols >= 0 && (rows == 0) == (cols == 0), "archive: bad cv::Mat header");
  if (rows == 0) return cv::Mat();
  cv::Mat m(rows, cols, type);
  read(m.data, m.total() * m.elemSize());
  return m;
}

void Archive::read(void* dst, size_t n) {
  checkRemaining(n);
  std::memcpy(dst, bytes_.data() + pos_, n);
  pos_ += n;
}

void Archive::checkRemaining(size_t n) const {
  PS_Check(n <= bytes_.size() - pos_, "archive: truncated entry");
}

StageCache::StageCache(fs::path folder) : folder_(std::move(folder)) {}

fs::path StageCache::entryPath(const std::string& stage, uint64_t key) const {
  return folder_ / fmt::format("{}-{:016x}.bin", stage, key);
}

std::optional<Archive> StageCache::load(const std::string& stage, uint64_t key) const {
  if (!enabled()) return std::nullopt;
  const fs::path path = entryPath(stage, key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  Archive a;
  a.bytes().assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  try {
    if (a.get<uint64_t>() != kMagic || a.get<uint32_t>() != kFormat || a.get<uint64_t>() != key ||
        a.getString() != stage)
      return std::nullopt;
    const std::vector<char> payload = a.getVector<char>();
    if (!a.atEnd()) return std::nullopt;
    Archive r;
    r.bytes() = payload;
    return r;
  } catch (const Exception&) {
    spdlog::warn("cache entry {} is unreadable; recomputing", path.string());
    return std::nullopt;
  }
}

void StageCache::store(const std::string& stage, uint64_t key, const Archive& archive) const {
  if (!enabled()) return;
  fs::create_directories(folder_);
  Archive a;
  a.put(kMagic);
  a.put(kFormat);
  a.put(key);
  a.putString(stage);
  a.putVector(archive.bytes());
  const fs::path path = entryPath(stage, key);
  io::writeAtomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(a.bytes().data(), static_cast<std::streamsize>(a.bytes().size()));
    PS_Check(static_cast<bool>(out), "cannot write cache entry " + tmp.string());
  });
  // one entry per stage: drop the entries of older keys
  const std::string prefix = stage + "-";
  for (const auto& e : fs::directory_iterator(folder_)) {
    const std::string name = e.path().filename().string();
    if (e.path() != path && name.size() == prefix.size() + 20 && name.rfind(prefix, 0) == 0 &&
        name.substr(name.size() - 4) == ".bin") {
      std::error_code ec;
      fs::remove(e.path(), ec);
    }
  }
}

uint64_t hashFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return 0;
  Hasher h;
  std::vector<char> buf(1 << 16);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    h.add(buf.data(), static_cast<size_t>(in.gcount()));
  }
  return h.digest();
}

void hashMat(Hasher& h, const cv::Mat& m) {
  h.add(m.rows).add(m.cols).add(m.type());
  if (m.empty()) return;
  if (m.isContinuous()) {
    h.add(m.data, m.total() * m.elemSize());
  } else {
    for (int y = 0; y < m.rows; ++y) h.add(m.ptr(y), m.cols * m.elemSize());
  }
}

}  // namespace ps
