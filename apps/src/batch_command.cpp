#include "batch_command.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include "cli_args.hpp"
#include "invfem/core/io/text_file.hpp"
#include "invfem/renders/image.hpp"
#include "invfem/renders/image_compare.hpp"
#include "input_check.hpp"
#include "memory_estimate.hpp"
#include "json_reader.hpp"
#include "preview.hpp"
#include "run_folder.hpp"
#include "run_manifest.hpp"
#include "run_output.hpp"
#include "scene.hpp"
#include "video.hpp"

extern char** environ;

namespace invfem::app {

const char* const kBatchHelp =
    "usage: invfem batch SCENE... --out DIR [--jobs N] [--quick] [--shard I/N] [--mp4] [--overwrite]\n"
    "                    [--memory-limit SIZE] [--strict]\n"
    "\n"
    "Runs and renders many scenes, each in its own process (one failing scene does not stop the\n"
    "others), into DIR/<scene>/ (the layout of invfem run, with png/), then writes\n"
    "DIR/contact_sheet.png: a grid of every scene's last frame.\n"
    "Options:\n"
    "  --out DIR     batch output folder\n"
    "  --jobs N      scenes run at once (default 1)\n"
    "  --quick       run each scene at its quick resolution (its \"quick\" overrides)\n"
    "  --shard I/N   run only the I-th of N slices of the scene list (0 <= I < N), for job arrays;\n"
    "                the slice is every N-th scene of the sorted list, starting at I\n"
    "  --mp4         also encode DIR/<scene>/<scene>.mp4 with ffmpeg (when ffmpeg is installed)\n"
    "  --overwrite   clear each scene's earlier run in DIR/<scene>/ (without it, a batch whose\n"
    "                folders hold earlier runs is refused before any scene starts)\n"
    "  --memory-limit SIZE  each scene's memory budget (invfem run --memory-limit); default: 80% of\n"
    "                this machine's memory shared by the --jobs scenes that run at once\n"
    "  --strict      each run refuses a scene with a warning at load (invfem run --strict)\n"
    "Exit code: 0 when every scene ran, 1 when any failed (they are listed), 2 bad input.\n";

namespace {

struct Job {
  std::filesystem::path scene;
  std::string name;  // folder under DIR: the scene file's stem
  pid_t pid = -1;
  int status = -1;
  std::string failure = {};  // "exit code 1", "killed by signal 9 (SIGKILL: Killed)"
};

// "9 (SIGKILL: Killed)": the number, its name where the C library knows it, and its description.
std::string signal_name(int sig) {
  std::string s = std::to_string(sig) + " (";
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 32))
  if (const char* abbrev = sigabbrev_np(sig)) s += std::string("SIG") + abbrev + ": ";
#endif
  const char* description = strsignal(sig);
  return s + (description ? description : "unknown signal") + ")";
}

pid_t spawn(const std::vector<std::string>& argv, const std::filesystem::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0].c_str(), &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(rc));
  return pid;
}


std::pair<int, int> parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument(text);
    std::size_t u1 = 0, u2 = 0;
    const int i = std::stoi(text.substr(0, slash), &u1);
    const int n = std::stoi(text.substr(slash + 1), &u2);
    if (u1 != slash || u2 != text.size() - slash - 1 || n < 1 || i < 0 || i >= n) throw std::invalid_argument(text);
    return {i, n};
  } catch (const std::exception&) {
    throw InputError("--shard: expected I/N with 0 <= I < N, found \"" + text + "\"");
  }
}

}  // namespace

