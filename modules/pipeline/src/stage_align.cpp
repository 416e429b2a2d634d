// Stages `align`, `observe` and `pin`: per view, the photo's regions matched to parts and the
// Eq. (1) box warp (align module); then per part, the view that sees it best, its aligned pixels
// and median colour; then the scale pin of the neutral materials.
#include <opencv2/imgproc.hpp>
#include "photoscene/core/log.hpp"

#include "photoscene/align.hpp"
#include "stages.hpp"
#include "photoscene/core/color.hpp"

namespace ps::pipeline {

namespace {

class AlignStage : public Stage {
 public:
  AlignStage() : Stage("align", Unit::View) {
    decl.scene = {"geometry",         "views[].camera",
                  "views[].image",    "views[].color_space",
                  "views[].segments", "views[].segment_parts"};
    decl.options = {"work_width"};
    decl.after = {"geometry"};
    decl.writes = {"ViewWork::photoMask", "ViewWork::warp", "ViewWork::fitMask",
                   "ViewWork::lightMask"};
  }

  bool compute(Context& ctx, const Reads& in, int v) override {
    ViewWork& view = ctx.views[v];
    const cv::Mat& photo = in.photo(v);
    const align::ViewAlignment a = align::alignView(photo, in.labels(v), in.segmentParts(v),
                                                    view.gbuffer.partId, view.gbuffer.coverage);
    view.photoMask = a.photoMask;
    view.warp = a.warp;
    view.fitMask = a.fitMask;
    view.lightMask = a.lightMask;
    for (const align::RegionMatch& r : a.regions)
      if (r.part < 0 && r.pixels > 0)
        spdlog::debug("view {}: region {} ({} px) matched no part (best IoU {:.2f})", v, r.label,
                      r.pixels, r.iou);
    return true;
  }
  void save(const Context& ctx, int v, Archive& a) const override {
    const ViewWork& view = ctx.views[v];
    a.put<int32_t>(static_cast<int32_t>(view.photoMask.size()));
    for (const auto& [part, mask] : view.photoMask) {
      a.put<int32_t>(part);
      a.putMat(mask);
      a.put(view.warp.at(part));
      a.putMat(view.fitMask.at(part));
    }
    a.putMat(view.lightMask);
  }
  bool load(Context& ctx, const Reads&, int v, Archive& a) override {
    ViewWork& view = ctx.views[v];
    const int n = a.get<int32_t>();
    for (int i = 0; i < n; ++i) {
      const int part = a.get<int32_t>();
      view.photoMask[part] = a.getMat();
      view.warp[part] = a.get<cv::Matx23d>();
      view.fitMask[part] = a.getMat();
    }
    view.lightMask = a.getMat();
    return true;
  }
};

// Every part's observations in every view first (for the views' relative exposure, estimated
// from the parts they share), then per part the view chooseView picks with exposure-corrected
// appearance, and its median colour divided by that view's exposure.
class ObserveStage : public DerivedStage {
 public:
  ObserveStage() : DerivedStage("observe", Unit::Part) {
    decl.scene = {"views[].camera", "views[].image", "views[].color_space"};
    decl.options = {"work_width"};
    decl.after = {"parts", "geometry", "align"};
    decl.writes = {"PartWork::view", "PartWork::pixels", "PartWork::median",
                   "PartWork::seen", "PartMode::Unseen", "Context::exposure (estimate)"};
  }

  bool compute(Context& ctx, const Reads& in, int u) override {
    if (obs_.empty()) observeAll(ctx, in);
    PartWork& p = ctx.parts[u];
    const std::vector<align::PartObservation>& obs = obs_[u];
    p.seen.clear();
    if (obs.empty()) {
      if (p.mode == PartMode::Fit) {
        p.mode = PartMode::Unseen;
        p.skipped = "not seen in any view (or its photo region was not found)";
      }
      return true;
    }
    const align::ViewChoice choice = align::chooseView(obs, ctx.exposure);
    for (size_t i = 0; i < obs.size(); ++i) {
      const align::PartObservation& o = obs[i];
      p.seen.push_back({o.view, o.pixels, o.meanCosine, choice.agreement[i], choice.scores[i],
                        maskConsistency(ctx, in, p, o.view, obs)});
      if (o.view == choice.view) {
        const float e = static_cast<float>(ctx.viewExposure(o.view));
        p.view = o.view;
        p.pixels = o.pixels;
        p.median = Vec3f(o.medianColor[0], o.medianColor[1], o.medianColor[2]) / e;
      }
    }
    return true;
  }
  void finish(Context&, const Reads&) override { obs_.clear(); }

