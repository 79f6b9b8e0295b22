"""The report's page, index.html: static and self-contained (every asset a relative path inside the
report folder, the CSS and vanilla JS in the page, nothing from the network).

Per scene, an A/B comparison of two images chosen among the reference and the methods (B is revealed
to the right of a divider: drag on the image or move the slider; wheel or click zooms at the pointer,
Shift+click zooms out, Shift+drag pans, double-click resets; A and B always share one zoom), then the
scene's image grid and probe views. After the scenes, the plots and the tables of
paper_outputs.build_figures_and_tables.
"""

import html
import pathlib
import re

STYLE = """
body { font-family: system-ui, sans-serif; margin: 1.5rem auto; max-width: 1100px; padding: 0 1rem; color: #222; }
h1 { margin-bottom: 0.2rem; } nav a { margin-right: 1rem; }
figure { margin: 1rem 0 2rem; } figure img { max-width: 100%; height: auto; border: 1px solid #ddd; }
figcaption { font-size: 0.9rem; color: #444; max-width: 900px; }
.compare { margin: 1rem 0 2rem; max-width: 720px; }
.compare .controls { display: flex; gap: 1rem; align-items: center; flex-wrap: wrap; margin-bottom: 0.4rem; font-size: 0.9rem; }
.compare .viewport { position: relative; overflow: hidden; width: 100%; background: #111; cursor: ew-resize;
  touch-action: none; user-select: none; }
.compare .layer { position: absolute; inset: 0; }
.compare .layer img { position: absolute; left: 0; top: 0; width: 100%; height: 100%; transform-origin: 0 0;
  image-rendering: pixelated; pointer-events: none; }
.compare .divider { position: absolute; top: 0; bottom: 0; width: 2px; margin-left: -1px; background: #fff;
  box-shadow: 0 0 3px #000; pointer-events: none; }
.compare .tag { position: absolute; top: 4px; padding: 1px 6px; background: rgba(0,0,0,0.6); color: #fff;
  font-size: 0.8rem; pointer-events: none; }
.compare .tag.a { left: 4px; } .compare .tag.b { right: 4px; }
.compare input[type=range] { width: 100%; }
table { border-collapse: collapse; margin: 0.5rem 0 1.5rem; font-size: 0.85rem; }
th, td { border: 1px solid #ccc; padding: 2px 8px; text-align: right; } th { background: #f3f3f3; }
td:first-child, th:first-child { text-align: left; }
"""

