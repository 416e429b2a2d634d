#include "photoscene/raytrace/path_tracer.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>

#include "distribution.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/core/parallel.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/raytrace/sampler.hpp"
#include "photoscene/raytrace/spherical_rectangle.hpp"

namespace ps {

namespace {
inline float luminance(const Vec3f& c) {
  return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z();
}
inline float powerHeuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0f;
}
inline float offsetScale(const Vec3f& p) {
  return 2e-5f * (1.0f + p.cwiseAbs().maxCoeff());
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Emitter tables

struct PathTracer::Lights {
  struct Tri {
    Vec3f p0, e1, e2, n;  // n: unit emission direction (area lights) or geometric normal (windows)
    float area;
    int light;
  };
  std::vector<Tri> tris;                  // area-emitter triangles
  std::vector<Distribution1D> lightTris;  // per area light: over its entries of lightTriIndex
  std::vector<std::vector<int>> lightTriIndex;
  std::vector<float> lightArea;
  std::vector<int> meshTriEmitter;   // mesh triangle -> tris index or -1
  std::vector<int> rectPrimEmitter;  // rectangle primitive -> tris index
  /// An emitter (or the windows) that is exactly one rectangle: sampled by solid angle.
  struct Rect {
    Vec3f corner = Vec3f::Zero(), ex = Vec3f::Zero(), ey = Vec3f::Zero();
    Vec3f n = Vec3f::Zero();  // emission side (area lights); unused for windows
    float area = 0;
    bool valid = false;
  };
  std::vector<Rect> lightRect;  // per area light
  Rect windowRect;              // all window triangles, when they form one rectangle

  bool hasEnv = false;
  EnvironmentLight envUnit;  // the environment with radiance 1
  Vec3f envRadiance = Vec3f::Ones();
  std::vector<Tri> windowTris;
  Distribution1D windowDist;
  float windowArea = 0;
  std::vector<int> meshTriWindow;  // mesh triangle -> windowTris index or -1
  Distribution2D envDist;          // image environments without windows
  float envMeanLum = 1;
  /// With windows: sum over window triangles of area x the environment's luminance through them
  /// weighted by |cos| to the window (over the outward hemisphere) / pi: the power that enters,
  /// in the units of an area light's luminance x area.
  float windowPower = 0;
  float sceneRadius = 1;
};

// What shines in one render call.
struct ActiveLights {
  std::vector<Vec3f> radiance;  // per area light (zero: off)
  bool envOn = false;
  Vec3f envScale = Vec3f::Ones();
  Distribution1D select;  // over area lights + (last) environment
  float selectPdf(int i) const { return select.pdf(i); }
};

namespace {

Vec3f envLookup(const PathTracer::Lights& L, const Vec3f& d) {
  return L.envUnit.radianceFrom(d);
}

// The rectangle that `tris` tile exactly (two triangles on either side of one of its
// diagonals, perpendicular edges, the same facing), or an invalid Rect.
PathTracer::Lights::Rect rectangleOf(const std::vector<const PathTracer::Lights::Tri*>& tris) {
  PathTracer::Lights::Rect r;
  if (tris.size() != 2) return r;
  float scale = 0;
  for (const auto* t : tris)
    scale = std::max({scale, t->p0.cwiseAbs().maxCoeff(), (t->p0 + t->e1).cwiseAbs().maxCoeff(),
                      (t->p0 + t->e2).cwiseAbs().maxCoeff()});
  const float eps = 1e-5f * (1.0f + scale);
  std::vector<Vec3f> uniq;
  int idx[2][3];
  for (int k = 0; k < 2; ++k) {
    const auto* t = tris[k];
    const Vec3f v[3] = {t->p0, t->p0 + t->e1, t->p0 + t->e2};
    for (int j = 0; j < 3; ++j) {
      int found = -1;
      for (size_t u = 0; u < uniq.size(); ++u)
        if ((v[j] - uniq[u]).norm() <= eps) found = static_cast<int>(u);
      if (found < 0) {
        found = static_cast<int>(uniq.size());
        uniq.push_back(v[j]);
      }
      idx[k][j] = found;
    }
  }
  if (uniq.size() != 4) return r;
  // the shared diagonal: the two vertices both triangles use
  std::vector<int> shared;
  for (int j = 0; j < 3; ++j)
    if (std::find(idx[1], idx[1] + 3, idx[0][j]) != idx[1] + 3) shared.push_back(idx[0][j]);
  if (shared.size() != 2) return r;
  std::vector<int> other;
  for (int u = 0; u < 4; ++u)
    if (u != shared[0] && u != shared[1]) other.push_back(u);
  // corner c = other[0], its neighbours the diagonal's ends, opposite corner other[1]
  const Vec3f c = uniq[other[0]], ex = uniq[shared[0]] - c, ey = uniq[shared[1]] - c;
  if ((c + ex + ey - uniq[other[1]]).norm() > 4 * eps) return r;
  const float lx = ex.norm(), ly = ey.norm();
  if (!(lx > 0) || !(ly > 0) || std::abs(ex.dot(ey)) > 1e-4f * lx * ly) return r;
  const Vec3f n = ex.cross(ey).normalized();
  if (std::abs(n.dot(tris[0]->n)) < 0.999f || tris[0]->n.dot(tris[1]->n) < 0.999f) return r;
  r.corner = c;
  r.ex = ex;
  r.ey = ey;
  r.n = tris[0]->n;
  r.area = lx * ly;
  r.valid = true;
  return r;
}

// Solid-angle sampling of a rectangle is used from x when its solid angle is in this range
// (below it, area sampling is as good and better conditioned).
constexpr float kMinSphericalSolidAngle = 1e-4f, kMaxSphericalSolidAngle = 6.2f;
inline bool useSpherical(const SphericalRectangle& sr) {
  return sr.valid() && sr.solidAngle() > kMinSphericalSolidAngle &&
         sr.solidAngle() < kMaxSphericalSolidAngle;
}

}  // namespace

PathTracer::PathTracer(const Scene& scene, const std::vector<PartMaterial>& materials)
    : scene_(scene), materials_(materials), gray_(PartMaterial::defaultGray("default")) {
  Timer timer;
  const Mesh& mesh = scene.mesh;
  accel_ = std::make_unique<RayAccel>(mesh, scene.lights.area);
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
  windowPart_.assign(scene.parts.size(), 0);
  if (scene.lights.environment)
    for (int p : scene.lights.environment->windowParts)
      if (p >= 0 && p < static_cast<int>(windowPart_.size())) windowPart_[p] = 1;

  lights_ = std::make_unique<Lights>();
  Lights& L = *lights_;
  const auto& area = scene.lights.area;
  L.meshTriEmitter.assign(nt, -1);
  L.meshTriWindow.assign(nt, -1);
  L.lightTris.resize(area.size());
  L.lightTriIndex.resize(area.size());
  L.lightArea.assign(area.size(), 0.0f);
  std::vector<int> partLight(scene.parts.size(), -1);
  for (size_t i = 0; i < area.size(); ++i)
    if (area[i].kind == AreaLight::Kind::Part && area[i].partId >= 0)
      partLight[area[i].partId] = static_cast<int>(i);
  for (size_t t = 0; t < nt; ++t) {
    const int part = mesh.partIds[t];
    const auto& f = mesh.triangles[t];
    Lights::Tri tri;
    tri.p0 = mesh.positions[f[0]];
    tri.e1 = mesh.positions[f[1]] - tri.p0;
    tri.e2 = mesh.positions[f[2]] - tri.p0;
    tri.area = mesh.area(static_cast<int>(t));
    tri.n = triNormal_[t];
    if (!(tri.area > 0) || tri.n.isZero()) continue;
    if (part >= 0 && part < static_cast<int>(partLight.size()) && partLight[part] >= 0) {
      // emits from the side its face normals point to: winding, or the OBJ normals when they
      // disagree
      const Vec3f nsum =
          mesh.cornerNormals[3 * t] + mesh.cornerNormals[3 * t + 1] + mesh.cornerNormals[3 * t + 2];
      if (nsum.dot(tri.n) < 0) tri.n = -tri.n;
      tri.light = partLight[part];
      L.meshTriEmitter[t] = static_cast<int>(L.tris.size());
      L.lightTriIndex[tri.light].push_back(static_cast<int>(L.tris.size()));
      L.tris.push_back(tri);
    }
    if (part >= 0 && part < static_cast<int>(windowPart_.size()) && windowPart_[part]) {
      tri.light = -1;
      L.meshTriWindow[t] = static_cast<int>(L.windowTris.size());
      L.windowTris.push_back(tri);
    }
  }
  int rectCount = 0;
  for (size_t i = 0; i < area.size(); ++i) {
    if (area[i].kind != AreaLight::Kind::Rectangle) continue;
    for (int k = 0; k < 2; ++k) {
      const int prim = 2 * rectCount + k;
      Vec3f p0, p1, p2;
      accel_->rectangleTriangle(prim, &p0, &p1, &p2);
      Lights::Tri tri;
      tri.p0 = p0;
      tri.e1 = p1 - p0;
      tri.e2 = p2 - p0;
      tri.area = 0.5f * tri.e1.cross(tri.e2).norm();
      tri.n = area[i].normal();
      tri.light = static_cast<int>(i);
      L.rectPrimEmitter.push_back(static_cast<int>(L.tris.size()));
      if (tri.area > 0 && tri.n.allFinite())
        L.lightTriIndex[i].push_back(static_cast<int>(L.tris.size()));
      L.tris.push_back(tri);
    }
    ++rectCount;
  }
  L.lightRect.resize(area.size());
  for (size_t i = 0; i < area.size(); ++i) {
    std::vector<float> w;
    std::vector<const Lights::Tri*> tp;
    for (int k : L.lightTriIndex[i]) {
      w.push_back(L.tris[k].area);
      tp.push_back(&L.tris[k]);
    }
    L.lightTris[i] = Distribution1D(w);
    L.lightArea[i] = L.lightTris[i].total();
    L.lightRect[i] = rectangleOf(tp);
  }
  const Eigen::AlignedBox3f box = mesh.bounds();
  L.sceneRadius = std::max(1e-3f, 0.5f * (box.max() - box.min()).norm());
  if (scene.lights.environment) {
    L.hasEnv = true;
    L.envUnit = *scene.lights.environment;
    L.envUnit.radiance = Vec3f::Ones();
    L.envRadiance = scene.lights.environment->radiance;
    std::vector<float> ww;
    for (const auto& t : L.windowTris) ww.push_back(t.area);
    L.windowDist = Distribution1D(ww);
    L.windowArea = L.windowDist.total();
    std::vector<const Lights::Tri*> wp;
    for (const auto& t : L.windowTris) wp.push_back(&t);
    L.windowRect = rectangleOf(wp);
    const cv::Mat& img = L.envUnit.image;
    if (!img.empty()) {
      // Radiance lookups are bilinear: a bright texel (the sun) spills up to half its value into
      // its neighbours' footprints. Sampling by each texel's own value would give those spill
      // regions the neighbours' small pdf (fireflies when a BSDF or window sample lands there);
      // each texel's weight is the maximum of the bilinear radiance over its footprint instead
      // (its center, edge midpoints and corners), so radiance / pdf stays bounded.
      const int W = img.cols, H = img.rows;
      std::vector<float> lum(static_cast<size_t>(W) * H);
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          const cv::Vec3f c = img.at<cv::Vec3f>(y, x);
          float l = luminance(Vec3f(c[0], c[1], c[2]));
          if (!std::isfinite(l) || l < 0) l = 0;
          lum[static_cast<size_t>(y) * W + x] = l;
        }
      auto at = [&](int x, int y) {  // wrap in u, clamp in v, as radianceFrom
        x = ((x % W) + W) % W;
        y = clampv(y, 0, H - 1);
        return lum[static_cast<size_t>(y) * W + x];
      };
      std::vector<float> w(static_cast<size_t>(W) * H);
      double lumSum = 0, wsum = 0;
      for (int y = 0; y < H; ++y) {
        const float sinT = std::sin(kPi * (y + 0.5f) / H);
        for (int x = 0; x < W; ++x) {
          const float c = at(x, y);
          float m = c;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              if (dx == 0 && dy == 0) continue;
              if (dx == 0 || dy == 0)
                m = std::max(m, 0.5f * (c + at(x + dx, y + dy)));
              else
                m = std::max(m, 0.25f * (c + at(x + dx, y) + at(x, y + dy) + at(x + dx, y + dy)));
            }
          w[static_cast<size_t>(y) * W + x] = m * sinT;
          lumSum += c * sinT;
          wsum += sinT;
        }
      }
      L.envMeanLum = wsum > 0 ? static_cast<float>(lumSum / wsum) : 0.0f;
      L.envDist = Distribution2D(w, W, H);
    } else {
      L.envMeanLum = 1.0f;
    }
    // power through the windows: what the environment sends in through each window triangle, not
    // its mean over the whole sphere (a sun outside a window would otherwise get a small selection
    // probability and its next-event samples a large weight: fireflies)
    const Vec3f center = 0.5f * (box.min() + box.max());
    double power = 0;
    for (const auto& t : L.windowTris) {
      const Vec3f c = t.p0 + (t.e1 + t.e2) / 3.0f;
      const Vec3f out =
          t.n.dot(c - center) >= 0 ? t.n : Vec3f(-t.n);  // away from the room's middle
      double e = 0;  // integral of luminance x cos+ over the sphere, / pi
      if (img.empty())
        e = 1.0;
      else {
        const int W = img.cols, H = img.rows;
        for (int y = 0; y < H; ++y)
          for (int x = 0; x < W; ++x) {
            const Vec3f d = L.envUnit.uvToDirection(Vec2f((x + 0.5f) / W, (y + 0.5f) / H));
            const float cs = d.dot(out);
            if (cs <= 0) continue;
            const cv::Vec3f v = img.at<cv::Vec3f>(y, x);
            const float l = luminance(Vec3f(v[0], v[1], v[2]));
            if (!std::isfinite(l) || l <= 0) continue;
            const double dOmega = (2 * kPiD / W) * (kPiD / H) * std::sin(kPiD * (y + 0.5) / H);
            e += l * cs * dOmega / kPiD;
          }
      }
      power += t.area * e;
    }
    L.windowPower = static_cast<float>(power);
  }
  setupSeconds_ = timer.seconds();
  spdlog::info(
      "path tracer: {} triangles, BVH {:.3f}s, {} emitter triangles, {} window triangles, setup "
      "{:.3f}s",
      nt, accel_->buildSeconds(), L.tris.size(), L.windowTris.size(), setupSeconds_);
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

namespace {

struct EscapeInfo {
  bool crossedWindow = false;
  int windowTri = -1;    // first window triangle crossed
  float windowDist = 0;  // distance to it
};

}  // namespace

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
  return true;
}

