#include "photoscene/io/scene_json.hpp"

#include "photoscene/core/log.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include "photoscene/core/error.hpp"

namespace ps::io {

namespace {

void warnUnknownKeys(const JsonValue& obj, const std::set<std::string>& known) {
  for (const auto& k : obj.keys()) {
    if (!known.count(k))
      spdlog::warn("{}: {}: unknown key ignored", obj.file(), obj.path().empty() ? k : obj.path() + "." + k);
  }
}

fs::path resolvePath(const fs::path& baseDir, const std::string& p) {
  fs::path path(p);
  return path.is_absolute() ? path : (baseDir / path).lexically_normal();
}

std::string requireNonEmptyString(const JsonValue& v) {
  const std::string s = v.string();
  if (s.empty()) v.fail("a non-empty string");
  return s;
}

Vec3d nonNegativeRgb(const JsonValue& v) {
  Vec3d c = v.vec3();
  if ((c.array() < 0).any()) v.fail("three non-negative numbers (linear RGB)");
  return c;
}

Vec3d unitRgb(const JsonValue& v) {
  Vec3d c = v.vec3();
  if ((c.array() < 0).any() || (c.array() > 1).any()) v.fail("three numbers in [0, 1] (linear RGB)");
  return c;
}

void checkRigid(const JsonValue& v, const Mat4d& m) {
  const Mat3d r = m.topLeftCorner<3, 3>();
  const double orthoErr = (r.transpose() * r - Mat3d::Identity()).cwiseAbs().maxCoeff();
  const double det = r.determinant();
  const bool lastRow = std::abs(m(3, 0)) < 1e-9 && std::abs(m(3, 1)) < 1e-9 &&
                       std::abs(m(3, 2)) < 1e-9 && std::abs(m(3, 3) - 1.0) < 1e-9;
  if (orthoErr > 1e-4 || det < 0 || !lastRow) {
    std::ostringstream os;
    os << "expected a rigid transform (rotation R with R^T R = I and det R = +1, last row 0 0 0 1); "
       << "got max |R^T R - I| = " << orthoErr << ", det R = " << det
       << (lastRow ? "" : ", last row not 0 0 0 1");
    v.failMessage(os.str());
  }
}

}  // namespace

EnvironmentDesc parseEnvironment(const JsonValue& env, const fs::path& baseDir) {
  warnUnknownKeys(env, {"type", "image", "window_parts", "radiance", "strength", "rotation_deg"});
  if (auto t = env.get("type")) {
    if (t->string() != "environment") t->fail("\"environment\"");
  }
  EnvironmentDesc e;
  if (auto img = env.get("image")) e.image = resolvePath(baseDir, requireNonEmptyString(*img));
  if (auto r = env.get("radiance")) {
    if (r->isNumber()) e.radiance = Vec3d::Constant(r->number(0, 1e9));
    else e.radiance = nonNegativeRgb(*r);
  } else if (auto s = env.get("strength")) {
    e.radiance = Vec3d::Constant(s->number(0, 1e9));
  }
  if (auto rot = env.get("rotation_deg")) e.rotationDeg = rot->number();
  if (auto w = env.get("window_parts")) {
    for (size_t i = 0; i < w->size(); ++i) e.windowParts.push_back(requireNonEmptyString((*w)[i]));
  }
  return e;
}

AreaLightDesc parseAreaLight(const JsonValue& a, bool radianceRequired) {
  if (!a.isObject()) a.fail("an object with \"part\" or \"center\", \"edge_u\", \"edge_v\"");
  warnUnknownKeys(a, {"name", "type", "part", "center", "edge_u", "edge_v", "radiance", "power"});
  AreaLightDesc l;
  if (auto n = a.get("name")) l.name = requireNonEmptyString(*n);
  if (auto t = a.get("type")) {
    if (t->string() != "area") t->fail("\"area\"");
  }
  if (auto p = a.get("part")) {
    l.part = requireNonEmptyString(*p);
  } else {
    if (!a.has("center") && !a.has("edge_u") && !a.has("edge_v"))
      a.failMessage("expected \"part\" (an OBJ part that emits) or a rectangle \"center\", \"edge_u\", \"edge_v\"");
    l.center = a["center"].vec3();
    l.edgeU = a["edge_u"].vec3();
    l.edgeV = a["edge_v"].vec3();
    if (l.edgeU.cross(l.edgeV).norm() < 1e-12)
      a.failMessage("expected edge_u and edge_v spanning a rectangle of non-zero area");
  }
  if (auto r = a.get("radiance")) l.radiance = nonNegativeRgb(*r);
  else if (radianceRequired) a["radiance"];  // throws "missing required key"
  return l;
}

std::string emitterType(const JsonValue& a) {
  if (!a.isObject()) a.fail("an object with \"part\" or \"center\", \"edge_u\", \"edge_v\"");
  if (auto t = a.get("type")) return requireNonEmptyString(*t);
  return "area";
}

Mat4d lookAtWorldToCamera(const Vec3d& eye, const Vec3d& target, const Vec3d& up) {
  Vec3d forward = target - eye;
  PS_Check(forward.norm() > 1e-12, "lookAtWorldToCamera: target equals eye");
  forward.normalize();
  Vec3d right = forward.cross(up);
  PS_Check(right.norm() > 1e-9, "lookAtWorldToCamera: view direction parallel to up");
  right.normalize();
  const Vec3d down = forward.cross(right);
  Mat4d m = Mat4d::Identity();
  m.block<1, 3>(0, 0) = right.transpose();
  m.block<1, 3>(1, 0) = down.transpose();
  m.block<1, 3>(2, 0) = forward.transpose();
  m.topRightCorner<3, 1>() = -m.topLeftCorner<3, 3>() * eye;
  return m;
}

CameraDesc lookAtCamera(int width, int height, double fovYDeg, const Vec3d& eye, const Vec3d& target,
                        const Vec3d& up) {
  CameraDesc cam;
  cam.width = width;
  cam.height = height;
  cam.worldToCamera = lookAtWorldToCamera(eye, target, up);
  cam.fy = 0.5 * height / std::tan(0.5 * fovYDeg * kPiD / 180.0);
  cam.fx = cam.fy;
  cam.cx = 0.5 * width - 0.5;
  cam.cy = 0.5 * height - 0.5;
  return cam;
}

CameraDesc parseCamera(const JsonValue& c) {
  if (!c.isObject()) c.fail("a camera object");
  warnUnknownKeys(c, {"width", "height", "fx", "fy", "cx", "cy", "world_to_camera", "position",
                      "look_at", "up", "fov_y_deg"});
  CameraDesc cam;
  cam.width = static_cast<int>(c["width"].integer(1, 1 << 16));
  cam.height = static_cast<int>(c["height"].integer(1, 1 << 16));
  const bool intrinsic = c.has("fx") || c.has("world_to_camera");
  const bool lookAt = c.has("position") || c.has("look_at") || c.has("fov_y_deg");
  if (intrinsic || !lookAt) {
    cam.fx = c["fx"].number(1e-6, 1e9);
    cam.fy = c["fy"].number(1e-6, 1e9);
    cam.cx = c["cx"].number();
    cam.cy = c["cy"].number();
    const JsonValue w2c = c["world_to_camera"];
    cam.worldToCamera = w2c.matrix4();
    checkRigid(w2c, cam.worldToCamera);
    return cam;
  }
  const Vec3d position = c["position"].vec3();
  const JsonValue lookAtValue = c["look_at"];
  const Vec3d target = lookAtValue.vec3();
  Vec3d up(0, 1, 0);
  if (auto u = c.get("up")) up = u->vec3();
  const JsonValue fovValue = c["fov_y_deg"];
  const double fov = fovValue.number();
  if (!(fov > 0.01 && fov < 179.0)) fovValue.fail("a vertical field of view in (0, 179) degrees");
  if ((target - position).norm() < 1e-12) lookAtValue.failMessage("expected look_at different from position");
  if ((target - position).normalized().cross(up).norm() < 1e-9)
    lookAtValue.failMessage("expected a view direction not parallel to up");
  const CameraDesc built = lookAtCamera(cam.width, cam.height, fov, position, target, up);
  cam = built;
  return cam;
}

nlohmann::json cameraToJson(const CameraDesc& c) {
  nlohmann::json j;
  j["width"] = c.width;
  j["height"] = c.height;
  j["fx"] = c.fx;
  j["fy"] = c.fy;
  j["cx"] = c.cx;
  j["cy"] = c.cy;
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int k = 0; k < 4; ++k) row.push_back(c.worldToCamera(r, k));
    rows.push_back(row);
  }
  j["world_to_camera"] = rows;
  return j;
}

