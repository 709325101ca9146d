// The read-backs of the programs one plan_part call makes, kept by what they read. An automatic
// choice programs the same plan more than once: the choice again on planar layers takes the same
// decomposition when its regions took planar layers, and the regions it turns elsewhere, the
// relief rounds and the fallbacks to one direction then make the same programs again. Reading a
// program back (verify::simulate and verify::verify_build) is most of a program's cost; a program
// read once is not read again.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/build_model.h"
#include "polyaxis/post/program.h"
#include "polyaxis/verify/simulate.h"
#include "polyaxis/verify/verify.h"

namespace polyaxis::planner::detail {

// What a read-back reads: the G-code text, the program it is compared with (every field of every
// point) and the build model it is checked against (the plate, the table, the head and the
// prebuilt body), each as a 64-bit FNV-1a hash. The machine and the process are those of the one
// call the memo serves.
struct ReadBackKey {
  std::uint64_t gcode = 0, program = 0, build_model = 0;
  auto operator<=>(const ReadBackKey&) const = default;
};

ReadBackKey read_back_key(std::string_view gcode, const std::vector<post::ProgramPoint>& program, const machine::BuildModel& model);

struct ReadBack {
  core::Result<verify::SimulationReport> simulation;
  core::Result<verify::BuildCheck> check;
  double simulate_s = 0.0, verify_s = 0.0;  // as first measured
};

// The read-backs by key; thread-safe. Two callers reading one program at once may both read it
// (the same result); the first kept stays.
class ReadBacks {
 public:
  std::optional<ReadBack> find(const ReadBackKey& key) const;
  void keep(const ReadBackKey& key, const ReadBack& read_back);
  std::size_t size() const;

 private:
  mutable std::mutex mutex_;
  std::map<ReadBackKey, ReadBack> kept_;
};

}  // namespace polyaxis::planner::detail
