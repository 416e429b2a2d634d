#include "photoscene/scene/material.hpp"

#include "photoscene/core/log.hpp"

#include <cmath>
#include <fstream>

#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/io/image_io.hpp"

namespace ps {

namespace fs = std::filesystem;

FloatTexture::FloatTexture(const cv::Mat& image) {
  PS_Check(image.type() == CV_32FC1 || image.type() == CV_32FC3,
           "FloatTexture expects CV_32FC1 or CV_32FC3, got " << typeName(image.type()));
  PS_Check(!image.empty(), "empty texture");
  width_ = image.cols;
  height_ = image.rows;
  channels_ = image.channels();
  data_.resize(static_cast<size_t>(width_) * height_ * channels_);
  for (int y = 0; y < height_; ++y) {
    const float* row = image.ptr<float>(y);
    std::copy(row, row + width_ * channels_, data_.data() + static_cast<size_t>(y) * width_ * channels_);
  }
  for (float& v : data_)
    if (!std::isfinite(v)) v = 0.0f;
}

Vec3f FloatTexture::texel(int x, int y) const {
  x = wrapIndex(x, width_);
  y = wrapIndex(y, height_);
  const float* p = data_.data() + (static_cast<size_t>(y) * width_ + x) * channels_;
  return channels_ == 3 ? Vec3f(p[0], p[1], p[2]) : Vec3f(p[0], 0.0f, 0.0f);
}

Vec3f FloatTexture::sample(const Vec2f& t) const {
  if (data_.empty()) return Vec3f::Zero();
  // fractional part without libm calls; NaN / Inf / huge coordinates fall back to 0
  auto frac = [](float v) {
    if (!(std::abs(v) < 8.0e6f)) return 0.0f;
    const float f = v - static_cast<float>(static_cast<int>(v));
    return f < 0 ? f + 1.0f : (f >= 1.0f ? 0.0f : f);
  };
  const float x = frac(t.x()) * width_ - 0.5f, y = (1.0f - frac(t.y())) * height_ - 0.5f;
  // x, y >= -0.5: truncation of (x + 1) is floor(x) + 1
  int x0 = static_cast<int>(x + 1.0f) - 1, y0 = static_cast<int>(y + 1.0f) - 1;
  const float ax = x - x0, ay = y - y0;
  x0 = x0 < 0 ? x0 + width_ : (x0 >= width_ ? x0 - width_ : x0);
  y0 = y0 < 0 ? y0 + height_ : (y0 >= height_ ? y0 - height_ : y0);
  const int x1 = x0 + 1 == width_ ? 0 : x0 + 1, y1 = y0 + 1 == height_ ? 0 : y0 + 1;
  const int c = channels_;
  const float* r0 = data_.data() + static_cast<size_t>(y0) * width_ * c;
  const float* r1 = data_.data() + static_cast<size_t>(y1) * width_ * c;
  const float w00 = (1 - ax) * (1 - ay), w10 = ax * (1 - ay), w01 = (1 - ax) * ay, w11 = ax * ay;
  if (c == 3) {
    const float *a = r0 + x0 * 3, *b = r0 + x1 * 3, *d = r1 + x0 * 3, *e = r1 + x1 * 3;
    return Vec3f(w00 * a[0] + w10 * b[0] + w01 * d[0] + w11 * e[0], w00 * a[1] + w10 * b[1] + w01 * d[1] + w11 * e[1],
                 w00 * a[2] + w10 * b[2] + w01 * d[2] + w11 * e[2]);
  }
  return Vec3f(w00 * r0[x0 * c] + w10 * r0[x1 * c] + w01 * r1[x0 * c] + w11 * r1[x1 * c], 0.0f, 0.0f);
}

UvTransform UvTransform::fromDesc(const io::UvTransformDesc& d) {
  UvTransform t;
  t.rotationDeg = static_cast<float>(d.rotationDeg);
  t.scale = d.scale.cast<float>();
  t.offset = d.offset.cast<float>();
  return t;
}

Eigen::Matrix2f UvTransform::linear() const {
  const float a = radians(rotationDeg);
  const float c = std::cos(a), s = std::sin(a);
  Eigen::Matrix2f R;
  R << c, -s, s, c;
  return R * scale.asDiagonal();
}

PartMaterial PartMaterial::defaultGray(const std::string& part) {
  PartMaterial m;
  m.part = part;
  return m;
}

namespace {
// A checkout made without symlink support (git core.symlinks=false, some archive tools) turns a
// symlinked folder into a small text file holding the link's target. Follows such placeholders
// along `path`; returns `path` unchanged when nothing needs following.
fs::path followSymlinkPlaceholders(const fs::path& path) {
  if (fs::exists(path)) return path;
  fs::path acc;
  auto it = path.begin();
  for (; it != path.end(); ++it) {
    acc /= *it;
    std::error_code ec;
    if (fs::is_regular_file(acc, ec) && std::next(it) != path.end() && fs::file_size(acc, ec) < 1024) {
      std::ifstream in(acc);
      std::string target;
      std::getline(in, target);
      while (!target.empty() && std::isspace(static_cast<unsigned char>(target.back()))) target.pop_back();
      const fs::path resolved = acc.parent_path() / target;
      if (target.empty() || !fs::is_directory(resolved, ec)) return path;
      spdlog::debug("{} is a symlink placeholder file; following it to {}", acc.string(), resolved.string());
      acc = resolved;
    }
  }
  return acc;
}

FloatTexture readMap(const fs::path& pathIn, const std::string& file, const std::string& key, bool color,
                     bool normal) {
  const fs::path path = followSymlinkPlaceholders(pathIn);
  if (!fs::exists(path)) throw InputError(file, key, "a map file, but " + path.string() + " does not exist");
  cv::Mat img;
  if (color) {
    img = io::readImage(path);  // sRGB decode for 8/16-bit, linear for float files
  } else {
    img = io::readDataImage(path);
    if (normal) {
      PS_Check(img.channels() >= 3, "");
      cv::Mat rgb(img.rows, img.cols, CV_32FC3);
      for (int y = 0; y < img.rows; ++y)
        for (int x = 0; x < img.cols; ++x) {
          const float* p = img.ptr<float>(y) + x * img.channels();
          Vec3f n(2 * p[0] - 1, 2 * p[1] - 1, 2 * p[2] - 1);
          const float len = n.norm();
          n = len > 1e-6f && std::isfinite(len) ? Vec3f(n / len) : Vec3f(0, 0, 1);
          rgb.at<cv::Vec3f>(y, x) = cv::Vec3f(n.x(), n.y(), n.z());
        }
      img = rgb;
    } else if (img.channels() != 1) {
      std::vector<cv::Mat> ch;
      cv::split(img, ch);
      img = ch[0];
    }
  }
  if (normal && img.channels() != 3)
    throw InputError(file, key, "an RGB normal map, got " + std::to_string(img.channels()) + " channels");
  return FloatTexture(img);
}
}  // namespace

PartMaterial PartMaterial::fromDesc(const io::MaterialFileDesc& desc, const std::string& file) {
  PartMaterial m;
  m.part = desc.part;
  m.fromFile = true;
  m.uv = UvTransform::fromDesc(desc.uv);
  m.albedo = desc.homogeneous.albedo.cast<float>();
  m.roughness = static_cast<float>(desc.homogeneous.roughness);
  m.metallic = static_cast<float>(desc.homogeneous.metallic);
  m.specular = static_cast<float>(desc.homogeneous.specular);
  m.albedoOffset = desc.albedoOffset.cast<float>();
  m.albedoScale = static_cast<float>(desc.albedoScale);
  m.roughnessScale = static_cast<float>(desc.roughnessScale);
  for (const auto& [name, path] : desc.maps) {
    const std::string key = "maps." + name;
    if (name == "albedo") m.albedoMap = readMap(path, file, key, true, false);
    else if (name == "normal") m.normalMap = readMap(path, file, key, false, true);
    else if (name == "roughness") m.roughnessMap = readMap(path, file, key, false, false);
    else if (name == "metallic") m.metallicMap = readMap(path, file, key, false, false);
  }
  return m;
}

MaterialSample PartMaterial::evaluate(const Vec2f& uvIn) const {
  MaterialSample s;
  s.specular = specular;
  if (!textured()) {
    s.albedo = albedo;
    s.roughness = roughness;
    s.metallic = metallic;
    return s;
  }
  const Vec2f t = uv.apply(uvIn);
  if (!albedoMap.empty())
    s.albedo = (albedoScale * (albedoMap.sample(t) + albedoOffset)).cwiseMax(0.0f).cwiseMin(1.0f);
  else
    s.albedo = albedo;
  s.roughness = roughnessMap.empty() ? roughness : clampv(roughnessScale * roughnessMap.sample(t).x(), 0.0f, 1.0f);
  s.metallic = metallicMap.empty() ? metallic : clampv(metallicMap.sample(t).x(), 0.0f, 1.0f);
  if (!normalMap.empty()) {
    const Vec3f n = normalMap.sample(t);
    const float len = n.norm();
    s.normalTs = (len > 1e-6f && std::isfinite(len) && n.z() > 0) ? Vec3f(n / len) : Vec3f(0, 0, 1);
  }
  return s;
}

bool tangentFrame(const Vec3f& dPdu, const Vec3f& dPdv, const Vec3f& n, const UvTransform& uv, Vec3f* T,
                  Vec3f* B) {
  // t = M uv + o  =>  dP/dt = dP/duv * M^-1 (columns: dP/dt_u, dP/dt_v)
  const Eigen::Matrix2f M = uv.linear();
  const float det = M.determinant();
  bool ok = std::abs(det) > 1e-12f && dPdu.allFinite() && dPdv.allFinite();
  Vec3f dPdtu = Vec3f::Zero(), dPdtv = Vec3f::Zero();
  if (ok) {
    const Eigen::Matrix2f Mi = M.inverse();
    dPdtu = dPdu * Mi(0, 0) + dPdv * Mi(1, 0);
    dPdtv = dPdu * Mi(0, 1) + dPdv * Mi(1, 1);
    Vec3f t = dPdtu - n * n.dot(dPdtu);
    const float tl = t.norm();
    Vec3f b = n.cross(t);
    if (tl > 1e-12f * (dPdtu.norm() + 1e-30f) && tl > 0 && std::isfinite(tl)) {
      t /= tl;
      b = n.cross(t);
      if (b.dot(dPdtv) < 0) b = -b;
      *T = t;
      *B = b;
      return true;
    }
    ok = false;
  }
  orthonormalBasis(n, *T, *B);
  return false;
}

Twin loadTwin(const fs::path& outDir, bool loadPhotos) {
  Timer timer;
  Twin twin;
  twin.dir = outDir;
  const fs::path sceneFile = outDir / "scene.json";
  if (!fs::exists(sceneFile))
    throw InputError(sceneFile.string(), "", "a twin folder with scene.json (the output of `photoscene run`)");
  LoadOptions lo;
  lo.loadPhotos = loadPhotos;
  twin.scene = loadScene(sceneFile, lo);
  Scene& scene = twin.scene;
  const fs::path lightsFile = outDir / "lights.json";
  if (fs::exists(lightsFile)) {
    const io::LightsFileDesc ld = io::readLightsJson(lightsFile);
    scene.lights = makeLights(ld, scene.mesh, scene.parts, scene.up, lightsFile.string());
    twin.exposure = ld.exposure;
  }
  twin.exposure.resize(scene.views.size(), 1.0);
  twin.materials.resize(scene.parts.size());
  int fromFiles = 0;
  for (const Part& p : scene.parts) {
    const fs::path mf = outDir / "materials" / (p.name + ".json");
    if (fs::exists(mf)) {
      const io::MaterialFileDesc desc = io::readMaterialJson(mf);
      twin.materials[p.id] = PartMaterial::fromDesc(desc, mf.string());
      twin.materials[p.id].part = p.name;
      ++fromFiles;
    } else {
      twin.materials[p.id] = PartMaterial::defaultGray(p.name);
    }
  }
  spdlog::info("twin {}: {} parts, {} with materials files ({:.2f}s)", outDir.string(), scene.parts.size(),
               fromFiles, timer.seconds());
  return twin;
}

}  // namespace ps