CameraDesc readCameraJson(const fs::path& path) {
  const nlohmann::json j = readJsonFile(path);
  JsonValue root(j, path.string());
  if (root.has("camera")) return parseCamera(root["camera"]);
  return parseCamera(root);
}

SceneDesc readSceneJson(const fs::path& path) {
  SceneDesc scene;
  scene.file = path;
  scene.baseDir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  scene.rawJson = readJsonFile(path);
  const JsonValue root(scene.rawJson, path.string());
  if (!root.isObject()) root.fail("a JSON object");
  warnUnknownKeys(root, {"version", "geometry", "up", "views", "lights", "parts", "options"});

  scene.version = static_cast<int>(root["version"].integer());
  if (scene.version != 1) root["version"].fail("version 1");
  scene.geometry = resolvePath(scene.baseDir, requireNonEmptyString(root["geometry"]));
  if (auto up = root.get("up")) {
    scene.up = up->vec3();
    if (scene.up.norm() < 1e-12) up->fail("a non-zero direction");
    scene.up.normalize();
  }

  const JsonValue views = root["views"];
  if (views.size() == 0) views.fail("at least one view");
  for (size_t i = 0; i < views.size(); ++i) {
    const JsonValue v = views[i];
    if (!v.isObject()) v.fail("a view object");
    warnUnknownKeys(v, {"image", "color_space", "camera", "segments", "segment_parts"});
    ViewDesc view;
    view.image = resolvePath(scene.baseDir, requireNonEmptyString(v["image"]));
    if (auto cs = v.get("color_space")) {
      view.colorSpace = cs->string();
      if (view.colorSpace != "srgb" && view.colorSpace != "linear") cs->fail("\"srgb\" or \"linear\"");
    }
    view.camera = parseCamera(v["camera"]);
    if (auto seg = v.get("segments")) view.segments = resolvePath(scene.baseDir, requireNonEmptyString(*seg));
    if (auto sp = v.get("segment_parts")) {
      if (!sp->isObject()) sp->fail("an object mapping region values to part names");
      for (const auto& key : sp->keys()) {
        int64_t value = 0;
        size_t used = 0;
        try {
          value = std::stoll(key, &used);
        } catch (...) {
          used = 0;
        }
        if (used != key.size() || value < 1 || value > 65535)
          throw InputError(path.string(), sp->path() + "." + key,
                           "expected a region value 1..65535 as the key, got \"" + key + "\"");
        view.segmentParts[value] = requireNonEmptyString((*sp)[key]);
      }
      if (!view.segments) sp->failMessage("segment_parts given without \"segments\"");
    }
    scene.views.push_back(std::move(view));
  }

  if (auto lights = root.get("lights")) {
    if (!lights->isObject()) lights->fail("an object");
    warnUnknownKeys(*lights, {"area", "auto_ceiling_spacing", "environment"});
    if (auto area = lights->get("area")) {
      for (size_t i = 0; i < area->size(); ++i) {
        const std::string type = emitterType((*area)[i]);
        if (type != "area") {
          scene.lights.registered.push_back({type, (*area)[i].path(), (*area)[i].raw()});
          continue;
        }
        AreaLightDesc l = parseAreaLight((*area)[i], false);
        if (l.name.empty()) l.name = l.part ? *l.part : "area_" + std::to_string(i);
        scene.lights.area.push_back(std::move(l));
      }
    }
    if (auto sp = lights->get("auto_ceiling_spacing")) scene.lights.autoCeilingSpacing = sp->number(0.1, 1000);
    if (auto env = lights->get("environment")) {
      if (!env->isObject()) env->fail("an object");
      scene.lights.environment = parseEnvironment(*env, scene.baseDir);
    }
  }

  if (auto parts = root.get("parts")) {
    if (!parts->isObject()) parts->fail("an object mapping part names to settings");
    for (const auto& name : parts->keys()) {
      const JsonValue p = (*parts)[name];
      if (!p.isObject()) p.fail("an object with \"graph\", \"category\", \"fixed\" or \"skip\"");
      warnUnknownKeys(p, {"graph", "category", "fixed", "skip"});
      PartDesc d;
      if (auto g = p.get("graph")) d.graph = requireNonEmptyString(*g);
      if (auto c = p.get("category")) d.category = requireNonEmptyString(*c);
      if (auto f = p.get("fixed")) {
        if (!f->isObject()) f->fail("an object with albedo and roughness");
        warnUnknownKeys(*f, {"albedo", "roughness", "metallic", "specular"});
        HomogeneousDesc h;
        h.albedo = unitRgb((*f)["albedo"]);
        h.roughness = (*f)["roughness"].number(0, 1);
        if (auto m = f->get("metallic")) h.metallic = m->number(0, 1);
        if (auto s = f->get("specular")) h.specular = s->number(0, 1);
        d.fixed = h;
      }
      if (auto s = p.get("skip")) d.skip = s->boolean();
      scene.parts[name] = d;
    }
  }

  if (auto options = root.get("options")) {
    if (!options->isObject()) options->fail("an object");
    if (auto preset = options->get("preset")) {
      scene.options.preset = preset->string();
      if (scene.options.preset != "fast" && scene.options.preset != "balanced" && scene.options.preset != "paper")
        preset->fail("\"fast\", \"balanced\" or \"paper\"");
    }
    if (auto seed = options->get("seed")) scene.options.seed = static_cast<uint64_t>(seed->integer(0));
    if (auto refine = options->get("refine_poses")) scene.options.refinePoses = refine->boolean();
  }
  return scene;
}

