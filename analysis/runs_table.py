"""The tidy tables of a results folder: one row per run and checkpoint (runs.csv), one per run and
frame (for curves over frames and stage times).

Columns, the same names whatever the experiment (missing values are NaN, written as empty cells):
  run_id                  the manifest's (gibench sweep writes it), empty otherwise
  experiment, run         the results folders' names (from the resolved config)
  method, scene, seed     method.name; the scene file's stem, or an inline scene's "name"; seed
  <swept parameters>      every other key a sweep varies (the manifest's sweep axes), or that
                          differs between runs of one method in one experiment: the dotted key
                          with "_" for ".", e.g. method_cell_size
  spp, resolution, frames, budget_seconds
                          method.spp, camera.resolution as "WxH", the most frames, budget.seconds
  frames_rendered, stopped_by      metrics.json: what the run did
  reference_noise_<layer> metrics.json "reference_noise": the expected relMSE of the reference
  checkpoint_kind         "frames", "seconds" (metrics.json checkpoints) or "final" (the last
                          measured frame); checkpoint_value: frames after which, or seconds of
                          render time as of which, the error was taken (empty for "final")
  frame, seconds          the frame the row's error is of (0-based, as frames.jsonl) and the
                          cumulative render time when it finished; empty where the run stopped first
  <metric>_<layer>        every metric of every layer measured, e.g. relmse_total, relmse_indirect
  probes, bytes           the method's probes and bytes (store + probe states) at that frame
The per-frame table has the same identity and parameter columns, then frame, seconds (cumulative),
frame_seconds, stage_<stage>_seconds, the error columns, probes and bytes.
"""

import json
import math
import pathlib

import numpy as np
import pandas as pd

import results_reader

# Keys of the config that have a column of their own, and those that say nothing about the result
# (as for gibench's run ids) or are reported per row anyway: neither is a swept parameter.
COMMON_KEYS = {"method.name": "method", "scene": "scene", "seed": "seed", "method.spp": "spp",
               "camera.resolution": "resolution", "frames": "frames", "budget.seconds": "budget_seconds"}
NOT_PARAMETERS = ("run", "experiment", "output", "threads", "checkpoints")
IDENTITY_COLUMNS = ["run_id", "experiment", "run", "method", "scene", "seed"]
COMMON_COLUMNS = ["spp", "resolution", "frames", "budget_seconds"]
OUTCOME_COLUMNS = ["frames_rendered", "stopped_by"]
CHECKPOINT_COLUMNS = ["checkpoint_kind", "checkpoint_value", "frame", "seconds"]
COUNTER_COLUMNS = ["probes", "bytes"]
# Layers first in this order (the ones the figures and tables use), any other after, by name.
LAYER_ORDER = ("total", "direct", "indirect")
# Columns every table has, measured or not, so that code reading them needs no check: the figures'
# and tables' metric of their layers, and the reference's noise in them.
ALWAYS_ERROR_COLUMNS = ("relmse_total", "relmse_direct", "relmse_indirect")
ALWAYS_NOISE_COLUMNS = ("reference_noise_total", "reference_noise_indirect")
# Columns that hold counts, kept integers (pandas' nullable Int64) where some are missing.
INTEGER_COLUMNS = ("seed", "frames", "frames_rendered", "frame", "probes", "bytes")


def flatten(value, prefix="") -> dict:
    """{"a.b": leaf} of a JSON object: objects are descended into, anything else is a leaf."""
    if isinstance(value, dict):
        out = {}
        for key, inner in value.items():
            out.update(flatten(inner, f"{prefix}{key}."))
        return out
    return {prefix[:-1]: value}


def cell(value):
    """A config value as a table cell: numbers stay numbers (non-finite ones missing), a list of
    numbers reads "32x32" as in gibench's run names, other lists and objects compact JSON."""
    if value is None:
        return math.nan
    if isinstance(value, bool):
        return value
    if isinstance(value, (int, float)):
        return value if math.isfinite(value) else math.nan
    if isinstance(value, list) and value and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        return "x".join(f"{v:g}" for v in value)
    if isinstance(value, (list, dict)):
        return json.dumps(value, separators=(",", ":"), sort_keys=True)
    return value


