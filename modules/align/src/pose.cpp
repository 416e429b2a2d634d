#include "photoscene/align/pose.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <set>

#include "photoscene/core/error.hpp"
#include "photoscene/raytrace/accel.hpp"

namespace ps {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The triangles of `mesh` that `keep` picks, with their parts: what a RayAccel needs.
template <typename Keep>
Mesh subMesh(const Mesh& mesh, Keep keep) {
  Mesh m;
  m.positions = mesh.positions;
  for (size_t t = 0; t < mesh.numTriangles(); ++t)
    if (keep(static_cast<int>(t))) {
      m.triangles.push_back(mesh.triangles[t]);
      m.partIds.push_back(mesh.partIds[t]);
    }
  return m;
}

// A labelled pixel near the object: its ray and what the rest of the scene shows there.
struct Sample {
  Vec3f dir;       // unit, world
  float staticT;   // distance to the first hit off the object (infinity: none)
  int staticPart;  // its part (-1: none)
  int label;       // the part the photo's labels give the pixel
  int view;
};

// The pixel window of `view` that the object can reach within the search bounds: its bounds
// grown by the largest move, projected. Empty when the object cannot be seen there.
cv::Rect reachableWindow(const Camera& camera, const Eigen::AlignedBox3f& bounds, float margin) {
  const cv::Rect image(0, 0, camera.width(), camera.height());
  Eigen::AlignedBox3f grown(bounds.min() - Vec3f::Constant(margin),
                            bounds.max() + Vec3f::Constant(margin));
  double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
  for (int c = 0; c < 8; ++c) {
    const Vec3f corner = grown.corner(static_cast<Eigen::AlignedBox3f::CornerType>(c));
    Vec2d px;
    double depth = 0;
    if (!camera.project(corner.cast<double>(), &px, &depth) || depth <= 0) return image;
    x0 = std::min(x0, px.x());
    y0 = std::min(y0, px.y());
    x1 = std::max(x1, px.x());
    y1 = std::max(y1, px.y());
  }
  const cv::Rect r(
      cv::Point(static_cast<int>(std::floor(x0)) - 1, static_cast<int>(std::floor(y0)) - 1),
      cv::Point(static_cast<int>(std::ceil(x1)) + 2, static_cast<int>(std::ceil(y1)) + 2));
  return r & image;
}

// The search's state for one object: its own triangles (as they were), the samples around it.
class ObjectSearch {
 public:
  ObjectSearch(const Mesh& mesh, const Vec3f& up, int object, const std::vector<PoseLabels>& views,
               const PoseSearch& search)
      : up_(up), views_(views) {
    horizontalAxes(up, &e1_, &e2_);
    pivot_ = objectPivot(mesh, object, up);
    std::set<int> parts;
    Eigen::AlignedBox3f bounds;
    float radius = 0;
    for (size_t t = 0; t < mesh.numTriangles(); ++t)
      if (mesh.objectIds[t] == object) {
        parts.insert(mesh.partIds[t]);
        for (int k = 0; k < 3; ++k) {
          const Vec3f& p = mesh.positions[mesh.triangles[t][k]];
          bounds.extend(p);
          radius = std::max(radius, (p - pivot_).norm());
        }
      }
    if (bounds.isEmpty()) return;
    const float margin = std::sqrt(2.0f) * search.maxShift +
                         radius * (search.maxScaleChange + search.maxYawDeg * float(M_PI) / 180);
    // own_: the object's triangles where they are now; rest_: everything else
    own_ = subMesh(mesh, [&](int t) { return mesh.objectIds[t] == object; });
    const Mesh rest = subMesh(mesh, [&](int t) { return mesh.objectIds[t] != object; });
    ownAccel_ = std::make_unique<RayAccel>(own_);
    const RayAccel restAccel(rest);
    for (size_t v = 0; v < views.size(); ++v) {
      const Camera& cam = views[v].camera;
      const cv::Rect win = reachableWindow(cam, bounds, margin);
      const Vec3f org = cam.position().cast<float>();
      for (int y = win.y; y < win.y + win.height; ++y) {
        const int* lab = views[v].parts.ptr<int>(y);
        for (int x = win.x; x < win.x + win.width; ++x) {
          if (lab[x] < 0) continue;
          Sample s;
          s.dir = cam.rayDirection(x, y).cast<float>();
          const RayHit h = restAccel.intersect(org, s.dir);
          s.staticT = h.valid() ? h.t : kInf;
          s.staticPart = h.valid() ? rest.partIds[h.prim] : -1;
          s.label = lab[x];
          s.view = static_cast<int>(v);
          samples_.push_back(s);
          own += parts.count(lab[x]) > 0;
        }
      }
    }
  }

  /// Pose of the search coordinates x = (shift e1, shift e2, yaw, log scale).
  ObjectPose pose(const std::array<float, 4>& x) const {
    ObjectPose p;
    p.pivot = pivot_;
    p.shift = e1_ * x[0] + e2_ * x[1];
    p.yaw = x[2];
    p.scale = std::exp(x[3]);
    return p;
  }

