// polyaxis-cad-import: the one program that links OpenCASCADE. read_cad (src/io/cad.cpp) runs it
// with fork() + execv() under RLIMIT_AS / RLIMIT_CPU and a wall-clock limit, with stdout and stderr
// on /dev/null, so that a crash, hang or memory blow-up inside OpenCASCADE on a malformed file
// cannot take the CLI down (RELIABILITY.md F16), and so that the CLI itself does not pay ~30 ms of
// dynamic loading for OpenCASCADE on every start.
//
//   polyaxis-cad-import --format step|iges --chordal-mm X --angular-deg Y --result-fd N [--] PATH
//
// Writes the result to the inherited descriptor N (an unlinked file, layout in io/cad_import.h)
// and exits with a cad_protocol::kExit* code. Not meant to be run by hand.
//
// Test hooks: POLYAXIS_CAD_TEST_CRASH=1 makes it raise SIGSEGV before importing,
// POLYAXIS_CAD_TEST_HANG=1 makes it sleep forever, so tests can check the crash and timeout paths
// without a file that actually crashes OpenCASCADE.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

#include "io/cad_import.h"

namespace {

namespace protocol = polyaxis::io::cad_protocol;
using polyaxis::io::Format;

bool env_flag(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr && std::string_view(value) == "1";
}

std::optional<double> parse_double(std::string_view text) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

std::optional<int> parse_fd(std::string_view text) {
  int value = -1;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < 0) return std::nullopt;
  return value;
}

[[noreturn]] void usage(const char* message) {
  const std::string line = std::string("polyaxis-cad-import: ") + message +
                           "\nusage: polyaxis-cad-import --format step|iges --chordal-mm X --angular-deg Y "
                           "--result-fd N [--] PATH\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, line.data(), line.size());
  ::_exit(protocol::kExitUsage);
}

}  // namespace

int main(int argc, char** argv) {
  // A crash must reach read_cad as a signal: undo any handler a sanitizer runtime installed.
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);

  std::optional<Format> format;
  std::optional<double> chordal_mm;
  std::optional<double> angular_deg;
  std::optional<int> result_fd;
  std::optional<std::string> path;
  bool options_done = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (options_done || (!arg.empty() && arg[0] != '-')) {
      if (path) usage("more than one PATH");
      path = std::string(arg);
    } else if (arg == "--") {
      options_done = true;
    } else if (arg == "--format" && has_value) {
      const std::string_view value = argv[++i];
      if (value == "step") {
        format = Format::kStep;
      } else if (value == "iges") {
        format = Format::kIges;
      } else {
        usage("--format must be step or iges");
      }
    } else if (arg == "--chordal-mm" && has_value) {
      if (!(chordal_mm = parse_double(argv[++i]))) usage("--chordal-mm needs a number");
    } else if (arg == "--angular-deg" && has_value) {
      if (!(angular_deg = parse_double(argv[++i]))) usage("--angular-deg needs a number");
    } else if (arg == "--result-fd" && has_value) {
      if (!(result_fd = parse_fd(argv[++i]))) usage("--result-fd needs a descriptor number");
    } else {
      usage(("unexpected argument " + std::string(arg)).c_str());
    }
  }
  if (!format || !chordal_mm || !angular_deg || !result_fd || !path) usage("missing argument");
  if (::fcntl(*result_fd, F_GETFD) == -1) usage("--result-fd is not an open descriptor");

  if (env_flag("POLYAXIS_CAD_TEST_CRASH")) std::raise(SIGSEGV);
  if (env_flag("POLYAXIS_CAD_TEST_HANG")) {
    for (;;) ::pause();
  }

  // _exit: nothing to flush, and OpenCASCADE's static destructors (and a sanitizer's leak check
  // over them) are no business of the result.
  ::_exit(polyaxis::io::import_cad_to_fd(*result_fd, *path, *format, *chordal_mm, *angular_deg));
}
