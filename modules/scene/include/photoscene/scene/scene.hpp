// A loaded scene: mesh and parts, views (camera, photo, segments), lights. loadScene reads
// scene.json and everything it names and cross-checks them; any inconsistency throws
// ps::InputError naming the file, the key and what was expected.
//
//   ps::Scene scene = ps::loadScene("room/scene.json");
//   for (const ps::View& view : scene.views) { ... view.photo ... }
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "photoscene/scene/camera.hpp"
#include "photoscene/scene/lights.hpp"
#include "photoscene/scene/mesh.hpp"

namespace ps {

namespace fs = std::filesystem;

struct View {
  fs::path imagePath;
  Camera camera;
  cv::Mat photo;     ///< CV_32FC3 linear RGB, camera.width() x camera.height() (empty if not loaded)
  cv::Mat segments;  ///< CV_32SC1 labels, 0 = unlabeled (empty when the view has none)
  std::map<int, int> segmentParts;  ///< region value -> part id (pinned in scene.json)
};

struct Scene {
  io::SceneDesc desc;  ///< scene.json as read
  Mesh mesh;
  std::vector<Part> parts;
  Vec3f up = Vec3f(0, 1, 0);
  std::vector<View> views;
  LightSet lights;

  /// Part id by name, or -1.
  int partId(const std::string& name) const;
};

/// The largest photo a scene may have (width x height), checked from the image header before it
/// is decoded. A run holds each photo and its label image at full size and renders and scores
/// every view at the camera's size: its peak memory grows by about 445 MiB per photo megapixel
/// (measured, `photoscene run` of a one-view scene: 519 MiB at 0.79 MP, 1,565 MiB at 3.1 MP),
/// so 24 megapixels (6,000 x 4,000) peaks near 10.6 GiB. Larger photos are refused ("scale the
/// photo and the camera down").
constexpr int64_t kMaxPhotoPixels = 24'000'000;

struct LoadOptions {
  bool loadPhotos = true;        ///< read the photos and segments (sizes are checked either way)
  bool loadEnvironment = true;   ///< read the environment image
};

/// Reads scene.json, the OBJ, the photos and label images, the environment image; checks:
/// image and segments sizes against each camera; part names in segment_parts, parts, lights;
/// that some triangle can be seen from some view. Places automatic ceiling lights when no area
/// light is given.
Scene loadScene(const fs::path& sceneJson, const LoadOptions& options = {});

/// Builds the light set from a description (scene.json's lights or a lights.json file).
LightSet makeLights(const io::LightsDesc& desc, const Mesh& mesh, const std::vector<Part>& parts,
                    const Vec3f& up, const std::string& file, bool loadEnvironment);
/// Replaces emitters and environment by those of a lights.json (emitters by name or part).
LightSet makeLights(const io::LightsFileDesc& desc, const Mesh& mesh,
                    const std::vector<Part>& parts, const Vec3f& up, const std::string& file);

/// Number of triangles that may be visible in the camera (conservative frustum test).
int countTrianglesInFrustum(const Mesh& mesh, const Camera& camera);

}  // namespace ps