namespace {

struct Tracer {
  const PathTracer& pt;
  const PathTracer::Lights& L;
  const ActiveLights& act;
  const RenderOptions& opt;
  const RayAccel& accel;
  uint64_t rays = 0;

  // Closest non-window hit; window parts are passed through.
  RayHit traceThroughWindows(const Vec3f& org, const Vec3f& dir, EscapeInfo* esc) {
    float tnear = 0;
    for (int k = 0; k < 16; ++k) {
      const RayHit hit = accel.intersect(org, dir, tnear);
      ++rays;
      if (!hit.valid()) return hit;
      if (hit.geom == 0 && L.meshTriWindow[hit.prim] >= 0) {
        if (!esc->crossedWindow) {
          esc->crossedWindow = true;
          esc->windowTri = L.meshTriWindow[hit.prim];
          esc->windowDist = hit.t;
        }
        tnear = hit.t * (1.0f + 1e-5f) + 1e-6f;
        continue;
      }
      return hit;
    }
    return RayHit();  // pathological stack of windows: treat as escaped
  }

  bool envVisibleThrough(const EscapeInfo& esc) const {
    return L.windowTris.empty() || esc.crossedWindow;
  }

  // Share of the window strategy in the environment's light sampling when it is seen through
  // windows: an image environment mixes it with image importance sampling (a bright sun through
  // a window is found by the image strategy, a dim uniform sky by the window strategy).
  float windowMix() const { return L.envUnit.image.empty() ? 1.0f : 0.5f; }

