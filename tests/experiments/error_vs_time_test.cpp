// analysis/error_vs_time.py over an experiment folder: which folders count as runs, and the
// equal-time, crossover and recovery tables, checked on runs with known error curves.

#include "support/temp_folder.h"

#include "core/config/params.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace gibench {
namespace {

// A finished run's files as the analysis reads them: frames finishing at each point's cumulative
// seconds with its total relMSE (indirect not measured).
void writeCurve(const TempFolder& dir, const std::string& folder, const std::string& method,
                const std::vector<std::pair<double, double>>& points) {
    dir.write(folder + "/manifest.json", Json{{"config", {{"method", {{"name", method}}}}}}.dump());
    std::string lines;
    double previous = 0.0;
    for (std::size_t f = 0; f < points.size(); ++f) {
        const auto [cumulative, relmse] = points[f];
        const Json frame = {{"frame", f},
                            {"seconds", cumulative - previous},
                            {"cumulative_seconds", cumulative},
                            {"stages", {{"path_trace", cumulative - previous}}},
                            {"stats", Json::object()},
                            {"error", {{"total", {{"relmse", relmse}}}, {"indirect", nullptr}}}};
        lines += frame.dump() + "\n";
        previous = cumulative;
    }
    dir.write(folder + "/frames.jsonl", lines);
}

// One measured frame.
void writeRun(const TempFolder& dir, const std::string& folder, const std::string& method, double relmse) {
    writeCurve(dir, folder, method, {{0.5, relmse}});
}

// The path tracer's curve of these tests: a frame every 0.1 s up to 1 s, relMSE 1 / frames so far.
std::vector<std::pair<double, double>> pathTracedCurve() {
    std::vector<std::pair<double, double>> points;
    for (int k = 1; k <= 10; ++k) points.emplace_back(k / 10.0, 1.0 / k);
    return points;
}

void runAnalysis(const TempFolder& dir) {
    const std::string command = "/usr/bin/python3 " + std::string(GIBENCH_SOURCE_DIR) + "/analysis/error_vs_time.py " +
                                (dir / "experiment").string() + " > " + (dir / "log.txt").string() + " 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
}

using CsvRow = std::map<std::string, std::string>;

// The rows of a CSV without quoted fields (the analysis' tables have none), by column name.
std::vector<CsvRow> readCsv(const std::filesystem::path& file) {
    const auto split = [](const std::string& line) {
        std::vector<std::string> cells;
        std::stringstream stream(line);
        for (std::string cell; std::getline(stream, cell, ',');) cells.push_back(cell);
        if (!line.empty() && line.back() == ',') cells.emplace_back();
        return cells;
    };
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> header = split(line);
    std::vector<CsvRow> rows;
    while (std::getline(in, line)) {
        const std::vector<std::string> cells = split(line);
        CsvRow row;
        for (std::size_t c = 0; c < header.size(); ++c) row[header[c]] = c < cells.size() ? cells[c] : "";
        rows.push_back(row);
    }
    return rows;
}

// The one row whose columns have these values (numbers compared as numbers: "1.0" is 1).
CsvRow rowWhere(const std::vector<CsvRow>& rows, const CsvRow& match) {
    std::vector<CsvRow> found;
    for (const CsvRow& row : rows) {
        bool all = true;
        for (const auto& [column, value] : match) {
            const std::string& cell = row.at(column);
            const bool number = !value.empty() && (std::isdigit(static_cast<unsigned char>(value[0])) != 0);
            all = all && (number ? !cell.empty() && std::stod(cell) == std::stod(value) : cell == value);
        }
        if (all) found.push_back(row);
    }
    EXPECT_EQ(found.size(), 1u) << "rows matching the " << match.size() << " columns asked";
    return found.empty() ? CsvRow{} : found.front();
}

double number(const CsvRow& row, const std::string& column) { return std::stod(row.at(column)); }

TEST(ErrorVsTime, HiddenStagingAndOldFoldersAreNotRuns) {
    TempFolder dir;
    writeRun(dir, "experiment/run", "path_traced", 0.25);
    // What a run being written, or a killed one, leaves: complete-looking, but not results.
    writeRun(dir, "experiment/.staging-run-123-0", "path_traced", 0.5);
    writeRun(dir, "experiment/.old-run-123-0", "path_traced", 0.75);
    runAnalysis(dir);
    std::ifstream summary(dir / "experiment" / "summary.csv");
    std::string header, row, extra;
    std::getline(summary, header);
    std::getline(summary, row);
    EXPECT_FALSE(std::getline(summary, extra)) << "a second run: " << extra;
    EXPECT_EQ(row.rfind("run,path_traced,1,0.5,0.25,", 0), 0u) << row;
}

TEST(ErrorVsTime, EqualTimeTakesTheLastFrameFinishedByEachBudget) {
    TempFolder dir;
    writeCurve(dir, "experiment/pt", "path_traced", pathTracedCurve());
    std::vector<std::pair<double, double>> cache;  // a frame every 0.05 s, relMSE 0.1 / frames so far
    for (int k = 1; k <= 20; ++k) cache.emplace_back(k / 20.0, 0.1 / k);
    writeCurve(dir, "experiment/cache", "mamba", cache);
    runAnalysis(dir);
    const std::vector<CsvRow> rows = readCsv(dir / "experiment" / "equal_time.csv");
    // Budgets 0.1, 0.25, 0.5 and 1 s: none past the longest run; 2 runs, 2 layers.
    EXPECT_EQ(rows.size(), 4u * 2u * 2u);

    // By 0.25 s the path tracer has finished 2 frames and the cache 5 (the one finishing at it counts).
    EXPECT_NEAR(number(rowWhere(rows, {{"run", "pt"}, {"layer", "total"}, {"budget_s", "0.25"}}), "relmse"), 0.5, 1e-12);
    const CsvRow at025 = rowWhere(rows, {{"run", "cache"}, {"layer", "total"}, {"budget_s", "0.25"}});
    EXPECT_NEAR(number(at025, "relmse"), 0.02, 1e-12);
    EXPECT_NEAR(number(at025, "ratio_to_path_traced"), 0.04, 1e-12);
    const CsvRow at1 = rowWhere(rows, {{"run", "cache"}, {"layer", "total"}, {"budget_s", "1"}});
    EXPECT_NEAR(number(at1, "relmse"), 0.005, 1e-12);
    EXPECT_NEAR(number(at1, "ratio_to_path_traced"), 0.05, 1e-12);
    // No ratio for the path tracer itself, no error for a layer never measured.
    EXPECT_EQ(rowWhere(rows, {{"run", "pt"}, {"layer", "total"}, {"budget_s", "1"}}).at("ratio_to_path_traced"), "");
    EXPECT_EQ(rowWhere(rows, {{"run", "cache"}, {"layer", "indirect"}, {"budget_s", "1"}}).at("relmse"), "");
}

TEST(ErrorVsTime, CrossoverIsTheLastCommonTimeBeforeTheCacheFirstStopsBeatingThePathTracer) {
    TempFolder dir;
    writeCurve(dir, "experiment/pt", "path_traced", pathTracedCurve());
    // A frame every 0.05 s at 0.8x the path tracer's error at that time up to 0.5 s (0.5x at 0.3 s),
    // 1.25x after; before its first frame at 0.1 s, as against 1.
    std::vector<std::pair<double, double>> winsThenLoses;
    for (int k = 1; k <= 20; ++k) {
        const int traced = k / 2;  // path-traced frames finished by k / 20 s
        winsThenLoses.emplace_back(k / 20.0, (k == 6 ? 0.5 : k <= 10 ? 0.8 : 1.25) / (traced > 0 ? traced : 1));
    }
    writeCurve(dir, "experiment/wins_then_loses", "mamba", winsThenLoses);
    // Twice the path tracer's error at the same times: never below it.
    std::vector<std::pair<double, double>> never, early;
    for (int k = 1; k <= 10; ++k) never.emplace_back(k / 10.0, 2.0 / k);
    writeCurve(dir, "experiment/never", "dense_grid", never);
    // As bad, but each frame 0.05 s earlier: its first, before the path tracer has any, beats it.
    for (int k = 1; k <= 10; ++k) early.emplace_back(k / 10.0 - 0.05, 2.0 / k);
    writeCurve(dir, "experiment/early", "hash_grid", early);
    runAnalysis(dir);
    const std::vector<CsvRow> rows = readCsv(dir / "experiment" / "crossover.csv");
    EXPECT_EQ(rows.size(), 3u * 2u);  // the caches, both layers

    const CsvRow wins = rowWhere(rows, {{"run", "wins_then_loses"}, {"layer", "total"}});
    EXPECT_DOUBLE_EQ(number(wins, "common_end_s"), 1.0);
    EXPECT_DOUBLE_EQ(number(wins, "beats_pt_up_to_s"), 0.5);  // at 0.55 s: 1.25 / 5 against 1 / 5
    EXPECT_NEAR(number(wins, "best_ratio"), 0.5, 1e-12);
    EXPECT_DOUBLE_EQ(number(wins, "best_ratio_at_s"), 0.3);
    EXPECT_NEAR(number(wins, "ratio_at_1s"), 1.25, 1e-12);

    const CsvRow lost = rowWhere(rows, {{"run", "never"}, {"layer", "total"}});
    EXPECT_EQ(lost.at("beats_pt_up_to_s"), "");
    EXPECT_NEAR(number(lost, "best_ratio"), 2.0, 1e-12);

    const CsvRow first = rowWhere(rows, {{"run", "early"}, {"layer", "total"}});
    EXPECT_DOUBLE_EQ(number(first, "beats_pt_up_to_s"), 0.05);
    EXPECT_DOUBLE_EQ(number(first, "common_end_s"), 0.95);
    EXPECT_EQ(first.at("ratio_at_1s"), "");  // past the shorter run's end

    // Nothing to compare in a layer neither run measured.
    EXPECT_EQ(rowWhere(rows, {{"run", "wins_then_loses"}, {"layer", "indirect"}}).at("beats_pt_up_to_s"), "");
}

TEST(ErrorVsTime, RecoveryHasARowPerRunEventAndLayerWithNullsEmpty) {
    TempFolder dir;
    writeRun(dir, "experiment/cache", "mamba", 0.1);
    const Json recovered = {{"before", 0.01},        {"first", 0.2}, {"recovery_frames", 3},      {"recovery_seconds", 0.3},
                            {"lag_frames", 1},       {"end", 0.009}, {"mean_ratio_first", 0.9}, {"mean_ratio_end", 1.0}};
    Json neverRecovered = recovered;
    neverRecovered["recovery_frames"] = nullptr;
    neverRecovered["recovery_seconds"] = nullptr;
    const Json events = Json::array({Json{{"frame", 4}, {"events", Json::array()}, {"total", recovered}, {"indirect", neverRecovered}},
                                     Json{{"frame", 8}, {"events", Json::array()}, {"total", recovered}, {"indirect", recovered}}});
    dir.write("experiment/cache/metrics.json", Json{{"events", events}}.dump());
    runAnalysis(dir);
    const std::filesystem::path file = dir / "experiment" / "recovery.csv";
    const std::vector<CsvRow> rows = readCsv(file);
    EXPECT_EQ(rows.size(), 4u);
    const CsvRow never = rowWhere(rows, {{"event", "0"}, {"layer", "indirect"}});
    EXPECT_EQ(never.at("frame"), "4");
    EXPECT_EQ(never.at("recovery_frames"), "");
    EXPECT_EQ(never.at("recovery_seconds"), "");
    const CsvRow second = rowWhere(rows, {{"event", "1"}, {"layer", "total"}});
    EXPECT_EQ(second.at("frame"), "8");
    EXPECT_EQ(second.at("recovery_frames"), "3");  // a count, not "3.0"
    EXPECT_NEAR(number(second, "recovery_seconds"), 0.3, 1e-12);
    std::ifstream in(file);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text.find("nan"), std::string::npos) << text;
    EXPECT_EQ(text.find("inf"), std::string::npos) << text;
}

}  // namespace
}  // namespace gibench
