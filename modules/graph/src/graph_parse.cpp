// Parsing and validation of graph JSON files (format: modules/graph/FORMAT.md).
#include "engine.hpp"
#include "photoscene/graph/graph_library.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <set>

namespace ps {

const char* mapKindName(MapKind kind) {
  static const char* names[] = {"albedo", "normal", "roughness", "metallic", "height"};
  return names[int(kind)];
}

const std::vector<std::string>& materialCategories() {
  static const std::vector<std::string> c = {"wood",      "tile",  "stone",   "concrete", "plaster",
                                             "paint",     "wallpaper", "brick", "fabric", "carpet",
                                             "leather",   "metal", "plastic", "cork",     "rubber",
                                             "paper",     "homogeneous"};
  return c;
}

}  // namespace ps

namespace ps::graphimpl {
namespace {

using nlohmann::json;

struct Parser {
  std::string src;
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(src, where, what);
  }
  std::string str(const json& j, const char* key, const std::string& where, bool required = true) {
    if (!j.contains(key)) {
      if (required) fail(where + "." + key, "expected a string, the key is missing");
      return {};
    }
    if (!j[key].is_string()) fail(where + "." + key, "expected a string, got " + j[key].dump());
    return j[key].get<std::string>();
  }
};

/// Reads a parameter value (number, [r,g,b], or a choice name) for parameter p.
std::vector<double> readValue(const Parser& ps, const json& v, const GraphParameter& p,
                              const std::string& where) {
  std::vector<double> out;
  if (p.kind == ParameterKind::Choice && v.is_string()) {
    for (size_t i = 0; i < p.choices.size(); ++i)
      if (p.choices[i] == v.get<std::string>()) return {double(i)};
    std::string all;
    for (const auto& c : p.choices) all += (all.empty() ? "" : ", ") + c;
    ps.fail(where, "expected one of " + all + ", got " + v.dump());
  }
  if (p.dim == 1 && v.is_number()) return {v.get<double>()};
  if (p.dim == 3 && v.is_array() && v.size() == 3) {
    for (const auto& e : v) {
      if (!e.is_number()) ps.fail(where, "expected 3 numbers, got " + v.dump());
      out.push_back(e.get<double>());
    }
    return out;
  }
  ps.fail(where, std::string("expected ") + (p.dim == 3 ? "[r, g, b]" : "a number") +
                     (p.kind == ParameterKind::Choice ? " or a choice name" : "") + ", got " +
                     v.dump());
}

}  // namespace

