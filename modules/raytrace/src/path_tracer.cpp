#include "photoscene/raytrace/path_tracer.hpp"

#include "photoscene/core/log.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

#include "photoscene/core/color.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/core/parallel.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/raytrace/sampler.hpp"
#include "photoscene/scene/distribution.hpp"

namespace ps {

namespace {
inline float powerHeuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0f;
}
inline float offsetScale(const Vec3f& p) {
  return 2e-5f * (1.0f + p.cwiseAbs().maxCoeff());
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// The prepared lights

struct PathTracer::Lights {
  /// Clones of scene.lights.all(), preprocessed against the mesh (their scale is read from the
  /// scene at every render call).
  std::vector<std::unique_ptr<Light>> lights;
  struct Prim {
    int light = -1, prim = -1;  // light index, the light's own primitive
  };
  std::vector<Prim> meshTriEmitter;     // mesh triangle -> emitter
  std::vector<Prim> shapePrim;          // light-shape primitive (geometry 1) -> emitter
  std::vector<uint8_t> meshTriOpening;  // mesh triangle of an opening part (rays pass through)
  std::vector<int> infinite;            // lights that escaped rays see
};

// What shines in one render call.
struct ActiveLights {
  std::vector<Vec3f> scale;  // per light (zero: off)
  std::vector<uint8_t> on;
  Distribution1D select;  // over the lights, half by power, half uniform
  /// Per-light mode (renderPerLight): every light shines at unit scale into its own image and
  /// gets its own next-event sample at every vertex (selection probability 1, as when it is
  /// rendered alone); neeOn[i]: light i has power to sample (else BSDF sampling alone finds it).
  bool perLight = false;
  std::vector<uint8_t> neeOn;
  float selectPdf(int i) const { return perLight ? 1.0f : select.pdf(i); }
};

PathTracer::PathTracer(const Scene& scene, const std::vector<PartMaterial>& materials)
    : scene_(scene), materials_(materials), gray_(PartMaterial::defaultGray("default")) {
  Timer timer;
  const Mesh& mesh = scene.mesh;
  lights_ = std::make_unique<Lights>();
  Lights& L = *lights_;
  const std::vector<const Light*> sceneLights = scene.lights.all();
  const int nl = static_cast<int>(sceneLights.size());
  std::vector<Vec3f> shapeVertices;
  for (int i = 0; i < nl; ++i) {
    L.lights.push_back(sceneLights[i]->clone());
    const size_t first = shapeVertices.size();
    L.lights[i]->shapes(&shapeVertices, nullptr);
    for (size_t k = first; k + 2 < shapeVertices.size(); k += 3)
      L.shapePrim.push_back({i, static_cast<int>((k - first) / 3)});
    if (L.lights[i]->isInfinite()) L.infinite.push_back(i);
  }
  accel_ = std::make_unique<RayAccel>(mesh, shapeVertices);
  const size_t nt = mesh.numTriangles();
  triNormal_.resize(nt);
  triDpdu_.resize(nt);
  triDpdv_.resize(nt);
  for (size_t t = 0; t < nt; ++t) {
    triNormal_[t] = mesh.faceNormal(static_cast<int>(t));
    const auto& f = mesh.triangles[t];
    const Vec3f e1 = mesh.positions[f[1]] - mesh.positions[f[0]],
                e2 = mesh.positions[f[2]] - mesh.positions[f[0]];
    const Vec2f d1 = mesh.cornerUvs[3 * t + 1] - mesh.cornerUvs[3 * t],
                d2 = mesh.cornerUvs[3 * t + 2] - mesh.cornerUvs[3 * t];
    const float det = d1.x() * d2.y() - d1.y() * d2.x();
    if (std::abs(det) > 1e-14f && std::isfinite(det)) {
      const float inv = 1.0f / det;
      triDpdu_[t] = (e1 * d2.y() - e2 * d1.y()) * inv;
      triDpdv_[t] = (e2 * d1.x() - e1 * d2.x()) * inv;
      if (!triDpdu_[t].allFinite() || !triDpdv_[t].allFinite())
        triDpdu_[t] = triDpdv_[t] = Vec3f::Zero();
    } else {
      triDpdu_[t] = triDpdv_[t] = Vec3f::Zero();
    }
  }
  // openings (windows): rays pass through their triangles
  windowPart_.assign(scene.parts.size(), 0);
  for (int p : scene.lights.openingParts())
    if (p >= 0 && p < static_cast<int>(windowPart_.size())) windowPart_[p] = 1;
  L.meshTriOpening.assign(nt, 0);
  int openingTris = 0;
  for (size_t t = 0; t < nt; ++t) {
    const int part = mesh.partIds[t];
    if (part >= 0 && part < static_cast<int>(windowPart_.size()) && windowPart_[part] &&
        mesh.area(static_cast<int>(t)) > 0 && !triNormal_[t].isZero()) {
      L.meshTriOpening[t] = 1;
      ++openingTris;
    }
  }
  // each emitting part belongs to the last light that claims it
  LightScene ls;
  ls.mesh = &mesh;
  ls.partEmitter.assign(scene.parts.size(), -1);
  for (int i = 0; i < nl; ++i)
    for (int p : L.lights[i]->emittingParts())
      if (p >= 0 && p < static_cast<int>(ls.partEmitter.size())) ls.partEmitter[p] = i;
  L.meshTriEmitter.assign(nt, {});
  size_t emitterTris = L.shapePrim.size();
  for (int i = 0; i < nl; ++i) {
    ls.self = i;
    L.lights[i]->preprocess(ls);
    const std::vector<int> tris = L.lights[i]->emittingTriangles();
    for (size_t k = 0; k < tris.size(); ++k)
      if (tris[k] >= 0 && tris[k] < static_cast<int>(nt))
        L.meshTriEmitter[tris[k]] = {i, static_cast<int>(k)};
    emitterTris += tris.size();
  }
  setupSeconds_ = timer.seconds();
  spdlog::info(
      "path tracer: {} triangles, BVH {:.3f}s, {} lights, {} emitter triangles, {} window "
      "triangles, setup "
      "{:.3f}s",
      nt, accel_->buildSeconds(), nl, emitterTris, openingTris, setupSeconds_);
}

PathTracer::~PathTracer() = default;

double PathTracer::buildSeconds() const {
  return accel_->buildSeconds();
}

const PartMaterial& PathTracer::material(int part) const {
  if (part >= 0 && part < static_cast<int>(materials_.size())) return materials_[part];
  return gray_;
}

bool PathTracer::isWindowPart(int part) const {
  return part >= 0 && part < static_cast<int>(windowPart_.size()) && windowPart_[part];
}

SurfacePoint PathTracer::surfacePoint(const RayHit& hit) const {
  const Mesh& mesh = scene_.mesh;
  SurfacePoint sp;
  const int t = hit.prim;
  sp.triangle = t;
  sp.part = mesh.partIds[t];
  const auto& f = mesh.triangles[t];
  const float b0 = 1.0f - hit.b1 - hit.b2;
  sp.p = b0 * mesh.positions[f[0]] + hit.b1 * mesh.positions[f[1]] + hit.b2 * mesh.positions[f[2]];
  sp.ng = triNormal_[t];
  Vec3f ns = b0 * mesh.cornerNormals[3 * t] + hit.b1 * mesh.cornerNormals[3 * t + 1] +
             hit.b2 * mesh.cornerNormals[3 * t + 2];
  const float nl = ns.norm();
  ns = (nl > 1e-8f && std::isfinite(nl)) ? Vec3f(ns / nl) : sp.ng;
  if (sp.ng.isZero()) sp.ng = ns;
  if (ns.dot(sp.ng) < 0) ns = -ns;  // shading normal on the geometric normal's side
  sp.ns = ns;
  sp.uv = b0 * mesh.cornerUvs[3 * t] + hit.b1 * mesh.cornerUvs[3 * t + 1] +
          hit.b2 * mesh.cornerUvs[3 * t + 2];
  sp.dpdu = triDpdu_[t];
  sp.dpdv = triDpdv_[t];
  return sp;
}

Vec3f shadingFrame(const SurfacePoint& sp, const PartMaterial& material, const MaterialSample& ms,
                   const Vec3f& wo, Vec3f* T, Vec3f* B) {
  const bool back = sp.ng.dot(wo) < 0;
  const Vec3f ng = back ? Vec3f(-sp.ng) : sp.ng;
  const Vec3f n0 = back ? Vec3f(-sp.ns) : sp.ns;
  Vec3f t, b;
  tangentFrame(sp.dpdu, sp.dpdv, n0, material.uv, &t, &b);
  Vec3f n = n0;
  if (!material.normalMap.empty() && ms.normalTs != Vec3f(0, 0, 1)) {
    const Vec3f nm = ms.normalTs.x() * t + ms.normalTs.y() * b + ms.normalTs.z() * n0;
    const float l = nm.norm();
    if (l > 1e-6f && std::isfinite(l)) n = nm / l;
  }
  if (n.dot(wo) < 1e-4f) n = n0;
  if (n.dot(wo) < 1e-4f) n = ng;
  // re-orthonormalise the tangent frame around n, keeping the handedness of (t, b)
  Vec3f tt = t - n * n.dot(t);
  const float tl = tt.norm();
  if (tl > 1e-6f && std::isfinite(tl)) {
    tt /= tl;
    Vec3f bb = n.cross(tt);
    if (bb.dot(b) < 0) bb = -bb;
    *T = tt;
    *B = bb;
  } else {
    orthonormalBasis(n, *T, *B);
  }
  return n;
}

// ---------------------------------------------------------------------------------------------
// Path tracing

bool RenderOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (spp < 1) return fail("spp must be >= 1");
  if (maxBounces < 0 || maxDiffuseBounces < 0 || maxGlossyBounces < 0)
    return fail("bounce limits must be >= 0");
  if (rouletteDepth < 0) return fail("rouletteDepth must be >= 0");
  if (!(filterWidth > 0) || filterWidth > 16) return fail("filterWidth must be in (0, 16]");
  if (clampSample < 0) return fail("clampSample must be >= 0");
  if (!(adaptiveThreshold >= 0) || !std::isfinite(adaptiveThreshold))
    return fail("adaptiveThreshold must be finite and >= 0");
  if (adaptiveMinSpp < 2) return fail("adaptiveMinSpp must be >= 2");
  return true;
}

namespace {

// What a camera path's first scattering point looks like, for the denoiser's guides.
struct FirstHit {
  bool surface = false;  // a surface that reflects (not an emitter, not the environment)
  Vec3f albedo = Vec3f::Ones(), normal = Vec3f::Zero(), position = Vec3f::Zero();
};

struct Tracer final : LightRays {
  const PathTracer& pt;
  const PathTracer::Lights& L;
  const ActiveLights& act;
  const RenderOptions& opt;
  const RayAccel& accel;
  mutable uint64_t rays = 0;

