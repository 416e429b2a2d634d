// The built-in lights of a scene: area emitters (an OBJ part, or a rectangle) and an environment
// (seen through window parts, or by every ray that leaves the scene), both ps::Light
// (light.hpp), and the LightSet that holds a scene's lights.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "photoscene/core/math.hpp"
#include "photoscene/io/scene_json.hpp"
#include "photoscene/scene/distribution.hpp"
#include "photoscene/scene/light.hpp"

namespace ps {

struct Mesh;

/// An emitting triangle as the built-in lights sample it.
struct EmitterTriangle {
  Vec3f p0 = Vec3f::Zero(), e1 = Vec3f::Zero(), e2 = Vec3f::Zero();
  Vec3f n = Vec3f::Zero();  ///< unit emission direction (area lights) or geometric normal (windows)
  float area = 0;
};

/// An emitter (or the set of windows) that is exactly one rectangle corner + a ex + b ey:
/// sampled uniformly in solid angle.
struct EmitterRectangle {
  Vec3f corner = Vec3f::Zero(), ex = Vec3f::Zero(), ey = Vec3f::Zero();
  Vec3f n = Vec3f::Zero();  ///< emission side (area lights)
  float area = 0;
  bool valid = false;
};

/// A one-sided area emitter with uniform radiance. Sampled uniformly in solid angle when it is
/// one rectangle (spherical_rectangle.hpp), else uniformly in area.
class AreaLight final : public Light {
 public:
  enum class Kind { Part, Rectangle };
  std::string name;
  Kind kind = Kind::Rectangle;
  int partId = -1;  ///< Kind::Part: the emitting part (its faces emit along their normals)
  /// Kind::Rectangle: spans center +- edgeU/2 +- edgeV/2, emits along normalize(edgeU x edgeV).
  Vec3f center = Vec3f::Zero(), edgeU = Vec3f::Zero(), edgeV = Vec3f::Zero();
  /// Emitted radiance (linear RGB, W / (m^2 sr) per channel); absent: to be fitted.
  std::optional<Vec3f> radiance;
  bool automatic = false;  ///< placed by the automatic ceiling grid

  /// Rectangle: unit emission direction.
  Vec3f normal() const { return edgeU.cross(edgeV).normalized(); }
  /// Rectangle area (m^2).
  float rectangleArea() const { return edgeU.cross(edgeV).norm(); }

  /// From a description (scene.json's lights.area[i] or lights.json's emitters[i], `key`).
  static AreaLight fromDesc(const io::AreaLightDesc& desc, const std::vector<Part>& parts,
                            const std::string& file, const std::string& key);
  /// The lights.json entry's factory (LightRegistry "area").
  static std::unique_ptr<Light> fromJson(const io::JsonValue& entry, const LightJsonContext& ctx);

  // ps::Light
  std::string type() const override { return "area"; }
  std::string label() const override { return name; }
  std::unique_ptr<Light> clone() const override { return std::make_unique<AreaLight>(*this); }
  std::optional<Vec3f> scale() const override { return radiance; }
  void setScale(const Vec3f& s) override { radiance = s; }
  std::vector<int> emittingParts() const override;
  void shapes(std::vector<Vec3f>* vertices, std::vector<Vec3f>* normals) const override;
  void preprocess(const LightScene& scene) override;
  std::vector<int> emittingTriangles() const override { return meshTriangles_; }
  float power(const Vec3f& scale) const override;
  bool sampleLi(const LightSampleContext& ctx, float u1, const Vec2f& u2,
                LightLiSample* out) const override;
  Vec3f L(const LightHit& hit) const override;
  float pdfLi(const LightSampleContext& ctx, const LightHit& hit) const override;
  nlohmann::json toJson(const LightJsonContext& ctx) const override;
  std::string describe(const std::vector<Part>& parts) const override;

 private:
  // sampling tables (preprocess)
  std::vector<EmitterTriangle>
      tris_;  // the light's primitives (mesh triangles or its rectangle's two)
  std::vector<int> meshTriangles_;  // Kind::Part: the mesh triangle of each of tris_
  std::vector<int> sampled_;        // tris_ with a positive area: what sampleLi draws from
  Distribution1D dist_;             // over sampled_, by area
  float totalArea_ = 0;
  EmitterRectangle rect_;
};

/// Distant light from an equirectangular image (or a constant), optionally seen only through
/// window parts. For a unit direction d in the frame where up = +Y:
///   u = frac(0.5 + (atan2(d.z, d.x) - rotation) / 2pi),  v = 0.5 - asin(d.y) / pi  (v = 0 at top).
/// Sampled by the image's luminance x sin(theta) (bounded against its bilinear lookup) and, with
/// windows, half through the window triangles (by solid angle when they form one rectangle).
class EnvironmentLight final : public Light {
 public:
  cv::Mat image;                       ///< CV_32FC3 linear, or empty for a constant
  std::filesystem::path imagePath;     ///< the file `image` was read from (empty: none)
  Vec3f radiance = Vec3f::Ones();      ///< multiplier on the image, or the constant radiance
  float rotationDeg = 0;
  std::vector<int> windowParts;        ///< part ids that are openings onto the environment
  Mat3f worldToEnv = Mat3f::Identity();  ///< rotation taking `up` onto +Y

