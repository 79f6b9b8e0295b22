"""Per scene, one figure of images side by side (PNG and PDF, no title; the caption says what is shown):

  row 1            the reference, then each method's image at equal time, with the crop regions outlined
  one row/region   those images zoomed into the region (nearest-neighbour, so pixels stay visible)
  last row         each method's relative squared error per pixel, (x - r)^2 / (r^2 + 0.01) averaged
                   over R, G, B (the per-pixel term of gibench's relMSE, core/image/metrics.h), on
                   one log colour scale with a colour bar

Every image of a grid is tone-mapped with one exposure, the reference's (its log-average luminance,
Reinhard et al. 2002's key, maps to middle grey), as gibench writes its PNGs: radiance x 2^exposure,
clamped to [0, 1], sRGB-encoded. Method colours come from method_styles.

Equal time: when every run of the scene stopped at the same render-time budget, each run's final
image; otherwise the frame_NNNN.exr of each run closest to the time the fastest run finished (when
the runs wrote any), else the final images, with each one's time in the caption.

Regions are (x, y, width, height) in pixels, (0, 0) the top-left corner; by default one square,
a quarter of the image's shorter side, where the best cache (lowest relMSE of the layer, path
tracing apart) has its highest summed error.
"""

import dataclasses
import json
import math
import pathlib
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors as mcolors  # noqa: E402
import matplotlib.patches as mpatches  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import configurations  # noqa: E402
import exr_io  # noqa: E402
from input_error import InputError  # noqa: E402

# kRelMseEpsilon of core/image/metrics.h: keeps the error finite where the reference is black.
REL_MSE_EPSILON = 0.01
# Middle grey, what the log-average luminance maps to, and the offset that keeps black pixels out of
# the logarithm (Reinhard et al. 2002, "Photographic tone reproduction", equation 1).
MIDDLE_GREY = 0.18
LOG_AVERAGE_DELTA = 1e-4
# Rec. 709 luminance weights (core/util/math.h).
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
# Outline colours of the crop regions, in order.
REGION_COLOURS = ("#ffd700", "#00e5ff", "#ff4fd8", "#7cfc00")
ERROR_COLOURMAP = "inferno"
PATH_TRACED = "path_traced"


@dataclasses.dataclass
class Column:
    """One image of a grid after the reference: a method's, at `seconds` of render time."""
    label: str
    method: str
    image: np.ndarray  # height x width x 3, linear
    seconds: float = math.nan
    relmse: float = math.nan  # of the image against the reference, the mean of its error map


@dataclasses.dataclass
class SceneGrid:
    scene: str
    slug: str  # file-name-safe and unique among the grids of a report
    exposure: float
    regions: list  # (x, y, width, height)
    displays: dict  # label -> tone-mapped image (height x width x 3 in [0, 1]), "reference" first
    error_maps: dict  # label -> relative squared error per pixel (height x width)
    figure: dict  # {"path", "pdf", "caption", "scene", "kind"}, paths relative to the output folder
    comparison: list  # [{"label", "method", "path"}]: one PNG per image, for the report's A/B view


def relative_squared_error(image: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """(x - r)^2 / (r^2 + REL_MSE_EPSILON) per pixel, averaged over the first 3 channels."""
    x, r = image[:, :, :3].astype(np.float64), reference[:, :, :3].astype(np.float64)
    return np.mean((x - r) ** 2 / (r * r + REL_MSE_EPSILON), axis=2)


def exposure_for(image: np.ndarray) -> float:
    """The exposure (log2 scale) that shows the image's log-average luminance as MIDDLE_GREY; 0 for an
    empty or black image."""
    luminance = np.clip(np.nan_to_num(image[:, :, :3].astype(np.float64) @ LUMINANCE, nan=0.0, posinf=0.0), 0.0, None)
    if luminance.size == 0 or not luminance.any():
        return 0.0
    key = float(np.exp(np.mean(np.log(LOG_AVERAGE_DELTA + luminance))))
    return math.log2(MIDDLE_GREY / key)


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1) of values in [0, 1], as core/image/image.h's."""
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(linear, 1 / 2.4) - 0.055)