  Tracer(const PathTracer& pt_, const PathTracer::Lights& L_, const ActiveLights& act_,
         const RenderOptions& opt_, const RayAccel& accel_)
      : pt(pt_), L(L_), act(act_), opt(opt_), accel(accel_) {}

  // Closest non-opening hit; opening parts (windows) are passed through.
  RayHit traceThroughWindows(const Vec3f& org, const Vec3f& dir, LightEscape* esc) const {
    float tnear = 0;
    for (int k = 0; k < 16; ++k) {
      const RayHit hit = accel.intersect(org, dir, tnear);
      ++rays;
      if (!hit.valid()) return hit;
      if (hit.geom == 0 && L.meshTriOpening[hit.prim]) {
        if (!esc->crossedOpening) {
          esc->crossedOpening = true;
          esc->triangle = hit.prim;
          esc->distance = hit.t;
        }
        tnear = hit.t * (1.0f + 1e-5f) + 1e-6f;
        continue;
      }
      return hit;
    }
    return RayHit();  // pathological stack of windows: treat as escaped
  }

  // LightRays
  bool unoccluded(const Vec3f& org, const Vec3f& y) const override {
    ++rays;
    const Vec3f d = y - org;
    const float len = d.norm();
    if (!(len > 0)) return false;
    return !accel.occluded(org, d / len, 0.0f, len * (1.0f - 1e-4f));
  }
  bool unoccludedToInfinity(const Vec3f& org, const Vec3f& dir) const override {
    ++rays;
    return !accel.occluded(org, dir, 0.0f, std::numeric_limits<float>::infinity());
  }
  bool escapesThroughOpenings(const Vec3f& org, const Vec3f& dir, LightEscape* esc) const override {
    return !traceThroughWindows(org, dir, esc).valid();
  }

