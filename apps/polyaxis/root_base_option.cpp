#include "root_base_option.h"

namespace polyaxis::app {

void add_root_base_option(CLI::App& cmd, std::string& text) {
  cmd.add_option("--root-base", text,
                 "Where the root region stands: z-min (the lowest point), a planar face id (analysis.json \"faces\"), or a plane "
                 "PX,PY,PZ,NX,NY,NZ (a point and the root's build direction); default: found from the centroidal axis");
}

}  // namespace polyaxis::app
