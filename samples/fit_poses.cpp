// Sample: object poses from the photos' labels (align/pose.hpp; the pipeline's `poses` stage).
//
//   ps_sample_poses [SCENE.json] [OUT.obj] [WIDTH]
//
// Every labelled view (its pinned segment_parts) is the evidence; each movable object of the OBJ
// (furniture: not the room's shell, not a lamp or window) is shifted, turned about up and scaled
// so that the parts it shows fall on the pixels labelled with them. Prints each object's fit and
// writes the moved OBJ.
#include <cstdio>

#include "photoscene/align.hpp"
#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/scene.hpp"

int main(int argc, char** argv) {
  ps::initLogging(ps::LogLevel::Warn);
  const std::string scenePath = argc > 1 ? argv[1] : PS_SAMPLE_SCENE;
  const std::filesystem::path out = argc > 2 ? argv[2] : "sample-poses.obj";
  const int width = argc > 3 ? std::atoi(argv[3]) : 320;  // the pipeline's working width
  try {
    ps::Scene scene = ps::loadScene(scenePath);
    std::vector<ps::PoseLabels> views;
    for (const ps::View& v : scene.views) {
      if (v.segments.empty()) continue;  // the labels the user gave are the evidence
      const int w = std::min(width, v.camera.width());
      const int h = static_cast<int>(std::lround(double(v.camera.height()) * w / v.camera.width()));
      const ps::Camera cam = v.camera.resized(w, h);
      views.push_back({cam, ps::pinnedPartLabels(v.segments, v.segmentParts, {w, h})});
    }
    const std::vector<int> objects = ps::movableObjects(scene);  // not the lamps or windows
    ps::Timer timer;
    const std::vector<ps::PoseFit> fits = ps::fitObjectPoses(scene.mesh, scene.up, objects, views);
    std::printf("%-12s %7s %9s %9s %6s %9s %8s %7s\n", "object", "pixels", "mismatch", "after",
                "evals", "shift cm", "yaw deg", "scale");
    ps::io::ObjMesh obj = ps::io::readObj(scene.desc.geometry);
    for (const ps::PoseFit& f : fits) {
      std::printf("%-12s %7d %9d %9d %6d %9.2f %8.2f %7.3f\n",
                  scene.mesh.objectNames[f.object].c_str(), f.pixels, f.mismatchBefore,
                  f.mismatchAfter, f.evaluations, 100 * f.pose.shift.norm(),
                  f.pose.yaw * 180 / M_PI, f.pose.scale);
      ps::applyObjectPose(obj, f.object, f.pose, scene.up);
    }
    ps::io::writeObj(out, obj);
    std::printf("%zu objects in %.2f s over %zu views; wrote %s\n", fits.size(), timer.seconds(),
                views.size(), out.string().c_str());
    return 0;
  } catch (const ps::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