def number(value) -> float:
    """A measured value as a float: NaN for anything missing, non-numeric or non-finite."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return math.nan
    return float(value)


def column_name(key: str) -> str:
    return key.replace(".", "_")


def scene_name(config: dict) -> str:
    scene = config.get("scene")
    if isinstance(scene, str):
        return pathlib.PurePath(scene).stem
    if isinstance(scene, dict):
        return str(scene.get("name") or "inline")
    return ""


def is_parameter(key: str) -> bool:
    return key not in COMMON_KEYS and key.split(".")[0] not in NOT_PARAMETERS


def swept_keys(runs) -> list:
    """The sorted dotted keys that are swept: the manifests' sweep axes (an axis whose values are
    objects, such as "method", by the keys inside them), and the keys whose values differ between
    runs of one method in one experiment."""
    keys = set()
    for run in runs:
        for axis, value in ((run.manifest.get("sweep") or {}).get("axes") or {}).items():
            keys.update(flatten(value, axis + ".") if isinstance(value, dict) else [axis])
    by_method = {}
    for run in runs:
        by_method.setdefault((run.experiment, run.method), []).append(flatten(run.config))
    for configs in by_method.values():
        every = set().union(*configs)
        keys.update(k for k in every if len({json.dumps(c.get(k), sort_keys=True) for c in configs}) > 1)
    return sorted(k for k in keys if is_parameter(k))


def run_columns(run, swept) -> dict:
    """The identity, parameter and outcome columns of a run."""
    config = flatten(run.config)
    noise = run.metrics.get("reference_noise") or {}
    row = {
        "run_id": run.manifest.get("run_id", math.nan),
        "experiment": run.experiment,
        "run": run.name,
        "method": run.method,
        "scene": scene_name(run.config),
        "seed": number(run.manifest.get("seed", run.config.get("seed"))),
    }
    row.update({column_name(k): cell(config.get(k)) for k in swept})
    row.update({
        "spp": number(config.get("method.spp")),
        "resolution": cell(config.get("camera.resolution")),
        "frames": number(config.get("frames")),
        "budget_seconds": number(config.get("budget.seconds")),
        "frames_rendered": number(run.metrics.get("frames", len(run.frames))),
        "stopped_by": run.metrics.get("stopped_by", math.nan),
    })
    row.update({f"reference_noise_{layer}": number(v) for layer, v in sorted(noise.items())})
    return row


def error_columns(error) -> dict:
    """{"<metric>_<layer>": value} of a frame's error record (null when not measured)."""
    out = {}
    for layer, metrics in (error or {}).items():
        if isinstance(metrics, dict):
            out.update({f"{metric}_{layer}": number(v) for metric, v in metrics.items()})
    return out


def counters(frame) -> dict:
    """probes and bytes (store + probe states) of a frame record; NaN for a method without them."""
    stats = (frame or {}).get("stats") or {}
    parts = [number(stats[k]) for k in ("store_bytes", "probe_state_bytes") if k in stats]
    return {"probes": number(stats.get("probes")), "bytes": sum(parts) if parts else math.nan}


def checkpoint_rows(run) -> list:
    """The run's checkpoints from metrics.json, then its final state: the last frame of
    frames.jsonl with an error (or its last frame when none has one)."""
    by_index = {f.get("frame"): f for f in run.frames}
    rows = []
    for kind in ("frames", "seconds"):
        for record in (run.metrics.get("checkpoints") or {}).get(kind) or []:
            frame = record.get("frame")
            row = {"checkpoint_kind": kind, "checkpoint_value": number(record.get("at")), "frame": number(frame),
                   "seconds": number(record.get("cumulative_seconds"))}
            row.update(error_columns(record.get("error")))
            row.update(counters(by_index.get(frame)) if frame is not None else {})
            rows.append(row)
    if run.frames:
        measured = [f for f in run.frames if f.get("error")]
        last = measured[-1] if measured else run.frames[-1]
        row = {"checkpoint_kind": "final", "checkpoint_value": math.nan, "frame": number(last.get("frame")),
               "seconds": number(last.get("cumulative_seconds"))}
        row.update(error_columns(last.get("error")))
        row.update(counters(last))
        rows.append(row)
    return rows


