// ps::EnvironmentLight: an equirectangular image (or a constant) at infinity, seen through window
// parts or by every ray that leaves the scene.
#include <cmath>

#include <fmt/format.h>

#include "light_geometry.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/io/image_io.hpp"
#include "photoscene/scene/lights.hpp"
#include "photoscene/scene/mesh.hpp"

namespace ps {

namespace {
Mat3f upToY(const Vec3f& up) {
  return Eigen::Quaternionf::FromTwoVectors(up.normalized(), Vec3f(0, 1, 0)).toRotationMatrix();
}
}  // namespace

EnvironmentLight EnvironmentLight::fromDesc(const io::EnvironmentDesc& e,
                                            const std::vector<Part>& parts, const Vec3f& up,
                                            const std::string& file, const std::string& key,
                                            bool loadImage) {
  EnvironmentLight env;
  env.radiance = e.radiance.cast<float>();
  env.rotationDeg = static_cast<float>(e.rotationDeg);
  env.worldToEnv = upToY(up);
  for (size_t i = 0; i < e.windowParts.size(); ++i)
    env.windowParts.push_back(requirePartId(parts, e.windowParts[i], file,
                                            key + ".window_parts[" + std::to_string(i) + "]"));
  if (e.image) {
    env.imagePath = *e.image;
    if (loadImage)
      env.image = io::readImage(*e.image);
    else
      io::readImageInfo(*e.image);  // fail early when missing
  }
  return env;
}

std::unique_ptr<Light> EnvironmentLight::fromJson(const io::JsonValue& entry,
                                                  const LightJsonContext& ctx) {
  PS_Check(ctx.parts, "EnvironmentLight::fromJson: no parts in the context");
  if (!entry.isObject()) entry.fail("an object");
  const io::EnvironmentDesc d =
      io::parseEnvironment(entry, ctx.baseDir.empty() ? "." : ctx.baseDir);
  return std::make_unique<EnvironmentLight>(
      fromDesc(d, *ctx.parts, ctx.up, entry.file(), entry.path(), ctx.loadImages));
}

nlohmann::json EnvironmentLight::toJson(const LightJsonContext& ctx) const {
  nlohmann::json e;
  e["type"] = "environment";
  e["radiance"] = {radiance.x(), radiance.y(), radiance.z()};
  if (!imagePath.empty()) e["image"] = ctx.refer(imagePath);
  e["rotation_deg"] = rotationDeg;
  std::vector<std::string> names;
  for (int p : windowParts) {
    PS_Check(ctx.parts && p >= 0 && p < static_cast<int>(ctx.parts->size()),
             "environment: window part " << p << " not in the context's parts");
    names.push_back((*ctx.parts)[p].name);
  }
  e["window_parts"] = names;
  return e;
}

std::string EnvironmentLight::describe(const std::vector<Part>&) const {
  return fmt::format("{}, {} window parts", image.empty() ? "constant" : "image",
                     windowParts.size());
}

Vec2f EnvironmentLight::directionToUv(const Vec3f& dirWorld) const {
  const Vec3f d = worldToEnv * dirWorld;
  const float rot = radians(rotationDeg);
  float u = 0.5f + (std::atan2(d.z(), d.x()) - rot) / (2 * kPi);
  u -= std::floor(u);
  const float v = 0.5f - std::asin(clampv(d.y(), -1.0f, 1.0f)) / kPi;
  return Vec2f(u, v);
}

Vec3f EnvironmentLight::uvToDirection(const Vec2f& uv) const {
  const float phi = (uv.x() - 0.5f) * 2 * kPi + radians(rotationDeg);
  const float theta = (0.5f - uv.y()) * kPi;  // elevation
  const Vec3f d(std::cos(theta) * std::cos(phi), std::sin(theta), std::cos(theta) * std::sin(phi));
  return worldToEnv.transpose() * d;
}

Vec3f EnvironmentLight::unitRadianceFrom(const Vec3f& dir) const {
  if (image.empty()) return Vec3f::Ones();
  const Vec2f uv = directionToUv(dir);
  const int w = image.cols, h = image.rows;
  // pixel centers at (i + 0.5) / w; wrap in u, clamp in v
  const float x = uv.x() * w - 0.5f, y = uv.y() * h - 0.5f;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float fx = x - x0, fy = y - y0;
  auto texel = [&](int xi, int yi) {
    xi = wrapIndex(xi, w);
    yi = clampv(yi, 0, h - 1);
    const cv::Vec3f& p = image.at<cv::Vec3f>(yi, xi);
    return Vec3f(p[0], p[1], p[2]);
  };
  return (1 - fy) * ((1 - fx) * texel(x0, y0) + fx * texel(x0 + 1, y0)) +
         fy * ((1 - fx) * texel(x0, y0 + 1) + fx * texel(x0 + 1, y0 + 1));
}

Vec3f EnvironmentLight::radianceFrom(const Vec3f& dir) const {
  if (image.empty()) return radiance;
  return unitRadianceFrom(dir).cwiseProduct(radiance);
}

void EnvironmentLight::preprocess(const LightScene& scene) {
  PS_Check(scene.mesh, "EnvironmentLight::preprocess: no mesh");
  const Mesh& mesh = *scene.mesh;
  const size_t nt = mesh.numTriangles();
  std::vector<uint8_t> isWindow;
  for (int p : windowParts) {
    if (p < 0) continue;
    if (p >= static_cast<int>(isWindow.size())) isWindow.resize(p + 1, 0);
    isWindow[p] = 1;
  }
  windowTris_.clear();
  meshTriWindow_.assign(nt, -1);
  for (size_t t = 0; t < nt; ++t) {
    const int part = mesh.partIds[t];
    if (part < 0 || part >= static_cast<int>(isWindow.size()) || !isWindow[part]) continue;
    EmitterTriangle tri;
    if (!meshTriangle(mesh, static_cast<int>(t), &tri)) continue;
    meshTriWindow_[t] = static_cast<int>(windowTris_.size());
    windowTris_.push_back(tri);
  }
  const Eigen::AlignedBox3f box = mesh.bounds();
  sceneRadius_ = std::max(1e-3f, 0.5f * (box.max() - box.min()).norm());
  std::vector<float> ww;
  for (const auto& t : windowTris_) ww.push_back(t.area);
  windowDist_ = Distribution1D(ww);
  windowArea_ = windowDist_.total();
  std::vector<const EmitterTriangle*> wp;
  for (const auto& t : windowTris_) wp.push_back(&t);
  windowRect_ = rectangleOf(wp);
  const cv::Mat& img = image;
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
        float l = luminanceOf(Vec3f(c[0], c[1], c[2]));
        if (!std::isfinite(l) || l < 0) l = 0;
        lum[static_cast<size_t>(y) * W + x] = l;
      }
    auto at = [&](int x, int y) {  // wrap in u, clamp in v, as radianceFrom
      x = wrapIndex(x, W);
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
    envMeanLum_ = wsum > 0 ? static_cast<float>(lumSum / wsum) : 0.0f;
    envDist_ = Distribution2D(w, W, H);
  } else {
    envMeanLum_ = 1.0f;
  }
  // power through the windows: what the environment sends in through each window triangle, not
  // its mean over the whole sphere (a sun outside a window would otherwise get a small selection
  // probability and its next-event samples a large weight: fireflies)
  const Vec3f center = 0.5f * (box.min() + box.max());
  double power = 0;
  for (const auto& t : windowTris_) {
    const Vec3f c = t.p0 + (t.e1 + t.e2) / 3.0f;
    const Vec3f out = t.n.dot(c - center) >= 0 ? t.n : Vec3f(-t.n);  // away from the room's middle
    double e = 0;  // integral of luminance x cos+ over the sphere, / pi
    if (img.empty())
      e = 1.0;
    else {
      const int W = img.cols, H = img.rows;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          const Vec3f d = uvToDirection(Vec2f((x + 0.5f) / W, (y + 0.5f) / H));
          const float cs = d.dot(out);
          if (cs <= 0) continue;
          const cv::Vec3f v = img.at<cv::Vec3f>(y, x);
          const float l = luminanceOf(Vec3f(v[0], v[1], v[2]));
          if (!std::isfinite(l) || l <= 0) continue;
          const double dOmega = (2 * kPiD / W) * (kPiD / H) * std::sin(kPiD * (y + 0.5) / H);
          e += l * cs * dOmega / kPiD;
        }
    }
    power += t.area * e;
  }
  windowPower_ = static_cast<float>(power);
}

