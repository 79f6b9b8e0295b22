#pragma once
// The stress suite (issue 8): stiff, extreme and degenerate scenes, each rendered by every method,
// checked for finite output and measured against an analytic value, another case's render, or an
// expected refusal. `gibench stress` runs configs/stress/ and prints the table;
// configs/stress/README.md describes the case files.

#include "core/config/params.h"

#include <filesystem>
#include <string>
#include <vector>

namespace gibench {

// One case rendered by one method.
struct StressRow {
    std::string caseName;
    std::string method;
    bool finite = true;      // every pixel of every layer, and every metric
    bool passed = false;     // finite, and the expectation met
    std::string measure;     // what `value` is: "mean", "mean ratio", "refused", ...
    double value = 0.0;
    double expected = 0.0;
    bool compared = false;   // `expected` holds a value to compare with
    double tolerance = 0.0;  // |value - expected| allowed; for the path tracer derived from its variance
    Json stats;              // the method's frame counters (probes, refused inserts, rays, ...)
    uint64_t fireflies = 0;  // pixels brighter than 100x the image's median luminance
    double seconds = 0.0;
    std::string note;        // the refusal's message, or why a row failed
};

// configs/stress/ of the source tree.
std::filesystem::path defaultStressCases();

// Every *.json case in `folder` (sorted by name) by every method it names; `onlyMethods`, when
// not empty, keeps those. Throws InputError for a case file that is not a valid case.
std::vector<StressRow> runStressSuite(const std::filesystem::path& folder, const std::vector<std::string>& onlyMethods,
                                      bool showProgress);

// The rows as a Markdown table, one line per case x method.
std::string stressTable(const std::vector<StressRow>& rows);
Json stressJson(const std::vector<StressRow>& rows);

}  // namespace gibench
