#include "experiments/checkpoints.h"

#include <algorithm>
#include <cmath>

namespace gibench {

namespace {

constexpr const char* kPowersOfTwo = "powers_of_two";

// An ascending list of numbers under `name`, each within [low, high] (`range` says so in words).
std::vector<double> ascendingNumbers(Params& block, const std::string& name, const Json& value, double low, double high, bool integers,
                                     const std::string& range) {
    if (!value.is_array()) block.fail(name, "expected an ascending array of " + range + ", got " + value.dump());
    std::vector<double> out;
    for (std::size_t i = 0; i < value.size(); ++i) {
        const Json& v = value[i];
        const bool ok = integers ? v.is_number_integer() : v.is_number();
        if (!ok || !(v.get<double>() >= low && v.get<double>() <= high))
            block.fail(name, "expected " + range + ", got " + v.dump() + " at index " + std::to_string(i));
        if (!out.empty() && !(v.get<double>() > out.back()))
            block.fail(name, "expected ascending values, got " + v.dump() + " after " + value[i - 1].dump() + " at index " + std::to_string(i));
        out.push_back(v.get<double>());
    }
    return out;
}

}  // namespace

// Seconds are read as JSON numbers, kept in double: the manifest shows the budget as written.
const ParamTable kBudgetParams = {
    {"seconds", ParamType::Json, nullptr, "stop once the frames' render time reaches this, in (0, 1e9]"},
};

const ParamTable kCheckpointParams = {
    {"frames", ParamType::Json, kPowersOfTwo,
     "after this many frames (ascending), or \"" + std::string(kPowersOfTwo) + "\": 1, 2, 4, ... and the run's frames"},
    {"seconds", ParamType::Json, Json(std::vector<double>(std::begin(kDefaultSecondCheckpoints), std::end(kDefaultSecondCheckpoints))),
     "after this much render time (ascending)"},
};

std::optional<double> readBudgetSeconds(Params& runConfig) {
    if (!runConfig.has("budget")) return std::nullopt;
    Params budget = runConfig.child("budget", &kBudgetParams, "budget");
    const Json seconds = budget.getJson("seconds");
    if (!seconds.is_number() || !(seconds.get<double>() > 0.0 && seconds.get<double>() <= 1e9))
        budget.fail("seconds", "expected a number of seconds in (0, 1e9], got " + seconds.dump());
    budget.finish();
    return seconds.get<double>();
}

Checkpoints readCheckpoints(Params& runConfig, int frames) {
    Checkpoints c;
    Params block = runConfig.child("checkpoints", &kCheckpointParams, "checkpoints");
    const Json f = block.getJson("frames");
    if (f == Json(kPowersOfTwo)) {
        for (int n = 1; n < frames; n *= 2) c.frames.push_back(n);
        c.frames.push_back(frames);
    } else {
        const std::string range = "integers in [1, " + std::to_string(frames) + "] (the run's frames)";
        for (const double n : ascendingNumbers(block, "frames", f, 1, double(frames), true, range)) c.frames.push_back(int(n));
    }
    c.seconds = ascendingNumbers(block, "seconds", block.getJson("seconds"), 1e-9, 1e9, false, "numbers in [1e-9, 1e9]");
    block.finish();
    c.resolved = {{"frames", c.frames}, {"seconds", c.seconds}};
    return c;
}

Json checkpointRecords(const Checkpoints& checkpoints, const std::vector<FrameSample>& samples) {
    const auto row = [](double at, const FrameSample* s) {
        Json r = {{"at", at}, {"frame", nullptr}};
        if (s) {
            r["frame"] = s->frame;
            r["cumulative_seconds"] = s->cumulativeSeconds;
            r["error"] = s->error;
        }
        return r;
    };
    Json frames = Json::array(), seconds = Json::array();
    for (const int n : checkpoints.frames) frames.push_back(row(double(n), n <= int(samples.size()) ? &samples[std::size_t(n - 1)] : nullptr));
    for (const double t : checkpoints.seconds) {
        // The last frame finished by t: the image the method had to show at that time; none when the
        // run's frames ended before t (what it would show then was not rendered).
        if (samples.empty() || samples.back().cumulativeSeconds < t) {
            seconds.push_back(row(t, nullptr));
            continue;
        }
        const auto after = std::upper_bound(samples.begin(), samples.end(), t,
                                            [](double time, const FrameSample& s) { return time < s.cumulativeSeconds; });
        seconds.push_back(row(t, after == samples.begin() ? nullptr : &*(after - 1)));
    }
    // Frame counts print as integers.
    for (Json& r : frames) r["at"] = int(r["at"].get<double>());
    return {{"frames", frames}, {"seconds", seconds}};
}

}  // namespace gibench
