// libFuzzer target: the 3MF toolpath reader (`polyaxis simulate PART.build.3mf`, the verification
// and the playback of a machine whose post is 3mf-toolpath) on arbitrary input. The first byte
// picks what the rest is: 0 the whole package; 1 the XML of its first layer part, or 2 the XML of
// its model part, put into an otherwise valid package the post writes here (so the XML readers
// are reached at once). A package is read or refused with kInvalidInput, or kMachineLimit for a
// pose no axis reaches; never a signal. The playback frames of a package read are finite and their
// clock never runs backwards.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "program_reader_checks.h"
#include "polyaxis/io/zip_archive.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/post/toolpath_3mf.h"
#include "polyaxis/process/process.h"
#include "polyaxis/verify/playback.h"
#include "polyaxis/verify/simulate.h"

using polyaxis::fuzz::require;

namespace {

using namespace polyaxis;

machine::MachineConfig toolpath_machine() {
  machine::MachineConfig m = machine::parse_machine(machine::default_machine_json(), "default").value();
  m.post = machine::PostDialect::k3mfToolpath;
  return m;
}

// A valid package: a tilted square bead on a 20 mm plate, written by the post.
const std::string& template_package() {
  static const std::string package = [] {
    mesh::Mesh plate;
    for (int k = 0; k < 8; ++k) plate.vertices.push_back({(k & 1) ? 20.0 : 0.0, (k & 2) ? 20.0 : 0.0, (k & 4) ? 2.0 : 0.0});
    plate.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    std::vector<post::ProgramPoint> pts;
    auto add = [&](core::Vec3 tip, core::Vec3 axis, bool on, double feed) {
      post::ProgramPoint p;
      p.tip_part_mm = tip, p.tool_axis_part = axis, p.process_on = on, p.feed_mm_s = feed;
      pts.push_back(p);
    };
    add({0, 0, 8}, {0, 0, 1}, false, 50.0);
    pts.back().comment_if_new_block = "approach";
    add({0, 0, 2.6}, {0, 0, 1}, false, 50.0);
    add({20, 0, 2.6}, {0, -0.5, 0.866}, true, 8.0);
    add({20, 20, 2.6}, {0.5, 0, 0.866}, true, 8.0);
    add({0, 20, 20}, {0, 0, 1}, false, 50.0);
    post::GcodeOptions o;
    o.part = &plate;
    const process::ProcessConfig p = process::parse_process(process::default_process_json(), "default").value();
    return post::write_toolpath_3mf(toolpath_machine(), p, pts, o).value();
  }();
  return package;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const machine::MachineConfig m = toolpath_machine();
  const process::ProcessConfig p = process::parse_process(process::default_process_json(), "default").value();
  const std::string_view rest(reinterpret_cast<const char*>(data + 1), size - 1);
  std::string package(rest);
  if (data[0] % 3 != 0) {
    auto edited = io::replace_zip_entry(template_package(), data[0] % 3 == 1 ? "Toolpath/Layers/layer00001.xml" : "3D/3dmodel.model", rest);
    require(edited.ok());
    package = std::move(edited.value());
  }
  polyaxis::fuzz::check_program_reader(m, p, package);
  return 0;
}
