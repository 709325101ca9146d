// report.html: one self-contained page that shows a plan in 3-D (SPEC §2.10). The page is the
// viewer's JavaScript (viewer/, bundled with three.js at build time and compiled into the
// program) and the plan's data as JSON (schema "polyaxis-view/1" in viewer/README.md).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "polyaxis/report/plan_view.h"

namespace polyaxis::report {

// A plan with more program points than this is shown decimated: within each run of deposit or
// travel moves every k-th point is kept, with the run's ends, so the page stays interactive.
inline constexpr std::size_t kViewerMaxPoints = 400'000;
// The machine playback keeps at most this many G-code blocks (or max_points when smaller; all when
// max_points is 0): every k-th and every one where the process, the layer or the motion mode
// changes. 33 bytes a block.
inline constexpr std::size_t kViewerMaxFrames = 200'000;

struct HtmlOptions {
  std::size_t max_points = kViewerMaxPoints;
};

// The viewer bundle compiled into the program: viewer/ bundled by esbuild at build time, or
// report/viewer_absent.js (a note that the page has no 3-D view) in a -DPOLYAXIS_VIEWER=OFF build.
std::string_view viewer_bundle();

// The data object the viewer reads (JSON text, schema "polyaxis-view/1").
std::string view_data_json(const PlanView& view, const HtmlOptions& options = {});

// The whole page: VIEW's data and BUNDLE (normally viewer_bundle()).
std::string report_html(const PlanView& view, std::string_view bundle, const HtmlOptions& options = {});

}  // namespace polyaxis::report
