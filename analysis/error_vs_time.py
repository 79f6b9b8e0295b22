#!/usr/bin/python3
"""Error against run time for every run of an experiment, from their frames.jsonl.

usage: /usr/bin/python3 analysis/error_vs_time.py results/<experiment> [--metric relmse]

Writes into the experiment folder:
  error_vs_time_<layer>_<metric>.png  one curve per run, error of each measured frame against the
                                      cumulative wall time of the frames (log-log), total and indirect
  summary.md, summary.csv             per run: method, frames, time, final error (total, indirect),
                                      probes, bytes; and the equal-time comparison: every run's error
                                      at the time the fastest run finished
  stages.md                           mean time per frame of each pipeline stage, per run
  equal_time.md, equal_time.csv       every run's error at fixed time budgets, and its ratio to the
                                      path tracer's at the same budget
  crossover.md, crossover.csv         per cache and layer: up to when it beats the path tracer, its
                                      best ratio to it and its ratio at 1 s
  recovery.md, recovery.csv           per run, scene event and layer: how the error recovered from
                                      the change (metrics.json "events"; only when a run has them)
Run by run, no averaging over seeds: analysis/paper_outputs.py gives the means over seeds.
"""

import argparse
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

import results_reader  # noqa: E402
from input_error import InputError  # noqa: E402
from method_styles import method_style  # noqa: E402

LAYERS = ("total", "indirect")
# Budgets of cumulative frame time (s) for the equal-time table: roughly doubling, from a few
# frames of a run to a long converging one.
BUDGETS_S = (0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0)
# The fields of each event's recovery record per layer, as experiments/event_recovery.h writes them.
RECOVERY_FIELDS = ("before", "first", "recovery_frames", "recovery_seconds", "lag_frames", "end", "mean_ratio_first", "mean_ratio_end")
# Times compare with this relative slack: cumulative seconds are sums of doubles, and a frame
# finished "at" a budget must count as finished by it.
SLACK = 1 + 1e-9


def markdown(table: pd.DataFrame) -> str:
    """A GitHub Markdown table; numbers with 4 significant digits."""
    def cell(v):
        if pd.isna(v):  # None, NaN, and pandas' NA of integer columns with nulls
            return ""
        return f"{v:.4g}" if isinstance(v, float) else str(v)
    lines = ["| " + " | ".join(table.columns) + " |", "|" + "---|" * len(table.columns)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in table.itertuples(index=False)]
    return "\n".join(lines) + "\n"


def load_runs(experiment: pathlib.Path):
    """Every finished run of the experiment folder, as results_reader finds them (hidden folders are
    not runs), named by its folder."""
    return [{"name": r.folder.name, "method": r.method, "manifest": r.manifest, "frames": r.frames, "metrics": r.metrics}
            for r in results_reader.read_runs(experiment)]


def error_of(frame, layer, metric):
    error = frame.get("error")
    if not error or not error.get(layer):
        return math.nan
    value = error[layer].get(metric)
    return math.nan if value is None or isinstance(value, str) else float(value)


def frame_table(run, metric):
    rows = []
    for f in run["frames"]:
        stats = f.get("stats", {})
        rows.append({
            "frame": f["frame"],
            "seconds": f["cumulative_seconds"],
            "total": error_of(f, "total", metric),
            "indirect": error_of(f, "indirect", metric),
            "probes": stats.get("probes"),
            "bytes": (stats.get("store_bytes") or 0) + (stats.get("probe_state_bytes") or 0) if "probes" in stats else None,
        })
    return pd.DataFrame(rows)


def error_at_time(table, layer, seconds):
    """Error of the last frame finished by `seconds` (NaN if none was)."""
    done = table[table["seconds"] <= seconds * SLACK]
    return done[layer].iloc[-1] if len(done) else math.nan


