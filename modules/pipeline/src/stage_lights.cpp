// Stages `lights0` and `lights1`: the scale of every light whose scale is fitted
// (Light::fitsScale), by non-negative least squares over per-light renders (one trace for all
// lights, PathTracer::renderPerLight, of the pixels the solve reads alone: lighting::
// solvePixels; lighting module); round 0 under the neutral materials
// (on the pixels of the parts of given material alone, where they suffice), round 1 under the
// fitted ones over every view (per-view exposure with several views). A light the photos show
// directly is pinned to those pixels, and every part whose reflectance is guessed gets a free
// factor, so the light comes from how shading varies within parts. The result is written
// into the scene the later path tracers see.
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <limits>

#include "photoscene/core.hpp"
#include "photoscene/lighting.hpp"
#include "stages.hpp"

namespace ps::pipeline {

namespace {

constexpr double kSaturation = 0.99;  ///< share of the clip level at which a pixel counts as clipped

class LightsStage : public Stage {
 public:
  explicit LightsStage(int round) : Stage(round == 0 ? "lights0" : "lights1"), round_(round) {
    decl.scene = {"geometry",       "up",
                  "lights",         "views[].camera",
                  "views[].image",  "views[].color_space",
                  "parts.{}.fixed", "options.seed"};
    decl.options = {"preset", "work_width", "baseline"};
    decl.after = {"parts", "geometry", "align", "observe", "pin"};
    if (round == 1) {
      decl.options.push_back("library");
      decl.after.insert(decl.after.end(), {"lights0", "select", "fit", "refine0"});
    }
    decl.writes = {"the free emitters' radiance (Context::applyLights)", "Context::exposure"};
    // 2: float photos (EXR, HDR) are not clipped at 0.99; 3: the photos divided by the
    // exposures known before the solve; 4: round 0 anchored on the parts of given material; 5: a
    // light the photos show (through a window, or its emitter unsaturated) pinned to those
    // pixels, and a free reflectance factor per part (lighting/solve.hpp); 6: a float photo's
    // bright pixels count with given emitters too (only an integer-coded photo clips); 7:
    // the given emitters' light a term of the model (lighting/solve.hpp), not taken off the photo;
    // 8: round 1's factors take their colour from a pinned light; 9: the renders trace the
    // pixels the solve reads alone (the same solution; the anchor's light shares are estimated
    // on those pixels)
    decl.version = 9;
  }

