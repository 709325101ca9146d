// The files of one lamination as `polyaxis laminate` writes them: lamination.json, report.html,
// sheet_<n>.svg and sheet_<n>.ngc per sheet, as one set (io::OutputSet), the programs last.
#pragma once

#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/lamination/job.h"

namespace polyaxis::report {

// Writes JOB's files under DIR (made when missing), all or nothing: kOutput naming the file when
// one cannot be written, and nothing of this run is left under the final names. JSON, when given,
// receives lamination.json's text.
core::Status write_lamination_files(const std::string& dir, const lamination::LaminateJob& job, std::string* json = nullptr);

}  // namespace polyaxis::report
