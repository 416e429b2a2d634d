#include "photoscene/raytrace/gbuffer.hpp"

#include "photoscene/core/error.hpp"
#include "photoscene/core/parallel.hpp"

namespace ps {

namespace {

RayHit firstHit(const PathTracer& tracer, const Vec3f& org, const Vec3f& dir, bool passWindows) {
  float tnear = 0;
  for (int k = 0; k < 16; ++k) {
    RayHit h = tracer.accel().intersect(org, dir, tnear);
    if (!h.valid() || h.geom != 0) return h.valid() ? RayHit() : h;  // rectangle emitters: not mesh parts
    if (passWindows && tracer.isWindowPart(tracer.scene().mesh.partIds[h.prim])) {
      tnear = h.t * (1.0f + 1e-5f) + 1e-6f;
      continue;
    }
    return h;
  }
  return RayHit();
}

// uv of the point where the ray (org, dir) meets the plane of triangle `tri`, by extrapolated
// barycentrics. Returns false when the ray is parallel to the plane.
bool uvOnPlane(const Mesh& mesh, int tri, const Vec3f& org, const Vec3f& dir, Vec2f* uv) {
  const auto& f = mesh.triangles[tri];
  const Vec3f p0 = mesh.positions[f[0]], p1 = mesh.positions[f[1]], p2 = mesh.positions[f[2]];
  const Vec3f n = (p1 - p0).cross(p2 - p0);
  const float nn = n.squaredNorm();
  const float dn = dir.dot(n);
  if (!(nn > 0) || std::abs(dn) < 1e-12f * std::sqrt(nn)) return false;
  const float t = (p0 - org).dot(n) / dn;
  const Vec3f p = org + t * dir;
  const float b1 = (p - p0).cross(p2 - p0).dot(n) / nn;
  const float b2 = (p1 - p0).cross(p - p0).dot(n) / nn;
  const float b0 = 1 - b1 - b2;
  *uv = b0 * mesh.cornerUvs[3 * tri] + b1 * mesh.cornerUvs[3 * tri + 1] + b2 * mesh.cornerUvs[3 * tri + 2];
  return uv->allFinite();
}

inline cv::Vec3f cv3(const Vec3f& v) { return cv::Vec3f(v.x(), v.y(), v.z()); }

}  // namespace

GBuffer renderGBuffer(const PathTracer& tracer, const Camera& camera, const GBufferOptions& options) {
  PS_Check(camera.width() > 0 && camera.height() > 0, "camera without size");
  PS_Check(options.coverageSamples >= 1 && options.coverageSamples <= 16, "coverageSamples in [1, 16]");
  const int W = camera.width(), H = camera.height();
  const Mesh& mesh = tracer.scene().mesh;
  const int nParts = static_cast<int>(tracer.scene().parts.size());
  GBuffer g;
  g.partId = cv::Mat(H, W, CV_32SC1, cv::Scalar(-1));
  g.triangleId = cv::Mat(H, W, CV_32SC1, cv::Scalar(-1));
  g.uv = cv::Mat(H, W, CV_32FC2, cv::Scalar::all(0));
  g.duvdx = cv::Mat(H, W, CV_32FC2, cv::Scalar::all(0));
  g.duvdy = cv::Mat(H, W, CV_32FC2, cv::Scalar::all(0));
  for (cv::Mat* m : {&g.position, &g.normalGeo, &g.normalShading, &g.tangent, &g.bitangent, &g.dpdu, &g.dpdv})
    *m = cv::Mat(H, W, CV_32FC3, cv::Scalar::all(0));
  g.depth = cv::Mat(H, W, CV_32FC1, cv::Scalar(0));
  const int n = options.coverageSamples;
  std::vector<uint8_t> partSeen(nParts, 0);
  std::vector<int> subPart(static_cast<size_t>(W) * H * n * n, -1);
  const Vec3f eye = camera.position().cast<float>();
  const Vec3f camZ = camera.cameraToWorld().block<3, 1>(0, 2).cast<float>();

  parallelForRanges(0, H, 4, [&](int64_t y0, int64_t y1) {
    for (int y = static_cast<int>(y0); y < y1; ++y) {
      for (int x = 0; x < W; ++x) {
        const Vec3f d = camera.rayDirection(x, y).cast<float>();
        const RayHit h = firstHit(tracer, eye, d, options.passWindows);
        if (h.valid()) {
          const SurfacePoint sp = tracer.surfacePoint(h);
          g.partId.at<int>(y, x) = sp.part;
          g.triangleId.at<int>(y, x) = sp.triangle;
          g.uv.at<cv::Vec2f>(y, x) = cv::Vec2f(sp.uv.x(), sp.uv.y());
          g.position.at<cv::Vec3f>(y, x) = cv3(sp.p);
          const bool back = sp.ng.dot(d) > 0;
          const Vec3f ng = back ? Vec3f(-sp.ng) : sp.ng, ns = back ? Vec3f(-sp.ns) : sp.ns;
          g.normalGeo.at<cv::Vec3f>(y, x) = cv3(ng);
          g.normalShading.at<cv::Vec3f>(y, x) = cv3(ns);
          g.dpdu.at<cv::Vec3f>(y, x) = cv3(sp.dpdu);
          g.dpdv.at<cv::Vec3f>(y, x) = cv3(sp.dpdv);
          Vec3f T, B;
          if (tangentFrame(sp.dpdu, sp.dpdv, ns, UvTransform(), &T, &B)) {
            g.tangent.at<cv::Vec3f>(y, x) = cv3(T);
            g.bitangent.at<cv::Vec3f>(y, x) = cv3(B);
          }
          g.depth.at<float>(y, x) = (sp.p - eye).dot(camZ);
          Vec2f uvx, uvy;
          if (uvOnPlane(mesh, sp.triangle, eye, camera.rayDirection(x + 1, y).cast<float>(), &uvx) &&
              uvOnPlane(mesh, sp.triangle, eye, camera.rayDirection(x, y + 1).cast<float>(), &uvy)) {
            const Vec2f ddx = uvx - sp.uv, ddy = uvy - sp.uv;
            g.duvdx.at<cv::Vec2f>(y, x) = cv::Vec2f(ddx.x(), ddx.y());
            g.duvdy.at<cv::Vec2f>(y, x) = cv::Vec2f(ddy.x(), ddy.y());
          }
        }
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) {
            int part = -1;
            if (n == 1) {
              part = g.partId.at<int>(y, x);
            } else {
              const double sx = x - 0.5 + (i + 0.5) / n, sy = y - 0.5 + (j + 0.5) / n;
              const RayHit hs = firstHit(tracer, eye, camera.rayDirection(sx, sy).cast<float>(), options.passWindows);
              if (hs.valid()) part = mesh.partIds[hs.prim];
            }
            subPart[((static_cast<size_t>(y) * W + x) * n + j) * n + i] = part;
          }
      }
    }
  });
  for (int p : subPart)
    if (p >= 0 && p < nParts) partSeen[p] = 1;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int p = g.partId.at<int>(y, x);
      if (p >= 0 && p < nParts) partSeen[p] = 1;
    }
  g.coverage.assign(nParts, cv::Mat());
  g.mask.assign(nParts, cv::Mat());
  for (int p = 0; p < nParts; ++p) {
    if (!partSeen[p]) continue;
    g.coverage[p] = cv::Mat(H, W, CV_32FC1, cv::Scalar(0));
    g.mask[p] = cv::Mat(H, W, CV_8UC1, cv::Scalar(0));
  }
  const float inv = 1.0f / (n * n);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int* s = &subPart[(static_cast<size_t>(y) * W + x) * n * n];
      for (int k = 0; k < n * n; ++k)
        if (s[k] >= 0 && s[k] < nParts) g.coverage[s[k]].at<float>(y, x) += inv;
      const int p = g.partId.at<int>(y, x);
      if (p >= 0 && p < nParts) g.mask[p].at<uint8_t>(y, x) = 255;
    }
  return g;
}

}  // namespace ps
