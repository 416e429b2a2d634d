#include "photoscene/select/exemplar_bank.hpp"

#include "photoscene/core/log.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/core/interrupt.hpp"
#include "photoscene/core/math.hpp"
#include "photoscene/core/parallel.hpp"
#include "photoscene/core/progress.hpp"
#include "photoscene/core/rng.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/io/files.hpp"
#include "photoscene/select/part_selection.hpp"
#include "photoscene/core/color.hpp"

namespace ps {

namespace {
constexpr char kMagic[8] = {'P', 'S', 'E', 'X', 'B', 'A', 'N', 'K'};
constexpr uint32_t kVersion = 4;

uint64_t nameHash(const std::string& s) {
  return Hasher().add(std::string_view(s)).digest();
}

/// The seed of draw `draw` of graph `name` (its values, its renderings' rotations and noise).
uint64_t drawSeed(const ExemplarBankOptions& options, const std::string& name, int draw) {
  return mix64(options.seed ^ nameHash(name)) + static_cast<uint64_t>(draw);
}

/// Box-prefiltered copy of a periodic map so that it has about `texels` texels across.
cv::Mat prefilter(const cv::Mat& map, int texels) {
  int size = map.cols;
  while (size / 2 >= texels && size > 4) size /= 2;
  if (size == map.cols) return map;
  cv::Mat out;
  cv::resize(map, out, cv::Size(size, size), 0, 0, cv::INTER_AREA);  // exact box for powers of 2
  return out;
}
}  // namespace

bool ExemplarBankOptions::IsValid(std::string* error) const {
  std::string keyError;
  if (drawsPerGraph < 1 || mapSize < 16 || (mapSize & (mapSize - 1)) || renderSize < 16 ||
      uvScales.empty() || !(spread >= 0 && spread <= 1) || !key.IsValid(&keyError)) {
    if (error)
      *error =
          "drawsPerGraph >= 1, mapSize a power of two >= 16, renderSize >= 16, uvScales non-empty, "
          "spread in [0, 1]" +
          keyError;
    return false;
  }
  const ObservationRanges& r = observation;
  if (observedPerDraw < 0 || r.width < 16 || r.height < 16 ||
      !(r.maxTiltDeg >= 0 && r.maxTiltDeg <= 75) ||
      !(r.minRepeats > 0 && r.maxRepeats >= r.minRepeats) || !(r.maxGradient >= 0) ||
      !(r.maxBlurSigma >= 0) || !(r.maxNoise >= 0) || !(shadingSigma >= 0)) {
    if (error)
      *error =
          "observedPerDraw >= 0, observation image >= 16 px, tilt in [0, 75], repeats 0 < min <= "
          "max, "
          "gradient, blur, noise and shadingSigma >= 0";
    return false;
  }
  for (float s : uvScales)
    if (!(s > 0)) {
      if (error) *error = "uvScales must be positive";
      return false;
    }
  return true;
}

uint64_t ExemplarBankOptions::hash() const {
  Hasher h;
  h.add(drawsPerGraph).add(spread).add(mapSize).add(renderSize).add(seed);
  for (float s : uvScales) h.add(s);
  const auto& d = key.descriptor;
  h.add(d.numScales)
      .add(d.numOrientations)
      .add(d.centerFrequency)
      .add(d.sigma)
      .add(d.kernelRadiusSigmas)
      .add(d.boundaryPower)
      .add(d.epsilon);
  h.add(discriminantProjection).add(statisticsWeight);
  const ObservationRanges& r = observation;
  h.add(observedPerDraw)
      .add(r.width)
      .add(r.height)
      .add(r.maxTiltDeg)
      .add(r.minRepeats)
      .add(r.maxRepeats)
      .add(r.maxGradient)
      .add(r.maxBlurSigma)
      .add(r.maxNoise)
      .add(r.oddMaskProbability)
      .add(shadingSigma);
  h.add(key.colorWeight).add(key.contrastWeight).add(key.anisotropyWeight).add(key.logFloor);
  if (key.psWeight > 0) h.add(std::string_view("ps")).add(key.psWeight);  // (absent: old hashes hold)
  h.add(structureWeight).add(structure.maxCorrelationSize).add(structure.logFloor);
  for (float v : structure.gradientSigmas) h.add(v);
  h.add(-1.0f);
  for (float v : structure.ringEdges) h.add(v);
  return h.digest();
}

int bankKeyLength(const ExemplarBankOptions& options) {
  return keyLength(options.key) + (options.statisticsWeight > 0 ? 12 : 0) +
         (options.structureWeight > 0 ? structureKeyLength(options.structure) : 0);
}

namespace {
/// Percentiles (in [0, 1]) of a vector, which is reordered.
std::vector<float> percentiles(std::vector<float>& v, std::initializer_list<double> ps) {
  std::vector<float> out;
  for (double p : ps) {
    if (v.empty()) {
      out.push_back(0.f);
      continue;
    }
    const size_t i = std::min(v.size() - 1, static_cast<size_t>(p * v.size()));
    std::nth_element(v.begin(), v.begin() + i, v.end());
    out.push_back(v[i]);
  }
  return out;
}
/// log(x / median x) percentiles (5, 25, 75, 95) of the masked luminance.
void logContrastPercentiles(const cv::Mat& image, const cv::Mat& mask, std::vector<float>& out) {
  std::vector<float> l;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      if (mask.at<uint8_t>(y, x)) {
        const cv::Vec3f c = image.at<cv::Vec3f>(y, x);
        l.push_back(std::log(std::max(1e-6f, luminance(c))));
      }
  const float med = percentiles(l, {0.5})[0];
  for (float v : percentiles(l, {0.05, 0.25, 0.75, 0.95})) out.push_back(v - med);
}
}  // namespace

namespace {
std::vector<float> describeTextureStatistics(const cv::Mat& image, const cv::Mat& mask,
                                             const ExemplarBankOptions& options) {
  std::vector<float> key = computeTextureKey(image, mask, options.key);
  if (options.statisticsWeight <= 0) return key;
  std::vector<float> st;
  logContrastPercentiles(image, mask, st);
  // 2 x 2 box filter, only where all four pixels are in the mask
  cv::Mat half, m01, cover;
  mask.convertTo(m01, CV_32F, 1.0 / 255.0);
  cv::threshold(m01, m01, 0, 1, cv::THRESH_BINARY);
  cv::resize(image, half, cv::Size(std::max(1, image.cols / 2), std::max(1, image.rows / 2)), 0, 0,
             cv::INTER_AREA);
  cv::resize(m01, cover, half.size(), 0, 0, cv::INTER_AREA);
  cv::Mat halfMask = cover > 0.99f;
  if (cv::countNonZero(halfMask) < 4) halfMask = cover > 0;
  logContrastPercentiles(half, halfMask, st);
  std::vector<float> rg, bg;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      if (mask.at<uint8_t>(y, x)) {
        const cv::Vec3f c = image.at<cv::Vec3f>(y, x);
        const float g = std::max(1e-6f, c[1]);
        rg.push_back(std::log(std::max(1e-6f, c[0]) / g));
        bg.push_back(std::log(std::max(1e-6f, c[2]) / g));
      }
  for (std::vector<float>* v : {&rg, &bg}) {
    const float med = percentiles(*v, {0.5})[0];
    for (float q : percentiles(*v, {0.1, 0.9})) st.push_back(q - med);
  }
  const float w = options.statisticsWeight / 2.0f;
  for (float v : st) key.push_back(w * v);
  return key;
}
}  // namespace

std::vector<float> describeTexture(const cv::Mat& image, const cv::Mat& mask,
                                   const ExemplarBankOptions& options) {
  std::vector<float> key = describeTextureStatistics(image, mask, options);
  if (options.structureWeight <= 0) return key;
  for (float v : computeStructureKey(image, mask, options.structure))
    key.push_back(options.structureWeight * v);
  return key;
}

cv::Mat renderCanonicalPatch(const MaterialMaps& maps, int size, float repeats, float rotationDeg,
                             const cv::Vec3f& lightColor) {
  PS_Check(!maps.albedo.empty() && !maps.normal.empty(),
           "renderCanonicalPatch needs albedo and normal maps");
  const int ss = 2 * size;
  const cv::Mat albedo = prefilter(maps.albedo, static_cast<int>(std::ceil(ss / repeats)));
  const cv::Mat normal = prefilter(maps.normal, static_cast<int>(std::ceil(ss / repeats)));
  const float th = radians(rotationDeg), c = std::cos(th), s = std::sin(th);
  // tangent frame of t on the patch (x right, y up, z towards the viewer): dP/dt_u ~ R(-th) e_x
  const Vec3f T(c, -s, 0), B(s, c, 0), N(0, 0, 1);
  const Vec3f light = Vec3f(-0.45f, 0.55f, 0.70f).normalized();
  cv::Mat big(ss, ss, CV_32FC3);
  parallelForRanges(0, ss, 16, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y) {
      cv::Vec3f* out = big.ptr<cv::Vec3f>(static_cast<int>(y));
      for (int x = 0; x < ss; ++x) {
        const float u = (x + 0.5f) / ss, v = 1.0f - (y + 0.5f) / ss;
        const float su = repeats * u, sv = repeats * v;
        const float tu = c * su - s * sv, tv = s * su + c * sv;
        const cv::Vec3f a = samplePeriodic(albedo, tu, tv);
        const cv::Vec3f nt = samplePeriodic(normal, tu, tv);
        Vec3f n = nt[0] * T + nt[1] * B + nt[2] * N;
        const float len = n.norm();
        n = len > 1e-6f ? Vec3f(n / len) : N;
        const float shade = 0.35f + 0.65f * std::max(0.0f, n.dot(light));
        out[x] =
            cv::Vec3f(a[0] * lightColor[0], a[1] * lightColor[1], a[2] * lightColor[2]) * shade;
      }
    }
  });
  cv::Mat small;
  cv::resize(big, small, cv::Size(size, size), 0, 0, cv::INTER_AREA);
  return small;
}

