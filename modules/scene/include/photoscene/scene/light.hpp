// The light interface (after pbrt-v4's lights.h): every kind of emitter -- area lights (an OBJ
// part or a rectangle), the environment (seen through window parts or around the scene) and any
// type registered by name -- is a ps::Light. The path tracer, one-light-at-a-time renders,
// incident-light grids and the light solve use only this interface, so a new light type is one
// file (a class derived from ps::Light) plus one registration line:
//
// clang-format off
//   class PointLight final : public ps::Light {   // point_light.cpp
//    public:
//     std::string name;
//     ps::Vec3f position = ps::Vec3f::Zero();
//     std::optional<ps::Vec3f> intensity;   // W / sr per channel; absent: to be fitted
//     std::string type() const override { return "point"; }
//     std::string label() const override { return name; }
//     std::unique_ptr<ps::Light> clone() const override { return std::make_unique<PointLight>(*this); }
//     std::optional<ps::Vec3f> scale() const override { return intensity; }
//     void setScale(const ps::Vec3f& s) override { intensity = s; }
//     bool isDeltaPosition() const override { return true; }
//     float power(const ps::Vec3f& s) const override { return 4 * ps::kPi * ps::luminanceOf(s); }
//     bool sampleLi(const ps::LightSampleContext& ctx, float, const ps::Vec2f&,
//                   ps::LightLiSample* out) const override {
//       const ps::Vec3f d = position - ctx.p;
//       out->dist = d.norm();
//       out->wi = d / out->dist;
//       if (out->wi.dot(ctx.n) <= 0) return false;
//       out->L = ps::Vec3f::Constant(1 / d.squaredNorm());  // for unit intensity
//       out->pdf = ctx.selectionPdf;                        // a delta in direction
//       return ctx.rays->unoccluded(ctx.org, position);
//     }
//     nlohmann::json toJson(const ps::LightJsonContext&) const override;  // {"type": "point", ...}
//     static std::unique_ptr<ps::Light> fromJson(const ps::io::JsonValue& entry,
//                                                const ps::LightJsonContext& ctx);
//   };
//   PS_REGISTER_LIGHT("point", PointLight::fromJson);   // lights.json: {"type": "point", ...}
// clang-format on
//
// (modules/raytrace/test/test_light_registry.cpp is that light, complete, with a test that
// renders it.)
//
// Conventions. Every radiance a light returns (L of a sample, L of a hit) is for unit scale():
// the renderer multiplies it by the scale (its radiance, radiance multiplier or intensity), so
// the light solve can render each light once at scale 1 and combine the images linearly. Every
// pdf is per unit solid angle at the shading point and already includes
// LightSampleContext::selectionPdf, the probability with which the light was chosen.
#pragma once

#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "photoscene/core/math.hpp"
#include "photoscene/io/json.hpp"
#include "photoscene/core/color.hpp"

