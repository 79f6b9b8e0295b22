"""The figures of one scene: error against render time, time per stage, memory and probes.

Each configuration (configurations.py) is one line or bar in its method's colour and marker
(method_styles.py); curves are the mean over seeds with mean ± SE as a band (seed_statistics.py).
No titles: the caption goes with the figure. Every figure is written as PDF and PNG.
"""

import hashlib
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import configurations  # noqa: E402
import error_curves  # noqa: E402
import seed_statistics  # noqa: E402
from method_styles import method_style  # noqa: E402

FIGURE_SIZE = (5.0, 3.6)
# The stages of gibench's pipelines in the order a frame runs them (probe cache, then path tracer):
# bars stack in this order and a stage has the same colour (tab20 by its place here) in every
# figure; a stage not listed comes after them, by name, with a colour from its name's hash.
STAGE_ORDER = ("gbuffer", "direct", "secondary_paths", "raster", "allocate", "update", "gather", "path_trace", "resolve")
# Linestyles telling apart configurations of one method (same colour), in order of appearance.
LINESTYLES = ("-", "--", "-.", ":")


def _save(fig, out_dir: pathlib.Path, name: str) -> dict:
    """Writes figures/<name>.png and .pdf under out_dir; their paths relative to it."""
    (out_dir / "figures").mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    png, pdf = f"figures/{name}.png", f"figures/{name}.pdf"
    # "tight" keeps a legend placed beside the axes inside the image.
    fig.savefig(out_dir / png, dpi=150, bbox_inches="tight")
    fig.savefig(out_dir / pdf, bbox_inches="tight")
    plt.close(fig)
    return {"path": png, "pdf": pdf}


def _styles(confs):
    """(label, colour, marker, linestyle) per configuration."""
    seen = {}
    out = []
    for conf, label in zip(confs, configurations.labels(confs)):
        style = method_style(conf["method"])
        count = seen.get(conf["method"], 0)
        seen[conf["method"]] = count + 1
        out.append((label, style["color"], style["marker"], LINESTYLES[count % len(LINESTYLES)]))
    return out


def _axes():
    fig, ax = plt.subplots(figsize=FIGURE_SIZE)
    ax.tick_params(labelsize=9)
    ax.grid(True, which="both", alpha=0.3)
    return fig, ax


def error_vs_time(frames, runs, layer, metric, out_dir, name):
    """log-log error against cumulative render time, or None when no configuration has a curve."""
    column = f"{metric}_{layer}"
    if column not in frames:
        return None
    grouped = list(configurations.groups(frames))
    fig, ax = _axes()
    drawn = 0
    for (conf, group), (label, color, marker, linestyle) in zip(grouped, _styles([c for c, _ in grouped])):
        curves = [(run["seconds"].to_numpy(), run[column].to_numpy()) for _, run in group.groupby("run", sort=False)]
        times = error_curves.common_times(curves)
        if not len(times):
            continue
        values = np.array([error_curves.error_at(t, e, times) for t, e in curves])
        stats = np.array([seed_statistics.mean_and_se(values[:, k]) for k in range(len(times))])
        mean, se = stats[:, 0], stats[:, 1]
        ax.plot(times, mean, color=color, marker=marker, linestyle=linestyle, markevery=max(1, len(times) // 6),
                markersize=4, label=label)
        if not np.all(np.isnan(se)):
            # A band reaching zero or below has no place on log axes: its foot is kept positive.
            ax.fill_between(times, np.maximum(mean - se, mean * 1e-3), mean + se, color=color, alpha=0.2, linewidth=0)
        drawn += 1
    if not drawn:
        plt.close(fig)
        return None
    # The reference's own expected relMSE: no method can be measured below it.
    noise_column = f"reference_noise_{layer}"
    if metric == "relmse" and noise_column in runs and runs[noise_column].notna().any():
        ax.axhline(runs[noise_column].mean(), color="black", linestyle="--", linewidth=1, label="reference noise")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("render time (s)")
    ax.set_ylabel(f"{metric} ({layer})")
    ax.legend(fontsize=8)
    return _save(fig, out_dir, name)


def stage_times(frames, out_dir, name):
    """Stacked bars: mean milliseconds per frame of each stage, per configuration (mean over seeds)."""
    stages = [c for c in frames.columns if c.startswith("stage_") and c.endswith("_seconds") and frames[c].notna().any()]
    if not stages:
        return None
    grouped = list(configurations.groups(frames))
    labels = [s[0] for s in _styles([c for c, _ in grouped])]
    palette = plt.get_cmap("tab20")
    fig, ax = _axes()
    ax.grid(True, axis="y", alpha=0.3)
    ax.grid(False, axis="x")
    bottom = np.zeros(len(grouped))
    for stage in sorted(stages, key=_stage_rank):
        ms = np.array([seed_statistics.mean_and_se(group.groupby("run")[stage].mean() * 1000.0, require_all=False)[0]
                       for _, group in grouped])
        ms = np.nan_to_num(ms)
        ax.bar(range(len(grouped)), ms, bottom=bottom, color=palette(_stage_colour_index(stage) % 20),
               label=_stage_name(stage))
        bottom += ms
    ax.set_xticks(range(len(grouped)), labels, rotation=30, ha="right")
    ax.set_ylabel("ms per frame")
    # Listed top down as they stack.
    handles, names = ax.get_legend_handles_labels()
    ax.legend(handles[::-1], names[::-1], fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    return _save(fig, out_dir, name)


def _stage_name(column):
    return column[len("stage_"):-len("_seconds")]


def _stage_rank(column):
    name = _stage_name(column)
    return (STAGE_ORDER.index(name), "") if name in STAGE_ORDER else (len(STAGE_ORDER), name)


def _stage_colour_index(column):
    name = _stage_name(column)
    if name in STAGE_ORDER:
        return STAGE_ORDER.index(name)
    return len(STAGE_ORDER) + int.from_bytes(hashlib.sha256(name.encode("utf-8")).digest()[:4], "big") % (20 - len(STAGE_ORDER))


def counter_over_frames(frames, counter, ylabel, scale, out_dir, name):
    """A method counter (probes, bytes) against the frame, mean over seeds ± SE; None when no
    configuration has it."""
    grouped = [(c, g) for c, g in configurations.groups(frames) if counter in g and g[counter].notna().any()]
    if not grouped:
        return None
    fig, ax = _axes()
    for (conf, group), (label, color, marker, linestyle) in zip(grouped, _styles([c for c, _ in grouped])):
        by_frame = group.groupby("frame")[counter]
        frame_index = np.array(sorted(by_frame.groups))
        stats = np.array([seed_statistics.mean_and_se(by_frame.get_group(f).astype(float) * scale) for f in frame_index])
        mean, se = stats[:, 0], stats[:, 1]
        ax.plot(frame_index, mean, color=color, marker=marker, linestyle=linestyle,
                markevery=max(1, len(frame_index) // 6), markersize=4, label=label)
        if not np.all(np.isnan(se)):
            ax.fill_between(frame_index, mean - se, mean + se, color=color, alpha=0.2, linewidth=0)
    ax.set_xlabel("frame")
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8)
    return _save(fig, out_dir, name)


def seeds_text(runs) -> str:
    """"n seeds" for a caption: the range when configurations differ."""
    counts = sorted({group["run"].nunique() for _, group in configurations.groups(runs)})
    if not counts:
        return "no runs"
    text = f"{counts[0]}" if len(counts) == 1 else f"{counts[0]}–{counts[-1]}"
    return text + (" seed" if counts == [1] else " seeds")
