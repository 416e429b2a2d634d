#include "photoscene/scene/scene.hpp"

#include "photoscene/core/log.hpp"

#include <set>
#include <sstream>

#include "photoscene/core/error.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/io/image_io.hpp"
#include "photoscene/io/obj_io.hpp"
#include "light_geometry.hpp"

namespace ps {

int Scene::partId(const std::string& name) const {
  for (const Part& p : parts)
    if (p.name == name) return p.id;
  return -1;
}

namespace {}  // namespace

namespace {

// Lights of registered types (any "type" but "area"), through ps::LightRegistry.
void addRegistered(LightSet* set, const std::vector<io::RegisteredLightDesc>& descs,
                   const std::vector<Part>& parts, const Vec3f& up, const std::string& file,
                   bool loadImages) {
  LightJsonContext ctx;
  ctx.parts = &parts;
  ctx.baseDir = fs::path(file).parent_path();
  if (ctx.baseDir.empty()) ctx.baseDir = ".";
  ctx.file = file;
  ctx.up = up;
  ctx.loadImages = loadImages;
  for (const io::RegisteredLightDesc& d : descs)
    set->add(LightRegistry::create(io::JsonValue(d.json, file, d.key), ctx));
}

}  // namespace

LightSet makeLights(const io::LightsDesc& desc, const Mesh& mesh, const std::vector<Part>& parts,
                    const Vec3f& up, const std::string& file, bool loadEnvironment) {
  LightSet set;
  for (size_t i = 0; i < desc.area.size(); ++i)
    set.area.push_back(
        AreaLight::fromDesc(desc.area[i], parts, file, "lights.area[" + std::to_string(i) + "]"));
  addRegistered(&set, desc.registered, parts, up, file, loadEnvironment);
  if (set.area.empty() && set.registered.empty()) {
    set.area = autoCeilingLights(mesh, up, static_cast<float>(desc.autoCeilingSpacing));
    spdlog::info("no area lights given: placed {} ceiling lights on a {:.2f} m grid", set.area.size(),
                 desc.autoCeilingSpacing);
  }
  if (desc.environment)
    set.environment = EnvironmentLight::fromDesc(*desc.environment, parts, up, file,
                                                 "lights.environment", loadEnvironment);
  return set;
}

LightSet makeLights(const io::LightsFileDesc& desc, const Mesh& mesh, const std::vector<Part>& parts,
                    const Vec3f& up, const std::string& file) {
  (void)mesh;
  LightSet set;
  for (size_t i = 0; i < desc.emitters.size(); ++i)
    set.area.push_back(
        AreaLight::fromDesc(desc.emitters[i], parts, file, "emitters[" + std::to_string(i) + "]"));
  addRegistered(&set, desc.registered, parts, up, file, true);
  if (desc.environment)
    set.environment =
        EnvironmentLight::fromDesc(*desc.environment, parts, up, file, "environment", true);
  return set;
}

int countTrianglesInFrustum(const Mesh& mesh, const Camera& camera) {
  // Camera-space planes: z > near, and the four image-border planes through the center.
  const double l = (-0.5 - camera.cx()) / camera.fx(), r = (camera.width() - 0.5 - camera.cx()) / camera.fx();
  const double t = (-0.5 - camera.cy()) / camera.fy(), b = (camera.height() - 0.5 - camera.cy()) / camera.fy();
  std::vector<Vec3d> cam(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) cam[i] = camera.toCamera(mesh.positions[i].cast<double>());
  int count = 0;
  for (const auto& f : mesh.triangles) {
    bool culled = false;
    auto allOutside = [&](auto&& outside) {
      return outside(cam[f[0]]) && outside(cam[f[1]]) && outside(cam[f[2]]);
    };
    culled |= allOutside([](const Vec3d& p) { return p.z() <= 1e-6; });
    culled |= allOutside([&](const Vec3d& p) { return p.x() < l * p.z(); });
    culled |= allOutside([&](const Vec3d& p) { return p.x() > r * p.z(); });
    culled |= allOutside([&](const Vec3d& p) { return p.y() < t * p.z(); });
    culled |= allOutside([&](const Vec3d& p) { return p.y() > b * p.z(); });
    if (!culled) ++count;
  }
  return count;
}

Scene loadScene(const fs::path& sceneJson, const LoadOptions& options) {
  Timer timer;
  Scene scene;
  scene.desc = io::readSceneJson(sceneJson);
  const std::string file = sceneJson.string();
  const io::SceneDesc& desc = scene.desc;
  scene.up = desc.up.cast<float>();

  const io::ObjMesh obj = io::readObj(desc.geometry);
  scene.mesh = meshFromObj(obj, &scene.parts, scene.up);

  // Part names used anywhere must exist in the OBJ.
  for (const auto& [name, part] : desc.parts)
    requirePartId(scene.parts, name, file, "parts." + name);

  for (size_t i = 0; i < desc.views.size(); ++i) {
    const io::ViewDesc& vd = desc.views[i];
    const std::string key = "views[" + std::to_string(i) + "]";
    View view;
    view.imagePath = vd.image;
    view.camera = Camera::fromDesc(vd.camera);
    const io::ImageInfo info = io::readImageInfo(vd.image);
    const int64_t pixels = static_cast<int64_t>(info.width) * info.height;
    if (pixels > kMaxPhotoPixels)
      throw InputError(
          file, key + ".image",
          "expected a photo of at most " + std::to_string(kMaxPhotoPixels / 1'000'000) +
              " megapixels (the supported size; scale the photo and the camera down), but " +
              vd.image.string() + " is " + std::to_string(info.width) + "x" +
              std::to_string(info.height) + " (" + std::to_string(pixels / 1'000'000) +
              " megapixels)");
    if (info.width != vd.camera.width || info.height != vd.camera.height)
      throw InputError(file, key + ".image",
                       "expected a " + std::to_string(vd.camera.width) + "x" + std::to_string(vd.camera.height) +
                           " image (the camera's width x height), but " + vd.image.string() + " is " +
                           std::to_string(info.width) + "x" + std::to_string(info.height));
    if (vd.segments) {
      const io::ImageInfo sinfo = io::readImageInfo(*vd.segments);
      if (sinfo.width != info.width || sinfo.height != info.height)
        throw InputError(file, key + ".segments",
                         "expected a label image of the photo's size " + std::to_string(info.width) + "x" +
                             std::to_string(info.height) + ", but " + vd.segments->string() + " is " +
                             std::to_string(sinfo.width) + "x" + std::to_string(sinfo.height));
    }
    for (const auto& [value, name] : vd.segmentParts)
      view.segmentParts[static_cast<int>(value)] =
          requirePartId(scene.parts, name, file, key + ".segment_parts." + std::to_string(value));
    if (options.loadPhotos) {
      view.photo = io::readImage(vd.image, io::parseColorSpace(vd.colorSpace));
      if (vd.segments) {
        view.segments = io::readLabelImage(*vd.segments);
        // which values occur, in one pass (a 16-bit label image may name up to 65,535 regions)
        std::vector<uint8_t> present(65536, 0);
        for (int y = 0; y < view.segments.rows; ++y) {
          const int* row = view.segments.ptr<int>(y);
          for (int x = 0; x < view.segments.cols; ++x) present[static_cast<uint16_t>(row[x])] = 1;
        }
        for (const auto& [value, part] : view.segmentParts) {
          if (value < 0 || value > 65535 || !present[value])
            spdlog::warn("{}: {}.segment_parts.{}: region value {} does not occur in {}", file, key, value,
                         value, vd.segments->string());
        }
      }
    }
    scene.views.push_back(std::move(view));
  }

  int visible = 0;
  for (const View& v : scene.views) visible += countTrianglesInFrustum(scene.mesh, v.camera);
  if (visible == 0)
    throw InputError(desc.geometry.string(), "",
                     "no triangle is visible from any view: expected geometry in front of the cameras "
                     "(check world_to_camera, and the OBJ's units (meters) and axes)");

  scene.lights = makeLights(desc.lights, scene.mesh, scene.parts, scene.up, file, options.loadEnvironment);

  int degenerate = 0;
  for (size_t t = 0; t < scene.mesh.numTriangles(); ++t)
    if (scene.mesh.area(static_cast<int>(t)) < 1e-12f) ++degenerate;
  spdlog::info(
      "scene {}: {} triangles ({} degenerate), {} parts, {} views, {} area lights{}{} ({:.2f}s)",
      sceneJson.filename().string(), scene.mesh.numTriangles(), degenerate, scene.parts.size(),
      scene.views.size(), scene.lights.area.size(),
      scene.lights.registered.empty()
          ? ""
          : fmt::format(" + {} registered", scene.lights.registered.size()),
      scene.lights.environment ? " + environment" : "", timer.seconds());
  return scene;
}

}  // namespace ps
