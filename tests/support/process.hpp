// Running a program from a test, as a person runs it from a shell: its exit status, or
// the signal that killed it, and what it printed. And a virtual X display (Xvfb) for
// tests of programs that open windows.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace logrid::test {

struct ProcessResult {
  int exit_code = -1;  // when it exited
  int signal = 0;      // when a signal ended it (a crash)
  std::string out, err;
};

// Environment changes for the child: a value sets a variable, nothing unsets it.
using EnvChanges = std::vector<std::pair<std::string, std::optional<std::string>>>;

// Runs argv[0] (searched on PATH) with argv; stdout and stderr go through files under
// `scratch` (a folder that exists), so any amount of output is fine.
inline ProcessResult runProcess(const std::vector<std::string>& argv, const EnvChanges& env,
                                const std::string& scratch) {
  ProcessResult r;
  const std::string out_file = scratch + "/stdout.txt", err_file = scratch + "/stderr.txt";
  const pid_t pid = fork();
  if (pid < 0) return r;
  if (pid == 0) {
    for (const auto& [name, value] : env) {
      if (value) {
        setenv(name.c_str(), value->c_str(), 1);
      } else {
        unsetenv(name.c_str());
      }
    }
    const int out = open(out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || err < 0) _exit(126);
    dup2(out, 1);
    dup2(err, 2);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  auto slurp = [](const std::string& path) {
    std::ifstream in(path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  r.out = slurp(out_file);
  r.err = slurp(err_file);
  return r;
}

// The program's path if it is on PATH.
inline std::optional<std::string> findProgram(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::string file = dir + "/" + name;
    if (!dir.empty() && access(file.c_str(), X_OK) == 0) return file;
  }
  return std::nullopt;
}

// An Xvfb server on the first free display number (Xvfb -displayfd picks it and holds
// its lock, so parallel tests never share or race for a display), stopped with the
// object. display() is empty, and error() says why, when it could not start.
class VirtualDisplay {
 public:
  VirtualDisplay() {
    const auto xvfb = findProgram("Xvfb");
    if (!xvfb) {
      error_ = "Xvfb is not installed (Debian: apt-get install xvfb; scripts/setup.sh)";
      return;
    }
    int fds[2];
    if (pipe(fds) != 0) {
      error_ = "pipe() failed";
      return;
    }
    pid_ = fork();
    if (pid_ == 0) {
      close(fds[0]);
      const int null = open("/dev/null", O_WRONLY);
      if (null >= 0) dup2(null, 1), dup2(null, 2);
      const std::string fd = std::to_string(fds[1]);
      execl(xvfb->c_str(), "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24",
            "-nolisten", "tcp", static_cast<char*>(nullptr));
      _exit(127);
    }
    close(fds[1]);
    if (pid_ < 0) {
      close(fds[0]);
      error_ = "fork() failed";
      return;
    }
    // Xvfb writes the display number and a newline once it accepts clients.
    std::string number;
    pollfd p{fds[0], POLLIN, 0};
    while (number.find('\n') == std::string::npos && poll(&p, 1, 60000) > 0) {
      char buffer[16];
      const ssize_t n = read(fds[0], buffer, sizeof buffer);
      if (n <= 0) break;
      number.append(buffer, std::size_t(n));
    }
    close(fds[0]);
    if (number.find('\n') == std::string::npos) {
      error_ = "Xvfb did not report a display within 60 s";
      return;
    }
    display_ = ":" + number.substr(0, number.find('\n'));
  }
  ~VirtualDisplay() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      int status = 0;
      waitpid(pid_, &status, 0);
    }
  }
  VirtualDisplay(const VirtualDisplay&) = delete;
  VirtualDisplay& operator=(const VirtualDisplay&) = delete;

  const std::string& display() const { return display_; }
  const std::string& error() const { return error_; }

 private:
  pid_t pid_ = -1;
  std::string display_, error_;
};

}  // namespace logrid::test
