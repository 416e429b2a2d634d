#include "photoscene/pipeline/batch.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "photoscene/core/error.hpp"
#include "photoscene/io/files.hpp"
#include "photoscene/io/json.hpp"
#include "photoscene/report/report.hpp"

extern char** environ;

namespace ps::batch {

namespace {

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r\n");
  return s.substr(a, b - a + 1);
}

const std::set<std::string> kPresets = {"fast", "balanced", "paper"};
const std::set<std::string> kBaselines = {"none", "pixel-median", "shading-median"};

// A name is one plain folder name: ROOT/<name> must not escape ROOT or hide as a dot folder.
void checkName(const std::string& name, const std::string& file, const std::string& where) {
  const bool ok = !name.empty() && name.size() <= 200 && name[0] != '.' &&
                  std::all_of(name.begin(), name.end(), [](unsigned char c) {
                    return std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '+';
                  });
  if (!ok)
    throw InputError(file, where,
                     fmt::format("expected a scene name of letters, digits, '-', '_', '.', '+' "
                                 "(not starting with '.'), got \"{}\"",
                                 name));
}

std::string defaultName(const fs::path& scene) {
  const std::string n = scene.parent_path().filename().string();
  return n.empty() ? scene.stem().string() : n;
}

RunOptions readOptions(const nlohmann::json& j, const std::string& file, const std::string& where) {
  RunOptions o;
  if (!j.is_object()) throw InputError(file, where, "expected an object");
  for (const auto& [key, v] : j.items()) {
    const std::string at = where + "." + key;
    if (key == "preset") {
      if (!v.is_string() || !kPresets.count(v.get<std::string>()))
        throw InputError(file, at, "expected \"fast\", \"balanced\" or \"paper\", got " + v.dump());
      o.preset = v.get<std::string>();
    } else if (key == "texture_size") {
      if (!v.is_number_integer() || v.get<int64_t>() < 4 || v.get<int64_t>() > 16384)
        throw InputError(file, at, "expected an integer from 4 to 16384, got " + v.dump());
      o.textureSize = v.get<int>();
    } else if (key == "baseline") {
      if (!v.is_string() || !kBaselines.count(v.get<std::string>()))
        throw InputError(
            file, at, "expected \"none\", \"pixel-median\" or \"shading-median\", got " + v.dump());
      o.baseline = v.get<std::string>();
    } else {
      throw InputError(file, at, "unknown key (expected preset, texture_size or baseline)");
    }
  }
  return o;
}

std::vector<SceneEntry> readJsonManifest(const fs::path& manifest, const std::string& text) {
  const std::string file = manifest.string();
  const nlohmann::json root = io::parseJson(text, file);
  if (!root.is_object())
    throw InputError(file, "", "expected a JSON object {\"version\": 1, \"scenes\": [...]}");
  for (const auto& [key, v] : root.items())
    if (key != "version" && key != "scenes")
      throw InputError(file, key, "unknown key (expected version and scenes)");
  if (!root.contains("version") || root["version"] != 1)
    throw InputError(
        file, "version",
        "expected 1, got " + (root.contains("version") ? root["version"].dump() : "nothing"));
  if (!root.contains("scenes") || !root["scenes"].is_array() || root["scenes"].empty())
    throw InputError(file, "scenes", "expected a non-empty array of {\"scene\": PATH, ...}");
  std::vector<SceneEntry> out;
  const nlohmann::json& scenes = root["scenes"];
  for (size_t i = 0; i < scenes.size(); ++i) {
    const std::string where = fmt::format("scenes[{}]", i);
    const nlohmann::json& s = scenes[i];
    if (!s.is_object())
      throw InputError(file, where,
                       "expected an object {\"scene\": PATH, \"name\": NAME, \"options\": {...}}");
    SceneEntry e;
    e.where = where;
    for (const auto& [key, v] : s.items()) {
      if (key == "scene") {
        if (!v.is_string() || v.get<std::string>().empty())
          throw InputError(file, where + ".scene",
                           "expected a path to a scene.json, got " + v.dump());
        e.scene = v.get<std::string>();
      } else if (key == "name") {
        if (!v.is_string())
          throw InputError(file, where + ".name", "expected a string, got " + v.dump());
        e.name = v.get<std::string>();
        checkName(e.name, file, where + ".name");
      } else if (key == "options") {
        e.options = readOptions(v, file, where + ".options");
      } else {
        throw InputError(file, where + "." + key, "unknown key (expected scene, name or options)");
      }
    }
    if (e.scene.empty())
      throw InputError(file, where + ".scene", "expected a path to a scene.json (missing)");
    out.push_back(std::move(e));
  }
  return out;
}

std::vector<SceneEntry> readTextManifest(const std::string& text) {
  std::vector<SceneEntry> out;
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    line = trim(line);
    if (line.empty()) continue;
    SceneEntry e;
    e.scene = line;
    e.where = fmt::format("line {}", n);
    out.push_back(std::move(e));
  }
  return out;
}

