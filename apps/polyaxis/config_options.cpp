#include "config_options.h"

namespace polyaxis::app {

void add_config_options(CLI::App& command, ConfigOptions& options, bool with_process) {
  command.add_option("--machine", options.machine_path, "Machine file (JSON, see examples/machines); default: 5-axis A/C DED");
  if (with_process) command.add_option("--process", options.process_path, "Process file (JSON, see examples/processes); default: ded_steel");
  command.add_option("--set", options.sets, "Override a field: machine.limits.c.max=360 or process.bead_width_mm=3 (repeatable)");
}

}  // namespace polyaxis::app