 private:
  // How much of the part view v's M_aln covers, as the other views' M_aln say where the part is:
  // their points that v sees on the part, the share in v's M_aln (align::maskConsistency from
  // each other view to v, pooled); -1 where v sees none of them. A low share says v's photo
  // region misses the part (or another view's holds more than the part).
  static double maskConsistency(const Context& ctx, const Reads& in, const PartWork& p, int v,
                                const std::vector<align::PartObservation>& obs) {
    align::MaskConsistency all;
    const ViewWork& to = ctx.views[v];
    const Camera& camera = in.camera(v);
    for (const align::PartObservation& other : obs) {
      if (other.view == v) continue;
      const ViewWork& from = ctx.views[other.view];
      const align::MaskConsistency c =
          align::maskConsistency(p.id, from.fitMask.at(p.id), from.gbuffer.position,
                                 to.fitMask.at(p.id), to.gbuffer.position, to.gbuffer.partId,
                                 [&](const Vec3d& x, Vec2d* q) { return camera.project(x, q); });
      all.seen += c.seen;
      all.inside += c.inside;
      if (c.seen >= 50 && c.share() < 0.8)
        spdlog::warn(
            "observe: part {}: of the {} points of its aligned mask in view {} that view {} sees, "
            "{:.0f} % are in its aligned mask there (view {}'s photo region may miss the part)",
            p.name, c.seen, other.view, v, 100 * c.share(), v);
    }
    return all.share();
  }

  void observeAll(Context& ctx, const Reads& in) {
    obs_.assign(ctx.parts.size(), {});
    for (size_t u = 0; u < ctx.parts.size(); ++u) {
      const PartWork& p = ctx.parts[u];
      for (int v = 0; v < in.viewCount(); ++v) {
        const ViewWork& view = ctx.views[v];
        const auto it = view.fitMask.find(p.id);
        if (it == view.fitMask.end()) continue;
        const auto o = align::observePart(partPhoto(in.photo(v), view, p.id), it->second,
                                          view.gbuffer.normalShading, view.gbuffer.position,
                                          in.camera(v).position());
        if (!o) continue;
        obs_[u].push_back(*o);
        obs_[u].back().view = v;
      }
    }
    // emitters (saturated) and openings (the environment) say nothing about the exposure
    std::vector<std::vector<align::PartObservation>> surfaces;
    for (size_t u = 0; u < ctx.parts.size(); ++u)
      if (ctx.parts[u].mode != PartMode::Emitter && ctx.parts[u].mode != PartMode::Window)
        surfaces.push_back(obs_[u]);
    ctx.exposure = align::estimateExposures(surfaces, in.viewCount());
    if (in.viewCount() > 1) {
      std::string s;
      for (double e : ctx.exposure) s += fmt::format(" {:.3f}", e);
      spdlog::info("observe: exposure estimated from the parts the views share:{}", s);
    }
  }
  std::vector<std::vector<align::PartObservation>> obs_;  ///< per part, set by the first unit
};

// The scale pin: neutral albedos = photo medians x pin, with a pixel-weighted mean luminance of
// `mean_albedo` over the parts to be fitted (pipeline.hpp: the scale one photo cannot fix).
class PinStage : public DerivedStage {
 public:
  PinStage() : DerivedStage("pin") {
    decl.options = {"mean_albedo"};
    decl.after = {"parts", "observe"};
    decl.writes = {"Context::albedoPin"};
  }

  bool compute(Context& ctx, const Reads& in, int) override {
    double lum = 0, weight = 0;
    for (const PartWork& p : ctx.parts)
      if ((p.mode == PartMode::Fit || p.mode == PartMode::Homogeneous) && p.view >= 0) {
        lum += luminance(p.median) * p.pixels;
        weight += p.pixels;
      }
    ctx.albedoPin =
        (lum > 1e-9 && weight > 0) ? static_cast<float>(in.meanAlbedo() / (lum / weight)) : 1.0f;
    spdlog::info("pin: neutral albedo = photo median x {:.4g} (mean albedo {} over {:.0f} px)",
                 ctx.albedoPin, in.meanAlbedo(), weight);
    return true;
  }
};

}  // namespace

std::unique_ptr<Stage> makeAlignStage() {
  return std::make_unique<AlignStage>();
}
std::unique_ptr<Stage> makeObserveStage() {
  return std::make_unique<ObserveStage>();
}
std::unique_ptr<Stage> makePinStage() {
  return std::make_unique<PinStage>();
}

}  // namespace ps::pipeline