def measured_errors_at(table, layer, times):
    """Error of the last frame with an error in `layer` finished by each of `times` (NaN before the
    first). A frame without one (the camera away from the reference's pose) says nothing about the
    run's error, so the latest measured one stands for it."""
    measured = table.dropna(subset=[layer])
    if not len(measured):
        return np.full(len(times), math.nan)
    last = np.searchsorted(measured["seconds"].to_numpy(), np.asarray(times, dtype=float) * SLACK, side="right") - 1
    return np.where(last >= 0, measured[layer].to_numpy()[np.maximum(last, 0)], math.nan)


def path_traced_reference(runs):
    """The path-traced run the caches are measured against (None without one), and a sentence
    saying which, since with several the choice is arbitrary: the first by folder name."""
    traced = [r for r in runs if r["method"] == "path_traced"]
    if not traced:
        return None, "No path_traced run, so no ratios."
    note = f"Ratios are to path_traced run `{traced[0]['name']}`"
    if len(traced) > 1:
        note += f", the first by folder name of {len(traced)} path_traced runs ({', '.join(r['name'] for r in traced)})"
    return traced[0], note + "."


def write_table(experiment: pathlib.Path, name: str, table: pd.DataFrame, text: str):
    """<name>.csv from `table`, nulls as empty cells (never "nan"), and <name>.md from `text`."""
    csv, md = experiment / f"{name}.csv", experiment / f"{name}.md"
    table.to_csv(csv, index=False, na_rep="")
    md.write_text(text)
    print(f"wrote {csv}\nwrote {md}")


def equal_time_table(runs, tables, reference, metric):
    """One row per layer, run and budget: the run's error at the budget (measured_errors_at) and,
    for a cache, its ratio to the reference path tracer's there. Budgets past the longest run would
    only repeat every run's final error, so they are left out."""
    longest = max(t["seconds"].iloc[-1] for t in tables.values() if len(t))
    budgets = [b for b in BUDGETS_S if b <= longest * SLACK]
    rows = []
    for layer in LAYERS:
        traced = measured_errors_at(tables[reference["name"]], layer, budgets) if reference else np.full(len(budgets), math.nan)
        for r in runs:
            errors = measured_errors_at(tables[r["name"]], layer, budgets)
            ratios = errors / traced if r["method"] != "path_traced" else np.full(len(budgets), math.nan)
            rows += [{"run": r["name"], "method": r["method"], "layer": layer, "budget_s": b, metric: e, "ratio_to_path_traced": q}
                     for b, e, q in zip(budgets, errors, ratios)]
    # Named columns keep the CSV's header when every run is shorter than the smallest budget.
    return pd.DataFrame(rows, columns=["run", "method", "layer", "budget_s", metric, "ratio_to_path_traced"])


def equal_time_markdown(table, metric, note):
    """The long table as one wide table per layer, a run per row and a budget per column, each
    cell "error (ratio×)": the layout to read a run's convergence along a row."""
    def cell(error, ratio):
        if math.isnan(error):
            return ""
        return f"{error:.4g}" + ("" if math.isnan(ratio) else f" ({ratio:.2g}×)")
    text = (f"# {metric} at equal time\n\nEach cell: the error of the run's last measured frame finished within the budget of "
            f"cumulative frame time (a run that ended before it keeps its final error), and in brackets its ratio to the "
            f"path tracer's at the same budget. {note}\n")
    if table.empty:
        return text + f"\nNo budget: every run took less than the smallest, {BUDGETS_S[0]:g} s.\n"
    for layer in LAYERS:
        rows = []
        for (run, method), cells in table[table["layer"] == layer].groupby(["run", "method"], sort=False):
            row = {"run": run, "method": method}
            row.update({f"{b:g} s": cell(e, q) for b, e, q in zip(cells["budget_s"], cells[metric], cells["ratio_to_path_traced"])})
            rows.append(row)
        text += f"\n## {layer}\n\n" + markdown(pd.DataFrame(rows))
    return text


