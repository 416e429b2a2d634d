// Unidirectional path tracer with next-event estimation and multiple importance sampling
// (power heuristic) over the scene's lights, every one through the ps::Light interface
// (photoscene/scene/light.hpp): area emitters (OBJ parts and rectangles, one-sided), the
// environment (constant or equirectangular image, importance-sampled by luminance x sin(theta);
// with window parts it is seen only through them and is sampled through the window triangles)
// and any registered light type. A light is picked with probability half by power, half
// uniform; delta lights (points, spots) get no MIS.
//
// Materials: ps::PartMaterial per part (contract's Lambert + GGX, maps through each part's UV
// transform, tangent-space normal maps in the frame of t). Window parts are openings: rays pass
// through them. Bounce rules follow Cycles (max / diffuse / glossy limits; a path that reaches
// a limit still collects emission at its next hit), Russian roulette after `rouletteDepth`.
//
// Sampling: render() draws every random number of sample s of pixel (x, y) from a
// SobolSampler(seed, y * width + x) (Owen-scrambled Sobol, sampler.hpp): pixel position, light
// pick, light point, BSDF lobe and direction and roulette each have their own dimension per
// bounce, so each is stratified over the pixel's samples. Rectangular emitters (and a window
// that is one rectangle) are sampled uniformly in solid angle (spherical_rectangle.hpp), other
// emitters by area; environment images by luminance (bounded against their bilinear lookup).
// The state is the pixel and the sample index only: a fixed seed gives the same image on any
// thread count.
//
//   ps::PathTracer tracer(scene, materials);
//   ps::RenderOptions opt;  opt.spp = 64;
//   cv::Mat img = tracer.render(scene.views[0].camera, opt);   // CV_32FC3 linear RGB
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/core/math.hpp"
#include "photoscene/core/rng.hpp"
#include "photoscene/raytrace/accel.hpp"
#include "photoscene/raytrace/bsdf.hpp"
#include "photoscene/scene/camera.hpp"
#include "photoscene/scene/material.hpp"
#include "photoscene/scene/scene.hpp"

