#include "photoscene/render/render_layer.hpp"

#include <algorithm>
#include <cmath>

#include "photoscene/core/error.hpp"
#include "photoscene/core/parallel.hpp"
#include "photoscene/core/shading.hpp"
#include "photoscene/raytrace/bsdf.hpp"

namespace ps {

// ---------------------------------------------------------------------------------------------
// UV parameters

UvTransform UvParams::toTransform() const {
  UvTransform t;
  t.rotationDeg = degrees(rotation);
  t.scale = Vec2f::Constant(std::exp(logScale));
  t.offset = offset;
  return t;
}

UvParams UvParams::fromTransform(const UvTransform& t) {
  UvParams p;
  p.rotation = radians(t.rotationDeg);
  p.logScale = 0.5f * (std::log(std::max(1e-12f, std::abs(t.scale.x()))) + std::log(std::max(1e-12f, std::abs(t.scale.y()))));
  p.offset = t.offset;
  return p;
}

// ---------------------------------------------------------------------------------------------
// Geometry

namespace {
Vec3f readVec3(const cv::Mat& m, int y, int x) {
  const cv::Vec3f v = m.at<cv::Vec3f>(y, x);
  return Vec3f(v[0], v[1], v[2]);
}
Vec2f readVec2(const cv::Mat& m, int y, int x) {
  const cv::Vec2f v = m.at<cv::Vec2f>(y, x);
  return Vec2f(v[0], v[1]);
}
Vec3f localDirection(float cosT, float phi) {
  const float sinT = std::sqrt(std::max(0.0f, 1 - cosT * cosT));
  return Vec3f(sinT * std::cos(phi), sinT * std::sin(phi), cosT);
}
bool finite3(const Vec3f& v) { return v.allFinite(); }
}  // namespace

PartGeometry preparePartGeometry(const GBuffer& gb, const Vec3f& cameraCenter, const IncidentLightGrid& grid,
                                 const cv::Mat& mask, int part) {
  PS_Check(!mask.empty() && mask.type() == CV_8UC1, "preparePartGeometry: mask must be CV_8UC1");
  PS_Check(mask.size() == gb.partId.size(), "preparePartGeometry: mask and G-buffer sizes differ");
  PS_Check(grid.width >= 1 && grid.height >= 1 && grid.thetaBins >= 1 && grid.phiBins >= 1,
           "preparePartGeometry: empty incident-light grid");
  const int W = mask.cols, H = mask.rows;
  PS_CheckEQ(grid.width, (W + grid.stride - 1) / grid.stride, "preparePartGeometry: grid does not match the image");
  PS_CheckEQ(grid.height, (H + grid.stride - 1) / grid.stride, "preparePartGeometry: grid does not match the image");
  PartGeometry g;
  g.imageSize = mask.size();
  g.part = part;
  g.thetaBins = grid.thetaBins;
  g.phiBins = grid.phiBins;
  g.bins = grid.thetaBins * grid.phiBins;
  g.binSolidAngle = grid.binSolidAngle();
  for (int i = 0; i < grid.thetaBins; ++i)
    for (int j = 0; j < grid.phiBins; ++j) g.binDir.push_back(grid.binDirection(i, j));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (mask.at<uint8_t>(y, x) && gb.partId.at<int>(y, x) >= 0) g.pixels.emplace_back(x, y);
  const int n = g.size();
  g.data.resize(n);
  g.light.assign(static_cast<size_t>(n) * g.bins * 3, 0.0f);
  // Grid points usable for a pixel: they see a surface of the same part with a similar normal.
  auto gridPart = [&](int gx, int gy) { return gb.partId.at<int>(grid.pixelY(gy, H), grid.pixelX(gx, W)); };
  parallelFor(0, n, [&](int64_t k) {
    const int x = g.pixels[k].x, y = g.pixels[k].y;
    PartGeometry::Pixel& px = g.data[k];
    const Vec3f N = readVec3(gb.normalShading, y, x);
    Vec3f T = readVec3(gb.tangent, y, x), B = readVec3(gb.bitangent, y, x);
    if (!(T.squaredNorm() > 0.5f) || !(B.squaredNorm() > 0.5f) || !finite3(T) || !finite3(B))
      orthonormalBasis(N, T, B);
    const Vec3f P = readVec3(gb.position, y, x);
    Vec3f wo = cameraCenter - P;
    const float wl = wo.norm();
    wo = (wl > 0 && std::isfinite(wl)) ? Vec3f(wo / wl) : N;
    px.wo = Vec3f(wo.dot(T), wo.dot(B), wo.dot(N));
    px.uv = readVec2(gb.uv, y, x);
    if (!px.uv.allFinite()) px.uv = Vec2f::Zero();
    const Vec2f dx = readVec2(gb.duvdx, y, x), dy = readVec2(gb.duvdy, y, x);
    const float fp = std::max(dx.norm(), dy.norm());
    px.footprint = std::isfinite(fp) ? fp : 0.0f;
    const Vec3f dpdu = readVec3(gb.dpdu, y, x), dpdv = readVec3(gb.dpdv, y, x);
    px.J[0] = T.dot(dpdu);
    px.J[1] = T.dot(dpdv);
    px.J[2] = B.dot(dpdu);
    px.J[3] = B.dot(dpdv);
    const float det = px.J[0] * px.J[3] - px.J[1] * px.J[2];
    px.frameOk = std::isfinite(det) && std::abs(det) > 1e-12f;
    if (!px.frameOk) {
      px.J[0] = 1, px.J[1] = 0, px.J[2] = 0, px.J[3] = 1;
    }
    // Bilinear weights over the 4 surrounding grid points, restricted to compatible ones.
    const float s = static_cast<float>(grid.stride);
    const float fx = (x - std::floor(s / 2)) / s, fy = (y - std::floor(s / 2)) / s;
    const int gx0 = clampv(static_cast<int>(std::floor(fx)), 0, grid.width - 1);
    const int gy0 = clampv(static_cast<int>(std::floor(fy)), 0, grid.height - 1);
    const int gx1 = std::min(gx0 + 1, grid.width - 1), gy1 = std::min(gy0 + 1, grid.height - 1);
    auto frac = [](int p, int p0, int p1) {
      return p1 > p0 ? clampv(static_cast<float>(p - p0) / static_cast<float>(p1 - p0), 0.0f, 1.0f) : 0.0f;
    };
    const float wx = frac(x, grid.pixelX(gx0, W), grid.pixelX(gx1, W));
    const float wy = frac(y, grid.pixelY(gy0, H), grid.pixelY(gy1, H));
    struct Cand {
      int gx, gy;
      float w;
    } cands[4] = {{gx0, gy0, (1 - wx) * (1 - wy)}, {gx1, gy0, wx * (1 - wy)}, {gx0, gy1, (1 - wx) * wy}, {gx1, gy1, wx * wy}};
    auto compatible = [&](int gx, int gy, bool samePart) {
      const size_t gi = static_cast<size_t>(gy) * grid.width + gx;
      if (!grid.valid[gi]) return false;
      if (samePart && gridPart(gx, gy) != part) return false;
      return grid.frameN[gi].dot(N) > 0.95f;
    };
    float wsum = 0;
    float* L = &g.light[static_cast<size_t>(k) * g.bins * 3];
    auto addPoint = [&](int gx, int gy, float w) {
      if (w <= 0) return;
      for (int b = 0; b < g.bins; ++b) {
        const Vec3f& v = grid.at(gx, gy, b / grid.phiBins, b % grid.phiBins);
        for (int c = 0; c < 3; ++c) L[c * g.bins + b] += w * (std::isfinite(v[c]) ? std::max(0.0f, v[c]) : 0.0f);
      }
      wsum += w;
    };
    for (const Cand& c : cands)
      if (compatible(c.gx, c.gy, true)) addPoint(c.gx, c.gy, c.w);
    if (!(wsum > 1e-6f)) {
      // The nearest compatible grid point (same part first, then any surface facing the same way).
      std::fill(L, L + g.bins * 3, 0.0f);
      wsum = 0;
      for (int pass = 0; pass < 2 && wsum == 0; ++pass) {
        int best = -1;
        float bestD = 1e30f;
        for (int gy = 0; gy < grid.height; ++gy)
          for (int gx = 0; gx < grid.width; ++gx) {
            if (!compatible(gx, gy, pass == 0)) continue;
            const float ddx = static_cast<float>(grid.pixelX(gx, W) - x), ddy = static_cast<float>(grid.pixelY(gy, H) - y);
            const float d = ddx * ddx + ddy * ddy;
            if (d < bestD) bestD = d, best = gy * grid.width + gx;
          }
        if (best >= 0) addPoint(best % grid.width, best / grid.width, 1.0f);
      }
    }
    if (wsum > 0)
      for (int i = 0; i < g.bins * 3; ++i) L[i] /= wsum;
  }, 64);
  return g;
}

namespace {
/// A part with `f`'s lighting bins and no pixels yet, at `imageSize` (after checking `f`).
PartGeometry withoutPixels(const PartGeometry& f, cv::Size imageSize, const char* who) {
  PS_Check(f.data.size() == f.pixels.size() && f.light.size() == f.pixels.size() * static_cast<size_t>(f.bins) * 3,
           who << ": inconsistent PartGeometry");
  PartGeometry g;
  g.imageSize = imageSize;
  g.part = f.part;
  g.bins = f.bins;
  g.thetaBins = f.thetaBins;
  g.phiBins = f.phiBins;
  g.binSolidAngle = f.binSolidAngle;
  g.binDir = f.binDir;
  return g;
}
}  // namespace

PartGeometry subsetPartGeometry(const PartGeometry& f, const std::vector<int>& keep) {
  PartGeometry s = withoutPixels(f, f.imageSize, "subsetPartGeometry");
  const size_t B3 = static_cast<size_t>(f.bins) * 3;
  s.pixels.reserve(keep.size());
  s.data.reserve(keep.size());
  s.light.reserve(keep.size() * B3);
  for (int k : keep) {
    PS_Check(k >= 0 && k < f.size(), "subsetPartGeometry: pixel index " << k << " out of range");
    s.pixels.push_back(f.pixels[k]);
    s.data.push_back(f.data[k]);
    s.light.insert(s.light.end(), f.light.begin() + k * B3, f.light.begin() + (k + 1) * B3);
  }
  return s;
}

PartGeometry downsamplePartGeometry(const PartGeometry& f, cv::Mat* maskOut) {
  PartGeometry c = withoutPixels(f, cv::Size(f.imageSize.width / 2, f.imageSize.height / 2),
                                 "downsamplePartGeometry");
  cv::Mat index(f.imageSize, CV_32SC1, cv::Scalar(-1));
  for (int k = 0; k < f.size(); ++k) index.at<int>(f.pixels[k]) = k;
  cv::Mat mask(c.imageSize, CV_8UC1, cv::Scalar(0));
  const int B3 = f.bins * 3;
  for (int y = 0; y < c.imageSize.height; ++y)
    for (int x = 0; x < c.imageSize.width; ++x) {
      int ks[4];
      bool all = true;
      for (int j = 0; j < 4 && all; ++j) {
        ks[j] = index.at<int>(2 * y + j / 2, 2 * x + j % 2);
        all = ks[j] >= 0;
      }
      if (!all) continue;
      PartGeometry::Pixel px;
      px.uv = Vec2f::Zero();
      px.wo = Vec3f::Zero();
      float fp = 0, J[4] = {0, 0, 0, 0};
      bool frameOk = true, fpOk = true;
      for (int k : ks) {
        const PartGeometry::Pixel& q = f.data[k];
        px.uv += 0.25f * q.uv;
        px.wo += q.wo;
        fp += 0.25f * q.footprint;
        fpOk = fpOk && q.footprint > 0;
        for (int i = 0; i < 4; ++i) J[i] += 0.25f * q.J[i];
        frameOk = frameOk && q.frameOk;
      }
      // a uv seam inside the block: the four uvs spread far more than the pixel footprint
      float spread = 0;
      for (int k : ks) spread = std::max(spread, (f.data[k].uv - px.uv).norm());
      if (!(spread <= 4 * std::max(fp, 1e-6f))) continue;
      const float wl = px.wo.norm();
      px.wo = wl > 0 ? Vec3f(px.wo / wl) : Vec3f(0, 0, 1);
      px.footprint = fpOk ? 2 * fp : 0.0f;
      std::copy(J, J + 4, px.J);
      px.frameOk = frameOk;
      c.pixels.emplace_back(x, y);
      c.data.push_back(px);
      const size_t base = c.light.size();
      c.light.resize(base + B3, 0.0f);
      for (int k : ks) {
        const float* L = &f.light[static_cast<size_t>(k) * B3];
        for (int i = 0; i < B3; ++i) c.light[base + i] += 0.25f * L[i];
      }
      mask.at<uint8_t>(y, x) = 255;
    }
  if (maskOut) *maskOut = mask;
  return c;
}

cv::Mat downsampleImage(const PartGeometry& c, const cv::Mat& fine) {
  PS_Check(fine.type() == CV_32FC3 && fine.cols >= 2 * c.imageSize.width && fine.rows >= 2 * c.imageSize.height,
           "downsampleImage: the image must be CV_32FC3 of the fine geometry's size");
  cv::Mat out(c.imageSize, CV_32FC3, cv::Scalar::all(0));
  for (const cv::Point& p : c.pixels) {
    const cv::Vec3f v = fine.at<cv::Vec3f>(2 * p.y, 2 * p.x) + fine.at<cv::Vec3f>(2 * p.y, 2 * p.x + 1) +
                        fine.at<cv::Vec3f>(2 * p.y + 1, 2 * p.x) + fine.at<cv::Vec3f>(2 * p.y + 1, 2 * p.x + 1);
    out.at<cv::Vec3f>(p) = 0.25f * v;
  }
  return out;
}

std::vector<Vec3f> gatherPixels(const PartGeometry& g, const cv::Mat& image) {
  std::vector<Vec3f> out;
  out.reserve(g.pixels.size());
  for (const cv::Point& p : g.pixels) out.push_back(readVec3(image, p.y, p.x));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Mip pyramids (periodic, power-of-two box filter)

namespace {

struct Pyramid {
  std::vector<cv::Mat> level;  // level[0] = the map
  int channels = 0;
  bool empty() const { return level.empty(); }
  int levels() const { return static_cast<int>(level.size()); }
  float log2Size = 0;
};

bool isPow2(int n) { return n > 0 && (n & (n - 1)) == 0; }

Pyramid buildPyramid(const cv::Mat& map, int channels, bool filter, const char* what) {
  Pyramid p;
  if (map.empty()) return p;
  PS_Check(map.type() == CV_MAKETYPE(CV_32F, channels), std::string("render layer: ") + what + " map has the wrong type");
  PS_Check(map.rows == map.cols && isPow2(map.rows), std::string("render layer: ") + what + " map must be N x N, N a power of two");
  p.channels = channels;
  p.level.push_back(map.isContinuous() ? map : map.clone());
  p.log2Size = std::log2(static_cast<float>(map.rows));
  while (filter && p.level.back().rows > 1) {
    const cv::Mat& a = p.level.back();
    const int n = a.rows / 2;
    cv::Mat b(n, n, a.type());
    for (int y = 0; y < n; ++y) {
      const float* r0 = a.ptr<float>(2 * y);
      const float* r1 = a.ptr<float>(2 * y + 1);
      float* o = b.ptr<float>(y);
      for (int x = 0; x < n; ++x)
        for (int c = 0; c < channels; ++c)
          o[x * channels + c] = 0.25f * (r0[2 * x * channels + c] + r0[(2 * x + 1) * channels + c] +
                                         r1[2 * x * channels + c] + r1[(2 * x + 1) * channels + c]);
    }
    p.level.push_back(b);
  }
  return p;
}

// The 4 taps of a periodic bilinear lookup at t on an n x n level.
struct Taps {
  int x0, x1, y0, y1;
  float fx, fy;
  float n;
};
inline Taps taps(float tu, float tv, int n) {
  Taps t;
  const float u = tu - std::floor(tu), v = tv - std::floor(tv);
  const float x = u * n - 0.5f, y = (1.0f - v) * n - 0.5f;
  const float xf = std::floor(x), yf = std::floor(y);
  t.fx = x - xf;
  t.fy = y - yf;
  auto wrap = [n](int i) { return i & (n - 1); };  // n is a power of two (two's complement wraps negatives)
  t.x0 = wrap(static_cast<int>(xf));
  t.x1 = wrap(t.x0 + 1);
  t.y0 = wrap(static_cast<int>(yf));
  t.y1 = wrap(t.y0 + 1);
  t.n = static_cast<float>(n);
  return t;
}

// Trilinear lookup: value, d value / d t (2 per channel), d value / d lod.
struct LodInfo {
  int l0 = 0, l1 = 0;
  float f = 0;        // weight of l1
  float dLodDls = 0;  // d lod / d logScale (0 when clamped)
};
inline LodInfo lodInfo(const Pyramid& p, float log2Footprint, bool finiteFootprint) {
  LodInfo li;
  if (p.levels() <= 1 || !finiteFootprint) return li;
  const float lod = log2Footprint + p.log2Size;
  const float maxL = static_cast<float>(p.levels() - 1);
  if (!(lod > 0)) return li;
  if (lod >= maxL) {
    li.l0 = li.l1 = p.levels() - 1;
    return li;
  }
  li.l0 = static_cast<int>(std::floor(lod));
  li.l1 = li.l0 + 1;
  li.f = lod - li.l0;
  li.dLodDls = 1.0f / std::log(2.0f);
  return li;
}

inline void sampleLevel(const cv::Mat& m, int C, const Taps& t, float w, float* val, float* dtu, float* dtv) {
  const float* r0 = m.ptr<float>(t.y0);
  const float* r1 = m.ptr<float>(t.y1);
  for (int c = 0; c < C; ++c) {
    const float v00 = r0[t.x0 * C + c], v10 = r0[t.x1 * C + c], v01 = r1[t.x0 * C + c], v11 = r1[t.x1 * C + c];
    const float a = v00 + t.fx * (v10 - v00), b = v01 + t.fx * (v11 - v01);
    val[c] += w * (a + t.fy * (b - a));
    if (dtu) {
      dtu[c] += w * t.n * ((1 - t.fy) * (v10 - v00) + t.fy * (v11 - v01));
      // y grows as t_v decreases
      dtv[c] += -w * t.n * ((1 - t.fx) * (v01 - v00) + t.fx * (v11 - v10));
    }
  }
}

struct Sample {
  float v[3] = {0, 0, 0};
  float dtu[3] = {0, 0, 0}, dtv[3] = {0, 0, 0};
  float dlod[3] = {0, 0, 0};
};

inline void samplePyramid(const Pyramid& p, const Vec2f& t, const LodInfo& li, bool wantGrad, Sample& s) {
  const int C = p.channels;
  const cv::Mat& m0 = p.level[li.l0];
  const Taps t0 = taps(t.x(), t.y(), m0.rows);
  if (li.l1 == li.l0 || li.f == 0) {
    sampleLevel(m0, C, t0, 1.0f, s.v, wantGrad ? s.dtu : nullptr, s.dtv);
    if (wantGrad && li.l1 != li.l0) {
      float v1[3] = {0, 0, 0};
      const cv::Mat& m1 = p.level[li.l1];
      sampleLevel(m1, C, taps(t.x(), t.y(), m1.rows), 1.0f, v1, nullptr, nullptr);
      for (int c = 0; c < C; ++c) s.dlod[c] = v1[c] - s.v[c];
    }
    return;
  }
  float v0[3] = {0, 0, 0}, v1[3] = {0, 0, 0};
  const cv::Mat& m1 = p.level[li.l1];
  sampleLevel(m0, C, t0, 1.0f - li.f, v0, wantGrad ? s.dtu : nullptr, s.dtv);
  sampleLevel(m1, C, taps(t.x(), t.y(), m1.rows), li.f, v1, wantGrad ? s.dtu : nullptr, s.dtv);
  for (int c = 0; c < C; ++c) {
    s.v[c] = v0[c] + v1[c];
    if (wantGrad) s.dlod[c] = v1[c] / li.f - v0[c] / (1.0f - li.f);
  }
}

// Adjoint of samplePyramid's value with respect to the texels.
inline void scatterLevel(cv::Mat& g, int C, const Taps& t, float w, const float* gv) {
  float* r0 = g.ptr<float>(t.y0);
  float* r1 = g.ptr<float>(t.y1);
  const float w00 = w * (1 - t.fx) * (1 - t.fy), w10 = w * t.fx * (1 - t.fy), w01 = w * (1 - t.fx) * t.fy,
              w11 = w * t.fx * t.fy;
  for (int c = 0; c < C; ++c) {
    r0[t.x0 * C + c] += w00 * gv[c];
    r0[t.x1 * C + c] += w10 * gv[c];
    r1[t.x0 * C + c] += w01 * gv[c];
    r1[t.x1 * C + c] += w11 * gv[c];
  }
}

// The per-direction loops are compiled twice on x86-64 with GCC: for AVX2 (8 lanes) and the
// baseline (SSE2, 4 lanes); the loader picks the first the CPU runs. The results are the same
// (element-wise IEEE operations in the same order; no FMA contraction in ISO C++ mode).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define PS_DIRECTION_LOOP __attribute__((target_clones("avx2", "default")))
#else
#define PS_DIRECTION_LOOP
#endif

// Blocked dot product with kLanes independent partial sums (vectorises without -ffast-math;
// the summation order is fixed, so results do not depend on the thread count).
constexpr int kLanes = 8;
inline float dotLanes(const float* a, const float* b, int n) {
  float acc[kLanes] = {0, 0, 0, 0, 0, 0, 0, 0};
  int i = 0;
  for (; i + kLanes <= n; i += kLanes)
    for (int j = 0; j < kLanes; ++j) acc[j] += a[i + j] * b[i + j];
  float tail = 0;
  for (; i < n; ++i) tail += a[i] * b[i];
  return ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7])) + tail;
}
inline float sumLanes(const float* a, int n) {
  float acc[kLanes] = {0, 0, 0, 0, 0, 0, 0, 0};
  int i = 0;
  for (; i + kLanes <= n; i += kLanes)
    for (int j = 0; j < kLanes; ++j) acc[j] += a[i + j];
  float tail = 0;
  for (; i < n; ++i) tail += a[i];
  return ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7])) + tail;
}