  struct LightSample {
    Vec3f wi, Le;
    float pdf = 0, dist = 0;
    bool delta = false;
  };

  // Picks a light with uSel (the remapped number goes on to the light), samples it from x and
  // tests visibility from `org` (x offset off the surface). False when nothing visible was
  // sampled.
  bool sampleVisibleLight(const Vec3f& x, const Vec3f& org, const Vec3f& ngo, float uSel,
                          const Vec2f& uPt, LightSample* ls, int* light) const {
    if (act.select.empty()) return false;
    float selPdf = 0, uRe = 0;
    const int i = act.select.sample(uSel, &selPdf, &uRe);
    *light = i;
    return sampleVisible(i, selPdf, x, org, ngo, uRe, uPt, ls);
  }

  // Samples light i (picked with probability selPdf; u remapped into it) from x, visibility
  // tested from `org`.
  bool sampleVisible(int i, float selPdf, const Vec3f& x, const Vec3f& org, const Vec3f& ngo,
                     float u, const Vec2f& uPt, LightSample* ls) const {
    const float uRe = std::min(u, 0.99999994f);
    LightSampleContext ctx;
    ctx.p = x;
    ctx.n = ngo;
    ctx.org = org;
    ctx.selectionPdf = selPdf;
    ctx.rays = this;
    LightLiSample s;
    if (!L.lights[i]->sampleLi(ctx, uRe, uPt, &s)) return false;
    ls->wi = s.wi;
    ls->pdf = s.pdf;
    ls->dist = s.dist;
    ls->Le = s.L.cwiseProduct(act.scale[i]);
    ls->delta = L.lights[i]->isDeltaPosition();
    return ls->Le.maxCoeff() > 0;
  }

