// Object poses from the photos' labels: each rigid object of the CAD model (an OBJ `o` group) is
// moved, turned about the up axis and scaled so that the parts it shows in every labelled view
// cover the pixels the labels give them.
//
// A coarse CAD model places furniture a few centimetres and degrees off (blender-room: 2-6 cm,
// 1-3 deg, 2-4 %). The paper leaves the geometry as given and aligns masks in 2D (Eq. 1); a twin
// rendered from a new viewpoint still shows the object where the CAD put it, and on thin parts
// (chair frames) that is most of the twin's error. Here the pose is searched in 3D against every
// view at once, so a second photo pins what one cannot (depth along the first camera's rays).
//
//   std::vector<ps::PoseLabels> views = {{camera, partLabels}};  // CV_32SC1, -1: unlabelled
//   ps::PoseSearch search;
//   for (const ps::PoseFit& f : ps::fitObjectPoses(mesh, up, objects, views, search))
//     ...  // mesh has been moved; f.pose says how, f.mismatchBefore / After how well
#pragma once

#include <map>
#include <opencv2/core.hpp>
#include <vector>

#include "photoscene/scene/camera.hpp"
#include "photoscene/scene/mesh.hpp"
#include "photoscene/scene/scene.hpp"

namespace ps {

/// One view's evidence: the part each pixel shows.
struct PoseLabels {
  Camera camera;  ///< the size of `parts`
  cv::Mat parts;  ///< CV_32SC1 part id per pixel; -1 where nothing is labelled (not counted)
};

/// The search: a compass search over (shift along the two horizontal axes, yaw, log scale),
/// each step halved when no move along any axis lowers the mismatch, within the bounds.
struct PoseSearch {
  float maxShift = 0.15f;  ///< meters, per horizontal axis
  float maxYawDeg = 8.0f;
  float maxScaleChange = 0.10f;  ///< |scale - 1|
  float firstShift = 0.04f;      ///< first steps
  float firstYawDeg = 2.0f;
  float firstScaleChange = 0.03f;
  int halvings = 4;  ///< steps halved this many times before it stops
  /// an object with fewer labelled pixels of its own over all views keeps its pose
  int minPixels = 30;
};

/// The pose found for one object.
struct PoseFit {
  int object = -1;
  ObjectPose pose;         ///< identity when nothing lowered the mismatch
  int pixels = 0;          ///< labelled pixels of the object's parts, all views
  int mismatchBefore = 0;  ///< labelled pixels around the object whose part the render gets
  int mismatchAfter = 0;   ///< wrong, before and after (the same pixels)
  int evaluations = 0;     ///< renders of the object's neighbourhood tried
};

/// The objects whose pose is worth fitting: each has some volume (at least 1 cm along up and both
/// horizontal axes: a wall, floor, window or lamp panel is flat), spans less than 3/4 of the
/// scene's horizontal extent on both axes (not the room's shell), and holds none of `fixedParts`
/// (emitters, windows: their placement is given).
std::vector<int> movableObjects(const Mesh& mesh, const Vec3f& up,
                                const std::vector<int>& fixedParts);
/// The same for a loaded scene: its lights' emitting and opening parts are the fixed ones.
std::vector<int> movableObjects(const Scene& scene);

/// The part labels of a view from its label image and the pinned regions (value -> part id);
/// other values -1. At `size` (nearest neighbour) when given.
cv::Mat pinnedPartLabels(const cv::Mat& segments, const std::map<int, int>& segmentParts,
                         cv::Size size = {});

/// Fits the pose of each of `objects` (indices into mesh.objectNames), one after the other in
/// that order, each against the mesh as the earlier ones left it, and moves them in `mesh`
/// (applyObjectPose). The objective is the number of labelled pixels, in a window around the
/// object in each view, whose first hit (a ray through the pixel centre) lies on another part
/// than the label says: occlusion by the rest of the scene is part of it.
std::vector<PoseFit> fitObjectPoses(Mesh& mesh, const Vec3f& up, const std::vector<int>& objects,
                                    const std::vector<PoseLabels>& views,
                                    const PoseSearch& search = {});

}  // namespace ps
