"""The probe views of a probe-cache run, as the seed paper's Figures 5 and 6 show them (PNG and PDF,
no title):

  left   (Figure 5, probe allocation) the run's image with every uncovered surface pixel, coverage 0
         where a surface is seen (depth > 0), in one flat colour, and the probes' positions as
         markers (layer probe_centres)
  right  (Figure 6, irradiance probes) layer probe_splat: each pixel lit by its nearest serving probe
         alone, so each probe shows as a flat patch over its footprint, with the same markers

Runs write layer "coverage" always and the two probe layers with the method key "probe_views": true
(methods/probe_cache/probe_views.h); without them only the left panel is drawn, without markers.
The left panel has the exposure of the scene's image grid; the right one its own (the same rule,
image_grid.exposure_for): it shows reflected light arriving, far dimmer than the image.
"""

import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import exr_io  # noqa: E402
import image_grid  # noqa: E402

UNCOVERED_COLOUR = (1.0, 0.0, 1.0)  # magenta: no rendered image shows it
MARKER_COLOUR = "#00ff66"


def uncovered_mask(coverage: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """Pixels that see a surface (depth > 0: gibench's depth is 0 where a pixel sees none) and that no
    probe covers (coverage == 0)."""
    return (coverage[:, :, 0] == 0) & (depth[:, :, 0] > 0)


def mark_uncovered(display: np.ndarray, mask: np.ndarray, colour=UNCOVERED_COLOUR) -> np.ndarray:
    """A copy of the display image with exactly the pixels of `mask` in `colour`."""
    marked = np.array(display, dtype=np.float64, copy=True)
    marked[mask] = colour
    return marked


def probe_pixels(centres: np.ndarray) -> tuple:
    """(x, y) of the pixels with a probe on them, as arrays."""
    ys, xs = np.nonzero(centres[:, :, 0] > 0)
    return xs, ys


def probe_view(run, out_dir, exposure: float, slug: str) -> dict:
    """Draws the run's probe views into out_dir/figures/probe_views_<slug>.{png,pdf}; its figure record
    (as image_grid's), or None when the run's image has no coverage layer (not a probe cache)."""
    layers = exr_io.read_layers(run.folder / "image.exr")
    if "coverage" not in layers or "depth" not in layers:
        return None
    mask = uncovered_mask(layers["coverage"], layers["depth"])
    allocation = mark_uncovered(image_grid.tone_map(layers["total"], exposure), mask)
    panels = [("probes and coverage", allocation)]
    if "probe_splat" in layers:
        splat_exposure = image_grid.exposure_for(layers["probe_splat"])
        panels.append(("nearest probe's irradiance / pi", image_grid.tone_map(layers["probe_splat"], splat_exposure)))
    markers = probe_pixels(layers["probe_centres"]) if "probe_centres" in layers else None

    fig, axes = plt.subplots(1, len(panels), figsize=(3.2 * len(panels), 3.4), squeeze=False)
    for ax, (label, image) in zip(axes[0], panels):
        ax.imshow(image, interpolation="nearest")
        if markers is not None:
            ax.scatter(markers[0], markers[1], s=14, facecolors="none", edgecolors=MARKER_COLOUR, linewidths=0.9)
        ax.set_xlabel(label, fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    figures = pathlib.Path(out_dir) / "figures"
    figures.mkdir(parents=True, exist_ok=True)
    stem = figures / f"probe_views_{slug}"
    fig.savefig(stem.with_suffix(".png"), dpi=150, bbox_inches="tight")
    fig.savefig(stem.with_suffix(".pdf"), bbox_inches="tight")
    plt.close(fig)

    surface = int(np.count_nonzero(layers["depth"][:, :, 0] > 0))
    share = f"{100.0 * np.count_nonzero(mask) / surface:.1f} %" if surface else "no"
    caption = (f"Probes of run {run.experiment}/{run.name} ({run.method}, scene {image_grid.scene_name(run)}), last frame: "
               f"its image with the uncovered surface pixels ({share} of them) in magenta")
    if markers is not None:
        caption += f", and the {int(layers['probe_centres'][:, :, 0].sum())} probes in view as green circles"
    if "probe_splat" in layers:
        caption += ("; right, each pixel lit by its nearest serving probe alone (the reflected light it caches: irradiance at "
                    f"the probe's normal / pi, no blending), exposure {splat_exposure:+.2f} stops")
    else:
        caption += " (the run had no probe_views layers)"
    caption += f". Left: exposure {exposure:+.2f} stops, as the scene's image grid."
    return {"path": f"figures/probe_views_{slug}.png", "pdf": f"figures/probe_views_{slug}.pdf", "caption": caption,
            "scene": image_grid.scene_name(run), "kind": "probe_views"}


def build_probe_views(runs: list, out_dir, grids: list) -> list:
    """The figure records of the views of one probe-cache run per configuration (experiment, scene,
    method and sweep axes but the seed: its first seed's run), each at the exposure of its scene's
    grid (the first grid of the scene; a scene without one, at its own image's exposure)."""
    exposures = {}
    for grid in grids:
        exposures.setdefault(grid.scene, grid.exposure)
    shown = {}
    for run in sorted(runs, key=lambda run: str(run.folder)):
        shown.setdefault((run.experiment, image_grid.scene_name(run), run.method, image_grid.configuration(run)), run)
    figures = []
    for run in shown.values():
        scene = image_grid.scene_name(run)
        exposure = exposures.get(scene)
        if exposure is None or not math.isfinite(exposure):
            exposure = image_grid.exposure_for(exr_io.read_layer(run.folder / "image.exr", "total"))
        slug = image_grid.slug_of(f"{run.experiment}_{run.name}")
        figure = probe_view(run, out_dir, exposure, slug)
        if figure is not None:
            figures.append(figure)
    return figures
