"""Equal-time and equal-error tables over configurations, mean over seeds ± standard error, as
Markdown and LaTeX (booktabs).

Equal time: each configuration's error at the runs' time checkpoints (metrics.json: the error of
the last frame finished by then). Equal error: the render time each configuration takes to reach
fixed errors, interpolated on its log-log error curve (error_curves.time_to_reach). In both,
lower is better: the lowest mean of each column is bold, entries within the spread of it
(seed_statistics.within_spread_of_best) carry a dagger, and "—" marks an entry some seed has no
value for (it stopped before the checkpoint, or never reached the error).
"""

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

import configurations
import error_curves
import seed_statistics

DAGGER_MD, DAGGER_TEX = "†", r"$^{\dagger}$"


@dataclass
class Comparison:
    """Rows are configurations, columns checkpoints; each cell a (mean, SE, seeds) triple."""
    row_labels: list
    column_labels: list
    means: np.ndarray  # rows × columns, NaN where missing
    ses: np.ndarray
    seeds: list  # seeds per row
    corner: str  # the header of the label column
    caption: str

    def footnote(self) -> str:
        if max(self.seeds, default=0) <= 1:
            spread = "One seed per configuration, so no spread."
        else:
            spread = ("Mean over seeds ± standard error of the mean (SE). "
                      "† within the spread of the best: its interval mean ± SE overlaps the best's (not significantly "
                      "different at ±1 SE).")
        return f"{spread} Bold: the lowest in its column. —: not reached by every seed."


def equal_time(runs: pd.DataFrame, layer: str, metric: str = "relmse") -> Comparison:
    """From the tidy table of one scene: the time checkpoints' errors."""
    column = f"{metric}_{layer}"
    rows = runs[runs["checkpoint_kind"] == "seconds"]
    budgets = sorted(rows["checkpoint_value"].dropna().unique())
    confs, means, ses, seeds = [], [], [], []
    for conf, group in configurations.groups(rows):
        stats = [seed_statistics.mean_and_se(group.loc[group["checkpoint_value"] == b, column]) if column in group
                 else (math.nan, math.nan, 0) for b in budgets]
        confs.append(conf)
        means.append([s[0] for s in stats])
        ses.append([s[1] for s in stats])
        seeds.append(group["run"].nunique())
    return Comparison(configurations.labels(confs), [f"{b:g} s" for b in budgets], _array(means, len(budgets)),
                      _array(ses, len(budgets)), seeds, "method",
                      f"{metric} ({layer}) at equal render time, mean over seeds ± SE")


def equal_error(frames: pd.DataFrame, layer: str, metric: str = "relmse", targets=None) -> Comparison:
    """From the per-frame tidy table of one scene: seconds of render time to reach each target
    error (by default error_curves.error_targets of the configurations' mean first and final
    errors), the targets from the highest down."""
    column = f"{metric}_{layer}"
    grouped = list(configurations.groups(frames))
    if targets is None:
        firsts, finals = [], []
        for _, group in grouped:
            if column in group:
                ends = group.dropna(subset=[column]).groupby("run")[column].agg(["first", "last"])
                firsts.append(ends["first"].mean())
                finals.append(ends["last"].mean())
        targets = error_curves.error_targets(firsts, finals) if firsts else []
    targets = sorted(targets, reverse=True)
    confs, means, ses, seeds = [], [], [], []
    for conf, group in grouped:
        per_run = [[error_curves.time_to_reach(run["seconds"], run[column], target) if column in run else math.nan
                    for target in targets] for _, run in group.groupby("run", sort=False)]
        stats = [seed_statistics.mean_and_se([times[j] for times in per_run]) for j in range(len(targets))]
        confs.append(conf)
        means.append([s[0] for s in stats])
        ses.append([s[1] for s in stats])
        seeds.append(len(per_run))
    return Comparison(configurations.labels(confs), [f"{t:g}" for t in targets], _array(means, len(targets)),
                      _array(ses, len(targets)), seeds, f"method / {metric}",
                      f"render time (s) to reach each {metric} ({layer}), mean over seeds ± SE")


def without_empty_columns(table: Comparison) -> Comparison:
    """The table without the columns no configuration has a value in (checkpoints past every run,
    errors none reaches): they would say only "—"."""
    keep = [j for j in range(len(table.column_labels)) if not np.all(np.isnan(table.means[:, j]))]
    return Comparison(table.row_labels, [table.column_labels[j] for j in keep], table.means[:, keep], table.ses[:, keep],
                      table.seeds, table.corner, table.caption)


def _array(values, columns):
    return np.array(values, dtype=float).reshape(len(values), columns)


def _cells(table: Comparison, bold, dagger, dash, plus_minus):
    """The formatted cells: 3 significant digits, the SE with 2."""
    out = []
    for j in range(len(table.column_labels)):
        column = table.means[:, j]
        best = seed_statistics.best_index(column)
        marks = seed_statistics.within_spread_of_best(column, table.ses[:, j])
        cells = []
        for i, (mean, se) in enumerate(zip(column, table.ses[:, j])):
            if math.isnan(mean):
                cells.append(dash)
                continue
            text = f"{mean:.3g}" + ("" if math.isnan(se) else f"{plus_minus}{se:.2g}")
            cells.append(bold(text) if i == best else text + (dagger if marks[i] else ""))
        out.append(cells)
    return [list(row) for row in zip(*out)] if out else [[] for _ in table.row_labels]


def markdown(table: Comparison) -> str:
    cells = _cells(table, lambda t: f"**{t}**", DAGGER_MD, "—", " ± ")
    header = [table.corner, "seeds"] + table.column_labels
    lines = [f"{table.caption}.", "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join([label, str(n)] + row) + " |" for label, n, row in zip(table.row_labels, table.seeds, cells)]
    return "\n".join(lines + ["", table.footnote(), ""])


def latex_escape(text: str) -> str:
    replacements = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_", "{": r"\{",
                    "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}
    return "".join(replacements.get(c, c) for c in text)


def latex(table: Comparison) -> str:
    cells = _cells(table, lambda t: rf"\textbf{{{t}}}", DAGGER_TEX, "---", r" $\pm$ ")
    header = [latex_escape(table.corner), "seeds"] + [latex_escape(c) for c in table.column_labels]
    footnote = (latex_escape(table.footnote()).replace("±", r"$\pm$").replace("†", DAGGER_TEX).replace("—", "---"))
    lines = [r"\begin{table}", r"\centering", rf"\caption{{{latex_escape(table.caption)}}}",
             r"\begin{tabular}{l" + "r" * (len(header) - 1) + "}", r"\toprule", " & ".join(header) + r" \\", r"\midrule"]
    lines += [" & ".join([latex_escape(label), str(n)] + row) + r" \\" for label, n, row in
              zip(table.row_labels, table.seeds, cells)]
    lines += [r"\bottomrule", r"\end{tabular}", r"\par\smallskip{\footnotesize " + footnote + "}", r"\end{table}", ""]
    return "\n".join(lines).replace("±", r"$\pm$")
