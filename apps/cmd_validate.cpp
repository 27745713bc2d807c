// ppohdem validate [--quick|--full] [--live] [--out FILE] [--engines a,b] [--only TEXT]
//     Runs the oracle suite (docs/validation.md) and writes ./validation-report.md (or --out).
// ppohdem validate --port | --save-baseline DIR | --against DIR | --export-scenes DIR ...
//     Port validation of chaotic runs (docs/port-validation.md).
//     The suite needs CGAL (validation/), which the `ppohdem` tool does not link: it lives in
//     the separate program `ppohdem-validate`, built with -DPPOHDEM_ENABLE_CGAL=ON (the default
//     when CGAL is found) and installed next to `ppohdem`. This command finds it there (or in
//     the build tree that built this binary) and runs it with the same arguments; its exit code
//     is returned (0 all checks passed, 1 a check failed, 2 bad input).
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::app {
namespace {

namespace fs = std::filesystem;

/// `ppohdem-validate` next to this executable, else where this build tree put it, else "".
std::string find_validate_program() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path beside = self.parent_path() / "ppohdem-validate";
    if (fs::exists(beside)) return beside.string();
  }
#ifdef PPOHDEM_VALIDATE_BUILD_PATH
  if (fs::exists(PPOHDEM_VALIDATE_BUILD_PATH)) return PPOHDEM_VALIDATE_BUILD_PATH;
#endif
  return {};
}

int run_program(const std::string& program, const std::vector<std::string>& args) {
  std::vector<char*> argv;
  std::vector<std::string> storage;
  storage.push_back(program);
  storage.insert(storage.end(), args.begin(), args.end());
  for (auto& s : storage) argv.push_back(s.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("validate: fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    execv(program.c_str(), argv.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error("validate: waitpid failed");
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 1;  // killed by a signal
}

}  // namespace

void register_validate(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "validate",
      "run every oracle check (Chung & Ooi, YADE, properties, stability), print one table, write "
      "docs/validation-report.md with plots; exit 1 if a check fails (needs ppohdem-validate, "
      "built with CGAL)");
  cmd->prefix_command();  // pass every argument through to ppohdem-validate unparsed
  cmd->footer("Options (handled by ppohdem-validate): --quick (default, CI) | --full, --live, "
              "--out FILE, --engines a,b, --only TEXT, --list, --source-dir DIR, --work-dir DIR; "
              "port validation (docs/port-validation.md): --port, --save-baseline DIR, --against DIR, "
              "--export-scenes DIR, --external RUN1 RUN2 RUN3, --jobs N, --launcher WORDS, --scale-parameter "
              "NAME=FACTOR, --scenes a,b, --refit");
  cmd->callback([cmd]() {
    const std::string program = find_validate_program();
    if (program.empty()) {
      throw InputError(
          "validate: the oracle suite program 'ppohdem-validate' was not found next to ppohdem. "
          "It is built only with CGAL: install libcgal-dev, configure with "
          "-DPPOHDEM_ENABLE_CGAL=ON and build the target ppohdem-validate");
    }
    const int rc = run_program(program, cmd->remaining());
    if (rc != 0) throw ExitStatus{rc};
  });
}

}  // namespace ppohdem::app