// Per-thread scratch of the per-direction loops.
struct Scratch {
  std::vector<float> cb, lA, lFb, lgb, wb1, wb2;   // per bin
  std::vector<float> w1, w2, a, c, e, lF, lg;      // per specular sub-direction
  Scratch(int bins, int subPadded)
      : cb(bins), lA(bins), lFb(bins), lgb(bins), wb1(bins), wb2(bins), w1(subPadded), w2(subPadded),
        a(subPadded), c(subPadded), e(subPadded), lF(subPadded), lg(subPadded) {}
};


// out[b] = x * a[b] + y * b[b] + z * c[b]
PS_DIRECTION_LOOP
void mix3(int n, const float* __restrict a, const float* __restrict b, const float* __restrict c, float x, float y,
          float z, float* __restrict out) {
  for (int i = 0; i < n; ++i) out[i] = x * a[i] + y * b[i] + z * c[i];
}

// The diffuse term's d loss / d n weights: lA[b] = [c_b > 0] sum_c wA_c L_bc.
PS_DIRECTION_LOOP
void diffuseGradWeights(int n, const float* __restrict cb, const float* __restrict l0, const float* __restrict l1,
                        const float* __restrict l2, float w0, float w1, float w2, float* __restrict lA) {
  for (int b = 0; b < n; ++b) lA[b] = (cb[b] > 0 ? 1.0f : 0.0f) * (w0 * l0[b] + w1 * l1[b] + w2 * l2[b]);
}