  float envImagePdf(const Vec3f& dir) const {
    if (L.envUnit.image.empty()) return 1.0f / (4 * kPi);
    const Vec2f uv = L.envUnit.directionToUv(dir);
    const float sinT = std::sin(kPi * clampv(uv.y(), 0.0f, 1.0f));
    if (sinT <= 1e-7f) return 0;
    return L.envDist.pdf(uv) / (2 * kPi * kPi * sinT);
  }

  // Solid-angle pdf at x of the window strategy for a direction that crossed a window first at
  // (esc.windowTri, esc.windowDist): uniform in solid angle over a single rectangular window
  // (seen from x), else uniform in area over all window triangles.
  float windowPdf(const Vec3f& x, const Vec3f& dir, const EscapeInfo& esc) const {
    if (L.windowRect.valid) {
      const SphericalRectangle sr(L.windowRect.corner, L.windowRect.ex, L.windowRect.ey, x);
      if (useSpherical(sr)) return 1.0f / sr.solidAngle();
    }
    const auto& w = L.windowTris[esc.windowTri];
    const float c = std::abs(w.n.dot(dir));
    return c < 1e-7f ? 0.0f : esc.windowDist * esc.windowDist / (L.windowArea * c);
  }

  // Light-sampling pdf (solid angle) at x of the environment for a direction that escaped,
  // selection probability included.
  float envPdf(const Vec3f& x, const Vec3f& dir, const EscapeInfo& esc) const {
    const int envIndex = static_cast<int>(act.radiance.size());
    const float sel = act.selectPdf(envIndex);
    if (sel <= 0) return 0;
    if (!L.windowTris.empty()) {
      if (!esc.crossedWindow || L.windowArea <= 0) return 0;
      const float m = windowMix();
      return sel * (m * windowPdf(x, dir, esc) + (m < 1 ? (1 - m) * envImagePdf(dir) : 0.0f));
    }
    return sel * envImagePdf(dir);
  }