  bool compute(Context& ctx, const Reads& in, int) override {
    const Scene& scene = in.litScene();
    const std::vector<int>& freeLights = in.freeLights();
    intensity_.clear();
    // without a solve (every light given), the exposures stay as observe estimated them
    exposure_.resize(ctx.views.size());
    for (size_t v = 0; v < exposure_.size(); ++v)
      exposure_[v] = ctx.viewExposure(static_cast<int>(v));
    if (freeLights.empty()) {
      spdlog::info("{}: skipped: every light has a given scale", decl.name);
      return false;
    }
    const std::vector<PartMaterial> mats =
        round_ == 1 ? fittedMaterials(ctx, in, in.fitOptions().mapSize) : neutralMaterials(ctx, in);
    lighting::SolveOptions so;
    so.saturation = std::numeric_limits<double>::infinity();  // per view below
    so.perViewExposure = ctx.views.size() > 1;
    // round 1 only: a window's measured colour sets the colour of the lights and the albedos
    // (lighting/solve.hpp); in round 0 it would move selection, which chose textures for the
    // blender-room example's east wall and table top under the lamps' true colour (balanced:
    // novel1 sRGB RMSE 18.08 -> 19.01; round 1 only: 18.10)
    so.pinnedLightSetsColour = round_ == 1;
    // the given lights shine at their scale; the free ones are each rendered at unit scale (all
    // in one trace)
    const PathTracer tracer(scene, mats);
    const std::vector<const Light*> lights = scene.lights.all();
    std::vector<uint8_t> isFree(lights.size(), 0);
    for (int k : freeLights) isFree[k] = 1;
    // round 0 may solve on the parts of given material alone (anchorOnFixedParts)
    const bool mayAnchor = round_ == 0 && in.baseline() != Baseline::PixelMedian;
    std::vector<int> fixedParts;
    for (const PartWork& p : ctx.parts)
      if (p.mode == PartMode::Fixed) fixedParts.push_back(p.id);
    std::vector<lighting::ViewLightData> data;
    std::vector<ViewMasks> masks;
    for (int v = 0; v < in.viewCount(); ++v) {
      checkInterrupted();
      const cv::Mat& photo = in.photo(v);
      lighting::ViewLightData d;
      // the photo divided by the exposure known so far (observe's estimate, or lights0's): the
      // solve finds what is left of it, close to 1, so that scaling one photo scales its
      // exposure and changes nothing else (the alternation does not start far from it)
      d.photo = photo / exposure_[v];
      cv::Mat all = ctx.views[v].lightMask.clone();
      if (const double clip = in.photoClip(v, 1.0); std::isfinite(clip)) {
        // an integer-coded photo clips (at 1): its saturated pixels (any channel) say nothing,
        // nor do they with the given emitters' light in the model (below); a float photo
        // (EXR, HDR) does not clip, and all of it counts at any exposure
        std::vector<cv::Mat> ch;
        cv::split(photo, ch);
        for (const cv::Mat& c : ch) all.setTo(0, c >= kSaturation * clip);
      }
      // where each free light is seen itself (its emitting parts, the windows that open onto
      // it): the solve pins it there (lighting/solve.hpp); taken before the anchor narrows the
      // mask, whose pixels it does not replace
      for (int k : freeLights) {
        std::vector<int> own = lights[k]->emittingParts();
        for (int id : lights[k]->openingParts()) own.push_back(id);
        d.direct.push_back(photoMaskOf(ctx.views[v], own, all.size()) & all);
      }
      // the pixels the solve reads (of the whole mask, of the fixed parts' if round 0 anchors
      // there, where a light is seen): the per-light renders trace those alone, with the values
      // that whole renders have there
      ViewMasks vm;
      vm.allPixels = cv::countNonZero(all);
      vm.allSampled = lighting::solvePixels(d.photo, all, so);
      cv::Mat traced = vm.allSampled.clone();
      if (mayAnchor) {
        const cv::Mat fixed = photoMaskOf(ctx.views[v], fixedParts, all.size()) & all;
        vm.fixedPixels = cv::countNonZero(fixed);
        vm.fixedSampled = lighting::solvePixels(d.photo, fixed, so);
        traced |= vm.fixedSampled;
      }
      for (const cv::Mat& m : d.direct) traced |= m;
      RenderOptions ro;
      ro.spp = in.budget().lightSpp;
      ro.seed = in.seed() + 17 * v;
      ro.pixels = traced;
      const std::vector<cv::Mat> perLight = tracer.renderPerLight(in.camera(v), ro);
      d.mask = vm.allSampled;
      cv::Mat fixed = cv::Mat::zeros(photo.size(), CV_32FC3);
      for (size_t k = 0; k < lights.size(); ++k) {
        if (isFree[k]) {
          d.perLight.push_back(perLight[k]);
        } else if (const std::optional<Vec3f> r = lights[k]->scale()) {
          fixed += perLight[k].mul(cv::Scalar((*r)[0], (*r)[1], (*r)[2]));
        }
      }
      // the given emitters' light: a known term of the model, which the view's exposure and
      // each part's free factor scale like the rest (not taken off the photo)
      if (cv::countNonZero(fixed.reshape(1)) > 0) d.given = fixed;
      // the parts whose reflectance the renders only guess (round 0: photo median x pin; round
      // 1: the fit's, made under round 0's lights) each get a free factor in the solve; not for
      // the pixel-median baseline, whose albedos are those guesses
      if (in.baseline() != Baseline::PixelMedian) {
        d.regions = cv::Mat(d.mask.size(), CV_32SC1, cv::Scalar(-1));
        for (const PartWork& p : ctx.parts) {
          if (p.mode != PartMode::Fit && p.mode != PartMode::Homogeneous) continue;
          const auto it = ctx.views[v].photoMask.find(p.id);
          if (it != ctx.views[v].photoMask.end() && it->second.size() == d.mask.size())
            d.regions.setTo(p.id, it->second);
        }
      }
      data.push_back(std::move(d));
      masks.push_back(std::move(vm));
    }
    // the pixel-median baseline's albedos are the neutral guesses themselves: its lights are
    // the ones solved with them, not anchored (else it renders at another level than its photo)
    if (mayAnchor) anchorOnFixedParts(masks, data);
    const lighting::LightSolution s = lighting::solveLights(data, so);
    spdlog::info("{}: {}", decl.name, s.summary());
    intensity_ = s.intensity;
    for (size_t v = 0; v < exposure_.size() && v < s.exposure.size(); ++v)
      exposure_[v] *= s.exposure[v] / s.exposure[0];
    return true;
  }
  void save(const Context&, int, Archive& a) const override {
    std::vector<double> flat;
    for (const Vec3d& x : intensity_) flat.insert(flat.end(), {x.x(), x.y(), x.z()});
    a.putVector(flat);
    a.putVector(exposure_);
  }
  bool load(Context&, const Reads&, int, Archive& a) override {
    const std::vector<double> flat = a.getVector<double>();
    exposure_ = a.getVector<double>();
    intensity_.clear();
    for (size_t i = 0; i + 2 < flat.size(); i += 3)
      intensity_.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
    return true;
  }
  // the free lights in scene.lights.all() order
  void finish(Context& ctx, const Reads&) override {
    ctx.applyLights(intensity_);
    ctx.exposure = exposure_;
  }