// The geometry of one sub-direction d = (dx, dy, dz) under normal n and view wo = (wx, wy, wz),
// shared by specularWeights and specularWeightsGrad: u = wo + d, h = u / |u| (inv = 1 / |u|),
// cI = n.d, cH = n.h, the Schlick weight fc = (1 - wo.h)^5, the cosines clamped at 0, and ok:
// the direction counts (cI > 0, cH > 0, u not degenerate). Inlined into the vectorised loops.
struct SubDirection {
  float inv, fc, cIc, cHc;
  bool ok;
};
[[gnu::always_inline]] inline SubDirection subDirection(float dx, float dy, float dz, float nx,
                                                        float ny, float nz, float wx, float wy,
                                                        float wz) {
  const float cI = nx * dx + ny * dy + nz * dz;
  const float ux = wx + dx, uy = wy + dy, uz = wz + dz;
  const float hl2 = ux * ux + uy * uy + uz * uz;
  SubDirection s;
  s.inv = 1.0f / std::sqrt(std::max(hl2, 1e-30f));
  const float cH = (nx * ux + ny * uy + nz * uz) * s.inv;
  const float woh = (wx * ux + wy * uy + wz * uz) * s.inv;
  s.fc = shading::schlickWeight(woh);
  s.cHc = std::max(cH, 0.0f);
  s.cIc = std::max(cI, 0.0f);
  s.ok = (cI > 0) & (cH > 0) & (hl2 > 1e-16f);
  return s;
}