  // Light-sampling pdf (solid angle, selection included) at x of area light i for a ray that hit
  // it at distance t with cosine cosl on the emitter.
  float areaLightPdf(int i, const Vec3f& x, float t, float cosl) const {
    const auto& R = L.lightRect[i];
    if (R.valid) {
      const SphericalRectangle sr(R.corner, R.ex, R.ey, x);
      if (useSpherical(sr)) return act.selectPdf(i) / sr.solidAngle();
    }
    return act.selectPdf(i) * t * t / (L.lightArea[i] * cosl);
  }

  Vec3f envRadiance(const Vec3f& dir) const { return envLookup(L, dir).cwiseProduct(act.envScale); }

  struct LightSample {
    Vec3f wi, Le;
    float pdf = 0, dist = 0;
  };

  // Samples an emitter point or an environment direction seen from x and tests its visibility
  // from `org` (x offset off the surface). uSel picks the light (and, remapped, the environment's
  // strategy), uPt the point. Returns false when nothing visible was sampled.
  bool sampleVisibleLight(const Vec3f& x, const Vec3f& org, const Vec3f& ngo, float uSel,
                          const Vec2f& uPt, LightSample* ls) {
    if (act.select.empty()) return false;
    float selPdf = 0, uRe = 0;
    const int i = act.select.sample(uSel, &selPdf, &uRe);
    const int envIndex = static_cast<int>(act.radiance.size());
    auto pointOn = [](const PathTracer::Lights::Tri& tri, float a, float b) {
      const float su = std::sqrt(a);
      return Vec3f(tri.p0 + tri.e1 * (su * (1 - b)) + tri.e2 * (su * b));
    };
    if (i < envIndex) {
      const auto& R = L.lightRect[i];
      Vec3f y, n;
      float pdfSA = -1;  // solid-angle pdf when sampled by solid angle
      if (R.valid) {
        n = R.n;
        if ((x - R.corner).dot(R.n) <= 0) return false;  // behind the one-sided emitter
        const SphericalRectangle sr(R.corner, R.ex, R.ey, x);
        if (useSpherical(sr)) {
          y = sr.sample(uPt.x(), uPt.y());
          pdfSA = selPdf / sr.solidAngle();
        } else {
          y = R.corner + uPt.x() * R.ex + uPt.y() * R.ey;
        }
      } else {
        const auto& dist = L.lightTris[i];
        if (dist.empty()) return false;
        float triPdf = 0, ux = 0;
        const auto& tri = L.tris[L.lightTriIndex[i][dist.sample(uPt.x(), &triPdf, &ux)]];
        y = pointOn(tri, ux, uPt.y());
        n = tri.n;
      }
      const Vec3f d = y - x;
      const float dist2 = d.squaredNorm();
      if (!(dist2 > 1e-12f)) return false;
      ls->dist = std::sqrt(dist2);
      ls->wi = d / ls->dist;
      const float cosl = -n.dot(ls->wi);
      if (cosl <= 1e-6f || ls->wi.dot(ngo) <= 0) return false;
      ls->pdf = pdfSA > 0 ? pdfSA : selPdf * dist2 / (L.lightArea[i] * cosl);
      ls->Le = act.radiance[i];
      if (!(ls->pdf > 0) || !std::isfinite(ls->pdf) || ls->Le.maxCoeff() <= 0) return false;
      ++rays;
      // the shadow ray runs from org (x lifted off the surface) to y: measured from x, the
      // segment would end past an emitter a few cm away (the lift is ~1e-4 m) and shadow it
      const Vec3f dOrg = y - org;
      const float lOrg = dOrg.norm();
      if (!(lOrg > 0)) return false;
      return !accel.occluded(org, dOrg / lOrg, 0.0f, lOrg * (1.0f - 1e-4f));
    }
    // environment
    if (!L.windowTris.empty()) {
      if (L.windowArea <= 0) return false;
      const float m = windowMix();
      if (uRe < m) {
        Vec3f y;
        bool done = false;
        if (L.windowRect.valid) {
          const SphericalRectangle sr(L.windowRect.corner, L.windowRect.ex, L.windowRect.ey, x);
          if (useSpherical(sr)) {
            y = sr.sample(uPt.x(), uPt.y());
            done = true;
          }
        }
        if (!done) {
          float triPdf = 0, ux = 0;
          const int k = L.windowDist.sample(uPt.x(), &triPdf, &ux);
          y = pointOn(L.windowTris[k], ux, uPt.y());
        }
        const Vec3f d = y - x;
        const float len = d.norm();
        if (!(len > 1e-6f)) return false;
        ls->wi = d / len;
      } else {
        float uvPdf = 0;
        const Vec2f uv = L.envDist.sample(uPt.x(), uPt.y(), &uvPdf);
        if (uvPdf <= 0) return false;
        ls->wi = L.envUnit.uvToDirection(uv);
      }
      if (ls->wi.dot(ngo) <= 0) return false;
      EscapeInfo esc;
      const RayHit h = traceThroughWindows(org, ls->wi, &esc);
      if (h.valid() || !esc.crossedWindow) return false;
      ls->pdf = envPdf(x, ls->wi, esc);
    } else {
      if (L.envUnit.image.empty()) {
        const float z = 1 - 2 * uPt.x(), r = std::sqrt(std::max(0.0f, 1 - z * z)),
                    phi = 2 * kPi * uPt.y();
        ls->wi = Vec3f(r * std::cos(phi), r * std::sin(phi), z);
      } else {
        float uvPdf = 0;
        const Vec2f uv = L.envDist.sample(uPt.x(), uPt.y(), &uvPdf);
        if (uvPdf <= 0) return false;
        ls->wi = L.envUnit.uvToDirection(uv);
      }
      if (ls->wi.dot(ngo) <= 0) return false;
      ls->pdf = selPdf * envImagePdf(ls->wi);
      if (!(ls->pdf > 0)) return false;
      ++rays;
      if (accel.occluded(org, ls->wi, 0.0f, std::numeric_limits<float>::infinity())) return false;
    }
    ls->dist = std::numeric_limits<float>::infinity();
    ls->Le = envRadiance(ls->wi);
    return ls->pdf > 0 && std::isfinite(ls->pdf) && ls->Le.maxCoeff() > 0;
  }

