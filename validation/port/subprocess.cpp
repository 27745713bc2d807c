// Child processes of the port check (subprocess.hpp).
#include "subprocess.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>

namespace ppohdem::port {
namespace {

pid_t start(const std::vector<std::string>& argv, const std::string& log_file,
            const std::vector<std::string>& launcher) {
  std::vector<std::string> words = launcher;
  words.insert(words.end(), argv.begin(), argv.end());
  std::vector<char*> args;
  for (auto& w : words) args.push_back(w.data());
  args.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    if (!log_file.empty()) {
      const int fd = ::open(log_file.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      if (fd >= 0) {
        ::dup2(fd, 1);
        ::dup2(fd, 2);
        ::close(fd);
      }
    }
    execvp(args[0], args.data());
    _exit(127);
  }
  return pid;
}

int status_of(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace

int run_program(const std::vector<std::string>& argv, const std::string& log_file,
                const std::vector<std::string>& launcher) {
  return run_programs({argv}, {log_file}, 1, launcher).front();
}

std::vector<int> run_programs(const std::vector<std::vector<std::string>>& commands,
                              const std::vector<std::string>& log_files, int jobs,
                              const std::vector<std::string>& launcher) {
  std::vector<int> result(commands.size(), -1);
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0;
  while (next < commands.size() || !running.empty()) {
    while (next < commands.size() && static_cast<int>(running.size()) < std::max(jobs, 1)) {
      running[start(commands[next], log_files.at(next), launcher)] = next;
      ++next;
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error("waitpid failed");
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    result[it->second] = status_of(status);
    running.erase(it);
  }
  return result;
}

std::string find_ppohdem_program() {
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec && std::filesystem::exists(self.parent_path() / "ppohdem")) return (self.parent_path() / "ppohdem").string();
  return "ppohdem";  // from PATH
}

}  // namespace ppohdem::port
