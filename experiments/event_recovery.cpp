#include "experiments/event_recovery.h"

#include <optional>

namespace gibench {
namespace {

// Metric `key` of `layer` in a frame record, when measured.
std::optional<double> metricOf(const Json& frame, const char* layer, const char* key) {
    if (!frame.contains("error")) return std::nullopt;
    const Json& error = frame["error"];
    if (!error.contains(layer) || !error[layer].is_object() || !error[layer].contains(key) || !error[layer][key].is_number()) return std::nullopt;
    return error[layer][key].get<double>();
}

std::optional<double> errorOf(const Json& frame, const char* layer) { return metricOf(frame, layer, "relmse"); }

// The frame's mean over its reference's, or null where the reference is black.
Json meanRatioOf(const Json& frame, const char* layer) {
    const std::optional<double> mean = metricOf(frame, layer, "mean"), reference = metricOf(frame, layer, "reference_mean");
    if (!mean || !reference || !(*reference > 0.0)) return nullptr;
    return *mean / *reference;
}

Json recoveryOf(const std::vector<Json>& frames, int start, int end, const char* layer) {
    Json r = {{"before", nullptr}, {"first", nullptr}, {"recovery_frames", nullptr}, {"recovery_seconds", nullptr}, {"lag_frames", nullptr},
              {"end", nullptr}, {"mean_ratio_first", nullptr}, {"mean_ratio_end", nullptr}};
    if (start < 1 || start >= int(frames.size())) return r;
    const std::optional<double> before = errorOf(frames[std::size_t(start - 1)], layer);
    const double secondsBefore = frames[std::size_t(start - 1)].value("cumulative_seconds", 0.0);
    std::optional<double> first;
    for (int f = start; f < end && f < int(frames.size()); ++f) {
        const std::optional<double> e = errorOf(frames[std::size_t(f)], layer);
        if (!e) continue;
        if (!first) {
            first = e;
            r["mean_ratio_first"] = meanRatioOf(frames[std::size_t(f)], layer);
        }
        r["end"] = *e;
        r["mean_ratio_end"] = meanRatioOf(frames[std::size_t(f)], layer);
        if (!before) continue;
        const int rendered = f - start + 1;
        if (r["lag_frames"].is_null() && *e <= *before + 0.5 * (*first - *before)) r["lag_frames"] = rendered;
        if (r["recovery_frames"].is_null() && *e <= 1.1 * *before) {
            r["recovery_frames"] = rendered;
            r["recovery_seconds"] = frames[std::size_t(f)].value("cumulative_seconds", 0.0) - secondsBefore;
        }
    }
    if (before) r["before"] = *before;
    if (first) r["first"] = *first;
    return r;
}

}  // namespace

Json eventRecovery(const std::vector<SceneEvent>& events, const std::vector<Json>& frames) {
    Json out = Json::array();
    const std::vector<int> starts = segmentStarts(events);
    for (std::size_t s = 1; s < starts.size(); ++s) {
        const int start = starts[s], end = s + 1 < starts.size() ? starts[s + 1] : int(frames.size());
        Json changes = Json::array();
        for (const SceneEvent& e : events)
            if (e.frame == start) changes.push_back(e.resolved);
        out.push_back({{"frame", start},
                       {"events", changes},
                       {"total", recoveryOf(frames, start, end, "total")},
                       {"indirect", recoveryOf(frames, start, end, "indirect")}});
    }
    return out;
}

}  // namespace gibench
