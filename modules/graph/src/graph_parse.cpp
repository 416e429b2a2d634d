// Parsing and validation of graph JSON files (format: modules/graph/FORMAT.md).
#include "engine.hpp"
#include "photoscene/graph/graph_library.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
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
  std::string str(const json& j, const char* key, const std::string& where,
                  bool required = true) const {
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


/// A link "node[.output]": the node by `index` (node id -> position in `nodes`), the output by
/// name (the first when none is named).
LinkRef parseLink(const Parser& ps, const std::string& ref, const std::string& where,
                  const std::map<std::string, int>& index, const std::vector<NodeSpec>& nodes) {
  std::string id = ref, port;
  const auto dot = ref.find('.');
  if (dot != std::string::npos) id = ref.substr(0, dot), port = ref.substr(dot + 1);
  const auto it = index.find(id);
  if (it == index.end()) ps.fail(where, "expected a node id, got \"" + ref + "\"");
  LinkRef l{it->second, 0};
  if (!port.empty()) {
    l.port = -1;
    const auto& outs = nodes[l.node].type->desc.outputs;
    for (size_t o = 0; o < outs.size(); ++o)
      if (outs[o].name == port) l.port = int(o);
    if (l.port < 0) ps.fail(where, "node \"" + id + "\" has no output \"" + port + "\"");
  }
  return l;
}

/// The nodes in file order with their types and constant parameters (their defaults, then the
/// file's `params`); `index` gets each node id's position.
std::vector<NodeSpec> readNodes(const Parser& ps, const json& jn,
                                std::map<std::string, int>& index) {
  std::vector<NodeSpec> nodes;
  for (size_t i = 0; i < jn.size(); ++i) {
    const std::string w = "nodes[" + std::to_string(i) + "]";
    if (!jn[i].is_object()) ps.fail(w, "expected an object");
    NodeSpec ns;
    ns.id = ps.str(jn[i], "id", w);
    const std::string type = ps.str(jn[i], "type", w);
    ns.type = findNodeType(type);
    if (!ns.type)
      ps.fail(w + ".type", "expected a node type of node_catalog.hpp, got \"" + type + "\"");
    if (index.count(ns.id)) ps.fail(w + ".id", "duplicate node id \"" + ns.id + "\"");
    index[ns.id] = int(i);
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
    nodes.push_back(std::move(ns));
  }
  return nodes;
}

/// Each node's input ports linked as the file's `inputs` say; a required port left open fails.
void linkInputs(const Parser& ps, const json& jn, const std::map<std::string, int>& index,
                std::vector<NodeSpec>& nodes) {
  for (size_t i = 0; i < jn.size(); ++i) {
    const std::string w = "nodes[" + std::to_string(i) + "].inputs";
    NodeSpec& ns = nodes[i];
    const auto& ports = ns.type->desc.inputs;
    ns.inputs.assign(ports.size(), LinkRef{});
    if (jn[i].contains("inputs")) {
      if (!jn[i]["inputs"].is_object()) ps.fail(w, "expected an object {port: \"node[.output]\"}");
      for (auto it = jn[i]["inputs"].begin(); it != jn[i]["inputs"].end(); ++it) {
        int p = -1;
        for (size_t q = 0; q < ports.size(); ++q)
          if (ports[q].name == it.key()) p = int(q);
        if (p < 0)
          ps.fail(w + "." + it.key(), "node type " + ns.type->desc.name + " has no such input");
        if (!it.value().is_string()) ps.fail(w + "." + it.key(), "expected \"node[.output]\"");
        ns.inputs[p] =
            parseLink(ps, it.value().get<std::string>(), w + "." + it.key(), index, nodes);
      }
    }
    for (size_t q = 0; q < ports.size(); ++q)
      if (!ports[q].optional && ns.inputs[q].node < 0)
        ps.fail(w + "." + ports[q].name, "required input is not linked");
  }
}

/// The nodes in topological order (Kahn's, the smallest file index first among the ready ones,
/// so the order is stable), their links renumbered; a cycle fails.
std::vector<NodeSpec> sortTopologically(const Parser& ps, const std::vector<NodeSpec>& nodes) {
  const int N = int(nodes.size());
  std::vector<int> indeg(N, 0), order;
  std::vector<std::vector<int>> users(N);
  for (int i = 0; i < N; ++i)
    for (const auto& l : nodes[i].inputs)
      if (l.node >= 0) ++indeg[i], users[l.node].push_back(i);
  std::vector<int> ready;
  for (int i = N - 1; i >= 0; --i)
    if (!indeg[i]) ready.push_back(i);
  while (!ready.empty()) {
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
  std::vector<NodeSpec> sorted;
  for (int k = 0; k < N; ++k) {
    NodeSpec ns = nodes[order[k]];
    for (auto& l : ns.inputs)
      if (l.node >= 0) l.node = newIndex[l.node];
    sorted.push_back(std::move(ns));
  }
  return sorted;
}

/// Each port's channel count (sorted nodes): a port of 0 channels takes the widest linked
/// input's, at least 1; a 1-channel link may feed a 3-channel port, nothing else may differ.
void resolveChannels(const Parser& ps, std::vector<NodeSpec>& nodes) {
  for (auto& ns : nodes) {
    const auto& d = ns.type->desc;
    int work = 1;
    for (size_t p = 0; p < d.inputs.size(); ++p)
      if (d.inputs[p].channels == 0 && ns.inputs[p].node >= 0)
        work = std::max(work, nodes[ns.inputs[p].node].outChannels[ns.inputs[p].port]);
    ns.inChannels.clear();
    for (size_t p = 0; p < d.inputs.size(); ++p) {
      const int want = d.inputs[p].channels == 0 ? work : d.inputs[p].channels;
      ns.inChannels.push_back(want);
      if (ns.inputs[p].node >= 0) {
        const int have = nodes[ns.inputs[p].node].outChannels[ns.inputs[p].port];
        if (have != want && !(have == 1 && want == 3))
          ps.fail("nodes." + ns.id + ".inputs." + d.inputs[p].name,
                  "expected a " + std::to_string(want) + "-channel image, the link gives " +
                      std::to_string(have) + " channels");
      }
    }
    ns.outChannels.clear();
    for (const auto& o : d.outputs) ns.outChannels.push_back(o.channels == 0 ? work : o.channels);
  }
}

/// The file's `outputs`: each map linked to a node output of the right channel count; albedo,
/// normal and roughness are required.
void readOutputs(const Parser& ps, const json& j, const std::map<std::string, int>& index,
                 GraphSpec& spec) {
  if (!j.contains("outputs") || !j["outputs"].is_object())
    ps.fail("outputs", "expected an object {albedo, normal, roughness[, metallic, height]}");
  for (auto it = j["outputs"].begin(); it != j["outputs"].end(); ++it) {
    int k = -1;
    for (int q = 0; q < kMapKindCount; ++q)
      if (it.key() == mapKindName(MapKind(q))) k = q;
    const std::string w = "outputs." + it.key();
    if (k < 0) ps.fail(w, "expected one of albedo, normal, roughness, metallic, height");
    if (!it.value().is_string()) ps.fail(w, "expected \"node[.output]\"");
    LinkRef l = parseLink(ps, it.value().get<std::string>(), w, index, spec.nodes);
    const int ch = spec.nodes[l.node].outChannels[l.port];
    if (k == int(MapKind::Normal) && ch != 3) ps.fail(w, "expected a 3-channel (normal) output");
    if (k >= int(MapKind::Roughness) && ch != 1) ps.fail(w, "expected a 1-channel output");
    spec.outputs[k] = l;
  }
  for (int k = 0; k < 3; ++k)
    if (spec.outputs[k].node < 0)
      ps.fail(std::string("outputs.") + mapKindName(MapKind(k)), "this output is required");
}

/// One exposed parameter (`jp`, at `w`): its targets "node.param" bound (every one of the first
/// one's kind and dimension; a continuous one marks its node parameter differentiable), its kind,
/// range and default from the first target's node parameter, narrowed by the file's min, max and
/// default. Returns the bindings; `gp` gets the rest (not its offset).
std::vector<Binding> readParameter(const Parser& ps, const json& jp, const std::string& w,
                                   const std::map<std::string, int>& index, GraphSpec& spec,
                                   GraphParameter& gp) {
  if (!jp.contains("targets") || !jp["targets"].is_array() || jp["targets"].empty())
    ps.fail(w + ".targets", "expected a non-empty array of \"node.param\"");
  std::vector<Binding> binds;
  const GraphParameter* first = nullptr;
  for (size_t t = 0; t < jp["targets"].size(); ++t) {
    const std::string tw = w + ".targets[" + std::to_string(t) + "]";
    const json& jt = jp["targets"][t];
    if (!jt.is_string()) ps.fail(tw, "expected \"node.param\"");
    const std::string s = jt.get<std::string>();
    const auto dot = s.find('.');
    if (dot == std::string::npos) ps.fail(tw, "expected \"node.param\", got \"" + s + "\"");
    auto it = index.find(s.substr(0, dot));
    if (it == index.end()) ps.fail(tw, "no node \"" + s.substr(0, dot) + "\"");
    const NodeType& nt = *spec.nodes[it->second].type;
    const int pi = nt.findParam(s.substr(dot + 1));
    if (pi < 0)
      ps.fail(tw, "node type " + nt.desc.name + " has no parameter \"" + s.substr(dot + 1) + "\"");
    const GraphParameter& np = nt.desc.params[pi];
    if (!first) {
      first = &np;
      gp.kind = np.kind;
      gp.dim = np.dim;
      gp.min = np.min;
      gp.max = np.max;
      gp.choices = np.choices;
      const auto& cst = spec.nodes[it->second].constants;
      gp.defaultValue.assign(cst.begin() + np.offset, cst.begin() + np.offset + np.dim);
    } else if (np.kind != first->kind || np.dim != first->dim || np.choices != first->choices) {
      ps.fail(tw, "all targets of a parameter must have the same kind and dimension");
    }
    binds.push_back({it->second, np.offset});
    if (np.kind == ParameterKind::Continuous) {
      NodeSpec& bn = spec.nodes[it->second];
      bn.hasDiffBinding = true;
      bn.diffParam.resize(nt.desc.params.size(), 0);
      bn.diffParam[pi] = 1;
    }
  }
  auto num = [&](const char* key, float& v) {
    if (!jp.contains(key)) return;
    if (!jp[key].is_number()) ps.fail(w + "." + key, "expected a number");
    v = jp[key].get<float>();
  };
  float lo = gp.min, hi = gp.max;
  num("min", lo);
  num("max", hi);
  if (lo < first->min - 1e-6f || hi > first->max + 1e-6f || lo > hi)
    ps.fail(w, "expected min <= max inside the node parameter's range [" +
                   std::to_string(first->min) + ", " + std::to_string(first->max) + "]");
  gp.min = lo, gp.max = hi;
  num("draw_spread", gp.drawSpread);
  if (!(gp.drawSpread >= 0.f && gp.drawSpread <= 1.f))
    ps.fail(w + ".draw_spread", "expected a number in [0, 1]");
  if (jp.contains("default")) {
    auto v = readValue(ps, jp["default"], gp, w + ".default");
    gp.defaultValue.assign(v.begin(), v.end());
  }
  for (float& v : gp.defaultValue)
    if (v < gp.min - 1e-6f || v > gp.max + 1e-6f)
      ps.fail(w + ".default", "expected the default inside [min, max]");
  return binds;
}

/// The file's exposed `parameters` (optional), laid out one after another in the value vector.
void readParameters(const Parser& ps, const json& j, const std::map<std::string, int>& index,
                    GraphSpec& spec) {
  if (!j.contains("parameters")) return;
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
    if (!seen.insert(gp.name).second)
      ps.fail(w + ".name", "duplicate parameter \"" + gp.name + "\"");
    std::vector<Binding> binds = readParameter(ps, jp[i], w, index, spec, gp);
    gp.offset = offset;
    offset += gp.dim;
    spec.params.push_back(gp);
    spec.bindings.push_back(std::move(binds));
  }
  spec.valueCount = offset;
}

/// The parameter every graph has last: albedo_offset, added to the albedo before the final clamp.
void addAlbedoOffset(GraphSpec& spec) {
  GraphParameter off;
  off.name = "albedo_offset";
  off.doc = "added to the albedo (linear RGB) before the final clamp to [0, 1]";
  off.kind = ParameterKind::Continuous;
  off.dim = 3;
  off.min = -0.5f;
  off.max = 0.5f;
  off.defaultValue = {0, 0, 0};
  off.offset = spec.valueCount;
  spec.albedoOffsetIndex = spec.valueCount;
  spec.valueCount += 3;
  spec.params.push_back(off);
  spec.bindings.push_back({});
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

  if (!j.contains("nodes") || !j["nodes"].is_array() || j["nodes"].empty())
    ps.fail("nodes", "expected a non-empty array of nodes");
  std::map<std::string, int> fileIndex;
  std::vector<NodeSpec> nodes = readNodes(ps, j["nodes"], fileIndex);
  linkInputs(ps, j["nodes"], fileIndex, nodes);
  spec->nodes = sortTopologically(ps, nodes);
  resolveChannels(ps, spec->nodes);
  std::map<std::string, int> index;  // node id -> position in the sorted nodes
  for (int k = 0; k < int(spec->nodes.size()); ++k) index[spec->nodes[k].id] = k;
  readOutputs(ps, j, index, *spec);
  readParameters(ps, j, index, *spec);
  addAlbedoOffset(*spec);
  // a node needs gradients where a continuous exposed parameter targets it or any node upstream
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