# The A/B comparisons: one transform (scale s, offset x, y in viewport pixels) per comparison for both
# images, and the divider at a fraction of the width.
SCRIPT = """
(function () {
  function setup(root) {
    var viewport = root.querySelector('.viewport');
    var imgA = root.querySelector('.layer.a img'), imgB = root.querySelector('.layer.b img');
    var layerB = root.querySelector('.layer.b'), divider = root.querySelector('.divider');
    var slider = root.querySelector('input[type=range]');
    var pickA = root.querySelector('select.pick-a'), pickB = root.querySelector('select.pick-b');
    var tagA = root.querySelector('.tag.a'), tagB = root.querySelector('.tag.b');
    var zoomLabel = root.querySelector('.zoom');
    var view = { s: 1, x: 0, y: 0 }, split = 0.5;
    function clamp() {
      var w = viewport.clientWidth, h = viewport.clientHeight;
      view.s = Math.min(64, Math.max(1, view.s));
      view.x = Math.min(0, Math.max(w - w * view.s, view.x));
      view.y = Math.min(0, Math.max(h - h * view.s, view.y));
    }
    function draw() {
      clamp();
      var t = 'translate(' + view.x + 'px,' + view.y + 'px) scale(' + view.s + ')';
      imgA.style.transform = t; imgB.style.transform = t;
      layerB.style.clipPath = 'inset(0 0 0 ' + (100 * split) + '%)';
      divider.style.left = (100 * split) + '%';
      slider.value = Math.round(1000 * split);
      zoomLabel.textContent = view.s.toFixed(view.s < 10 ? 2 : 1) + 'x';
    }
    function zoomAt(px, py, factor) {
      var s = Math.min(64, Math.max(1, view.s * factor));
      view.x = px - (px - view.x) * s / view.s; view.y = py - (py - view.y) * s / view.s; view.s = s;
      draw();
    }
    function pick(select, img, tag) {
      var option = select.options[select.selectedIndex];
      img.src = option.value; img.alt = option.textContent; tag.textContent = option.textContent;
    }
    function local(e) { var r = viewport.getBoundingClientRect(); return [e.clientX - r.left, e.clientY - r.top]; }
    var press = null;
    viewport.addEventListener('pointerdown', function (e) {
      press = { p: local(e), moved: false, pan: e.shiftKey, x: view.x, y: view.y };
      viewport.setPointerCapture(e.pointerId);
    });
    viewport.addEventListener('pointermove', function (e) {
      if (!press) return;
      var p = local(e);
      if (Math.abs(p[0] - press.p[0]) + Math.abs(p[1] - press.p[1]) > 3) press.moved = true;
      if (!press.moved) return;
      if (press.pan) { view.x = press.x + p[0] - press.p[0]; view.y = press.y + p[1] - press.p[1]; }
      else split = Math.min(1, Math.max(0, p[0] / viewport.clientWidth));
      draw();
    });
    viewport.addEventListener('pointerup', function (e) {
      if (press && !press.moved) { var p = local(e); zoomAt(p[0], p[1], e.shiftKey ? 0.5 : 2); }
      press = null;
    });
    viewport.addEventListener('wheel', function (e) {
      e.preventDefault(); var p = local(e); zoomAt(p[0], p[1], Math.exp(-e.deltaY / 300));
    }, { passive: false });
    viewport.addEventListener('dblclick', function () { view = { s: 1, x: 0, y: 0 }; draw(); });
    root.querySelector('button.reset').addEventListener('click', function () { view = { s: 1, x: 0, y: 0 }; split = 0.5; draw(); });
    slider.addEventListener('input', function () { split = slider.value / 1000; draw(); });
    pickA.addEventListener('change', function () { pick(pickA, imgA, tagA); });
    pickB.addEventListener('change', function () { pick(pickB, imgB, tagB); });
    window.addEventListener('resize', draw);
    pick(pickA, imgA, tagA); pick(pickB, imgB, tagB); draw();
  }
  document.querySelectorAll('.compare').forEach(setup);
})();
"""


# A cell of a table's separator row: "---", ":--", "--:", ":-:".
SEPARATOR = re.compile(r":?-+:?")


def esc(text) -> str:
    return html.escape(str(text), quote=True)


def markdown_table_html(markdown: str) -> str:
    """GitHub pipe tables of `markdown` as HTML tables (header row, separator, body rows); any other
    non-empty line as a paragraph. Cells are escaped."""
    def cells(line):
        return [c.strip() for c in line.strip().strip("|").split("|")]

    out, rows = [], []

    def flush():
        if rows:
            head, body = rows[0], [r for r in rows[1:] if not all(SEPARATOR.fullmatch(c) for c in r)]
            out.append("<table><thead><tr>" + "".join(f"<th>{esc(c)}</th>" for c in head) + "</tr></thead><tbody>"
                       + "".join("<tr>" + "".join(f"<td>{esc(c)}</td>" for c in r) + "</tr>" for r in body) + "</tbody></table>")
            rows.clear()

    for line in markdown.splitlines():
        if line.strip().startswith("|"):
            rows.append(cells(line))
            continue
        flush()
        if line.strip():
            out.append(f"<p>{esc(line.strip().lstrip('#').strip())}</p>")
    flush()
    return "\n".join(out)


def figure_html(figure: dict) -> str:
    pdf = f' (<a href="{esc(figure["pdf"])}">PDF</a>)' if figure.get("pdf") else ""
    return (f'<figure><img src="{esc(figure["path"])}" alt="{esc(figure.get("kind", "figure"))}">'
            f'<figcaption>{esc(figure.get("caption", ""))}{pdf}</figcaption></figure>')


