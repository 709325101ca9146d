// ABB RAPID modules for a robot carrying the torch over a two-axis positioner (issue 15, item 2;
// machine/robot.h has the cell). One coordinated work object on the positioner's mechanical unit
// holds every robtarget, so the controller moves the robot and the positioner together and the
// TCP's speed is its speed over the part:
//
//   MODULE polyaxis_plan
//     ! polyaxis: machine ..., robot ..., process ..., post abb-rapid
//     PERS tooldata tPolyaxis := [TRUE,[[x,y,z],[q1,q2,q3,q4]],[mass,[0,0,z/2],[1,0,0,0],0,0,0]];
//     PERS wobjdata wPolyaxis := [FALSE,FALSE,"STN1",[[0,0,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
//     PROC main()
//       ConfJ \On; ConfL \Off; SingArea \Wrist; ActUnit STN1;
//       MoveJ [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[A,C,9E+09,9E+09,9E+09,9E+09]],[v,vo,vl,vr],fine,tPolyaxis\WObj:=wPolyaxis;
//       ! layer N region R perimeter
//       SetDO doProcess,1;  WaitTime 0.5;          (or ArcLStart / ArcL / ArcLEnd with seam and weld data)
//       MoveL [...],[v,vo,vl,vr],z0,tPolyaxis\WObj:=wPolyaxis;
//       ...
//       SetDO doProcess,0;  DeactUnit STN1;
//     ENDPROC
//   ENDMODULE
//
// - robtarget: the TCP's position (mm, 4 decimals) and orientation (unit quaternion, 6 decimals) in
//   the work object, whose object frame is polyaxis's part frame on the positioner's plate (the
//   user frame calibrated on STN1 must be the part frame at A = C = 0); z points toward the work,
//   so the tool axis is −z. eax_a and eax_b are the positioner's tilt and turn (degrees, 4
//   decimals, the machine file's A/B and C). confdata is the robot's own inverse kinematics'
//   configuration (robot.h), solved for every target and kept along the program.
// - speeddata: v_tcp the tip's speed over the part (mm/s, rounded down to 0.001), lowered where the
//   positioner would turn faster than feed.rotary_max_deg_min or the TCP move faster than
//   feed.linear_max_mm_min; v_ori and v_reax the rotary maximum, v_leax the linear one.
// - zones: z0 along the path, fine where the process switches and at the end.
// - the process: the process file's "rapid": SetDO on its signal with a WaitTime of dwell_on_s, or
//   ArcLStart (moves to the bead's start and strikes the arc there), ArcL, ArcLEnd (ends it at the
//   last point) with its seamdata and welddata.
// - a move on which the arm must change configuration is a MoveJ, and only with the process off; a
//   target the arm cannot reach in its joint limits is kMachineLimit naming the point and why.
#pragma once

#include <span>
#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/post/program.h"
#include "polyaxis/process/process.h"

namespace polyaxis::post {

// The module for POINTS on a robot cell (MACHINE.robot set). Errors as write_traori's, and
// kMachineLimit for a target the arm cannot reach or a configuration change inside a bead.
core::Result<std::string> write_rapid(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                      std::span<const ProgramPoint> points, const GcodeOptions& options = {});

// RAPID's "no external axis" value (9E+09) and the tool and work object names the module declares.
inline constexpr double kRapidNoAxis = 9e9;
inline constexpr const char* kRapidTool = "tPolyaxis";
inline constexpr const char* kRapidWobj = "wPolyaxis";

}  // namespace polyaxis::post
