#include "huge_pages.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <string_view>

namespace polyaxis::app {
namespace {

constexpr const char* kTunable = "glibc.malloc.hugetlb";

// Inputs smaller than this gain less from huge pages than the re-execution costs (about 4 ms).
constexpr long long kMinInputBytes = 16LL << 20;  // a binary STL of about 330k triangles

bool names_a_large_file(char** argv) {
  for (char** a = argv + 1; *a != nullptr; ++a) {
    struct stat st {};
    if (stat(*a, &st) == 0 && S_ISREG(st.st_mode) && st.st_size >= kMinInputBytes) return true;
  }
  return false;
}

// `plan` makes a program and reads it back: its samples, material index and G-code run to hundreds
// of MB whatever the mesh's size (bumpy_82k, a 4 MB mesh: 4.9M deposit samples).
bool plans(char** argv) {
  for (char** a = argv + 1; *a != nullptr; ++a) {
    if (std::string_view(*a) == "plan") return true;
  }
  return false;
}

bool huge_pages_on_request() {
  std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  return std::getline(mode, line) && line.find("[madvise]") != std::string::npos;
}

}  // namespace

void use_huge_pages(char** argv) {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string current = tunables != nullptr ? tunables : "";
  if (current.find(kTunable) != std::string::npos || !(names_a_large_file(argv) || plans(argv)) || !huge_pages_on_request()) return;
  const std::string wanted = (current.empty() ? "" : current + ":") + kTunable + "=1";
  if (setenv("GLIBC_TUNABLES", wanted.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // Not possible (no /proc): run on without, and leave the environment as it was.
  if (tunables != nullptr) {
    setenv("GLIBC_TUNABLES", current.c_str(), 1);
  } else {
    unsetenv("GLIBC_TUNABLES");
  }
}

}  // namespace polyaxis::app
