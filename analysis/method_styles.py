"""The colour and marker of each method, the same in every figure and image grid.

The five methods gibench ships have fixed styles; any other method name gets one from a fallback
palette picked by a hash of its name, so it keeps its style from one run of the analysis to the next
(Python's own hash() is salted per process, hence SHA-256).
"""

import hashlib

METHOD_STYLES = {
    "path_traced": {"color": "#4d4d4d", "marker": "s"},
    "mamba": {"color": "#d62728", "marker": "o"},
    "dense_grid": {"color": "#1f77b4", "marker": "^"},
    "cards": {"color": "#2ca02c", "marker": "D"},
    "hash_grid": {"color": "#9467bd", "marker": "v"},
}

# Colours and markers none of the fixed styles use.
FALLBACK_COLORS = ("#ff7f0e", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f")
FALLBACK_MARKERS = ("P", "X", "*", "h", "<", ">")


def method_style(method: str) -> dict:
    """{"color": "#rrggbb", "marker": a matplotlib marker} of a method (a copy: callers may change it)."""
    if method in METHOD_STYLES:
        return dict(METHOD_STYLES[method])
    digest = int.from_bytes(hashlib.sha256(method.encode("utf-8")).digest()[:8], "big")
    return {"color": FALLBACK_COLORS[digest % len(FALLBACK_COLORS)],
            "marker": FALLBACK_MARKERS[(digest // len(FALLBACK_COLORS)) % len(FALLBACK_MARKERS)]}