namespace ps {

struct Mesh;
struct Part;

/// Linear-RGB luminance (Rec. 709 weights), the measure light selection uses for power.
inline float luminanceOf(const Vec3f& c) {
  return luminance(c);
}

/// Where a ray that left the scene went out: the first triangle of an opening part (a window)
/// it passed through, if any.
struct LightEscape {
  bool crossedOpening = false;
  int triangle = -1;   ///< mesh triangle of the first opening crossed
  float distance = 0;  ///< distance to it along the ray
};

/// Visibility queries a light's sampleLi uses; implemented by the renderer (thread-safe).
class LightRays {
 public:
  virtual ~LightRays() = default;
  /// True when nothing blocks the segment from `org` to the point `y` (y itself excluded).
  virtual bool unoccluded(const Vec3f& org, const Vec3f& y) const = 0;
  /// True when nothing blocks the ray org + t dir, t > 0 (unit `dir`): it leaves the scene.
  virtual bool unoccludedToInfinity(const Vec3f& org, const Vec3f& dir) const = 0;
  /// Follows org + t dir through opening parts (windows); true when the ray leaves the scene,
  /// with `escape` saying which opening it crossed first.
  virtual bool escapesThroughOpenings(const Vec3f& org, const Vec3f& dir,
                                      LightEscape* escape) const = 0;
};

/// The shading point a light is sampled from (or a hit's pdf is evaluated at).
struct LightSampleContext {
  Vec3f p = Vec3f::Zero();    ///< the shading point
  Vec3f n = Vec3f::Zero();    ///< unit geometric normal on the side light must arrive from
  Vec3f org = Vec3f::Zero();  ///< p lifted off the surface: where visibility rays start
  float selectionPdf = 1;     ///< probability the light was chosen with (included in every pdf)
  const LightRays* rays = nullptr;  ///< visibility queries (sampleLi only)
};

/// A light sample: direction, distance, radiance for unit scale, pdf (solid angle, selection
/// included).
struct LightLiSample {
  Vec3f wi = Vec3f::Zero();  ///< unit direction from p towards the light
  Vec3f L = Vec3f::Zero();   ///< radiance arriving along -wi, for unit scale()
  float pdf = 0;  ///< per steradian at p, selection included (delta lights: selection only)
  float dist =
      std::numeric_limits<float>::infinity();  ///< to the sampled point; infinite: at infinity
};

/// A path vertex that found a light: a hit on one of its emitting triangles or shapes, or a ray
/// that left the scene (infinite lights).
struct LightHit {
  Vec3f dir = Vec3f::Zero();                         ///< unit ray direction (towards the light)
  float t = std::numeric_limits<float>::infinity();  ///< hit distance; infinite: escaped
  int primitive =
      -1;  ///< the light's own triangle index (emittingTriangles() or shapes()), -1: escaped
  LightEscape escape;  ///< escaped rays: the opening crossed
};

/// The scene a light is prepared against (Light::preprocess).
struct LightScene {
  const Mesh* mesh = nullptr;
  /// part id -> index (in LightSet::all()) of the light whose emittingParts() has it (the last
  /// one when several claim a part), or -1
  std::vector<int> partEmitter;
  int self = -1;  ///< this light's index in LightSet::all()
};

/// What serialisation needs beyond the light: part names, the folder relative paths resolve
/// against, the file named in messages, the scene's up direction.
struct LightJsonContext {
  const std::vector<Part>* parts = nullptr;
  std::filesystem::path baseDir;
  std::string file;
  Vec3f up = Vec3f(0, 1, 0);
  bool loadImages = true;  ///< read images a light names (false: only check they exist)
  /// toJson: how a file the light names (an image) is written into the entry. Empty: its path
  /// relative to baseDir; an export sets it to copy the file into the output folder and return
  /// the copy's relative path.
  std::function<std::string(const std::filesystem::path&)> fileRef;
  /// toJson: the path `file` is written as (fileRef, else relative to baseDir).
  std::string refer(const std::filesystem::path& file) const;
};

/// One light source. Implementations are small value types (copyable through clone()); the
/// renderer clones the scene's lights and calls preprocess() on its copies.
class Light {
 public:
  virtual ~Light() = default;

  /// The type name used in lights.json ("area", "environment", or the registered name).
  virtual std::string type() const = 0;
  /// A name for messages and tables (the emitter's name; "environment").
  virtual std::string label() const = 0;
  virtual std::unique_ptr<Light> clone() const = 0;

  /// The RGB scale the renderer multiplies every radiance by (area: radiance; environment:
  /// radiance multiplier; point: intensity), the quantity the light solve fits. Absent: not
  /// known yet (to be fitted); rendering all lights then fails.
  virtual std::optional<Vec3f> scale() const = 0;
  virtual void setScale(const Vec3f& scale) = 0;
  /// True when the light solve fits the scale: by default when none is given; the environment's
  /// multiplier is always fitted.
  virtual bool fitsScale() const { return !scale().has_value(); }

  /// Delta position (a point or spot): sampleLi's pdf is the selection probability only and no
  /// ray ever hits it (no MIS).
  virtual bool isDeltaPosition() const { return false; }
  /// Infinite: rays that leave the scene see it (L(hit) with hit.t infinite).
  virtual bool isInfinite() const { return false; }

  /// Parts whose triangles emit this light (hits on them are this light's).
  virtual std::vector<int> emittingParts() const { return {}; }
  /// Parts that are openings onto this light: rays pass through them, they get no material.
  virtual std::vector<int> openingParts() const { return {}; }
  /// Triangles this light adds to the scene (emitting surfaces that are not mesh parts, e.g. a
  /// rectangle): three vertices each, appended to `vertices`, and (when `normals` is given) the
  /// unit emission direction at each vertex. Their order is the light's primitive numbering in
  /// LightHit.
  virtual void shapes(std::vector<Vec3f>* vertices, std::vector<Vec3f>* normals) const {
    (void)vertices, (void)normals;
  }

