"""The run folders under a results root or one experiment folder, read into memory.

A run is a folder holding manifest.json (results/README.md); hidden folders (.staging-*, .old-*,
.logs, ...) never are, even when complete-looking: they are runs being written or left by a killed
one. A results root holds <experiment>/<run>/, an experiment folder <run>/, and results_dir may be
either (or itself a run). Anything that does not parse is an InputError naming the file.
"""

import json
import pathlib
from dataclasses import dataclass, field

from input_error import InputError


@dataclass
class Run:
    folder: pathlib.Path
    manifest: dict
    metrics: dict  # {} when the run has no metrics.json (nothing was measured)
    frames: list = field(default_factory=list)  # frames.jsonl, one dict per frame in order

    @property
    def config(self) -> dict:
        return self.manifest.get("config", {})

    @property
    def experiment(self) -> str:
        return str(self.config.get("experiment") or self.folder.parent.name)

    @property
    def name(self) -> str:
        return str(self.config.get("run") or self.folder.name)

    @property
    def method(self) -> str:
        return str((self.config.get("method") or {}).get("name", ""))


def _read_json(file: pathlib.Path) -> dict:
    try:
        value = json.loads(file.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise InputError(f"{file}: not readable as JSON ({e})") from e
    if not isinstance(value, dict):
        raise InputError(f"{file}: expected a JSON object, got {type(value).__name__}")
    return value


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _read_frames(file: pathlib.Path) -> list:
    if not file.exists():
        raise InputError(f"{file}: missing (every run has one line per frame)")
    try:
        lines = file.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(f"{file}: not readable ({e})") from e
    frames = []
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            frame = json.loads(line)
        except json.JSONDecodeError as e:
            raise InputError(f"{file}:{number}: not a JSON line ({e})") from e
        if not isinstance(frame, dict) or not _is_number(frame.get("cumulative_seconds")) or not isinstance(frame.get("frame"), int):
            raise InputError(f"{file}:{number}: expected a frame record with a \"frame\" index and \"cumulative_seconds\"")
        for key in ("error", "stages", "stats"):
            if frame.get(key) is not None and not isinstance(frame[key], dict):
                raise InputError(f"{file}:{number}: \"{key}\": expected an object or null")
        frames.append(frame)
    return frames


def _check_checkpoints(file: pathlib.Path, metrics: dict):
    """metrics.json's "checkpoints": {"frames": [records], "seconds": [records]}, each record an object."""
    checkpoints = metrics.get("checkpoints")
    if checkpoints is None:
        return
    if not isinstance(checkpoints, dict):
        raise InputError(f"{file}: \"checkpoints\": expected an object with \"frames\" and \"seconds\" lists")
    for kind in ("frames", "seconds"):
        records = checkpoints.get(kind, [])
        if not isinstance(records, list) or not all(isinstance(r, dict) and (r.get("error") is None or isinstance(r["error"], dict))
                                                    for r in records):
            raise InputError(f"{file}: \"checkpoints\".\"{kind}\": expected a list of checkpoint records "
                             "({\"at\", \"frame\", \"cumulative_seconds\", \"error\"})")
    if metrics.get("reference_noise") is not None and not isinstance(metrics["reference_noise"], dict):
        raise InputError(f"{file}: \"reference_noise\": expected an object of relMSE per layer")


def read_run(folder: pathlib.Path) -> Run:
    manifest = _read_json(folder / "manifest.json")
    if not isinstance(manifest.get("config"), dict):
        raise InputError(f"{folder / 'manifest.json'}: expected a \"config\" object (the resolved run config)")
    if manifest["config"].get("method") is not None and not isinstance(manifest["config"]["method"], dict):
        raise InputError(f"{folder / 'manifest.json'}: \"config\".\"method\": expected an object with a \"name\"")
    sweep = manifest.get("sweep")
    if sweep is not None and not (isinstance(sweep, dict) and isinstance(sweep.get("axes", {}), dict)):
        raise InputError(f"{folder / 'manifest.json'}: \"sweep\": expected an object with an \"axes\" object")
    metrics_file = folder / "metrics.json"
    metrics = _read_json(metrics_file) if metrics_file.exists() else {}
    _check_checkpoints(metrics_file, metrics)
    return Run(folder, manifest, metrics, _read_frames(folder / "frames.jsonl"))


def run_folders(results_dir: pathlib.Path) -> list:
    """The run folders at results_dir itself, one level and two levels below it, sorted, hidden ones
    (and everything inside them) left out."""
    if (results_dir / "manifest.json").is_file():
        return [results_dir]
    found = []
    for child in sorted(results_dir.iterdir()):
        if child.name.startswith(".") or not child.is_dir():
            continue
        if (child / "manifest.json").is_file():
            found.append(child)
            continue
        found += [run for run in sorted(child.iterdir())
                  if not run.name.startswith(".") and run.is_dir() and (run / "manifest.json").is_file()]
    return found


def read_runs(results_dir: pathlib.Path) -> list:
    """Every run under results_dir; InputError when it is no folder or holds no run."""
    results_dir = pathlib.Path(results_dir)
    if not results_dir.is_dir():
        raise InputError(f"{results_dir}: not a folder (expected a results root or an experiment folder)")
    folders = run_folders(results_dir)
    if not folders:
        raise InputError(f"{results_dir}: no runs (no <run>/manifest.json or <experiment>/<run>/manifest.json)")
    return [read_run(folder) for folder in folders]
