// Generator nodes: uniform values, noises, gradients, stripes, checker, shapes, tiles,
// herringbone, weave. All periodic on the unit square (integer frequencies), all spatial
// parameters in texture units. u = (x + 0.5) / n, v = 1 - (y + 0.5) / n (row 0 at the top).
#include "node.hpp"

#include <algorithm>
#include <array>

namespace ps::graphimpl {
namespace {

template <class T>
inline T uCoord(int x, int n) {
  return (T(x) + T(0.5)) / T(n);
}
template <class T>
inline T vCoord(int y, int n) {
  return T(1) - (T(y) + T(0.5)) / T(n);
}
template <class T>
inline T smooth3(T t) {
  return t * t * (T(3) - T(2) * t);
}
template <class T>
inline T smooth3d(T t) {
  return T(6) * t * (T(1) - t);
}
/// Position of texture coordinate t (u or v) in its cell of `count` cells per unit, in
/// [-0.5, 0.5).
template <class T>
inline T cellCoord(T t, int count) {
  return fracT(t * T(count)) - T(0.5);
}

/// The pixel loops of a generator with one gray output. `row(y)` computes what pixel row y shares
/// and returns the row's pixel function. writeRows: out(x, y) = pixel(x), rows in parallel.
/// visitRowGradients: pixel(x, g) with g = d loss / d out(x, y), every row and pixel in order (a
/// fixed summation order for the parameter gradients).
template <class T, class Row>
void writeRows(NodeCtx<T>& c, Row&& row) {
  forRows(c.n, [&](int y) {
    T* o = c.out[0]->row(y);
    const auto pixel = row(y);
    for (int x = 0; x < c.n; ++x) o[x] = pixel(x);
  });
}
template <class T, class Row>
void visitRowGradients(NodeCtx<T>& c, Row&& row) {
  for (int y = 0; y < c.n; ++y) {
    const T* g = c.dOut[0]->row(y);
    const auto pixel = row(y);
    for (int x = 0; x < c.n; ++x) pixel(x, g[x]);
  }
}
/// The same loops over cell positions (lx, ly) = (cellCoord(u), cellCoord(v)) of count x count
/// cells: out = value(lx, ly), and body(g, lx, ly).
template <class T, class F>
void writeCells(NodeCtx<T>& c, int count, F&& value) {
  writeRows(c, [&](int y) {
    const T ly = cellCoord(vCoord<T>(y, c.n), count);
    return [&, ly](int x) { return value(cellCoord(uCoord<T>(x, c.n), count), ly); };
  });
}
template <class T, class F>
void visitCellGradients(NodeCtx<T>& c, int count, F&& body) {
  visitRowGradients(c, [&](int y) {
    const T ly = cellCoord(vCoord<T>(y, c.n), count);
    return [&, ly](int x, T g) { body(g, cellCoord(uCoord<T>(x, c.n), count), ly); };
  });
}

/// A linear edge: 1 within width / 2 of a center (d: distance to it), 0 beyond, a ramp `soft`
/// wide between; softEdgeAdjoint accumulates g times its partials in width and soft.
template <class T>
inline T softEdge(T width, T d, T soft) {
  return clamp01((T(0.5) * width - d) / soft + T(0.5));
}
template <class T>
inline void softEdgeAdjoint(T g, T width, T d, T soft, T& dWidth, T& dSoft) {
  const T z = (T(0.5) * width - d) / soft + T(0.5);
  if (z > 0 && z < 1) {
    dWidth += g * T(0.5) / soft;
    dSoft -= g * (T(0.5) * width - d) / (soft * soft);
  }
}

/// Base of the node types without continuous parameters or inputs: nothing to differentiate.
struct NoGradient {
  template <class T>
  static void backward(NodeCtx<T>&) {}
};

// ---------------------------------------------------------------- uniform
/// uniform_gray (C = 1) and uniform_color (C = 3): every pixel is parameter 0.
template <int C>
struct Uniform {
  static NodeTypeDesc desc() {
    if constexpr (C == 1)
      return {"uniform_gray",
              "A constant gray value.",
              {},
              {{"out", 1}},
              {pCont("value", 0, 1, 0.5f, "the value")}};
    else
      return {"uniform_color",
              "A constant linear RGB color.",
              {},
              {{"out", 3}},
              {pColor("color", 0.5f, 0.5f, 0.5f, "linear RGB")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    auto& o = c.out[0]->d;
    for (size_t i = 0; i < o.size(); i += C)
      for (int k = 0; k < C; ++k) o[i + k] = c.P(0, k);
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const auto& g = c.dOut[0]->d;
    T s[C] = {};
    for (size_t i = 0; i < g.size(); i += C)
      for (int k = 0; k < C; ++k) s[k] += g[i + k];
    for (int k = 0; k < C; ++k) c.dP(0, k) += s[k];
  }
};

// ---------------------------------------------------------------- gradient noise (fBm)
constexpr float kGradDirs[16][2] = {
    {1.f, 0.f},  {0.92388f, 0.38268f},   {0.70711f, 0.70711f},   {0.38268f, 0.92388f},
    {0.f, 1.f},  {-0.38268f, 0.92388f},  {-0.70711f, 0.70711f},  {-0.92388f, 0.38268f},
    {-1.f, 0.f}, {-0.92388f, -0.38268f}, {-0.70711f, -0.70711f}, {-0.38268f, -0.92388f},
    {0.f, -1.f}, {0.38268f, -0.92388f},  {0.70711f, -0.70711f},  {0.92388f, -0.38268f}};

/// Periodic Perlin noise of one octave evaluated row by row. The per-column quantities (lattice
/// cell, fraction, quintic weight) are computed once per octave, the lattice gradients once per
/// lattice row (reused while consecutive pixel rows stay in the same cell row).
template <class T>
struct PerlinOctave {
  int n = 0, px = 1, py = 1;
  uint32_t seed = 0;
  std::vector<int> ix0, ix1;  // per column: wrapped lattice columns
  std::vector<T> fx, sx;      // per column: fraction in the cell, quintic weight
  bool rowTable = false;      // gradients per lattice column (px small) or per pixel column
  void init(int n_, int px_, int py_, uint32_t seed_) {
    n = n_, px = px_, py = py_, seed = seed_;
    ix0.resize(n), ix1.resize(n), fx.resize(n), sx.resize(n);
    const T scale = T(px) / T(n);
    for (int x = 0; x < n; ++x) {
      const T u = (T(x) + T(0.5)) * scale;
      const T f0 = std::floor(u);
      const T f = u - f0;
      ix0[x] = wrapIndex(static_cast<int>(f0), px);
      ix1[x] = (ix0[x] + 1) % px;
      fx[x] = f;
      sx[x] = f * f * f * (f * (f * T(6) - T(15)) + T(10));
    }
    rowTable = px <= 2 * n;
  }
  /// Per-thread cache: the gradients of the two lattice rows around the current pixel row,
  /// expanded per pixel column (corner a = ix0, b = ix1) so the row loop reads them contiguously.
  struct Slot {
    int iy = -1;
    std::vector<T> ax, ay, bx, by;
  };
  struct Rows {
    Slot s0, s1;  // lattice rows iy0 and iy1
  };
  void fill(Slot& sl, int iy) const {
    sl.iy = iy;
    sl.ax.resize(n), sl.ay.resize(n), sl.bx.resize(n), sl.by.resize(n);
    auto grad = [&](int ix, T& gx, T& gy) {
      const uint32_t h = hash3(uint32_t(ix), uint32_t(iy), seed) & 15u;
      gx = kGradDirs[h][0];
      gy = kGradDirs[h][1];
    };
    if (rowTable) {
      thread_local std::vector<T> gxv, gyv;
      gxv.resize(px), gyv.resize(px);
      for (int i = 0; i < px; ++i) grad(i, gxv[i], gyv[i]);
      for (int x = 0; x < n; ++x) {
        sl.ax[x] = gxv[ix0[x]], sl.ay[x] = gyv[ix0[x]];
        sl.bx[x] = gxv[ix1[x]], sl.by[x] = gyv[ix1[x]];
      }
    } else {  // more cells than pixels: only the cells the pixels touch
      for (int x = 0; x < n; ++x) {
        grad(ix0[x], sl.ax[x], sl.ay[x]);
        grad(ix1[x], sl.bx[x], sl.by[x]);
      }
    }
  }
  /// Writes the noise of pixel row y to dst (n values).
  void row(T* dst, int y, Rows& r) const {
    const T v = vCoord<T>(y, n) * T(py);
    const T fy0 = std::floor(v);
    const T fy = v - fy0;
    const int iy0 = wrapIndex(static_cast<int>(fy0), py), iy1 = (iy0 + 1) % py;
    const T sy = fy * fy * fy * (fy * (fy * T(6) - T(15)) + T(10));
    if (r.s0.iy != iy0 || r.s1.iy != iy1) {
      if (r.s0.iy == iy1) std::swap(r.s0, r.s1);  // rows walk down: the old iy0 is the new iy1
      if (r.s0.iy != iy0) fill(r.s0, iy0);
      if (r.s1.iy != iy1) fill(r.s1, iy1);
    }
    const T fy1 = fy - 1;
    const T *ax0 = r.s0.ax.data(), *ay0 = r.s0.ay.data(), *bx0 = r.s0.bx.data(),
            *by0 = r.s0.by.data();
    const T *ax1 = r.s1.ax.data(), *ay1 = r.s1.ay.data(), *bx1 = r.s1.bx.data(),
            *by1 = r.s1.by.data();
    const T *fxp = fx.data(), *sxp = sx.data();
    for (int x = 0; x < n; ++x) {
      const T f = fxp[x], f1 = f - 1, s = sxp[x];
      const T d00 = ax0[x] * f + ay0[x] * fy, d10 = bx0[x] * f1 + by0[x] * fy;
      const T d01 = ax1[x] * f + ay1[x] * fy1, d11 = bx1[x] * f1 + by1[x] * fy1;
      const T aa = d00 + s * (d10 - d00), bb = d01 + s * (d11 - d01);
      dst[x] = aa + sy * (bb - aa);
    }
  }
};

/// The octaves of a Perlin sum: octave k has (sx << k, sy << k) cells per unit and seed
/// seed * 131 + k (fbm and fbm_bands draw the same octaves).
template <class T>
std::vector<PerlinOctave<T>> perlinOctaves(int n, int sx, int sy, int K, uint32_t seed) {
  std::vector<PerlinOctave<T>> oct(K);
  for (int k = 0; k < K; ++k) oct[k].init(n, sx << k, sy << k, seed * 131u + k);
  return oct;
}

/// Calls body(y, octave) for every pixel row y, rows split between threads; octave(k) returns
/// octave k's row y (computed on demand, so a body that skips an octave does not pay for it).
template <class T, class F>
void forOctaveRows(int n, const std::vector<PerlinOctave<T>>& oct, F&& body) {
  const int K = static_cast<int>(oct.size());
  forRowRanges(n, [&](int y0, int y1) {
    std::vector<typename PerlinOctave<T>::Rows> rows(K);
    std::vector<T> v(n);
    for (int y = y0; y < y1; ++y) {
      auto octave = [&](int k) -> const T* {
        oct[k].row(v.data(), y, rows[k]);
        return v.data();
      };
      body(y, octave);
    }
  });
}

struct Fbm {
  enum { kScaleX, kScaleY, kOctaves, kRoughness, kSeed };
  static NodeTypeDesc desc() {
    return {"fbm",
            "Tileable gradient (Perlin) noise, octaves summed with amplitude roughness^k; "
            "output centered on 0.5 (about [0, 1]).",
            {},
            {{"out", 1}},
            {pInt("scale_x", 1, 256, 4, "cells per unit along u"),
             pInt("scale_y", 1, 256, 4, "cells per unit along v"),
             pInt("octaves", 1, 8, 5, "number of octaves (frequency doubles each)"),
             pCont("roughness", 0, 1, 0.5f, "amplitude ratio between octaves"), pSeed()}};
  }
  static constexpr double kGain = 0.9;
  /// amp_k = r^k, damp_k = d amp_k / dr = k r^(k-1), q = sqrt(sum amp^2), dq = dq/dr.
  template <class T>
  static void amplitudes(T r, int K, std::vector<T>& amp, std::vector<T>& damp, T& q, T& dq) {
    amp.assign(K, T(0));
    damp.assign(K, T(0));
    T q2 = 0, dq2 = 0;
    for (int k = 0; k < K; ++k) {
      amp[k] = k == 0 ? T(1) : amp[k - 1] * r;
      damp[k] = k == 0 ? T(0) : k == 1 ? T(1) : T(k) * amp[k - 1];
      q2 += amp[k] * amp[k];
      dq2 += T(2) * amp[k] * damp[k];
    }
    q = std::sqrt(std::max(q2, T(1e-12)));
    dq = dq2 / (T(2) * q);
  }
  // scratch: [0] = sum_k amp_k noise_k, [1] = sum_k damp_k noise_k (what backward needs)
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n, K = c.I(kOctaves);
    std::vector<T> amp, damp;
    T q, dq;
    amplitudes(c.P(kRoughness), K, amp, damp, q, dq);
    auto& S = *c.scratch;
    S.resize(2);
    S[0].create(n, 1);
    S[1].create(n, 1);
    const auto oct =
        perlinOctaves<T>(n, c.I(kScaleX), c.I(kScaleY), K, static_cast<uint32_t>(c.I(kSeed)));
    const T gq = T(kGain) / q;
    forOctaveRows(n, oct, [&](int y, auto&& octave) {
      T* s = S[0].row(y);
      T* ds = S[1].row(y);
      std::fill(s, s + n, T(0));
      std::fill(ds, ds + n, T(0));
      for (int k = 0; k < K; ++k) {
        const T* v = octave(k);
        const T a = amp[k], da = damp[k];
        for (int x = 0; x < n; ++x) {
          s[x] += a * v[x];
          ds[x] += da * v[x];
        }
      }
      T* o = c.out[0]->row(y);
      for (int x = 0; x < n; ++x) o[x] = T(0.5) + gq * s[x];
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int n = c.n, K = c.I(kOctaves);
    if (K < 2 || !c.wantP(kRoughness)) return;
    std::vector<T> amp, damp;
    T q, dq;
    amplitudes(c.P(kRoughness), K, amp, damp, q, dq);
    const auto& S = *c.scratch;
    T acc = 0;
    for (int y = 0; y < n; ++y) {
      const T* g = c.dOut[0]->row(y);
      const T* s = S[0].row(y);
      const T* ds = S[1].row(y);
      T racc = 0;
      for (int x = 0; x < n; ++x) racc += g[x] * (ds[x] * q - s[x] * dq);
      acc += racc;
    }
    c.dP(kRoughness) += T(kGain) * acc / (q * q);
  }
};

/// fbm whose octaves each have their own amplitude (a radial power spectrum in octave steps that
/// the fit shapes freely, where fbm's one `roughness` can only tilt a power law). Octave k has
/// scale << k cells per unit; out = 0.5 + 0.9 s / q with s = sum_k a_k v_k and q = sqrt(sum_k
/// a_k^2), so the output's spread does not depend on the amplitudes' common level (the
/// ramps after it set the contrast) and only their ratios shape the look.
struct FbmBands {
  static constexpr int kBands = 8;
  enum { kScaleX, kScaleY, kOctaves, kSeed, kBand0 };
  static NodeTypeDesc desc() {
    NodeTypeDesc d{
        "fbm_bands",
        "Tileable gradient (Perlin) noise with one amplitude per octave (band_k: "
        "octave k, scale << k cells per unit); normalised, output centered on 0.5.",
        {},
        {{"out", 1}},
        {pInt("scale_x", 1, 256, 4, "cells per unit along u of octave 0"),
         pInt("scale_y", 1, 256, 4, "cells per unit along v of octave 0"),
         pInt("octaves", 1, kBands, 6, "number of octaves (frequency doubles each)"), pSeed()}};
    static const char* names[kBands] = {"band_0", "band_1", "band_2", "band_3",
                                        "band_4", "band_5", "band_6", "band_7"};
    for (int k = 0; k < kBands; ++k)
      d.params.push_back(pCont(names[k], 0, 1, static_cast<float>(std::pow(0.6, k)),
                               "amplitude of octave k (relative to the others)"));
    return d;
  }
  static constexpr double kGain = 0.9;
  // q^2 as fbm computes it (the same floor), so that band_k = roughness^k gives fbm's maps to the
  // bit where the amplitudes are the same floats
  template <class T>
  static T norm2(const NodeCtx<T>& c, int K) {
    T q2 = 0;
    for (int k = 0; k < K; ++k) q2 += c.P(kBand0 + k) * c.P(kBand0 + k);
    return std::max(q2, T(1e-12));
  }
  template <class T>
  static int octaves(const NodeCtx<T>& c) {
    return std::clamp(c.I(kOctaves), 1, int(kBands));
  }
  template <class T>
  static std::vector<PerlinOctave<T>> makeOctaves(const NodeCtx<T>& c, int K) {
    return perlinOctaves<T>(c.n, c.I(kScaleX), c.I(kScaleY), K, static_cast<uint32_t>(c.I(kSeed)));
  }
  /// Octave planes kept from forward for backward up to this many values (K n^2; 256 px maps
  /// with 8 octaves, a fit's size, are kept); above it (an export's texture size, where K planes
  /// would cost K times a map's memory) backward regenerates the octaves. Both give the same
  /// values.
  static constexpr size_t kKeepOctaveValues = size_t(1) << 19;
  static bool keepsOctaves(int n, int K) {
    return size_t(K) * size_t(n) * size_t(n) <= kKeepOctaveValues;
  }
  // scratch: [0] = s, then the K octave planes where keepsOctaves
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n, K = octaves(c);
    const T gq = T(kGain) / std::sqrt(norm2(c, K));
    const bool keep = keepsOctaves(n, K);
    auto& S = *c.scratch;
    S.resize(keep ? 1 + K : 1);
    for (auto& plane : S) plane.create(n, 1);
    const std::vector<PerlinOctave<T>> oct = makeOctaves(c, K);
    forOctaveRows(n, oct, [&](int y, auto&& octave) {
      T* s = S[0].row(y);
      std::fill(s, s + n, T(0));
      for (int k = 0; k < K; ++k) {
        const T* v = octave(k);
        if (keep) std::copy(v, v + n, S[1 + k].row(y));
        const T a = c.P(kBand0 + k);
        for (int x = 0; x < n; ++x) s[x] += a * v[x];
      }
      T* o = c.out[0]->row(y);
      for (int x = 0; x < n; ++x) o[x] = T(0.5) + gq * s[x];
    });
  }
  // d out / d a_j = G (v_j / q - s a_j / q^3); the sums over pixels are kept per row and added in
  // row order, so the gradient does not depend on how rows were split between threads
  template <class T>
  static void backward(NodeCtx<T>& c) {
    if (!c.needParamGrad) return;
    const int n = c.n, K = octaves(c);
    const T q2 = norm2(c, K), q = std::sqrt(q2);
    const auto& S = *c.scratch;
    std::vector<T> perRow(static_cast<size_t>(n) * (K + 1),
                          T(0));  // [y][k] sum g v_k, [y][K] sum g s
    auto accumulate = [&](int y, auto&& octave) {
      const T* g = c.dOut[0]->row(y);
      const T* s = S[0].row(y);
      T* acc = &perRow[static_cast<size_t>(y) * (K + 1)];
      for (int x = 0; x < n; ++x) acc[K] += g[x] * s[x];
      for (int k = 0; k < K; ++k) {
        if (!c.wantP(kBand0 + k)) continue;
        const T* v = octave(k);
        for (int x = 0; x < n; ++x) acc[k] += g[x] * v[x];
      }
    };
    if (static_cast<int>(S.size()) == 1 + K)  // the octaves forward kept
      forRowRanges(n, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) accumulate(y, [&](int k) { return S[1 + k].row(y); });
      });
    else
      forOctaveRows(n, makeOctaves(c, K), accumulate);
    std::vector<T> sum(K + 1, T(0));
    for (int y = 0; y < n; ++y)
      for (int k = 0; k <= K; ++k) sum[k] += perRow[static_cast<size_t>(y) * (K + 1) + k];
    for (int k = 0; k < K; ++k)
      if (c.wantP(kBand0 + k))
        c.dP(kBand0 + k) += T(kGain) * (sum[k] / q - sum[K] * c.P(kBand0 + k) / (q * q2));
  }
};

// ---------------------------------------------------------------- value noise / white noise
struct ValueNoise : NoGradient {
  enum { kScale, kOctaves, kSeed };
  static NodeTypeDesc desc() {
    return {"value_noise",
            "Blurred noise: random values on a periodic lattice, smoothly interpolated, octaves "
            "with amplitude 1/2^k; in [0, 1].",
            {},
            {{"out", 1}},
            {pInt("scale", 1, 512, 8, "lattice cells per unit"),
             pInt("octaves", 1, 8, 1, "octaves"), pSeed()}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n, K = c.I(kOctaves), s0 = c.I(kScale);
    const uint32_t seed = uint32_t(c.I(kSeed));
    forRows(n, [&](int y) {
      T* o = c.out[0]->row(y);
      std::fill(o, o + n, T(0));
      T norm = 0;
      for (int k = 0; k < K; ++k) {
        const int p = s0 << k;
        const T a = std::pow(T(0.5), T(k));
        norm += a;
        const T v = vCoord<T>(y, n) * T(p) - T(0.5);
        const T fy0 = std::floor(v);
        const T sy = smooth3(v - fy0);
        const int iy0 = wrapIndex(int(fy0), p), iy1 = (iy0 + 1) % p;
        for (int x = 0; x < n; ++x) {
          const T u = uCoord<T>(x, n) * T(p) - T(0.5);
          const T fx0 = std::floor(u);
          const T sx = smooth3(u - fx0);
          const int ix0 = wrapIndex(int(fx0), p), ix1 = (ix0 + 1) % p;
          const uint32_t sd = seed * 977u + k;
          const T h00 = hashf(ix0, iy0, sd), h10 = hashf(ix1, iy0, sd);
          const T h01 = hashf(ix0, iy1, sd), h11 = hashf(ix1, iy1, sd);
          const T aa = h00 + sx * (h10 - h00), bb = h01 + sx * (h11 - h01);
          o[x] += a * (aa + sy * (bb - aa));
        }
      }
      for (int x = 0; x < n; ++x) o[x] /= norm;
    });
  }
};

struct WhiteNoise : NoGradient {
  enum { kScale, kSeed };
  static NodeTypeDesc desc() {
    return {"white_noise",
            "Independent uniform values in [0, 1] on a grid of scale x scale cells.",
            {},
            {{"out", 1}},
            {pInt("scale", 1, 4096, 256, "cells per unit"), pSeed()}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n, s = c.I(kScale);
    const uint32_t seed = uint32_t(c.I(kSeed));
    writeRows(c, [&](int y) {
      const int iy = std::min(s - 1, int(vCoord<T>(y, n) * T(s)));
      return [&, iy](int x) {
        const int ix = std::min(s - 1, int(uCoord<T>(x, n) * T(s)));
        return T(hashf(ix, iy, seed));
      };
    });
  }
};

// ---------------------------------------------------------------- voronoi
struct Voronoi {
  enum { kScale, kJitter, kMode, kSeed };
  static NodeTypeDesc desc() {
    return {"voronoi",
            "Cellular noise on a periodic grid of jittered points: F1 (distance to the nearest "
            "point), F2 - F1 (cell borders) or the nearest cell's random value; distances in cell "
            "units.",
            {},
            {{"out", 1}},
            {pInt("scale", 1, 256, 8, "cells per unit"),
             pCont("jitter", 0, 1, 0.9f, "how far points move from cell centers"),
             pChoice("mode", {"f1", "f2_minus_f1", "cell_value"}, 0, "what to output"), pSeed()}};
  }
  /// The two nearest points of a position (px, py) in cell units: distances d, wrapped cells b,
  /// positions f and random offsets h of the nearest (1) and second nearest (2).
  template <class T>
  struct Hit {
    T px, py, d1, d2, f1[2] = {0, 0}, f2[2] = {0, 0}, h1[2] = {0, 0}, h2[2] = {0, 0};
    int b1[2] = {0, 0}, b2[2] = {0, 0};
  };
  /// The random point offsets of the lattice rows cy-1..cy+1, columns -1..s (3 x (s+2) cells),
  /// built once per lattice row instead of 9 cells x 2 hashes per pixel.
  template <class T>
  struct RowTable {
    int cy = INT32_MIN, s = 0;
    std::vector<T> h;  // [(j+1) * (s+2) + qx+1] * 2 + {0, 1}
    void build(int cy_, int s_, uint32_t seed) {
      cy = cy_, s = s_;
      h.resize(size_t(3) * (s + 2) * 2);
      for (int j = -1; j <= 1; ++j)
        for (int qx = -1; qx <= s; ++qx) {
          const int wx = wrapIndex(qx, s), wy = wrapIndex(cy + j, s);
          T* o = &h[(size_t(j + 1) * (s + 2) + qx + 1) * 2];
          o[0] = hashf(wx, wy, seed), o[1] = hashf(wx, wy, seed + 1);
        }
    }
  };
  template <class T>
  static void search(Hit<T>& r, int s, T jitter, uint32_t seed, const RowTable<T>* tab) {
    const T px = r.px, py = r.py;
    T &d1 = r.d1, &d2 = r.d2;
    int *b1 = r.b1, *b2 = r.b2;
    T *f1 = r.f1, *f2 = r.f2, *h1 = r.h1, *h2 = r.h2;
    const int cx = int(std::floor(px)), cy = int(std::floor(py));
    if (tab && tab->cy != cy) tab = nullptr;
    d1 = d2 = T(1e9);
    for (int j = -1; j <= 1; ++j)
      for (int i = -1; i <= 1; ++i) {
        const int qx = cx + i, qy = cy + j;
        const int wx = wrapIndex(qx, s), wy = wrapIndex(qy, s);
        T hx, hy;
        if (tab && qx >= -1 && qx <= s) {
          const T* t = &tab->h[(size_t(j + 1) * (s + 2) + qx + 1) * 2];
          hx = t[0], hy = t[1];
        } else {
          hx = hashf(wx, wy, seed), hy = hashf(wx, wy, seed + 1);
        }
        const T fx = T(qx) + T(0.5) + jitter * (hx - T(0.5));
        const T fy = T(qy) + T(0.5) + jitter * (hy - T(0.5));
        const T d = std::sqrt((px - fx) * (px - fx) + (py - fy) * (py - fy));
        if (d < d1) {
          d2 = d1;
          b2[0] = b1[0], b2[1] = b1[1];
          f2[0] = f1[0], f2[1] = f1[1];
          h2[0] = h1[0], h2[1] = h1[1];
          d1 = d;
          b1[0] = wx, b1[1] = wy;
          f1[0] = fx, f1[1] = fy;
          h1[0] = hx, h1[1] = hy;
        } else if (d < d2) {
          d2 = d;
          b2[0] = wx, b2[1] = wy;
          f2[0] = fx, f2[1] = fy;
          h2[0] = hx, h2[1] = hy;
        }
      }
  }
  /// Calls f(x, y, hit) with the nearest points of every pixel of rows [ya, yb), in order.
  template <class T, class F>
  static void searchRows(const NodeCtx<T>& c, int ya, int yb, F&& f) {
    const int n = c.n, s = c.I(kScale);
    const T jit = c.P(kJitter);
    const uint32_t seed = uint32_t(c.I(kSeed)) * 7u;
    const bool useTab = s <= 2 * n;
    RowTable<T> tab;
    for (int y = ya; y < yb; ++y) {
      const T py = vCoord<T>(y, n) * T(s);
      const int cy = int(std::floor(py));
      if (useTab && tab.cy != cy) tab.build(cy, s, seed);
      for (int x = 0; x < n; ++x) {
        Hit<T> r;
        r.px = uCoord<T>(x, n) * T(s);
        r.py = py;
        search(r, s, jit, seed, useTab ? &tab : nullptr);
        f(x, y, r);
      }
    }
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int mode = c.I(kMode);
    const uint32_t seed = uint32_t(c.I(kSeed)) * 7u;
    forRowRanges(c.n, [&](int ya, int yb) {
      searchRows(c, ya, yb, [&](int x, int y, const Hit<T>& r) {
        c.out[0]->at(x, y) = mode == 0   ? r.d1
                             : mode == 1 ? r.d2 - r.d1
                                         : T(hashf(r.b1[0], r.b1[1], seed + 5));
      });
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int mode = c.I(kMode);
    if (mode == 2 || !c.wantP(kJitter)) return;
    T acc = 0;
    searchRows(c, 0, c.n, [&](int x, int y, const Hit<T>& r) {
      // d distance / d jitter of the nearest and second nearest points
      auto dd = [&](T d, const T* f, const T* h) {
        if (d < T(1e-9)) return T(0);
        return -((r.px - f[0]) * (h[0] - T(0.5)) + (r.py - f[1]) * (h[1] - T(0.5))) / d;
      };
      const T g1 = dd(r.d1, r.f1, r.h1);
      acc += c.dOut[0]->at(x, y) * (mode == 0 ? g1 : dd(r.d2, r.f2, r.h2) - g1);
    });
    c.dP(kJitter) += acc;
  }
};

// ---------------------------------------------------------------- gradients
struct GradientLinear : NoGradient {
  enum { kDir, kRepeats, kShape };
  static NodeTypeDesc desc() {
    return {"gradient_linear",
            "A ramp 0 -> 1 repeated `repeats` times along u or v (saw) or 0 -> 1 -> 0 (triangle).",
            {},
            {{"out", 1}},
            {pChoice("direction", {"u", "v"}, 0, "axis of the ramp"),
             pInt("repeats", 1, 256, 1, "ramps per unit"),
             pChoice("shape", {"saw", "triangle"}, 1, "ramp shape")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n, dir = c.I(kDir), rep = c.I(kRepeats), tri = c.I(kShape);
    writeRows(c, [&](int y) {
      return [&, y](int x) {
        const T t = fracT((dir == 0 ? uCoord<T>(x, n) : vCoord<T>(y, n)) * T(rep));
        return tri ? T(1) - std::abs(T(2) * t - T(1)) : t;
      };
    });
  }
};

struct GradientRadial {
  enum { kCount, kRadius };
  static NodeTypeDesc desc() {
    return {"gradient_radial",
            "1 at the center of each of count x count cells falling linearly to 0 at `radius` "
            "(1 = the cell's edge midpoint).",
            {},
            {{"out", 1}},
            {pInt("count", 1, 256, 1, "cells per unit"),
             pCont("radius", 0.05f, 1.5f, 1.f, "radius where the value reaches 0")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const T rad = c.P(kRadius);
    writeCells(c, c.I(kCount), [&](T lx, T ly) {
      return clamp01(T(1) - T(2) * std::sqrt(lx * lx + ly * ly) / rad);
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const T rad = c.P(kRadius);
    T acc = 0;
    visitCellGradients(c, c.I(kCount), [&](T g, T lx, T ly) {
      const T r = T(2) * std::sqrt(lx * lx + ly * ly);
      const T z = T(1) - r / rad;
      if (z > 0 && z < 1) acc += g * r / (rad * rad);
    });
    c.dP(kRadius) += acc;
  }
};

// ---------------------------------------------------------------- stripes / checker / shape
struct Stripes {
  enum { kCount, kDir, kWidth, kSoft };
  static NodeTypeDesc desc() {
    return {
        "stripes",
        "Parallel stripes, `count` per unit; the phase runs along u (vertical stripes), v "
        "(horizontal), u+v or u-v (diagonals); 1 on the stripe, 0 between, linear edges.",
        {},
        {{"out", 1}},
        {pInt("count", 1, 512, 8, "stripes per unit"),
         pChoice("direction", {"u", "v", "diagonal", "antidiagonal"}, 0, "phase direction"),
         pCont("width", 0, 1, 0.5f, "stripe width as a fraction of the period"),
         pCont("softness", 0.002f, 0.5f, 0.05f, "edge ramp width as a fraction of the period")}};
  }
  template <class T>
  static T phase(int dir, T u, T v) {
    switch (dir) {
      case 0:
        return u;
      case 1:
        return v;
      case 2:
        return u + v;
      default:
        return u - v;
    }
  }
  /// Distance to the nearest stripe center, in periods.
  template <class T>
  static T distance(int dir, int count, T u, T v) {
    return std::abs(fracT(phase(dir, u, v) * T(count)) - T(0.5));
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n, cnt = c.I(kCount), dir = c.I(kDir);
    const T w = c.P(kWidth), s = c.P(kSoft);
    writeRows(c, [&](int y) {
      const T v = vCoord<T>(y, n);
      return [&, v](int x) { return softEdge(w, distance(dir, cnt, uCoord<T>(x, n), v), s); };
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int n = c.n, cnt = c.I(kCount), dir = c.I(kDir);
    const T w = c.P(kWidth), s = c.P(kSoft);
    T dw = 0, ds = 0;
    visitRowGradients(c, [&](int y) {
      const T v = vCoord<T>(y, n);
      return [&, v](int x, T g) {
        softEdgeAdjoint(g, w, distance(dir, cnt, uCoord<T>(x, n), v), s, dw, ds);
      };
    });
    c.dP(kWidth) += dw;
    c.dP(kSoft) += ds;
  }
};

struct Checker {
  enum { kCount, kSoft };
  static NodeTypeDesc desc() {
    return {"checker",
            "A checkerboard of count x count periods per unit, each period 2 x 2 squares (1 and "
            "0), soft edges.",
            {},
            {{"out", 1}},
            {pInt("count", 1, 512, 8, "periods (2 x 2 squares) per unit"),
             pCont("softness", 0.002f, 0.5f, 0.02f, "edge ramp as a fraction of a square")}};
  }
  template <class T>
  static T signedEdge(T x) {  // distance to the nearest transition, + in first half
    const T w = fracT(x);
    return w < T(0.5) ? std::min(w, T(0.5) - w) : -std::min(w - T(0.5), T(1) - w);
  }
  /// The soft square wave along one axis (t: u or v): clamp(signedEdge / softness, -1, 1), and
  /// its derivative in the softness.
  template <class T>
  struct Wave {
    T value, dSoft;
    Wave(T t, int count, T s) {
      const T e = signedEdge(t * T(count));
      value = std::clamp(e / s, T(-1), T(1));
      dSoft = std::abs(e / s) < 1 ? -e / (s * s) : T(0);
    }
  };
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n, cnt = c.I(kCount);
    const T s = c.P(kSoft);
    writeRows(c, [&](int y) {
      const T sv = Wave<T>(vCoord<T>(y, n), cnt, s).value;
      return
          [&, sv](int x) { return T(0.5) + T(0.5) * Wave<T>(uCoord<T>(x, n), cnt, s).value * sv; };
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int n = c.n, cnt = c.I(kCount);
    const T s = c.P(kSoft);
    T acc = 0;
    visitRowGradients(c, [&](int y) {
      const Wave<T> wv(vCoord<T>(y, n), cnt, s);
      return [&, wv](int x, T g) {
        const Wave<T> wu(uCoord<T>(x, n), cnt, s);
        acc += g * T(0.5) * (wu.dSoft * wv.value + wu.value * wv.dSoft);
      };
    });
    c.dP(kSoft) += acc;
  }
};

struct Shape {
  enum { kCount, kShape, kSize, kSoft };
  static NodeTypeDesc desc() {
    return {"shape",
            "One shape centered in each of count x count cells: disc, square (1 inside, linear "
            "edge) or bell (raised cosine, 1 at the center, 0 at radius size/2).",
            {},
            {{"out", 1}},
            {pInt("count", 1, 256, 4, "cells per unit"),
             pChoice("shape", {"disc", "square", "bell"}, 0, "the shape"),
             pCont("size", 0.01f, 1.f, 0.6f, "diameter / side as a fraction of the cell"),
             pCont("softness", 0.002f, 0.5f, 0.05f, "edge ramp as a fraction of the cell")}};
  }
  template <class T>
  static T radius(int shape, T lx, T ly) {
    return shape == 1 ? std::max(std::abs(lx), std::abs(ly)) : std::sqrt(lx * lx + ly * ly);
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int sh = c.I(kShape);
    const T size = c.P(kSize), s = c.P(kSoft);
    writeCells(c, c.I(kCount), [&](T lx, T ly) {
      const T r = radius(sh, lx, ly);
      if (sh != 2) return softEdge(size, r, s);
      const T q = std::min(r / (T(0.5) * size), T(1));
      return T(0.5) + T(0.5) * std::cos(T(M_PI) * q);
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int sh = c.I(kShape);
    const T size = c.P(kSize), s = c.P(kSoft);
    T dsize = 0, dsoft = 0;
    visitCellGradients(c, c.I(kCount), [&](T g, T lx, T ly) {
      const T r = radius(sh, lx, ly);
      if (sh != 2) return softEdgeAdjoint(g, size, r, s, dsize, dsoft);
      const T q = r / (T(0.5) * size);
      if (q < 1) dsize += g * (-T(0.5) * T(M_PI) * std::sin(T(M_PI) * q)) * (-q / size);
    });
    c.dP(kSize) += dsize;
    c.dP(kSoft) += dsoft;
  }
};

// ---------------------------------------------------------------- tiles and herringbone
/// Bevel profile of a tile from the distance d to its nearest edge: smoothstep((d - gap/2)/bevel).
template <class T>
struct Bevel {
  T h, dGap, dBevel, dD;  // value and partials
  Bevel(T d, T gap, T bevel) {
    const T t = (d - T(0.5) * gap) / bevel;
    if (t <= 0) {
      h = 0, dGap = dBevel = dD = 0;
    } else if (t >= 1) {
      h = 1, dGap = dBevel = dD = 0;
    } else {
      h = smooth3(t);
      const T s = smooth3d(t);
      dD = s / bevel;
      dGap = -T(0.5) * s / bevel;
      dBevel = -s * t / bevel;
    }
  }
};

/// The ports of tile-like nodes: an optional `pattern` in; height, random and sampled out.
inline NodeTypeDesc tileLikeDesc(const char* name, const char* doc,
                                 std::vector<GraphParameter> params) {
  return {name,
          doc,
          {{"pattern", 0, true}},
          {{"height", 1}, {"random", 1}, {"sampled", 0}},
          std::move(params)};
}

/// Shared output layout of tile-like nodes: height, random, sampled (pattern with a per-tile
/// offset; transposed when `transpose`).
template <class T>
inline void writeSampled(NodeCtx<T>& c, int x, int y, int sx, int sy, bool transpose) {
  Plane<T>& o = *c.out[2];
  const int m = c.n - 1;
  T* dst = o.ptr(x, y);
  if (!c.in[0]) {
    for (int k = 0; k < o.c; ++k) dst[k] = 0;
    return;
  }
  const Plane<T>& p = *c.in[0];
  const int px = transpose ? (y + sx) & m : (x + sx) & m;
  const int py = transpose ? (x + sy) & m : (y + sy) & m;
  const T* src = p.ptr(px, py);
  for (int k = 0; k < o.c; ++k) dst[k] = src[p.c == 1 ? 0 : k];
}
template <class T>
inline void scatterSampled(NodeCtx<T>& c, int x, int y, int sx, int sy, bool transpose) {
  if (!c.in[0] || !c.dIn[0]) return;
  Plane<T>& p = *c.dIn[0];
  const int m = c.n - 1;
  const int px = transpose ? (y + sx) & m : (x + sx) & m;
  const int py = transpose ? (x + sy) & m : (y + sy) & m;
  const T* g = c.dOut[2]->ptr(x, y);
  T* dst = p.ptr(px, py);
  for (int k = 0; k < c.dOut[2]->c; ++k) dst[p.c == 1 ? 0 : k] += g[k];
}

/// d loss / d sampled at (x, y), spread to the pattern's channels (a gray pattern read into a
/// colour output gets the sum).
template <class T>
inline std::array<T, 3> sampledGradient(const NodeCtx<T>& c, int x, int y) {
  std::array<T, 3> g{T(0), T(0), T(0)};
  const T* d = c.dOut[2]->ptr(x, y);
  for (int k = 0; k < c.dOut[2]->c; ++k) g[c.in[0]->c == 1 ? 0 : k] += d[k];
  return g;
}
/// d loss / d (sx, sy) of sampled = pattern(sx, sy) (bilinear), g = sampledGradient there.
template <class T>
inline void samplePositionGradient(const NodeCtx<T>& c, const std::array<T, 3>& g, T sx, T sy,
                                   T& Dx, T& Dy) {
  T v[3], gx[3], gy[3];
  sampleBilinear(*c.in[0], sx, sy, v, gx, gy);
  Dx = 0, Dy = 0;
  for (int k = 0; k < c.in[0]->c; ++k) Dx += g[k] * gx[k], Dy += g[k] * gy[k];
}

struct Tile {
  enum { kLayout, kRows, kCols, kRowOffset, kGap, kBevel, kLumVar, kSeed, kPatternScale };
  static NodeTypeDesc desc() {
    return tileLikeDesc(
        "tile",
        "Tile generator: rows x cols tiles (bricks: every other row shifted by row_offset; "
        "grid: no shift; planks: each row shifted by a random fraction of row_offset). "
        "Outputs the bevelled height (0 in the gap, 1 on the tile), a per-tile random value "
        "0.5 + lum_var (r - 0.5), and the optional `pattern` input shifted by a random offset "
        "per tile and scaled by pattern_scale about it (bilinear; a grain finer or coarser than "
        "the tiles, the tiles' size unchanged). gap and bevel are in units of the tile height.",
        {pChoice("layout", {"bricks", "grid", "planks"}, 0, "row layout"),
         pInt("rows", 1, 128, 8, "rows per unit (bricks: rounded up to even)"),
         pInt("cols", 1, 128, 4, "tiles per row per unit"),
         pCont("row_offset", 0, 1, 0.5f, "row shift as a fraction of a tile length"),
         pCont("gap", 0, 0.5f, 0.06f, "gap (mortar, grout) width"),
         pCont("bevel", 0.005f, 0.5f, 0.06f, "bevel width"),
         pCont("lum_var", 0, 1, 0.3f, "per-tile random value spread"), pSeed(),
         pCont("pattern_scale", 0.25f, 2, 1,
               "pattern cycles per tile relative to the pattern's own (> 1: finer)")});
  }
  template <class T>
  struct Geo {
    int row, col;
    T dx, dy, dShift, sgn, aspect;
    T lx,
        ly;  ///< position in the tile in pixels, increasing with x and y (continuous across a wrap)
    T dlx;   ///< d lx / d row_offset
  };
  template <class T>
  static Geo<T> locate(const NodeCtx<T>& c, int x, int y) {
    const int layout = int(c.P(kLayout) + T(0.5)), C = int(c.P(kCols) + T(0.5));
    int R = int(c.P(kRows) + T(0.5));
    if (layout == 0 && (R & 1)) ++R;
    const T ro = c.P(kRowOffset);
    Geo<T> g;
    const T yt = vCoord<T>(y, c.n) * T(R);
    g.row = std::min(R - 1, int(yt));
    const T fy = yt - T(g.row);
    g.dShift = layout == 0 ? T(g.row & 1) : layout == 2 ? T(hashf(g.row, 17, c.I(kSeed))) : T(0);
    const T xt = uCoord<T>(x, c.n) * T(C) + ro * g.dShift;
    const T cf = std::floor(xt);
    const T fx = xt - cf;
    g.col = wrapIndex(int(cf), C);
    g.aspect = T(R) / T(C);
    g.sgn = fx < T(0.5) ? T(1) : T(-1);
    g.dx = std::min(fx, T(1) - fx) * g.aspect;
    g.dy = std::min(fy, T(1) - fy);
    g.lx = fx * T(c.n) / T(C);
    g.ly = -fy * T(c.n) / T(R);  // v runs against y
    g.dlx = g.dShift * T(c.n) / T(C);
    return g;
  }
  /// Where `sampled` reads the pattern: the pixel shifted by the tile's offset (ox, oy), then
  /// scaled by s about it along the tile's own coordinates: the identity at s = 1.
  template <class T>
  static void source(const Geo<T>& g, int x, int y, int ox, int oy, T s, T& sx, T& sy) {
    sx = T(x + ox) + (s - T(1)) * g.lx;
    sy = T(y + oy) + (s - T(1)) * g.ly;
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n;
    const uint32_t seed = uint32_t(c.I(kSeed));
    const T gap = c.P(kGap), bevel = c.P(kBevel), lv = c.P(kLumVar), scale = c.P(kPatternScale);
    forRows(n, [&](int y) {
      int lastCol = -1, lastRow = -1, ox = 0, oy = 0;
      T rnd = 0;
      for (int x = 0; x < n; ++x) {
        const Geo<T> g = locate(c, x, y);
        if (g.col != lastCol || g.row != lastRow) {  // per-tile randoms, hashed once per tile run
          lastCol = g.col, lastRow = g.row;
          rnd = T(0.5) + lv * (T(hashf(g.col, g.row, seed)) - T(0.5));
          ox = int(hashf(g.col, g.row, seed + 1) * float(n));
          oy = int(hashf(g.col, g.row, seed + 2) * float(n));
        }
        c.out[0]->at(x, y) = Bevel<T>(std::min(g.dx, g.dy), gap, bevel).h;
        c.out[1]->at(x, y) = rnd;
        if (scale == T(1) || !c.in[0]) {
          writeSampled(c, x, y, ox, oy, false);
        } else {
          T sx, sy, v[3];
          source(g, x, y, ox, oy, scale, sx, sy);
          sampleBilinear(*c.in[0], sx, sy, v);
          T* dst = c.out[2]->ptr(x, y);
          for (int k = 0; k < c.out[2]->c; ++k) dst[k] = v[c.in[0]->c == 1 ? 0 : k];
        }
      }
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int n = c.n;
    const uint32_t seed = uint32_t(c.I(kSeed));
    const T gap = c.P(kGap), bevel = c.P(kBevel), scale = c.P(kPatternScale);
    T dg = 0, db = 0, dro = 0, dlv = 0, dscale = 0;
    const bool wantLv = c.wantP(kLumVar), sampled = c.in[0] && c.dIn[0];
    // the sample position moves with pattern_scale, and off s = 1 with row_offset (lx)
    const bool moves =
        c.in[0] && (c.wantP(kPatternScale) || (scale != T(1) && c.wantP(kRowOffset)));
    for (int y = 0; y < n; ++y) {
      int lastCol = -1, lastRow = -1, ox = 0, oy = 0;
      T rnd = 0;
      for (int x = 0; x < n; ++x) {
        const Geo<T> g = locate(c, x, y);
        const T gh = c.dOut[0]->at(x, y);
        if (gh != 0) {
          const Bevel<T> b(std::min(g.dx, g.dy), gap, bevel);
          dg += gh * b.dGap;
          db += gh * b.dBevel;
          if (g.dx < g.dy) dro += gh * b.dD * g.sgn * g.aspect * g.dShift;
        }
        if (!wantLv && !sampled && !moves) continue;
        if (g.col != lastCol || g.row != lastRow) {
          lastCol = g.col, lastRow = g.row;
          rnd = T(hashf(g.col, g.row, seed)) - T(0.5);
          ox = int(hashf(g.col, g.row, seed + 1) * float(n));
          oy = int(hashf(g.col, g.row, seed + 2) * float(n));
        }
        dlv += c.dOut[1]->at(x, y) * rnd;
        if (!c.in[0]) continue;
        if (scale == T(1) && !moves) {
          if (sampled) scatterSampled(c, x, y, ox, oy, false);
          continue;
        }
        T sx, sy;
        source(g, x, y, ox, oy, scale, sx, sy);
        const std::array<T, 3> gs = sampledGradient(c, x, y);
        if (sampled) scatterBilinear(*c.dIn[0], sx, sy, gs.data());
        if (moves) {
          T Dx, Dy;
          samplePositionGradient(c, gs, sx, sy, Dx, Dy);
          dscale += Dx * g.lx + Dy * g.ly;
          dro += Dx * (scale - T(1)) * g.dlx;
        }
      }
    }
    c.dP(kGap) += dg;
    c.dP(kBevel) += db;
    c.dP(kRowOffset) += dro;
    c.dP(kLumVar) += dlv;
    c.dP(kPatternScale) += dscale;
  }
};

struct Herringbone {
  enum { kCount, kRatio, kGap, kBevel, kLumVar, kSeed };
  static NodeTypeDesc desc() {
    return tileLikeDesc(
        "herringbone",
        "Herringbone parquet of 1 x ratio planks (horizontal and vertical in a staircase), "
        "repeated count x count times per unit. Outputs as `tile`; the `pattern` input is "
        "transposed on vertical planks so a grain along u follows every plank. gap and bevel "
        "are in units of the plank width.",
        {pInt("count", 1, 32, 2, "pattern repeats per unit"),
         pInt("ratio", 2, 8, 4, "plank length / width"), pCont("gap", 0, 0.5f, 0.04f, "gap width"),
         pCont("bevel", 0.005f, 0.5f, 0.08f, "bevel width"),
         pCont("lum_var", 0, 1, 0.3f, "per-plank random value spread"), pSeed()});
  }
  template <class T>
  struct Geo {
    T d;
    int a, b, vertical;
  };
  template <class T>
  static Geo<T> locate(const NodeCtx<T>& c, int x, int y) {
    const int L = c.I(kRatio), cnt = c.I(kCount);
    const T P = T(2 * L * cnt);
    const T px = uCoord<T>(x, c.n) * P, py = vCoord<T>(y, c.n) * P;
    Geo<T> g;
    // horizontal plank [ox, ox+L] x [oy, oy+1], origin o = a (1,1) + b (L,-L)
    const int m = int(std::floor(py));
    int b = int(std::floor((px - T(m)) / T(2 * L)));
    int ox = m + 2 * b * L, oy = m;
    if (px - T(ox) <= T(L)) {
      g.vertical = 0;
      g.d = std::min(std::min(px - T(ox), T(ox + L) - px), std::min(py - T(oy), T(oy + 1) - py));
    } else {
      // vertical plank [ox+L, ox+L+1] x [oy+1-L, oy+1]
      const int k = int(std::floor(px));
      ox = k - L;
      b = int(std::ceil((T(k - 2 * L + 1) - py) / T(2 * L)));
      oy = ox - 2 * b * L;
      g.vertical = 1;
      g.d = std::min(std::min(px - T(ox + L), T(ox + L + 1) - px),
                     std::min(py - T(oy + 1 - L), T(oy + 1) - py));
      g.d = std::max(g.d, T(0));
    }
    int a = (ox + oy) / 2;
    b = (ox - oy) / (2 * L);
    int bb = wrapIndex(b, 2 * cnt);
    if (bb >= cnt) {
      bb -= cnt;
      a -= cnt * L;
    }
    g.a = wrapIndex(a, 2 * cnt * L);
    g.b = bb;
    return g;
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n;
    const uint32_t seed = uint32_t(c.I(kSeed)) * 2u;
    const T gap = c.P(kGap), bevel = c.P(kBevel), lv = c.P(kLumVar);
    forRows(n, [&](int y) {
      for (int x = 0; x < n; ++x) {
        const Geo<T> g = locate(c, x, y);
        const uint32_t sd = seed + g.vertical;
        c.out[0]->at(x, y) = Bevel<T>(g.d, gap, bevel).h;
        c.out[1]->at(x, y) = T(0.5) + lv * (T(hashf(g.a, g.b, sd)) - T(0.5));
        writeSampled(c, x, y, int(hashf(g.a, g.b, sd + 11) * float(n)),
                     int(hashf(g.a, g.b, sd + 13) * float(n)), g.vertical);
      }
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int n = c.n;
    const uint32_t seed = uint32_t(c.I(kSeed)) * 2u;
    const T gap = c.P(kGap), bevel = c.P(kBevel);
    T dg = 0, db = 0, dlv = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const Geo<T> g = locate(c, x, y);
        const uint32_t sd = seed + g.vertical;
        const T gh = c.dOut[0]->at(x, y);
        if (gh != 0) {
          const Bevel<T> b(g.d, gap, bevel);
          dg += gh * b.dGap;
          db += gh * b.dBevel;
        }
        dlv += c.dOut[1]->at(x, y) * (T(hashf(g.a, g.b, sd)) - T(0.5));
        scatterSampled(c, x, y, int(hashf(g.a, g.b, sd + 11) * float(n)),
                       int(hashf(g.a, g.b, sd + 13) * float(n)), g.vertical);
      }
    c.dP(kGap) += dg;
    c.dP(kBevel) += db;
    c.dP(kLumVar) += dlv;
  }
};

// ---------------------------------------------------------------- weave
struct Weave {
  enum { kCount, kPattern, kWidth, kSeed };
  static NodeTypeDesc desc() {
    return {
        "weave",
        "Woven threads, count per unit each way: warp threads run along v, weft along u. "
        "Outputs the thread height (0.5 + 0.5 sin arch on top, 0.5 below, parabolic "
        "cross-section), a mask that is 1 where the warp is on top, and a per-thread random "
        "value.",
        {},
        {{"height", 1}, {"warp", 1}, {"random", 1}},
        {pInt("count", 2, 512, 32, "threads per unit (rounded up to the pattern period)"),
         pChoice("pattern", {"plain", "twill_2_2", "twill_3_1", "basket_2_2"}, 0, "weave"),
         pCont("width", 0.3f, 1.f, 0.85f, "thread width as a fraction of the spacing"), pSeed()}};
  }
  static bool warpTop(int pattern, int i, int j) {
    switch (pattern) {
      case 0:
        return ((i + j) & 1) == 0;
      case 1:
        return wrapIndex(i + j, 4) < 2;
      case 2:
        return wrapIndex(i + j, 4) < 3;
      default:
        return (((i >> 1) + (j >> 1)) & 1) == 0;
    }
  }
  template <class T>
  struct Eval {
    T h, dh;  // height, d height / d width
    bool warp;
    int i, j;
  };
  template <class T>
  static Eval<T> eval(const NodeCtx<T>& c, int x, int y) {
    const int pat = c.I(kPattern);
    const int period = pat == 0 ? 2 : 4;
    const int N = (c.I(kCount) + period - 1) / period * period;
    const T w = c.P(kWidth);
    const T uu = uCoord<T>(x, c.n) * T(N), vv = vCoord<T>(y, c.n) * T(N);
    Eval<T> e;
    e.i = std::min(N - 1, int(uu));
    e.j = std::min(N - 1, int(vv));
    const T fx = uu - T(e.i), fy = vv - T(e.j);
    const bool top = warpTop(pat, e.i, e.j);
    auto prof = [&](T f, T& d) {
      const T q = (f - T(0.5)) / (T(0.5) * w);
      const T a = T(1) - q * q;
      if (a <= 0) {
        d = 0;
        return T(0);
      }
      d = T(8) * (f - T(0.5)) * (f - T(0.5)) / (w * w * w);
      return a;
    };
    T daW, daF;
    const T aW = prof(fx, daW), aF = prof(fy, daF);
    const T bW = top ? T(0.5) + T(0.5) * std::sin(T(M_PI) * fy) : T(0.5);
    const T bF = top ? T(0.5) : T(0.5) + T(0.5) * std::sin(T(M_PI) * fx);
    const T hW = aW * bW, hF = aF * bF;
    e.warp = hW >= hF;
    e.h = e.warp ? hW : hF;
    e.dh = e.warp ? daW * bW : daF * bF;
    return e;
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const uint32_t seed = uint32_t(c.I(kSeed));
    forRows(c.n, [&](int y) {
      for (int x = 0; x < c.n; ++x) {
        const Eval<T> e = eval(c, x, y);
        c.out[0]->at(x, y) = e.h;
        c.out[1]->at(x, y) = e.warp ? T(1) : T(0);
        c.out[2]->at(x, y) = e.warp ? hashf(e.i, 0, seed) : hashf(e.j, 1, seed);
      }
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    T acc = 0;
    for (int y = 0; y < c.n; ++y)
      for (int x = 0; x < c.n; ++x) {
        const T g = c.dOut[0]->at(x, y);
        if (g != 0) acc += g * eval(c, x, y).dh;
      }
    c.dP(kWidth) += acc;
  }
};

}  // namespace

void addGeneratorNodes(std::vector<NodeType>& out) {
  addNodeTypes<Uniform<1>, Uniform<3>, Fbm, FbmBands, ValueNoise, WhiteNoise, Voronoi,
               GradientLinear, GradientRadial, Stripes, Checker, Shape, Tile, Herringbone, Weave>(
      out);
}

}  // namespace ps::graphimpl
