// The read-backs one plan_part call keeps (planner/read_backs.h): a program is known again by its
// G-code, its program points and its build model, and by nothing less.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "planner/read_backs.h"

namespace polyaxis::planner::detail {
namespace {

std::vector<post::ProgramPoint> some_program(int n) {
  std::vector<post::ProgramPoint> program;
  for (int i = 0; i < n; ++i) {
    post::ProgramPoint p;
    p.tip_part_mm = {0.5 * i, -0.25 * i, 0.1 * (i / 4)};
    p.tool_axis_part = {0.0, 0.01 * i, 1.0};
    p.feed_mm_s = 10.0 + i % 3;
    p.process_on = i % 5 != 0;
    p.layer = static_cast<std::uint32_t>(i / 4);
    p.region = static_cast<std::uint32_t>(i / 8);
    if (i % 4 == 0) p.comment_if_new_block = "perimeter";
    program.push_back(p);
  }
  return program;
}

machine::BuildModel some_model() {
  machine::BuildModel m;
  m.substrate = {-30.0, -20.0, 30.0, 20.0, 0.0, 10.0};
  m.table_centre_mm = {1.0, 2.0, 0.0};
  m.prebuilt.spacing_mm = 0.4;
  m.prebuilt.surface_mm = {{0, 0, 1}, {1, 0, 1}};
  m.prebuilt.normals = {{0, 0, 1}, {0, 0, 1}};
  return m;
}

TEST(ReadBackKey, TheSameInputsGiveTheSameKey) {
  const std::string gcode = "G1 X1 Y2 Z3\nG1 X2\n";
  EXPECT_EQ(read_back_key(gcode, some_program(40), some_model()), read_back_key(std::string(gcode), some_program(40), some_model()));
}

TEST(ReadBackKey, AnyChangeOfWhatIsReadChangesTheKey) {
  const std::string gcode = "G1 X1 Y2 Z3\nG1 X2\n";
  const auto program = some_program(40);
  const auto model = some_model();
  const ReadBackKey key = read_back_key(gcode, program, model);
  EXPECT_NE(key, read_back_key("G1 X1 Y2 Z3\nG1 X2.001\n", program, model));
  EXPECT_NE(key, read_back_key(gcode, some_program(39), model));
  // Each field of one point.
  const std::vector<void (*)(post::ProgramPoint&)> changes = {
      [](post::ProgramPoint& p) { p.tip_part_mm.z += 1e-9; },
      [](post::ProgramPoint& p) { p.tool_axis_part.x += 1e-12; },
      [](post::ProgramPoint& p) { p.feed_mm_s *= 2.0; },
      [](post::ProgramPoint& p) { p.process_on = !p.process_on; },
      [](post::ProgramPoint& p) { ++p.layer; },
      [](post::ProgramPoint& p) { ++p.region; },
      [](post::ProgramPoint& p) { p.comment_if_new_block += " "; },
      [](post::ProgramPoint& p) { p.c_unwind = !p.c_unwind; },
  };
  for (std::size_t k = 0; k < changes.size(); ++k) {
    auto changed = program;
    changes[k](changed[17]);
    EXPECT_NE(key, read_back_key(gcode, changed, model)) << "change " << k;
  }
  // The build model: the plate, the table and the prebuilt body.
  auto plate = model;
  plate.substrate.x_max_mm += 0.5;
  EXPECT_NE(key, read_back_key(gcode, program, plate));
  auto table = model;
  table.table_centre_mm.y = -2.0;
  EXPECT_NE(key, read_back_key(gcode, program, table));
  auto prebuilt = model;
  prebuilt.prebuilt.surface_mm[1].z = 1.5;
  EXPECT_NE(key, read_back_key(gcode, program, prebuilt));
  auto none = model;
  none.prebuilt = {};
  EXPECT_NE(key, read_back_key(gcode, program, none));
}

TEST(ReadBacks, KeepsTheFirstReadBackOfAKeyAndFindsOnlyWhatWasKept) {
  ReadBacks memo;
  const ReadBackKey a{1, 2, 3}, b{1, 2, 4};
  EXPECT_FALSE(memo.find(a));
  verify::SimulationReport sim;
  sim.moves = 12;
  verify::BuildCheck check;
  check.samples = 34;
  memo.keep(a, ReadBack{sim, check, 0.5, 0.25});
  sim.moves = 99;
  memo.keep(a, ReadBack{sim, check, 9.0, 9.0});  // the first kept stays
  memo.keep(b, ReadBack{core::make_error(core::ErrorCode::kMachineLimit, "C past its end stop"), check, 0.1, 0.1});
  EXPECT_EQ(memo.size(), 2u);
  const auto found = memo.find(a);
  ASSERT_TRUE(found);
  ASSERT_TRUE(found->simulation);
  EXPECT_EQ(found->simulation.value().moves, 12u);
  ASSERT_TRUE(found->check);
  EXPECT_EQ(found->check.value().samples, 34u);
  EXPECT_EQ(found->simulate_s, 0.5);
  const auto failed = memo.find(b);
  ASSERT_TRUE(failed);
  ASSERT_FALSE(failed->simulation);
  EXPECT_EQ(failed->simulation.error().code, core::ErrorCode::kMachineLimit);
  EXPECT_FALSE(memo.find(ReadBackKey{2, 2, 3}));
}

}  // namespace
}  // namespace polyaxis::planner::detail