  /// Builds the sampling tables against the scene (after which the light is ready to sample).
  virtual void preprocess(const LightScene& scene) { (void)scene; }
  /// Mesh triangles that emit this light after preprocess(); their order is the light's
  /// primitive numbering in LightHit (hits on other triangles are not this light's).
  virtual std::vector<int> emittingTriangles() const { return {}; }

  /// Power estimate at the given scale, in the units light selection compares (luminance x
  /// m^2 x sr of emitted radiance; 0: never selected).
  virtual float power(const Vec3f& scale) const = 0;
  /// Samples a direction from ctx.p towards the light with `u1`, `u2` in [0, 1) and tests its
  /// visibility with ctx.rays. False when nothing visible (or nothing with a non-zero pdf) was
  /// sampled.
  virtual bool sampleLi(const LightSampleContext& ctx, float u1, const Vec2f& u2,
                        LightLiSample* out) const = 0;
  /// Radiance (unit scale) a ray sees at `hit` (zero from behind a one-sided emitter, or for an
  /// escaped ray that did not leave through this light's openings).
  virtual Vec3f L(const LightHit& hit) const {
    (void)hit;
    return Vec3f::Zero();
  }
  /// The pdf sampleLi would have for the direction of `hit` from ctx.p (selection included).
  virtual float pdfLi(const LightSampleContext& ctx, const LightHit& hit) const {
    (void)ctx, (void)hit;
    return 0;
  }

  /// The lights.json entry of this light ("type" included; paths relative to ctx.baseDir).
  virtual nlohmann::json toJson(const LightJsonContext& ctx) const = 0;
  /// One line for people (`photoscene check`): what the light is and its scale. The default
  /// is the lights.json entry.
  virtual std::string describe(const std::vector<Part>& parts) const;

 protected:
  Light() = default;
  Light(const Light&) = default;
  Light& operator=(const Light&) = default;
};

/// A Light owned by value: copies clone the light.
class LightHandle {
 public:
  LightHandle() = default;
  explicit LightHandle(std::unique_ptr<Light> light) : p_(std::move(light)) {}
  LightHandle(const LightHandle& o) : p_(o.p_ ? o.p_->clone() : nullptr) {}
  LightHandle(LightHandle&&) noexcept = default;
  LightHandle& operator=(const LightHandle& o) {
    if (this != &o) p_ = o.p_ ? o.p_->clone() : nullptr;
    return *this;
  }
  LightHandle& operator=(LightHandle&&) noexcept = default;
  Light* get() const { return p_.get(); }
  Light* operator->() const { return p_.get(); }
  Light& operator*() const { return *p_; }
  explicit operator bool() const { return p_ != nullptr; }

 private:
  std::unique_ptr<Light> p_;
};

/// Makes a light from its lights.json entry (an object with "type"); errors throw
/// ps::InputError naming entry.file(), the key and what was expected.
using LightFactory =
    std::function<std::unique_ptr<Light>(const io::JsonValue& entry, const LightJsonContext& ctx)>;

/// Light types by name. "area" and "environment" are built in; other types register once,
/// before scenes are read (a PS_REGISTER_LIGHT line in the type's file, or add() at start-up).
class LightRegistry {
 public:
  /// Registers `type` (replacing an earlier factory of that name). Returns true.
  static bool add(const std::string& type, LightFactory factory);
  static bool has(const std::string& type);
  /// Every registered type name, sorted.
  static std::vector<std::string> types();
  /// Makes a light of entry["type"]; an unknown type throws ps::InputError at entry.type.
  static std::unique_ptr<Light> create(const io::JsonValue& entry, const LightJsonContext& ctx);
};

#define PS_LIGHT_CONCAT2(a, b) a##b
#define PS_LIGHT_CONCAT(a, b) PS_LIGHT_CONCAT2(a, b)
/// Registers a light type from a file that is linked into the program (an executable's own
/// file or an object library: a static library drops files nothing references, so register
/// lights that live in one with LightRegistry::add in the library's start-up instead).
#define PS_REGISTER_LIGHT(type_name, factory)                       \
  static const bool PS_LIGHT_CONCAT(psLightRegistered_, __LINE__) = \
      ::ps::LightRegistry::add(type_name, factory)

}  // namespace ps