def frame_rows(run) -> list:
    rows = []
    for f in run.frames:
        row = {"frame": number(f.get("frame")), "seconds": number(f.get("cumulative_seconds")),
               "frame_seconds": number(f.get("seconds"))}
        row.update({f"stage_{stage}_seconds": number(s) for stage, s in (f.get("stages") or {}).items()})
        row.update(error_columns(f.get("error")))
        row.update(counters(f))
        rows.append(row)
    return rows


def error_column_order(columns) -> list:
    """The <metric>_<layer> columns among `columns`: by layer (LAYER_ORDER first), then metric."""
    def key(column):
        metric, layer = column.rsplit("_", 1)
        return (LAYER_ORDER.index(layer) if layer in LAYER_ORDER else len(LAYER_ORDER), layer, metric)
    return sorted(columns, key=key)


def tidy(runs, rows_of, middle_columns) -> pd.DataFrame:
    """One row per run and record of rows_of(run), with the run's columns in front; columns in a
    fixed order (identity, parameters, outcome, middle_columns, errors, counters)."""
    swept = swept_keys(runs)
    rows = []
    for run in runs:
        base = run_columns(run, swept)
        rows += [{**base, **record} for record in rows_of(run)]
    table = pd.DataFrame(rows)
    fixed = IDENTITY_COLUMNS + [column_name(k) for k in swept] + COMMON_COLUMNS + OUTCOME_COLUMNS
    noise = sorted(set(ALWAYS_NOISE_COLUMNS).union(c for c in table.columns if c.startswith("reference_noise_")))
    stages = sorted(c for c in table.columns if c.startswith("stage_") and c.endswith("_seconds"))
    known = set(fixed + noise + middle_columns + stages + COUNTER_COLUMNS)
    errors = error_column_order(set(ALWAYS_ERROR_COLUMNS).union(c for c in table.columns if c not in known))
    order = fixed + noise + middle_columns + stages + errors + COUNTER_COLUMNS
    table = table.reindex(columns=order)
    table["run_id"] = table["run_id"].astype("object")
    for column in INTEGER_COLUMNS:
        if column in table:
            table[column] = pd.to_numeric(table[column]).round().astype("Int64")
    measured = noise + stages + errors + ["checkpoint_value", "spp", "budget_seconds", "seconds", "frame_seconds"]
    for column in (c for c in measured if c in table):
        table[column] = pd.to_numeric(table[column], errors="coerce").astype("float64")
    return table


def runs_table(runs) -> pd.DataFrame:
    return tidy(runs, checkpoint_rows, CHECKPOINT_COLUMNS)


def frames_table(runs) -> pd.DataFrame:
    return tidy(runs, frame_rows, ["frame", "seconds", "frame_seconds"])


def load_runs(results_dir) -> pd.DataFrame:
    """The tidy table of every run under results_dir (a results root or one experiment folder):
    one row per run and checkpoint, as runs.csv holds it. InputError on bad input."""
    return runs_table(results_reader.read_runs(pathlib.Path(results_dir)))


def load_frames(results_dir) -> pd.DataFrame:
    """The per-frame tidy table of every run under results_dir."""
    return frames_table(results_reader.read_runs(pathlib.Path(results_dir)))


def read_csv(file) -> pd.DataFrame:
    """runs.csv as load_runs returns it: names and ids stay text (a run id of hex digits only
    would otherwise read as a number), counts nullable integers."""
    table = pd.read_csv(file, dtype={c: "object" for c in ("run_id", "experiment", "run", "method", "scene", "resolution",
                                                          "stopped_by", "checkpoint_kind")})
    for column in INTEGER_COLUMNS:
        if column in table:
            table[column] = table[column].astype("Int64")
    return table


def write_csv(table: pd.DataFrame, file: pathlib.Path):
    """A tidy table as CSV: missing values as empty cells, never "nan" or "inf"."""
    numeric = table.select_dtypes(include=[np.floating]).columns
    clean = table.copy()
    clean[numeric] = clean[numeric].where(np.isfinite(clean[numeric]))
    clean.to_csv(file, index=False, na_rep="")
