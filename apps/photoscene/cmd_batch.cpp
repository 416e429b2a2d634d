// `photoscene batch MANIFEST -o ROOT`: many scenes, locally (N at a time) or as a Slurm job array;
// `photoscene batch --status ROOT`: what is done, failed (with the error) and pending.
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "commands.hpp"
#include "photoscene/core.hpp"
#include "photoscene/io/files.hpp"
#include "photoscene/pipeline/batch.hpp"

namespace ps::app {

namespace fs = std::filesystem;

namespace {

struct BatchArgs {
  std::string manifest, root, status;
  int jobs = 1;
  int threads = 0;
  std::string preset, baseline;
  int textureSize = 0;
  bool slurm = false, wait = false;
  std::string partition, mem, timeLimit;
  int maxParallel = 0, cpusPerTask = 0;
  int taskIndex = -1;
};

fs::path selfExecutable() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("batch: cannot find the photoscene executable (/proc/self/exe)");
  return p;
}

void printRecords(const batch::Batch& b, const std::vector<batch::SceneRecord>& records) {
  std::printf("%-24s %-10s %5s %9s  %s\n", "scene", "status", "exit", "seconds", "error");
  for (const batch::SceneRecord& r : records) {
    std::string err = r.error;
    if (err.size() > 160) err = err.substr(0, 157) + "...";
    std::printf("%-24s %-10s %5s %9s  %s\n", r.name.c_str(), batch::statusName(r.status),
                r.exitCode ? std::to_string(*r.exitCode).c_str() : "",
                r.seconds > 0 ? fmt::format("{:.1f}", r.seconds).c_str() : "", err.c_str());
  }
  std::printf("wrote %s and %s\n", (b.root / "summary.csv").c_str(),
              (b.root / "index.html").c_str());
}

batch::Batch loadBatch(const BatchArgs& a) {
  batch::Batch b;
  b.manifest = fs::absolute(a.manifest).lexically_normal();
  b.scenes = batch::readManifest(a.manifest);
  b.root = fs::absolute(a.root).lexically_normal();
  if (!a.preset.empty()) b.options.preset = a.preset;
  if (a.textureSize > 0) b.options.textureSize = a.textureSize;
  if (!a.baseline.empty()) b.options.baseline = a.baseline;
  fs::create_directories(b.root);
  batch::writeBatchFile(b);
  return b;
}

// Output of a shell command (stdout), and its exit status.
int capture(const std::string& cmd, std::string* out) {
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return -1;
  char buf[4096];
  while (fgets(buf, sizeof(buf), pipe)) *out += buf;
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

int runTask(const BatchArgs& a) {
  const batch::Batch b = loadBatch(a);
  if (a.taskIndex < 0 || static_cast<size_t>(a.taskIndex) >= b.scenes.size())
    throw InputError(
        a.manifest, "--task-index",
        fmt::format("expected an index from 0 to {}, got {}", b.scenes.size() - 1, a.taskIndex));
  const size_t i = static_cast<size_t>(a.taskIndex);
  if (batch::isFinished(b, i)) {
    std::printf("%s: done already (%s)\n", b.scenes[i].name.c_str(),
                (b.root / b.scenes[i].name).c_str());
    return 0;
  }
  // under Slurm every process of the task gets scancel's SIGTERM itself: do not send a second one
  const bool forward = std::getenv("SLURM_JOB_ID") == nullptr;
  const batch::SceneRecord r = batch::runScene(b, i, a.threads, selfExecutable(), forward);
  std::printf("%s: %s%s%s\n", r.name.c_str(), batch::statusName(r.status),
              r.error.empty() ? "" : ": ", r.error.c_str());
  return r.exitCode.value_or(1);
}

int runLocalBatch(const BatchArgs& a) {
  const batch::Batch b = loadBatch(a);
  batch::LocalOptions o;
  o.jobs = a.jobs;
  o.threads = a.threads;
  o.executable = selfExecutable();
  size_t finished = 0;
  o.onScene = [&](size_t i, const batch::SceneRecord& r, bool skipped) {
    ++finished;
    if (skipped)
      spdlog::info("[{}/{}] {}: done already, skipped", finished, b.scenes.size(),
                   b.scenes[i].name);
    else if (r.status == batch::Status::Done)
      spdlog::info("[{}/{}] {}: done in {:.1f} s", finished, b.scenes.size(), r.name, r.seconds);
    else
      spdlog::warn("[{}/{}] {}: {} ({}) after {:.1f} s: {}", finished, b.scenes.size(), r.name,
                   batch::statusName(r.status), r.exitCode.value_or(-1), r.seconds, r.error);
  };
  spdlog::info("batch: {} scenes, {} at a time, into {}", b.scenes.size(), a.jobs, b.root.string());
  const std::vector<batch::SceneRecord> records = batch::runLocal(b, o);
  batch::writeSummary(b, records);
  printRecords(b, records);
  if (const int sig = batch::interruptSignal()) throw Interrupted(sig);
  return batch::exitStatus(records);
}

int submitSlurm(const BatchArgs& a) {
  const batch::Batch b = loadBatch(a);
  const fs::path slurmDir = b.root / ".batch" / "slurm";
  fs::create_directories(slurmDir);
  // a job of this batch still in the queue would run the same scenes twice
  std::string ids;
  if (std::ifstream in(slurmDir / "jobs.txt"); in)
    for (std::string id; std::getline(in, id);)
      if (!id.empty()) ids += (ids.empty() ? "" : ",") + id;
  if (!ids.empty()) {
    std::string queued;
    if (capture("squeue -h -o %i -j " + shellQuote(ids) + " 2>/dev/null", &queued) == 0 &&
        !queued.empty())
      throw std::runtime_error(
          "batch: a Slurm job of this batch is still queued or running (squeue -j " + ids +
          "); wait for it or scancel it, then resubmit");
  }
  std::vector<size_t> todo;
  for (size_t i = 0; i < b.scenes.size(); ++i)
    if (!batch::isFinished(b, i)) todo.push_back(i);
  if (todo.empty()) {
    const auto records = batch::readRecords(b);
    batch::writeSummary(b, records);
    printRecords(b, records);
    return batch::exitStatus(records);
  }
  batch::SlurmOptions so;
  so.partition = a.partition;
  so.maxParallel = a.maxParallel;
  so.cpusPerTask = a.cpusPerTask;
  so.mem = a.mem;
  so.timeLimit = a.timeLimit;
  const fs::path script = b.root / ".batch" / "job.sh";
  io::writeTextFile(script, batch::slurmScript(b, todo, so, selfExecutable()));
  fs::permissions(script, fs::perms::owner_exec, fs::perm_options::add);
  std::string out;
  const int rc = capture(std::string("sbatch --parsable") + (a.wait ? " --wait" : "") + " " +
                             shellQuote(script.string()) + " 2>&1",
                         &out);
  std::string jobId = out.substr(0, out.find_first_of(";\n"));
  if (jobId.empty() || jobId.find_first_not_of("0123456789") != std::string::npos)
    throw std::runtime_error("batch: sbatch " + script.string() + " failed (exit " +
                             std::to_string(rc) + "): " + out);
  std::ofstream(slurmDir / "jobs.txt", std::ios::app) << jobId << "\n";
  std::printf("submitted Slurm job %s: %zu scene(s), array %s (script %s)\n", jobId.c_str(),
              todo.size(), batch::arrayRanges(todo).c_str(), script.c_str());
  if (!a.wait) {
    batch::writeSummary(b, batch::readRecords(b));
    std::printf("follow it with: photoscene batch --status %s\n", b.root.c_str());
    return 0;
  }
  const auto records = batch::readRecords(b);
  batch::writeSummary(b, records);
  printRecords(b, records);
  return batch::exitStatus(records);
}

int showStatus(const BatchArgs& a) {
  const batch::Batch b = batch::readBatchFile(a.status);
  const auto records = batch::readRecords(b);
  batch::writeSummary(b, records);
  printRecords(b, records);
  return batch::exitStatus(records);
}

}  // namespace

void addBatchCommand(CLI::App& root) {
  auto a = std::make_shared<BatchArgs>();
  auto* cmd = root.add_subcommand("batch",
                                  "Run many scenes: locally, N at a time, or as a Slurm job array");
  cmd->add_option("manifest", a->manifest,
                  "Text file, one scene.json per line (relative to it; # comments), or JSON "
                  "{\"version\":1,\"scenes\":[{\"scene\",\"name\",\"options\"}]}");
  cmd->add_option("-o,--out", a->root,
                  "Output root: ROOT/<name>/ per scene, ROOT/summary.csv, ROOT/index.html");
  cmd->add_option("--status", a->status,
                  "Print done / failed (with the error) / pending per scene of ROOT; "
                  "rewrites its summary.csv and index.html")
      ->excludes("manifest")
      ->excludes("--out");
  cmd->add_option("-j,--jobs", a->jobs, "Scenes at a time (local mode)")->check(CLI::Range(1, 256));
  cmd->add_option("--threads", a->threads,
                  "Threads in all, shared by the scenes at a time (default: all cores); "
                  "with --task-index, the scene's own")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--preset", a->preset, "fast | balanced | paper, for every scene without its own")
      ->check(CLI::IsMember({"fast", "balanced", "paper"}));
  cmd->add_option("--texture-size", a->textureSize,
                  "Exported texture size, for every scene without its own")
      ->check(CLI::Range(4, 16384));
  cmd->add_option("--baseline", a->baseline, "pixel-median | shading-median (see photoscene run)")
      ->check(CLI::IsMember({"none", "pixel-median", "shading-median"}));
  auto* slurm = cmd->add_flag("--slurm", a->slurm,
                              "Submit one Slurm array task per unfinished scene (sbatch)");
  cmd->add_option("--partition", a->partition, "Slurm partition")->needs(slurm);
  cmd->add_option("--max-parallel", a->maxParallel,
                  "Slurm: at most M tasks at once (--array=...%M)")
      ->needs(slurm)
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--cpus-per-task", a->cpusPerTask,
                  "Slurm: CPUs per task (default by preset: fast 2, balanced 4, paper 8)")
      ->needs(slurm)
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--mem", a->mem,
                  "Slurm: memory per task, sbatch syntax (default by preset: fast 2G, balanced 4G, "
                  "paper 8G)")
      ->needs(slurm);
  cmd->add_option("--time", a->timeLimit, "Slurm: time limit per task, sbatch syntax")
      ->needs(slurm);
  cmd->add_flag("--wait", a->wait, "Slurm: wait for the job to end (sbatch --wait), then summarize")
      ->needs(slurm);
  cmd->add_option(
         "--task-index", a->taskIndex,
         "Run only scene I of the manifest (0-based) and record its outcome: the entry point of "
         "a scheduler's task ($SLURM_ARRAY_TASK_ID, $JOB_COMPLETION_INDEX)")
      ->excludes(slurm)
      ->check(CLI::NonNegativeNumber);
  cmd->footer(
      "Each scene runs as `photoscene run SCENE -o ROOT/<name>` (log: ROOT/.batch/logs/<name>.log; "
      "record: "
      "ROOT/.batch/status/<name>.json). A scene that fails does not stop the others. Rerunning the "
      "same "
      "command resumes: done scenes are skipped, the others continue from their stage cache.\n"
      "Exit status: 0 every scene done; 2 some scene had bad input (or the manifest is bad), the "
      "rest done; "
      "1 otherwise (failed or pending scenes); 130 / 143 after SIGINT / SIGTERM. --slurm without "
      "--wait: 0 "
      "once submitted. --status: as the batch would. --task-index: that scene's `photoscene run` "
      "status.");
  cmd->callback([a] {
    int code = 0;
    if (!a->status.empty()) {
      code = showStatus(*a);
    } else {
      if (a->manifest.empty())
        throw InputError("photoscene batch", "MANIFEST",
                         "expected a manifest file (or --status ROOT)");
      if (a->root.empty())
        throw InputError("photoscene batch", "-o", "expected an output root folder");
      if (a->taskIndex >= 0)
        code = runTask(*a);
      else if (a->slurm)
        code = submitSlurm(*a);
      else
        code = runLocalBatch(*a);
    }
    if (code != 0) throw ExitStatus(code);
  });
}

}  // namespace ps::app