ExemplarBank::ExemplarBank(ExemplarBank&&) noexcept = default;
ExemplarBank& ExemplarBank::operator=(ExemplarBank&&) noexcept = default;
ExemplarBank::~ExemplarBank() = default;

ExemplarBank ExemplarBank::build(const GraphLibrary& library, const ExemplarBankOptions& options) {
  std::string why;
  PS_Check(options.IsValid(&why), why);
  Timer timer;
  ExemplarBank bank;
  bank.options_ = options;
  bank.graphNames_ = library.names();
  for (const auto& n : bank.graphNames_) bank.categories_.push_back(library.get(n).category());
  const int graphs = static_cast<int>(bank.graphNames_.size());
  const int scales = static_cast<int>(options.uvScales.size());
  const int perDraw = scales + options.observedPerDraw;
  const int perGraph = options.drawsPerGraph * perDraw;
  bank.dim_ = bankKeyLength(options);
  bank.exemplars_.resize(static_cast<size_t>(graphs) * perGraph);
  bank.keys_.assign(bank.exemplars_.size() * bank.dim_, 0.f);
  const cv::Mat fullMask(options.renderSize, options.renderSize, CV_8UC1, cv::Scalar(255));
  PartSelectionOptions query;
  // a minute or two on a laptop, once per library: say what is happening
  Progress progress("exemplar bank (" + std::to_string(bank.exemplars_.size()) + " renderings)",
                    graphs);
  parallelFor(0, graphs, [&](int64_t g) {
    MaterialGraph graph = library.create(bank.graphNames_[g]);
    for (int d = 0; d < options.drawsPerGraph; ++d) {
      // Ctrl-C stops the build within a draw (a fraction of a second; the whole build takes a
      // minute or more): the exception cancels the other graphs' tasks and nothing is saved
      checkInterrupted();
      const uint64_t seed = drawSeed(options, bank.graphNames_[g], d);
      graph.setValues(bankDrawValues(graph, options, d));
      const MaterialMaps maps =
          graph.evaluate(options.mapSize, MapSet::of({MapKind::Albedo, MapKind::Normal}));
      Rng rng(seed, 17);
      for (int i = 0; i < perDraw; ++i) {
        const size_t row = static_cast<size_t>(g) * perGraph + static_cast<size_t>(d) * perDraw + i;
        std::vector<float> key;
        if (i < scales) {
          const float rotation = rng.uniform(0.f, 360.f);
          const cv::Mat patch =
              renderCanonicalPatch(maps, options.renderSize, options.uvScales[i], rotation);
          key = describeTexture(removeSmoothShading(patch, fullMask, options.shadingSigma),
                                fullMask, options);
          bank.exemplars_[row] =
              Exemplar{static_cast<int>(g), d, options.uvScales[i], rotation, -1.f};
        } else {
          const ObservedPlaneParams p = randomObservation(options.observation, rng);
          const ObservedPlane obs = renderObservedPlane(maps, p);
          const PartTexture t = preparePartTexture(obs.image, obs.mask, obs.uv, cv::Mat(),
                                                   options.shadingSigma, query);
          key = describeTexture(t.image, t.mask, options);
          bank.exemplars_[row] =
              Exemplar{static_cast<int>(g), d, p.repeats, p.rotationDeg, p.tiltDeg};
        }
        std::copy(key.begin(), key.end(), bank.keys_.begin() + row * bank.dim_);
      }
    }
    progress.advance();
  });
  progress.finish();
  bank.countRenderingsPerDraw();
  if (options.discriminantProjection) bank.learnProjection();
  bank.index_ =
      std::make_unique<KnnIndex>(bank.keys_, bank.rows(), bank.indexDim(), options.indexType);
  bank.buildSeconds_ = timer.seconds();
  spdlog::info(
      "exemplar bank: {} graphs x {} draws x ({} scales + {} observed) = {} exemplars of {} floats "
      "in {:.1f}s",
      graphs, options.drawsPerGraph, scales, options.observedPerDraw, bank.rows(), bank.dim_,
      bank.buildSeconds_);
  return bank;
}

