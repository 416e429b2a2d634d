// Many rooms: a manifest of scenes run into one output root, each scene as its own
// `photoscene run` process (spec ../shared/spec/scene-format.md section 4, `photoscene batch`).
//
// Layout of ROOT:
//   ROOT/<name>/                   the scene's output folder (section 3), written by `photoscene
//   run` ROOT/summary.csv               one row per scene: name, status, exit code, seconds per
//   stage, metrics ROOT/index.html                every scene's status, its report and its log
//   ROOT/.batch/batch.json         the resolved manifest and run options (what `--status ROOT`
//   reads) ROOT/.batch/status/<name>.json the scene's record (status, exit code, error line, start,
//   end);
//                                  written to a temporary name and renamed, so it is always whole
//   ROOT/.batch/logs/<name>.log    the scene's stdout and stderr
//   ROOT/.batch/job.sh             Slurm mode: the sbatch array script; task logs in .batch/slurm/
//
// Resuming: a scene whose record says `done` for the same run command, and whose metrics.json is
// there, is skipped; every other scene is run again, and `photoscene run`'s stage cache
// (ROOT/<name>/.cache) makes the rerun load every stage that finished before it stopped.
//
//   auto scenes = ps::batch::readManifest("rooms.txt");          // ps::InputError on a bad
//   manifest ps::batch::Batch b{"twins", "rooms.txt", scenes, {}}; ps::batch::writeBatchFile(b);
//   auto records = ps::batch::runLocal(b, {.jobs = 2, .threads = 8, .executable =
//   "/usr/bin/photoscene"}); ps::batch::writeSummary(b, records); int code =
//   ps::batch::exitStatus(records);                     // 0 / 2 / 1 as the spec says
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace ps::batch {

namespace fs = std::filesystem;

/// The `photoscene run` options a scene (or the whole batch) can set.
struct RunOptions {
  std::optional<std::string> preset;    ///< fast | balanced | paper
  std::optional<int> textureSize;       ///< exported maps, 4..16384
  std::optional<std::string> baseline;  ///< none | pixel-median | shading-median
};

/// One line (text manifest) or one `scenes[i]` entry (JSON manifest).
struct SceneEntry {
  fs::path scene;      ///< scene.json, absolute (resolved against the manifest's folder)
  std::string name;    ///< ROOT/<name>; default: the scene's folder name
  RunOptions options;  ///< the entry's own options (JSON manifest only); they win over the batch's
  std::string where;   ///< "line 3" or "scenes[2]", for messages
};

/// Reads a manifest: a text file with one scene.json path per line (relative to the manifest's
/// folder; `#` starts a comment; blank lines ignored), or a JSON file
/// `{"version": 1, "scenes": [{"scene": PATH, "name": NAME, "options": {"preset": ..,
/// "texture_size": ..}}]}` (recognised by its first non-blank character `{`).
/// Throws ps::InputError naming the manifest, the line or key, and what was expected: no scenes,
/// an unknown key, a wrong type, a name that is not a plain folder name, two scenes with one name.
/// The scene files themselves are not read here: a missing or bad scene is that scene's
/// `bad-input`, found when it runs.
std::vector<SceneEntry> readManifest(const fs::path& manifest);

/// A batch: where it goes, what it runs, and the options every scene gets.
struct Batch {
  fs::path root;                   ///< ROOT (absolute)
  fs::path manifest;               ///< the manifest it was read from (absolute)
  std::vector<SceneEntry> scenes;  ///< in manifest order; the task index is the position here
  RunOptions options;              ///< the command line's run options (a scene's own win)
};

/// Writes ROOT/.batch/batch.json (atomically). Creates ROOT/.batch.
void writeBatchFile(const Batch& batch);
/// Reads ROOT/.batch/batch.json; ps::InputError when ROOT holds no batch.
Batch readBatchFile(const fs::path& root);

enum class Status { Pending, Running, Done, Failed, BadInput };
/// "pending", "running", "done", "failed", "bad-input" (summary.csv's words).
const char* statusName(Status s);

/// What is known about one scene: ROOT/.batch/status/<name>.json.
struct SceneRecord {
  std::string name;
  Status status = Status::Pending;
  std::optional<int> exitCode;  ///< of `photoscene run` (128 + signal when it was stopped by one)
  std::string error;            ///< the last error line of its log (failed, bad-input, interrupted)
  std::string started, finished;  ///< UTC, ISO 8601
  double seconds = 0;             ///< wall time of the last attempt
  std::string host;               ///< where the last attempt ran
  long pid = 0;                   ///< its task process (running records)
  std::string command;            ///< the run command without --threads (a resume matches it)
  int attempts = 0;
};

fs::path statusFile(const fs::path& root, const std::string& name);
fs::path logFile(const fs::path& root, const std::string& name);
/// The scene's record; Pending when it has none. A `running` record whose process is gone (same
/// host, pid not alive: killed without a chance to record) reads as pending, with that said in
/// `error`.
SceneRecord readRecord(const fs::path& root, const std::string& name);
void writeRecord(const fs::path& root, const SceneRecord& record);

/// The effective options of scene i: its own, else the batch's.
RunOptions sceneOptions(const Batch& batch, size_t i);
/// `photoscene run` arguments (after the executable) for scene i; threads 0 = all cores.
std::vector<std::string> runArguments(const Batch& batch, size_t i, int threads);
/// True when scene i's record is `done` for the same command and its metrics.json exists.
bool isFinished(const Batch& batch, size_t i);

/// Runs scene i as a child process `EXECUTABLE run ...` (its own process group, stdout and stderr
/// to its log), recording `running` first and the outcome after: exit 0 done, 2 bad-input,
/// 130 / 143 or killed by a signal pending (interrupted: a rerun continues from the stage cache),
/// anything else failed. SIGINT / SIGTERM received by this process while it waits are forwarded
/// to the child (unless `forwardSignals` is false: under Slurm every process of the task gets the
/// signal already, and a second one would stop the child at once instead of at a check point).
SceneRecord runScene(const Batch& batch, size_t i, int threads, const fs::path& executable,
                     bool forwardSignals = true);

struct LocalOptions {
  int jobs = 1;         ///< scenes at a time
  int threads = 0;      ///< in all (0 = all cores); each scene gets threads / jobs (at least 1)
  fs::path executable;  ///< the `photoscene` binary
  /// Called as each scene ends (from the worker threads, serialized), e.g. to print a line.
  std::function<void(size_t index, const SceneRecord&, bool skipped)> onScene;
};

/// Runs every unfinished scene, `jobs` at a time, while installing SIGINT / SIGTERM handlers that
/// stop handing out scenes and forward the signal to the running ones. Returns every scene's
/// record (finished ones as they were). Afterwards interrupted() says whether it was stopped.
std::vector<SceneRecord> runLocal(const Batch& batch, const LocalOptions& options);
/// The signal that stopped the last runLocal / runScene (0 when none).
int interruptSignal();

/// Every scene's record, in manifest order.
std::vector<SceneRecord> readRecords(const Batch& batch);
/// 0 every scene done; 2 some bad-input and the rest done; 1 otherwise.
int exitStatus(const std::vector<SceneRecord>& records);

/// Writes ROOT/summary.csv and ROOT/index.html (atomically) from the records and each done
/// scene's metrics.json (seconds per stage; mean RMSE / PSNR / SSIM over the input views, and over
/// the novel and relit ground-truth images when the scene has them).
void writeSummary(const Batch& batch, const std::vector<SceneRecord>& records);

/// Slurm: resources of one array task.
struct SlurmOptions {
  std::string partition;  ///< empty: the cluster's default
  int maxParallel = 0;    ///< `%M` throttle; 0 = none
  int cpusPerTask = 0;    ///< 0: by preset (fast 2, balanced 4, paper 8)
  std::string mem;        ///< sbatch --mem; empty: by preset (fast 2G, balanced 4G, paper 8G)
  std::string timeLimit;  ///< sbatch --time; empty: none
};
/// CPUs and memory of one task for a preset (see SlurmOptions).
int presetCpus(const std::string& preset);
std::string presetMemory(const std::string& preset);
/// "0-2,5,7-9" for sorted indices.
std::string arrayRanges(const std::vector<size_t>& indices);
/// The sbatch script for the given scene indices: one array task per scene, each running
/// `EXECUTABLE batch MANIFEST -o ROOT --task-index $SLURM_ARRAY_TASK_ID --threads
/// $SLURM_CPUS_PER_TASK` with the batch's run options; task logs in ROOT/.batch/slurm/%A_%a.out.
std::string slurmScript(const Batch& batch, const std::vector<size_t>& indices,
                        const SlurmOptions& options, const fs::path& executable);

}  // namespace ps::batch