LightsFileDesc readLightsJson(const fs::path& path) {
  const nlohmann::json j = readJsonFile(path);
  const JsonValue root(j, path.string());
  if (!root.isObject()) root.fail("a JSON object");
  const fs::path baseDir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  LightsFileDesc out;
  if (auto em = root.get("emitters")) {
    for (size_t i = 0; i < em->size(); ++i) {
      const std::string type = emitterType((*em)[i]);
      if (type != "area") {
        out.registered.push_back({type, (*em)[i].path(), (*em)[i].raw()});
        continue;
      }
      AreaLightDesc l = parseAreaLight((*em)[i], true);
      if (l.name.empty()) l.name = l.part ? *l.part : "emitter_" + std::to_string(i);
      out.emitters.push_back(std::move(l));
    }
  }
  if (auto env = root.get("environment")) out.environment = parseEnvironment(*env, baseDir);
  if (auto ex = root.get("exposure")) {
    for (size_t i = 0; i < ex->size(); ++i) out.exposure.push_back((*ex)[i].number(0, 1e9));
  }
  return out;
}

void writeLightsJson(const fs::path& path, const LightsFileDesc& lights) {
  const fs::path baseDir = path.parent_path();
  nlohmann::json j;
  j["emitters"] = nlohmann::json::array();
  for (const auto& l : lights.emitters) {
    nlohmann::json e;
    e["name"] = l.name;
    e["type"] = "area";
    if (l.part) {
      e["part"] = *l.part;
    } else {
      e["center"] = {l.center.x(), l.center.y(), l.center.z()};
      e["edge_u"] = {l.edgeU.x(), l.edgeU.y(), l.edgeU.z()};
      e["edge_v"] = {l.edgeV.x(), l.edgeV.y(), l.edgeV.z()};
    }
    const Vec3d r = l.radiance.value_or(Vec3d::Zero());
    e["radiance"] = {r.x(), r.y(), r.z()};
    j["emitters"].push_back(e);
  }
  for (const auto& r : lights.registered) j["emitters"].push_back(r.json);
  if (lights.environment) {
    const auto& env = *lights.environment;
    nlohmann::json e;
    e["radiance"] = {env.radiance.x(), env.radiance.y(), env.radiance.z()};
    if (env.image) e["image"] = fs::relative(*env.image, baseDir.empty() ? "." : baseDir).generic_string();
    e["rotation_deg"] = env.rotationDeg;
    e["window_parts"] = env.windowParts;
    j["environment"] = e;
  }
  j["exposure"] = lights.exposure;
  writeJsonFile(path, j);
}

