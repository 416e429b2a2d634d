// The stages of the method in order (see pipeline.hpp); the outputs are in outputs.cpp.
#include "photoscene/pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <numeric>
#include <thread>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <opencv2/imgproc.hpp>

#include "context.hpp"
#include "photoscene/align.hpp"
#include "photoscene/core.hpp"
#include "photoscene/core/memory.hpp"
#include "photoscene/features.hpp"
#include "photoscene/io.hpp"
#include "photoscene/lighting.hpp"
#include "photoscene/select.hpp"

namespace ps {

namespace fs = std::filesystem;

Baseline parseBaseline(const std::string& name) {
  if (name.empty() || name == "none") return Baseline::None;
  if (name == "pixel-median") return Baseline::PixelMedian;
  if (name == "shading-median") return Baseline::ShadingMedian;
  throw InputError("--baseline", "", "expected none, pixel-median or shading-median, got '" + name + "'");
}

const char* baselineName(Baseline b) {
  switch (b) {
    case Baseline::PixelMedian: return "pixel-median";
    case Baseline::ShadingMedian: return "shading-median";
    default: return "none";
  }
}

const StageRecord* PipelineResult::stage(const std::string& name) const {
  for (const StageRecord& s : stages)
    if (s.name == name) return &s;
  return nullptr;
}

int PipelineResult::computedUnits() const {
  int n = 0;
  for (const StageRecord& s : stages) n += s.computed;
  return n;
}

namespace pipeline {

// Bump when a stage's algorithm changes so old cache entries are not reused.
constexpr uint64_t kCacheVersion = 6;
// The per-part fit's own version (its key, and so the stages after it): 2 = the spectral UV prior
// and `balanced` at 100 steps; 3 = the full-resolution steps after the coarse phase at a quarter of
// the learning rate; 4 = `balanced` at 40 steps, `fast` at 30.
constexpr uint64_t kFitVersion = 4;

PresetBudget PresetBudget::of(const std::string& preset) {
  PresetBudget b;
  // incident-light samples: below 4 per bin the grid's noise reads as texture and the UV fit
  // runs to a much finer scale (the sample's floor: 0.5 with 4 samples, 6.5 with 2)
  b.incidentSamples = 8;
  if (preset == "fast") {
    b.lightSpp = 16;
    b.incidentSamples = 4;
    b.incidentStride = 8;
    b.renderSpp = 32;
    b.refineCandidates = 5;
  } else if (preset == "paper") {
    b.lightSpp = 64;
    b.incidentSamples = 16;
    b.incidentStride = 4;
    b.renderSpp = 256;
    b.refineCandidates = 9;
  }
  return b;
}

const char* partModeName(PartMode m) {
  switch (m) {
    case PartMode::Fit: return "fit";
    case PartMode::Homogeneous: return "homogeneous";
    case PartMode::Fixed: return "fixed";
    case PartMode::Skip: return "skip";
    case PartMode::Emitter: return "emitter";
    case PartMode::Window: return "window";
    case PartMode::Unseen: return "unseen";
  }
  return "?";
}

cv::Mat ViewWork::partPhoto(int part) const {
  cv::Mat out;
  cv::warpAffine(photo, out, cv::Mat(warp.at(part)), photo.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  return out;
}

namespace {

// The testing hooks of pipeline.hpp: a failure or a pause (for a signal) at a stage's start.
void stageTestingHooks(const std::string& stage) {
  if (const char* f = std::getenv("PS_FAIL_AT_STAGE"); f && stage == f)
    throw Exception(
        fmt::format("PS_FAIL_AT_STAGE={}: failure injected into stage {} (a testing hook)", f,
                    stage),
        __FILE__, __LINE__, __func__);
  if (const char* p = std::getenv("PS_PAUSE_AT_STAGE"); p && stage == p) {
    if (const char* marker = std::getenv("PS_PAUSE_MARKER"); marker && *marker)
      std::ofstream(marker) << stage << '\n';
    spdlog::info("PS_PAUSE_AT_STAGE={}: waiting for SIGINT / SIGTERM (a testing hook)", p);
    for (int i = 0; i < 6000 && !interruptRequested(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    checkInterrupted();
  }
}

}  // namespace

StageScope::StageScope(Context& ctx, std::string name)
    : ctx_(ctx), exceptions_(std::uncaught_exceptions()) {
  rec_.name = std::move(name);
  checkInterrupted();
  spdlog::info("stage {}", rec_.name);
  stageTestingHooks(rec_.name);
}

StageScope::~StageScope() {
  rec_.seconds = timer_.seconds();
  rec_.peakMemoryMiB = peakMemoryMiB();
  if (std::uncaught_exceptions() > exceptions_)
    spdlog::info("stage {} stopped: {} computed, {} cached (kept in the stage cache)", rec_.name,
                 rec_.computed, rec_.cached);
  else
    spdlog::info("stage {} done: {} computed, {} cached, {:.2f} s, peak memory {:.0f} MiB",
                 rec_.name, rec_.computed, rec_.cached, rec_.seconds, rec_.peakMemoryMiB);
  // a stage run more than once (lights, incident) adds up
  for (StageRecord& r : ctx_.result.stages)
    if (r.name == rec_.name) {
      r.seconds += rec_.seconds;
      r.computed += rec_.computed;
      r.cached += rec_.cached;
      r.peakMemoryMiB = std::max(r.peakMemoryMiB, rec_.peakMemoryMiB);
      return;
    }
  ctx_.result.stages.push_back(rec_);
}

namespace {

// ---------------------------------------------------------------- serialisation helpers

void putVec3s(Archive& a, const std::vector<Vec3f>& v) {
  std::vector<float> f(v.size() * 3);
  for (size_t i = 0; i < v.size(); ++i)
    for (int c = 0; c < 3; ++c) f[3 * i + c] = v[i][c];
  a.putVector(f);
}

std::vector<Vec3f> getVec3s(Archive& a) {
  const std::vector<float> f = a.getVector<float>();
  std::vector<Vec3f> v(f.size() / 3);
  for (size_t i = 0; i < v.size(); ++i) v[i] = Vec3f(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
  return v;
}

void putMats(Archive& a, const std::vector<cv::Mat>& v) {
  a.put<uint64_t>(v.size());
  for (const cv::Mat& m : v) a.putMat(m);
}

std::vector<cv::Mat> getMats(Archive& a) {
  std::vector<cv::Mat> v(a.get<uint64_t>());
  for (cv::Mat& m : v) m = a.getMat();
  return v;
}

void putGBuffer(Archive& a, const GBuffer& g) {
  for (const cv::Mat* m : {&g.partId, &g.triangleId, &g.uv, &g.duvdx, &g.duvdy, &g.position, &g.normalGeo,
                           &g.normalShading, &g.tangent, &g.bitangent, &g.dpdu, &g.dpdv, &g.depth})
    a.putMat(*m);
  putMats(a, g.coverage);
  putMats(a, g.mask);
}

GBuffer getGBuffer(Archive& a) {
  GBuffer g;
  for (cv::Mat* m : {&g.partId, &g.triangleId, &g.uv, &g.duvdx, &g.duvdy, &g.position, &g.normalGeo,
                     &g.normalShading, &g.tangent, &g.bitangent, &g.dpdu, &g.dpdv, &g.depth})
    *m = a.getMat();
  g.coverage = getMats(a);
  g.mask = getMats(a);
  return g;
}

void putGrid(Archive& a, const IncidentLightGrid& g) {
  for (int v : {g.width, g.height, g.stride, g.thetaBins, g.phiBins}) a.put<int32_t>(v);
  putVec3s(a, g.radiance);
  a.putVector(g.valid);
  putVec3s(a, g.position);
  putVec3s(a, g.frameT);
  putVec3s(a, g.frameB);
  putVec3s(a, g.frameN);
}

IncidentLightGrid getGrid(Archive& a) {
  IncidentLightGrid g;
  for (int* v : {&g.width, &g.height, &g.stride, &g.thetaBins, &g.phiBins}) *v = a.get<int32_t>();
  g.radiance = getVec3s(a);
  g.valid = a.getVector<uint8_t>();
  g.position = getVec3s(a);
  g.frameT = getVec3s(a);
  g.frameB = getVec3s(a);
  g.frameN = getVec3s(a);
  return g;
}

void hashCamera(Hasher& h, const Camera& c) {
  h.add(c.width()).add(c.height()).add(c.fx()).add(c.fy()).add(c.cx()).add(c.cy());
  h.add(c.worldToCamera().data(), sizeof(double) * 16);
}

void hashVec(Hasher& h, const Vec3f& v) { h.add(v.x()).add(v.y()).add(v.z()); }

float luminance(const Vec3f& c) { return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z(); }

uint64_t partSeed(const Context& ctx, const std::string& part) {
  return Hasher().add(ctx.seed).add(std::string_view(part)).digest();
}

}  // namespace

// ---------------------------------------------------------------- materials

std::vector<PartMaterial> Context::neutralMaterials() const {
  std::vector<PartMaterial> mats;
  for (const PartWork& p : parts) {
    PartMaterial m = PartMaterial::defaultGray(p.name);
    if (p.mode == PartMode::Fixed) {
      m.albedo = p.albedo;
      m.roughness = p.roughness;
      m.metallic = p.metallic;
      m.specular = p.specular;
    } else if (p.mode == PartMode::Emitter) {
      m.albedo = Vec3f::Zero();
    } else if (p.mode == PartMode::Fit || p.mode == PartMode::Homogeneous) {
      m.albedo = (p.median * albedoPin).cwiseMin(0.95f).cwiseMax(0.005f);
      m.roughness = 0.7f;
    }
    mats.push_back(std::move(m));
  }
  return mats;
}

std::vector<PartMaterial> Context::fittedMaterials(int mapSize, bool withRefine) const {
  std::vector<PartMaterial> mats = neutralMaterials();
  for (const PartWork& p : parts) {
    PartMaterial& m = mats[p.id];
    const float as = withRefine ? p.albedoScale : 1.0f;
    const float rf = withRefine ? p.roughnessFactor : 1.0f;
    if (p.mode == PartMode::Homogeneous) {
      m.albedo = (p.albedo * as).cwiseMin(1.0f);
      m.roughness = std::clamp(p.roughness * rf, 0.0f, 1.0f);
    } else if (p.mode == PartMode::Fit) {
      MaterialGraph g = library->create(p.graph);
      g.setValues(p.values);
      const MaterialMaps maps = g.evaluate(mapSize, MapSet::of({MapKind::Albedo, MapKind::Normal, MapKind::Roughness}));
      m.albedoMap = FloatTexture(maps.albedo);
      m.normalMap = FloatTexture(maps.normal);
      m.roughnessMap = FloatTexture(maps.roughness);
      m.uv = p.uv.toTransform();
      m.albedoScale = as;
      if (withRefine) m.albedoOffset = p.albedoOffset;
      m.roughnessScale = p.roughnessScale * rf;
      m.roughness = p.roughness;
      m.fromFile = true;
    }
  }
  return mats;
}

// ---------------------------------------------------------------- geometry

void stageGeometry(Context& ctx) {
  StageScope stage(ctx, "geometry");
  const std::vector<PartMaterial> gray(ctx.scene.parts.size());
  const PathTracer tracer(ctx.scene, gray);
  const uint64_t objHash = hashFile(ctx.scene.desc.geometry);
  for (size_t v = 0; v < ctx.views.size(); ++v) {
    ViewWork& view = ctx.views[v];
    Hasher h;
    h.add(kCacheVersion).add(objHash);
    hashCamera(h, view.camera);
    for (const Part& p : ctx.scene.parts) h.add(std::string_view(p.name));
    view.geometryKey = h.digest();
    const std::string name = fmt::format("geometry-{}", v);
    if (auto hit = ctx.cache->load(name, view.geometryKey)) {
      view.gbuffer = getGBuffer(*hit);
      stage.cached();
      continue;
    }
    view.gbuffer = renderGBuffer(tracer, view.camera);
    Archive a;
    putGBuffer(a, view.gbuffer);
    ctx.cache->store(name, view.geometryKey, a);
    stage.computed();
  }
}

// ---------------------------------------------------------------- align

void stageAlign(Context& ctx) {
  StageScope stage(ctx, "align");
  for (size_t v = 0; v < ctx.views.size(); ++v) {
    ViewWork& view = ctx.views[v];
    const View& input = ctx.scene.views[v];
    Hasher h;
    h.add(kCacheVersion).add(view.geometryKey).add(view.photoKey);
    if (!view.labels.empty()) hashMat(h, view.labels);
    for (const auto& [label, part] : input.segmentParts) h.add(label).add(part);
    view.alignKey = h.digest();
    const std::string name = fmt::format("align-{}", v);
    if (auto hit = ctx.cache->load(name, view.alignKey)) {
      const int n = hit->get<int32_t>();
      for (int i = 0; i < n; ++i) {
        const int part = hit->get<int32_t>();
        view.photoMask[part] = hit->getMat();
        view.warp[part] = hit->get<cv::Matx23d>();
        view.fitMask[part] = hit->getMat();
      }
      view.lightMask = hit->getMat();
      stage.cached();
      continue;
    }
    // M_geo: the interior of each part (coverage ~1: no pixel mixes two parts)
    std::map<int, cv::Mat> geo = align::partMasks(view.gbuffer.partId);
    std::map<int, int> pinned = input.segmentParts;
    cv::Mat labels = view.labels;
    if (labels.empty()) labels = align::proposeRegions(view.photo, geo, &pinned);
    const align::MatchResult match = align::matchRegions(labels, geo, pinned);
    view.lightMask = cv::Mat::zeros(view.photo.size(), CV_8UC1);
    Archive a;
    a.put<int32_t>(static_cast<int32_t>(match.photoMasks.size()));
    for (const auto& [part, photoMask] : match.photoMasks) {
      if (!geo.count(part) || cv::countNonZero(photoMask) == 0) {
        a.put<int32_t>(part);
        a.putMat(photoMask);
        a.put(cv::Matx23d(1, 0, 0, 0, 1, 0));
        a.putMat(cv::Mat::zeros(photoMask.size(), CV_8UC1));
        continue;
      }
      const cv::Mat& geoMask = geo.at(part);
      const cv::Matx23d A = align::boxAffine(geoMask, photoMask);
      cv::Mat warpedPhotoMask;
      cv::warpAffine(photoMask, warpedPhotoMask, cv::Mat(A), geoMask.size(), cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
      cv::Mat interior;
      cv::threshold(view.gbuffer.coverage[part], interior, 0.99, 255, cv::THRESH_BINARY);
      interior.convertTo(interior, CV_8UC1);
      cv::Mat fit = geoMask & warpedPhotoMask & interior;
      if (cv::countNonZero(fit) == 0) fit = geoMask & warpedPhotoMask;  // thin parts: no interior
      view.photoMask[part] = photoMask;
      view.warp[part] = A;
      view.fitMask[part] = fit;
      // lighting: where the unwarped photo region and the geometry agree (no warp: the solve needs
      // the pixel's own geometry)
      view.lightMask |= geoMask & photoMask & interior;
      a.put<int32_t>(part);
      a.putMat(photoMask);
      a.put(A);
      a.putMat(fit);
    }
    a.putMat(view.lightMask);
    ctx.cache->store(name, view.alignKey, a);
    stage.computed();
    for (const align::RegionMatch& r : match.regions)
      if (r.part < 0 && r.pixels > 0)
        spdlog::debug("view {}: region {} ({} px) matched no part (best IoU {:.2f})", v, r.label, r.pixels, r.iou);
  }
  // per part: the view that sees it best, its aligned pixels and median colour
  for (PartWork& p : ctx.parts) {
    std::vector<align::PartObservation> obs;
    for (size_t v = 0; v < ctx.views.size(); ++v) {
      const ViewWork& view = ctx.views[v];
      auto it = view.fitMask.find(p.id);
      if (it == view.fitMask.end()) continue;
      const int pixels = cv::countNonZero(it->second);
      if (pixels == 0) continue;
      align::PartObservation o;
      o.view = static_cast<int>(v);
      o.pixels = pixels;
      double cosSum = 0;
      const Vec3d cam = view.camera.position();
      for (int y = 0; y < it->second.rows; ++y)
        for (int x = 0; x < it->second.cols; ++x) {
          if (!it->second.at<uint8_t>(y, x)) continue;
          const cv::Vec3f n = view.gbuffer.normalShading.at<cv::Vec3f>(y, x);
          const cv::Vec3f pos = view.gbuffer.position.at<cv::Vec3f>(y, x);
          Vec3d d(cam.x() - pos[0], cam.y() - pos[1], cam.z() - pos[2]);
          d.normalize();
          cosSum += std::abs(n[0] * d.x() + n[1] * d.y() + n[2] * d.z());
        }
      o.meanCosine = cosSum / pixels;
      o.medianColor = align::maskedMedian(view.partPhoto(p.id), it->second);
      obs.push_back(o);
    }
    if (obs.empty()) {
      if (p.mode == PartMode::Fit) {
        p.mode = PartMode::Unseen;
        p.skipped = "not seen in any view (or its photo region was not found)";
      }
      continue;
    }
    const align::ViewChoice choice = align::chooseView(obs);
    for (const align::PartObservation& o : obs)
      if (o.view == choice.view) {
        p.view = o.view;
        p.pixels = o.pixels;
        p.median = Vec3f(o.medianColor[0], o.medianColor[1], o.medianColor[2]);
      }
  }
  // the scale pin: neutral albedos = photo medians x pin, pixel-weighted mean luminance = meanAlbedo
  double lum = 0, weight = 0;
  for (const PartWork& p : ctx.parts)
    if ((p.mode == PartMode::Fit || p.mode == PartMode::Homogeneous) && p.view >= 0) {
      lum += luminance(p.median) * p.pixels;
      weight += p.pixels;
    }
  ctx.albedoPin = (lum > 1e-9 && weight > 0) ? static_cast<float>(ctx.options.meanAlbedo / (lum / weight)) : 1.0f;
}

// ---------------------------------------------------------------- lights

void stageLights(Context& ctx, bool fitted) {
  StageScope stage(ctx, fitted ? "lights1" : "lights0");
  const bool hasEnv = ctx.scene.lights.environment.has_value();
  const int nFree = static_cast<int>(ctx.freeLights.size()) + (hasEnv ? 1 : 0);
  Hasher h;
  h.add(kCacheVersion).add(fitted).add(ctx.budget.lightSpp).add(ctx.seed).add(ctx.albedoPin);
  for (const ViewWork& v : ctx.views) h.add(v.alignKey).add(v.photoKey);
  for (size_t k = 0; k < ctx.scene.lights.area.size(); ++k) {
    const AreaLight& l = ctx.scene.lights.area[k];
    hashVec(h, l.center);
    hashVec(h, l.edgeU);
    hashVec(h, l.edgeV);
    h.add(l.partId);
    const bool free = std::find(ctx.freeLights.begin(), ctx.freeLights.end(), int(k)) != ctx.freeLights.end();
    h.add(free);
    if (!free && l.radiance) hashVec(h, *l.radiance);
  }
  for (const PartWork& p : ctx.parts) {
    h.add(fitted ? p.fitKey : p.selectKey).add(static_cast<int>(p.mode));
    hashVec(h, p.median);
  }
  const uint64_t key = h.digest();
  (fitted ? ctx.lights1Key : ctx.lights0Key) = key;
  std::vector<Vec3d> intensity;
  std::vector<double> exposure(ctx.views.size(), 1.0);
  const std::string name = fitted ? "lights1" : "lights0";
  if (auto hit = ctx.cache->load(name, key)) {
    const std::vector<double> flat = hit->getVector<double>();
    exposure = hit->getVector<double>();
    for (size_t i = 0; i + 2 < flat.size(); i += 3) intensity.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
    stage.cached();
  } else if (nFree == 0) {
    stage.computed(0);  // every emitter has a given radiance: nothing to solve
  } else {
    const std::vector<PartMaterial> mats =
        fitted ? ctx.fittedMaterials(ctx.fitOptions.mapSize, true) : ctx.neutralMaterials();
    // the fixed emitters shine at their radiance; the free ones are rendered one at a time
    const PathTracer tracer(ctx.scene, mats);
    std::vector<uint8_t> isFree(ctx.scene.lights.area.size(), 0);
    for (int k : ctx.freeLights) isFree[k] = 1;
    std::vector<lighting::ViewLightData> data;
    for (size_t v = 0; v < ctx.views.size(); ++v) {
      checkInterrupted();
      const ViewWork& view = ctx.views[v];
      RenderOptions ro;
      ro.spp = ctx.budget.lightSpp;
      ro.seed = ctx.seed + 17 * v;
      const std::vector<cv::Mat> perLight = tracer.renderPerLight(view.camera, ro);
      lighting::ViewLightData d;
      d.photo = view.photo.clone();
      d.mask = view.lightMask.clone();
      cv::Mat fixed = cv::Mat::zeros(view.photo.size(), CV_32FC3);
      for (size_t k = 0; k < ctx.scene.lights.area.size(); ++k) {
        const auto& r = ctx.scene.lights.area[k].radiance;
        if (isFree[k]) d.perLight.push_back(perLight[k]);
        else if (r) fixed += perLight[k].mul(cv::Scalar((*r)[0], (*r)[1], (*r)[2]));
      }
      if (hasEnv) d.perLight.push_back(perLight.back());
      if (cv::countNonZero(fixed.reshape(1)) > 0) {
        // photo - fixed emitters, with saturated pixels left out before the subtraction
        cv::Mat sat;
        cv::inRange(view.photo, cv::Scalar::all(0.99), cv::Scalar::all(1e30), sat);
        cv::Mat anySat = sat;
        d.mask.setTo(0, anySat);
        d.photo -= fixed;
      }
      data.push_back(std::move(d));
    }
    lighting::SolveOptions so;
    so.perViewExposure = ctx.views.size() > 1;
    const lighting::LightSolution s = lighting::solveLights(data, so);
    spdlog::info("{}: {}", name, s.summary());
    intensity = s.intensity;
    exposure = s.exposure;
    Archive a;
    std::vector<double> flat;
    for (const Vec3d& x : intensity) flat.insert(flat.end(), {x.x(), x.y(), x.z()});
    a.putVector(flat);
    a.putVector(exposure);
    ctx.cache->store(name, key, a);
    stage.computed();
  }
  // apply: free area lights in order, then the environment
  for (size_t i = 0; i < ctx.freeLights.size() && i < intensity.size(); ++i)
    ctx.scene.lights.area[ctx.freeLights[i]].radiance = intensity[i].cast<float>();
  if (hasEnv && intensity.size() == ctx.freeLights.size() + 1) {
    ctx.scene.lights.environment->radiance = intensity.back().cast<float>();
  }
  ctx.exposure = exposure;
}

// ---------------------------------------------------------------- incident light

void stageIncident(Context& ctx, bool fitted) {
  StageScope stage(ctx, fitted ? "incident1" : "incident0");
  const std::vector<PartMaterial> mats =
      fitted ? ctx.fittedMaterials(ctx.fitOptions.mapSize, true) : ctx.neutralMaterials();
  std::unique_ptr<PathTracer> tracer;
  for (size_t v = 0; v < ctx.views.size(); ++v) {
    ViewWork& view = ctx.views[v];
    Hasher h;
    h.add(kCacheVersion).add(view.geometryKey).add(fitted ? ctx.lights1Key : ctx.lights0Key);
    h.add(ctx.budget.incidentSamples).add(ctx.budget.incidentStride).add(ctx.seed);
    for (const AreaLight& l : ctx.scene.lights.area)
      if (l.radiance) hashVec(h, *l.radiance);
    view.incidentKey = h.digest();
    const std::string name = fmt::format("{}-{}", fitted ? "incident1" : "incident0", v);
    if (auto hit = ctx.cache->load(name, view.incidentKey)) {
      view.grid = getGrid(*hit);
      stage.cached();
      continue;
    }
    if (!tracer) tracer = std::make_unique<PathTracer>(ctx.scene, mats);
    IncidentLightOptions o;
    o.stride = ctx.budget.incidentStride;
    o.samplesPerBin = ctx.budget.incidentSamples;
    o.render.seed = ctx.seed + 101 * v;
    view.grid = computeIncidentLight(*tracer, view.gbuffer, view.camera, o);
    Archive a;
    putGrid(a, view.grid);
    ctx.cache->store(name, view.incidentKey, a);
    stage.computed();
  }
}

// ---------------------------------------------------------------- select

void stageSelect(Context& ctx) {
  StageScope stage(ctx, "select");
  std::unique_ptr<ExemplarBank> bank;
  const std::string bankName = ExemplarBank::cacheFileName(*ctx.library, {});
  for (PartWork& p : ctx.parts) {
    checkInterrupted();
    if (p.mode != PartMode::Fit) continue;
    const ViewWork& view = ctx.views[p.view];
    const io::PartDesc* desc = nullptr;
    if (auto it = ctx.scene.desc.parts.find(p.name); it != ctx.scene.desc.parts.end()) desc = &it->second;
    const int minPixels = homogeneousThreshold(view.camera.width(), view.camera.height());
    Hasher h;
    h.add(kCacheVersion).add(view.alignKey).add(p.view).add(std::string_view(p.name));
    if (desc && desc->graph) h.add(std::string_view(*desc->graph));
    // the bank's file name carries its format version, the library's content hash and its
    // options: a new bank (or library) redoes the selections made with the old one
    h.add(std::string_view(bankName)).add(std::string_view("candidates"));
    p.selectKey = h.digest();
    const std::string name = "select-" + p.name;
    if (auto hit = ctx.cache->load(name, p.selectKey)) {
      p.graph = hit->getString();
      p.category = hit->getString();
      const int n = hit->get<int32_t>();
      p.runnersUp.clear();
      for (int i = 0; i < n; ++i) p.runnersUp.push_back(hit->getString());
      p.candidates.resize(hit->get<int32_t>());
      for (GraphVote& v : p.candidates) v = {hit->getString(), hit->getString(), hit->get<double>(), hit->get<int32_t>()};
      stage.cached();
    } else {
      p.runnersUp.clear();
      p.candidates.clear();
      if (desc && desc->graph) {
        p.graph = *desc->graph;
      } else if (cv::countNonZero(view.photoMask.at(p.id)) < minPixels) {
        p.graph = "homogeneous";
      } else {
        if (!bank) {
          bool cached = false;
          bank = std::make_unique<ExemplarBank>(
              ExemplarBank::loadOrBuild(*ctx.library, {}, ctx.options.bankCache, &cached));
          spdlog::info("exemplar bank: {} exemplars {}", bank->rows(), cached ? "loaded" : "built");
        }
        // the part's photo in the render frame, where the G-buffer UVs are: selectForPart unwarps
        // it into texture space and removes smooth shading before the kNN vote
        const cv::Mat& fit = view.fitMask.at(p.id);
        const GraphChoice c = cv::countNonZero(fit) > 0
                                  ? selectForPart(*bank, view.partPhoto(p.id), fit, view.gbuffer.uv)
                                  : selectForPart(*bank, view.photo, view.photoMask.at(p.id), cv::Mat());
        p.graph = c.graph;
        for (size_t i = 1; i < c.votes.size() && i < 4; ++i) p.runnersUp.push_back(c.votes[i].graph);
        double total = 0;
        for (const GraphVote& v : c.votes) total += v.weight;
        for (size_t i = 0; i < c.votes.size() && i < 5; ++i)
          p.candidates.push_back({c.votes[i].graph, c.votes[i].category, total > 0 ? c.votes[i].weight / total : 0,
                                  c.votes[i].count});
      }
      p.category = ctx.library->get(p.graph).category();
      Archive a;
      a.putString(p.graph);
      a.putString(p.category);
      a.put<int32_t>(static_cast<int32_t>(p.runnersUp.size()));
      for (const std::string& r : p.runnersUp) a.putString(r);
      a.put<int32_t>(static_cast<int32_t>(p.candidates.size()));
      for (const GraphVote& v : p.candidates) {
        a.putString(v.graph);
        a.putString(v.category);
        a.put(v.weight);
        a.put<int32_t>(v.count);
      }
      ctx.cache->store(name, p.selectKey, a);
      stage.computed();
    }
    if (p.category == "homogeneous") p.mode = PartMode::Homogeneous;
  }
}

// ---------------------------------------------------------------- homogeneous closed form

namespace {

// The render layer's image of a part with constant albedo `a` is I0 + a (.) D (per channel,
// exactly, for a dielectric: diffuse is linear in albedo, specular does not depend on it). So
// for a roughness the best homogeneous albedo is a closed form per channel; the roughness is
// searched over `candidates` values.
struct HomogeneousFit {
  Vec3f albedo = Vec3f::Constant(0.5f);
  float roughness = 0.7f;
  double loss = 0;
};

cv::Mat constantMap(const Vec3f& v) { return cv::Mat(4, 4, CV_32FC3, cv::Scalar(v.x(), v.y(), v.z())); }

HomogeneousFit fitHomogeneous(const PartGeometry& geo, const cv::Mat& photo, const std::vector<float>& roughnesses) {
  HomogeneousFit best;
  best.loss = std::numeric_limits<double>::infinity();
  cv::Scalar photoMean(0, 0, 0);
  for (const cv::Point& q : geo.pixels) {
    const cv::Vec3f c = photo.at<cv::Vec3f>(q);
    for (int k = 0; k < 3; ++k) photoMean[k] += c[k];
  }
  for (int k = 0; k < 3; ++k) photoMean[k] /= std::max<size_t>(1, geo.pixels.size());
  for (float r : roughnesses) {
    RenderLayerParams p;
    p.geometry = &geo;
    p.roughnessValue = r;
    p.albedo = constantMap(Vec3f::Zero());
    renderLayerForward(p);
    const cv::Mat i0 = p.image.clone();
    p.albedo = constantMap(Vec3f::Ones());
    renderLayerForward(p);
    const cv::Mat d = p.image - i0;
    cv::Scalar s0(0, 0, 0), sd(0, 0, 0);
    for (const cv::Point& q : geo.pixels) {
      const cv::Vec3f a = i0.at<cv::Vec3f>(q), b = d.at<cv::Vec3f>(q);
      for (int k = 0; k < 3; ++k) {
        s0[k] += a[k];
        sd[k] += b[k];
      }
    }
    Vec3f albedo;
    const double n = std::max<size_t>(1, geo.pixels.size());
    for (int k = 0; k < 3; ++k) {
      const double diffuse = sd[k] / n;
      albedo[k] = diffuse > 1e-9 ? static_cast<float>((photoMean[k] - s0[k] / n) / diffuse) : 0.5f;
    }
    albedo = albedo.cwiseMax(0.0f).cwiseMin(1.0f);
    const cv::Mat render = i0 + d.mul(cv::Scalar(albedo.x(), albedo.y(), albedo.z()));
    const double loss = statLoss(photo, render, geo.pixels, nullptr);
    if (loss < best.loss) best = {albedo, r, loss};
  }
  return best;
}

std::vector<float> roughnessGrid(int n) {
  std::vector<float> r;
  for (int i = 0; i < n; ++i) r.push_back(0.15f + 0.8f * i / std::max(1, n - 1));
  return r;
}

}  // namespace

// ---------------------------------------------------------------- fit (round 1)

void stageFit(Context& ctx) {
  StageScope stage(ctx, "fit");
  std::vector<int> todo;
  for (const PartWork& p : ctx.parts)
    if (p.mode == PartMode::Fit || p.mode == PartMode::Homogeneous) todo.push_back(p.id);
  // keys first (cheap), then the fits that miss the cache in parallel
  std::vector<int> missing;
  for (int id : todo) {
    PartWork& p = ctx.parts[id];
    const ViewWork& view = ctx.views[p.view];
    Hasher h;
    h.add(kCacheVersion).add(kFitVersion).add(p.selectKey).add(std::string_view(p.graph)).add(view.incidentKey);
    h.add(std::string_view(ctx.preset)).add(ctx.seed);
    h.add(ctx.options.maxFitIterations.value_or(-1));
    p.fitKey = h.digest();
    if (auto hit = ctx.cache->load("fit-" + p.name, p.fitKey)) {
      p.values = hit->getVector<float>();
      p.uv.rotation = hit->get<float>();
      p.uv.logScale = hit->get<float>();
      p.uv.offset.x() = hit->get<float>();
      p.uv.offset.y() = hit->get<float>();
      p.roughness = hit->get<float>();
      p.roughnessScale = hit->get<float>();
      for (int k = 0; k < 3; ++k) p.albedo[k] = hit->get<float>();
      p.loss = hit->get<double>();
      p.seconds = hit->get<double>();
      p.iterations = hit->get<int32_t>();
      p.history = hit->getVector<double>();
      stage.cached();
    } else {
      missing.push_back(id);
    }
  }
  Progress progress("fit", static_cast<int64_t>(missing.size()));
  parallelFor(0, static_cast<int64_t>(missing.size()), [&](int64_t i) {
    if (interruptRequested()) return;
    PartWork& p = ctx.parts[missing[i]];
    const ViewWork& view = ctx.views[p.view];
    Timer timer;
    const cv::Mat photo = view.partPhoto(p.id);
    const cv::Mat& mask = view.fitMask.at(p.id);
    const PartGeometry geo = preparePartGeometry(view.gbuffer, view.camera.position().cast<float>(), view.grid, mask, p.id);
    if (p.mode == PartMode::Homogeneous || geo.size() < 16) {
      const HomogeneousFit f = fitHomogeneous(geo, photo, roughnessGrid(ctx.budget.refineCandidates));
      p.mode = PartMode::Homogeneous;
      p.graph = "homogeneous";
      p.category = "homogeneous";
      p.albedo = f.albedo;
      p.roughness = f.roughness;
      p.loss = f.loss;
      p.iterations = 0;
      p.history.clear();
    } else {
      PartFitOptions o = ctx.fitOptions;
      o.seed = partSeed(ctx, p.name);
      if (ctx.options.maxFitIterations) o.maxIterations = std::min(o.maxIterations, *ctx.options.maxFitIterations);
      // Ctrl-C stops a fit between two steps (a `paper` fit of one part runs for minutes)
      o.onProgress = [](const PartFitProgress&) { return !interruptRequested(); };
      const TextureLossTarget target(photo, mask);
      const PartFitResult r = fitPart(ctx.library->get(p.graph), geo, photo, target, o);
      if (r.cancelled) return;  // not a result: nothing is stored, checkInterrupted below throws
      if (const char* debug = std::getenv("PS_DEBUG_DIR"); debug && *debug) {
        // photo over the fitted mask | the fit's render, for looking at what the fit did
        cv::Mat masked = cv::Mat::zeros(photo.size(), CV_32FC3), side;
        photo.copyTo(masked, mask);
        cv::hconcat(masked, r.render, side);
        fs::create_directories(debug);
        io::writeImage(fs::path(debug) / ("fit-" + p.name + ".png"), side);
      }
      p.values = r.values;
      p.uv = r.uv;
      p.roughness = r.roughness;
      p.roughnessScale = r.roughnessScale;
      p.loss = r.loss;
      p.iterations = r.iterations;
      p.history = r.history;
    }
    p.seconds = timer.seconds();
    Archive a;
    a.putVector(p.values);
    for (float f : {p.uv.rotation, p.uv.logScale, p.uv.offset.x(), p.uv.offset.y(), p.roughness, p.roughnessScale,
                    p.albedo.x(), p.albedo.y(), p.albedo.z()})
      a.put(f);
    a.put(p.loss);
    a.put(p.seconds);
    a.put<int32_t>(p.iterations);
    a.putVector(p.history);
    // the mode may have changed (too few pixels): the select key fixes it, so the key stays valid
    ctx.cache->store("fit-" + p.name, p.fitKey, a);
    spdlog::info("fit {}: {} ({}), loss {:.4f}, {} iterations, {:.1f} s", p.name, p.graph, p.category, p.loss,
                 p.iterations, p.seconds);
    progress.advance();
  });
  progress.finish();
  checkInterrupted();
  stage.computed(static_cast<int>(missing.size()));
  // a part fitted as homogeneous (cache hit) has no graph values
  for (int id : todo) {
    PartWork& p = ctx.parts[id];
    if (p.values.empty()) {
      p.mode = PartMode::Homogeneous;
      p.graph = p.category = "homogeneous";
    }
  }
}

// ---------------------------------------------------------------- baselines

void stageBaseline(Context& ctx) {
  StageScope stage(ctx, std::string("baseline-") + baselineName(ctx.options.baseline));
  for (PartWork& p : ctx.parts) {
    if (p.mode != PartMode::Fit && p.mode != PartMode::Homogeneous) continue;
    p.mode = PartMode::Homogeneous;
    p.graph = p.category = "homogeneous";
    p.roughness = 0.7f;
    p.values.clear();
    if (ctx.options.baseline == Baseline::PixelMedian) {
      p.albedo = (p.median * ctx.albedoPin).cwiseMin(1.0f);
    } else {
      // median over the part's pixels of photo / diffuse shading (the render with white albedo)
      const ViewWork& view = ctx.views[p.view];
      const cv::Mat photo = view.partPhoto(p.id);
      const PartGeometry geo = preparePartGeometry(view.gbuffer, view.camera.position().cast<float>(), view.grid,
                                                   view.fitMask.at(p.id), p.id);
      RenderLayerParams rp;
      rp.geometry = &geo;
      rp.roughnessValue = 1.0f;
      rp.specular = 0.0f;  // pure Lambert shading
      rp.albedo = constantMap(Vec3f::Ones());
      renderLayerForward(rp);
      std::vector<float> ratio[3];
      for (const cv::Point& q : geo.pixels) {
        const cv::Vec3f s = rp.image.at<cv::Vec3f>(q), c = photo.at<cv::Vec3f>(q);
        for (int k = 0; k < 3; ++k)
          if (s[k] > 1e-6f) ratio[k].push_back(c[k] / s[k]);
      }
      for (int k = 0; k < 3; ++k) {
        if (ratio[k].empty()) {
          p.albedo[k] = 0.5f;
          continue;
        }
        std::nth_element(ratio[k].begin(), ratio[k].begin() + ratio[k].size() / 2, ratio[k].end());
        p.albedo[k] = std::clamp(ratio[k][ratio[k].size() / 2], 0.0f, 1.0f);
      }
    }
    p.skipped.clear();
    stage.computed();
  }
}

// ---------------------------------------------------------------- refine (round 2)

void stageRefine(Context& ctx, int round) {
  StageScope stage(ctx, "refine");
  const std::string entry = fmt::format("refine{}-", round);
  std::vector<int> missing;
  for (PartWork& p : ctx.parts) {
    if (p.mode != PartMode::Fit && p.mode != PartMode::Homogeneous) continue;
    Hasher h;
    h.add(kCacheVersion).add(round).add(p.fitKey).add(ctx.views[p.view].incidentKey).add(ctx.budget.refineCandidates);
    p.refineKey = h.digest();
    if (auto hit = ctx.cache->load(entry + p.name, p.refineKey)) {
      p.albedoScale = hit->get<float>();
      for (int k = 0; k < 3; ++k) p.albedoOffset[k] = hit->get<float>();
      p.roughnessFactor = hit->get<float>();
      for (int k = 0; k < 3; ++k) p.albedo[k] = hit->get<float>();
      p.roughness = hit->get<float>();
      p.refineLoss = hit->get<double>();
      stage.cached();
    } else {
      missing.push_back(p.id);
    }
  }
  Progress progress("refine", static_cast<int64_t>(missing.size()));
  parallelFor(0, static_cast<int64_t>(missing.size()), [&](int64_t i) {
    if (interruptRequested()) return;
    PartWork& p = ctx.parts[missing[i]];
    const ViewWork& view = ctx.views[p.view];
    const cv::Mat photo = view.partPhoto(p.id);
    const PartGeometry geo = preparePartGeometry(view.gbuffer, view.camera.position().cast<float>(), view.grid,
                                                 view.fitMask.at(p.id), p.id);
    if (p.mode == PartMode::Homogeneous) {
      // homogeneous: the albedo (per channel, closed form) and roughness again under the new lights
      const HomogeneousFit f = fitHomogeneous(geo, photo, roughnessGrid(ctx.budget.refineCandidates));
      p.albedo = f.albedo;
      p.roughness = f.roughness;
      p.refineLoss = f.loss;
    } else {
      // textured: only one albedo scale and the roughness factor (the maps keep their pattern)
      MaterialGraph g = ctx.library->create(p.graph);
      g.setValues(p.values);
      const MaterialMaps maps = g.evaluate(ctx.fitOptions.mapSize, MapSet::of({MapKind::Albedo, MapKind::Normal}));
      double bestLoss = std::numeric_limits<double>::infinity();
      const int n = ctx.budget.refineCandidates;
      for (int c = 0; c < n; ++c) {
        const float factor = std::exp(std::log(0.5f) + (std::log(2.0f) - std::log(0.5f)) * c / std::max(1, n - 1));
        RenderLayerParams rp;
        rp.geometry = &geo;
        rp.uv = p.uv;
        rp.normal = maps.normal;
        rp.roughnessValue = std::clamp(p.roughness * factor, 0.02f, 1.0f);
        rp.albedo = cv::Mat::zeros(maps.albedo.size(), CV_32FC3);
        renderLayerForward(rp);
        const cv::Mat i0 = rp.image.clone();
        rp.albedo = maps.albedo;
        renderLayerForward(rp);
        const cv::Mat d = rp.image - i0;
        rp.albedo = cv::Mat(maps.albedo.size(), CV_32FC3, cv::Scalar::all(1));
        renderLayerForward(rp);
        const cv::Mat w = rp.image - i0;  // the diffuse response to a white albedo
        // the render is linear in the albedo (a dielectric): i0 + s (d + o (.) w) for the contract's
        // albedo = s (map + o). One scale s by least squares on the channel means, then the
        // per-channel offset o that matches each channel's mean: the pattern keeps its contrast, the
        // colour comes out right even where the graph's colour parameters could not reach it.
        double num = 0, den = 0;
        const cv::Mat& fm = view.fitMask.at(p.id);
        const cv::Scalar mp = cv::mean(photo, fm), m0 = cv::mean(i0, fm), md = cv::mean(d, fm), mw = cv::mean(w, fm);
        for (int k = 0; k < 3; ++k) {
          num += (mp[k] - m0[k]) * md[k];
          den += md[k] * md[k];
        }
        const float s = den > 1e-12 ? std::clamp(static_cast<float>(num / den), 0.25f, 4.0f) : 1.0f;
        Vec3f o = Vec3f::Zero();
        for (int k = 0; k < 3; ++k)
          if (mw[k] > 1e-9) o[k] = std::clamp(static_cast<float>((mp[k] - m0[k] - s * md[k]) / (s * mw[k])), -0.5f, 0.5f);
        const cv::Mat render = i0 + (d + w.mul(cv::Scalar(o.x(), o.y(), o.z()))) * s;
        const double loss = statLoss(photo, render, geo.pixels, nullptr);
        if (loss < bestLoss) {
          bestLoss = loss;
          p.albedoScale = s;
          p.albedoOffset = o;
          p.roughnessFactor = rp.roughnessValue / std::max(p.roughness, 1e-4f);
        }
      }
      p.refineLoss = bestLoss;
    }
    Archive a;
    a.put(p.albedoScale);
    for (int k = 0; k < 3; ++k) a.put(p.albedoOffset[k]);
    a.put(p.roughnessFactor);
    for (int k = 0; k < 3; ++k) a.put(p.albedo[k]);
    a.put(p.roughness);
    a.put(p.refineLoss);
    ctx.cache->store(entry + p.name, p.refineKey, a);
    progress.advance();
  });
  progress.finish();
  checkInterrupted();
  stage.computed(static_cast<int>(missing.size()));
}

// ---------------------------------------------------------------- set-up

namespace {

fs::path defaultBankCache() {
  if (const char* d = std::getenv("PS_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return fs::path(d) / "photoscene";
  if (const char* d = std::getenv("HOME"); d && *d) return fs::path(d) / ".cache/photoscene";
  return fs::temp_directory_path() / "photoscene-cache";
}

// Everything a run needs from the user, checked before anything is written.
void validate(Context& ctx) {
  const PipelineOptions& o = ctx.options;
  if (o.textureSize < 4 || o.textureSize > 16384)
    throw InputError("--texture-size", "", fmt::format("expected 4..16384, got {}", o.textureSize));
  ctx.scene = loadScene(o.scene);
  ctx.preset = o.preset.value_or(ctx.scene.desc.options.preset);
  if (ctx.preset != "fast" && ctx.preset != "balanced" && ctx.preset != "paper")
    throw InputError(o.scene.string(), "options.preset", "expected fast, balanced or paper, got '" + ctx.preset + "'");
  ctx.library = std::make_unique<GraphLibrary>(GraphLibrary::load());
  for (const auto& [name, part] : ctx.scene.desc.parts)
    if (part.graph) {
      const std::vector<std::string> names = ctx.library->names();
      if (!std::binary_search(names.begin(), names.end(), *part.graph))
        throw InputError(o.scene.string(), "parts." + name + ".graph",
                         "expected a graph of the library (`photoscene graphs --list`), got '" + *part.graph + "'");
    }
  ctx.seed = ctx.scene.desc.options.seed;
  ctx.budget = PresetBudget::of(ctx.preset);
  if (o.renderSpp) ctx.budget.renderSpp = *o.renderSpp;
  ctx.fitOptions = PartFitOptions::preset(ctx.preset);
}

void prepare(Context& ctx) {
  const Scene& scene = ctx.scene;
  // parts: what each one gets
  std::vector<uint8_t> emitter(scene.parts.size(), 0), window(scene.parts.size(), 0);
  for (const AreaLight& l : scene.lights.area)
    if (l.kind == AreaLight::Kind::Part && l.partId >= 0) emitter[l.partId] = 1;
  if (scene.lights.environment)
    for (int w : scene.lights.environment->windowParts) window[w] = 1;
  for (const Part& part : scene.parts) {
    PartWork p;
    p.id = part.id;
    p.name = part.name;
    const auto it = scene.desc.parts.find(part.name);
    if (emitter[part.id]) {
      p.mode = PartMode::Emitter;
      p.skipped = "emitter";
    } else if (window[part.id]) {
      p.mode = PartMode::Window;
      p.skipped = "window (an opening onto the environment)";
    } else if (it != scene.desc.parts.end() && it->second.skip) {
      p.mode = PartMode::Skip;
      p.skipped = "skip (scene.json)";
    } else if (it != scene.desc.parts.end() && it->second.fixed) {
      const io::HomogeneousDesc& f = *it->second.fixed;
      p.mode = PartMode::Fixed;
      p.skipped = "fixed (scene.json)";
      p.albedo = f.albedo.cast<float>();
      p.roughness = static_cast<float>(f.roughness);
      p.metallic = static_cast<float>(f.metallic);
      p.specular = static_cast<float>(f.specular);
    }
    ctx.parts.push_back(std::move(p));
  }
  for (size_t k = 0; k < scene.lights.area.size(); ++k)
    if (!scene.lights.area[k].radiance) ctx.freeLights.push_back(static_cast<int>(k));
  // views at the working resolution
  for (const View& input : scene.views) {
    ViewWork w;
    const int width = std::min(input.camera.width(), std::max(16, ctx.options.workWidth));
    const int height = std::max(1, static_cast<int>(std::lround(double(input.camera.height()) * width / input.camera.width())));
    w.camera = input.camera.resized(width, height);
    if (width == input.photo.cols && height == input.photo.rows)
      w.photo = input.photo;
    else
      cv::resize(input.photo, w.photo, cv::Size(width, height), 0, 0, cv::INTER_AREA);
    if (!input.segments.empty()) cv::resize(input.segments, w.labels, w.photo.size(), 0, 0, cv::INTER_NEAREST);
    Hasher h;
    hashMat(h, w.photo);
    w.photoKey = h.digest();
    ctx.views.push_back(std::move(w));
  }
}

}  // namespace

}  // namespace pipeline

PipelineResult runPipeline(const PipelineOptions& options) {
  using namespace pipeline;
  Timer total;
  InterruptGuard interrupts;
  ThreadLimit threads(options.threads);
  Context ctx;
  ctx.options = options;
  if (ctx.options.bankCache.empty()) ctx.options.bankCache = defaultBankCache();
  validate(ctx);  // bad input: nothing written yet
  prepare(ctx);
  fs::create_directories(options.out);
  ctx.cache = std::make_unique<StageCache>(options.useStageCache ? options.out / ".cache" : fs::path());
  ctx.result.out = options.out;
  ctx.result.preset = ctx.preset;
  spdlog::info("run: {} ({} views, {} parts, {} area lights{}), preset {}{}", options.scene.string(),
               ctx.scene.views.size(), ctx.scene.parts.size(), ctx.scene.lights.area.size(),
               ctx.scene.lights.environment ? " + environment" : "", ctx.preset,
               options.baseline == Baseline::None ? "" : fmt::format(", baseline {}", baselineName(options.baseline)));

  stageGeometry(ctx);
  stageAlign(ctx);
  stageLights(ctx, false);
  stageIncident(ctx, false);
  if (options.baseline == Baseline::None) {
    stageSelect(ctx);
    stageFit(ctx);
    // each part's albedo scale under the first lights, so that a part whose fit missed its mean
    // does not bend the global light solve; then the solve, new grids, and the second round
    stageRefine(ctx, 0);
    stageLights(ctx, true);
    stageIncident(ctx, true);
    stageRefine(ctx, 1);
  } else {
    stageBaseline(ctx);  // under lights0, the lighting both start from
  }
  stageExport(ctx);
  stageMetrics(ctx, total.seconds());
  stageReport(ctx);

  ctx.result.totalSeconds = total.seconds();
  for (const AreaLight& l : ctx.scene.lights.area) {
    ctx.result.lightNames.push_back(l.name);
    ctx.result.lightRadiance.push_back(l.radiance.value_or(Vec3f::Zero()).cast<double>());
  }
  if (ctx.scene.lights.environment) {
    ctx.result.lightNames.push_back("environment");
    ctx.result.lightRadiance.push_back(ctx.scene.lights.environment->radiance.cast<double>());
  }
  ctx.result.exposure = ctx.exposure;
  ctx.result.peakMemoryMiB = peakMemoryMiB();
  spdlog::info("run: {:.1f} s, peak memory {:.0f} MiB", ctx.result.totalSeconds,
               ctx.result.peakMemoryMiB);
  return ctx.result;
}

}  // namespace ps