// One sub-direction d of the specular sum (the layer's GGX, written branch-free so the loops over
// directions vectorise): with u = wo + d, h = u / |u|, cI = n.d, cH = n.h, Fc = (1 - wo.h)^5,
// w1 = D(cH) G1(cI) (1 - Fc), w2 = D(cH) G1(cI) Fc, zero where cI <= 0 or cH <= 0.
PS_DIRECTION_LOOP
void specularWeights(int Q, const float* __restrict sx, const float* __restrict sy, const float* __restrict sz,
                     float nx, float ny, float nz, float wx, float wy, float wz, float a2,
                     float* __restrict w1, float* __restrict w2) {
  for (int q = 0; q < Q; ++q) {
    const SubDirection d = subDirection(sx[q], sy[q], sz[q], nx, ny, nz, wx, wy, wz);
    const float fc = d.fc;
    const float D = shading::ggxD(d.cHc, a2);
    const float G = shading::smithG1(d.cIc, a2);
    const float DG = D * G * (d.ok ? 1.0f : 0.0f);
    w1[q] = DG * (1 - fc);
    w2[q] = DG * fc;
  }
}

// specularWeights and, given the per-direction radiance weights lF = sum_c g_c F0_c L_c and
// lg = F90 sum_c g_c L_c, the coefficients of d loss / d n = sum_q ca (wo + d) + (cc - ca) d
// (stored as cc = ca + the d term) and of d loss / d alpha (ce).
PS_DIRECTION_LOOP
void specularWeightsGrad(int Q, const float* __restrict sx, const float* __restrict sy, const float* __restrict sz,
                         float nx, float ny, float nz, float wx, float wy, float wz, float alpha, float kq,
                         const float* __restrict lFq, const float* __restrict lgq, float* __restrict w1,
                         float* __restrict w2, float* __restrict ca, float* __restrict cc, float* __restrict ce) {
  for (int q = 0; q < Q; ++q) {
    const SubDirection d = subDirection(sx[q], sy[q], sz[q], nx, ny, nz, wx, wy, wz);
    const float fc = d.fc;
    const shading::TermGrad Dg = shading::ggxDGrad(d.cHc, alpha);
    const shading::TermGrad Gg = shading::smithG1Grad(d.cIc, alpha);
    const float D = Dg.value, Ddc = Dg.dCos, Dda = Dg.dAlpha;
    const float G = Gg.value, Gdc = Gg.dCos, Gda = Gg.dAlpha;
    const float okf = d.ok ? 1.0f : 0.0f;
    const float DG = D * G * okf;
    w1[q] = DG * (1 - fc);
    w2[q] = DG * fc;
    const float wq = kq * (lFq[q] * (1 - fc) + lgq[q] * fc) * okf;
    const float a = wq * Ddc * G * d.inv;
    ca[q] = a;
    cc[q] = a + wq * D * Gdc;
    ce[q] = wq * (Dda * G + D * Gda);
  }
}

}  // namespace