// UTC with milliseconds: "2026-11-24T06:41:05.123Z" (sorts as text)
std::string nowIso() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%S", &tm);
  return fmt::format("{}.{:03d}Z", buf, static_cast<int>(ms));
}

std::string hostName() {
  char buf[256] = {0};
  if (gethostname(buf, sizeof(buf) - 1) != 0) return "";
  return buf;
}

nlohmann::json optionsJson(const RunOptions& o) {
  nlohmann::json j = nlohmann::json::object();
  if (o.preset) j["preset"] = *o.preset;
  if (o.textureSize) j["texture_size"] = *o.textureSize;
  if (o.baseline) j["baseline"] = *o.baseline;
  return j;
}

std::string joinCommand(const std::vector<std::string>& args) {
  std::string s;
  for (const std::string& a : args) {
    if (!s.empty()) s += ' ';
    s += a;
  }
  return s;
}

// --- signals: a flag, and the children to forward them to ---------------------------------

constexpr int kMaxChildren = 256;
std::atomic<int> g_signal{0};
std::atomic<bool> g_forward{true};
std::atomic<pid_t> g_children[kMaxChildren];

extern "C" void onBatchSignal(int sig) {
  int none = 0;
  g_signal.compare_exchange_strong(none, sig);
  if (!g_forward.load()) return;
  for (auto& c : g_children)
    if (const pid_t p = c.load(); p > 0) kill(p, sig);
}

// Installs the handlers for its scope (nested scopes share the outer one).
class SignalScope {
 public:
  explicit SignalScope(bool forward) {
    if (depth_++ > 0) return;
    g_signal.store(0);
    g_forward.store(forward);
    struct sigaction sa {};
    sa.sa_handler = onBatchSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &oldInt_);
    sigaction(SIGTERM, &sa, &oldTerm_);
  }
  ~SignalScope() {
    if (--depth_ > 0) return;
    sigaction(SIGINT, &oldInt_, nullptr);
    sigaction(SIGTERM, &oldTerm_, nullptr);
  }
  SignalScope(const SignalScope&) = delete;
  SignalScope& operator=(const SignalScope&) = delete;

 private:
  static inline int depth_ = 0;
  static inline struct sigaction oldInt_, oldTerm_;
};

int registerChild(pid_t pid) {
  for (int k = 0; k < kMaxChildren; ++k) {
    pid_t none = 0;
    if (g_children[k].compare_exchange_strong(none, pid)) return k;
  }
  return -1;
}

// The last "[error]" / "[critical]" line written from `offset` on, without the logger's prefix.
std::string lastErrorLine(const fs::path& log, std::streamoff offset) {
  std::ifstream in(log, std::ios::binary);
  if (!in) return "";
  in.seekg(offset);
  std::string line, last;
  while (std::getline(in, line)) {
    line = trim(line);
    for (const char* tag : {"[error] ", "[critical] "})
      if (const size_t at = line.find(tag); at != std::string::npos)
        last = line.substr(at + std::strlen(tag));
  }
  return last.size() > 2000 ? last.substr(0, 2000) + "..." : last;
}

