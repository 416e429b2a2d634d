// The JSON files of the contract (../shared/spec/scene-format.md): scene.json, a camera object,
// lights.json and materials/<part>.json, read into plain structs with every key validated where
// it is read. Errors throw ps::InputError naming the file, the key path and what was expected.
//
// These structs are descriptions (what the file says, paths resolved against the file's folder);
// the scene module turns them into a loaded, cross-checked ps::Scene.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "photoscene/core/math.hpp"
#include "photoscene/io/json.hpp"

namespace ps::io {

namespace fs = std::filesystem;

/// A pinhole camera in OpenCV convention (x right, y down, z forward; pixel (0,0) is the center
/// of the top-left pixel). The look-at form is converted on read.
struct CameraDesc {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Mat4d worldToCamera = Mat4d::Identity();  ///< rigid, row-major in the file
};

struct ViewDesc {
  fs::path image;                          ///< resolved path of the photo
  std::string colorSpace = "srgb";         ///< "srgb" | "linear" (integer files; float is linear)
  CameraDesc camera;
  std::optional<fs::path> segments;        ///< resolved path of the label image
  std::map<int64_t, std::string> segmentParts;  ///< region value -> part name
};

/// An area emitter: an OBJ part (its faces emit along their normals) or a rectangle
/// center +- edgeU/2 +- edgeV/2 emitting along normalize(edgeU x edgeV).
struct AreaLightDesc {
  std::string name;                   ///< lights.json name; scene.json: "area_<i>" or the part
  std::optional<std::string> part;
  Vec3d center = Vec3d::Zero(), edgeU = Vec3d::Zero(), edgeV = Vec3d::Zero();
  std::optional<Vec3d> radiance;      ///< emitted radiance, linear RGB; absent: to be fitted
};

struct EnvironmentDesc {
  std::optional<fs::path> image;      ///< equirectangular, linear (resolved path)
  Vec3d radiance = Vec3d::Ones();     ///< multiplier on the image, or constant radiance
  double rotationDeg = 0;
  std::vector<std::string> windowParts;
};

/// An emitter of a registered light type (a "type" other than "area"): kept as written, made
/// into a ps::Light by the scene module (ps::LightRegistry), which checks it.
struct RegisteredLightDesc {
  std::string type;
  std::string key;      ///< where it is in its file ("lights.area[2]", "emitters[0]")
  nlohmann::json json;  ///< the entry as written (relative paths unresolved)
};

struct LightsDesc {
  std::vector<AreaLightDesc> area;
  std::vector<RegisteredLightDesc> registered;  ///< lights.area entries with another "type"
  double autoCeilingSpacing = 3.0;
  std::optional<EnvironmentDesc> environment;
};

/// A homogeneous material (`parts.<name>.fixed`, or `homogeneous` of a materials file).
struct HomogeneousDesc {
  Vec3d albedo = Vec3d::Constant(0.5);
  double roughness = 0.7;
  double metallic = 0.0;
  double specular = 0.5;  ///< F0_dielectric = 0.08 * specular
};

struct PartDesc {
  std::optional<std::string> graph;
  /// `category`: the part's material category (a library category: wood, tile, ...); selection
  /// picks a graph of it, and the fit keeps it (optional key, added to the format's contract)
  std::optional<std::string> category;
  std::optional<HomogeneousDesc> fixed;
  bool skip = false;
};

struct OptionsDesc {
  std::string preset = "balanced";  ///< fast | balanced | paper
  uint64_t seed = 0;
  /// `refine_poses`: move each piece of furniture (an OBJ object) onto the pinned labels of the
  /// views before anything else (align/pose.hpp); false keeps the geometry as given
  bool refinePoses = true;
};

struct SceneDesc {
  fs::path file;      ///< the scene.json read
  fs::path baseDir;   ///< its folder: relative paths resolve against it
  int version = 1;
  fs::path geometry;  ///< resolved OBJ path
  Vec3d up = Vec3d(0, 1, 0);  ///< unit
  std::vector<ViewDesc> views;
  LightsDesc lights;
  std::map<std::string, PartDesc> parts;
  OptionsDesc options;
  nlohmann::json rawJson;  ///< the file as read (kept so outputs can extend it)
};

/// Reads and validates scene.json (syntax, types, required keys, ranges, rigid cameras).
/// Cross-checks that need other files (image sizes, part names) are the scene module's.
SceneDesc readSceneJson(const fs::path& path);

/// The world_to_camera (OpenCV axes: x right, y down, z forward) of a camera at `eye` looking at
/// `target`, with `up` pointing roughly up in the image. Throws ps::Exception when target equals
/// eye or the view direction is parallel to up.
Mat4d lookAtWorldToCamera(const Vec3d& eye, const Vec3d& target, const Vec3d& up = Vec3d(0, 1, 0));
/// The camera of the look-at form: fx = fy = (height / 2) / tan(fovYDeg / 2), principal point at
/// the image center ((width - 1) / 2, (height - 1) / 2).
CameraDesc lookAtCamera(int width, int height, double fovYDeg, const Vec3d& eye, const Vec3d& target,
                        const Vec3d& up = Vec3d(0, 1, 0));

/// Parses one camera object (either form). `where` is the key path used in messages.
CameraDesc parseCamera(const JsonValue& camera);
/// Reads a CAMERA.json file holding one camera object.
CameraDesc readCameraJson(const fs::path& path);
nlohmann::json cameraToJson(const CameraDesc& camera);

/// lights.json: emitters with radiance, optional environment, per-view exposure.
struct LightsFileDesc {
  std::vector<AreaLightDesc> emitters;
  std::vector<RegisteredLightDesc>
      registered;  ///< emitters with a "type" other than "area" (written after `emitters`)
  std::optional<EnvironmentDesc> environment;
  std::vector<double> exposure;
};
LightsFileDesc readLightsJson(const fs::path& path);
/// Parses one area emitter (scene.json's lights.area[i], lights.json's emitters[i]);
/// `radianceRequired` for lights.json. "type", when present, must be "area".
AreaLightDesc parseAreaLight(const JsonValue& entry, bool radianceRequired);
/// Parses an environment object; a relative image path resolves against `baseDir`.
EnvironmentDesc parseEnvironment(const JsonValue& env, const fs::path& baseDir);
/// The "type" of an emitter entry: "area" when absent; throws when not a non-empty string.
std::string emitterType(const JsonValue& entry);
void writeLightsJson(const fs::path& path, const LightsFileDesc& lights);

/// materials/<part>.json
struct UvTransformDesc {
  double rotationDeg = 0;
  Vec2d scale = Vec2d::Ones();  ///< (su, sv); a scalar `scale` gives su = sv
  Vec2d offset = Vec2d::Zero();
};
struct MaterialFileDesc {
  std::string part, graph, category;
  nlohmann::json params = nlohmann::json::object();
  UvTransformDesc uv;
  Vec3d albedoOffset = Vec3d::Zero();
  double albedoScale = 1.0, roughnessScale = 1.0;
  HomogeneousDesc homogeneous;
  std::map<std::string, fs::path> maps;  ///< "albedo" | "normal" | "roughness" | "metallic" -> resolved
  std::optional<int> fitView;
  std::optional<double> fitLoss, fitSeconds;
  std::optional<std::string> skipped;
  /// Further keys written into "fit" (optional extensions such as "history", the loss per
  /// iteration); not read back.
  nlohmann::json fitExtra = nlohmann::json::object();
};
MaterialFileDesc readMaterialJson(const fs::path& path);
/// Writes a materials file; map paths are written relative to `outDir`.
void writeMaterialJson(const fs::path& path, const MaterialFileDesc& material, const fs::path& outDir);

}  // namespace ps::io