std::vector<float> bankDrawValues(const MaterialGraph& graph, const ExemplarBankOptions& options,
                                  int draw) {
  if (draw <= 0) return graph.defaultValues();
  return graph.randomValues(drawSeed(options, graph.name(), draw), options.spread);
}

void ExemplarBank::rebuildIndex(KnnIndexType type) {
  index_ = std::make_unique<KnnIndex>(keys_, rows(), indexDim(), type);
}

void ExemplarBank::learnProjection() {
  // Fisher LDA with graphs as classes: maximise between-graph over within-graph scatter.
  const int d = dim_, n = rows(), classes = static_cast<int>(graphNames_.size());
  Eigen::MatrixXd X(n, d);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < d; ++j) X(i, j) = keys_[static_cast<size_t>(i) * d + j];
  // standardize every entry over the bank first (folded into the projection below): the
  // shrinkage of the within-graph scatter then treats entries of different units alike
  Eigen::RowVectorXd mean = X.colwise().mean();
  Eigen::VectorXd invStd(d);
  for (int j = 0; j < d; ++j) {
    const double sd = std::sqrt((X.col(j).array() - mean(j)).square().mean());
    invStd(j) = sd > 1e-9 ? 1.0 / sd : 0.0;
    X.col(j) = (X.col(j).array() - mean(j)) * invStd(j);
  }
  mean.setZero();
  Eigen::MatrixXd classMean = Eigen::MatrixXd::Zero(classes, d);
  std::vector<int> count(classes, 0);
  for (int i = 0; i < n; ++i) {
    classMean.row(exemplars_[i].graph) += X.row(i);
    count[exemplars_[i].graph]++;
  }
  Eigen::MatrixXd Sb = Eigen::MatrixXd::Zero(d, d), Sw = Eigen::MatrixXd::Zero(d, d);
  for (int c = 0; c < classes; ++c) {
    if (!count[c]) continue;
    classMean.row(c) /= count[c];
    const Eigen::RowVectorXd dm = classMean.row(c) - mean;
    Sb += count[c] * dm.transpose() * dm;
  }
  for (int i = 0; i < n; ++i) {
    const Eigen::RowVectorXd dx = X.row(i) - classMean.row(exemplars_[i].graph);
    Sw += dx.transpose() * dx;
  }
  // shrink the within-class scatter towards its mean variance: keeps the metric well posed when a
  // direction hardly varies inside the bank
  Sw += (0.05 * Sw.trace() / d) * Eigen::MatrixXd::Identity(d, d);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(Sb, Sw);
  if (solver.info() != Eigen::Success) {
    spdlog::warn("exemplar bank: discriminant projection failed; using raw keys");
    return;
  }
  // eigenvectors satisfy W^T Sw W = I; keep them all (largest first), weighted by the square root
  // of their discriminant ratio so that directions that separate graphs count more
  const int k = d;
  projectedDim_ = k;
  projection_.assign(static_cast<size_t>(d) * k, 0.f);
  const double scaleRef = std::sqrt(static_cast<double>(n));
  for (int c = 0; c < k; ++c) {
    const int src = d - 1 - c;
    const double w = std::sqrt(std::max(0.0, solver.eigenvalues()[src])) * scaleRef;
    for (int r = 0; r < d; ++r)
      projection_[static_cast<size_t>(r) * k + c] =
          static_cast<float>(solver.eigenvectors()(r, src) * w * invStd(r));
  }
  std::vector<float> projected(static_cast<size_t>(n) * k);
  for (int i = 0; i < n; ++i) {
    const std::vector<float> raw(keys_.begin() + static_cast<size_t>(i) * d,
                                 keys_.begin() + static_cast<size_t>(i + 1) * d);
    const std::vector<float> p = project(raw);
    std::copy(p.begin(), p.end(), projected.begin() + static_cast<size_t>(i) * k);
  }
  keys_ = std::move(projected);
}

