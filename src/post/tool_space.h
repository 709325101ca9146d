// The block sequence of the posts whose programs give the tool's pose over the part and leave the
// axes to the controller (Sinumerik TRAORI, ABB RAPID in a work object on the positioner): one
// loop decides the moves (first move, turns in place, feeds slowed to the axes' maxima, deposit
// blocks the axes would stall split into a turn in place and the bead); a dialect writes them.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/post/program.h"
#include "polyaxis/process/process.h"

namespace polyaxis::post::detail {

// The kind of a block the loop asks for.
enum class BlockKind {
  kFirst,       // to the first point, from wherever the machine is
  kTurnInPlace, // the tool turns, the tip stays: process off
  kFeed,        // at a feed, with the process as ProgramPoint::process_on says
};

class ToolSpaceDialect {
 public:
  virtual ~ToolSpaceDialect() = default;
  // The axes as the program's reader will see them at PT (the words as written), the solution
  // branch and C turn following PREVIOUS (null for the first point).
  virtual core::Result<machine::MachinePose> pose_of(const ProgramPoint& pt, const machine::MachinePose* previous) = 0;
  virtual void header() = 0;
  virtual void comment(const ProgramPoint& pt) = 0;
  // PT is the block's end; POSE its axes; FEED_MM_S the tip's speed over the part (kFeed only);
  // NEXT the program's next point (null at the end), for dialects that close a bead on its last move.
  virtual core::Status block(BlockKind kind, const ProgramPoint& pt, const machine::MachinePose& pose, double feed_mm_s,
                             const ProgramPoint* next) = 0;
  virtual void switch_process(bool on) = 0;
  virtual void footer(std::uint64_t stall_splits) = 0;
  virtual std::size_t size() const = 0;
};

// What the G-code dialects of the loop share (Sinumerik TRAORI, ISO TCP): the program's text by
// lines, the process switched by the process file's codes with a dwell after switching on, the
// feed word where the feed changes, and the writer that checks the machine has rotary axes.
class GcodeDialect : public ToolSpaceDialect {
 public:
  GcodeDialect(const machine::MachineConfig& m, const process::ProcessConfig& p, const GcodeOptions& o) : m_(m), p_(p), o_(o) {}
  void switch_process(bool on) override;
  std::size_t size() const override { return out_.size(); }
  std::string take() { return std::move(out_); }

 protected:
  // The dwell of SECONDS in the dialect ("G4 F0.5000", "G4 X0.5000").
  virtual std::string dwell_block(double seconds) const = 0;
  void line(std::string_view s) {
    out_ += s;
    out_ += '\n';
  }
  // " F<mm/min>" for FEED_MM_S (as the loop rounded it down) where it differs from the last F
  // written, else ""; counts the feed block.
  std::string feed_word(double feed_mm_s);

  const machine::MachineConfig& m_;
  const process::ProcessConfig& p_;
  const GcodeOptions& o_;

 private:
  std::string out_;
  bool on_ = false;
  std::optional<double> last_feed_;
};

// Writes POINTS through DIALECT (a GcodeDialect of a post named WHAT that orients the tool):
// kInfeasible for an empty program, kUsage on a machine without rotary axes, else
// write_tool_space's errors.
core::Result<std::string> write_oriented(std::string_view what, const machine::MachineConfig& machine, std::span<const ProgramPoint> points,
                                         const GcodeOptions& options, GcodeDialect& dialect);

// The tip and the unit tool vector as 4 and 6 decimals write them (written_vector normalised again;
// rounded_vector the 6-decimal components themselves, which the dialects print).
core::Vec3 written_tip(core::Vec3 p);
core::Vec3 written_vector(core::Vec3 a);
core::Vec3 rounded_vector(core::Vec3 a);

// "move to point I (layer L region R, tip (...), axis (...))", for messages.
std::string where(std::size_t i, const ProgramPoint& p);

// Printable ASCII for a comment.
std::string comment_text(std::string_view s);

// Writes POINTS through DIALECT. Errors: kInternal for a non-finite value or a feed ≤ 0, the
// dialect's pose_of and block errors (kMachineLimit) naming the point, kOutput above
// OPTIONS.max_output_bytes.
core::Status write_tool_space(const machine::MachineConfig& machine, std::span<const ProgramPoint> points, const GcodeOptions& options,
                              ToolSpaceDialect& dialect);

}  // namespace polyaxis::post::detail