MaterialFileDesc readMaterialJson(const fs::path& path) {
  const nlohmann::json j = readJsonFile(path);
  const JsonValue root(j, path.string());
  if (!root.isObject()) root.fail("a JSON object");
  // maps are relative to the output folder, the parent of materials/
  const fs::path outDir = path.parent_path().parent_path();
  MaterialFileDesc m;
  m.part = root["part"].string();
  if (auto g = root.get("graph")) m.graph = g->string();
  if (auto c = root.get("category")) m.category = c->string();
  if (auto p = root.get("params")) m.params = p->raw();
  if (auto uv = root.get("uv_transform")) {
    if (auto r = uv->get("rotation_deg")) m.uv.rotationDeg = r->number();
    if (auto s = uv->get("scale")) {
      if (s->isNumber()) m.uv.scale = Vec2d::Constant(s->number(1e-9, 1e9));
      else m.uv.scale = s->vec2();
      if ((m.uv.scale.array().abs() < 1e-12).any()) s->fail("a non-zero scale");
    }
    if (auto o = uv->get("offset")) m.uv.offset = o->vec2();
  }
  if (auto a = root.get("albedo_offset")) m.albedoOffset = a->vec3();
  if (auto a = root.get("albedo_scale")) m.albedoScale = a->number(0, 1e6);
  if (auto r = root.get("roughness_scale")) m.roughnessScale = r->number(0, 1e6);
  if (auto h = root.get("homogeneous")) {
    if (auto a = h->get("albedo")) m.homogeneous.albedo = unitRgb(*a);
    if (auto r = h->get("roughness")) m.homogeneous.roughness = r->number(0, 1);
    if (auto me = h->get("metallic")) m.homogeneous.metallic = me->number(0, 1);
    if (auto s = h->get("specular")) m.homogeneous.specular = s->number(0, 1);
  }
  if (auto maps = root.get("maps")) {
    for (const auto& key : maps->keys()) {
      const JsonValue v = (*maps)[key];
      m.maps[key] = resolvePath(outDir, requireNonEmptyString(v));
    }
  }
  if (auto fit = root.get("fit")) {
    if (auto v = fit->get("view")) m.fitView = static_cast<int>(v->integer(0));
    if (auto l = fit->get("loss")) m.fitLoss = l->number();
    if (auto s = fit->get("seconds")) m.fitSeconds = s->number();
    if (auto s = fit->get("skipped")) m.skipped = s->string();
  }
  return m;
}

