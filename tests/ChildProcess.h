#pragma once
// The executables of build/bin run as child processes under limits, for the tests that need a
// real process: signals, resource limits, a hang (alarm), peak memory (wait4).
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace budget_slam::testing {

/// build/bin/<tool>.
inline std::string binary(const std::string& tool) {
  return std::string(BUDGET_SLAM_BINARY_DIR) + "/bin/" + tool;
}

/// How a child ended.
struct ChildExit {
  int code = -1;         ///< exit code, or -signal when killed
  long max_rss_kib = 0;  ///< peak resident memory (wait4)
  double cpu_s = 0;      ///< user + system CPU time [s] (wait4): what a load does not stretch
  bool signaled() const { return code < 0; }
};

/// A child's exit from wait4's status and resource use.
inline ChildExit childExit(int status, const rusage& use) {
  ChildExit r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  r.max_rss_kib = use.ru_maxrss;
  r.cpu_s = static_cast<double>(use.ru_utime.tv_sec + use.ru_stime.tv_sec) +
            1e-6 * static_cast<double>(use.ru_utime.tv_usec + use.ru_stime.tv_usec);
  return r;
}

/// Starts `program args` with stderr into `err_file`, stdout into `out_fd` (default /dev/null),
/// every other descriptor closed, SIGPIPE at its default as a shell leaves it, and `setup` run in
/// the child before exec (limits: setrlimit, alarm).
inline pid_t startChild(const std::string& program, const std::vector<std::string>& args,
                        const std::string& err_file, const std::function<void()>& setup = {},
                        int out_fd = -1) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  const int e = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ::dup2(e, 2);
  const int o = out_fd >= 0 ? out_fd : ::open("/dev/null", O_WRONLY);
  ::dup2(o, 1);
  for (int fd = 3; fd < 1024; ++fd) ::close(fd);
  std::signal(SIGPIPE, SIG_DFL);
  if (setup) setup();
  std::vector<char*> argv = {const_cast<char*>(program.c_str())};
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  ::execv(program.c_str(), argv.data());
  ::_exit(127);
}

inline ChildExit waitChild(pid_t pid) {
  int status = 0;
  rusage use{};
  ::wait4(pid, &status, 0, &use);
  return childExit(status, use);
}

/// Waits (at most `seconds`) until child `pid` is blocked opening a FIFO (Linux: its wait channel
/// is the FIFO's wait_for_partner), so that a signal sent next finds its handlers in place however
/// slowly the machine started it. False when that was not seen in time.
inline bool waitUntilBlockedOnFifo(pid_t pid, double seconds = 60) {
  const std::string wchan = "/proc/" + std::to_string(pid) + "/wchan";
  for (double waited = 0; waited < seconds; waited += 0.01) {
    char buf[64] = {};
    const int fd = ::open(wchan.c_str(), O_RDONLY);
    if (fd >= 0) {
      const ssize_t n = ::read(fd, buf, sizeof buf - 1);
      ::close(fd);
      if (n > 0 && std::string(buf, static_cast<std::size_t>(n)) == "wait_for_partner") return true;
    }
    ::usleep(10000);
  }
  return false;
}

/// Writes `text` into the FIFO `fifo` once child `pid` opens it, and waits for the child. A child
/// that ends without opening it (killed by an early signal, or done before it reads) is waited
/// for all the same: never a writer blocked for ever on a FIFO nobody will read.
inline ChildExit feedFifoAndWait(pid_t pid, const std::string& fifo, const std::string& text) {
  for (;;) {
    const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
    if (fd >= 0) {
      ::fcntl(fd, F_SETFL, 0);
      for (std::size_t at = 0; at < text.size();) {
        const ssize_t n = ::write(fd, text.data() + at, text.size() - at);
        if (n <= 0) break;
        at += static_cast<std::size_t>(n);
      }
      ::close(fd);
      return waitChild(pid);
    }
    int status = 0;
    rusage use{};
    if (::wait4(pid, &status, WNOHANG, &use) == pid) return childExit(status, use);
    ::usleep(10000);
  }
}

inline ChildExit runChild(const std::string& program, const std::vector<std::string>& args,
                          const std::string& err_file, const std::function<void()>& setup = {},
                          int out_fd = -1) {
  return waitChild(startChild(program, args, err_file, setup, out_fd));
}

/// Runs `count` children, `parallel` at a time: `start(i)` starts child i, `done(i, exit)` gets
/// how it ended.
inline void runChildren(std::size_t count, std::size_t parallel,
                        const std::function<pid_t(std::size_t)>& start,
                        const std::function<void(std::size_t, const ChildExit&)>& done) {
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0;
  while (next < count || !running.empty()) {
    while (next < count && running.size() < parallel) {
      const pid_t pid = start(next);
      running[pid] = next++;
    }
    int status = 0;
    rusage use{};
    const pid_t pid = ::wait4(-1, &status, 0, &use);
    if (pid <= 0) break;
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const ChildExit r = childExit(status, use);
    const std::size_t i = it->second;
    running.erase(it);
    done(i, r);
  }
}

/// The limits of issue 23's hostile-input runs: a 3 GiB address space and a 60 s alarm (a child
/// that hangs dies by SIGALRM, which the caller sees as a signal).
inline void hostileLimits() {
  const rlimit as{rlim_t{3} << 30, rlim_t{3} << 30};
  ::setrlimit(RLIMIT_AS, &as);
  ::alarm(60);
}

}  // namespace budget_slam::testing
