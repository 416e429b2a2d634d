// A procedural material graph: a DAG of image nodes with named, ranged parameters, evaluated to
// tileable material maps at any power-of-two size, with a reverse-mode backward pass.
//
// Conventions of every map a graph returns (size N x N, N a power of two):
//   albedo     CV_32FC3, linear RGB (R first), in [0, 1]; the graph's albedo offset already added
//   normal     CV_32FC3, unit tangent-space vector (X, Y, Z) stored as floats in [-1, 1],
//              OpenGL convention: +X along +t_u, +Y along +t_v, Z out of the surface
//   roughness  CV_32FC1, in [0, 1] (GGX alpha = roughness^2)
//   metallic   CV_32FC1, in [0, 1] (optional output)
//   height     CV_32FC1, in [0, 1] (optional output; relative, unitless)
// Orientation: texture coordinate t = (0, 0) is the bottom-left of a map and t_v grows upwards, so
// row 0 of a cv::Mat is the TOP of the texture (t_v near 1). Pixel (x, y) covers
// t in [x/N, (x+1)/N] x [1 - (y+1)/N, 1 - y/N]. Every map is periodic with period 1 (tileable).
//
// Parameters (Mitsuba style): a graph exposes its parameters by name; optimizers read and write a
// flat float vector (values()/setValues()) whose layout is parameters()[i].offset .. + dim, and
// never touch nodes. Continuous parameters are differentiable; Integer and Choice parameters are
// discrete (their gradient is always 0). Every graph has the parameter "albedo_offset" (RGB,
// [-0.5, 0.5], default 0), added to the albedo before the final clamp to [0, 1], as the paper does.
//
// Example:
//   ps::GraphLibrary lib = ps::GraphLibrary::load();           // PHOTOSCENE_GRAPH_LIBRARY or default
//   ps::MaterialGraph g = lib.create("wood_planks");
//   g.setValues(g.randomValues(/*seed=*/7));
//   ps::MaterialMaps maps = g.evaluate(256, ps::MapSet::all());
//   ps::MaterialMaps dMaps;                                   // d loss / d map, same types
//   dMaps.albedo = 2.0f * (maps.albedo - target);
//   std::vector<float> dValues = g.backward(dMaps);            // d loss / d values()
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ps {

/// The maps a graph can output.
enum class MapKind { Albedo = 0, Normal, Roughness, Metallic, Height };
inline constexpr int kMapKindCount = 5;
/// "albedo", "normal", "roughness", "metallic", "height".
const char* mapKindName(MapKind kind);

/// A set of MapKind (bit set).
struct MapSet {
  unsigned bits = 0;
  static MapSet all() { return MapSet{0x1fu}; }
  static MapSet of(std::initializer_list<MapKind> kinds) {
    MapSet s;
    for (MapKind k : kinds) s.bits |= 1u << static_cast<int>(k);
    return s;
  }
  bool has(MapKind k) const { return (bits >> static_cast<int>(k)) & 1u; }
};

/// Material maps (see the conventions at the top of this file). An empty cv::Mat means "not
/// computed" or, for gradients, "zero".
struct MaterialMaps {
  cv::Mat albedo;     ///< CV_32FC3 linear RGB [0, 1]
  cv::Mat normal;     ///< CV_32FC3 unit tangent-space XYZ, OpenGL convention
  cv::Mat roughness;  ///< CV_32FC1 [0, 1]
  cv::Mat metallic;   ///< CV_32FC1 [0, 1]
  cv::Mat height;     ///< CV_32FC1 [0, 1]
  cv::Mat& get(MapKind k);
  const cv::Mat& get(MapKind k) const;
};

/// How a parameter varies.
enum class ParameterKind {
  Continuous,  ///< a real number in [min, max]; differentiable
  Integer,     ///< an integer in [min, max] (counts, seeds); discrete
  Choice       ///< an index into `choices` (pattern choices); discrete
};

/// One exposed parameter of a graph (or one parameter of a node type).
struct GraphParameter {
  std::string name;
  std::string doc;
  ParameterKind kind = ParameterKind::Continuous;
  int dim = 1;                        ///< 1 (scalar) or 3 (RGB color, each component in [min, max])
  float min = 0.f, max = 1.f;         ///< inclusive range of every component
  std::vector<float> defaultValue;    ///< dim values
  std::vector<std::string> choices;   ///< names of the choices (kind == Choice)
  /// How far randomValues moves this parameter from its default, relative to the draw's spread
  /// (file key `draw_spread`, [0, 1]): 0 keeps a fitting freedom (an octave's amplitude) out of
  /// the draws that stand for the graph's look; the fit's range stays [min, max].
  float drawSpread = 1.f;
  int offset = 0;                     ///< first index in the flat value vector
  bool differentiable() const { return kind == ParameterKind::Continuous; }
};

class GraphEngine;  // private

/// A material graph with its parameter values and its evaluation caches. Move-only; use clone()
/// for an independent copy (same graph and values, empty caches). Not thread-safe: use one
/// MaterialGraph per thread.
class MaterialGraph {
 public:
  /// Parses a graph file (format: modules/graph/FORMAT.md). Throws ps::InputError naming the
  /// file, the key and what was expected.
  static MaterialGraph fromFile(const std::string& path);
  /// Parses graph JSON text; `sourceName` names it in error messages.
  static MaterialGraph fromString(const std::string& json, const std::string& sourceName);

  MaterialGraph(MaterialGraph&&) noexcept;
  MaterialGraph& operator=(MaterialGraph&&) noexcept;
  ~MaterialGraph();
  MaterialGraph clone() const;

  const std::string& name() const;
  const std::string& category() const;
  const std::string& description() const;
  /// The source file (or sourceName).
  const std::string& source() const;
  /// Hash of the graph's content (structure, constants, parameter declarations), not its values.
  uint64_t contentHash() const;

  /// Exposed parameters, including "albedo_offset".
  const std::vector<GraphParameter>& parameters() const;
  /// Index into parameters() of the parameter `name`; -1 when absent.
  int findParameter(const std::string& name) const;
  /// The colour ramps: for each gradient_map node that two or more exposed RGB parameters drive,
  /// the indices into parameters() of those parameters (the ramp's colours), in parameter order.
  std::vector<std::vector<int>> colorRamps() const;
  /// Length of the flat value vector.
  int valueCount() const;
  std::vector<float> defaultValues() const;
  const std::vector<float>& values() const;
  /// Sets all values (length valueCount()); values are projected into their ranges (integers and
  /// choices rounded). Nodes whose effective parameters did not change keep their caches.
  void setValues(const std::vector<float>& values);
  /// Projects `values` into the parameter ranges (the optimizer's projection step).
  std::vector<float> projectValues(std::vector<float> values) const;
  void setParameter(const std::string& name, const std::vector<float>& value);
  std::vector<float> parameter(const std::string& name) const;
  /// 1 for every index of a continuous parameter, else 0.
  std::vector<uint8_t> differentiableMask() const;

  /// A random draw: each value = lerp(default, uniform sample in its range, spread x its
  /// drawSpread); discrete parameters take a uniform sample with probability spread x drawSpread,
  /// else their default. Colours
  /// vary around their default in Oklab: lightness x exp(+-0.35 spread shared by all colours of
  /// the draw +-0.12 spread per colour), chroma x exp(+-0.3 spread shared +-0.12 spread own), hue
  /// turned by +-0.2 spread shared +-0.08 spread own radians, so draws stay plausible materials
  /// of the graph's kind and colour ramps keep their order. The albedo offset is a gray shift in
  /// [-0.06, 0.06] * spread plus +-0.01 * spread per channel. Same seed, same values.
  std::vector<float> randomValues(uint64_t seed, float spread = 0.5f) const;

  /// True when the graph defines map `kind` (albedo, normal and roughness are always defined).
  bool hasOutput(MapKind kind) const;

  /// Evaluates the maps in `outputs` (those the graph defines) at size x size. Only the nodes the
  /// requested maps need run, and only those whose inputs or parameters changed since their last
  /// run. The returned maps share no memory with the graph.
  /// @param size a power of two in [4, 8192]
  MaterialMaps evaluate(int size, MapSet outputs = MapSet::all());

  /// Reverse-mode pass through the last evaluate(): given d loss / d map for any of the maps it
  /// returned (same type and size; empty = zero), returns d loss / d values() (0 for discrete
  /// parameters). Analytic adjoints per node, not finite differences.
  std::vector<float> backward(const MaterialMaps& dMaps);

  /// Drops all caches (the next evaluate recomputes every node).
  void clearCache();

  /// Number of node forward runs since construction (for cache tests and profiling).
  int64_t nodeRuns() const;

 private:
  MaterialGraph();
  friend class GraphLibrary;
  friend struct GraphAccess;
  std::unique_ptr<GraphEngine> engine_;
};

}  // namespace ps
