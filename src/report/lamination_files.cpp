#include "polyaxis/report/lamination_files.h"

#include <fmt/format.h>

#include "polyaxis/io/output_set.h"

namespace polyaxis::report {

core::Status write_lamination_files(const std::string& dir, const lamination::LaminateJob& job, std::string* json) {
  auto set = io::OutputSet::open(dir);
  if (!set) return set.error();
  const lamination::Lamination& l = job.lamination;
  std::string text = lamination::lamination_json(l, job.sheets, job.meta);
  if (auto s = set.value().add("lamination.json", text); !s) return s;
  if (auto s = set.value().add("report.html", lamination::lamination_html(l, job.sheets, job.process, job.meta)); !s) return s;
  for (const auto& sheet : job.sheets) {
    if (auto s = set.value().add(fmt::format("sheet_{}.svg", sheet.index), lamination::sheet_svg(l, sheet, job.process)); !s) return s;
  }
  for (std::size_t i = 0; i < job.programs.size(); ++i) {
    if (auto s = set.value().add(job.meta.programs[i], job.programs[i], io::Durability::kSynced); !s) return s;
  }
  if (auto s = set.value().commit(); !s) return s;
  if (json) *json = std::move(text);
  return {};
}

}  // namespace polyaxis::report