float EnvironmentLight::power(const Vec3f& scale) const {
  // estimated power entering the scene: through the windows, or over a sphere around the scene
  const float lum = envMeanLum_ * luminanceOf(scale);
  float w = windowTris_.empty() ? std::max(0.0f, lum * kPi * sceneRadius_ * sceneRadius_)
                                : std::max(0.0f, windowPower_ * luminanceOf(scale));
  if (!windowTris_.empty() && windowArea_ <= 0) w = 0;
  if (windowTris_.empty() && !image.empty() && envDist_.empty()) w = 0;
  return w;
}

float EnvironmentLight::imagePdf(const Vec3f& dir) const {
  if (image.empty()) return 1.0f / (4 * kPi);
  const Vec2f uv = directionToUv(dir);
  const float sinT = std::sin(kPi * clampv(uv.y(), 0.0f, 1.0f));
  if (sinT <= 1e-7f) return 0;
  return envDist_.pdf(uv) / (2 * kPi * kPi * sinT);
}

// Solid-angle pdf at x of the window strategy for a direction that crossed a window first at
// (esc.triangle, esc.distance): uniform in solid angle over a single rectangular window (seen
// from x), else uniform in area over all window triangles.
float EnvironmentLight::windowPdf(const Vec3f& x, const Vec3f& dir, const LightEscape& esc) const {
  if (windowRect_.valid) {
    const SphericalRectangle sr(windowRect_.corner, windowRect_.ex, windowRect_.ey, x);
    if (useSpherical(sr)) return 1.0f / sr.solidAngle();
  }
  const auto& w = windowTris_[meshTriWindow_[esc.triangle]];
  const float c = std::abs(w.n.dot(dir));
  return c < 1e-7f ? 0.0f : esc.distance * esc.distance / (windowArea_ * c);
}

