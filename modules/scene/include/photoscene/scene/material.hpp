// Per-part materials of a twin: the contract's shading model (../shared/spec/scene-format.md
// section 3, materials/<part>.json) as the path tracer and the render layer evaluate it.
//
// Shading model: Lambert diffuse + GGX microfacet specular (Smith shadowing, Schlick Fresnel),
//   alpha = roughness^2, F0 = lerp(F0_dielectric, albedo, metallic), F0_dielectric = 0.08 * specular,
//   diffuse weight = albedo * (1 - metallic).
//
// Texture lookup: t = R(rotation) * (S * uv) + offset, maps repeat with period 1 in t;
// t = (0, 0) is the BOTTOM-left corner of a map, t_v grows upwards, so the continuous pixel
// coordinate of t is x = t_u * W - 0.5, y = (1 - t_v) * H - 0.5 (texel centers at integers).
// Normal maps are tangent-space, OpenGL convention, in the frame of t: +X along dP/dt_u,
// +Y along dP/dt_v (a rotated mapping rotates the tangent frame).
//
//   ps::Twin twin = ps::loadTwin("OUT");               // OUT/scene.json, lights.json, materials/
//   const ps::PartMaterial& m = twin.materials[partId];
//   ps::MaterialSample s = m.evaluate(uv);              // albedo, roughness, metallic, F0, normal
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/core/math.hpp"
#include "photoscene/io/scene_json.hpp"
#include "photoscene/scene/scene.hpp"

namespace ps {

/// A float texture with `channels` (1 or 3) channels, bilinear lookup, periodic in t.
class FloatTexture {
 public:
  FloatTexture() = default;
  /// @param image CV_32FC1 or CV_32FC3 (row 0 = top of the map, i.e. t_v = 1)
  explicit FloatTexture(const cv::Mat& image);
  bool empty() const { return data_.empty(); }
  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  /// Bilinear lookup at texture coordinate t (period 1 in both axes). Channels beyond
  /// channels() are left 0.
  Vec3f sample(const Vec2f& t) const;
  /// Texel (x, y), row 0 on top; x and y wrap.
  Vec3f texel(int x, int y) const;

 private:
  int width_ = 0, height_ = 0, channels_ = 0;
  std::vector<float> data_;
};

/// The contract's UV transform t = R(rotationDeg) * (diag(scale) * uv) + offset.
struct UvTransform {
  float rotationDeg = 0;
  Vec2f scale = Vec2f::Ones();
  Vec2f offset = Vec2f::Zero();

  static UvTransform fromDesc(const io::UvTransformDesc& d);
  /// The 2x2 linear part M = R * S (t = M uv + offset).
  Eigen::Matrix2f linear() const;
  Vec2f apply(const Vec2f& uv) const { return linear() * uv + offset; }
};

/// What a material gives at one surface point.
struct MaterialSample {
  Vec3f albedo = Vec3f::Constant(0.5f);  ///< linear base colour in [0, 1]
  float roughness = 0.7f;                ///< [0, 1]; alpha = roughness^2
  float metallic = 0.0f;                 ///< [0, 1]
  float specular = 0.5f;                 ///< F0_dielectric = 0.08 * specular
  Vec3f normalTs = Vec3f(0, 0, 1);       ///< unit tangent-space normal (frame of t), +Z = surface normal

  Vec3f diffuseColor() const { return albedo * (1.0f - metallic); }
  Vec3f f0() const {
    const float d = 0.08f * specular;
    return Vec3f::Constant(d) * (1.0f - metallic) + albedo * metallic;
  }
};

/// One part's material: maps (each optional) with homogeneous fallbacks.
struct PartMaterial {
  std::string part;
  UvTransform uv;
  FloatTexture albedoMap;     ///< linear RGB (decoded from sRGB)
  FloatTexture normalMap;     ///< tangent-space unit normals, OpenGL convention
  FloatTexture roughnessMap;  ///< linear, channel 0
  FloatTexture metallicMap;   ///< linear, channel 0
  Vec3f albedo = Vec3f::Constant(0.5f);  ///< used where there is no albedo map
  float roughness = 0.7f, metallic = 0.0f, specular = 0.5f;
  Vec3f albedoOffset = Vec3f::Zero();    ///< added to the albedo map
  float albedoScale = 1.0f;              ///< multiplies the albedo map (after the offset)
  float roughnessScale = 1.0f;           ///< multiplies the roughness map
  bool fromFile = false;                 ///< false: the gray default (no materials file)

  /// The gray default of a part with no materials file (albedo 0.5, roughness 0.7).
  static PartMaterial defaultGray(const std::string& part);
  /// Builds a material from a parsed materials file, reading its maps. Throws ps::InputError
  /// naming `desc`'s map file when one is missing or unreadable.
  static PartMaterial fromDesc(const io::MaterialFileDesc& desc, const std::string& file);

  bool textured() const {
    return !albedoMap.empty() || !normalMap.empty() || !roughnessMap.empty() || !metallicMap.empty();
  }
  /// Evaluates the maps at OBJ texture coordinate `uv` (the UV transform is applied here).
  /// albedo = clamp(albedoScale * (map + albedoOffset), 0, 1) with a map, else `albedo`;
  /// roughness = clamp(roughnessScale * map, 0, 1) with a map, else `roughness`.
  MaterialSample evaluate(const Vec2f& uv) const;
};

/// A twin output folder loaded for rendering.
struct Twin {
  std::filesystem::path dir;
  Scene scene;                          ///< geometry, parts, views; lights from lights.json when present
  std::vector<PartMaterial> materials;  ///< indexed by part id
  std::vector<double> exposure;         ///< per view (from lights.json; 1 where absent)
};

/// Reads OUT/scene.json (geometry, views, lights), OUT/lights.json when present (replacing the
/// scene's lights), and OUT/materials/<part>.json for every part with their maps. A part
/// without a materials file renders gray (albedo 0.5, roughness 0.7), as the contract's "skip".
/// Throws ps::InputError for missing or malformed files.
Twin loadTwin(const std::filesystem::path& outDir, bool loadPhotos = false);

/// The shading frame of a mapping: given dP/du and dP/dv of the OBJ uv and the unit shading
/// normal n, returns unit T along dP/dt_u and B along dP/dt_v (orthogonalised against n; B's
/// handedness follows dP/dt_v), for t = M uv + offset. Falls back to an arbitrary frame around n
/// when the uv derivatives are degenerate. Returns false in that case.
bool tangentFrame(const Vec3f& dPdu, const Vec3f& dPdv, const Vec3f& n, const UvTransform& uv,
                  Vec3f* T, Vec3f* B);

}  // namespace ps