struct RenderLayerWorkspace {
  Pyramid albedo, normal, roughness;
  // Directions as structure of arrays (the per-direction loops below are written to vectorise):
  // bin centres (diffuse) and the specular sub-directions, sub^2 consecutive ones per bin, padded
  // to a multiple of kLanes with directions whose weight is masked to zero.
  std::vector<float> binX, binY, binZ;
  std::vector<float> subX, subY, subZ;
  int subCount = 0;   // bins * sub^2 (real sub-directions)
  int subPadded = 0;  // subCount rounded up to kLanes
  float subSolidAngle = 0;
  float lobeFloor2 = 0;  // (lobeFilter * sqrt(subSolidAngle))^2, added to alpha^2
  int sub = 0;
};

namespace {

struct PixelGrad {
  Vec2f t = Vec2f::Zero();
  float gA[3] = {0, 0, 0}, gN[3] = {0, 0, 0}, gR = 0;
  LodInfo liA, liN, liR;
  float gRot = 0, gLs = 0;
  Vec2f gT = Vec2f::Zero();
  float gRoughValue = 0, gMetal = 0;
};

// Renders pixel k; with g != null (and gradOut = d loss / d I), fills the pixel's gradients.
Vec3f shadePixel(const RenderLayerParams& p, const RenderLayerWorkspace& ws, int k, const Vec3f* gradOut,
                 PixelGrad* pg, Scratch* scratch) {
  const PartGeometry& geo = *p.geometry;
  const PartGeometry::Pixel& px = geo.data[k];
  const Vec3f& wo = px.wo;
  if (!(wo.z() > 0)) return Vec3f::Zero();  // the path tracer returns no reflection here
  const bool wantGrad = pg != nullptr;
  const float cr = std::cos(p.uv.rotation), sr = std::sin(p.uv.rotation);
  const float scale = std::exp(p.uv.logScale);
  const Vec2f su = scale * px.uv;
  const Vec2f t(cr * su.x() - sr * su.y() + p.uv.offset.x(), sr * su.x() + cr * su.y() + p.uv.offset.y());
  const bool fpOk = px.footprint > 0 && std::isfinite(px.footprint);
  const float log2Fp = fpOk ? std::log2(px.footprint * scale) : 0.0f;

  // ---- material lookups ----
  Sample sA, sN, sR;
  LodInfo liA, liN, liR;
  liA = p.filter ? lodInfo(ws.albedo, log2Fp, fpOk) : LodInfo{};
  samplePyramid(ws.albedo, t, liA, wantGrad, sA);
  const float A[3] = {sA.v[0], sA.v[1], sA.v[2]};
  float rough = p.roughnessValue;
  if (!ws.roughness.empty()) {
    liR = p.filter ? lodInfo(ws.roughness, log2Fp, fpOk) : LodInfo{};
    samplePyramid(ws.roughness, t, liR, wantGrad, sR);
    rough = sR.v[0];
  }
  // normal: tangent space -> local frame
  Vec3f nts(0, 0, 1);
  Vec3f nraw(0, 0, 1);
  float nlen = 1;
  bool normalActive = false;
  if (!ws.normal.empty()) {
    liN = p.filter ? lodInfo(ws.normal, log2Fp, fpOk) : LodInfo{};
    samplePyramid(ws.normal, t, liN, wantGrad, sN);
    nraw = Vec3f(sN.v[0], sN.v[1], sN.v[2]);
    nlen = nraw.norm();
    if (nlen > 1e-6f && std::isfinite(nlen) && nraw.z() > 0) {
      nts = nraw / nlen;
      normalActive = true;
    }
  }
  // frame of t in the local tangent plane: T along dP/dt_u, B along dP/dt_v
  const float* J = px.J;
  Vec2f Tt(1, 0), Bt(0, 1), dTt = Vec2f::Zero(), dBt = Vec2f::Zero();
  if (px.frameOk) {
    const Vec2f v(J[0] * cr - J[1] * sr, J[2] * cr - J[3] * sr);
    const Vec2f w(J[0] * sr + J[1] * cr, J[2] * sr + J[3] * cr);
    const float vl = v.norm();
    if (vl > 1e-12f && std::isfinite(vl)) {
      Tt = v / vl;
      const Vec2f Bp(-Tt.y(), Tt.x());
      const float sgn = Bp.dot(w) < 0 ? -1.0f : 1.0f;
      Bt = sgn * Bp;
      const Vec2f dv = -w;  // d v / d rotation
      dTt = (dv - Tt * Tt.dot(dv)) / vl;
      dBt = sgn * Vec2f(-dTt.y(), dTt.x());
    }
  }
  Vec3f n(nts.x() * Tt.x() + nts.y() * Bt.x(), nts.x() * Tt.y() + nts.y() * Bt.y(), nts.z());
  bool nFree = normalActive;
  if (n.dot(wo) < 1e-4f) {
    n = Vec3f(0, 0, 1);
    nFree = false;
  }

  // ---- shading ----
  const float m = clampv(p.metallic, 0.0f, 1.0f);
  const float f0d = 0.08f * clampv(p.specular, 0.0f, 1.0f);
  float Ac[3], F0[3];
  for (int c = 0; c < 3; ++c) {
    Ac[c] = clampv(A[c], 0.0f, 1.0f);
    F0[c] = clampv(f0d * (1 - m) + Ac[c] * m, 0.0f, 1.0f);
  }
  const bool noSpec = std::max({F0[0], F0[1], F0[2]}) <= 0.0f;
  const float f90 = std::min(1.0f, 50.0f * F0[1]);
  const float rc = clampv(std::isfinite(rough) ? rough : 1.0f, 0.0f, 1.0f);
  const float alphaMat = std::max(rc * rc, kMinAlpha);
  const float alpha = std::sqrt(alphaMat * alphaMat + ws.lobeFloor2);
  const float dAlphaDr =
      (rc * rc > kMinAlpha && rough > 0 && rough < 1) ? 2 * rc * alphaMat / alpha : 0.0f;
  const int B = geo.bins;
  const float* L0 = &geo.light[static_cast<size_t>(k) * 3 * B];  // planar: [c * bins + b]
  const float* Lc[3] = {L0, L0 + B, L0 + 2 * B};
  const float dOm = geo.binSolidAngle;
  Scratch& sc = *scratch;
  const float nx = n.x(), ny = n.y(), nz = n.z();

  // diffuse: E_c = sum_b L_bc (n.d_b)+ over the bin centres; d/dn accumulated in the same pass
  const float kd0 = (1 - m) * shading::kLambert * dOm;
  const Vec3f gOut = wantGrad ? *gradOut : Vec3f::Zero();
  const float wA[3] = {gOut[0] * Ac[0] * kd0, gOut[1] * Ac[1] * kd0, gOut[2] * Ac[2] * kd0};
  const bool nGrad = wantGrad && nFree;
  const float* bx = ws.binX.data();
  const float* by = ws.binY.data();
  const float* bz = ws.binZ.data();
  float* cb = sc.cb.data();
  for (int b = 0; b < B; ++b) cb[b] = std::max(0.0f, nx * bx[b] + ny * by[b] + nz * bz[b]);
  float E[3];
  for (int ch = 0; ch < 3; ++ch) E[ch] = dotLanes(Lc[ch], cb, B);
  Vec3f gnDiffuse = Vec3f::Zero();
  if (nGrad) {
    float* lA = sc.lA.data();
    diffuseGradWeights(B, cb, Lc[0], Lc[1], Lc[2], wA[0], wA[1], wA[2], lA);
    gnDiffuse = Vec3f(dotLanes(lA, bx, B), dotLanes(lA, by, B), dotLanes(lA, bz, B));
  }
  Vec3f I;
  const float kd = (1 - m) * shading::kLambert * dOm;
  for (int ch = 0; ch < 3; ++ch) I[ch] = Ac[ch] * kd * E[ch];

  // specular: per sub-direction q (sub^2 consecutive ones per bin) the weights
  // DG (1 - Fc) and DG Fc, summed per bin, then against the bin's radiance
  float S1[3] = {0, 0, 0}, S2[3] = {0, 0, 0};
  shading::TermGrad K{0, 0, 0};
  const float cO = n.dot(wo);
  const float dOs = ws.subSolidAngle;
  Vec3f gnSpec = Vec3f::Zero();
  float gAlphaSpec = 0;
  if (!noSpec) {
    K = shading::specularK(cO, alpha);
    const int Q = ws.subPadded, s2 = ws.sub * ws.sub;
    const float a2 = alpha * alpha;
    const float wx = wo.x(), wy = wo.y(), wz = wo.z();
    const float* sx = ws.subX.data();
    const float* sy = ws.subY.data();
    const float* sz = ws.subZ.data();
    float* w1 = sc.w1.data();
    float* w2 = sc.w2.data();
    if (!wantGrad) {
      specularWeights(Q, sx, sy, sz, nx, ny, nz, wx, wy, wz, a2, w1, w2);
    } else {
      // per-direction radiance weights of the gradient: sum_c g_c F0_c L_c and sum_c g_c L_c
      float* lFq = sc.lF.data();
      float* lgq = sc.lg.data();
      float* lFb = s2 == 1 ? lFq : sc.lFb.data();
      float* lgb = s2 == 1 ? lgq : sc.lgb.data();
      const float gF0[3] = {gOut[0] * F0[0], gOut[1] * F0[1], gOut[2] * F0[2]};
      mix3(B, Lc[0], Lc[1], Lc[2], gF0[0], gF0[1], gF0[2], lFb);
      mix3(B, Lc[0], Lc[1], Lc[2], f90 * gOut[0], f90 * gOut[1], f90 * gOut[2], lgb);
      if (s2 > 1)
        for (int b = 0; b < B; ++b)
          for (int j = 0; j < s2; ++j) lFq[b * s2 + j] = lFb[b], lgq[b * s2 + j] = lgb[b];
      for (int q = ws.subCount; q < Q; ++q) lFq[q] = lgq[q] = 0;
      const float kq = K.value * dOs;
      float* ca = sc.a.data();  // coefficient of (wo + d) in d loss / d n
      float* cc = sc.c.data();  // coefficient of d
      float* ce = sc.e.data();  // d loss / d alpha
      specularWeightsGrad(Q, sx, sy, sz, nx, ny, nz, wx, wy, wz, alpha, kq, lFq, lgq, w1, w2, ca, cc, ce);
      gnSpec = Vec3f(wx, wy, wz) * sumLanes(ca, Q) + Vec3f(dotLanes(cc, sx, Q), dotLanes(cc, sy, Q), dotLanes(cc, sz, Q));
      gAlphaSpec = sumLanes(ce, Q);
    }
    const float* wb1 = w1;
    const float* wb2 = w2;
    if (s2 > 1) {
      float* r1 = sc.wb1.data();
      float* r2 = sc.wb2.data();
      for (int b = 0; b < B; ++b) {
        float t1 = 0, t2 = 0;
        for (int j = 0; j < s2; ++j) t1 += w1[b * s2 + j], t2 += w2[b * s2 + j];
        r1[b] = t1, r2[b] = t2;
      }
      wb1 = r1, wb2 = r2;
    }
    for (int ch = 0; ch < 3; ++ch) {
      S1[ch] = dotLanes(Lc[ch], wb1, B);
      S2[ch] = dotLanes(Lc[ch], wb2, B);
      I[ch] += K.value * dOs * (F0[ch] * S1[ch] + f90 * S2[ch]);
    }
  }
  if (!I.allFinite()) I = Vec3f::Zero();
  if (!wantGrad) return I;

  // ---- backward ----
  const Vec3f g = *gradOut;
  Vec3f gn = Vec3f::Zero();  // d loss / d n (local)
  float gAlpha = 0;
  float gAc[3] = {0, 0, 0};
  float gF0[3] = {0, 0, 0}, gF90 = 0, gM = 0;
  // diffuse
  for (int ch = 0; ch < 3; ++ch) {
    gAc[ch] += g[ch] * kd * static_cast<float>(E[ch]);
    gM += -g[ch] * shading::kLambert * dOm * Ac[ch] * static_cast<float>(E[ch]);
  }
  gn += gnDiffuse;
  if (!noSpec) {
    float gK = 0;
    for (int ch = 0; ch < 3; ++ch) {
      const float Q = static_cast<float>(dOs * (F0[ch] * S1[ch] + f90 * S2[ch]));
      gK += g[ch] * Q;
      gF0[ch] += g[ch] * K.value * dOs * static_cast<float>(S1[ch]);
      gF90 += g[ch] * K.value * dOs * static_cast<float>(S2[ch]);
    }
    if (nFree) gn += gK * K.dCos * wo;
    gAlpha += gK * K.dAlpha;
    gn += gnSpec;
    gAlpha += gAlphaSpec;
    // F0 = clamp(f0d (1 - m) + A m), F90 = min(1, 50 F0_g)
    if (50.0f * F0[1] < 1.0f) gF0[1] += 50.0f * gF90;
    for (int ch = 0; ch < 3; ++ch) {
      gAc[ch] += gF0[ch] * m;
      gM += gF0[ch] * (Ac[ch] - f0d);
    }
  }
  PixelGrad& out = *pg;
  out.t = t;
  out.liA = liA;
  out.liN = liN;
  out.liR = liR;
  for (int ch = 0; ch < 3; ++ch) out.gA[ch] = (A[ch] >= 0 && A[ch] <= 1) ? gAc[ch] : 0.0f;
  out.gMetal = (p.metallic > 0 && p.metallic < 1) ? gM : 0.0f;
  const float gR = gAlpha * dAlphaDr;
  if (ws.roughness.empty()) out.gRoughValue = gR;
  else out.gR = gR;
  float gRot = 0;
  if (nFree) {
    // n.xy = nts.x Tt + nts.y Bt, n.z = nts.z
    const Vec2f gxy(gn.x(), gn.y());
    const Vec3f gts(gxy.dot(Tt), gxy.dot(Bt), gn.z());
    gRot += gxy.dot(nts.x() * dTt + nts.y() * dBt);
    const Vec3f graw = (gts - nts * nts.dot(gts)) / nlen;
    for (int c = 0; c < 3; ++c) out.gN[c] = graw[c];
  }
  // through t and the lod
  Vec2f gt = Vec2f::Zero();
  float gLod = 0;
  for (int c = 0; c < 3; ++c) {
    gt += out.gA[c] * Vec2f(sA.dtu[c], sA.dtv[c]);
    gLod += out.gA[c] * sA.dlod[c] * liA.dLodDls;
    gt += out.gN[c] * Vec2f(sN.dtu[c], sN.dtv[c]);
    gLod += out.gN[c] * sN.dlod[c] * liN.dLodDls;
  }
  gt += out.gR * Vec2f(sR.dtu[0], sR.dtv[0]);
  gLod += out.gR * sR.dlod[0] * liR.dLodDls;
  out.gT = gt;
  // t = R(rot) s uv + o
  const Vec2f dtdRot(-sr * su.x() - cr * su.y(), cr * su.x() - sr * su.y());
  const Vec2f dtdLs = t - p.uv.offset;
  out.gRot = gRot + gt.dot(dtdRot);
  out.gLs = gt.dot(dtdLs) + gLod;
  return I;
}

void prepareWorkspace(RenderLayerParams& p) {
  PS_Check(p.geometry != nullptr, "render layer: params.geometry is null");
  PS_Check(!p.albedo.empty(), "render layer: the albedo map is required");
  PS_Check(p.specularSub >= 1 && p.specularSub <= 8, "render layer: specularSub must be in [1, 8]");
  PS_Check(std::isfinite(p.lobeFilter) && p.lobeFilter >= 0 && p.lobeFilter <= 4,
           "render layer: lobeFilter must be in [0, 4]");
  PS_Check(std::isfinite(p.uv.rotation) && std::isfinite(p.uv.logScale) && p.uv.offset.allFinite(),
           "render layer: UV parameters must be finite");
  auto ws = std::make_shared<RenderLayerWorkspace>();
  ws->albedo = buildPyramid(p.albedo, 3, p.filter, "albedo");
  ws->normal = buildPyramid(p.normal, 3, p.filter, "normal");
  ws->roughness = buildPyramid(p.roughness, 1, p.filter, "roughness");
  const PartGeometry& g = *p.geometry;
  const int sub = p.specularSub;
  ws->sub = sub;
  ws->subSolidAngle = g.binSolidAngle / (sub * sub);
  ws->lobeFloor2 = p.lobeFilter * p.lobeFilter * ws->subSolidAngle;
  PS_Check(g.bins == g.thetaBins * g.phiBins && static_cast<int>(g.binDir.size()) == g.bins &&
               g.light.size() == static_cast<size_t>(g.size()) * g.bins * 3,
           "render layer: PartGeometry bins, binDir and light sizes disagree");
  for (const Vec3f& d : g.binDir) {
    ws->binX.push_back(d.x());
    ws->binY.push_back(d.y());
    ws->binZ.push_back(d.z());
  }
  for (int i = 0; i < g.thetaBins; ++i)
    for (int j = 0; j < g.phiBins; ++j)
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b) {
          const float cosT = 1.0f - (i + (a + 0.5f) / sub) / g.thetaBins;
          const float phi = 2 * kPi * (j + (b + 0.5f) / sub) / g.phiBins;
          const Vec3f d = localDirection(cosT, phi);
          ws->subX.push_back(d.x());
          ws->subY.push_back(d.y());
          ws->subZ.push_back(d.z());
        }
  ws->subCount = static_cast<int>(ws->subX.size());
  ws->subPadded = (ws->subCount + kLanes - 1) / kLanes * kLanes;
  // padding: pointing into the surface (n.d < 0 for every shading normal), so masked out
  ws->subX.resize(ws->subPadded, 0.0f);
  ws->subY.resize(ws->subPadded, 0.0f);
  ws->subZ.resize(ws->subPadded, -1.0f);
  p.workspace = ws;
}

}  // namespace