// Light-sampling pdf (solid angle) at x for a direction that escaped, selection included.
float EnvironmentLight::pdf(const Vec3f& x, const Vec3f& dir, const LightEscape& esc,
                            float sel) const {
  if (sel <= 0) return 0;
  if (!windowTris_.empty()) {
    if (!esc.crossedOpening || windowArea_ <= 0) return 0;
    if (esc.triangle < 0 || esc.triangle >= static_cast<int>(meshTriWindow_.size()) ||
        meshTriWindow_[esc.triangle] < 0)
      return 0;  // left through another light's opening
    const float m = windowMix();
    return sel * (m * windowPdf(x, dir, esc) + (m < 1 ? (1 - m) * imagePdf(dir) : 0.0f));
  }
  return sel * imagePdf(dir);
}

Vec3f EnvironmentLight::L(const LightHit& hit) const {
  if (!std::isinf(hit.t)) return Vec3f::Zero();
  // with windows, seen only through them
  if (!windowTris_.empty() && (!hit.escape.crossedOpening || hit.escape.triangle < 0 ||
                               hit.escape.triangle >= static_cast<int>(meshTriWindow_.size()) ||
                               meshTriWindow_[hit.escape.triangle] < 0))
    return Vec3f::Zero();
  return unitRadianceFrom(hit.dir);
}

float EnvironmentLight::pdfLi(const LightSampleContext& ctx, const LightHit& hit) const {
  if (!std::isinf(hit.t)) return 0;
  return pdf(ctx.p, hit.dir, hit.escape, ctx.selectionPdf);
}

bool EnvironmentLight::sampleImage(const Vec2f& u, Vec3f* wi) const {
  float uvPdf = 0;
  const Vec2f uv = envDist_.sample(u.x(), u.y(), &uvPdf);
  if (uvPdf <= 0) return false;
  *wi = uvToDirection(uv);
  return true;
}

bool EnvironmentLight::sampleLi(const LightSampleContext& ctx, float uRe, const Vec2f& uPt,
                                LightLiSample* ls) const {
  const Vec3f& x = ctx.p;
  if (!windowTris_.empty()) {
    if (windowArea_ <= 0) return false;
    const float m = windowMix();
    if (uRe < m) {
      Vec3f y;
      bool done = false;
      if (windowRect_.valid) {
        const SphericalRectangle sr(windowRect_.corner, windowRect_.ex, windowRect_.ey, x);
        if (useSpherical(sr)) {
          y = sr.sample(uPt.x(), uPt.y());
          done = true;
        }
      }
      if (!done) {
        float triPdf = 0, ux = 0;
        const int k = windowDist_.sample(uPt.x(), &triPdf, &ux);
        y = pointOnTriangle(windowTris_[k], ux, uPt.y());
      }
      const Vec3f d = y - x;
      const float len = d.norm();
      if (!(len > 1e-6f)) return false;
      ls->wi = d / len;
    } else if (!sampleImage(uPt, &ls->wi)) {
      return false;
    }
    if (ls->wi.dot(ctx.n) <= 0) return false;
    LightEscape esc;
    if (!ctx.rays->escapesThroughOpenings(ctx.org, ls->wi, &esc) || !esc.crossedOpening)
      return false;
    ls->pdf = pdf(x, ls->wi, esc, ctx.selectionPdf);
  } else {
    if (image.empty()) {
      const float z = 1 - 2 * uPt.x(), r = std::sqrt(std::max(0.0f, 1 - z * z)),
                  phi = 2 * kPi * uPt.y();
      ls->wi = Vec3f(r * std::cos(phi), r * std::sin(phi), z);
    } else if (!sampleImage(uPt, &ls->wi)) {
      return false;
    }
    if (ls->wi.dot(ctx.n) <= 0) return false;
    ls->pdf = ctx.selectionPdf * imagePdf(ls->wi);
    if (!(ls->pdf > 0)) return false;
    if (!ctx.rays->unoccludedToInfinity(ctx.org, ls->wi)) return false;
  }
  ls->dist = std::numeric_limits<float>::infinity();
  ls->L = unitRadianceFrom(ls->wi);
  return ls->pdf > 0 && std::isfinite(ls->pdf);
}

}  // namespace ps
