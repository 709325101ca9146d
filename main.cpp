#include <cstdio>
#include <cmath>
#include <cstdint>
#include "polyaxis/machine/build_model.h"
#include "polyaxis/process/process.h"
namespace polyaxis::machine { namespace dbgns {
double lowest_on_face(const struct Frustum& f, int i, double val, double lo, double hi);
}}
using namespace polyaxis; using namespace polyaxis::machine;
int main(){
  MachineConfig m = parse_machine(default_machine_json(), "m").value();
  auto p = process::parse_process(process::default_process_json(), "p").value();
  BuildModel model = make_build_model(m, p, -20, -30, 20, 30);
  model.table_centre_mm = {1e9,0,0};
  std::uint64_t seed = 12345; const double kPi=M_PI;
  auto uniform = [&](double lo, double hi) { seed = seed * 6364136223846793005ULL + 1442695040888963407ULL; return lo + (hi - lo) * static_cast<double>(seed >> 11) / 9007199254740992.0; };
  for (int trial=0; trial<150; ++trial){
    const Vec3 tip{uniform(-60, 60), uniform(-70, 70), uniform(-5, 30)};
    const double tilt = uniform(0, 100) * kPi / 180.0, azimuth = uniform(0, 2 * kPi);
    const Vec3 axis{std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt)};
    if (trial!=131) continue;
    printf("tilt %f az %f axis %f %f %f\n", tilt*180/kPi, azimuth*180/kPi, axis.x,axis.y,axis.z);
    printf("exact %f\n", head_clearance_mm(model, tip, axis));
  }
}
