"""Configurations: the groups of runs that differ only in their seed, and how to name them.

Every curve point and table entry of the analysis is a statistic over the seeds of one
configuration (seed_statistics.py). A configuration is everything the tidy table records about a
run's setup (runs_table.py): experiment, scene, method, the swept parameters and the common ones,
but neither seed nor run name nor run id.
"""

import pandas as pd

import runs_table
from method_styles import METHOD_STYLES

PER_RUN = ("run_id", "run", "seed")


def configuration_columns(table: pd.DataFrame) -> list:
    """The columns naming a configuration: identity and parameter columns but the per-run ones."""
    first, end = list(table.columns).index("experiment"), list(table.columns).index(runs_table.OUTCOME_COLUMNS[0])
    return [c for c in list(table.columns)[first:end] if c not in PER_RUN]


def groups(table: pd.DataFrame) -> list:
    """[(configuration dict, its rows)]: methods in METHOD_STYLES' order (any other after, by name),
    configurations of one method in the order they first appear."""
    columns = configuration_columns(table)
    found = [(dict(zip(columns, key if isinstance(key, tuple) else (key,))), rows)
             for key, rows in table.groupby(columns, dropna=False, sort=False)]
    order = list(METHOD_STYLES)

    def rank(method):
        return (order.index(method), "") if method in order else (len(order), str(method))
    return sorted(found, key=lambda item: rank(item[0]["method"]))


def _text(value) -> str:
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return f"{value:g}" if isinstance(value, float) else str(value)


def labels(configurations: list) -> list:
    """A short label per configuration: its method, then "key=value" of each parameter that differs
    between the given configurations of that method (so a plain method comparison reads just
    "mamba", "path_traced", whatever parameters only one of them has)."""
    def varying(method):
        same = [conf for conf in configurations if conf["method"] == method]
        return [c for c in same[0] if c not in ("method", "experiment", "scene") and len({_text(conf.get(c)) for conf in same}) > 1]
    shown = {conf["method"]: varying(conf["method"]) for conf in configurations}

    def label(conf):
        parts = [f"{c}={_text(conf[c])}" for c in shown[conf["method"]] if not pd.isna(conf.get(c))]
        return str(conf["method"]) + (f" ({', '.join(parts)})" if parts else "")
    return [label(conf) for conf in configurations]
