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
"""

import argparse
import json
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402


def markdown(table: pd.DataFrame) -> str:
    """A GitHub Markdown table; numbers with 4 significant digits."""
    def cell(v):
        if v is None or (isinstance(v, float) and math.isnan(v)):
            return ""
        return f"{v:.4g}" if isinstance(v, float) else str(v)
    lines = ["| " + " | ".join(table.columns) + " |", "|" + "---|" * len(table.columns)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in table.itertuples(index=False)]
    return "\n".join(lines) + "\n"


def load_runs(experiment: pathlib.Path):
    """Every finished run: a folder with a manifest. gibench's hidden folders (.staging-*, .old-*:
    runs being written, or left by a killed one) are not runs, though glob's "*" matches them."""
    runs = []
    for manifest_file in sorted(experiment.glob("*/manifest.json")):
        folder = manifest_file.parent
        if folder.name.startswith("."):
            continue
        manifest = json.loads(manifest_file.read_text())
        frames = [json.loads(line) for line in (folder / "frames.jsonl").read_text().splitlines() if line.strip()]
        runs.append({"name": folder.name, "method": manifest["config"]["method"]["name"], "manifest": manifest, "frames": frames})
    return runs


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
    done = table[table["seconds"] <= seconds * (1 + 1e-9)]
    return done[layer].iloc[-1] if len(done) else math.nan


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("experiment", type=pathlib.Path)
    parser.add_argument("--metric", default="relmse")
    args = parser.parse_args()
    runs = load_runs(args.experiment)
    if not runs:
        sys.exit(f"error: {args.experiment}: no runs (no */manifest.json)")
    tables = {r["name"]: frame_table(r, args.metric) for r in runs}

    for layer in ("total", "indirect"):
        fig, ax = plt.subplots(figsize=(6, 4))
        for r in runs:
            t = tables[r["name"]].dropna(subset=[layer])
            if len(t):
                ax.loglog(t["seconds"], t[layer], marker="." if len(t) < 40 else None, label=f'{r["name"]} ({r["method"]})')
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


if __name__ == "__main__":
    main()