def comparison_html(grid) -> str:
    """The A/B view of a scene's images: A the reference, B the first method."""
    options = [(image["path"], image["label"]) for image in grid.comparison]
    b_default = 1 if len(options) > 1 else 0
    height, width = grid.displays["reference"].shape[:2]

    def select(kind, chosen):
        return (f'<select class="pick-{kind}" aria-label="image {kind.upper()}">'
                + "".join(f'<option value="{esc(path)}"{" selected" if i == chosen else ""}>{esc(label)}</option>'
                          for i, (path, label) in enumerate(options)) + "</select>")

    return (f'<div class="compare" id="compare-{esc(grid.slug)}">'
            f'<div class="controls"><label>A (left) {select("a", 0)}</label><label>B (right) {select("b", b_default)}</label>'
            f'<button class="reset" type="button">reset</button><span>zoom <span class="zoom">1.00x</span></span>'
            f'<span>wheel or click: zoom, Shift+click: out, Shift+drag: pan, drag: divider</span></div>'
            f'<div class="viewport" style="aspect-ratio: {width} / {height}">'
            f'<div class="layer a"><img src="{esc(options[0][0])}" alt="{esc(options[0][1])}"></div>'
            f'<div class="layer b"><img src="{esc(options[b_default][0])}" alt="{esc(options[b_default][1])}"></div>'
            f'<div class="divider"></div><span class="tag a"></span><span class="tag b"></span></div>'
            f'<input type="range" class="ab-slider" min="0" max="1000" value="500" aria-label="A/B divider"></div>')


def write_report(out_dir, title: str, outputs: dict, grids: list, probe_figures: list) -> pathlib.Path:
    """Writes out_dir/index.html from what the report's steps made (paths relative to out_dir);
    returns its path."""
    out_dir = pathlib.Path(out_dir)
    scenes = sorted({grid.scene for grid in grids} | {f["scene"] for f in probe_figures})
    body = [f"<h1>gibench report</h1><p>{esc(title)}</p>"]
    links = [f'<a href="#scene-{esc(s)}">{esc(s)}</a>' for s in scenes] + ['<a href="#plots">plots</a>', '<a href="#tables">tables</a>']
    body.append("<nav>" + "".join(links) + "</nav>")
    if not grids:
        body.append("<p>No image grids: no run names a reference image that exists.</p>")
    for scene in scenes:
        body.append(f'<section id="scene-{esc(scene)}"><h2>Scene {esc(scene)}</h2>')
        for grid in (g for g in grids if g.scene == scene):
            body.append(comparison_html(grid))
            body.append(figure_html(grid.figure))
        body += [figure_html(f) for f in probe_figures if f["scene"] == scene]
        body.append("</section>")
    body.append('<section id="plots"><h2>Plots</h2>')
    body += [figure_html(f) for f in outputs.get("figures", [])]
    body.append("</section>")
    body.append('<section id="tables"><h2>Tables</h2>')
    if outputs.get("runs_csv"):
        body.append(f'<p>Every run and checkpoint: <a href="{esc(outputs["runs_csv"])}">{esc(outputs["runs_csv"])}</a></p>')
    for table in outputs.get("tables", []):
        markdown = (out_dir / table["markdown"]).read_text(encoding="utf-8")
        latex = f' (<a href="{esc(table["latex"])}">LaTeX</a>)' if table.get("latex") else ""
        body.append(f'<h3>{esc(table.get("caption", table["markdown"]))}{latex}</h3>' + markdown_table_html(markdown))
    body.append("</section>")
    page = ("<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>gibench report: {esc(title)}</title><style>{STYLE}</style></head>\n<body>\n"
            + "\n".join(body) + f"\n<script>{SCRIPT}</script>\n</body></html>\n")
    index = out_dir / "index.html"
    index.write_text(page, encoding="utf-8")
    return index

