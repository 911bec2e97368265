"""The plots a study asks for ([[plot]] tables), drawn from its results table as SVG.

kind = "xy": `y` against `x`, one line per value of `group`, marked cases labelled (only the
cases that match `where = { variable = value }`, when given);
kind = "histogram": the distribution of `column` over the finished cases, with its 95th
percentile and, when the study gives one, the column's allowance and the fraction over it;
kind = "sensitivity": SALib's indices of `column` per variable with their confidence intervals
(Sobol': S1 and ST bars; Morris: mu* bars).

The legend sits right of the axes, so it covers no curve, mark or label. Every SVG carries its
layout as matplotlib's renderer measured it, in a `<g class="layout">` of empty rects (axes,
legend-box, mark, label; SVG units, pt), which src/report/svg_check.rs checks (docs/plots.md)."""

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

plt.rcParams["svg.hashsalt"] = "mbstudy"  # the same results draw the same file


def draw(study, table, out_dir, prefix="", found=None):
    """The study's [[plot]]s as SVG files in `out_dir`; `found`: analysis.analyse's tables."""
    found = found or {"sensitivity": [], "extremes": [], "allowances": []}
    rows = [r for r in table.to_pylist() if r["status"] == "done"]
    written = []
    for p in study.plots:
        fig, ax = plt.subplots(figsize=(8.5, 4.5))
        if p["kind"] == "xy":
            marks, labels = _xy(ax, p, rows)
        elif p["kind"] == "histogram":
            marks, labels = _histogram(ax, p, rows, found["allowances"])
        elif p["kind"] == "sensitivity":
            marks, labels = _sensitivity(ax, p, found["sensitivity"])
        else:
            raise ValueError(f"[[plot]] {p.get('file')}: unknown kind {p['kind']} (xy, histogram, sensitivity)")
        ax.set_title(p.get("title", study.name))
        fig.tight_layout()
        path = out_dir / (prefix + p["file"])
        path.write_text(with_layout(fig, ax, marks, labels))
        plt.close(fig)
        written.append(path)
    return written


def with_layout(fig, ax, marks, labels):
    """The figure as SVG text with its `<g class="layout">` (see the module doc)."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    to_pt = 72.0 / fig.dpi
    height = fig.get_figheight() * 72.0

    def rect(cls, bb):
        x0, x1, y0, y1 = bb.x0 * to_pt, bb.x1 * to_pt, bb.y0 * to_pt, bb.y1 * to_pt
        return (f'<rect class="{cls}" x="{x0:.2f}" y="{height - y1:.2f}" width="{x1 - x0:.2f}" '
                f'height="{y1 - y0:.2f}" fill="none" stroke="none"/>')

    parts = [rect("axes", ax.get_window_extent(renderer))]
    legend = ax.get_legend()
    if legend is not None:
        parts.append(rect("legend-box", legend.get_window_extent(renderer)))
    parts += [rect("mark", m.get_window_extent(renderer)) for m in marks]
    parts += [rect("label", t.get_window_extent(renderer)) for t in labels]
    buf = io.StringIO()
    fig.savefig(buf, format="svg", metadata={"Date": None})
    svg = buf.getvalue()
    end = svg.rindex("</svg>")
    return svg[:end] + '<g class="layout">' + "".join(parts) + "</g>\n" + svg[end:]


def _legend_outside(ax):
    """The legend right of the axes, top-aligned with them."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)


def _xy(ax, p, rows):
    rows = [r for r in rows if all(r.get(k) == v for k, v in p.get("where", {}).items())]
    groups = sorted({r[p["group"]] for r in rows}) if "group" in p else [None]
    for g in groups:
        sel = sorted((r for r in rows if g is None or r[p["group"]] == g), key=lambda r: r[p["x"]])
        label = None if g is None else f"{p['group']} = {g:g}"
        ax.plot([r[p["x"]] for r in sel], [r[p["y"]] for r in sel], "o-", label=label)
    marks, labels = [], []
    for r in rows:
        if r.get("mark"):
            marks += ax.plot(r[p["x"]], r[p["y"]], "ks", fillstyle="none", markersize=12)
            labels.append(ax.annotate(r["mark"], (r[p["x"]], r[p["y"]]), textcoords="offset points",
                                      xytext=(8, -12)))
    if p.get("logx"):
        ax.set_xscale("log")
    if p.get("logy"):
        ax.set_yscale("log")
    ax.set_xlabel(p.get("xlabel", p["x"]))
    ax.set_ylabel(p.get("ylabel", p["y"]))
    ax.grid(True, alpha=0.3)
    if groups != [None]:
        _legend_outside(ax)
    return marks, labels


def _sensitivity(ax, p, found):
    """Bars of the column's indices per variable, SALib's confidence interval as error bars."""
    mine = [r for r in found if r["column"] == p["column"]]
    names = list(dict.fromkeys(r["variable"] for r in mine))
    keys = ["S1", "ST"] if mine and mine[0]["method"] == "sobol" else ["mu_star"]
    width = 0.8 / len(keys)
    x = np.arange(len(names))
    for k, key in enumerate(keys):
        sel = {r["variable"]: r for r in mine if r["index"] == key}
        v = np.array([sel[n]["value"] if n in sel else np.nan for n in names])
        c = np.array([sel[n]["conf"] if n in sel else np.nan for n in names])
        ax.bar(x + (k - (len(keys) - 1) / 2) * width, v, width, yerr=c, capsize=4,
               label=f"{key} ({int(round(100 * p.get('conf_level', 0.95)))} % interval)")
    ax.set_xticks(x, names)
    ax.set_xlabel(p.get("xlabel", "variable"))
    ax.set_ylabel(p.get("ylabel", f"index of {p['column']}"))
    ax.grid(True, axis="y", alpha=0.3)
    if names:
        _legend_outside(ax)
    return [], []


def _histogram(ax, p, rows, allowances=()):
    x = np.array([r[p["column"]] for r in rows], float)
    x = x[np.isfinite(x)]
    ax.hist(x, bins=p.get("bins", 20), edgecolor="black")
    ax.set_xlabel(p.get("xlabel", p["column"]))
    ax.set_ylabel(f"cases (of {len(x)})")
    if len(x):
        ax.axvline(np.percentile(x, 95), color="k", linestyle="--", label=f"95th percentile {np.percentile(x, 95):.3f}")
        for a in allowances:
            if a["column"] == p["column"]:
                ax.axvline(a["allowance"], color="r", linestyle="-",
                           label=f"allowance {a['allowance']:g}: {a['count']} of {a['n']} {a['side']}")
        _legend_outside(ax)
    return [], []