def tone_map(rgb: np.ndarray, exposure: float) -> np.ndarray:
    """Display values in [0, 1]: radiance x 2^exposure, clamped, sRGB-encoded; NaN shows as black."""
    scaled = np.nan_to_num(rgb[:, :, :3].astype(np.float64) * 2.0 ** exposure, nan=0.0)
    return srgb_encode(np.clip(scaled, 0.0, 1.0))


def to_bytes(display: np.ndarray) -> np.ndarray:
    """8-bit values of display values in [0, 1], rounded as gibench's PNGs: floor(255 v + 0.5)."""
    return np.floor(255.0 * display + 0.5).astype(np.uint8)


def highest_error_region(error_map: np.ndarray, size: int) -> tuple:
    """The size x size window (clipped to the image) with the largest sum of error_map; the first
    in row order among equal ones."""
    height, width = error_map.shape
    w, h = min(size, width), min(size, height)
    table = np.zeros((height + 1, width + 1))
    table[1:, 1:] = np.nan_to_num(error_map, nan=0.0, posinf=0.0).cumsum(axis=0).cumsum(axis=1)
    sums = table[h:, w:] - table[:-h, w:] - table[h:, :-w] + table[:-h, :-w]
    y, x = np.unravel_index(int(np.argmax(sums)), sums.shape)
    return (int(x), int(y), w, h)