double number(const nlohmann::json& j) {
  return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

// Mean of `key` (srgb255) over an array of scored images; NaN when none.
double meanMetric(const nlohmann::json& arr, const char* key) {
  if (!arr.is_array()) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0;
  int n = 0;
  for (const auto& e : arr)
    if (e.contains("srgb255") && e["srgb255"].contains(key)) {
      const double v = number(e["srgb255"][key]);
      if (std::isfinite(v)) {
        sum += v;
        ++n;
      }
    }
  return n ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return q + "\"";
}

std::string csvNumber(double v) {
  return std::isfinite(v) ? fmt::format("{:.6g}", v) : "";
}


// The pipeline's stage order (pipeline.hpp); stages it does not list follow alphabetically.
const std::vector<std::string> kStageOrder = {"geometry", "align",  "lights0", "incident0",
                                              "select",   "fit",    "lights1", "incident1",
                                              "refine",   "bounce", "export", "metrics",
                                              "report"};

}  // namespace

// --- manifest ----------------------------------------------------------------------------------

std::vector<SceneEntry> readManifest(const fs::path& manifest) {
  const std::string text = io::readTextFile(manifest);
  const fs::path base = fs::absolute(manifest).parent_path();
  const std::string first = trim(text).substr(0, 1);
  std::vector<SceneEntry> scenes =
      first == "{" ? readJsonManifest(manifest, text) : readTextManifest(text);
  if (scenes.empty())
    throw InputError(manifest.string(), "",
                     "expected at least one scene.json path (one per line, '#' comments)");
  std::map<std::string, std::string> used;  // name -> where
  for (SceneEntry& e : scenes) {
    e.scene = (base / e.scene).lexically_normal();
    const bool named = !e.name.empty();
    if (!named) {
      e.name = defaultName(e.scene);
      checkName(e.name, manifest.string(), e.where);
    }
    if (auto [it, fresh] = used.emplace(e.name, e.where); !fresh)
      throw InputError(
          manifest.string(), e.where + (named ? ".name" : ""),
          fmt::format("expected a unique scene name: \"{}\" is already the name of {}{}", e.name,
                      it->second, first == "{" ? "" : " (use a JSON manifest to name scenes)"));
  }
  return scenes;
}

// --- batch.json --------------------------------------------------------------------------------

void writeBatchFile(const Batch& b) {
  fs::create_directories(b.root / ".batch");
  nlohmann::json scenes = nlohmann::json::array();
  for (const SceneEntry& e : b.scenes)
    scenes.push_back({{"scene", e.scene.string()},
                      {"name", e.name},
                      {"options", optionsJson(e.options)},
                      {"where", e.where}});
  const nlohmann::json j = {{"version", 1},
                            {"manifest", b.manifest.string()},
                            {"options", optionsJson(b.options)},
                            {"scenes", scenes}};
  const fs::path file = b.root / ".batch" / "batch.json";
  // every task of an array writes it: skip the write when it is already the same
  std::error_code ec;
  if (fs::exists(file, ec)) {
    try {
      if (io::readJsonFile(file) == j) return;
    } catch (const std::exception&) {
    }
  }
  io::writeJsonFile(file, j);
}

Batch readBatchFile(const fs::path& root) {
  const fs::path file = root / ".batch" / "batch.json";
  if (!fs::exists(file))
    throw InputError(root.string(), "",
                     "expected a batch output root (" + file.string() + " not found)");
  const nlohmann::json j = io::readJsonFile(file);
  Batch b;
  b.root = fs::absolute(root).lexically_normal();
  try {
    b.manifest = j.at("manifest").get<std::string>();
    b.options = readOptions(j.at("options"), file.string(), "options");
    for (const auto& s : j.at("scenes")) {
      SceneEntry e;
      e.scene = s.at("scene").get<std::string>();
      e.name = s.at("name").get<std::string>();
      e.where = s.value("where", "");
      e.options = readOptions(s.at("options"), file.string(), "scenes.options");
      b.scenes.push_back(std::move(e));
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string(), "", std::string("expected a batch description: ") + e.what());
  }
  return b;
}