void renderLayerForward(RenderLayerParams& p) {
  prepareWorkspace(p);
  const PartGeometry& g = *p.geometry;
  p.image.create(g.imageSize, CV_32FC3);
  p.image.setTo(cv::Scalar::all(0));
  const RenderLayerWorkspace& ws = *p.workspace;
  parallelForRanges(0, g.size(), 64, [&](int64_t k0, int64_t k1) {
    Scratch sc(g.bins, ws.subPadded);
    for (int64_t k = k0; k < k1; ++k) {
      const Vec3f I = shadePixel(p, ws, static_cast<int>(k), nullptr, nullptr, &sc);
      p.image.at<cv::Vec3f>(g.pixels[k].y, g.pixels[k].x) = cv::Vec3f(I.x(), I.y(), I.z());
    }
  });
}

void renderLayerBackward(const RenderLayerParams& p, const cv::Mat& gradImage, RenderLayerGradients& out) {
  PS_Check(p.workspace != nullptr, "renderLayerBackward: call renderLayerForward first");
  const PartGeometry& g = *p.geometry;
  PS_Check(gradImage.type() == CV_32FC3 && gradImage.size() == g.imageSize,
           "renderLayerBackward: gradImage must be CV_32FC3 of the image size");
  const RenderLayerWorkspace& ws = *p.workspace;
  std::vector<PixelGrad> pgs(g.size());
  parallelForRanges(0, g.size(), 64, [&](int64_t k0, int64_t k1) {
    Scratch sc(g.bins, ws.subPadded);
    for (int64_t k = k0; k < k1; ++k) {
      const cv::Vec3f gi = gradImage.at<cv::Vec3f>(g.pixels[k].y, g.pixels[k].x);
      Vec3f go(gi[0], gi[1], gi[2]);
      if (!go.allFinite()) go = Vec3f::Zero();
      shadePixel(p, ws, static_cast<int>(k), &go, &pgs[k], &sc);
    }
  });
  out = RenderLayerGradients{};
  // maps: scatter into every level, then the adjoint of the box pyramid down to level 0
  auto scatterMap = [&](const Pyramid& pyr, auto getGrad, auto getLi, cv::Mat& result) {
    if (pyr.empty()) return;
    std::vector<cv::Mat> gl(pyr.levels());
    for (int l = 0; l < pyr.levels(); ++l) gl[l] = cv::Mat::zeros(pyr.level[l].size(), pyr.level[l].type());
    for (int k = 0; k < g.size(); ++k) {
      const PixelGrad& pg = pgs[k];
      const float* gv = getGrad(pg);
      const LodInfo& li = getLi(pg);
      if (gv[0] == 0 && (pyr.channels == 1 || (gv[1] == 0 && gv[2] == 0))) continue;
      const float w1 = (li.l1 == li.l0) ? 0.0f : li.f;
      scatterLevel(gl[li.l0], pyr.channels, taps(pg.t.x(), pg.t.y(), gl[li.l0].rows), 1.0f - w1, gv);
      if (w1 > 0) scatterLevel(gl[li.l1], pyr.channels, taps(pg.t.x(), pg.t.y(), gl[li.l1].rows), w1, gv);
    }
    const int C = pyr.channels;
    for (int l = pyr.levels() - 1; l >= 1; --l) {
      const cv::Mat& src = gl[l];
      cv::Mat& dst = gl[l - 1];
      for (int y = 0; y < src.rows; ++y) {
        const float* s = src.ptr<float>(y);
        float* d0 = dst.ptr<float>(2 * y);
        float* d1 = dst.ptr<float>(2 * y + 1);
        for (int x = 0; x < src.cols; ++x)
          for (int c = 0; c < C; ++c) {
            const float v = 0.25f * s[x * C + c];
            d0[2 * x * C + c] += v;
            d0[(2 * x + 1) * C + c] += v;
            d1[2 * x * C + c] += v;
            d1[(2 * x + 1) * C + c] += v;
          }
      }
    }
    result = gl[0];
  };
  scatterMap(ws.albedo, [](const PixelGrad& q) { return q.gA; }, [](const PixelGrad& q) -> const LodInfo& { return q.liA; }, out.albedo);
  scatterMap(ws.normal, [](const PixelGrad& q) { return q.gN; }, [](const PixelGrad& q) -> const LodInfo& { return q.liN; }, out.normal);
  scatterMap(ws.roughness, [](const PixelGrad& q) { return &q.gR; }, [](const PixelGrad& q) -> const LodInfo& { return q.liR; }, out.roughness);
  double rot = 0, ls = 0, ox = 0, oy = 0, rv = 0, mt = 0;
  for (const PixelGrad& q : pgs) {
    rot += q.gRot;
    ls += q.gLs;
    ox += q.gT.x();
    oy += q.gT.y();
    rv += q.gRoughValue;
    mt += q.gMetal;
  }
  auto fin = [](double v) { return std::isfinite(v) ? static_cast<float>(v) : 0.0f; };
  out.rotation = fin(rot);
  out.logScale = fin(ls);
  out.offset = Vec2f(fin(ox), fin(oy));
  out.roughnessValue = fin(rv);
  out.metallic = fin(mt);
  for (cv::Mat* m : {&out.albedo, &out.normal, &out.roughness})
    if (!m->empty()) cv::patchNaNs(*m, 0.0);
}

}  // namespace ps
