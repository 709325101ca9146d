// The post the machine file chooses (machine::PostDialect), its file extension, and the output
// set's id in its program.
#include <fmt/format.h>

#include "polyaxis/post/gcode.h"
#include "polyaxis/post/iso_tcp.h"
#include "polyaxis/post/rapid.h"
#include "polyaxis/post/toolpath_3mf.h"
#include "polyaxis/post/traori.h"

namespace polyaxis::post {

core::Result<std::string> write_program(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                        std::span<const ProgramPoint> points, const GcodeOptions& options) {
  switch (machine.post) {
    case machine::PostDialect::kSiemensTraori: return write_traori(machine, process, points, options);
    case machine::PostDialect::kAbbRapid: return write_rapid(machine, process, points, options);
    case machine::PostDialect::k3mfToolpath: return write_toolpath_3mf(machine, process, points, options);
    case machine::PostDialect::kIsoTcp: return write_iso_tcp(machine, process, points, options);
    case machine::PostDialect::kLinuxCnc: break;
  }
  return write_gcode(machine, process, points, options);
}

std::string_view program_extension(const machine::MachineConfig& machine) { return machine::program_extension(machine.post); }

core::Result<std::string> with_set_id(const machine::MachineConfig& machine, std::string program, std::string_view id) {
  if (machine.post == machine::PostDialect::k3mfToolpath) return stamp_toolpath_3mf(program, id);
  // The first comment, `(polyaxis: …)` → `(polyaxis: …, set ID)` (Sinumerik's `; polyaxis: …`,
  // RAPID's `! polyaxis: …` under MODULE, ISO's under its leading `%`): the line count stays, so
  // the lines the report names are unchanged.
  if (program.rfind("%\n", 0) == 0) {
    auto rest = with_set_id(machine, program.substr(2), id);
    if (rest) rest.value().insert(0, "%\n");
    return rest;
  }
  const std::size_t eol = program.find('\n');
  if (program.rfind("MODULE ", 0) == 0 && eol != std::string::npos) {
    const std::size_t eol2 = program.find('\n', eol + 1);
    if (eol2 != std::string::npos) return program.insert(eol2, fmt::format(", set {}", id));
  }
  if (eol != std::string::npos && eol > 0 && program[0] == ';') return program.insert(eol, fmt::format(", set {}", id));
  if (eol == std::string::npos || eol == 0 || program[eol - 1] != ')' || program[0] != '(') return fmt::format("(polyaxis set {})\n", id) + program;
  return program.insert(eol - 1, fmt::format(", set {}", id));
}

}  // namespace polyaxis::post
