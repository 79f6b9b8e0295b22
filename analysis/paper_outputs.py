#!/usr/bin/python3
"""The figures and tables of a results folder, for a paper and for the HTML report.

usage: /usr/bin/python3 analysis/paper_outputs.py RESULTS_DIR --out OUT_DIR

RESULTS_DIR is a results root (<experiment>/<run>/) or one experiment folder. Writes into OUT_DIR:
  runs.csv                     the tidy table, one row per run and checkpoint (runs_table.py)
  figures/<name>.png, .pdf     per experiment and scene: error against render time (total,
                               indirect), time per stage, bytes and probes over frames
  tables/<name>.md, .tex       per experiment, scene and layer: equal time and equal error
  outputs.json                 what was written, with a caption each (build_figures_and_tables)
Every curve and entry is a mean over the seeds of a configuration with its standard error.
Bad input (no runs, a file that does not parse) prints "error: ..." naming the file, exit code 2.
"""

import argparse
import json
import pathlib
import re
import sys

import comparison_tables
import figures
import results_reader
import runs_table
from input_error import InputError

LAYERS = ("total", "indirect")
METRIC = "relmse"


def _name(*parts) -> str:
    """A file name from experiment, scene, ...: characters other than letters, digits, '.', '-' as '_'."""
    return "_".join(re.sub(r"[^A-Za-z0-9.-]", "_", str(p)) for p in parts if p != "")


def _scenes(table):
    """(experiment, scene, rows) per experiment and scene, in order of appearance."""
    for (experiment, scene), rows in table.groupby(["experiment", "scene"], sort=False):
        yield experiment, scene, rows


def _figures(runs, frames, out_dir):
    written = []
    for experiment, scene, scene_frames in _scenes(frames):
        scene_runs = runs[(runs["experiment"] == experiment) & (runs["scene"] == scene)]
        where = f"{scene} ({experiment}), {figures.seeds_text(scene_runs)}"
        for layer in LAYERS:
            paths = figures.error_vs_time(scene_frames, scene_runs, layer, METRIC, out_dir,
                                          _name("error_vs_time", experiment, scene, layer))
            if paths:
                written.append({**paths, "kind": "error_vs_time", "scene": scene,
                                "caption": f"{METRIC} ({layer}) against render time, {where}: mean over seeds where every seed is "
                                           f"measured, band ± SE (standard error of the mean); dashed: the reference's own "
                                           f"noise where known."})
        paths = figures.stage_times(scene_frames, out_dir, _name("stage_times", experiment, scene))
        if paths:
            written.append({**paths, "kind": "stage_times", "scene": scene,
                            "caption": f"Mean milliseconds per frame of each stage, {where}: mean over frames, then seeds."})
        for counter, kind, ylabel, scale, what in (("bytes", "memory", "memory (MiB)", 1.0 / 2 ** 20, "Memory (store and "
                                                    "probe states)"), ("probes", "probes", "probes", 1.0, "Probes")):
            paths = figures.counter_over_frames(scene_frames, counter, ylabel, scale, out_dir, _name(kind, experiment, scene))
            if paths:
                written.append({**paths, "kind": kind, "scene": scene,
                                "caption": f"{what} over frames, {where}: mean over seeds, band ± SE."})
    return written


def _tables(runs, frames, out_dir):
    (out_dir / "tables").mkdir(parents=True, exist_ok=True)
    written = []
    for experiment, scene, scene_runs in _scenes(runs):
        scene_frames = frames[(frames["experiment"] == experiment) & (frames["scene"] == scene)]
        for layer in LAYERS:
            for kind, table in (("equal_time", comparison_tables.equal_time(scene_runs, layer, METRIC)),
                                ("equal_error", comparison_tables.equal_error(scene_frames, layer, METRIC))):
                table = comparison_tables.without_empty_columns(table)
                if not table.column_labels:
                    continue
                name = _name(kind, experiment, scene, layer)
                (out_dir / "tables" / f"{name}.md").write_text(comparison_tables.markdown(table), encoding="utf-8")
                (out_dir / "tables" / f"{name}.tex").write_text(comparison_tables.latex(table), encoding="utf-8")
                written.append({"markdown": f"tables/{name}.md", "latex": f"tables/{name}.tex", "kind": kind,
                                "caption": f"{table.caption[0].upper()}{table.caption[1:]}, {scene} ({experiment})."})
    return written


def build_figures_and_tables(results_dir: pathlib.Path, out_dir: pathlib.Path) -> dict:
    """Reads every run under results_dir, writes out_dir/runs.csv, figures/, tables/ and
    outputs.json, and returns what outputs.json holds: {"runs_csv", "figures": [{"path" (PNG),
    "pdf", "caption", "scene", "kind"}], "tables": [{"markdown", "latex", "caption", "kind"}]}, paths
    relative to out_dir. InputError on bad input, before anything is written."""
    results_dir, out_dir = pathlib.Path(results_dir), pathlib.Path(out_dir)
    runs = results_reader.read_runs(results_dir)
    checkpoints, frames = runs_table.runs_table(runs), runs_table.frames_table(runs)
    out_dir.mkdir(parents=True, exist_ok=True)
    runs_table.write_csv(checkpoints, out_dir / "runs.csv")
    outputs = {"runs_csv": "runs.csv", "figures": _figures(checkpoints, frames, out_dir),
               "tables": _tables(checkpoints, frames, out_dir)}
    (out_dir / "outputs.json").write_text(json.dumps(outputs, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    return outputs


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results_dir", type=pathlib.Path)
    parser.add_argument("--out", type=pathlib.Path, required=True, help="folder to write into")
    args = parser.parse_args()
    try:
        outputs = build_figures_and_tables(args.results_dir, args.out)
    except InputError as e:
        print(f"error: {e}", file=sys.stderr)
        sys.exit(2)
    print(f"wrote {args.out / 'runs.csv'}, {len(outputs['figures'])} figures and {len(outputs['tables'])} tables "
          f"({args.out / 'outputs.json'})")


if __name__ == "__main__":
    main()