def default_region_size(width: int, height: int) -> int:
    return max(1, min(width, height) // 4)


def check_regions(regions, width: int, height: int, where: str) -> list:
    """The regions as int tuples; InputError naming `where` for one outside the image or empty."""
    checked = []
    for region in regions:
        x, y, w, h = (int(v) for v in region)
        if w < 1 or h < 1 or x < 0 or y < 0 or x + w > width or y + h > height:
            raise InputError(f"{where}: region {x},{y},{w},{h} is not inside the {width}x{height} image "
                             f"(expected x,y,width,height with width, height >= 1)")
        checked.append((x, y, w, h))
    return checked


def slug_of(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_") or "scene"


def best_cache(columns: list) -> Column:
    """The column with the lowest relMSE among the caches (not path tracing), or among all when only
    path tracing ran."""
    caches = [c for c in columns if c.method != PATH_TRACED] or columns
    return min(caches, key=lambda c: c.relmse if math.isfinite(c.relmse) else math.inf)


def compose_grid(scene: str, slug: str, reference: np.ndarray, columns: list, out_dir, regions=None, note: str = "",
                 layer: str = "total") -> SceneGrid:
    """Draws the grid of `columns` against `reference` into out_dir/figures/image_grid_<slug>.{png,pdf} and
    each image, tone-mapped, into out_dir/images/<slug>/<n>.png. `note` says how the images were
    picked in time; regions None: the best cache's highest-error square."""
    out_dir = pathlib.Path(out_dir)
    height, width = reference.shape[:2]
    for column in columns:
        if column.image.shape[:2] != (height, width):
            raise InputError(f"{column.label}: a {column.image.shape[1]}x{column.image.shape[0]} image, "
                             f"but the reference of scene {scene} is {width}x{height}")
    error_maps = {c.label: relative_squared_error(c.image, reference) for c in columns}
    for column in columns:
        column.relmse = float(np.mean(error_maps[column.label]))
    automatic = regions is None
    if automatic:
        best = best_cache(columns) if columns else None
        regions = [highest_error_region(error_maps[best.label], default_region_size(width, height))] if best else []
    regions = check_regions(regions, width, height, f"scene {scene}")
    exposure = exposure_for(reference)
    displays = {"reference": tone_map(reference, exposure)}
    displays.update({c.label: tone_map(c.image, exposure) for c in columns})

    figure_dir, image_dir = out_dir / "figures", out_dir / "images" / slug
    figure_dir.mkdir(parents=True, exist_ok=True)
    image_dir.mkdir(parents=True, exist_ok=True)
    comparison = []
    for index, (label, display) in enumerate(displays.items()):
        path = image_dir / f"{index}.png"
        plt.imsave(path, to_bytes(display))
        method = "reference" if index == 0 else columns[index - 1].method
        comparison.append({"label": label, "method": method, "path": path.relative_to(out_dir).as_posix()})

    _draw(displays, columns, error_maps, regions, figure_dir / f"image_grid_{slug}")
    caption = _caption(scene, layer, columns, regions, automatic, exposure, note)
    figure = {"path": f"figures/image_grid_{slug}.png", "pdf": f"figures/image_grid_{slug}.pdf", "caption": caption, "scene": scene,
              "kind": "image_grid"}
    return SceneGrid(scene, slug, exposure, regions, displays, error_maps, figure, comparison)


def error_norm(error_maps) -> mcolors.LogNorm:
    """One log scale for every error map of a grid: from the 1st percentile of their positive values to
    the largest (at least a decade apart, so that a flat map still shows)."""
    values = np.concatenate([m[np.isfinite(m) & (m > 0)].ravel() for m in error_maps] + [np.zeros(0)])
    if values.size == 0:
        return mcolors.LogNorm(1e-6, 1e-5)
    low, high = float(np.percentile(values, 1)), float(values.max())
    return mcolors.LogNorm(min(low, high / 10), high)


def _draw(displays, columns, error_maps, regions, stem: pathlib.Path):
    from method_styles import method_style

    labels = list(displays)
    rows = 2 + len(regions)
    cell = 2.0
    fig, axes = plt.subplots(rows, len(labels), figsize=(cell * len(labels) + 0.9, cell * rows), squeeze=False,
                             gridspec_kw={"wspace": 0.04, "hspace": 0.12})
    colours = ["black"] + [method_style(c.method)["color"] for c in columns]
    for col, label in enumerate(labels):
        ax = axes[0][col]
        ax.imshow(displays[label], interpolation="nearest")
        details = ""
        if col > 0:
            column = columns[col - 1]
            details = "\n" + (f"{column.seconds:.3g} s, " if math.isfinite(column.seconds) else "") + f"relMSE {column.relmse:.3g}"
        ax.set_title(label.replace(" (", "\n(") + details, color=colours[col], fontsize=9)
        for k, (x, y, w, h) in enumerate(regions):
            ax.add_patch(mpatches.Rectangle((x - 0.5, y - 0.5), w, h, fill=False, lw=1.2, ec=REGION_COLOURS[k % len(REGION_COLOURS)]))
        for k, (x, y, w, h) in enumerate(regions):
            crop = axes[1 + k][col]
            crop.imshow(displays[label][y:y + h, x:x + w], interpolation="nearest")
            for spine in crop.spines.values():
                spine.set_edgecolor(REGION_COLOURS[k % len(REGION_COLOURS)])
                spine.set_linewidth(2)
    norm = error_norm(list(error_maps.values()))
    mappable = None
    for col, label in enumerate(labels[1:], start=1):
        values = np.clip(np.nan_to_num(error_maps[label], nan=norm.vmax, posinf=norm.vmax), norm.vmin, None)
        mappable = axes[-1][col].imshow(values, cmap=ERROR_COLOURMAP, norm=norm, interpolation="nearest")
    axes[-1][0].text(0.5, 0.5, "relative\nsquared error", ha="center", va="center", fontsize=9, transform=axes[-1][0].transAxes)
    for ax in axes.ravel():
        ax.set_xticks([])
        ax.set_yticks([])
    for ax in axes[1:, :].ravel():
        if not ax.images:
            ax.axis("off")
    if mappable is not None:
        fig.colorbar(mappable, ax=list(axes[-1, :]), fraction=0.04, pad=0.02)
    fig.savefig(stem.with_suffix(".png"), dpi=150, bbox_inches="tight")
    fig.savefig(stem.with_suffix(".pdf"), bbox_inches="tight")
    plt.close(fig)


def _caption(scene, layer, columns, regions, automatic, exposure, note) -> str:
    methods = ", ".join(f"{c.label} ({c.seconds:.3g} s)" if math.isfinite(c.seconds) else c.label for c in columns)
    where = "; ".join(f"({x}, {y}) {w}x{h}" for x, y, w, h in regions)
    if automatic and columns:
        where += f", chosen where {best_cache(columns).label}, the best cache, has its highest error"
    return (f"Scene {scene}, layer {layer}: the reference, then {methods}. {note} "
            f"One exposure for every image ({exposure:+.2f} stops). Zoomed crops: {where}. Bottom row: relative squared "
            f"error per pixel, (x - r)^2 / (r^2 + {REL_MSE_EPSILON}) averaged over R, G, B, log colour scale.").replace("  ", " ")


# --- From the runs of a results folder ----------------------------------------------------------

def reference_file(run) -> pathlib.Path:
    """The reference image a run was measured against: <root>/references/<key>.exr when the results
    root (two levels up from the run) holds it, else the file the manifest names; None when none."""
    reference = run.manifest.get("reference") or {}
    key = reference.get("key")
    if key:
        stored = run.folder.parent.parent / "references" / f"{key}.exr"
        if stored.is_file():
            return stored
    for field in ("image", "file"):
        if reference.get(field) and pathlib.Path(reference[field]).is_file():
            return pathlib.Path(reference[field])
    return None


def scene_name(run) -> str:
    scene = run.config.get("scene")
    if isinstance(scene, str):
        return pathlib.PurePath(scene).stem
    if isinstance(scene, dict):
        return str(scene.get("name") or "inline")
    return "scene"


def final_seconds(run) -> float:
    return float(run.frames[-1]["cumulative_seconds"]) if run.frames else math.nan


def budget_seconds(run):
    budget = run.config.get("budget")
    return budget.get("seconds") if isinstance(budget, dict) else None


def frame_files(run) -> dict:
    """{frame index: frame_NNNN.exr} of a run."""
    files = {}
    for file in run.folder.glob("frame_*.exr"):
        match = re.fullmatch(r"frame_(\d+)\.exr", file.name)
        if match:
            files[int(match.group(1))] = file
    return files


def image_at(run, seconds: float) -> tuple:
    """(file, its frame's cumulative seconds) of the run's image closest to `seconds`: its
    frame_NNNN.exr files and its final image.exr."""
    times = {int(f.get("frame", i)): float(f["cumulative_seconds"]) for i, f in enumerate(run.frames)}
    candidates = [(file, times[frame]) for frame, file in frame_files(run).items() if frame in times]
    candidates.append((run.folder / "image.exr", final_seconds(run)))
    return min(candidates, key=lambda c: (abs(c[1] - seconds), c[1]))


def equal_time_images(runs: list) -> tuple:
    """([(run, file, seconds)], note): each run's image at equal time, and how they were chosen."""
    budgets = {budget_seconds(run) for run in runs}
    if len(budgets) == 1 and None not in budgets:
        return ([(run, run.folder / "image.exr", final_seconds(run)) for run in runs],
                f"Each run's final image: every run stopped at its render-time budget of {budgets.pop():.3g} s.")
    if any(frame_files(run) for run in runs):
        target = min(final_seconds(run) for run in runs)
        return ([(run, *image_at(run, target)) for run in runs],
                f"Equal time: each run's saved frame (frame_NNNN.exr) closest to {target:.3g} s, when the fastest run finished.")
    return ([(run, run.folder / "image.exr", final_seconds(run)) for run in runs],
            "Each run's final image (the runs had no common budget and saved no intermediate frames: times differ).")


def representative(runs: list, layer: str) -> tuple:
    """The run of several of one method whose final relMSE of `layer` is the median, with the count."""
    def error(run):
        value = ((run.metrics.get("error") or {}).get(layer) or {}).get("relmse")
        return value if isinstance(value, (int, float)) else math.inf
    ordered = sorted(runs, key=lambda run: (error(run), str(run.folder)))
    return ordered[(len(ordered) - 1) // 2], len(ordered)


def scene_groups(runs: list) -> dict:
    """{(experiment, scene, reference file): runs}: the runs one grid shows; runs without a
    reference are left out."""
    groups = {}
    for run in runs:
        reference = reference_file(run)
        if reference is not None:
            groups.setdefault((run.experiment, scene_name(run), reference), []).append(run)
    return groups


def configuration(run) -> tuple:
    """What sets a run apart from the other seeds of its configuration: its sweep axes but the seed
    and the scene, as sorted (key, JSON text) pairs; () for a run no sweep made."""
    axes = (run.manifest.get("sweep") or {}).get("axes") or {}
    return tuple(sorted((key, json.dumps(value, sort_keys=True)) for key, value in axes.items() if key not in ("seed", "scene")))


def column_labels(keys: list) -> dict:
    """{(method, configuration): label}, the labels of the tables and figures
    (configurations.labels()): the method, then the axes that differ between the configurations of
    that method ("mamba (gather_neighbours=4)"); a method block's keys count one by one."""
    def parameters(method, conf):
        flat = {"method": method}
        for key, text in conf:
            value = json.loads(text)
            if key == "method" and isinstance(value, dict):
                flat.update({k: v for k, v in value.items() if k != "name"})
            elif key != "method.name":
                flat[key.rsplit(".", 1)[-1]] = value
        # Lists and blocks as text: a label shows them as written, and they compare by value.
        return {k: json.dumps(v) if isinstance(v, (list, dict)) else v for k, v in flat.items()}
    confs = [parameters(method, conf) for method, conf in keys]
    keys_of_all = sorted({k for conf in confs for k in conf})
    confs = [{k: conf.get(k) for k in keys_of_all} for conf in confs]
    return dict(zip(keys, configurations.labels(confs)))


def build_image_grids(runs: list, out_dir, regions=None, layer: str = "total") -> list:
    """A SceneGrid per scene and reference among `runs` (results_reader.Run), one column per method
    (the median-error run where a method ran several times)."""
    grids = []
    groups = scene_groups(runs)
    scenes = [(experiment, scene) for experiment, scene, _ in groups]
    for (experiment, scene, reference), group in sorted(groups.items(), key=lambda item: (item[0][0], item[0][1], str(item[0][2]))):
        by_column = {}
        for run in group:
            by_column.setdefault((run.method, configuration(run)), []).append(run)
        labels = column_labels(sorted(by_column))
        chosen = {labels[key]: representative(column_runs, layer) for key, column_runs in sorted(by_column.items())}
        picks, note = equal_time_images([run for run, _ in chosen.values()])
        several = [f"{label}: the median-error run of {count}" for label, (_, count) in chosen.items() if count > 1]
        if several:
            note += " " + "; ".join(several) + "."
        label_of = {id(run): label for label, (run, _) in chosen.items()}
        columns = [Column(label_of[id(run)], run.method, exr_io.read_layer(file, layer)[:, :, :3], seconds) for run, file, seconds in picks]
        reference_image = exr_io.read_layer(reference, layer)[:, :, :3]
        slug = slug_of(f"{experiment}_{scene}" if scenes.count((experiment, scene)) == 1 else f"{experiment}_{scene}_{reference.stem[:12]}")
        grids.append(compose_grid(scene, slug, reference_image, columns, out_dir, regions, note, layer))
    return grids
