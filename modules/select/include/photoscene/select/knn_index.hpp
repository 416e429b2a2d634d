// A k-nearest-neighbour index over fixed-length float keys, backed by the standalone FLANN
// library. Kept free of OpenCV types: FLANN's headers must not meet OpenCV's in one translation
// unit (both define a `flann` namespace), so only knn_index.cpp includes <flann/flann.hpp>.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace ps {

enum class KnnIndexType {
  Linear,   ///< exhaustive search (exact)
  KdTree,   ///< randomized kd-trees (4 trees, 128 checks)
  KMeans,   ///< hierarchical k-means tree (branching 16, 128 checks)
};
const char* knnIndexTypeName(KnnIndexType type);

struct KnnResult {
  std::vector<int> index;        ///< row of each neighbour, nearest first
  std::vector<float> distance;   ///< Euclidean distance (not squared)
};

class KnnIndex {
 public:
  /// Builds an index over `rows` keys of `dim` floats (row-major, copied).
  KnnIndex(const std::vector<float>& keys, int rows, int dim, KnnIndexType type = KnnIndexType::KdTree);
  ~KnnIndex();
  KnnIndex(KnnIndex&&) noexcept;
  KnnIndex& operator=(KnnIndex&&) noexcept;

  KnnResult search(const std::vector<float>& query, int k) const;
  int rows() const;
  int dim() const;
  KnnIndexType type() const;
  /// Saves the index structure (FLANN's format); load() needs the same keys.
  void save(const std::string& path) const;
  static KnnIndex load(const std::string& path, const std::vector<float>& keys, int rows, int dim,
                       KnnIndexType type);

 private:
  KnnIndex() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ps