  // The light-sampling pdf at x (selection included) of light i for a ray that found it;
  // `alone`: as sampled on its own (selection probability 1, PathTracer::sampleDirectLight).
  float lightPdf(int i, const Vec3f& x, const LightHit& hit, bool alone = false) const {
    LightSampleContext ctx;
    ctx.p = x;
    ctx.selectionPdf = alone ? 1.0f : act.selectPdf(i);
    return L.lights[i]->pdfLi(ctx, hit);
  }

  // The MIS weight of emission from light i found by the ray leaving prevPos: on the first ray,
  // against sampleDirectLight's samples when the caller gave the first ray's density (firstPdf),
  // else 1; later, against next-event estimation from the last vertex.
  float emissionWeight(int i, int depth, float firstPdf, float prevPdf, bool neeOn,
                       const Vec3f& prevPos, const LightHit& lh) const {
    if (depth == 0)
      return firstPdf > 0 ? powerHeuristic(firstPdf, lightPdf(i, prevPos, lh, true)) : 1.0f;
    return neeOn && prevPdf > 0 ? powerHeuristic(prevPdf, lightPdf(i, prevPos, lh)) : 1.0f;
  }

  // Sample dimensions: 2D 0 is the pixel position; bounce b uses 1D dimensions 4b .. 4b + 2
  // (light pick, BSDF lobe, roulette) and 2D dimensions 1 + 2b, 2 + 2b (light point, BSDF
  // direction), the same for every sample of a pixel (so each is stratified across samples).
  //
  // perLight (act.perLight only): one sum per light, where every contribution goes to the
  // light it came from (emission found by BSDF sampling to the light that was hit, next-event
  // samples of each light to that light); the return value is then their sum.
  template <class Sampler>
  Vec3f path(Vec3f org, Vec3f dir, const Sampler& smp, Vec3f* perLight = nullptr,
             FirstHit* first = nullptr, float firstPdf = 0, AlbedoSensitivity* sens = nullptr) {
    Vec3f Lsum = Vec3f::Zero(), beta = Vec3f::Ones();
    // the scatterings so far (sens only): part and the diffuse share of its BSDF value there
    constexpr int kMaxVertices = 32;
    std::array<int, kMaxVertices> vertexPart{};
    std::array<Vec3f, kMaxVertices> vertexShare;
    int vertices = 0;
    auto add = [&](int light, const Vec3f& c) {
      Lsum += c;
      if (perLight) perLight[light] += c;
      if (sens)
        for (int k = 0; k < vertices; ++k) sens->add(vertexPart[k], c.cwiseProduct(vertexShare[k]));
    };
    // the share of a BSDF value f that its diffuse lobe carries (per channel, in [0, 1])
    auto diffuseShare = [](const Vec3f& f, const Vec3f& fSpecular) {
      Vec3f s;
      for (int c = 0; c < 3; ++c)
        s[c] = f[c] > 0 ? std::clamp((f[c] - fSpecular[c]) / f[c], 0.0f, 1.0f) : 0.0f;
      return s;
    };
    Vec3f prevPos =
        org;  // the last scattering point (MIS pdfs of light strategies are taken there)
    float prevPdf = 0;
    bool terminateAfterHit = false;
    int bounce = 0, diffuse = 0, glossy = 0;
    const bool nee = opt.nextEventEstimation && (act.perLight || !act.select.empty());
    // whether light i was also sampled by next-event estimation (then hits are MIS-weighted)
    auto neeFor = [&](int i) { return nee && (!act.perLight || act.neeOn[i]); };
    for (int depth = 0;; ++depth) {
      LightEscape esc;
      const RayHit hit = traceThroughWindows(org, dir, &esc);
      if (!hit.valid()) {
        for (int i : L.infinite) {
          if (!act.on[i]) continue;
          LightHit lh;
          lh.dir = dir;
          lh.escape = esc;
          const Vec3f Le = L.lights[i]->L(lh).cwiseProduct(act.scale[i]);
          // infinite lights are not in sampleDirectLight: the first ray alone finds them
          const float w = emissionWeight(i, depth, 0.0f, prevPdf, neeFor(i), prevPos, lh);
          add(i, beta.cwiseProduct(Le) * w);
        }
        break;
      }
      // emission
      const PathTracer::Lights::Prim em =
          hit.geom == 1 ? L.shapePrim[hit.prim] : L.meshTriEmitter[hit.prim];
      if (em.light >= 0) {
        LightHit lh;
        lh.dir = dir;
        lh.t = hit.t;
        lh.primitive = em.prim;
        const Vec3f Le = L.lights[em.light]->L(lh).cwiseProduct(act.scale[em.light]);
        if (Le.maxCoeff() > 0) {
          const float w =
              emissionWeight(em.light, depth, firstPdf, prevPdf, neeFor(em.light), prevPos, lh);
          add(em.light, beta.cwiseProduct(Le) * w);
        }
      }
      if (terminateAfterHit || hit.geom == 1) break;  // rectangle emitters reflect nothing

      const SurfacePoint sp = pt.surfacePoint(hit);
      const PartMaterial& mat = pt.material(sp.part);
      const MaterialSample ms = mat.evaluate(sp.uv);
      if (depth == 0 && first && em.light < 0) {  // an emitter is no surface to filter
        first->surface = true;
        first->albedo = (ms.diffuseColor() + ms.f0()).cwiseMax(0.0f).cwiseMin(1.0f);
        first->normal = sp.ns.dot(dir) > 0 ? Vec3f(-sp.ns) : sp.ns;
        first->position = sp.p;
      }
      const MicrofacetBsdf bsdf(ms.diffuseColor(), ms.f0(), ms.roughness, opt.principledDiffuse);
      if (bsdf.black()) break;
      const Vec3f wo = -dir;
      Vec3f T, B;
      const Vec3f N = shadingFrame(sp, mat, ms, wo, &T, &B);
      const Vec3f ngo = sp.ng.dot(wo) >= 0 ? sp.ng : Vec3f(-sp.ng);
      auto toLocal = [&](const Vec3f& w) { return Vec3f(w.dot(T), w.dot(B), w.dot(N)); };
      const Vec3f woL = toLocal(wo);
      if (woL.z() <= 0) break;
      const Vec3f orgNext = sp.p + ngo * offsetScale(sp.p);
      const uint32_t d1 = 4u * static_cast<uint32_t>(depth),
                     d2 = 1u + 2u * static_cast<uint32_t>(depth);

      if (nee) {
        auto shadeSample = [&](int light, const LightSample& ls) {
          const Vec3f wiL = toLocal(ls.wi);
          const Vec3f f = bsdf.eval(woL, wiL);
          if (f.maxCoeff() > 0) {
            const float bp = bsdf.pdf(woL, wiL);
            const float w = ls.delta ? 1.0f : powerHeuristic(ls.pdf, bp);
            const Vec3f c = beta.cwiseProduct(f).cwiseProduct(ls.Le) * (wiL.z() * w / ls.pdf);
            add(light, c);
            if (sens)  // this vertex's BSDF is in it too
              sens->add(sp.part, c.cwiseProduct(diffuseShare(f, bsdf.evalSpecular(woL, wiL))));
          }
        };
        LightSample ls;
        if (act.perLight) {
          // every light its own sample, from the same numbers as when it is rendered alone
          const float u = smp.get1D(d1);
          const Vec2f uPt = smp.get2D(d2);
          for (size_t i = 0; i < act.neeOn.size(); ++i)
            if (act.neeOn[i] &&
                sampleVisible(static_cast<int>(i), 1.0f, sp.p, orgNext, ngo, u, uPt, &ls))
              shadeSample(static_cast<int>(i), ls);
        } else {
          int light = -1;
          if (sampleVisibleLight(sp.p, orgNext, ngo, smp.get1D(d1), smp.get2D(d2), &ls, &light))
            shadeSample(light, ls);
        }
      }

      BsdfSample bs;
      const float uL = smp.get1D(d1 + 1);
      const Vec2f ub = smp.get2D(d2 + 1);
      if (!bsdf.sample(woL, uL, ub.x(), ub.y(), &bs)) break;
      const Vec3f wi = bs.wi.x() * T + bs.wi.y() * B + bs.wi.z() * N;
      if (wi.dot(ngo) <= 0) break;  // below the geometric surface
      beta = beta.cwiseProduct(bs.f) * (bs.wi.z() / bs.pdf);
      if (!beta.allFinite() || beta.maxCoeff() <= 0) break;
      if (sens && vertices < kMaxVertices) {
        vertexPart[vertices] = sp.part;
        vertexShare[vertices] = diffuseShare(bs.f, bsdf.evalSpecular(woL, bs.wi));
        ++vertices;
      }
      prevPdf = bs.pdf;
      prevPos = sp.p;

      ++bounce;
      const bool diffuseLabel = !bs.specular || bsdf.alpha() >= 1.0f;
      if (diffuseLabel)
        ++diffuse;
      else
        ++glossy;
      if (bounce >= opt.maxBounces || (diffuseLabel && diffuse >= opt.maxDiffuseBounces) ||
          (!diffuseLabel && glossy >= opt.maxGlossyBounces))
        terminateAfterHit = true;
      if (bounce >= opt.rouletteDepth) {
        const float q = std::min(1.0f, beta.maxCoeff());
        if (q < 1.0f) {
          if (smp.get1D(d1 + 2) >= q) break;
          beta /= q;
        }
      }
      org = orgNext;
      dir = wi.normalized();
    }
    return Lsum;
  }
};

// Separable pixel filter importance sampling (Cycles: Blackman-Harris over twice the width).
class FilterSampler {
 public:
  FilterSampler(PixelFilter f, float width) {
    if (f == PixelFilter::Box) {
      box_ = true;
      half_ = 0.5f * width;
      return;
    }
    const float w = 2.0f * width;  // Cycles doubles the width of Blackman-Harris
    half_ = 0.5f * w;
    const int n = 1024;
    cdf_.assign(n + 1, 0.0f);
    for (int i = 0; i < n; ++i) {
      const float x = (i + 0.5f) / n * w - half_;
      const float v = 2 * kPi * (x / w + 0.5f);
      const float y = 0.35875f - 0.48829f * std::cos(v) + 0.14128f * std::cos(2 * v) -
                      0.01168f * std::cos(3 * v);
      cdf_[i + 1] = cdf_[i] + std::abs(y);
    }
    for (float& c : cdf_) c /= cdf_.back();
  }
  float sample(float u) const {
    if (box_) return (u - 0.5f) * 2 * half_;
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    const int i =
        clampv(static_cast<int>(it - cdf_.begin()) - 1, 0, static_cast<int>(cdf_.size()) - 2);
    const float d = cdf_[i + 1] - cdf_[i];
    const float t = d > 0 ? (u - cdf_[i]) / d : 0.5f;
    return ((i + t) / (cdf_.size() - 1)) * 2 * half_ - half_;
  }

