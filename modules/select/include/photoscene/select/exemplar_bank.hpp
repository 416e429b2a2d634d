// Graph selection by k-nearest neighbours (paper section 3.2, "Material graph selection").
//
// The exemplar bank holds, for every library graph, `drawsPerGraph` random parameter draws, each
// rendered in a canonical setting (a flat patch, frontal, under one white key light plus ambient,
// at each of `uvScales` texture repeats and a random in-plane rotation) and reduced to its
// lighting-invariant texture key (features module). A FLANN index over the keys answers queries;
// the k = 21 nearest exemplars vote for their graph with weight 1 / distance, as the paper does.
//
// The bank is built once per library content: it is cached in a versioned file keyed by the
// library's content hash and the bank options, and later runs load it in milliseconds.
//
//   ps::GraphLibrary lib = ps::GraphLibrary::load();
//   ps::ExemplarBank bank = ps::ExemplarBank::loadOrBuild(lib, {}, cacheFolder);
//   ps::GraphChoice choice = bank.select(ps::computeTextureKey(photo, partMask), 21);
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/features/texture_descriptor.hpp"
#include "photoscene/graph/graph_library.hpp"
#include "photoscene/select/knn_index.hpp"

namespace ps {

struct ExemplarBankOptions {
  int drawsPerGraph = 10;                     ///< N random draws per graph (the paper: 10)
  float spread = 0.6f;                        ///< MaterialGraph::randomValues spread
  int mapSize = 256;                          ///< graph evaluation size
  int renderSize = 96;                        ///< canonical patch size (pixels)
  std::vector<float> uvScales = {2.0f, 4.0f}; ///< texture repeats across the patch
  uint64_t seed = 0;
  KnnIndexType indexType = KnnIndexType::KdTree;
  /// Project keys with linear discriminant analysis learned on the bank itself (classes =
  /// graphs): distances then discount the variation a graph shows across its own draws, scales
  /// and rotations, and stress what tells graphs apart. No outside data is used.
  bool discriminantProjection = true;
  TextureKeyOptions key;
  bool IsValid(std::string* error) const;
  /// Hash of everything that changes the bank's content.
  uint64_t hash() const;
};

/// Renders material maps on a frontal, flat patch: t = R(rotation) * (repeats * uv), uv in
/// [0, 1]^2 across the patch, Lambert + ambient under a white key light from the upper left
/// (light direction fixed in the patch frame), supersampled 2 x 2.
/// @param maps albedo (CV_32FC3) and normal (CV_32FC3) at least
/// @param lightColor multiplies the image (lighting color and level)
/// @return CV_32FC3 linear RGB, size x size
cv::Mat renderCanonicalPatch(const MaterialMaps& maps, int size, float repeats, float rotationDeg,
                             const cv::Vec3f& lightColor = cv::Vec3f(1, 1, 1));

struct Exemplar {
  int graph = 0;   ///< index into ExemplarBank::graphNames()
  int draw = 0;
  float uvScale = 1;
  float rotationDeg = 0;
};

struct GraphVote {
  std::string graph;
  std::string category;
  double weight = 0;  ///< sum of 1 / distance of the neighbours voting for it
  int count = 0;
};

struct GraphChoice {
  std::string graph, category;
  std::vector<GraphVote> votes;        ///< sorted by weight, largest first
  std::vector<GraphVote> categoryVotes;
  std::vector<int> neighbours;         ///< exemplar rows, nearest first
  std::vector<float> distances;
};

class ExemplarBank {
 public:
  /// Renders and describes every exemplar (parallel over graphs). Deterministic for a seed.
  static ExemplarBank build(const GraphLibrary& library, const ExemplarBankOptions& options = {});
  /// The cached bank in `cacheFolder` when its file matches the library and options (format
  /// version, library content hash, options hash), else builds and saves it (atomically).
  static ExemplarBank loadOrBuild(const GraphLibrary& library, const ExemplarBankOptions& options,
                                  const std::filesystem::path& cacheFolder, bool* loadedFromCache = nullptr);
  /// The cache file name for a library and options.
  static std::string cacheFileName(const GraphLibrary& library, const ExemplarBankOptions& options);

  void save(const std::filesystem::path& file) const;
  /// Loads a saved bank; std::nullopt-like empty result (rows() == 0) when the file is missing,
  /// of another version or made for another library/options.
  static ExemplarBank load(const std::filesystem::path& file, uint64_t libraryHash, const ExemplarBankOptions& options);

  ExemplarBank(ExemplarBank&&) noexcept;
  ExemplarBank& operator=(ExemplarBank&&) noexcept;
  ~ExemplarBank();

  int rows() const { return static_cast<int>(exemplars_.size()); }
  int dim() const { return dim_; }
  const std::vector<std::string>& graphNames() const { return graphNames_; }
  const std::vector<std::string>& categories() const { return categories_; }
  const std::vector<Exemplar>& exemplars() const { return exemplars_; }
  /// Keys as indexed (after the projection when enabled), rows() x indexDim() floats.
  const std::vector<float>& keys() const { return keys_; }
  /// Length of the indexed keys.
  int indexDim() const { return projection_.empty() ? dim_ : projectedDim_; }
  /// Maps a raw texture key (dim() floats) into the indexed space.
  std::vector<float> project(const std::vector<float>& key) const;
  const KnnIndex& index() const { return *index_; }
  double buildSeconds() const { return buildSeconds_; }

  /// k-NN vote over a raw texture key (dim() floats): each of the k nearest exemplars adds
  /// 1 / (distance + 1e-6) to its graph.
  GraphChoice select(const std::vector<float>& key, int k = 21) const;
  /// Rebuilds the index with another type (for the benchmark).
  void rebuildIndex(KnnIndexType type);

 private:
  ExemplarBank() = default;
  void learnProjection();
  std::vector<std::string> graphNames_, categories_;
  std::vector<Exemplar> exemplars_;
  std::vector<float> keys_;
  int dim_ = 0;
  double buildSeconds_ = 0;
  uint64_t libraryHash_ = 0, optionsHash_ = 0;
  std::vector<float> projection_;  ///< dim_ x projectedDim_, row-major; empty: identity
  int projectedDim_ = 0;
  std::unique_ptr<KnnIndex> index_;
};

/// Parts smaller than this many pixels get the homogeneous material: `pixelsAt320x240` at
/// 320 x 240, scaled with the image's pixel count (the paper's small-part rule).
int homogeneousThreshold(int imageWidth, int imageHeight, int pixelsAt320x240 = 1000);

}  // namespace ps
