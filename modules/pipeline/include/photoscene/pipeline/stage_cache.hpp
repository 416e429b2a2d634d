// On-disk cache of pipeline stage results, keyed by a hash of everything a stage reads.
//
// Every stage unit has a 64-bit key, derived by the stage runner from what the stage declares it
// reads (scene.json keys, file contents, options, upstream stage keys), and looks for
// `<folder>/<stage>-<key>.bin`. A hit is loaded instead of recomputed; a miss runs
// the stage and stores its result atomically (temporary name + rename), so an interrupted run
// never leaves a half-written cache entry. A file that fails to read (truncated, older format) is
// treated as a miss. Keys chain: a stage's key includes its upstream stages' keys, so changing an
// input redoes exactly the stages that depend on it.
//
//   ps::Archive a;  a.put(3.5);  a.putMat(mask);
//   cache.store("fit-floor", key, a);
//   if (auto r = cache.load("fit-floor", key)) { double x = r->get<double>(); cv::Mat m = r->getMat(); }
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/core/rng.hpp"

namespace ps {

/// A flat binary record of trivially copyable values, strings, vectors and cv::Mats.
class Archive {
 public:
  template <typename T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    // resize + memcpy, not insert: gcc 12 -O3 misreads the inlined insert of a local's bytes as
    // an overflow (-Wstringop-overflow)
    const size_t at = bytes_.size();
    bytes_.resize(at + sizeof(T));
    std::memcpy(bytes_.data() + at, &v, sizeof(T));
  }
  void putString(const std::string& s);
  template <typename T>
  void putVector(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<uint64_t>(v.size());
    const auto* p = reinterpret_cast<const char*>(v.data());
    bytes_.insert(bytes_.end(), p, p + v.size() * sizeof(T));
  }
  void putMat(const cv::Mat& m);  ///< any type; empty Mats round-trip as empty

  template <typename T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    read(&v, sizeof(T));
    return v;
  }
  std::string getString();
  template <typename T>
  std::vector<T> getVector() {
    const uint64_t n = get<uint64_t>();
    checkRemaining(n * sizeof(T));
    std::vector<T> v(n);
    read(v.data(), n * sizeof(T));
    return v;
  }
  cv::Mat getMat();

  const std::vector<char>& bytes() const { return bytes_; }
  std::vector<char>& bytes() { return bytes_; }
  bool atEnd() const { return pos_ == bytes_.size(); }

 private:
  void read(void* dst, size_t n);
  void checkRemaining(size_t n) const;
  std::vector<char> bytes_;
  size_t pos_ = 0;
};

class StageCache {
 public:
  /// @param folder where entries live (created on the first store); empty = caching disabled
  explicit StageCache(std::filesystem::path folder);
  /// The entry of `stage` for `key`, or nothing (missing, unreadable or of another format).
  std::optional<Archive> load(const std::string& stage, uint64_t key) const;
  /// Stores an entry atomically; an older entry of the same stage with another key is removed.
  void store(const std::string& stage, uint64_t key, const Archive& archive) const;
  std::filesystem::path entryPath(const std::string& stage, uint64_t key) const;
  bool enabled() const { return !folder_.empty(); }

 private:
  std::filesystem::path folder_;
};

/// Hash of a file's bytes (0 when it cannot be read).
uint64_t hashFile(const std::filesystem::path& path);
/// Hash of a cv::Mat's type, size and pixels.
void hashMat(Hasher& h, const cv::Mat& m);

}  // namespace ps
