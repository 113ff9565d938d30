#pragma once
// The real hexcover-server binary as a child process on a free loopback port, for the
// end-to-end tests (e2e_*) and bench/server_bench.cpp. Tests that need it skip when the binary
// was not built (HEXCOVER_SERVER_OR_SKIP, for files that include gtest).

#include <fcntl.h>
#include <httplib.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace hexcover::server::test {

#ifdef HEXCOVER_SERVER
inline constexpr const char* kServerBinary = HEXCOVER_SERVER;
#else
inline constexpr const char* kServerBinary = nullptr;
#endif

#define HEXCOVER_SERVER_OR_SKIP()                         \
  if (::hexcover::server::test::kServerBinary == nullptr) \
  GTEST_SKIP() << "hexcover-server was not built (core/pipeline/pipeline.cpp is missing)"

class ServerProcess {
 public:
  /// Starts the server on `dataDir` with `--port 0` and the extra flags; waits until it logs
  /// that it listens. The log (JSON lines) goes to dataDir/../<name>.log.
  ServerProcess(const std::filesystem::path& dataDir, std::vector<std::string> flags = {})
      : log_(dataDir.string() + ".log") {
    std::vector<std::string> args = {kServerBinary, "--host",     "127.0.0.1",     "--port",
                                     "0",           "--data-dir", dataDir.string()};
    args.insert(args.end(), flags.begin(), flags.end());
    const int before = listeningLines().size();  // a restart appends to the same log
    pid_ = fork();
    if (pid_ == 0) {
      const int fd = open(log_.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(kServerBinary, argv.data());
      _exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (port_ == 0 && std::chrono::steady_clock::now() < deadline) {
      const auto lines = listeningLines();
      if (int(lines.size()) > before)
        port_ = nlohmann::json::parse(lines.back()).at("port").get<int>();
      else
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  ~ServerProcess() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGTERM);
      if (waitFor(std::chrono::seconds(20)) < 0) {
        ::kill(pid_, SIGKILL);
        waitFor(std::chrono::seconds(5));
      }
    }
  }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  bool started() const { return port_ > 0; }
  httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(60);
    c.set_write_timeout(60);
    return c;
  }
  void signal(int sig) const { ::kill(pid_, sig); }
  /// Waits for the process to end; its exit status, -2 when killed by a signal, -1 on timeout.
  int waitFor(std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -2;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1;
  }
  std::string log() const {
    std::ifstream in(log_);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

 private:
  std::vector<std::string> listeningLines() const {
    std::ifstream in(log_);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);)
      if (line.find("\"event\":\"listening\"") != std::string::npos) lines.push_back(line);
    return lines;
  }

  std::string log_;
  pid_t pid_ = -1;
  int port_ = 0;
  bool exited_ = false;
};

}  // namespace hexcover::server::test