CROSSOVER_DEFINITION = """\
For a cache against the path tracer, per layer, over the common times: the frame-finish times
(cumulative frame time) of either run's frames with an error in the layer, up to the end of the
shorter run (common_end_s), at which the cache has an error. Each run's error at a time is that of
its last measured frame finished by then.

- beats_pt_up_to_s: the largest common time t such that at every common time up to t the cache's
  error is below the path tracer's, or the path tracer has no measured frame yet; empty when the
  cache does not beat it at its first common time.
- best_ratio, best_ratio_at_s: the smallest cache/path-tracer error ratio over the common times
  where both have an error, and the first time it occurs.
- ratio_at_1s: the ratio at 1 s; empty past common_end_s.
"""


def crossover(cache, traced, layer):
    """Where a cache's error curve stands against the path tracer's, as CROSSOVER_DEFINITION tells
    the reader. Common times: the union of both runs' measured frame-finish times up to the shorter
    run's end, where the cache has an error; each run's error at t is its last measured by t.
    beats_pt_up_to_s is the last common time before the first one where the cache's error is not
    below a path-traced error (the path tracer having none yet counts as beaten), NaN when that is
    the first; best_ratio is over the common times where both have an error. All NaN when either
    run has no error in the layer, since there is nothing to compare."""
    row = {"common_end_s": math.nan, "beats_pt_up_to_s": math.nan, "best_ratio": math.nan, "best_ratio_at_s": math.nan,
           "ratio_at_1s": math.nan}
    cache_measured, traced_measured = cache.dropna(subset=[layer]), traced.dropna(subset=[layer])
    if not len(cache_measured) or not len(traced_measured):
        return row
    end = min(cache["seconds"].iloc[-1], traced["seconds"].iloc[-1])
    times = np.union1d(cache_measured["seconds"], traced_measured["seconds"])
    times = times[times <= end * SLACK]
    ours, theirs = measured_errors_at(cache, layer, times), measured_errors_at(traced, layer, times)
    common = ~np.isnan(ours)
    times, ours, theirs = times[common], ours[common], theirs[common]
    row["common_end_s"] = end
    lost = np.flatnonzero(~(np.isnan(theirs) | (ours < theirs)))
    last_won = (lost[0] if len(lost) else len(times)) - 1
    if last_won >= 0:
        row["beats_pt_up_to_s"] = times[last_won]
    both = ~np.isnan(theirs)
    if both.any():
        ratios = ours[both] / theirs[both]
        row["best_ratio"], row["best_ratio_at_s"] = ratios.min(), times[both][ratios.argmin()]
    if 1.0 <= end * SLACK:
        row["ratio_at_1s"] = (measured_errors_at(cache, layer, [1.0]) / measured_errors_at(traced, layer, [1.0]))[0]
    return row


def crossover_table(runs, tables, reference):
    return pd.DataFrame([{"run": r["name"], "method": r["method"], "layer": layer,
                          **crossover(tables[r["name"]], tables[reference["name"]], layer)}
                         for layer in LAYERS for r in runs if r["method"] != "path_traced"])


def recovery_table(runs):
    """One row per run, scene event (its index in metrics.json's "events") and layer, with the
    event's recovery record; nulls stay missing, and the counts stay integers."""
    rows = []
    for r in runs:
        for index, event in enumerate(r["metrics"].get("events", [])):
            for layer in LAYERS:
                record = event.get(layer) or {}
                row = {"run": r["name"], "method": r["method"], "event": index, "frame": event.get("frame"), "layer": layer}
                row.update({field: record.get(field) for field in RECOVERY_FIELDS})
                rows.append(row)
    return pd.DataFrame(rows).astype({"frame": "Int64", "recovery_frames": "Int64", "lag_frames": "Int64"})