int batch_command(const std::vector<std::string>& raw, const std::string& self_exe) {
  const ParsedArgs args = parse_args(raw, "batch", {"--out", "--jobs", "--shard", "--memory-limit"},
                                     {"--help", "-h", "--quick", "--mp4", "--overwrite", "--strict"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kBatchHelp;
    return 0;
  }
  if (args.positional.empty()) throw InputError("batch: no scene files given (see invfem batch --help)");
  if (!args.has("--out")) throw InputError("batch: --out DIR is required");
  const std::filesystem::path out = args.value("--out");
  const int jobs = args.integer("--jobs", 1, 1, 256);
  // Scenes running side by side share the machine: each gets its part of the default budget.
  const std::string memory_limit =
      args.has("--memory-limit")
          ? (parse_memory_size(args.value("--memory-limit"), "--memory-limit"), args.value("--memory-limit"))
          : std::to_string(std::max<std::uint64_t>(default_memory_limit() / static_cast<std::uint64_t>(jobs), 1000000));

  std::vector<std::filesystem::path> scenes;
  for (const auto& s : args.positional) {
    if (const std::string problem = input_file_problem(s); !problem.empty())
      throw InputError(s + ": no such scene file (" + problem + ")");
    scenes.push_back(std::filesystem::absolute(s));
  }
  std::sort(scenes.begin(), scenes.end());
  std::map<std::string, std::filesystem::path> by_name;
  for (const auto& s : scenes)
    if (!by_name.emplace(s.stem().string(), s).second)
      throw InputError(s.string() + ": another scene in the batch has the same file name (" +
                       by_name[s.stem().string()].string() + "); their outputs would collide");
  std::vector<Job> todo;
  const auto [shard, shards] = args.has("--shard") ? parse_shard(args.value("--shard")) : std::pair<int, int>{0, 1};
  for (std::size_t k = 0; k < scenes.size(); ++k)
    if (static_cast<int>(k % shards) == shard) todo.push_back({scenes[k], scenes[k].stem().string()});
  prepare_output_dir(out, "--out");
  const bool overwrite = args.flag("--overwrite");
  if (!overwrite)  // a run owns its folder (run_folder.hpp): say so before any scene starts
    for (const Job& j : todo)
      if (const EarlierRun e = find_earlier_run(out / j.name); e.present)
        throw InputError("--out " + (out / j.name).string() + " holds an earlier run of " + j.name +
                         ": --overwrite clears the batch's earlier runs first, or give another folder");
  const bool mp4 = args.flag("--mp4");
  if (mp4 && !have_ffmpeg()) std::cerr << "warning: --mp4: ffmpeg is not installed; no videos will be written\n";

  // Run: at most `jobs` children at once.
  std::size_t next = 0, running = 0, done = 0;
  std::map<pid_t, Job*> live;
  while (done < todo.size()) {
    while (running < static_cast<std::size_t>(jobs) && next < todo.size()) {
      Job& j = todo[next++];
      const auto dir = out / j.name;
      std::filesystem::create_directories(dir);
      std::vector<std::string> argv{self_exe, "run", j.scene.string(), "--out", dir.string(), "--render"};
      if (args.flag("--quick")) argv.push_back("--quick");
      if (overwrite) argv.push_back("--overwrite");
      if (args.flag("--strict")) argv.push_back("--strict");
      argv.insert(argv.end(), {"--memory-limit", memory_limit});
      j.pid = spawn(argv, dir / "log.txt");
      live[j.pid] = &j;
      ++running;
      std::printf("started %s (%zu/%zu)\n", j.name.c_str(), next, todo.size());
      std::fflush(stdout);
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) break;
    auto it = live.find(pid);
    if (it == live.end()) continue;
    Job& j = *it->second;
    j.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    live.erase(it);
    --running;
    ++done;
    const auto log = out / j.name / "log.txt";
    std::string how;  // why it failed, when the log cannot say: a signal ends the child without a word
    if (WIFSIGNALED(status)) {
      how = " (killed by signal " + signal_name(WTERMSIG(status)) + ")";
      std::ofstream(log, std::ios::app) << "invfem batch: the run was killed by signal "
                                        << signal_name(WTERMSIG(status)) << (WCOREDUMP(status) ? ", core dumped" : "")
                                        << "\n";
      j.failure = "killed by signal " + signal_name(WTERMSIG(status));
    } else if (j.status != 0) {
      how = " (exit code " + std::to_string(j.status) + ")";
      j.failure = "exit code " + std::to_string(j.status);
    }
    std::printf("%s %s%s (%zu/%zu); log: %s\n", j.status == 0 ? "finished" : "FAILED", j.name.c_str(), how.c_str(),
                done, todo.size(), log.string().c_str());
    std::fflush(stdout);
  }

  // Contact sheet of the last frames, and optional videos.
  std::vector<renders::Image> images;
  std::vector<std::string> labels;
  std::vector<std::string> failed;
  for (const auto& j : todo) {
    if (j.status != 0) {
      failed.push_back(j.name + " (" + j.failure + ")");
      continue;
    }
    const auto dir = out / j.name;
    Scene written;  // the scene as run (its frame rate and first frame number), from its scene.json
    try {
      written = parse_scene(parse_json(read_text_file((dir / "scene.json").string(), 1u << 26, "batch"),
                                       (dir / "scene.json").string()),
                            dir / "scene.json", /*check_files=*/false);
    } catch (const std::exception& e) {
      failed.push_back(j.name + " (its scene.json: " + e.what() + ")");
      continue;
    }
    const int first = written.first_frame_number;
    int last = first - 1;
    while (std::filesystem::exists(dir / "png" / (RunOutput::frame_name(last + 1) + ".png"))) ++last;
    if (last < first) {
      failed.push_back(j.name + " (no preview written)");
      continue;
    }
    images.push_back(renders::read_png((dir / "png" / (RunOutput::frame_name(last) + ".png")).string()));
    labels.push_back(j.name + " frame " + std::to_string(last));
    if (mp4 && have_ffmpeg()) {
      try {  // at the scene's frame rate
        if (RunManifest::exists(dir)) RunManifest(dir).record(dir / (j.name + ".mp4"));
        encode_mp4(dir / "png", first, last, written.fps, dir / (j.name + ".mp4"));
      } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << "\n";
        failed.push_back(j.name + " (mp4 encoding)");
      }
    }
  }
  if (!images.empty()) {
    const int columns = static_cast<int>(std::ceil(std::sqrt(double(images.size()))));
    const auto sheet = out / (shards > 1 ? "contact_sheet_" + std::to_string(shard) + ".png" : "contact_sheet.png");
    renders::write_png(sheet.string(), renders::contact_sheet(images, columns, labels));
    std::printf("contact sheet: %s (%zu scenes)\n", sheet.string().c_str(), images.size());
  }
  if (!failed.empty()) {
    std::fprintf(stderr, "error: %zu of %zu scenes failed:", failed.size(), todo.size());
    for (const auto& f : failed) std::fprintf(stderr, " %s", f.c_str());
    std::fprintf(stderr, "\n");
    return 1;
  }
  return 0;
}

}  // namespace invfem::app