// --- records -----------------------------------------------------------------------------------

const char* statusName(Status s) {
  switch (s) {
    case Status::Pending:
      return "pending";
    case Status::Running:
      return "running";
    case Status::Done:
      return "done";
    case Status::Failed:
      return "failed";
    case Status::BadInput:
      return "bad-input";
  }
  return "?";
}

fs::path statusFile(const fs::path& root, const std::string& name) {
  return root / ".batch" / "status" / (name + ".json");
}
fs::path logFile(const fs::path& root, const std::string& name) {
  return root / ".batch" / "logs" / (name + ".log");
}

SceneRecord readRecord(const fs::path& root, const std::string& name) {
  SceneRecord r;
  r.name = name;
  const fs::path file = statusFile(root, name);
  std::error_code ec;
  if (!fs::exists(file, ec)) return r;
  try {
    const nlohmann::json j = io::readJsonFile(file);
    const std::string s = j.value("status", "pending");
    for (Status st :
         {Status::Pending, Status::Running, Status::Done, Status::Failed, Status::BadInput})
      if (s == statusName(st)) r.status = st;
    if (j.contains("exit_code") && j["exit_code"].is_number_integer())
      r.exitCode = j["exit_code"].get<int>();
    r.error = j.value("error", "");
    r.started = j.value("started", "");
    r.finished = j.value("finished", "");
    r.seconds = j.value("seconds", 0.0);
    r.host = j.value("host", "");
    r.pid = j.value("pid", 0L);
    r.command = j.value("command", "");
    r.attempts = j.value("attempts", 0);
  } catch (const std::exception& e) {
    r.status = Status::Pending;
    r.error = std::string("status record unreadable: ") + e.what();
    return r;
  }
  if (r.status == Status::Running && r.pid > 0 && r.host == hostName() &&
      kill(static_cast<pid_t>(r.pid), 0) != 0 && errno == ESRCH) {
    r.status = Status::Pending;
    r.error = fmt::format(
        "its task (pid {} on {}) ended without recording an outcome (killed?); a rerun resumes it",
        r.pid, r.host);
  }
  return r;
}

void writeRecord(const fs::path& root, const SceneRecord& r) {
  fs::create_directories(statusFile(root, r.name).parent_path());
  nlohmann::json j = {
      {"name", r.name},
      {"status", statusName(r.status)},
      {"exit_code", r.exitCode ? nlohmann::json(*r.exitCode) : nlohmann::json(nullptr)},
      {"error", r.error},
      {"started", r.started},
      {"finished", r.finished},
      {"seconds", std::round(r.seconds * 100) / 100},
      {"host", r.host},
      {"pid", r.pid},
      {"command", r.command},
      {"attempts", r.attempts}};
  io::writeJsonFile(statusFile(root, r.name), j);
}

std::vector<SceneRecord> readRecords(const Batch& b) {
  std::vector<SceneRecord> out;
  for (const SceneEntry& e : b.scenes) out.push_back(readRecord(b.root, e.name));
  return out;
}

int exitStatus(const std::vector<SceneRecord>& records) {
  bool bad = false;
  for (const SceneRecord& r : records) {
    if (r.status == Status::BadInput)
      bad = true;
    else if (r.status != Status::Done)
      return 1;
  }
  return bad ? 2 : 0;
}

// --- one scene ---------------------------------------------------------------------------------

RunOptions sceneOptions(const Batch& b, size_t i) {
  RunOptions o = b.options;
  const RunOptions& own = b.scenes.at(i).options;
  if (own.preset) o.preset = own.preset;
  if (own.textureSize) o.textureSize = own.textureSize;
  if (own.baseline) o.baseline = own.baseline;
  return o;
}