def write_closing_tables(experiment, runs, tables, metric):
    """equal_time, crossover (with a path-traced run and a cache) and recovery (with scene events),
    .md and .csv."""
    reference, note = path_traced_reference(runs)
    equal_time = equal_time_table(runs, tables, reference, metric)
    write_table(experiment, "equal_time", equal_time, equal_time_markdown(equal_time, metric, note))
    if reference and any(r["method"] != "path_traced" for r in runs):
        table = crossover_table(runs, tables, reference)
        text = f"# {metric}: caches against the path tracer\n\n{CROSSOVER_DEFINITION}\n{note}\n"
        for layer in LAYERS:
            text += f"\n## {layer}\n\n" + markdown(table[table["layer"] == layer].drop(columns="layer"))
        write_table(experiment, "crossover", table, text)
    if any(r["metrics"].get("events") for r in runs):
        table = recovery_table(runs)
        text = ("# recovery from scene events\n\nrelMSE against each segment's own reference; event is the index in the run's "
                "metrics.json, frame the frame it changed the scene at, the fields those of experiments/event_recovery.h.\n\n")
        write_table(experiment, "recovery", table, text + markdown(table))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("experiment", type=pathlib.Path)
    parser.add_argument("--metric", default="relmse")
    args = parser.parse_args()
    try:
        runs = load_runs(args.experiment)
    except InputError as e:
        print(f"error: {e}", file=sys.stderr)
        sys.exit(2)
    tables = {r["name"]: frame_table(r, args.metric) for r in runs}

    for layer in LAYERS:
        fig, ax = plt.subplots(figsize=(6, 4))
        for r in runs:
            t = tables[r["name"]].dropna(subset=[layer])
            if len(t):
                ax.loglog(t["seconds"], t[layer], color=method_style(r["method"])["color"], marker="." if len(t) < 40 else None,
                          label=f'{r["name"]} ({r["method"]})')
        ax.set_xlabel("cumulative frame time (s)")
        ax.set_ylabel(f"{args.metric} ({layer})")
        ax.set_title(f"{args.experiment.name}: {layer} error against time")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        out = args.experiment / f"error_vs_time_{layer}_{args.metric}.png"
        fig.savefig(out, dpi=120)
        plt.close(fig)
        print(f"wrote {out}")

    equal_time = min(t["seconds"].iloc[-1] for t in tables.values() if len(t))
    rows = []
    for r in runs:
        t = tables[r["name"]]
        last = t.iloc[-1]
        rows.append({
            "run": r["name"],
            "method": r["method"],
            "frames": len(t),
            "time_s": round(float(last["seconds"]), 3),
            f"{args.metric}_total": last["total"],
            f"{args.metric}_indirect": last["indirect"],
            f"{args.metric}_total_at_{equal_time:.2f}s": error_at_time(t, "total", equal_time),
            f"{args.metric}_indirect_at_{equal_time:.2f}s": error_at_time(t, "indirect", equal_time),
            "probes": last["probes"],
            "bytes": last["bytes"],
            "bytes_per_probe": (last["bytes"] / last["probes"]) if last["probes"] else None,
        })
    summary = pd.DataFrame(rows)
    summary.to_csv(args.experiment / "summary.csv", index=False)
    (args.experiment / "summary.md").write_text(markdown(summary))
    print(summary.to_string(index=False))

    stage_rows = []
    for r in runs:
        frames = r["frames"]
        stages = {}
        for f in frames:
            for name, seconds in f.get("stages", {}).items():
                stages[name] = stages.get(name, 0.0) + seconds
        row = {"run": r["name"]}
        row.update({name: 1000.0 * total / len(frames) for name, total in stages.items()})
        row["frame_ms"] = 1000.0 * sum(f["seconds"] for f in frames) / len(frames)
        stage_rows.append(row)
    stages = pd.DataFrame(stage_rows)
    (args.experiment / "stages.md").write_text("mean milliseconds per frame\n\n" + markdown(stages))
    print(stages.to_string(index=False))

    write_closing_tables(args.experiment, runs, tables, args.metric)


if __name__ == "__main__":
    main()