  /// Radiance arriving from world direction `dir` (unit), bilinear in the image.
  Vec3f radianceFrom(const Vec3f& dir) const;
  /// (u, v) in [0, 1) x [0, 1] for a unit world direction.
  Vec2f directionToUv(const Vec3f& dir) const;
  /// Inverse of directionToUv.
  Vec3f uvToDirection(const Vec2f& uv) const;

  /// From a description (scene.json's lights.environment or lights.json's environment at `key`).
  static EnvironmentLight fromDesc(const io::EnvironmentDesc& desc, const std::vector<Part>& parts,
                                   const Vec3f& up, const std::string& file, const std::string& key,
                                   bool loadImage);
  /// The lights.json "environment" object's factory (LightRegistry "environment").
  static std::unique_ptr<Light> fromJson(const io::JsonValue& entry, const LightJsonContext& ctx);

  // ps::Light
  std::string type() const override { return "environment"; }
  std::string label() const override { return "environment"; }
  std::unique_ptr<Light> clone() const override {
    return std::make_unique<EnvironmentLight>(*this);
  }
  std::optional<Vec3f> scale() const override { return radiance; }
  void setScale(const Vec3f& s) override { radiance = s; }
  bool fitsScale() const override { return true; }
  bool isInfinite() const override { return true; }
  std::vector<int> openingParts() const override { return windowParts; }
  void preprocess(const LightScene& scene) override;
  bool sampleLi(const LightSampleContext& ctx, float u1, const Vec2f& u2,
                LightLiSample* out) const override;
  Vec3f L(const LightHit& hit) const override;
  float pdfLi(const LightSampleContext& ctx, const LightHit& hit) const override;
  float power(const Vec3f& scale) const override;
  nlohmann::json toJson(const LightJsonContext& ctx) const override;
  std::string describe(const std::vector<Part>& parts) const override;

 private:
  Vec3f unitRadianceFrom(const Vec3f& dir) const;  // the lookup at radiance 1
  bool sampleImage(const Vec2f& u, Vec3f* wi) const;  // a direction by the image's importance
  float windowMix() const { return image.empty() ? 1.0f : 0.5f; }
  float imagePdf(const Vec3f& dir) const;
  float windowPdf(const Vec3f& x, const Vec3f& dir, const LightEscape& esc) const;
  float pdf(const Vec3f& x, const Vec3f& dir, const LightEscape& esc, float selectionPdf) const;

  // sampling tables (preprocess)
  std::vector<EmitterTriangle> windowTris_;
  std::vector<int> meshTriWindow_;  // mesh triangle -> windowTris_ index or -1
  Distribution1D windowDist_;
  float windowArea_ = 0;
  EmitterRectangle windowRect_;  // all window triangles, when they form one rectangle
  Distribution2D envDist_;       // image importance (by luminance x sin(theta))
  float envMeanLum_ = 1;
  /// With windows: sum over window triangles of area x the environment's luminance through them
  /// weighted by |cos| to the window (over the outward hemisphere) / pi: the power that enters,
  /// in the units of an area light's luminance x area.
  float windowPower_ = 0;
  float sceneRadius_ = 1;
};

/// A scene's lights. The built-in types keep their own lists (`area`, `environment`); lights of
/// registered types are in `registered`. all() is the one order every renderer and solver uses:
/// area lights, registered lights, the environment last.
struct LightSet {
  std::vector<AreaLight> area;
  std::vector<LightHandle> registered;
  std::optional<EnvironmentLight> environment;

  std::vector<const Light*> all() const;
  std::vector<Light*> all();
  size_t size() const { return area.size() + registered.size() + (environment ? 1 : 0); }
  bool empty() const { return size() == 0; }
  /// Index of the environment in all(), or -1.
  int environmentIndex() const { return environment ? static_cast<int>(size()) - 1 : -1; }
  /// Appends a light: an AreaLight or EnvironmentLight to its list, any other type to `registered`.
  void add(std::unique_ptr<Light> light);
  /// Parts that emit (emittingParts of every light) and parts that are openings (windows).
  std::vector<int> emittingParts() const;
  std::vector<int> openingParts() const;
  /// Indices in all() of the lights whose scale the light solve fits (Light::fitsScale).
  std::vector<int> fittedLights() const;
};

/// Index in `list` of the light that stands for `light` in another light set (a relit or an
/// original lights.json): the same type, and a shared emitting part, else the same label, else
/// (lights with no emitting part) the nearest centroid of shapes() within `maxDistance` meters;
/// -1 when none.
int matchLight(const Light& light, const std::vector<const Light*>& list,
               float maxDistance = 0.5f);

/// The lights.json form of a light set (section 3 of the contract): "emitters" (every light but
/// the infinite ones, in all() order), "environment" when there is one, "exposure".
nlohmann::json lightsToJson(const LightSet& lights, const LightJsonContext& ctx,
                            const std::vector<double>& exposure = {});

/// Ceiling lights on a grid: the room's horizontal extent (the mesh's bounding box across `up`)
/// is split into ceil(extent / spacing) cells per axis, one square light of side `size` centered
/// in each, `offset` meters below the top of the box, facing down. A 6 x 4 m room at 3 m spacing
/// gets 2 x 2 lights.
std::vector<AreaLight> autoCeilingLights(const Mesh& mesh, const Vec3f& up, float spacing,
                                         float size = 0.5f, float offset = 0.01f);

}  // namespace ps
