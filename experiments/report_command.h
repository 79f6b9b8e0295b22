#pragma once
// `gibench report DIR [--out OUT]`: the report of a results folder (image grids, probe views, plots,
// tables, one static HTML page), made by analysis/report.py with Debian's python3 (numpy,
// matplotlib, pandas, OpenImageIO); analysis/README.md says what it writes.

#include <filesystem>
#include <optional>

namespace gibench {

// The interpreter the analysis runs with (the Debian packages, never a virtual environment's).
inline constexpr const char* kAnalysisPython = "/usr/bin/python3";

// Runs `kAnalysisPython <source>/analysis/report.py DIR [--out OUT]` with this process's standard
// streams and returns its exit code (2 for bad input, as gibench's; a signal: 128 + its number).
// InputError when DIR is not a folder; std::runtime_error when the interpreter cannot be started.
int runReport(const std::filesystem::path& resultsDir, const std::optional<std::filesystem::path>& out);

}  // namespace gibench
