// The light registry and LightSet.
#include "photoscene/scene/light.hpp"

#include <algorithm>
#include <map>
#include <mutex>
#include <sstream>

#include "light_geometry.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/scene/lights.hpp"
#include "photoscene/scene/mesh.hpp"

namespace ps {

namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, LightFactory> factories;
  Registry() {
    // the built-in types are listed here (a static library drops a file that only registers)
    factories["area"] = &AreaLight::fromJson;
    factories["environment"] = &EnvironmentLight::fromJson;
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

bool LightRegistry::add(const std::string& type, LightFactory factory) {
  PS_Check(!type.empty() && factory, "LightRegistry::add: a type name and a factory");
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.factories[type] = std::move(factory);
  return true;
}

bool LightRegistry::has(const std::string& type) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  return r.factories.count(type) > 0;
}

std::vector<std::string> LightRegistry::types() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> out;
  for (const auto& [name, f] : r.factories) out.push_back(name);
  return out;
}

std::unique_ptr<Light> LightRegistry::create(const io::JsonValue& entry,
                                             const LightJsonContext& ctx) {
  if (!entry.isObject()) entry.fail("an object with a \"type\"");
  const io::JsonValue t = entry["type"];
  const std::string type = t.string();
  LightFactory f;
  {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    auto it = r.factories.find(type);
    if (it != r.factories.end()) f = it->second;
  }
  if (!f) {
    std::ostringstream os;
    os << "one of the light types";
    const auto names = types();
    for (size_t i = 0; i < names.size(); ++i) os << (i ? ", \"" : " \"") << names[i] << "\"";
    t.fail(os.str());
  }
  std::unique_ptr<Light> light = f(entry, ctx);
  PS_Check(light && light->type() == type,
           "light factory of \"" << type << "\" made "
                                 << (light ? "\"" + light->type() + "\"" : "nothing"));
  return light;
}

std::string Light::describe(const std::vector<Part>& parts) const {
  LightJsonContext ctx;
  ctx.parts = &parts;
  return toJson(ctx).dump();
}

// ---------------------------------------------------------------------------------------------

std::vector<const Light*> LightSet::all() const {
  std::vector<const Light*> out;
  out.reserve(size());
  for (const AreaLight& a : area) out.push_back(&a);
  for (const LightHandle& h : registered) out.push_back(h.get());
  if (environment) out.push_back(&*environment);
  return out;
}

std::vector<Light*> LightSet::all() {
  std::vector<Light*> out;
  out.reserve(size());
  for (AreaLight& a : area) out.push_back(&a);
  for (LightHandle& h : registered) out.push_back(h.get());
  if (environment) out.push_back(&*environment);
  return out;
}

void LightSet::add(std::unique_ptr<Light> light) {
  PS_Check(light, "LightSet::add: no light");
  if (auto* a = dynamic_cast<AreaLight*>(light.get())) {
    area.push_back(std::move(*a));
  } else if (auto* e = dynamic_cast<EnvironmentLight*>(light.get())) {
    PS_Check(!environment, "LightSet::add: a second environment");
    environment = std::move(*e);
  } else {
    registered.emplace_back(std::move(light));
  }
}

std::vector<int> LightSet::emittingParts() const {
  std::vector<int> out;
  for (const Light* l : all())
    for (int p : l->emittingParts()) out.push_back(p);
  return out;
}

std::vector<int> LightSet::fittedLights() const {
  std::vector<int> out;
  const std::vector<const Light*> lights = all();
  for (size_t i = 0; i < lights.size(); ++i)
    if (lights[i]->fitsScale()) out.push_back(static_cast<int>(i));
  return out;
}

std::string LightJsonContext::refer(const std::filesystem::path& f) const {
  if (fileRef) return fileRef(f);
  return std::filesystem::relative(f, baseDir.empty() ? "." : baseDir).generic_string();
}

namespace {

// The mean of a light's shape vertices (its center for a rectangle); false when it has none.
bool shapeCentroid(const Light& l, Vec3f* c) {
  std::vector<Vec3f> v;
  l.shapes(&v, nullptr);
  if (v.empty()) return false;
  Vec3f sum = Vec3f::Zero();
  for (const Vec3f& x : v) sum += x;
  *c = sum / static_cast<float>(v.size());
  return true;
}

}  // namespace

int matchLight(const Light& light, const std::vector<const Light*>& list, float maxDistance) {
  const std::string type = light.type();
  const std::vector<int> parts = light.emittingParts();
  for (size_t i = 0; i < list.size(); ++i) {
    if (list[i]->type() != type) continue;
    for (int p : list[i]->emittingParts())
      if (std::find(parts.begin(), parts.end(), p) != parts.end()) return static_cast<int>(i);
  }
  const std::string label = light.label();
  for (size_t i = 0; i < list.size(); ++i)
    if (!label.empty() && list[i]->type() == type && list[i]->label() == label)
      return static_cast<int>(i);
  Vec3f c;
  if (!parts.empty() || !shapeCentroid(light, &c)) return -1;
  int best = -1;
  float bestD = maxDistance;
  for (size_t i = 0; i < list.size(); ++i) {
    Vec3f ci;
    if (list[i]->type() != type || !list[i]->emittingParts().empty() ||
        !shapeCentroid(*list[i], &ci))
      continue;
    const float d = (ci - c).norm();
    if (d <= bestD) bestD = d, best = static_cast<int>(i);
  }
  return best;
}

std::vector<int> LightSet::openingParts() const {
  std::vector<int> out;
  for (const Light* l : all())
    for (int p : l->openingParts()) out.push_back(p);
  return out;
}

nlohmann::json lightsToJson(const LightSet& lights, const LightJsonContext& ctx,
                            const std::vector<double>& exposure) {
  nlohmann::json j;
  j["emitters"] = nlohmann::json::array();
  for (const Light* l : lights.all()) {
    nlohmann::json e = l->toJson(ctx);
    if (l->isInfinite()) {
      PS_Check(!j.contains("environment"), "lightsToJson: more than one infinite light");
      e.erase("type");  // the contract's "environment" object has no type
      j["environment"] = e;
    } else {
      j["emitters"].push_back(e);
    }
  }
  j["exposure"] = exposure;
  return j;
}

int requirePartId(const std::vector<Part>& parts, const std::string& name, const std::string& file,
                  const std::string& key) {
  for (const Part& p : parts)
    if (p.name == name) return p.id;
  std::ostringstream os;
  for (size_t i = 0; i < parts.size() && i < 12; ++i) os << (i ? ", " : "") << parts[i].name;
  if (parts.size() > 12) os << ", ... (" << parts.size() << " parts)";
  throw InputError(file, key,
                   "unknown part \"" + name + "\": the OBJ's parts (usemtl names) are " + os.str());
}

}  // namespace ps