  // Sample dimensions: 2D 0 is the pixel position; bounce b uses 1D dimensions 4b .. 4b + 2
  // (light pick, BSDF lobe, roulette) and 2D dimensions 1 + 2b, 2 + 2b (light point, BSDF
  // direction), the same for every sample of a pixel (so each is stratified across samples).
  template <class Sampler>
  Vec3f path(Vec3f org, Vec3f dir, const Sampler& smp) {
    Vec3f Lsum = Vec3f::Zero(), beta = Vec3f::Ones();
    Vec3f prevPos =
        org;  // the last scattering point (MIS pdfs of light strategies are taken there)
    float prevPdf = 0;
    bool terminateAfterHit = false;
    int bounce = 0, diffuse = 0, glossy = 0;
    const bool nee = opt.nextEventEstimation && !act.select.empty();
    for (int depth = 0;; ++depth) {
      EscapeInfo esc;
      const RayHit hit = traceThroughWindows(org, dir, &esc);
      if (!hit.valid()) {
        if (act.envOn && envVisibleThrough(esc)) {
          const Vec3f Le = envRadiance(dir);
          const float w = (depth == 0 || !nee || prevPdf <= 0)
                              ? 1.0f
                              : powerHeuristic(prevPdf, envPdf(prevPos, dir, esc));
          Lsum += beta.cwiseProduct(Le) * w;
        }
        break;
      }
      // emission
      int em = -1;
      if (hit.geom == 1)
        em = L.rectPrimEmitter[hit.prim];
      else
        em = L.meshTriEmitter[hit.prim];
      if (em >= 0) {
        const auto& tri = L.tris[em];
        const float cosl = -tri.n.dot(dir);
        const Vec3f& Le = act.radiance[tri.light];
        if (cosl > 0 && Le.maxCoeff() > 0) {
          float w = 1.0f;
          if (depth > 0 && nee && prevPdf > 0)
            w = powerHeuristic(prevPdf, areaLightPdf(tri.light, prevPos, hit.t, cosl));
          Lsum += beta.cwiseProduct(Le) * w;
        }
      }
      if (terminateAfterHit || hit.geom == 1) break;  // rectangle emitters reflect nothing

      const SurfacePoint sp = pt.surfacePoint(hit);
      const PartMaterial& mat = pt.material(sp.part);
      const MaterialSample ms = mat.evaluate(sp.uv);
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
        LightSample ls;
        if (sampleVisibleLight(sp.p, orgNext, ngo, smp.get1D(d1), smp.get2D(d2), &ls)) {
          const Vec3f wiL = toLocal(ls.wi);
          const Vec3f f = bsdf.eval(woL, wiL);
          if (f.maxCoeff() > 0) {
            const float bp = bsdf.pdf(woL, wiL);
            const float w = powerHeuristic(ls.pdf, bp);
            Lsum += beta.cwiseProduct(f).cwiseProduct(ls.Le) * (wiL.z() * w / ls.pdf);
          }
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
  const auto& area = scene.lights.area;
  act.radiance.assign(area.size(), Vec3f::Zero());
  std::vector<float> w(area.size() + 1, 0.0f);
  for (size_t i = 0; i < area.size(); ++i) {
    bool on = false;
    Vec3f rad = Vec3f::Zero();
    if (sel.kind == LightSelection::Kind::All) {
      PS_Check(area[i].radiance.has_value(),
               "area light '" << area[i].name
                              << "' has no radiance: give one, or render one light at a time");
      rad = *area[i].radiance;
      on = true;
    } else if (sel.kind == LightSelection::Kind::OneArea && static_cast<int>(i) == sel.areaIndex) {
      rad = Vec3f::Ones();
      on = true;
    }
    if (!rad.allFinite()) rad = Vec3f::Zero();
    rad = rad.cwiseMax(0.0f);
    act.radiance[i] = on ? rad : Vec3f::Zero();
    w[i] = luminance(act.radiance[i]) * L.lightArea[i];
    if (L.lightTris[i].empty()) w[i] = 0;
  }
  if (L.hasEnv && (sel.kind == LightSelection::Kind::All ||
                   sel.kind == LightSelection::Kind::EnvironmentOnly)) {
    act.envOn = true;
    act.envScale = sel.kind == LightSelection::Kind::All ? Vec3f(L.envRadiance.cwiseMax(0.0f))
                                                         : Vec3f(Vec3f::Ones());
    const float lum = L.envMeanLum * luminance(act.envScale);
    // estimated power entering the scene: through the windows, or over a sphere around the scene
    w[area.size()] = L.windowTris.empty()
                         ? std::max(0.0f, lum * kPi * L.sceneRadius * L.sceneRadius)
                         : std::max(0.0f, L.windowPower * luminance(act.envScale));
    if (!L.windowTris.empty() && L.windowArea <= 0) w[area.size()] = 0;
    if (L.windowTris.empty() && !L.envUnit.image.empty() && L.envDist.empty()) w[area.size()] = 0;
  }
  // half by power, half uniform over the shining lights (as Cycles before its light tree): power
  // alone says nothing about where a light matters (a sun through a window is a small share of
  // the power but all of the light on its patch; at 5 % its samples came back 20 x: fireflies)
  float total = 0;
  int n = 0;
  for (float x : w)
    if (x > 0) total += x, ++n;
  if (n > 0)
    for (float& x : w)
      if (x > 0) x = 0.5f * x / total + 0.5f / n;
  act.select = Distribution1D(w);
  return act;
}

}  // namespace

Vec3f PathTracer::radiance(const Vec3f& org, const Vec3f& dir, const RenderOptions& options,
                           Rng& rng, uint64_t* rays) const {
  const ActiveLights act = makeActive(scene_, *lights_, options.lights);
  Tracer tr{*this, *lights_, act, options, *accel_};
  const IndependentSampler smp(rng);
  Vec3f L = tr.path(org, dir.normalized(), smp);
  if (rays) *rays += tr.rays;
  return L.allFinite() ? L : Vec3f::Zero();
}

cv::Mat PathTracer::render(const Camera& camera, const RenderOptions& options,
                           RenderStats* stats) const {
  std::string err;
  PS_Check(options.IsValid(&err), err);
  PS_Check(camera.width() > 0 && camera.height() > 0, "camera without size");
  Timer timer;
  const ActiveLights act = makeActive(scene_, *lights_, options.lights);
  const int W = camera.width(), H = camera.height();
  cv::Mat img(H, W, CV_32FC3, cv::Scalar::all(0));
  const FilterSampler filter(options.filter, options.filterWidth);
  const Vec3f eye = camera.position().cast<float>();
  std::atomic<uint64_t> totalRays{0}, dropped{0};
  parallelForRanges(0, H, 1, [&](int64_t y0, int64_t y1) {
    Tracer tr{*this, *lights_, act, options, *accel_};
    uint64_t bad = 0;
    for (int64_t y = y0; y < y1; ++y) {
      cv::Vec3f* row = img.ptr<cv::Vec3f>(static_cast<int>(y));
      for (int x = 0; x < W; ++x) {
        SobolSampler smp(options.seed, static_cast<uint64_t>(y) * W + x);
        Vec3f sum = Vec3f::Zero();
        for (int s = 0; s < options.spp; ++s) {
          smp.startSample(static_cast<uint32_t>(s));
          const Vec2f up = smp.get2D(0);
          const float ox = filter.sample(up.x()), oy = filter.sample(up.y());
          const Vec3f d = camera.rayDirection(x + ox, y + oy).cast<float>();
          Vec3f c = tr.path(eye, d, smp);
          if (!c.allFinite()) {
            ++bad;
            continue;
          }
          if (options.clampSample > 0) c = c.cwiseMin(options.clampSample);
          sum += c;
        }
        sum /= static_cast<float>(options.spp);
        row[x] = cv::Vec3f(sum.x(), sum.y(), sum.z());
      }
    }
    totalRays += tr.rays;
    dropped += bad;
  });
  if (dropped > 0) spdlog::warn("path tracer: {} non-finite samples dropped", dropped.load());
  if (stats) {
    stats->seconds = timer.seconds();
    stats->rays = totalRays.load();
    stats->samples = static_cast<uint64_t>(W) * H * options.spp;
  }
  return img;
}

std::vector<cv::Mat> PathTracer::renderPerLight(const Camera& camera, const RenderOptions& options,
                                                RenderStats* stats) const {
  std::vector<cv::Mat> out;
  RenderStats total;
  RenderOptions o = options;
  const int n = static_cast<int>(scene_.lights.area.size());
  for (int i = 0; i <= n; ++i) {
    if (i == n && !scene_.lights.environment) break;
    o.lights = i < n ? LightSelection::area(i) : LightSelection::environment();
    RenderStats s;
    out.push_back(render(camera, o, &s));
    total.seconds += s.seconds;
    total.rays += s.rays;
    total.samples += s.samples;
  }
  if (stats) *stats = total;
  return out;
}

}  // namespace ps
