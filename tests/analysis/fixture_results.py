"""Tiny results folders written the way gibench writes them (results/README.md), for the analysis
tests: no renderer needed. Also puts analysis/ on the import path."""

import json
import pathlib
import sys

ANALYSIS = pathlib.Path(__file__).resolve().parents[2] / "analysis"
if str(ANALYSIS) not in sys.path:
    sys.path.insert(0, str(ANALYSIS))


def error_record(total, indirect):
    """A frame's error: relMSE and MSE (a second metric) of total and indirect, None = not measured."""
    record = {}
    for layer, value in (("total", total), ("indirect", indirect)):
        if value is not None:
            record[layer] = {"relmse": value, "mse": value / 10.0, "pixels": 1024}
    return record or None


def write_run(root, experiment, run, method, seed, curve, *, method_params=None, sweep_axes=None, run_id=None,
              frame_checkpoints=(1, 2), second_checkpoints=(0.25, 1.0), probes=None, reference_noise=None, scene="cornell_box",
              stages=None):
    """Writes root/<experiment>/<run>/ with a frame per curve point (cumulative_seconds, relmse_total,
    relmse_indirect), checkpoints at those frames and seconds taken from the curve as gibench takes them
    (a frames checkpoint n is frame n - 1, null past the run's frames; a seconds checkpoint t the last
    frame finished by t, null when the run's render time ends before t), and, when probes is given, probes[k] probes and 100 bytes each
    (60 store + 40 state) at frame k."""
    folder = pathlib.Path(root) / experiment / run
    folder.mkdir(parents=True)
    config = {"experiment": experiment, "run": run, "scene": f"../scenes/{scene}.json", "frames": len(curve), "seed": seed,
              "camera": {"resolution": [32, 24]}, "method": {"name": method, **(method_params or {})},
              "output": {"root": str(root)}, "threads": 1}
    manifest = {"config": config, "seed": seed}
    if run_id:
        manifest["run_id"] = run_id
    if sweep_axes is not None:
        manifest["sweep"] = {"file": "sweep.json", "axes": sweep_axes}
    (folder / "manifest.json").write_text(json.dumps(manifest))
    lines, previous = [], 0.0
    for k, (cumulative, total, indirect) in enumerate(curve):
        frame = {"frame": k, "seconds": cumulative - previous, "cumulative_seconds": cumulative,
                 "stages": stages or {"path_trace": cumulative - previous}, "stats": {},
                 "error": error_record(total, indirect)}
        if probes is not None:
            frame["stats"] = {"probes": probes[k], "store_bytes": 60 * probes[k], "probe_state_bytes": 40 * probes[k]}
        lines.append(json.dumps(frame))
        previous = cumulative
    (folder / "frames.jsonl").write_text("\n".join(lines) + "\n")

    def record(at, k):
        if k is None:
            return {"at": at, "frame": None}
        return {"at": at, "frame": k, "cumulative_seconds": curve[k][0], "error": error_record(curve[k][1], curve[k][2])}
    end = curve[-1][0]
    by_time = [record(t, None if end < t else max((k for k, p in enumerate(curve) if p[0] <= t), default=None))
               for t in second_checkpoints]
    by_frames = [record(n, n - 1 if n <= len(curve) else None) for n in frame_checkpoints]
    metrics = {"frames": len(curve), "stopped_by": "frames", "error": error_record(curve[-1][1], curve[-1][2]),
               "checkpoints": {"frames": by_frames, "seconds": by_time}}
    if reference_noise is not None:
        metrics["reference_noise"] = reference_noise
    (folder / "metrics.json").write_text(json.dumps(metrics))
    return folder