namespace ps {

/// Which lights shine. Lights are numbered as scene.lights.all() lists them: area lights,
/// lights of registered types, the environment last.
struct LightSelection {
  enum class Kind { All, One, EnvironmentOnly } kind = Kind::All;
  int index = -1;  ///< Kind::One: index into scene.lights.all()
  /// All: lights without a scale (radiance) are an error; One / EnvironmentOnly: the chosen
  /// light shines at unit scale (area: radiance 1; environment: its image x 1), for the
  /// lighting least squares (image = sum_i scale_i * image_i).
  static LightSelection all() { return {}; }
  static LightSelection one(int i) { return {Kind::One, i}; }
  /// Area light i (area lights come first in all()).
  static LightSelection area(int i) { return one(i); }
  static LightSelection environment() { return {Kind::EnvironmentOnly, -1}; }
};

enum class PixelFilter { Box, BlackmanHarris };

struct RenderOptions {
  int spp = 64;               ///< samples per pixel
  int maxBounces = 12;        ///< total scattering events (Cycles' max bounces)
  int maxDiffuseBounces = 6;  ///< Cycles' diffuse bounce limit
  int maxGlossyBounces = 4;   ///< Cycles' glossy bounce limit
  int rouletteDepth = 3;      ///< Russian roulette from this bounce on (0 = from the first)
  uint64_t seed = 0;
  bool nextEventEstimation = true;  ///< false: BSDF sampling only (for tests)
  PixelFilter filter = PixelFilter::BlackmanHarris;
  float filterWidth = 1.5f;  ///< full width in pixels (Cycles' default 1.5)
  LightSelection lights;
  /// Burley (Disney) diffuse instead of Lambert, as Blender's Principled BSDF v1: not the
  /// contract's model; only to measure how much of a difference to Cycles that explains.
  bool principledDiffuse = false;
  /// Clamp of a single sample's contribution (0 = none; Cycles' 'no clamping' is 0).
  float clampSample = 0.0f;
  /// Adaptive sampling (0 = off; render() only, never renderPerLight): after adaptiveMinSpp
  /// samples, and then every 4, a pixel stops once the standard error of its mean luminance
  /// (from the samples' own variance) is at most adaptiveThreshold * (sqrt(mean) + 0.001): an
  /// error tolerance on a square-root tone curve, so dark and bright pixels stop at about the
  /// same visible noise. spp is the most a pixel gets. Flat, evenly lit walls stop early;
  /// glossy edges and penumbrae take the samples.
  float adaptiveThreshold = 0.0f;
  int adaptiveMinSpp = 16;
  /// Optional: CV_8UC1 of the camera's size; only its non-zero pixels are traced, the others
  /// stay 0 (and keep the guides' no-hit values). A traced pixel's value does not depend on
  /// which others are traced (each pixel's sampler is seeded by its index), so a caller that
  /// reads a few pixels (the light solve) gets them at the cost of those alone.
  cv::Mat pixels;
  bool IsValid(std::string* error) const;
};

struct RenderStats {
  double seconds = 0;
  uint64_t rays = 0;     ///< closest-hit + shadow rays traced
  uint64_t samples = 0;  ///< camera samples taken (fewer than pixels x spp when adaptive)
  double raysPerSecond() const { return seconds > 0 ? rays / seconds : 0; }
};

/// What a denoiser is steered by, per pixel, of the noisy image's size (ps::denoise). From
/// PathTracer::render: the average over the pixel's own camera samples (the pixel filter's
/// footprint, so edges and textures match the image exactly).
struct DenoiseGuides {
  cv::Mat albedo;  ///< CV_32FC3, linear RGB reflectance of the first hit in [0, 1] (diffuse
                   ///< colour + F0: what the light is multiplied by); 1 where there is no surface
  cv::Mat normal;  ///< CV_32FC3, unit world-space shading normal of the first hit; 0 where no hit
  cv::Mat depth;   ///< CV_32FC1, camera-space z (m) of the first hit, > 0; 0 where no hit
  cv::Mat
      variance;  ///< optional (empty: estimated from the image): CV_32FC1, variance of the
                 ///< luminance (Rec. 709) of each noisy pixel's mean, in the noisy image's units
};

/// A shading point on the mesh.
/// A light sample from a surface point (PathTracer::sampleDirectLight): the direction towards
/// the light (world) and its MIS-weighted estimate w Le / pdf (radiance arriving, scaled by the
/// light's scale, over the light's own solid-angle pdf, times its power-heuristic weight against
/// the caller's direction sampling; 1 for delta lights, which no direction sampling finds).
struct DirectLightSample {
  Vec3f wi, value;
};

/// What a radiance estimate owes to the diffuse albedo of each part its path scattered on: per
/// part, d L / d ln(scale of the part's diffuse albedo), linear RGB. A contribution that passed
/// through k scatterings on a part scales with that part's diffuse albedo to the k-th power in
/// its diffuse share; the sum is what a first-order change of that albedo changes (the grid
/// point's own scattering is not on the path: radiance() starts at the next surface). Entries
/// are few (the parts one path touches), kept in a flat list.
struct AlbedoSensitivity {
  std::vector<int> part;
  std::vector<Vec3f> value;
  void add(int p, const Vec3f& v);
  /// this += s * other
  void addScaled(const AlbedoSensitivity& other, float s);
  void clear() {
    part.clear();
    value.clear();
  }
};

struct SurfacePoint {
  Vec3f p = Vec3f::Zero();
  Vec3f ng = Vec3f::Zero();  ///< unit geometric normal (winding order), not flipped
  Vec3f ns = Vec3f::Zero();  ///< unit interpolated shading normal, on ng's side
  Vec2f uv = Vec2f::Zero();  ///< OBJ texture coordinates
  Vec3f dpdu = Vec3f::Zero(), dpdv = Vec3f::Zero();  ///< of the triangle (zero when degenerate)
  int triangle = -1, part = -1;
};

class PathTracer {
 public:
  /// @param scene      geometry, parts and lights (kept by reference: must outlive the tracer)
  /// @param materials  one per part (kept by reference); missing entries render gray
  PathTracer(const Scene& scene, const std::vector<PartMaterial>& materials);
  ~PathTracer();