 private:
  // Of a view's light mask less its clipped pixels (`all`) and of the parts of given material
  // in it (`fixed`, round 0 only): the pixel counts and the pixels the solve reads
  // (lighting::solvePixels, CV_8UC1, render frame), which are all that the renders trace.
  struct ViewMasks {
    int allPixels = 0, fixedPixels = 0;
    cv::Mat allSampled, fixedSampled;
  };

  // Round 0 knows no albedo of a part to be fitted: its guess (photo median x pin) carries the
  // light's colour and level, so a solve over those pixels reads a warm light as neutral and
  // paints the warmth into the albedos. Parts of given material (`fixed`) do not: where they
  // fill enough of the views and every free light reaches them, round 0 solves on their pixels
  // alone, so colour and level come from known albedos. Else the whole light mask stays.
  void anchorOnFixedParts(const std::vector<ViewMasks>& masks,
                          std::vector<lighting::ViewLightData>& data) const {
    int pixels = 0, total = 0;
    std::vector<double> onFixed(data.empty() ? 0 : data[0].perLight.size(), 0.0);
    std::vector<double> onAll(onFixed.size(), 0.0);
    for (size_t v = 0; v < data.size(); ++v) {
      const ViewMasks& m = masks[v];
      pixels += m.fixedPixels;
      total += m.allPixels;
      for (size_t k = 0; k < onFixed.size() && k < data[v].perLight.size(); ++k) {
        onFixed[k] += energy(data[v].perLight[k], m.fixedSampled, m.fixedPixels);
        onAll[k] += energy(data[v].perLight[k], m.allSampled, m.allPixels);
      }
    }
    const int minPixels = std::max(kAnchorMinPixels, static_cast<int>(kAnchorMinShare * total));
    if (pixels < minPixels) return;
    for (size_t k = 0; k < onFixed.size(); ++k)
      if (onAll[k] > 0 && onFixed[k] < kAnchorMinLightShare * onAll[k]) {
        spdlog::info("{}: not anchored on the fixed parts: free light {} barely reaches them",
                     decl.name, k);
        return;
      }
    for (size_t v = 0; v < data.size(); ++v) data[v].mask = masks[v].fixedSampled;
    spdlog::info("{}: anchored on the parts of given material ({} px of {})", decl.name, pixels,
                 total);
  }

  // the union of the parts' M_photo in a view (CV_8UC1 of `size`; parts it lacks add nothing)
  static cv::Mat photoMaskOf(const ViewWork& view, const std::vector<int>& parts, cv::Size size) {
    cv::Mat m = cv::Mat::zeros(size, CV_8UC1);
    for (int id : parts) {
      const auto it = view.photoMask.find(id);
      if (it != view.photoMask.end() && it->second.size() == size) m |= it->second;
    }
    return m;
  }

  // the sum of a render's three channels over a mask of n pixels, from its `sampled` pixels
  // (the render's traced ones): their mean times n
  static double energy(const cv::Mat& render, const cv::Mat& sampled, int n) {
    if (n == 0 || cv::countNonZero(sampled) == 0) return 0;
    const cv::Scalar m = cv::mean(render, sampled);
    return (m[0] + m[1] + m[2]) * n;
  }

  static constexpr int kAnchorMinPixels = 500;
  static constexpr double kAnchorMinShare = 0.02;      ///< of the usable pixels
  static constexpr double kAnchorMinLightShare = 0.05; ///< of each free light's energy
  int round_;
  std::vector<Vec3d> intensity_;
  std::vector<double> exposure_;
};

}  // namespace

std::unique_ptr<Stage> makeLightsStage(int round) {
  return std::make_unique<LightsStage>(round);
}

}  // namespace ps::pipeline
