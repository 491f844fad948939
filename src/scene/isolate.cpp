// SPDX-License-Identifier: MIT
#include "src/scene/isolate.h"

#include "src/base/error.h"

#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <new>

// Present only in sanitizer builds (weak: null otherwise). libFuzzer and the
// sanitizers register a death callback that writes a crash artifact and
// final stats; a contained child must not do that on the parent's behalf.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace plancheck {
namespace {

// Sanitizers reserve terabytes of shadow address space, so an address-space
// limit would make every later allocation fail: no limit there.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

bool g_in_child = false;  // set once in the child, right after the fork

constexpr char kResult = 'R', kInputError = 'I', kOtherError = 'X';

bool write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

std::size_t memory_budget_bytes(const IsolationLimits& limits) {
  if (limits.memory_mb > 0) return limits.memory_mb << 20;
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return std::size_t{8} << 30;
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) / 2;
}

// The child's address space may grow by the budget beyond what it maps at
// the fork (the parent's heap, libraries and thread stacks come along).
void limit_address_space(std::size_t budget) {
  std::FILE* statm = std::fopen("/proc/self/statm", "r");
  unsigned long mapped_pages = 0;
  const bool known = statm != nullptr && std::fscanf(statm, "%lu", &mapped_pages) == 1;
  if (statm != nullptr) std::fclose(statm);
  if (!known) return;
  const rlim_t want = static_cast<rlim_t>(mapped_pages) * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE)) + budget;
  rlimit now{};
  if (::getrlimit(RLIMIT_AS, &now) != 0) return;
  rlimit next = now;
  next.rlim_cur = now.rlim_max == RLIM_INFINITY ? want : std::min<rlim_t>(want, now.rlim_max);
  if (now.rlim_cur != RLIM_INFINITY && now.rlim_cur < next.rlim_cur) return;  // already tighter
  ::setrlimit(RLIMIT_AS, &next);
}

[[noreturn]] void child_main(int fd, const std::function<std::string()>& work, const IsolationLimits& limits) {
  g_in_child = true;
  // A crash must end the child quietly with its signal, not run the
  // parent's handlers (libFuzzer's, the sanitizers').
  for (int s : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGTRAP, SIGSYS}) std::signal(s, SIG_DFL);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  if (__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
  const std::size_t budget = memory_budget_bytes(limits);
  if (!kSanitized) limit_address_space(budget);

  char tag = kOtherError;
  std::string body;
  try {
    body = work();
    tag = kResult;
  } catch (const InputError& e) {
    tag = kInputError;
    body = e.what();
  } catch (const std::bad_alloc&) {
    body = "ran out of memory (limit " + std::to_string(budget >> 20) + " MB)";
  } catch (const std::exception& e) {
    body = e.what();
  } catch (...) {
    body = "failed with an exception of unknown type";
  }
  const bool sent = write_all(fd, &tag, 1) && write_all(fd, body.data(), body.size());
  ::_exit(sent ? 0 : 3);  // no atexit handlers, no static destructors: the parent owns those
}

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", seconds);
  return text;
}

// The child's last words: the last non-blank line it wrote to stderr
// (assimp's "ai_assert failure in ..."), cut to a readable length.
std::string last_line(const std::string& text) {
  std::size_t end = text.find_last_not_of(" \t\r\n");
  if (end == std::string::npos) return {};
  const std::size_t newline = text.rfind('\n', end);
  const std::size_t begin = newline == std::string::npos ? 0 : newline + 1;
  std::string line = text.substr(begin, end + 1 - begin);
  if (line.size() > 300) line = line.substr(0, 297) + "...";
  return line;
}

}  // namespace

bool in_isolated_child() { return g_in_child; }

SideWork::SideWork(const std::function<void(const std::atomic<bool>& stop)>& work) {
  if (work) job_ = std::make_unique<BesideJob>([this, work] { work(stop_); });
}

SideWork::~SideWork() {
  stop_ = true;
  job_.reset();  // joins; what the work threw is dropped
}

std::string run_isolated(const std::function<std::string()>& work, const IsolationLimits& limits,
                         const std::function<void(const std::atomic<bool>& stop)>& meanwhile) {
  if (!limits.isolate) return work();
  int out_fds[2], err_fds[2];
  if (::pipe2(out_fds, O_CLOEXEC) != 0) return work();
  if (::pipe2(err_fds, O_CLOEXEC) != 0) {
    ::close(out_fds[0]);
    ::close(out_fds[1]);
    return work();
  }
  ::fcntl(out_fds[0], F_SETPIPE_SZ, 1 << 20);  // fewer round trips for a big model; best effort
  const pid_t pid = ::fork();
  if (pid < 0) {
    for (int fd : {out_fds[0], out_fds[1], err_fds[0], err_fds[1]}) ::close(fd);
    return work();
  }
  if (pid == 0) {
    ::close(out_fds[0]);
    ::close(err_fds[0]);
    ::dup2(err_fds[1], STDERR_FILENO);
    child_main(out_fds[1], work, limits);
  }
  ::close(out_fds[1]);
  ::close(err_fds[1]);

  // The caller's work while the child runs (this thread only waits): on a
  // thread of its own, started after the fork (the child inherits no
  // running thread), joined on every way out; what it throws is dropped.
  SideWork side(meanwhile);

  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(std::max(0.0, limits.seconds)));
  std::string out, err;
  bool timed_out = false, read_failed = false;
  pollfd fds[2] = {{out_fds[0], POLLIN, 0}, {err_fds[0], POLLIN, 0}};
  std::string* sinks[2] = {&out, &err};
  char buffer[1 << 16];
  while (fds[0].fd >= 0 || fds[1].fd >= 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    const int ready = ::poll(fds, 2, static_cast<int>(std::min<long long>(left, INT_MAX)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0) {
      read_failed = true;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      const ssize_t n = ::read(fds[i].fd, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n > 0) {
        // stderr is kept to its last 64 KB: only its end is ever shown.
        sinks[i]->append(buffer, static_cast<std::size_t>(n));
        if (i == 1 && err.size() > (1 << 17)) err.erase(0, err.size() - (1 << 16));
        continue;
      }
      if (n < 0 && i == 0) read_failed = true;
      ::close(fds[i].fd);  // end of file: the child is exiting
      fds[i].fd = -1;
    }
    if (read_failed) break;
  }
  side.stop();  // the child has answered (or failed): `meanwhile` has had its time
  for (const pollfd& p : fds)
    if (p.fd >= 0) ::close(p.fd);
  if (timed_out || read_failed) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }

  const std::string said = last_line(err);
  const std::string because = said.empty() ? std::string() : ": " + said;
  if (timed_out) throw IsolationError("did not finish within " + seconds_text(limits.seconds) + " s" + because);
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* name = ::strsignal(sig);
    std::string what = "crashed (signal " + std::to_string(sig) + ", " + (name ? name : "unknown") + ")";
    if (sig == SIGKILL) what += "; the system may have run out of memory";
    throw IsolationError(what + because);
  }
  if (read_failed || !WIFEXITED(status) || WEXITSTATUS(status) != 0 || out.empty())
    throw IsolationError("exited with status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                         " without a result" + because);
  // A child that worked but said something: pass it on, not hide it.
  if (!err.empty()) (void)!::write(STDERR_FILENO, err.data(), err.size());
  const char tag = out[0];
  out.erase(0, 1);
  if (tag == kInputError) throw InputError(out);
  if (tag == kOtherError) throw std::runtime_error(out);
  return out;
}

}  // namespace plancheck