void writeMaterialJson(const fs::path& path, const MaterialFileDesc& m, const fs::path& outDir) {
  nlohmann::json j;
  j["part"] = m.part;
  j["graph"] = m.graph;
  j["category"] = m.category;
  j["params"] = m.params;
  j["uv_transform"] = {{"rotation_deg", m.uv.rotationDeg},
                       {"scale", m.uv.scale.x() == m.uv.scale.y()
                                     ? nlohmann::json(m.uv.scale.x())
                                     : nlohmann::json::array({m.uv.scale.x(), m.uv.scale.y()})},
                       {"offset", {m.uv.offset.x(), m.uv.offset.y()}}};
  j["albedo_offset"] = {m.albedoOffset.x(), m.albedoOffset.y(), m.albedoOffset.z()};
  j["albedo_scale"] = m.albedoScale;
  j["roughness_scale"] = m.roughnessScale;
  const auto& h = m.homogeneous;
  j["homogeneous"] = {{"albedo", {h.albedo.x(), h.albedo.y(), h.albedo.z()}},
                      {"roughness", h.roughness},
                      {"metallic", h.metallic},
                      {"specular", h.specular}};
  nlohmann::json maps = nlohmann::json::object();
  for (const auto& [k, p] : m.maps) maps[k] = fs::relative(p, outDir).generic_string();
  j["maps"] = maps;
  nlohmann::json fit;
  fit["view"] = m.fitView ? nlohmann::json(*m.fitView) : nlohmann::json(nullptr);
  fit["loss"] = m.fitLoss ? nlohmann::json(*m.fitLoss) : nlohmann::json(nullptr);
  fit["seconds"] = m.fitSeconds ? nlohmann::json(*m.fitSeconds) : nlohmann::json(nullptr);
  fit["skipped"] = m.skipped ? nlohmann::json(*m.skipped) : nlohmann::json(nullptr);
  for (const auto& [k, v] : m.fitExtra.items()) fit[k] = v;
  j["fit"] = fit;
  writeJsonFile(path, j);
}

}  // namespace ps::io
