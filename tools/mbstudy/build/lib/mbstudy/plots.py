"""The plots a study asks for ([[plot]] tables), drawn from its results table as SVG.

kind = "xy": `y` against `x`, one line per value of `group`, marked cases labelled;
kind = "histogram": the distribution of `column` over the finished cases."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

plt.rcParams["svg.hashsalt"] = "mbstudy"  # the same results draw the same file


def draw(study, table, out_dir):
    rows = [r for r in table.to_pylist() if r["status"] == "done"]
    written = []
    for p in study.plots:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        if p["kind"] == "xy":
            _xy(ax, p, rows)
        elif p["kind"] == "histogram":
            _histogram(ax, p, rows)
        else:
            raise ValueError(f"[[plot]] {p.get('file')}: unknown kind {p['kind']} (xy, histogram)")
        ax.set_title(p.get("title", study.name))
        fig.tight_layout()
        path = out_dir / p["file"]
        fig.savefig(path, metadata={"Date": None})
        plt.close(fig)
        written.append(path)
    return written


def _xy(ax, p, rows):
    groups = sorted({r[p["group"]] for r in rows}) if "group" in p else [None]
    for g in groups:
        sel = sorted((r for r in rows if g is None or r[p["group"]] == g), key=lambda r: r[p["x"]])
        label = None if g is None else f"{p['group']} = {g:g}"
        ax.plot([r[p["x"]] for r in sel], [r[p["y"]] for r in sel], "o-", label=label)
    for r in rows:
        if r.get("mark"):
            ax.plot(r[p["x"]], r[p["y"]], "ks", fillstyle="none", markersize=12)
            ax.annotate(r["mark"], (r[p["x"]], r[p["y"]]), textcoords="offset points", xytext=(8, -12))
    if p.get("logx"):
        ax.set_xscale("log")
    if p.get("logy"):
        ax.set_yscale("log")
    ax.set_xlabel(p.get("xlabel", p["x"]))
    ax.set_ylabel(p.get("ylabel", p["y"]))
    ax.grid(True, alpha=0.3)
    if groups != [None]:
        ax.legend()


def _histogram(ax, p, rows):
    x = np.array([r[p["column"]] for r in rows], float)
    x = x[np.isfinite(x)]
    ax.hist(x, bins=p.get("bins", 20), edgecolor="black")
    ax.set_xlabel(p.get("xlabel", p["column"]))
    ax.set_ylabel(f"cases (of {len(x)})")
    if len(x):
        ax.axvline(np.percentile(x, 95), color="k", linestyle="--", label=f"95th percentile {np.percentile(x, 95):.3f}")
        ax.legend()