 private:
  bool box_ = false;
  float half_ = 0.5f;
  std::vector<float> cdf_;
};

ActiveLights makeActive(const Scene& scene, const PathTracer::Lights& L,
                        const LightSelection& sel) {
  ActiveLights act;
  const std::vector<const Light*> sceneLights = scene.lights.all();
  const size_t n = sceneLights.size();
  PS_Check(n == L.lights.size(), "path tracer: the scene has "
                                     << n << " lights, the tracer was built with "
                                     << L.lights.size());
  const int one = sel.kind == LightSelection::Kind::One ? sel.index
                  : sel.kind == LightSelection::Kind::EnvironmentOnly
                      ? scene.lights.environmentIndex()
                      : -1;
  act.scale.assign(n, Vec3f::Zero());
  act.on.assign(n, 0);
  std::vector<float> w(n, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    bool on = false;
    Vec3f rad = Vec3f::Zero();
    if (sel.kind == LightSelection::Kind::All) {
      const std::optional<Vec3f> s = sceneLights[i]->scale();
      PS_Check(s.has_value(), sceneLights[i]->type()
                                  << " light '" << sceneLights[i]->label()
                                  << "' has no radiance: give one, or render one light at a time");
      rad = *s;
      on = true;
    } else if (static_cast<int>(i) == one) {
      rad = Vec3f::Ones();
      on = true;
    }
    if (!rad.allFinite()) rad = Vec3f::Zero();
    rad = rad.cwiseMax(0.0f);
    act.scale[i] = on ? rad : Vec3f::Zero();
    act.on[i] = on ? 1 : 0;
    w[i] = on ? L.lights[i]->power(act.scale[i]) : 0.0f;
  }
  // half by power, half uniform over the shining lights (as Cycles before its light tree): power
  // alone says nothing about where a light matters (a sun through a window is a small share of
  // the power but all of the light on its patch; at 5 % its samples came back 20 x: fireflies)
  float total = 0;
  int count = 0;
  for (float x : w)
    if (x > 0) total += x, ++count;
  if (count > 0)
    for (float& x : w)
      if (x > 0) x = 0.5f * x / total + 0.5f / count;
  act.select = Distribution1D(w);
  return act;
}

}  // namespace

Vec3f PathTracer::radiance(const Vec3f& org, const Vec3f& dir, const RenderOptions& options,
                           Rng& rng, uint64_t* rays, float firstPdf,
                           AlbedoSensitivity* sensitivity) const {
  const ActiveLights act = makeActive(scene_, *lights_, options.lights);
  Tracer tr{*this, *lights_, act, options, *accel_};
  const IndependentSampler smp(rng);
  AlbedoSensitivity own;
  Vec3f L = tr.path(org, dir.normalized(), smp, nullptr, nullptr,
                    options.nextEventEstimation ? firstPdf : 0.0f, sensitivity ? &own : nullptr);
  if (rays) *rays += tr.rays;
  if (!L.allFinite()) return Vec3f::Zero();
  if (sensitivity)
    for (size_t i = 0; i < own.part.size(); ++i)
      if (own.value[i].allFinite()) sensitivity->add(own.part[i], own.value[i]);
  return L;
}

void AlbedoSensitivity::add(int p, const Vec3f& v) {
  for (size_t i = 0; i < part.size(); ++i)
    if (part[i] == p) {
      value[i] += v;
      return;
    }
  part.push_back(p);
  value.push_back(v);
}

void AlbedoSensitivity::addScaled(const AlbedoSensitivity& other, float s) {
  for (size_t i = 0; i < other.part.size(); ++i) add(other.part[i], other.value[i] * s);
}

std::vector<DirectLightSample> PathTracer::sampleDirectLight(const Vec3f& p, const Vec3f& org,
                                                             const Vec3f& ng, int n, float firstPdf,
                                                             const RenderOptions& options, Rng& rng,
                                                             uint64_t* rays) const {
  std::vector<DirectLightSample> out;
  if (n < 1 || !options.nextEventEstimation) return out;
  const ActiveLights act = makeActive(scene_, *lights_, options.lights);
  Tracer tr{*this, *lights_, act, options, *accel_};
  for (size_t i = 0; i < act.on.size(); ++i) {
    if (!act.on[i] || lights_->lights[i]->isInfinite()) continue;
    for (int k = 0; k < n; ++k) {
      // stratified in the light's first dimension, independent in the other two
      const float u = (k + rng.uniform()) / n;
      const Vec2f uPt(rng.uniform(), rng.uniform());
      Tracer::LightSample ls;
      if (!tr.sampleVisible(static_cast<int>(i), 1.0f, p, org, ng, u, uPt, &ls)) continue;
      if (!(ls.pdf > 0) || !ls.Le.allFinite()) continue;
      const float w = ls.delta ? 1.0f : powerHeuristic(ls.pdf, firstPdf);
      const Vec3f value = ls.Le * (w / ls.pdf);
      if (value.allFinite()) out.push_back({ls.wi, value});
    }
  }
  if (rays) *rays += tr.rays;
  return out;
}

namespace {

// The pixel loop of render() and renderPerLight(): one image, or (act.perLight) one per light.
// `guides` (one image only): the denoiser's guides from the pixel's own samples.
std::vector<cv::Mat> renderImages(const PathTracer& pt, const PathTracer::Lights& lights,
                                  const RayAccel& accel, const Camera& camera,
                                  const RenderOptions& options, const ActiveLights& act,
                                  RenderStats* stats, DenoiseGuides* guides = nullptr) {
  std::string err;
  PS_Check(options.IsValid(&err), err);
  PS_Check(camera.width() > 0 && camera.height() > 0, "camera without size");
  Timer timer;
  const int W = camera.width(), H = camera.height();
  const cv::Mat& only = options.pixels;
  if (!only.empty())
    PS_Check(only.type() == CV_8UC1 && only.cols == W && only.rows == H,
             "path tracer: RenderOptions::pixels must be CV_8UC1 of the camera's size "
                 << W << " x " << H);
  const int nImages = act.perLight ? static_cast<int>(act.scale.size()) : 1;
  std::vector<cv::Mat> images(nImages);
  for (cv::Mat& m : images) m = cv::Mat(H, W, CV_32FC3, cv::Scalar::all(0));
  const bool adaptive = nImages == 1 && options.adaptiveThreshold > 0 &&
                        options.adaptiveMinSpp < options.spp;
  const bool features = guides && nImages == 1;
  if (features) {
    guides->albedo = cv::Mat(H, W, CV_32FC3, cv::Scalar::all(1));
    guides->normal = cv::Mat(H, W, CV_32FC3, cv::Scalar::all(0));
    guides->depth = cv::Mat(H, W, CV_32FC1, cv::Scalar(0));
    guides->variance = cv::Mat(H, W, CV_32FC1, cv::Scalar(0));
  }
  const FilterSampler filter(options.filter, options.filterWidth);
  const Vec3f eye = camera.position().cast<float>();
  const Vec3f camZ = camera.cameraToWorld().block<3, 1>(0, 2).cast<float>();
  std::atomic<uint64_t> totalRays{0}, dropped{0}, totalSamples{0};
  parallelForRanges(0, H, 1, [&](int64_t y0, int64_t y1) {
    Tracer tr{pt, lights, act, options, accel};
    uint64_t bad = 0, taken = 0;
    std::vector<Vec3f> sample(nImages), sum(nImages);
    for (int64_t y = y0; y < y1; ++y)
      for (int x = 0; x < W; ++x) {
        if (!only.empty() && !only.ptr<uint8_t>(static_cast<int>(y))[x]) continue;
        SobolSampler smp(options.seed, static_cast<uint64_t>(y) * W + x);
        std::fill(sum.begin(), sum.end(), Vec3f::Zero());
        // Welford over the samples' luminance (adaptive stop, variance guide); first-hit sums.
        double lumMean = 0, lumM2 = 0;
        Vec3f albedoSum = Vec3f::Zero(), normalSum = Vec3f::Zero();
        float depthSum = 0;
        int hits = 0, n = 0;
        for (int s = 0; s < options.spp; ++s) {
          if (adaptive && s >= options.adaptiveMinSpp && s % 4 == 0) {
            // standard error of the mean luminance against a tone-mapped tolerance
            const double se = std::sqrt(lumM2 / (double(n) * (n - 1)));
            if (se <= options.adaptiveThreshold * (std::sqrt(std::max(lumMean, 0.0)) + 1e-3)) break;
          }
          smp.startSample(static_cast<uint32_t>(s));
          const Vec2f up = smp.get2D(0);
          const float ox = filter.sample(up.x()), oy = filter.sample(up.y());
          const Vec3f d = camera.rayDirection(x + ox, y + oy).cast<float>();
          FirstHit fh;
          if (act.perLight) {
            std::fill(sample.begin(), sample.end(), Vec3f::Zero());
            tr.path(eye, d, smp, sample.data());
          } else {
            sample[0] = tr.path(eye, d, smp, nullptr, features ? &fh : nullptr);
          }
          ++n;
          for (int k = 0; k < nImages; ++k) {
            Vec3f c = sample[k];
            if (!c.allFinite()) {
              ++bad;
              c = Vec3f::Zero();  // counted as a black sample: the mean stays over n samples
            }
            if (options.clampSample > 0) c = c.cwiseMin(options.clampSample);
            sum[k] += c;
            if (k == 0 && (adaptive || features)) {  // the value the mean is made of
              const double l = luminance(c);
              const double delta = l - lumMean;
              lumMean += delta / n;
              lumM2 += delta * (l - lumMean);
            }
          }
          if (features) {
            albedoSum += fh.albedo;
            if (fh.surface) {
              normalSum += fh.normal;
              depthSum += (fh.position - eye).dot(camZ);
              ++hits;
            }
          }
        }
        taken += n;
        const float inv = 1.0f / static_cast<float>(n);
        for (int k = 0; k < nImages; ++k) {
          const Vec3f m = sum[k] * inv;
          images[k].ptr<cv::Vec3f>(static_cast<int>(y))[x] = cv::Vec3f(m.x(), m.y(), m.z());
        }
        if (features) {
          const int yi = static_cast<int>(y);
          const Vec3f a = albedoSum * inv;
          guides->albedo.ptr<cv::Vec3f>(yi)[x] = cv::Vec3f(a.x(), a.y(), a.z());
          if (2 * hits > n && normalSum.norm() > 0) {  // mostly a surface: filter it
            const Vec3f nn = normalSum.normalized();
            guides->normal.ptr<cv::Vec3f>(yi)[x] = cv::Vec3f(nn.x(), nn.y(), nn.z());
            guides->depth.ptr<float>(yi)[x] = std::max(depthSum / hits, 1e-6f);
          }
          guides->variance.ptr<float>(yi)[x] =
              n > 1 ? static_cast<float>(lumM2 / (double(n) * (n - 1))) : 0.0f;
        }
      }
    totalRays += tr.rays;
    dropped += bad;
    totalSamples += taken;
  });
  if (dropped > 0) spdlog::warn("path tracer: {} non-finite samples dropped", dropped.load());
  if (stats) {
    stats->seconds = timer.seconds();
    stats->rays = totalRays.load();
    stats->samples = totalSamples.load();
  }
  return images;
}

}  // namespace

cv::Mat PathTracer::render(const Camera& camera, const RenderOptions& options, RenderStats* stats,
                           DenoiseGuides* guides) const {
  const ActiveLights act = makeActive(scene_, *lights_, options.lights);
  return renderImages(*this, *lights_, *accel_, camera, options, act, stats, guides)[0];
}

std::vector<cv::Mat> PathTracer::renderPerLight(const Camera& camera, const RenderOptions& options,
                                                RenderStats* stats) const {
  // every light at unit scale, each with its own next-event sample (makeActive's One, for all)
  const std::vector<const Light*> sceneLights = scene_.lights.all();
  const size_t n = sceneLights.size();
  PS_Check(n == lights_->lights.size(), "path tracer: the scene has "
                                            << n << " lights, the tracer was built with "
                                            << lights_->lights.size());
  if (n == 0) return {};
  ActiveLights act;
  act.perLight = true;
  act.scale.assign(n, Vec3f::Ones());
  act.on.assign(n, 1);
  act.neeOn.assign(n, 0);
  for (size_t i = 0; i < n; ++i) act.neeOn[i] = lights_->lights[i]->power(Vec3f::Ones()) > 0;
  return renderImages(*this, *lights_, *accel_, camera, options, act, stats);
}

}  // namespace ps