  /// Renders a linear RGB image (CV_32FC3, camera.width() x camera.height()). `guides`
  /// (optional): the denoiser's guides from the same samples: the mean first-hit albedo, the
  /// first hit's shading normal and camera-space depth where most of the pixel's samples hit a
  /// reflecting surface (emitters, windows' outside and the environment: no surface), and the
  /// variance of each pixel's mean luminance from its samples.
  cv::Mat render(const Camera& camera, const RenderOptions& options, RenderStats* stats = nullptr,
                 DenoiseGuides* guides = nullptr) const;
  /// One image per light of scene.lights.all() at unit scale (area emitters, registered lights,
  /// the environment last): the images the lighting least squares combines. One trace for all
  /// lights: each camera path is traced once; at every vertex each light gets its own
  /// next-event sample (selection probability 1, from the same numbers a render of that light
  /// alone draws), and emission found by BSDF sampling goes to the light that was hit, with the
  /// MIS weight of that light. Image i is therefore the same, bit for bit, as
  /// render() with LightSelection::one(i) and the same seed (options.lights is not used), at
  /// the cost of one render plus one shadow ray per extra light per vertex.
  std::vector<cv::Mat> renderPerLight(const Camera& camera, const RenderOptions& options,
                                      RenderStats* stats = nullptr) const;
  /// Radiance arriving at `org` from direction -dir (i.e. seen along dir), one path sample.
  /// `rays` (optional) is incremented by the rays traced. `firstPdf` > 0 (with next-event
  /// estimation on): emission that this first ray finds is weighted by the power heuristic
  /// against sampleDirectLight's samples from `org`, firstPdf being the direction sampling's
  /// density per light sample (the gatherer's samples per steradian over its light samples per
  /// light); the gatherer adds those samples (DirectLightSample) with the complementary weight.
  /// `sensitivity` (optional) is added to: what the returned radiance owes to each part's
  /// diffuse albedo (AlbedoSensitivity).
  Vec3f radiance(const Vec3f& org, const Vec3f& dir, const RenderOptions& options, Rng& rng,
                 uint64_t* rays = nullptr, float firstPdf = 0,
                 AlbedoSensitivity* sensitivity = nullptr) const;
  /// `n` samples of every active light with a shape (area emitters; not the environment, whose
  /// light a direction sampler finds well) seen from surface point `p` (geometric normal `ng`,
  /// facing the side to light; shadow rays from `org`, offset off the surface), each light at
  /// selection probability 1; only visible ones with radiance are returned. Empty without
  /// next-event estimation. Paired with radiance()'s first rays at the same `firstPdf`, this is
  /// multiple importance sampling of the direct light: each sample carries the power heuristic's
  /// weight of its pdf against firstPdf, the first rays' emission the complement.
  std::vector<DirectLightSample> sampleDirectLight(const Vec3f& p, const Vec3f& org,
                                                   const Vec3f& ng, int n, float firstPdf,
                                                   const RenderOptions& options, Rng& rng,
                                                   uint64_t* rays = nullptr) const;

  const RayAccel& accel() const { return *accel_; }
  const Scene& scene() const { return scene_; }
  /// The surface point of a mesh hit (geometry 0).
  SurfacePoint surfacePoint(const RayHit& hit) const;
  /// Material of a part (gray default when `materials` had no entry).
  const PartMaterial& material(int part) const;
  bool isWindowPart(int part) const;
  double buildSeconds() const;

  struct Lights;  // emitter sampling tables (private)

 private:
  const Scene& scene_;
  const std::vector<PartMaterial>& materials_;
  PartMaterial gray_;
  std::unique_ptr<RayAccel> accel_;
  std::vector<uint8_t> windowPart_;
  std::vector<Vec3f> triNormal_, triDpdu_, triDpdv_;
  std::unique_ptr<Lights> lights_;
  double setupSeconds_ = 0;
};

/// The shading frame of a surface point for a material (tangent frame of t + normal map),
/// oriented to the side of `wo` (unit, pointing away from the surface). Returns the shading
/// normal used and writes T, B.
Vec3f shadingFrame(const SurfacePoint& sp, const PartMaterial& material, const MaterialSample& ms,
                   const Vec3f& wo, Vec3f* T, Vec3f* B);

}  // namespace ps
