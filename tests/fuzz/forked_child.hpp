#pragma once
// A forked child with time bounds, shared by the fuzz programs: fuzz_run runs a reader in the
// child, scene_fuzz execs the invfem command there. The wall-clock bound is alarm(2), and an
// optional CPU-time bound is RLIMIT_CPU: both survive exec, and the default actions of SIGALRM
// and SIGXCPU end the child (and every thread it started), so a hang is told from a crash by the
// signal alone, with no watchdog in the parent. The CPU bound is the one to rely on when the
// machine is shared (under load a sanitized run's wall time can be several times its CPU time); the
// wall bound then only catches a child that blocks.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

#if defined(__SANITIZE_ADDRESS__)
#define INVFEM_FUZZ_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define INVFEM_FUZZ_ASAN 1
#endif
#endif

namespace invfem::fuzz {

// Address-space cap in the child, not under ASan (which reserves terabytes of shadow memory): a
// program that trusts a corrupt count and asks for gigabytes gets bad_alloc instead of the
// machine's memory. The programs a sanitized fuzzer starts are sanitized too (same build
// directory); there ASAN_OPTIONS bounds allocations instead (scene_fuzz sets it).
#ifdef INVFEM_FUZZ_ASAN
constexpr bool kCapAddressSpace = false;
#else
constexpr bool kCapAddressSpace = true;
#endif

// How a child ended: a signal (SIGALRM = the time bound), or an exit code.
struct ChildEnd {
  bool timed_out = false;  // SIGALRM (wall clock) or SIGXCPU (CPU time)
  int signal = 0;  // 0 when it exited
  int code = 0;    // exit code when it exited
  std::string describe() const {
    if (timed_out) return signal == SIGXCPU ? "TIMEOUT (CPU time)" : "TIMEOUT (wall clock)";
    if (signal) return "SIGNAL " + std::to_string(signal) + " (" + strsignal(signal) + ")";
    return "exit " + std::to_string(code);
  }
};

inline ChildEnd decode_status(int status) {
  ChildEnd e;
  if (WIFSIGNALED(status)) {
    e.signal = WTERMSIG(status);
    e.timed_out = e.signal == SIGALRM || e.signal == SIGXCPU;
  } else {
    e.code = WEXITSTATUS(status);
  }
  return e;
}

// Starts `body` in a forked child whose stdin is /dev/null, whose stdout and stderr go to the
// given files (the same file for both if the paths are equal), with core dumps off, the address
// space capped at address_space_cap bytes (when kCapAddressSpace), alarm(timeout_s) armed and,
// if cpu_seconds > 0, its CPU time limited to that. The child _exits with body's
// return value (body may exec instead). Returns the child's pid.
inline pid_t start_child(const std::function<int()>& body, int timeout_s, const std::filesystem::path& out_log,
                         const std::filesystem::path& err_log, rlim_t address_space_cap, int cpu_seconds = 0) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  if (pid > 0) return pid;
  const int in = ::open("/dev/null", O_RDONLY);
  if (in >= 0) ::dup2(in, 0), ::close(in);
  const int out = ::open(out_log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (out >= 0) ::dup2(out, 1), ::close(out);
  if (err_log == out_log) {
    ::dup2(1, 2);
  } else {
    const int err = ::open(err_log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (err >= 0) ::dup2(err, 2), ::close(err);
  }
  rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  if (kCapAddressSpace) {
    rlimit cap{address_space_cap, address_space_cap};
    ::setrlimit(RLIMIT_AS, &cap);
  }
  if (cpu_seconds > 0) {
    rlimit cpu{static_cast<rlim_t>(cpu_seconds), static_cast<rlim_t>(cpu_seconds) + 10};
    ::setrlimit(RLIMIT_CPU, &cpu);
  }
  ::alarm(static_cast<unsigned>(timeout_s));
  const int code = body();
  std::fflush(nullptr);
  ::_exit(code);
}

// start_child, then wait for it.
inline ChildEnd run_child(const std::function<int()>& body, int timeout_s, const std::filesystem::path& out_log,
                          const std::filesystem::path& err_log, rlim_t address_space_cap) {
  const pid_t pid = start_child(body, timeout_s, out_log, err_log, address_space_cap);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return decode_status(status);
}

}  // namespace invfem::fuzz