  /// Labelled samples whose first hit, with the object at `pose`, is on another part.
  int mismatch(const ObjectPose& pose) const {
    const Mat3f rt = pose.rotation(up_).transpose();
    std::vector<Vec3f> origin(views_.size());
    for (size_t v = 0; v < views_.size(); ++v) {  // the camera centre in the object's own frame
      const Vec3f o = views_[v].camera.position().cast<float>();
      origin[v] = pivot_ + rt * (o - pivot_ - pose.shift) / pose.scale;
    }
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, samples_.size(), 256), 0,
        [&](const tbb::blocked_range<size_t>& r, int n) {
          for (size_t i = r.begin(); i != r.end(); ++i) {
            const Sample& s = samples_[i];
            const RayHit h = ownAccel_->intersect(origin[s.view], rt * s.dir);
            const int part =
                h.valid() && h.t * pose.scale < s.staticT ? own_.partIds[h.prim] : s.staticPart;
            n += part != s.label;
          }
          return n;
        },
        std::plus<int>());
  }

  int own = 0;  ///< labelled pixels of the object's parts

 private:
  Vec3f up_, e1_, e2_, pivot_;
  const std::vector<PoseLabels>& views_;
  Mesh own_;
  std::unique_ptr<RayAccel> ownAccel_;
  std::vector<Sample> samples_;
};

}  // namespace

std::vector<int> movableObjects(const Mesh& mesh, const Vec3f& up,
                                const std::vector<int>& fixedParts) {
  Vec3f e1, e2;
  horizontalAxes(up, &e1, &e2);
  const int n = static_cast<int>(mesh.objectNames.size());
  std::vector<Eigen::AlignedBox3f> box(n);  // in (e1, e2, up) coordinates
  std::vector<uint8_t> fixed(n, 0);
  Eigen::AlignedBox3f scene;
  for (size_t t = 0; t < mesh.numTriangles(); ++t) {
    const int o = mesh.objectIds[t];
    for (int k = 0; k < 3; ++k) {
      const Vec3f& p = mesh.positions[mesh.triangles[t][k]];
      const Vec3f q(p.dot(e1), p.dot(e2), p.dot(up));
      scene.extend(q);
      if (o >= 0) box[o].extend(q);
    }
    if (o >= 0 &&
        std::find(fixedParts.begin(), fixedParts.end(), mesh.partIds[t]) != fixedParts.end())
      fixed[o] = 1;
  }
  std::vector<int> out;
  for (int o = 0; o < n; ++o) {
    if (fixed[o] || box[o].isEmpty()) continue;
    const Vec3f size = box[o].sizes(), room = scene.sizes();
    if (size.minCoeff() < 0.01f) continue;
    if (size.x() >= 0.75f * room.x() || size.y() >= 0.75f * room.y()) continue;
    out.push_back(o);
  }
  return out;
}

std::vector<int> movableObjects(const Scene& scene) {
  std::vector<int> fixed = scene.lights.emittingParts();
  for (int p : scene.lights.openingParts()) fixed.push_back(p);
  return movableObjects(scene.mesh, scene.up, fixed);
}

cv::Mat pinnedPartLabels(const cv::Mat& segments, const std::map<int, int>& segmentParts,
                         cv::Size size) {
  cv::Mat labels(segments.size(), CV_32SC1, cv::Scalar(-1));
  for (int y = 0; y < segments.rows; ++y) {
    const int* s = segments.ptr<int>(y);
    int* l = labels.ptr<int>(y);
    for (int x = 0; x < segments.cols; ++x)
      if (const auto it = segmentParts.find(s[x]); it != segmentParts.end()) l[x] = it->second;
  }
  if (!size.empty() && size != labels.size()) {
    cv::Mat small;
    cv::resize(labels, small, size, 0, 0, cv::INTER_NEAREST);
    return small;
  }
  return labels;
}

std::vector<PoseFit> fitObjectPoses(Mesh& mesh, const Vec3f& up, const std::vector<int>& objects,
                                    const std::vector<PoseLabels>& views,
                                    const PoseSearch& search) {
  for (const PoseLabels& v : views)
    if (v.parts.type() != CV_32SC1 || v.parts.cols != v.camera.width() ||
        v.parts.rows != v.camera.height())
      throw Exception("fitObjectPoses: labels must be CV_32SC1 at the camera's size", __FILE__,
                      __LINE__, __func__);
  const float deg = float(M_PI) / 180;
  const std::array<float, 4> bound = {search.maxShift, search.maxShift, search.maxYawDeg * deg,
                                      std::log1p(search.maxScaleChange)};
  std::vector<PoseFit> fits;
  for (int object : objects) {
    PoseFit f;
    f.object = object;
    const ObjectSearch s(mesh, up, object, views, search);
    f.pixels = s.own;
    if (s.own < search.minPixels) {
      fits.push_back(f);
      continue;
    }
    std::array<float, 4> x = {0, 0, 0, 0};
    std::array<float, 4> step = {search.firstShift, search.firstShift, search.firstYawDeg * deg,
                                 std::log1p(search.firstScaleChange)};
    int best = s.mismatch(s.pose(x));
    f.mismatchBefore = best;
    f.evaluations = 1;
    for (int h = 0; h <= search.halvings; ++h) {
      for (bool moved = true; moved;) {
        moved = false;
        for (int i = 0; i < 4; ++i)
          for (float sign : {1.0f, -1.0f}) {
            std::array<float, 4> y = x;
            y[i] += sign * step[i];
            if (std::abs(y[i]) > bound[i] * (1 + 1e-4f)) continue;
            const int m = s.mismatch(s.pose(y));
            ++f.evaluations;
            if (m < best) {
              best = m;
              x = y;
              moved = true;
              break;
            }
          }
      }
      for (float& st : step) st *= 0.5f;
    }
    f.mismatchAfter = best;
    if (best < f.mismatchBefore) {
      f.pose = s.pose(x);
      applyObjectPose(mesh, object, f.pose, up);
    }
    fits.push_back(f);
  }
  return fits;
}

}  // namespace ps