std::vector<std::string> runArguments(const Batch& b, size_t i, int threads) {
  const SceneEntry& e = b.scenes.at(i);
  const RunOptions o = sceneOptions(b, i);
  std::vector<std::string> a = {"run", e.scene.string(), "-o", (b.root / e.name).string()};
  if (o.preset) a.insert(a.end(), {"--preset", *o.preset});
  if (o.textureSize) a.insert(a.end(), {"--texture-size", std::to_string(*o.textureSize)});
  if (o.baseline) a.insert(a.end(), {"--baseline", *o.baseline});
  if (threads > 0) a.insert(a.end(), {"--threads", std::to_string(threads)});
  return a;
}

bool isFinished(const Batch& b, size_t i) {
  const SceneRecord r = readRecord(b.root, b.scenes.at(i).name);
  std::error_code ec;
  return r.status == Status::Done && r.command == joinCommand(runArguments(b, i, 0)) &&
         fs::exists(b.root / b.scenes[i].name / "metrics.json", ec);
}

SceneRecord runScene(const Batch& b, size_t i, int threads, const fs::path& executable,
                     bool forwardSignals) {
  SignalScope signals(forwardSignals);
  const SceneEntry& e = b.scenes.at(i);
  SceneRecord r = readRecord(b.root, e.name);
  r.name = e.name;
  r.status = Status::Running;
  r.exitCode.reset();
  r.error.clear();
  r.started = nowIso();
  r.finished.clear();
  r.seconds = 0;
  r.host = hostName();
  r.pid = getpid();
  r.command = joinCommand(runArguments(b, i, 0));
  r.attempts += 1;
  writeRecord(b.root, r);

  const fs::path log = logFile(b.root, e.name);
  fs::create_directories(log.parent_path());
  std::error_code ec;
  const std::streamoff offset =
      fs::exists(log, ec) ? static_cast<std::streamoff>(fs::file_size(log, ec)) : 0;
  const std::vector<std::string> args = runArguments(b, i, threads);
  {
    std::ofstream(log, std::ios::app)
        << fmt::format("=== photoscene batch: {} attempt {} on {} at {}\n=== {} {}\n", e.name,
                       r.attempts, r.host, r.started, executable.string(), joinCommand(args));
  }

  std::vector<std::string> argvStore;
  argvStore.push_back(executable.string());
  argvStore.insert(argvStore.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& s : argvStore) argv.push_back(s.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND,
                                   0644);
  posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t def, none;
  sigemptyset(&def);
  sigaddset(&def, SIGINT);
  sigaddset(&def, SIGTERM);
  sigemptyset(&none);
  posix_spawnattr_setsigdefault(&attr, &def);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setpgroup(&attr,
                            0);  // its own group: a terminal's Ctrl-C reaches it once, forwarded
  posix_spawnattr_setflags(&attr,
                           POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETPGROUP);

  const auto t0 = std::chrono::steady_clock::now();
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, executable.c_str(), &fa, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  int status = 0;
  if (rc != 0) {
    r.status = Status::Failed;
    r.error = fmt::format("cannot start {}: {}", executable.string(), std::strerror(rc));
  } else {
    const int slot = registerChild(pid);
    if (const int sig = g_signal.load(); sig && forwardSignals)
      kill(pid, sig);  // arrived before the slot
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (slot >= 0) g_children[slot].store(0);
    if (WIFEXITED(status)) {
      const int code = WEXITSTATUS(status);
      r.exitCode = code;
      if (code == 0) {
        r.status = Status::Done;
      } else if (code == 2) {
        r.status = Status::BadInput;
      } else if (code == 128 + SIGINT || code == 128 + SIGTERM) {
        r.status = Status::Pending;
      } else {
        r.status = Status::Failed;
      }
    } else if (WIFSIGNALED(status)) {
      const int sig = WTERMSIG(status);
      r.exitCode = 128 + sig;
      // killed by an interrupt: it stopped between whole files; anything else (SIGSEGV...) failed
      r.status =
          (sig == SIGINT || sig == SIGTERM || sig == SIGKILL) ? Status::Pending : Status::Failed;
      r.error = fmt::format("killed by signal {} ({})", sig, strsignal(sig));
    }
    if (r.status != Status::Done) {
      const std::string line = lastErrorLine(log, offset);
      if (r.status == Status::Pending)
        r.error = fmt::format(
            "interrupted ({}); a rerun continues from the stage cache",
            r.error.empty() ? fmt::format("exit {}", r.exitCode.value_or(-1)) : r.error);
      else if (!line.empty())
        r.error = line;
      else if (r.error.empty())
        r.error =
            fmt::format("exit {} (no error line; see {})", r.exitCode.value_or(-1), log.string());
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.finished = nowIso();
  r.pid = 0;
  writeRecord(b.root, r);
  return r;
}

int interruptSignal() {
  return g_signal.load();
}

std::vector<SceneRecord> runLocal(const Batch& b, const LocalOptions& o) {
  SignalScope signals(true);
  const int jobs = std::max(1, std::min<int>(o.jobs, static_cast<int>(b.scenes.size())));
  const int total = o.threads > 0
                        ? o.threads
                        : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = std::max(1, total / jobs);
  std::vector<SceneRecord> records(b.scenes.size());
  std::atomic<size_t> next{0};
  std::mutex mutex;
  auto worker = [&] {
    for (;;) {
      if (g_signal.load()) return;
      const size_t i = next.fetch_add(1);
      if (i >= b.scenes.size()) return;
      const bool skip = isFinished(b, i);
      records[i] =
          skip ? readRecord(b.root, b.scenes[i].name) : runScene(b, i, threads, o.executable, true);
      if (o.onScene) {
        std::lock_guard<std::mutex> lock(mutex);
        o.onScene(i, records[i], skip);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int k = 0; k < jobs; ++k) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
  // scenes never started (interrupted) are as their records say
  for (size_t i = 0; i < b.scenes.size(); ++i)
    if (records[i].name.empty()) records[i] = readRecord(b.root, b.scenes[i].name);
  return records;
}

// --- summary.csv and index.html ----------------------------------------------------------------

void writeSummary(const Batch& b, const std::vector<SceneRecord>& records) {
  PS_CheckEQ(records.size(), b.scenes.size(), "one record per scene");
  std::vector<nlohmann::json> metrics(records.size());
  std::set<std::string> stageNames;
  for (size_t i = 0; i < records.size(); ++i) {
    if (records[i].status != Status::Done) continue;
    const fs::path f = b.root / b.scenes[i].name / "metrics.json";
    try {
      metrics[i] = io::readJsonFile(f);
    } catch (const std::exception&) {
      continue;  // a done scene whose metrics.json went missing: no numbers for it
    }
    if (metrics[i].contains("stages") && metrics[i]["stages"].is_object())
      for (const auto& [name, v] : metrics[i]["stages"].items()) stageNames.insert(name);
  }
  std::vector<std::string> stages;
  for (const std::string& s : kStageOrder)
    if (stageNames.erase(s)) stages.push_back(s);
  stages.insert(stages.end(), stageNames.begin(), stageNames.end());

  struct MetricColumn {
    std::string name;
    const char* array;
    const char* key;
  };
  const std::vector<MetricColumn> metricColumns = {
      {"view_rmse", "views", "rmse"},  {"view_psnr", "views", "psnr"},
      {"view_ssim", "views", "ssim"},  {"novel_rmse", "novel", "rmse"},
      {"novel_ssim", "novel", "ssim"}, {"relit_rmse", "relit", "rmse"},
      {"relit_ssim", "relit", "ssim"}};

  std::ostringstream csv;
  csv << "name,status,exit_code,seconds,preset";
  for (const std::string& s : stages) csv << ",seconds_" << s;
  for (const MetricColumn& m : metricColumns) csv << "," << m.name;
  csv << ",error\n";

  std::ostringstream rows;
  int counts[5] = {0, 0, 0, 0, 0};
  for (size_t i = 0; i < records.size(); ++i) {
    const SceneRecord& r = records[i];
    const nlohmann::json& m = metrics[i];
    ++counts[static_cast<int>(r.status)];
    const std::string preset = m.is_object() && m.contains("preset") && m["preset"].is_string()
                                   ? m["preset"].get<std::string>()
                                   : sceneOptions(b, i).preset.value_or("");
    // the contract's four words: a scene still running is pending in summary.csv
    csv << csvField(r.name) << ","
        << statusName(r.status == Status::Running ? Status::Pending : r.status) << ","
        << (r.exitCode ? std::to_string(*r.exitCode) : "") << ","
        << (r.seconds > 0 ? csvNumber(r.seconds) : "") << "," << csvField(preset);
    for (const std::string& s : stages)
      csv << ","
          << (m.is_object() && m.contains("stages") && m["stages"].contains(s)
                  ? csvNumber(number(m["stages"][s]))
                  : "");
    std::vector<std::string> values;  // for the page: SSIM to 3 decimals, RMSE and PSNR to 2
    for (const MetricColumn& c : metricColumns) {
      const double v = m.is_object() && m.contains(c.array)
                           ? meanMetric(m[c.array], c.key)
                           : std::numeric_limits<double>::quiet_NaN();
      values.push_back(!std::isfinite(v)              ? ""
                       : std::string(c.key) == "ssim" ? fmt::format("{:.3f}", v)
                                                      : fmt::format("{:.2f}", v));
      csv << "," << csvNumber(v);
    }
    csv << "," << csvField(r.error) << "\n";

    const fs::path report = b.root / r.name / "report.html";
    std::error_code ec;
    const std::string logRel = ".batch/logs/" + r.name + ".log";
    rows << "<tr class=\"" << statusName(r.status) << "\"><td>" << escapeHtml(r.name) << "</td><td>"
         << statusName(r.status) << "</td><td>" << (r.exitCode ? std::to_string(*r.exitCode) : "")
         << "</td><td>" << (r.seconds > 0 ? fmt::format("{:.1f}", r.seconds) : "") << "</td>";
    for (size_t k = 0; k < 3; ++k) rows << "<td>" << values[k] << "</td>";
    rows << "<td>" << values[3] << "</td><td>" << values[5] << "</td><td>";
    if (fs::exists(report, ec))
      rows << "<a href=\"" << escapeHtml(r.name) << "/report.html\">report</a> ";
    if (fs::exists(b.root / logRel, ec)) rows << "<a href=\"" << escapeHtml(logRel) << "\">log</a>";
    rows << "</td><td>" << escapeHtml(r.error) << "</td></tr>\n";
  }
  io::writeTextFile(b.root / "summary.csv", csv.str());

  std::ostringstream page;
  page << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>photoscene batch: "
       << escapeHtml(b.root.filename().string()) << "</title>\n<style>"
       << "body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
       << "td,th{border:1px solid #ccc;padding:4px 8px;text-align:left}"
       << "tr.done td:nth-child(2){color:#080}tr.failed td:nth-child(2),tr.bad-input "
          "td:nth-child(2){color:#b00}"
       << "tr.pending td:nth-child(2),tr.running td:nth-child(2){color:#a60}</style></head><body>\n"
       << "<h1>photoscene batch</h1>\n<p>" << records.size() << " scenes from <code>"
       << escapeHtml(b.manifest.string()) << "</code>: " << counts[static_cast<int>(Status::Done)]
       << " done, " << counts[static_cast<int>(Status::Failed)] << " failed, "
       << counts[static_cast<int>(Status::BadInput)] << " bad input, "
       << counts[static_cast<int>(Status::Running)] << " running, "
       << counts[static_cast<int>(Status::Pending)]
       << " pending. <a href=\"summary.csv\">summary.csv</a></p>\n"
       << "<table><tr><th>scene</th><th>status</th><th>exit</th><th>seconds</th><th>RMSE "
          "(views)</th>"
       << "<th>PSNR (views)</th><th>SSIM (views)</th><th>RMSE (novel)</th><th>RMSE "
          "(relit)</th><th>links</th>"
       << "<th>error</th></tr>\n"
       << rows.str()
       << "</table>\n<p>RMSE on the sRGB 0-255 scale, means over the images; novel and relit: "
       << "against the scene's ground truth, when it has one.</p>\n</body></html>\n";
  io::writeTextFile(b.root / "index.html", page.str());
}

// --- Slurm -------------------------------------------------------------------------------------

int presetCpus(const std::string& preset) {
  if (preset == "fast") return 2;
  if (preset == "paper") return 8;
  return 4;
}

std::string presetMemory(const std::string& preset) {
  if (preset == "fast") return "2G";
  if (preset == "paper") return "8G";
  return "4G";
}

std::string arrayRanges(const std::vector<size_t>& idx) {
  std::string s;
  for (size_t k = 0; k < idx.size();) {
    size_t e = k;
    while (e + 1 < idx.size() && idx[e + 1] == idx[e] + 1) ++e;
    if (!s.empty()) s += ',';
    s += e == k ? std::to_string(idx[k]) : fmt::format("{}-{}", idx[k], idx[e]);
    k = e + 1;
  }
  return s;
}

namespace {
std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

std::string slurmScript(const Batch& b, const std::vector<size_t>& indices, const SlurmOptions& o,
                        const fs::path& executable) {
  // the largest preset of the submitted scenes sizes every task
  std::string preset = "fast";
  const std::map<std::string, int> rank = {{"fast", 0}, {"balanced", 1}, {"paper", 2}};
  for (size_t i : indices) {
    const std::string p = sceneOptions(b, i).preset.value_or("balanced");
    if (rank.at(p) > rank.at(preset)) preset = p;
  }
  const int cpus = o.cpusPerTask > 0 ? o.cpusPerTask : presetCpus(preset);
  const std::string mem = o.mem.empty() ? presetMemory(preset) : o.mem;
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# Written by photoscene batch: one array task per scene of " << b.manifest.string() << ".\n"
    << "# Each task runs one scene and records its outcome in ROOT/.batch/status/<name>.json.\n"
    << "#SBATCH --job-name=photoscene-" << b.root.filename().string() << "\n"
    << "#SBATCH --array=" << arrayRanges(indices)
    << (o.maxParallel > 0 ? fmt::format("%{}", o.maxParallel) : "") << "\n"
    << "#SBATCH --ntasks=1\n"
    << "#SBATCH --cpus-per-task=" << cpus << "\n"
    << "#SBATCH --mem=" << mem << "\n"
    << "#SBATCH --output=" << (b.root / ".batch" / "slurm" / "%A_%a.out").string() << "\n";
  if (!o.partition.empty()) s << "#SBATCH --partition=" << o.partition << "\n";
  if (!o.timeLimit.empty()) s << "#SBATCH --time=" << o.timeLimit << "\n";
  s << "exec " << shellQuote(executable.string()) << " batch " << shellQuote(b.manifest.string())
    << " -o " << shellQuote(b.root.string())
    << " --task-index \"$SLURM_ARRAY_TASK_ID\" --threads \"${SLURM_CPUS_PER_TASK:-" << cpus
    << "}\"";
  if (b.options.preset) s << " --preset " << *b.options.preset;
  if (b.options.textureSize) s << " --texture-size " << *b.options.textureSize;
  if (b.options.baseline) s << " --baseline " << *b.options.baseline;
  s << "\n";
  return s.str();
}

}  // namespace ps::batch
