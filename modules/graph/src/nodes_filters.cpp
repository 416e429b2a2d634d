// Filter nodes: blend, levels, curve, HSL, gradient map, blurs, warps, transform, height ->
// normal, edge detect, histogram scan, invert, clamp, grayscale. Every filter wraps around the
// edges (periodic), and every spatial quantity is in texture units.
#include "node.hpp"
#include "photoscene/core/color.hpp"

#include <algorithm>

namespace ps::graphimpl {
namespace {

constexpr double kTwoPi = 6.283185307179586;

/// Central differences of a gray plane in texture units (+u right, +v up):
/// gx = (h[x+1] - h[x-1]) n / 2, gy = (h[y-1] - h[y+1]) n / 2.
template <class T>
void centralDiff(const Plane<T>& h, int x, int y, T& gx, T& gy) {
  const int n = h.n, m = n - 1;
  gx = (h.at((x + 1) & m, y) - h.at((x - 1) & m, y)) * T(0.5) * T(n);
  gy = (h.at(x, (y - 1) & m) - h.at(x, (y + 1) & m)) * T(0.5) * T(n);
}
/// Adjoint of centralDiff: given dL/dgx (Gx) and dL/dgy (Gy) per pixel, accumulates dL/dh.
template <class T>
void centralDiffAdjoint(const Plane<T>& Gx, const Plane<T>& Gy, Plane<T>& dh) {
  const int n = dh.n, m = n - 1;
  const T s = T(0.5) * T(n);
  forRows(n, [&](int y) {
    const T* gx = Gx.row(y);
    const T* gyd = Gy.row((y + 1) & m);
    const T* gyu = Gy.row((y - 1) & m);
    T* d = dh.row(y);
    for (int x = 0; x < n; ++x)
      d[x] += s * (gx[(x - 1) & m] - gx[(x + 1) & m] + gyd[x] - gyu[x]);
  });
}
/// Backward through centralDiff of the gray plane h: for every pixel in order,
/// pixel(x, y, gx, gy, Gx, Gy) sets Gx, Gy = d loss / d gx, d gy (left 0 when not set); then d loss
/// / d h is accumulated into dh (when not null). Gx, Gy are kept in the node's scratch.
template <class T, class F>
void centralDiffBackward(NodeCtx<T>& c, const Plane<T>& h, Plane<T>* dh, F&& pixel) {
  const int n = c.n;
  c.scratch->resize(2);
  Plane<T>& Gx = (*c.scratch)[0];
  Plane<T>& Gy = (*c.scratch)[1];
  Gx.zeros(n, 1);
  Gy.zeros(n, 1);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      T gx, gy;
      centralDiff(h, x, y, gx, gy);
      pixel(x, y, gx, gy, Gx.at(x, y), Gy.at(x, y));
    }
  if (dh) centralDiffAdjoint(Gx, Gy, *dh);
}

/// Derivatives of the loss through out(x, y) = in0(sx, sy) (sampleBilinear) in the sample
/// position: Dx = sum over channels of d loss / d out * d in0 / d sx, Dy likewise.
template <class T>
void sampleGradient(const NodeCtx<T>& c, int x, int y, T sx, T sy, T& Dx, T& Dy) {
  T tmp[3], sgx[3], sgy[3];
  sampleBilinear(*c.in[0], sx, sy, tmp, sgx, sgy);
  const T* g = c.dOut[0]->ptr(x, y);
  Dx = 0, Dy = 0;
  for (int q = 0; q < c.out[0]->c; ++q) Dx += g[q] * sgx[q], Dy += g[q] * sgy[q];
}

/// The loops of a point operation on input 0 (per value, any channel count). mapValues: out =
/// f(in), rows in parallel. visitValueGradients: body(a, g, da) for every value in order, a the
/// input, g = d loss / d out, da the input's gradient to accumulate into (null when not needed).
template <class T, class F>
void mapValues(NodeCtx<T>& c, F&& f) {
  const int len = c.n * c.out[0]->c;
  forRows(c.n, [&](int y) {
    const T* a = c.in[0]->row(y);
    T* o = c.out[0]->row(y);
    for (int i = 0; i < len; ++i) o[i] = f(a[i]);
  });
}
template <class T, class F>
void visitValueGradients(NodeCtx<T>& c, F&& body) {
  const int len = c.n * c.out[0]->c;
  for (int y = 0; y < c.n; ++y) {
    const T* a = c.in[0]->row(y);
    const T* g = c.dOut[0]->row(y);
    T* da = c.dIn[0] ? c.dIn[0]->row(y) : nullptr;
    for (int i = 0; i < len; ++i) body(a[i], g[i], da ? da + i : nullptr);
  }
}

// ---------------------------------------------------------------- blend
struct Blend {
  enum { kMode, kOpacity };
  static NodeTypeDesc desc() {
    return {"blend",
            "Blends fg over bg: out = bg + opacity * mask * (f(fg, bg) - bg), f by mode (copy = "
            "lerp by mask, add, multiply, screen, overlay, min, max, subtract = bg - fg).",
            {{"fg", 0}, {"bg", 0}, {"mask", 1, true}},
            {{"out", 0}},
            {pChoice("mode",
                     {"copy", "add", "multiply", "screen", "overlay", "min", "max", "subtract"}, 0,
                     "blend mode"),
             pCont("opacity", 0, 1, 1, "blend amount")}};
  }
  template <class T>
  static inline T f(int mode, T a, T b, T& fa, T& fb) {
    switch (mode) {
      case 0: fa = 1, fb = 0; return a;
      case 1: fa = 1, fb = 1; return a + b;
      case 2: fa = b, fb = a; return a * b;
      case 3: fa = 1 - b, fb = 1 - a; return 1 - (1 - a) * (1 - b);
      case 4:
        if (b < T(0.5)) {
          fa = 2 * b, fb = 2 * a;
          return 2 * a * b;
        }
        fa = 2 * (1 - b), fb = 2 * (1 - a);
        return 1 - 2 * (1 - a) * (1 - b);
      case 5: fa = a < b ? 1 : 0, fb = 1 - fa; return std::min(a, b);
      case 6: fa = a > b ? 1 : 0, fb = 1 - fa; return std::max(a, b);
      default: fa = -1, fb = 1; return b - a;
    }
  }
  /// Calls fn(std::integral_constant<int, mode>) so the per-pixel mode switch folds away.
  template <class Fn>
  static void withMode(int mode, Fn&& fn) {
    switch (mode) {
      case 0: fn(std::integral_constant<int, 0>{}); break;
      case 1: fn(std::integral_constant<int, 1>{}); break;
      case 2: fn(std::integral_constant<int, 2>{}); break;
      case 3: fn(std::integral_constant<int, 3>{}); break;
      case 4: fn(std::integral_constant<int, 4>{}); break;
      case 5: fn(std::integral_constant<int, 5>{}); break;
      case 6: fn(std::integral_constant<int, 6>{}); break;
      default: fn(std::integral_constant<int, 7>{}); break;
    }
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    withMode(c.I(kMode), [&](auto M) { forwardM<T, decltype(M)::value>(c); });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    withMode(c.I(kMode), [&](auto M) { backwardM<T, decltype(M)::value>(c); });
  }
  template <class T, int mode>
  static void forwardM(NodeCtx<T>& c) {
    const int n = c.n, ch = c.out[0]->c;
    const T op = c.P(kOpacity);
    forRows(n, [&](int y) {
      const T* a = c.in[0]->row(y);
      const T* b = c.in[1]->row(y);
      const T* mk = c.in[2] ? c.in[2]->row(y) : nullptr;
      T* o = c.out[0]->row(y);
      for (int x = 0; x < n; ++x) {
        const T w = op * (mk ? mk[x] : T(1));
        for (int k = 0; k < ch; ++k) {
          const int i = x * ch + k;
          T fa, fb;
          o[i] = b[i] + w * (f(mode, a[i], b[i], fa, fb) - b[i]);
        }
      }
    });
  }
  template <class T, int mode>
  static void backwardM(NodeCtx<T>& c) {
    const int n = c.n, ch = c.out[0]->c;
    const T op = c.P(kOpacity);
    T dop = 0;
    for (int y = 0; y < n; ++y) {
      const T* a = c.in[0]->row(y);
      const T* b = c.in[1]->row(y);
      const T* mk = c.in[2] ? c.in[2]->row(y) : nullptr;
      const T* g = c.dOut[0]->row(y);
      T* da = c.dIn[0] ? c.dIn[0]->row(y) : nullptr;
      T* db = c.dIn[1] ? c.dIn[1]->row(y) : nullptr;
      T* dm = c.dIn[2] ? c.dIn[2]->row(y) : nullptr;
      for (int x = 0; x < n; ++x) {
        const T m = mk ? mk[x] : T(1);
        const T w = op * m;
        T gm = 0;
        for (int k = 0; k < ch; ++k) {
          const int i = x * ch + k;
          T fa, fb;
          const T diff = f(mode, a[i], b[i], fa, fb) - b[i];
          if (da) da[i] += g[i] * w * fa;
          if (db) db[i] += g[i] * (1 - w + w * fb);
          gm += g[i] * diff;
        }
        dop += gm * m;
        if (dm) dm[x] += gm * op;
      }
    }
    c.dP(kOpacity) += dop;
  }
};

// ---------------------------------------------------------------- levels
struct Levels {
  enum { kInLow, kInHigh, kGamma, kOutLow, kOutHigh };
  static NodeTypeDesc desc() {
    return {"levels",
            "out = out_low + (out_high - out_low) * clamp((x - in_low) / (in_high - in_low), 0, "
            "1)^(1/gamma), per channel.",
            {{"in", 0}},
            {{"out", 0}},
            {pCont("in_low", -1, 2, 0, "input black point"),
             pCont("in_high", -1, 2, 1, "input white point"),
             pCont("gamma", 0.2f, 5, 1, "midtone gamma (> 1 brightens)"),
             pCont("out_low", -1, 2, 0, "output black"), pCont("out_high", -1, 2, 1, "output white")}};
  }
  template <class T>
  static T den(const NodeCtx<T>& c) {
    const T d = c.P(kInHigh) - c.P(kInLow);
    return std::abs(d) < T(1e-4) ? (d < 0 ? T(-1e-4) : T(1e-4)) : d;
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const T il = c.P(kInLow), d = den(c), ig = T(1) / c.P(kGamma), ol = c.P(kOutLow),
            oh = c.P(kOutHigh);
    auto t = [&](T a) { return std::max(clamp01((a - il) / d), T(1e-4)); };
    if (ig == T(1))  // no pow
      mapValues(c, [&](T a) { return ol + (oh - ol) * t(a); });
    else
      mapValues(c, [&](T a) { return ol + (oh - ol) * std::pow(t(a), ig); });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const T il = c.P(kInLow), ih = c.P(kInHigh), d = den(c), gm = c.P(kGamma), ig = T(1) / gm,
            ol = c.P(kOutLow), oh = c.P(kOutHigh);
    const bool guarded = std::abs(ih - il) < T(1e-4);
    const bool unit = ig == T(1), wantGamma = c.wantP(kGamma);  // no pow / log unless needed
    T dil = 0, dih = 0, dgm = 0, dol = 0, doh = 0;
    visitValueGradients(c, [&](T a, T g, T* da) {
      const T t = (a - il) / d;
      const T te = std::max(clamp01(t), T(1e-4));
      const T p = unit ? te : std::pow(te, ig);
      dol += g * (1 - p);
      doh += g * p;
      const T gp = g * (oh - ol);
      if (wantGamma) dgm += gp * p * std::log(te) * (-ig * ig);
      if (t > T(1e-4) && t < 1) {
        const T gt = gp * ig * p / te;
        if (da) *da += gt / d;
        if (!guarded) {
          dil += gt * (a - ih) / (d * d);
          dih -= gt * (a - il) / (d * d);
        }
      }
    });
    c.dP(kInLow) += dil;
    c.dP(kInHigh) += dih;
    c.dP(kGamma) += dgm;
    c.dP(kOutLow) += dol;
    c.dP(kOutHigh) += doh;
  }
};

// ---------------------------------------------------------------- curve
struct Curve {
  static NodeTypeDesc desc() {
    return {"curve",
            "A tone curve through 5 points at x = 0, 0.25, 0.5, 0.75, 1 (piecewise linear; input "
            "clamped to [0, 1]), per channel.",
            {{"in", 0}},
            {{"out", 0}},
            {pCont("p0", -0.5f, 1.5f, 0, "value at 0"), pCont("p1", -0.5f, 1.5f, 0.25f, "at 0.25"),
             pCont("p2", -0.5f, 1.5f, 0.5f, "at 0.5"), pCont("p3", -0.5f, 1.5f, 0.75f, "at 0.75"),
             pCont("p4", -0.5f, 1.5f, 1, "value at 1")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    T p[5];
    for (int k = 0; k < 5; ++k) p[k] = c.P(k);
    mapValues(c, [&](T a) {
      const T t = clamp01(a) * 4;
      const int s = std::min(3, int(t));
      return p[s] + (t - s) * (p[s + 1] - p[s]);
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    T p[5], dp[5] = {0, 0, 0, 0, 0};
    for (int k = 0; k < 5; ++k) p[k] = c.P(k);
    visitValueGradients(c, [&](T a, T g, T* da) {
      const T t = clamp01(a) * 4;
      const int s = std::min(3, int(t));
      const T f = t - s;
      dp[s] += g * (1 - f);
      dp[s + 1] += g * f;
      if (da && a > 0 && a < 1) *da += g * 4 * (p[s + 1] - p[s]);
    });
    for (int k = 0; k < 5; ++k) c.dP(k) += dp[k];
  }
};

// ---------------------------------------------------------------- HSL adjust
struct Hsl {
  enum { kHue, kSat, kLight };
  static NodeTypeDesc desc() {
    return {"hsl",
            "HSL-style adjust in linear RGB: hue rotates the chroma about the gray axis (turns), "
            "saturation scales the chroma, lightness is added: out = m + lightness + saturation * "
            "R(hue)(rgb - m), m = mean(rgb).",
            {{"in", 3}},
            {{"out", 3}},
            {pCont("hue", -0.5f, 0.5f, 0, "hue rotation in turns"),
             pCont("saturation", 0, 2, 1, "chroma scale"),
             pCont("lightness", -0.5f, 0.5f, 0, "added to every channel")}};
  }
  template <class T>
  static void cross(const T* c, T* o) {  // (1,1,1)/sqrt(3) x c
    const T a = T(0.5773502691896258);
    o[0] = a * (c[2] - c[1]);
    o[1] = a * (c[0] - c[2]);
    o[2] = a * (c[1] - c[0]);
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const T th = c.P(kHue) * T(kTwoPi), cs = std::cos(th), sn = std::sin(th), S = c.P(kSat),
            L = c.P(kLight);
    forRows(c.n, [&](int y) {
      const T* a = c.in[0]->row(y);
      T* o = c.out[0]->row(y);
      for (int x = 0; x < c.n; ++x) {
        const T* p = a + 3 * x;
        const T m = (p[0] + p[1] + p[2]) / 3;
        const T ch[3] = {p[0] - m, p[1] - m, p[2] - m};
        T kc[3];
        cross(ch, kc);
        for (int k = 0; k < 3; ++k) o[3 * x + k] = m + L + S * (cs * ch[k] + sn * kc[k]);
      }
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const T th = c.P(kHue) * T(kTwoPi), cs = std::cos(th), sn = std::sin(th), S = c.P(kSat);
    T dh = 0, ds = 0, dl = 0;
    for (int y = 0; y < c.n; ++y) {
      const T* a = c.in[0]->row(y);
      const T* gr = c.dOut[0]->row(y);
      T* da = c.dIn[0] ? c.dIn[0]->row(y) : nullptr;
      for (int x = 0; x < c.n; ++x) {
        const T* p = a + 3 * x;
        const T* g = gr + 3 * x;
        const T m = (p[0] + p[1] + p[2]) / 3;
        const T ch[3] = {p[0] - m, p[1] - m, p[2] - m};
        T kc[3];
        cross(ch, kc);
        for (int k = 0; k < 3; ++k) {
          dl += g[k];
          ds += g[k] * (cs * ch[k] + sn * kc[k]);
          dh += g[k] * S * (-sn * ch[k] + cs * kc[k]);
        }
        if (da) {
          const T gm = (g[0] + g[1] + g[2]) / 3;
          T kg[3];
          cross(g, kg);
          for (int k = 0; k < 3; ++k) da[3 * x + k] += gm + S * (cs * (g[k] - gm) - sn * kg[k]);
        }
      }
    }
    c.dP(kHue) += dh * T(kTwoPi);
    c.dP(kSat) += ds;
    c.dP(kLight) += dl;
  }
};

// ---------------------------------------------------------------- gradient map
struct GradientMap {
  enum { kC0, kC1, kC2, kPos };
  static NodeTypeDesc desc() {
    return {"gradient_map",
            "Maps a gray image (clamped to [0, 1]) to a color ramp color_0 (at 0) -> color_1 (at "
            "position) -> color_2 (at 1), linear RGB.",
            {{"in", 1}},
            {{"out", 3}},
            {pColor("color_0", 0.1f, 0.1f, 0.1f, "color at 0"),
             pColor("color_1", 0.5f, 0.5f, 0.5f, "color at position"),
             pColor("color_2", 0.9f, 0.9f, 0.9f, "color at 1"),
             pCont("position", 0.05f, 0.95f, 0.5f, "where color_1 sits")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const T p = c.P(kPos);
    T col[3][3];
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) col[j][k] = c.P(kC0 + j, k);
    forRows(c.n, [&](int y) {
      const T* a = c.in[0]->row(y);
      T* o = c.out[0]->row(y);
      for (int x = 0; x < c.n; ++x) {
        const T t = clamp01(a[x]);
        const bool lo = t < p;
        const T w = lo ? t / p : (t - p) / (1 - p);
        const T* c0 = lo ? col[0] : col[1];
        const T* c1 = lo ? col[1] : col[2];
        for (int k = 0; k < 3; ++k) o[3 * x + k] = c0[k] + w * (c1[k] - c0[k]);
      }
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const T p = c.P(kPos);
    T col[3][3], dcol[3][3] = {}, dp = 0;
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) col[j][k] = c.P(kC0 + j, k);
    for (int y = 0; y < c.n; ++y) {
      const T* a = c.in[0]->row(y);
      const T* g = c.dOut[0]->row(y);
      T* da = c.dIn[0] ? c.dIn[0]->row(y) : nullptr;
      for (int x = 0; x < c.n; ++x) {
        const T t = clamp01(a[x]);
        const bool lo = t < p;
        const int j0 = lo ? 0 : 1;
        const T w = lo ? t / p : (t - p) / (1 - p);
        const T dwdt = lo ? 1 / p : 1 / (1 - p);
        const T dwdp = lo ? -t / (p * p) : (t - 1) / ((1 - p) * (1 - p));
        T gw = 0;
        for (int k = 0; k < 3; ++k) {
          const T gk = g[3 * x + k];
          dcol[j0][k] += gk * (1 - w);
          dcol[j0 + 1][k] += gk * w;
          gw += gk * (col[j0 + 1][k] - col[j0][k]);
        }
        dp += gw * dwdp;
        if (da && a[x] > 0 && a[x] < 1) da[x] += gw * dwdt;
      }
    }
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c.dP(kC0 + j, k) += dcol[j][k];
    c.dP(kPos) += dp;
  }
};

// ---------------------------------------------------------------- gaussian blur
struct Blur {
  enum { kSigma };
  static NodeTypeDesc desc() {
    return {"blur", "Gaussian blur (separable, wrapping); sigma in texture units.", {{"in", 0}},
            {{"out", 0}}, {pCont("sigma", 0, 0.05f, 0.005f, "standard deviation")}};
  }
  template <class T>
  static void kernel(T sp, std::vector<T>& k, std::vector<T>& dk) {
    const int R = std::max(1, int(std::ceil(3 * sp)));
    k.assign(2 * R + 1, 0);
    dk.assign(2 * R + 1, 0);
    T z = 0, m2 = 0;
    for (int i = -R; i <= R; ++i) z += (k[i + R] = std::exp(-T(i * i) / (2 * sp * sp)));
    for (int i = -R; i <= R; ++i) m2 += (k[i + R] /= z) * T(i * i);
    for (int i = -R; i <= R; ++i) dk[i + R] = k[i + R] * (T(i * i) - m2) / (sp * sp * sp);
  }
  /// out = K conv in along x (horiz) or y, wrapping.
  template <class T>
  static void conv(const Plane<T>& in, Plane<T>& out, const std::vector<T>& k, bool horiz) {
    const int n = in.n, ch = in.c, R = int(k.size()) / 2, m = n - 1;
    out.create(n, ch);
    forRows(n, [&](int y) {
      T* o = out.row(y);
      std::fill(o, o + n * ch, T(0));
      for (int j = -R; j <= R; ++j) {
        const T w = k[j + R];
        if (horiz) {
          const T* src = in.row(y);
          for (int x = 0; x < n; ++x) {
            const T* s = src + ((x + j) & m) * ch;
            for (int q = 0; q < ch; ++q) o[x * ch + q] += w * s[q];
          }
        } else {
          const T* src = in.row((y + j) & m);
          for (int i = 0; i < n * ch; ++i) o[i] += w * src[i];
        }
      }
    });
  }
  template <class T>
  static T dotConv(const Plane<T>& g, const Plane<T>& in, const std::vector<T>& k, bool horiz) {
    thread_local Plane<T> tmp;  // reused between calls (no allocation per backward)
    conv(in, tmp, k, horiz);
    T s = 0;
    for (size_t i = 0; i < tmp.d.size(); ++i) s += g.d[i] * tmp.d[i];
    return s;
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const T sp = c.P(kSigma) * T(c.n);
    if (sp < T(0.2)) {
      c.out[0]->d = c.in[0]->d;
      return;
    }
    std::vector<T> k, dk;
    kernel(sp, k, dk);
    if (c.scratch->empty()) c.scratch->resize(1);
    conv(*c.in[0], (*c.scratch)[0], k, true);
    conv((*c.scratch)[0], *c.out[0], k, false);
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const T sp = c.P(kSigma) * T(c.n);
    if (sp < T(0.2)) {
      if (c.dIn[0])
        for (size_t i = 0; i < c.dIn[0]->d.size(); ++i) c.dIn[0]->d[i] += c.dOut[0]->d[i];
      return;
    }
    std::vector<T> k, dk;
    kernel(sp, k, dk);
    c.scratch->resize(3);
    Plane<T>& A = (*c.scratch)[1];
    Plane<T>& B = (*c.scratch)[2];
    conv(*c.dOut[0], A, k, false);  // Ky^T dOut
    if (c.dIn[0]) {
      conv(A, B, k, true);
      for (size_t i = 0; i < B.d.size(); ++i) c.dIn[0]->d[i] += B.d[i];
    }
    if (c.needParamGrad) {
      const T d = dotConv(*c.dOut[0], (*c.scratch)[0], dk, false) + dotConv(A, *c.in[0], dk, true);
      c.dP(kSigma) += d * T(c.n);
    }
  }
};

// ---------------------------------------------------------------- directional blur
struct DirectionalBlur {
  enum { kLength, kAngle, kTaps };
  static NodeTypeDesc desc() {
    return {"directional_blur",
            "Motion blur: the mean of `taps` bilinear samples along a segment of `length` "
            "(texture units) at `angle` (turns, 0 = +u, 0.25 = +v), centered on the pixel.",
            {{"in", 0}},
            {{"out", 0}},
            {pCont("length", 0, 0.25f, 0.02f, "segment length"),
             pCont("angle", -0.5f, 0.5f, 0, "direction in turns"),
             pInt("taps", 2, 64, 16, "samples")}};
  }
  /// A tap's offset is the same for every pixel: integer shift (ix, iy) and bilinear fractions
  /// (fx, fy) computed once per tap instead of a floor per pixel.
  template <class T>
  struct Tap {
    int ix, iy;
    T fx, fy;
    Tap(T ax, T ay) {
      const T flx = std::floor(ax), fly = std::floor(ay);
      ix = static_cast<int>(flx), iy = static_cast<int>(fly);
      fx = ax - flx, fy = ay - fly;
    }
  };
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n, K = c.I(kTaps), ch = c.out[0]->c, m = n - 1;
    const T th = c.P(kAngle) * T(kTwoPi), L = c.P(kLength);
    const T ox = L * std::cos(th) * T(n), oy = -L * std::sin(th) * T(n);
    const Plane<T>& in = *c.in[0];
    forRows(n, [&](int y) {
      T* o = c.out[0]->row(y);
      std::fill(o, o + n * ch, T(0));
      for (int k = 0; k < K; ++k) {
        const T t = T(k) / T(K - 1) - T(0.5);
        const Tap<T> tp(t * ox, t * oy);
        const T* r0 = in.row((y + tp.iy) & m);
        const T* r1 = in.row((y + tp.iy + 1) & m);
        const T fx = tp.fx, fy = tp.fy;
        for (int x = 0; x < n; ++x) {
          const int x0 = (x + tp.ix) & m, x1 = (x0 + 1) & m;
          for (int q = 0; q < ch; ++q) {
            const T a = r0[x0 * ch + q], b = r0[x1 * ch + q], cc = r1[x0 * ch + q], dd = r1[x1 * ch + q];
            const T top = a + fx * (b - a), bot = cc + fx * (dd - cc);
            o[x * ch + q] += (top + fy * (bot - top)) / T(K);
          }
        }
      }
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int n = c.n, K = c.I(kTaps), ch = c.out[0]->c, m = n - 1;
    const T th = c.P(kAngle) * T(kTwoPi), L = c.P(kLength);
    const T cs = std::cos(th), sn = std::sin(th);
    const T ox = L * cs * T(n), oy = -L * sn * T(n);
    const bool wantP = c.wantP(kLength) || c.wantP(kAngle);
    const Plane<T>& in = *c.in[0];
    T dL = 0, dth = 0;
    for (int k = 0; k < K; ++k) {
      const T t = T(k) / T(K - 1) - T(0.5);
      const Tap<T> tp(t * ox, t * oy);
      const T fx = tp.fx, fy = tp.fy;
      const T w00 = (1 - fx) * (1 - fy), w10 = fx * (1 - fy), w01 = (1 - fx) * fy, w11 = fx * fy;
      T tDx = 0, tDy = 0;  // sum over pixels of d loss / d sample position for this tap
      for (int y = 0; y < n; ++y) {
        const int y0 = (y + tp.iy) & m, y1 = (y0 + 1) & m, ym = (y0 - 1) & m;
        const T* g = c.dOut[0]->row(y);
        if (wantP) {
          const T* r0 = in.row(y0);
          const T* r1 = in.row(y1);
          const T* rm = in.row(ym);
          for (int x = 0; x < n; ++x) {
            const int x0 = (x + tp.ix) & m, x1 = (x0 + 1) & m, xm = (x0 - 1) & m;
            for (int q = 0; q < ch; ++q) {
              const T a = r0[x0 * ch + q], b = r0[x1 * ch + q], cc = r1[x0 * ch + q], dd = r1[x1 * ch + q];
              const T top = a + fx * (b - a), bot = cc + fx * (dd - cc);
              // derivatives as sampleBilinear (central differences exactly on a pixel center)
              T gx = (1 - fy) * (b - a) + fy * (dd - cc), gy = bot - top;
              if (fx == T(0)) gx = T(0.5) * ((1 - fy) * (b - r0[xm * ch + q]) + fy * (dd - r1[xm * ch + q]));
              if (fy == T(0)) {
                const T um = rm[x0 * ch + q], umx = rm[x1 * ch + q];
                gy = T(0.5) * (bot - (um + fx * (umx - um)));
              }
              const T gs = g[x * ch + q] / T(K);
              tDx += gs * gx;
              tDy += gs * gy;
            }
          }
        }
        if (c.dIn[0]) {
          T* d0 = c.dIn[0]->row(y0);
          T* d1 = c.dIn[0]->row(y1);
          for (int x = 0; x < n; ++x) {
            const int x0 = (x + tp.ix) & m, x1 = (x0 + 1) & m;
            for (int q = 0; q < ch; ++q) {
              const T gs = g[x * ch + q] / T(K);
              d0[x0 * ch + q] += w00 * gs;
              d0[x1 * ch + q] += w10 * gs;
              d1[x0 * ch + q] += w01 * gs;
              d1[x1 * ch + q] += w11 * gs;
            }
          }
        }
      }
      // d(sx)/dL = t cs n, d(sy)/dL = -t sn n; d(sx)/dth = -t L sn n, d(sy)/dth = -t L cs n
      dL += t * T(n) * (tDx * cs - tDy * sn);
      dth += -t * L * T(n) * (tDx * sn + tDy * cs);
    }
    c.dP(kLength) += dL;
    c.dP(kAngle) += dth * T(kTwoPi);
  }
};

// ---------------------------------------------------------------- warp / directional warp
struct Warp {
  enum { kIntensity };
  static NodeTypeDesc desc() {
    return {"warp",
            "out(t) = in(t + intensity * grad(height)(t)); the gradient is in texture units.",
            {{"in", 0}, {"height", 1}},
            {{"out", 0}},
            {pCont("intensity", -0.02f, 0.02f, 0.003f, "displacement per unit of gradient")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n, ch = c.out[0]->c;
    const T k = c.P(kIntensity);
    forRows(n, [&](int y) {
      for (int x = 0; x < n; ++x) {
        T gx, gy;
        centralDiff(*c.in[1], x, y, gx, gy);
        sampleBilinear(*c.in[0], T(x) + k * gx * T(n), T(y) - k * gy * T(n), c.out[0]->ptr(x, y));
      }
    });
    (void)ch;
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int n = c.n;
    const T k = c.P(kIntensity);
    T dk = 0;
    centralDiffBackward(c, *c.in[1], c.dIn[1], [&](int x, int y, T gx, T gy, T& Gx, T& Gy) {
      const T sx = T(x) + k * gx * T(n), sy = T(y) - k * gy * T(n);
      T Dx, Dy;
      sampleGradient(c, x, y, sx, sy, Dx, Dy);
      dk += Dx * gx * T(n) - Dy * gy * T(n);
      Gx = Dx * k * T(n);
      Gy = -Dy * k * T(n);
      if (c.dIn[0]) scatterBilinear(*c.dIn[0], sx, sy, c.dOut[0]->ptr(x, y));
    });
    c.dP(kIntensity) += dk;
  }
};

struct DirectionalWarp {
  enum { kIntensity, kAngle };
  static NodeTypeDesc desc() {
    return {"directional_warp",
            "out(t) = in(t + intensity * height(t) * (cos a, sin a)), a = 2 pi angle.",
            {{"in", 0}, {"height", 1}},
            {{"out", 0}},
            {pCont("intensity", -0.2f, 0.2f, 0.02f, "displacement at height 1 (texture units)"),
             pCont("angle", -0.5f, 0.5f, 0, "direction in turns")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n;
    const T th = c.P(kAngle) * T(kTwoPi), k = c.P(kIntensity);
    const T ox = k * std::cos(th) * T(n), oy = -k * std::sin(th) * T(n);
    forRows(n, [&](int y) {
      for (int x = 0; x < n; ++x) {
        const T h = c.in[1]->at(x, y);
        sampleBilinear(*c.in[0], T(x) + h * ox, T(y) + h * oy, c.out[0]->ptr(x, y));
      }
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int n = c.n;
    const T th = c.P(kAngle) * T(kTwoPi), k = c.P(kIntensity);
    const T cs = std::cos(th), sn = std::sin(th);
    const T ox = k * cs * T(n), oy = -k * sn * T(n);
    T dk = 0, dth = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const T h = c.in[1]->at(x, y);
        const T sx = T(x) + h * ox, sy = T(y) + h * oy;
        T Dx, Dy;
        sampleGradient(c, x, y, sx, sy, Dx, Dy);
        if (c.dIn[1]) c.dIn[1]->at(x, y) += Dx * ox + Dy * oy;
        dk += h * T(n) * (Dx * cs - Dy * sn);
        dth += -h * k * T(n) * (Dx * sn + Dy * cs);
        if (c.dIn[0]) scatterBilinear(*c.dIn[0], sx, sy, c.dOut[0]->ptr(x, y));
      }
    c.dP(kIntensity) += dk;
    c.dP(kAngle) += dth * T(kTwoPi);
  }
};

// ---------------------------------------------------------------- transform
struct Transform {
  enum { kTile, kRotation, kOffU, kOffV };
  static NodeTypeDesc desc() {
    return {"transform",
            "out(t) = in(R (tile * t) + offset): tiles the input tile x tile times, rotates by a "
            "multiple of 90 degrees (counter-clockwise) and shifts (wrapping, bilinear).",
            {{"in", 0}},
            {{"out", 0}},
            {pInt("tile", 1, 64, 1, "repeats per unit"),
             pChoice("rotation", {"0", "90", "180", "270"}, 0, "rotation"),
             pCont("offset_u", -1, 1, 0, "shift along u"),
             pCont("offset_v", -1, 1, 0, "shift along v")}};
  }
  template <class T>
  static void source(const NodeCtx<T>& c, int x, int y, T& sx, T& sy) {
    const T tl = T(c.I(kTile));
    T u = (T(x) + T(0.5)) / T(c.n) * tl, v = (T(1) - (T(y) + T(0.5)) / T(c.n)) * tl;
    for (int r = 0; r < c.I(kRotation); ++r) {
      const T t = u;
      u = -v;
      v = t;
    }
    u += c.P(kOffU);
    v += c.P(kOffV);
    sx = u * T(c.n) - T(0.5);
    sy = (T(1) - v) * T(c.n) - T(0.5);
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    forRows(c.n, [&](int y) {
      for (int x = 0; x < c.n; ++x) {
        T sx, sy;
        source(c, x, y, sx, sy);
        sampleBilinear(*c.in[0], sx, sy, c.out[0]->ptr(x, y));
      }
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int ch = c.out[0]->c;
    T du = 0, dv = 0, tmp[3], sgx[3], sgy[3];
    for (int y = 0; y < c.n; ++y)
      for (int x = 0; x < c.n; ++x) {
        T sx, sy;
        source(c, x, y, sx, sy);
        sampleBilinear(*c.in[0], sx, sy, tmp, sgx, sgy);
        const T* g = c.dOut[0]->ptr(x, y);
        for (int q = 0; q < ch; ++q) du += g[q] * sgx[q] * T(c.n), dv -= g[q] * sgy[q] * T(c.n);
        if (c.dIn[0]) scatterBilinear(*c.dIn[0], sx, sy, g);
      }
    c.dP(kOffU) += du;
    c.dP(kOffV) += dv;
  }
};

// ---------------------------------------------------------------- height -> normal
struct Normal {
  enum { kIntensity };
  static NodeTypeDesc desc() {
    return {"normal",
            "Tangent-space normal from a height map: normalize(-k dh/du, -k dh/dv, 1) (OpenGL "
            "convention, derivatives in texture units, central differences).",
            {{"height", 1}},
            {{"out", 3}},
            {pCont("intensity", 0, 0.2f, 0.02f, "height scale k (texture units per unit height)")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const int n = c.n, m = n - 1;
    const T k = c.P(kIntensity), hn = T(0.5) * T(n);
    forRows(n, [&](int y) {
      const T* r = c.in[0]->row(y);
      const T* up = c.in[0]->row((y - 1) & m);
      const T* dn = c.in[0]->row((y + 1) & m);
      T* o = c.out[0]->row(y);
      for (int x = 0; x < n; ++x) {
        const T gx = (r[(x + 1) & m] - r[(x - 1) & m]) * hn, gy = (up[x] - dn[x]) * hn;
        const T a = -k * gx, b = -k * gy, il = T(1) / std::sqrt(a * a + b * b + 1);
        o[3 * x] = a * il, o[3 * x + 1] = b * il, o[3 * x + 2] = il;
      }
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const int n = c.n, m = n - 1;
    const T k = c.P(kIntensity), hn = T(0.5) * T(n);
    // d loss / d height = adjoint of the central differences of (Gx, Gy); two rows of each kept
    auto& S = *c.scratch;
    S.resize(2);
    Plane<T>& Gx = S[0];
    Plane<T>& Gy = S[1];
    Gx.create(n, 1);
    Gy.create(n, 1);
    T dk = 0;
    for (int y = 0; y < n; ++y) {
      const T* r = c.in[0]->row(y);
      const T* up = c.in[0]->row((y - 1) & m);
      const T* dn = c.in[0]->row((y + 1) & m);
      const T* g = c.dOut[0]->row(y);
      T* gxr = Gx.row(y);
      T* gyr = Gy.row(y);
      for (int x = 0; x < n; ++x) {
        const T gx = (r[(x + 1) & m] - r[(x - 1) & m]) * hn, gy = (up[x] - dn[x]) * hn;
        const T a = -k * gx, b = -k * gy, il = T(1) / std::sqrt(a * a + b * b + 1);
        const T nn[3] = {a * il, b * il, il};
        const T* gg = g + 3 * x;
        const T dot = gg[0] * nn[0] + gg[1] * nn[1] + gg[2] * nn[2];
        const T da = (gg[0] - nn[0] * dot) * il, db = (gg[1] - nn[1] * dot) * il;
        dk += -da * gx - db * gy;
        gxr[x] = -k * da;
        gyr[x] = -k * db;
      }
    }
    if (c.dIn[0]) centralDiffAdjoint(Gx, Gy, *c.dIn[0]);
    c.dP(kIntensity) += dk;
  }
};

// ---------------------------------------------------------------- edge detect
struct EdgeDetect {
  enum { kStrength };
  static NodeTypeDesc desc() {
    return {"edge_detect",
            "Edge strength: min(1, strength * |grad(in)|), gradient in texture units.",
            {{"in", 1}},
            {{"out", 1}},
            {pCont("strength", 0, 0.1f, 0.01f, "scale of the gradient magnitude")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const T s = c.P(kStrength);
    forRows(c.n, [&](int y) {
      for (int x = 0; x < c.n; ++x) {
        T gx, gy;
        centralDiff(*c.in[0], x, y, gx, gy);
        c.out[0]->at(x, y) = std::min(T(1), s * std::sqrt(gx * gx + gy * gy + T(1e-12)));
      }
    });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const T s = c.P(kStrength);
    T ds = 0;
    centralDiffBackward(c, *c.in[0], c.dIn[0], [&](int x, int y, T gx, T gy, T& Gx, T& Gy) {
      const T m = std::sqrt(gx * gx + gy * gy + T(1e-12));
      if (s * m >= 1) return;
      const T g = c.dOut[0]->at(x, y);
      ds += g * m;
      Gx = g * s * gx / m;
      Gy = g * s * gy / m;
    });
    c.dP(kStrength) += ds;
  }
};

// ---------------------------------------------------------------- point operations
struct HistogramScan {
  enum { kPos, kContrast };
  static NodeTypeDesc desc() {
    return {"histogram_scan",
            "Thresholds around 1 - position with a ramp of width 1 - contrast: out = clamp((x - (1 "
            "- position)) / (1 - contrast) + 0.5, 0, 1).",
            {{"in", 0}},
            {{"out", 0}},
            {pCont("position", 0, 1, 0.5f, "how much passes (higher = more white)"),
             pCont("contrast", 0, 0.99f, 0.5f, "sharpness of the threshold")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const T c0 = 1 - c.P(kPos), w = 1 - c.P(kContrast);
    mapValues(c, [&](T a) { return clamp01((a - c0) / w + T(0.5)); });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const T c0 = 1 - c.P(kPos), w = 1 - c.P(kContrast);
    T dp = 0, dc = 0;
    visitValueGradients(c, [&](T a, T g, T* da) {
      const T z = (a - c0) / w + T(0.5);
      if (z <= 0 || z >= 1) return;
      if (da) *da += g / w;
      dp += g / w;
      dc += g * (a - c0) / (w * w);
    });
    c.dP(kPos) += dp;
    c.dP(kContrast) += dc;
  }
};

struct Invert {
  static NodeTypeDesc desc() {
    return {"invert", "out = 1 - in, per channel.", {{"in", 0}}, {{"out", 0}}, {}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    mapValues(c, [](T a) { return 1 - a; });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    if (c.dIn[0]) visitValueGradients(c, [](T, T g, T* da) { *da -= g; });
  }
};

struct Clamp {
  enum { kLow, kHigh };
  static NodeTypeDesc desc() {
    return {"clamp", "out = min(max(in, low), high), per channel.", {{"in", 0}}, {{"out", 0}},
            {pCont("low", -1, 2, 0, "lower bound"), pCont("high", -1, 2, 1, "upper bound")}};
  }
  template <class T>
  static void forward(NodeCtx<T>& c) {
    const T lo = c.P(kLow), hi = c.P(kHigh);
    mapValues(c, [&](T a) { return std::min(std::max(a, lo), hi); });
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    const T lo = c.P(kLow), hi = c.P(kHigh);
    T dlo = 0, dhi = 0;
    visitValueGradients(c, [&](T a, T g, T* da) {
      const T v = std::max(a, lo);
      if (v >= hi)
        dhi += g;
      else if (a <= lo)
        dlo += g;
      else if (da)
        *da += g;
    });
    c.dP(kLow) += dlo;
    c.dP(kHigh) += dhi;
  }
};

struct Grayscale {
  static NodeTypeDesc desc() {
    return {"grayscale", "Rec. 709 luminance of a linear RGB image.", {{"in", 3}}, {{"out", 1}},
            {}};
  }
  static constexpr const double* kW = kLuminanceWeights;
  template <class T>
  static void forward(NodeCtx<T>& c) {
    auto& o = c.out[0]->d;
    const auto& a = c.in[0]->d;
    for (size_t i = 0; i < o.size(); ++i)
      o[i] = T(kW[0]) * a[3 * i] + T(kW[1]) * a[3 * i + 1] + T(kW[2]) * a[3 * i + 2];
  }
  template <class T>
  static void backward(NodeCtx<T>& c) {
    if (!c.dIn[0]) return;
    auto& d = c.dIn[0]->d;
    const auto& g = c.dOut[0]->d;
    for (size_t i = 0; i < g.size(); ++i)
      for (int k = 0; k < 3; ++k) d[3 * i + k] += T(kW[k]) * g[i];
  }
};

}  // namespace

void addFilterNodes(std::vector<NodeType>& out) {
  addNodeTypes<Blend, Levels, Curve, Hsl, GradientMap, Blur, DirectionalBlur, Warp, DirectionalWarp,
               Transform, Normal, EdgeDetect, HistogramScan, Invert, Clamp, Grayscale>(out);
}

const std::vector<NodeType>& nodeTypes() {
  static const std::vector<NodeType> types = [] {
    std::vector<NodeType> t;
    addGeneratorNodes(t);
    addFilterNodes(t);
    std::sort(t.begin(), t.end(),
              [](const NodeType& a, const NodeType& b) { return a.desc.name < b.desc.name; });
    return t;
  }();
  return types;
}

const NodeType* findNodeType(const std::string& name) {
  for (const auto& t : nodeTypes())
    if (t.desc.name == name) return &t;
  return nullptr;
}

}  // namespace ps::graphimpl

namespace ps {
std::vector<NodeTypeDesc> nodeCatalog() {
  std::vector<NodeTypeDesc> out;
  for (const auto& t : graphimpl::nodeTypes()) out.push_back(t.desc);
  return out;
}
}  // namespace ps