std::vector<float> ExemplarBank::project(const std::vector<float>& key) const {
  PS_CheckEQ(static_cast<int>(key.size()), dim_, "key length");
  if (projection_.empty()) return key;
  std::vector<float> out(projectedDim_, 0.f);
  for (int r = 0; r < dim_; ++r)
    for (int c = 0; c < projectedDim_; ++c)
      out[c] += key[r] * projection_[static_cast<size_t>(r) * projectedDim_ + c];
  return out;
}

std::string ExemplarBank::cacheFileName(const GraphLibrary& library,
                                        const ExemplarBankOptions& options) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "exemplars-v%u-%016llx-%016llx.bin", kVersion,
                static_cast<unsigned long long>(library.contentHash()),
                static_cast<unsigned long long>(options.hash()));
  return buf;
}

namespace {
template <typename T>
void put(std::ostream& os, const T& v) {
  os.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <typename T>
bool get(std::istream& is, T& v) {
  return static_cast<bool>(is.read(reinterpret_cast<char*>(&v), sizeof(T)));
}
void putString(std::ostream& os, const std::string& s) {
  put(os, static_cast<uint32_t>(s.size()));
  os.write(s.data(), static_cast<std::streamsize>(s.size()));
}
bool getString(std::istream& is, std::string& s) {
  uint32_t n = 0;
  if (!get(is, n) || n > (1u << 16)) return false;
  s.resize(n);
  return static_cast<bool>(is.read(s.data(), n));
}
}  // namespace

void ExemplarBank::save(const std::filesystem::path& file) const {
  // the header carries what load() checks; written whole-or-nothing
  io::writeAtomically(file, [&](const std::filesystem::path& tmp) {
    std::ofstream os(tmp, std::ios::binary);
    os.write(kMagic, 8);
    put(os, kVersion);
    put(os, libraryHash_);
    put(os, optionsHash_);
    put(os, static_cast<uint32_t>(graphNames_.size()));
    for (size_t i = 0; i < graphNames_.size(); ++i) {
      putString(os, graphNames_[i]);
      putString(os, categories_[i]);
    }
    put(os, static_cast<uint32_t>(rows()));
    put(os, static_cast<uint32_t>(dim_));
    for (const Exemplar& e : exemplars_) {
      put(os, e.graph);
      put(os, e.draw);
      put(os, e.uvScale);
      put(os, e.rotationDeg);
      put(os, e.tiltDeg);
    }
    put(os, static_cast<uint32_t>(indexDim()));
    os.write(reinterpret_cast<const char*>(keys_.data()),
             static_cast<std::streamsize>(keys_.size() * sizeof(float)));
    put(os, static_cast<uint32_t>(projectedDim_));
    os.write(reinterpret_cast<const char*>(projection_.data()),
             static_cast<std::streamsize>(projection_.size() * sizeof(float)));
    put(os, buildSeconds_);
    PS_Check(os.good(), "cannot write the exemplar bank " << file);
  });
  io::writeAtomically(std::filesystem::path(file.string() + ".flann"),
                      [&](const std::filesystem::path& tmp) { index_->save(tmp.string()); });
}

ExemplarBank ExemplarBank::load(const std::filesystem::path& file, uint64_t libraryHash,
                                const ExemplarBankOptions& options) {
  ExemplarBank bank;
  std::ifstream is(file, std::ios::binary);
  if (!is) return bank;
  char magic[8];
  uint32_t version = 0, graphs = 0, rows = 0, dim = 0;
  uint64_t lh = 0, oh = 0;
  if (!is.read(magic, 8) || std::memcmp(magic, kMagic, 8) != 0 || !get(is, version) ||
      version != kVersion || !get(is, lh) || lh != libraryHash || !get(is, oh) ||
      oh != options.hash() || !get(is, graphs))
    return bank;
  std::vector<std::string> names(graphs), cats(graphs);
  for (uint32_t i = 0; i < graphs; ++i)
    if (!getString(is, names[i]) || !getString(is, cats[i])) return bank;
  if (!get(is, rows) || !get(is, dim) || dim != static_cast<uint32_t>(bankKeyLength(options)) ||
      rows > (1u << 24))
    return bank;
  std::vector<Exemplar> ex(rows);
  for (auto& e : ex)
    if (!get(is, e.graph) || !get(is, e.draw) || !get(is, e.uvScale) || !get(is, e.rotationDeg) ||
        !get(is, e.tiltDeg) || e.graph < 0 || e.graph >= static_cast<int>(graphs))
      return bank;
  uint32_t indexDim = 0, projectedDim = 0;
  if (!get(is, indexDim) || indexDim == 0 || indexDim > 4096) return bank;
  std::vector<float> keys(static_cast<size_t>(rows) * indexDim);
  if (!is.read(reinterpret_cast<char*>(keys.data()),
               static_cast<std::streamsize>(keys.size() * sizeof(float))))
    return bank;
  if (!get(is, projectedDim) || projectedDim > 4096) return bank;
  std::vector<float> projection(static_cast<size_t>(dim) * projectedDim);
  if (!is.read(reinterpret_cast<char*>(projection.data()),
               static_cast<std::streamsize>(projection.size() * sizeof(float))))
    return bank;
  if ((projectedDim ? projectedDim : dim) != indexDim) return bank;
  double seconds = 0;
  get(is, seconds);
  bank.graphNames_ = std::move(names);
  bank.categories_ = std::move(cats);
  bank.exemplars_ = std::move(ex);
  bank.keys_ = std::move(keys);
  bank.dim_ = static_cast<int>(dim);
  bank.projection_ = std::move(projection);
  bank.projectedDim_ = static_cast<int>(projectedDim);
  bank.buildSeconds_ = seconds;
  bank.countRenderingsPerDraw();
  bank.libraryHash_ = libraryHash;
  bank.optionsHash_ = options.hash();
  bank.options_ = options;
  const std::filesystem::path indexFile(file.string() + ".flann");
  std::error_code ec;
  if (std::filesystem::exists(indexFile, ec)) {
    try {
      bank.index_ = std::make_unique<KnnIndex>(KnnIndex::load(
          indexFile.string(), bank.keys_, bank.rows(), bank.indexDim(), options.indexType));
    } catch (const std::exception& e) {
      spdlog::warn("exemplar bank index {} unreadable ({}); rebuilding it", indexFile.string(),
                   e.what());
    }
  }
  if (!bank.index_)
    bank.index_ =
        std::make_unique<KnnIndex>(bank.keys_, bank.rows(), bank.indexDim(), options.indexType);
  return bank;
}

ExemplarBank ExemplarBank::loadOrBuild(const GraphLibrary& library,
                                       const ExemplarBankOptions& options,
                                       const std::filesystem::path& cacheFolder,
                                       bool* loadedFromCache) {
  const std::filesystem::path file = cacheFolder / cacheFileName(library, options);
  Timer timer;
  ExemplarBank bank = load(file, library.contentHash(), options);
  if (bank.rows() > 0) {
    if (loadedFromCache) *loadedFromCache = true;
    spdlog::info("exemplar bank: loaded {} exemplars from {} in {:.1f} ms", bank.rows(),
                 file.string(), timer.milliseconds());
    return bank;
  }
  // One builder per cache file: processes sharing the cache (parallel runs, the test suite) wait
  // on an advisory lock and then load what the first one built. The lock goes with the process.
  std::filesystem::create_directories(cacheFolder);
  const std::filesystem::path lockPath = file.string() + ".lock";
  const int lock = ::open(lockPath.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock >= 0) {
    while (::flock(lock, LOCK_EX) != 0 && errno == EINTR) {
    }
    bank = load(file, library.contentHash(), options);
    if (bank.rows() > 0) {
      ::close(lock);
      if (loadedFromCache) *loadedFromCache = true;
      spdlog::info(
          "exemplar bank: loaded {} exemplars from {} (built by another process) in {:.1f} ms",
          bank.rows(), file.string(), timer.milliseconds());
      return bank;
    }
  }
  if (loadedFromCache) *loadedFromCache = false;
  spdlog::info(
      "exemplar bank: none cached for this library in {}: building it (once; later runs "
      "load it in milliseconds)",
      cacheFolder.string());
  try {
    bank = build(library, options);
    bank.libraryHash_ = library.contentHash();
    bank.optionsHash_ = options.hash();
    bank.save(file);
  } catch (...) {
    if (lock >= 0) ::close(lock);
    throw;
  }
  if (lock >= 0) ::close(lock);
  return bank;
}

void ExemplarBank::countRenderingsPerDraw() {
  std::map<std::pair<int, int>, int> count;
  maxRenderingsPerDraw_ = 1;
  for (const Exemplar& e : exemplars_)
    maxRenderingsPerDraw_ = std::max(maxRenderingsPerDraw_, ++count[{e.graph, e.draw}]);
}

GraphChoice ExemplarBank::select(const std::vector<float>& key, int k, bool categoryFirst,
                                 bool distinctDraws) const {
  PS_Check(k >= 1, "select: k must be >= 1, got " << k);
  KnnResult r;
  if (!distinctDraws || maxRenderingsPerDraw_ <= 1) {
    r = index_->search(project(key), k);
  } else {
    // k * renderings rows always hold at least k distinct draws; a draw's first row in distance
    // order is its nearest rendering, so the first k distinct draws are the k nearest draws
    const KnnResult all = index_->search(project(key), k * maxRenderingsPerDraw_);
    std::vector<std::pair<int, int>> seen;
    for (size_t i = 0; i < all.index.size() && static_cast<int>(r.index.size()) < k; ++i) {
      const Exemplar& e = exemplars_[all.index[i]];
      const std::pair<int, int> id{e.graph, e.draw};
      if (std::find(seen.begin(), seen.end(), id) != seen.end()) continue;
      seen.push_back(id);
      r.index.push_back(all.index[i]);
      r.distance.push_back(all.distance[i]);
    }
  }
  return vote(r, categoryFirst);
}

GraphChoice ExemplarBank::selectInCategory(const std::vector<float>& key, int k,
                                           const std::string& category) const {
  PS_Check(k >= 1, "selectInCategory: k must be >= 1, got " << k);
  PS_Check(std::find(categories_.begin(), categories_.end(), category) != categories_.end(),
           "selectInCategory: no graph of the bank has the category '" << category << "'");
  const std::vector<float> q = project(key);
  const int d = indexDim();
  std::vector<std::pair<float, int>> near;  // (distance, row) of the category's rows
  for (int row = 0; row < rows(); ++row) {
    if (categories_[exemplars_[row].graph] != category) continue;
    const float* x = &keys_[static_cast<size_t>(row) * d];
    double d2 = 0;
    for (int c = 0; c < d; ++c) d2 += (x[c] - q[c]) * (x[c] - q[c]);
    near.emplace_back(static_cast<float>(std::sqrt(d2)), row);
  }
  // all of them in order (a category's rows are a few thousand; the graphs no neighbour votes
  // for are listed below by their nearest row)
  std::sort(near.begin(), near.end());
  const size_t n = std::min(near.size(), static_cast<size_t>(k));
  KnnResult r;
  for (size_t i = 0; i < n; ++i) {
    r.index.push_back(near[i].second);
    r.distance.push_back(near[i].first);
  }
  GraphChoice choice = vote(r, false);
  // then the category's graphs no neighbour voted for, by their nearest row (weight 0): the
  // finalists are the list's first graphs, and a vote that one graph's draws fill (a plain wall
  // near one low-contrast concrete) would leave a single finalist of the category to weigh
  std::set<int> listed;
  for (const int row : r.index) listed.insert(exemplars_[row].graph);
  for (const auto& [dist, row] : near) {  // nearest first: a graph's first row is its nearest
    const int g = exemplars_[row].graph;
    if (!listed.insert(g).second) continue;
    GraphVote v;
    v.graph = graphNames_[g];
    v.category = categories_[g];
    v.nearestDraw = exemplars_[row].draw;
    choice.votes.push_back(v);
  }
  return choice;
}

GraphChoice ExemplarBank::vote(const KnnResult& r, bool categoryFirst) const {
  GraphChoice choice;
  std::map<int, GraphVote> votes;
  std::map<std::string, GraphVote> catVotes;
  for (size_t i = 0; i < r.index.size(); ++i) {
    const Exemplar& e = exemplars_[r.index[i]];
    const double w = 1.0 / (r.distance[i] + 1e-6);
    GraphVote& v = votes[e.graph];
    if (v.count == 0) v.nearestDraw = e.draw;  // rows come nearest first
    v.graph = graphNames_[e.graph];
    v.category = categories_[e.graph];
    v.weight += w;
    v.count++;
    GraphVote& c = catVotes[categories_[e.graph]];
    c.category = categories_[e.graph];
    c.weight += w;
    c.count++;
  }
  for (auto& [g, v] : votes) choice.votes.push_back(v);
  for (auto& [g, v] : catVotes) choice.categoryVotes.push_back(v);
  auto byWeight = [](const GraphVote& a, const GraphVote& b) {
    return a.weight != b.weight ? a.weight > b.weight : a.graph < b.graph;
  };
  std::sort(choice.votes.begin(), choice.votes.end(), byWeight);
  std::sort(choice.categoryVotes.begin(), choice.categoryVotes.end(), byWeight);
  if (!choice.votes.empty()) {
    choice.graph = choice.votes[0].graph;
    choice.category = choice.votes[0].category;
    if (categoryFirst) {
      const std::string& best = choice.categoryVotes[0].category;
      for (const GraphVote& v : choice.votes)
        if (v.category == best) {
          choice.graph = v.graph;
          choice.category = v.category;
          break;
        }
    }
  }
  choice.neighbours = r.index;
  choice.distances = r.distance;
  return choice;
}

int homogeneousThreshold(int imageWidth, int imageHeight, int pixelsAt320x240) {
  return static_cast<int>(std::lround(
      pixelsAt320x240 * (static_cast<double>(imageWidth) * imageHeight) / (320.0 * 240.0)));
}

int interiorPixels(const cv::Mat& mask, int radiusAt320) {
  if (mask.empty()) return 0;
  const int r = std::max(1, static_cast<int>(std::lround(radiusAt320 * mask.cols / 320.0)));
  cv::Mat inside;
  cv::erode(mask, inside, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 2 * r + 1)),
            cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  return cv::countNonZero(inside);
}

bool isSmallPart(const cv::Mat& mask, int imageWidth, int imageHeight) {
  return interiorPixels(mask) < homogeneousThreshold(imageWidth, imageHeight);
}

}  // namespace ps
