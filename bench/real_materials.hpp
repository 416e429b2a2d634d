// The photographed materials of ../shared/data that the real-texture benchmarks run on, and the
// decoding of their normal maps (shared by ps_bench_real_textures and ps_bench_graph_coverage).
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ps::bench {

struct RealMaterial {
  std::string name, category;
  std::filesystem::path albedo, normal, roughness;  ///< empty when absent
  bool normalDirectX = false;  ///< the normal map's green channel points down (DirectX)
  double sizeM = 0;            ///< physical size of one map period in metres (0: unknown)
};

/// Every entry of `data`/textures/cc0/manifest.json in its order (its category, maps, normal
/// convention and physical size), then the 1k maps of `data`/textures/polyhaven
/// (`<stem>_diff_1k.jpg`, `_nor_gl_1k.jpg`, `_rough_1k.jpg`; OpenGL normals) in name order, named
/// `polyhaven1k_<stem>`, their category the first of concrete, tile, wood, plaster, stone, brick,
/// metal, fabric, carpet in the stem (a stem with none is left out). Throws ps::InputError naming
/// the manifest and the key when the manifest cannot be read or an entry lacks its name, category
/// or an albedo map.
std::vector<RealMaterial> listRealMaterials(const std::filesystem::path& data);

/// A tangent-space normal map read as unit OpenGL normals (CV_32FC3, RGB = xyz), resized to
/// `size` x `size` (INTER_AREA on the encoded values); a one-channel file is taken as grey, a
/// DirectX map's y is flipped and z is kept at least 1e-3 (no normal below the surface). Throws
/// ps::InputError when the file cannot be read.
cv::Mat loadNormalMap(const std::filesystem::path& file, bool directX, int size);

/// 64-bit FNV-1a of `s`: the fixed hash behind the split and the cases' random streams.
uint64_t fnv1a(const std::string& s);
/// The yardstick's half of a material: "tune" or "check", by the parity of fnv1a(name).
std::string splitOf(const std::string& name);

}  // namespace ps::bench
