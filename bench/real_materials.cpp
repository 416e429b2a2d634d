#include "real_materials.hpp"

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <set>

#include "photoscene/core/error.hpp"
#include "photoscene/io/json.hpp"
#include "photoscene/io/image_io.hpp"

namespace ps::bench {

namespace fs = std::filesystem;

std::vector<RealMaterial> listRealMaterials(const fs::path& data) {
  std::vector<RealMaterial> out;
  const fs::path cc0 = data / "textures/cc0";
  const fs::path manifestFile = cc0 / "manifest.json";
  const nlohmann::json manifest = io::readJsonFile(manifestFile);
  if (!manifest.is_array()) throw InputError(manifestFile.string(), "", "an array of materials");
  for (size_t i = 0; i < manifest.size(); ++i) {
    const nlohmann::json& e = manifest[i];
    const std::string at = "[" + std::to_string(i) + "]";
    if (!e.is_object() || !e.contains("name") || !e["name"].is_string())
      throw InputError(manifestFile.string(), at + ".name", "a material name");
    RealMaterial m;
    m.name = e["name"].get<std::string>();
    if (!e.contains("category") || !e["category"].is_string())
      throw InputError(manifestFile.string(), m.name + ".category", "a category name");
    m.category = e["category"].get<std::string>();
    std::set<std::string> maps;
    if (e.contains("maps") && e["maps"].is_array())
      for (const auto& x : e["maps"])
        if (x.is_string()) maps.insert(x.get<std::string>());
    const fs::path dir = cc0 / m.name;
    if (!maps.count("albedo"))
      throw InputError(manifestFile.string(), m.name + ".maps", "an albedo map");
    m.albedo = dir / "albedo.jpg";
    if (maps.count("normal")) m.normal = dir / "normal.jpg";
    if (maps.count("roughness")) m.roughness = dir / "roughness.jpg";
    m.normalDirectX = e.contains("normal_convention") && e["normal_convention"] == "directx";
    if (e.contains("physical_size_m") && e["physical_size_m"].is_number())
      m.sizeM = e["physical_size_m"].get<double>();
    out.push_back(m);
  }
  const fs::path ph = data / "textures/polyhaven";
  if (!fs::is_directory(ph)) return out;
  std::vector<std::string> stems;
  const std::string suffix = "_diff_1k.jpg";
  for (const auto& de : fs::directory_iterator(ph)) {
    const std::string fn = de.path().filename().string();
    if (fn.size() > suffix.size() && fn.ends_with(suffix))
      stems.push_back(fn.substr(0, fn.size() - suffix.size()));
  }
  std::sort(stems.begin(), stems.end());
  for (const std::string& stem : stems) {
    RealMaterial m;
    m.name = "polyhaven1k_" + stem;
    m.albedo = ph / (stem + suffix);
    if (fs::exists(ph / (stem + "_nor_gl_1k.jpg"))) m.normal = ph / (stem + "_nor_gl_1k.jpg");
    if (fs::exists(ph / (stem + "_rough_1k.jpg"))) m.roughness = ph / (stem + "_rough_1k.jpg");
    for (const char* c :
         {"concrete", "tile", "wood", "plaster", "stone", "brick", "metal", "fabric", "carpet"})
      if (stem.find(c) != std::string::npos) {
        m.category = c;
        break;
      }
    if (!m.category.empty()) out.push_back(m);
  }
  return out;
}

cv::Mat loadNormalMap(const fs::path& file, bool directX, int size) {
  cv::Mat n = io::readDataImage(file);
  if (n.channels() == 1) cv::cvtColor(n, n, cv::COLOR_GRAY2RGB);
  cv::resize(n, n, {size, size}, 0, 0, cv::INTER_AREA);
  cv::Mat normal;
  n.convertTo(normal, CV_32F, 2.0, -1.0);
  normal.forEach<cv::Vec3f>([directX](cv::Vec3f& v, const int*) {
    if (directX) v[1] = -v[1];
    v[2] = std::max(v[2], 1e-3f);
    v /= static_cast<float>(cv::norm(v));
  });
  return normal;
}

uint64_t fnv1a(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string splitOf(const std::string& name) { return fnv1a(name) % 2 == 0 ? "tune" : "check"; }

}  // namespace ps::bench