std::shared_ptr<const GraphSpec> parseGraph(const std::string& text, const std::string& source) {
  Parser ps{source};
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    // parse_error (syntax) and out_of_range (a number that overflows: found by the graph_json
    // fuzzer) are both bad input
    ps.fail("", std::string("expected valid JSON: ") + e.what());
  }
  if (!j.is_object()) ps.fail("", "expected a JSON object");
  auto spec = std::make_shared<GraphSpec>();
  spec->source = source;
  spec->name = ps.str(j, "name", "");
  spec->category = ps.str(j, "category", "");
  spec->description = ps.str(j, "description", "", false);
  if (spec->name.empty()) ps.fail("name", "expected a non-empty name");
  const auto& cats = materialCategories();
  if (std::find(cats.begin(), cats.end(), spec->category) == cats.end())
    ps.fail("category", "expected one of the categories of scene-format.md section 4, got \"" +
                            spec->category + "\"");

  // ---- nodes
  if (!j.contains("nodes") || !j["nodes"].is_array() || j["nodes"].empty())
    ps.fail("nodes", "expected a non-empty array of nodes");
  const json& jn = j["nodes"];
  std::map<std::string, int> idIndex;
  std::vector<NodeSpec> raw;
  for (size_t i = 0; i < jn.size(); ++i) {
    const std::string w = "nodes[" + std::to_string(i) + "]";
    if (!jn[i].is_object()) ps.fail(w, "expected an object");
    NodeSpec ns;
    ns.id = ps.str(jn[i], "id", w);
    const std::string type = ps.str(jn[i], "type", w);
    ns.type = findNodeType(type);
    if (!ns.type) ps.fail(w + ".type", "expected a node type of node_catalog.hpp, got \"" + type + "\"");
    if (idIndex.count(ns.id)) ps.fail(w + ".id", "duplicate node id \"" + ns.id + "\"");
    idIndex[ns.id] = int(i);
    const auto& d = ns.type->desc;
    for (const auto& p : d.params)
      for (float v : p.defaultValue) ns.constants.push_back(v);
    if (jn[i].contains("params")) {
      if (!jn[i]["params"].is_object()) ps.fail(w + ".params", "expected an object");
      for (auto it = jn[i]["params"].begin(); it != jn[i]["params"].end(); ++it) {
        const int pi = ns.type->findParam(it.key());
        const std::string pw = w + ".params." + it.key();
        if (pi < 0) ps.fail(pw, "no parameter of that name in node type " + type);
        const auto& p = d.params[pi];
        auto v = readValue(ps, it.value(), p, pw);
        for (int k = 0; k < p.dim; ++k) {
          if (v[k] < p.min - 1e-6 || v[k] > p.max + 1e-6)
            ps.fail(pw, "expected a value in [" + std::to_string(p.min) + ", " +
                            std::to_string(p.max) + "], got " + std::to_string(v[k]));
          ns.constants[p.offset + k] = v[k];
        }
      }
    }
    raw.push_back(std::move(ns));
  }
  auto parseRef = [&](const std::string& ref, const std::string& where, bool outputPort) {
    LinkRef l;
    std::string id = ref, port;
    const auto dot = ref.find('.');
    if (dot != std::string::npos) id = ref.substr(0, dot), port = ref.substr(dot + 1);
    auto it = idIndex.find(id);
    if (it == idIndex.end()) ps.fail(where, "expected a node id, got \"" + ref + "\"");
    l.node = it->second;
    const auto& outs = raw[l.node].type->desc.outputs;
    if (!port.empty()) {
      l.port = -1;
      for (size_t o = 0; o < outs.size(); ++o)
        if (outs[o].name == port) l.port = int(o);
      if (l.port < 0) ps.fail(where, "node \"" + id + "\" has no output \"" + port + "\"");
    }
    (void)outputPort;
    return l;
  };
  for (size_t i = 0; i < jn.size(); ++i) {
    const std::string w = "nodes[" + std::to_string(i) + "].inputs";
    NodeSpec& ns = raw[i];
    const auto& ports = ns.type->desc.inputs;
    ns.inputs.assign(ports.size(), LinkRef{});
    if (jn[i].contains("inputs")) {
      if (!jn[i]["inputs"].is_object()) ps.fail(w, "expected an object {port: \"node[.output]\"}");
      for (auto it = jn[i]["inputs"].begin(); it != jn[i]["inputs"].end(); ++it) {
        int p = -1;
        for (size_t q = 0; q < ports.size(); ++q)
          if (ports[q].name == it.key()) p = int(q);
        if (p < 0) ps.fail(w + "." + it.key(), "node type " + ns.type->desc.name + " has no such input");
        if (!it.value().is_string()) ps.fail(w + "." + it.key(), "expected \"node[.output]\"");
        ns.inputs[p] = parseRef(it.value().get<std::string>(), w + "." + it.key(), true);
      }
    }
    for (size_t q = 0; q < ports.size(); ++q)
      if (!ports[q].optional && ns.inputs[q].node < 0)
        ps.fail(w + "." + ports[q].name, "required input is not linked");
  }
  // ---- topological order (Kahn), refusing cycles
  const int N = int(raw.size());
  std::vector<int> indeg(N, 0), order;
  std::vector<std::vector<int>> users(N);
  for (int i = 0; i < N; ++i)
    for (const auto& l : raw[i].inputs)
      if (l.node >= 0) ++indeg[i], users[l.node].push_back(i);
  std::vector<int> ready;
  for (int i = N - 1; i >= 0; --i)
    if (!indeg[i]) ready.push_back(i);
  while (!ready.empty()) {
    // smallest index first for a stable order
    auto it = std::min_element(ready.begin(), ready.end());
    const int i = *it;
    ready.erase(it);
    order.push_back(i);
    for (int u : users[i])
      if (--indeg[u] == 0) ready.push_back(u);
  }
  if (int(order.size()) != N) ps.fail("nodes", "expected an acyclic graph, the links form a cycle");
  std::vector<int> newIndex(N);
  for (int k = 0; k < N; ++k) newIndex[order[k]] = k;
  for (int k = 0; k < N; ++k) {
    NodeSpec ns = raw[order[k]];
    for (auto& l : ns.inputs)
      if (l.node >= 0) l.node = newIndex[l.node];
    spec->nodes.push_back(std::move(ns));
  }
  // ---- channels
  for (auto& ns : spec->nodes) {
    const auto& d = ns.type->desc;
    int work = 1;
    for (size_t p = 0; p < d.inputs.size(); ++p)
      if (d.inputs[p].channels == 0 && ns.inputs[p].node >= 0)
        work = std::max(work, spec->nodes[ns.inputs[p].node].outChannels[ns.inputs[p].port]);
    ns.inChannels.clear();
    for (size_t p = 0; p < d.inputs.size(); ++p) {
      const int want = d.inputs[p].channels == 0 ? work : d.inputs[p].channels;
      ns.inChannels.push_back(want);
      if (ns.inputs[p].node >= 0) {
        const int have = spec->nodes[ns.inputs[p].node].outChannels[ns.inputs[p].port];
        if (have != want && !(have == 1 && want == 3))
          ps.fail("nodes." + ns.id + ".inputs." + d.inputs[p].name,
                  "expected a " + std::to_string(want) + "-channel image, the link gives " +
                      std::to_string(have) + " channels");
      }
    }
    ns.outChannels.clear();
    for (const auto& o : d.outputs) ns.outChannels.push_back(o.channels == 0 ? work : o.channels);
  }
  std::map<std::string, int> sortedIndex;
  for (int k = 0; k < N; ++k) sortedIndex[spec->nodes[k].id] = k;
  auto ref = [&](const std::string& r, const std::string& where) {
    std::string id = r, port;
    const auto dot = r.find('.');
    if (dot != std::string::npos) id = r.substr(0, dot), port = r.substr(dot + 1);
    auto it = sortedIndex.find(id);
    if (it == sortedIndex.end()) ps.fail(where, "expected a node id, got \"" + r + "\"");
    LinkRef l{it->second, 0};
    if (!port.empty()) {
      l.port = -1;
      const auto& outs = spec->nodes[l.node].type->desc.outputs;
      for (size_t o = 0; o < outs.size(); ++o)
        if (outs[o].name == port) l.port = int(o);
      if (l.port < 0) ps.fail(where, "node \"" + id + "\" has no output \"" + port + "\"");
    }
    return l;
  };

  // ---- outputs
  if (!j.contains("outputs") || !j["outputs"].is_object())
    ps.fail("outputs", "expected an object {albedo, normal, roughness[, metallic, height]}");
  for (auto it = j["outputs"].begin(); it != j["outputs"].end(); ++it) {
    int k = -1;
    for (int q = 0; q < kMapKindCount; ++q)
      if (it.key() == mapKindName(MapKind(q))) k = q;
    const std::string w = "outputs." + it.key();
    if (k < 0) ps.fail(w, "expected one of albedo, normal, roughness, metallic, height");
    if (!it.value().is_string()) ps.fail(w, "expected \"node[.output]\"");
    LinkRef l = ref(it.value().get<std::string>(), w);
    const int ch = spec->nodes[l.node].outChannels[l.port];
    if (k == int(MapKind::Normal) && ch != 3) ps.fail(w, "expected a 3-channel (normal) output");
    if (k >= int(MapKind::Roughness) && ch != 1) ps.fail(w, "expected a 1-channel output");
    spec->outputs[k] = l;
  }
  for (int k = 0; k < 3; ++k)
    if (spec->outputs[k].node < 0)
      ps.fail(std::string("outputs.") + mapKindName(MapKind(k)), "this output is required");

  // ---- exposed parameters
  if (j.contains("parameters")) {
    if (!j["parameters"].is_array()) ps.fail("parameters", "expected an array");
    std::set<std::string> seen;
    int offset = 0;
    const json& jp = j["parameters"];
    for (size_t i = 0; i < jp.size(); ++i) {
      const std::string w = "parameters[" + std::to_string(i) + "]";
      GraphParameter gp;
      gp.name = ps.str(jp[i], "name", w);
      gp.doc = ps.str(jp[i], "doc", w, false);
      if (gp.name == "albedo_offset") ps.fail(w + ".name", "albedo_offset is added to every graph");
      if (!seen.insert(gp.name).second) ps.fail(w + ".name", "duplicate parameter \"" + gp.name + "\"");
      if (!jp[i].contains("targets") || !jp[i]["targets"].is_array() || jp[i]["targets"].empty())
        ps.fail(w + ".targets", "expected a non-empty array of \"node.param\"");
      std::vector<Binding> binds;
      const GraphParameter* first = nullptr;
      for (size_t t = 0; t < jp[i]["targets"].size(); ++t) {
        const std::string tw = w + ".targets[" + std::to_string(t) + "]";
        const json& jt = jp[i]["targets"][t];
        if (!jt.is_string()) ps.fail(tw, "expected \"node.param\"");
        const std::string s = jt.get<std::string>();
        const auto dot = s.find('.');
        if (dot == std::string::npos) ps.fail(tw, "expected \"node.param\", got \"" + s + "\"");
        auto it = sortedIndex.find(s.substr(0, dot));
        if (it == sortedIndex.end()) ps.fail(tw, "no node \"" + s.substr(0, dot) + "\"");
        const NodeType& nt = *spec->nodes[it->second].type;
        const int pi = nt.findParam(s.substr(dot + 1));
        if (pi < 0) ps.fail(tw, "node type " + nt.desc.name + " has no parameter \"" + s.substr(dot + 1) + "\"");
        const GraphParameter& np = nt.desc.params[pi];
        if (!first) {
          first = &np;
          gp.kind = np.kind;
          gp.dim = np.dim;
          gp.min = np.min;
          gp.max = np.max;
          gp.choices = np.choices;
          const auto& cst = spec->nodes[it->second].constants;
          gp.defaultValue.assign(cst.begin() + np.offset, cst.begin() + np.offset + np.dim);
        } else if (np.kind != first->kind || np.dim != first->dim || np.choices != first->choices) {
          ps.fail(tw, "all targets of a parameter must have the same kind and dimension");
        }
        binds.push_back({it->second, np.offset});
        if (np.kind == ParameterKind::Continuous) {
          NodeSpec& bn = spec->nodes[it->second];
          bn.hasDiffBinding = true;
          bn.diffParam.resize(nt.desc.params.size(), 0);
          bn.diffParam[pi] = 1;
        }
      }
      auto num = [&](const char* key, float& v) {
        if (!jp[i].contains(key)) return;
        if (!jp[i][key].is_number()) ps.fail(w + "." + key, "expected a number");
        v = jp[i][key].get<float>();
      };
      float lo = gp.min, hi = gp.max;
      num("min", lo);
      num("max", hi);
      if (lo < first->min - 1e-6f || hi > first->max + 1e-6f || lo > hi)
        ps.fail(w, "expected min <= max inside the node parameter's range [" +
                       std::to_string(first->min) + ", " + std::to_string(first->max) + "]");
      gp.min = lo, gp.max = hi;
      if (jp[i].contains("default")) {
        auto v = readValue(ps, jp[i]["default"], gp, w + ".default");
        gp.defaultValue.assign(v.begin(), v.end());
      }
      for (float& v : gp.defaultValue)
        if (v < gp.min - 1e-6f || v > gp.max + 1e-6f)
          ps.fail(w + ".default", "expected the default inside [min, max]");
      gp.offset = offset;
      offset += gp.dim;
      spec->params.push_back(gp);
      spec->bindings.push_back(binds);
    }
    spec->valueCount = offset;
  }
  {
    GraphParameter off;
    off.name = "albedo_offset";
    off.doc = "added to the albedo (linear RGB) before the final clamp to [0, 1]";
    off.kind = ParameterKind::Continuous;
    off.dim = 3;
    off.min = -0.5f;
    off.max = 0.5f;
    off.defaultValue = {0, 0, 0};
    off.offset = spec->valueCount;
    spec->albedoOffsetIndex = spec->valueCount;
    spec->valueCount += 3;
    spec->params.push_back(off);
    spec->bindings.push_back({});
  }
  // ---- gradient flags
  for (auto& ns : spec->nodes) {
    ns.requiresGrad = ns.hasDiffBinding;
    for (const auto& l : ns.inputs)
      if (l.node >= 0 && spec->nodes[l.node].requiresGrad) ns.requiresGrad = true;
  }
  Hasher h;
  h.add(std::string_view(j.dump()));
  spec->hash = h.digest();
  return spec;
}

}  // namespace ps::graphimpl
