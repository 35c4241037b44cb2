#!/usr/bin/env python3
"""Draws Littoral's charts with matplotlib.

Usage: littoral_plots.py CHARTS.json
CHARTS.json is a list of charts; each is written as PNG next to the JSON file:
  {"file": "name.png", "title": ..., "xlabel": ..., "ylabel": ..., "logx": bool, "logy": bool,
   "series": [{"label": ..., "x": [...], "y": [...], "yerr": [...] or [], "markers": bool,
               "dashed": bool, "line": bool, "colour": n}]}
("colour" >= 0 picks the n-th colour of matplotlib's cycle, so that a prediction and its points match.)
Non-finite values (JSON null) and, on log axes, non-positive values are left out of a series.
Littoral writes this script beside the data, so a chart can be redrawn or restyled by hand.
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogFormatterSciNotation, LogLocator, NullFormatter  # noqa: E402


def finite(v):
    return v is not None and isinstance(v, (int, float)) and math.isfinite(v)


def points(series, logx, logy):
    xs, ys, es = [], [], []
    yerr = series.get("yerr") or []
    for i, (x, y) in enumerate(zip(series.get("x", []), series.get("y", []))):
        if not (finite(x) and finite(y)):
            continue
        if (logx and x <= 0) or (logy and y <= 0):
            continue
        xs.append(x)
        ys.append(y)
        e = yerr[i] if i < len(yerr) else None
        es.append(e if finite(e) and e >= 0 else 0.0)
    return xs, ys, es


def log_axis(axis, values):
    """Round-number ticks on a log axis: 1-2-5 (or denser) steps printed as plain numbers when the
    data spans few decades, powers of ten when it spans many."""
    values = [v for v in values if v > 0]
    span = math.log10(max(values) / min(values)) if values else 3
    if span < 1:
        subs = (1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0)
    elif span < 2.5:
        subs = (1.0, 2.0, 5.0)
    else:
        subs = None
    if subs:
        axis.set_major_locator(LogLocator(base=10, subs=subs))
        axis.set_major_formatter(FuncFormatter(lambda v, _: "%g" % float("%.3g" % v)))
    else:
        axis.set_major_locator(LogLocator(base=10))
        axis.set_major_formatter(LogFormatterSciNotation(base=10))
    axis.set_minor_formatter(NullFormatter())


def draw(chart, folder):
    logx, logy = bool(chart.get("logx")), bool(chart.get("logy"))
    fig, ax = plt.subplots(figsize=(7.0, 4.4), dpi=110)
    drawn = 0
    all_x, all_y = [], []
    for s in chart.get("series", []):
        xs, ys, es = points(s, logx, logy)
        if not xs:
            continue
        all_x += xs
        all_y += ys
        style = "--" if s.get("dashed") else "-"
        if not s.get("line", True):
            style = "none"
        marker = "o" if s.get("markers", True) else None
        extra = {}
        if isinstance(s.get("colour"), int) and s["colour"] >= 0:
            extra["color"] = "C%d" % (s["colour"] % 10)
        if any(e > 0 for e in es):
            ax.errorbar(xs, ys, yerr=es, linestyle=style, marker=marker, markersize=4, capsize=3,
                        label=s.get("label"), **extra)
        else:
            ax.plot(xs, ys, linestyle=style, marker=marker, markersize=4, label=s.get("label"), **extra)
        drawn += 1
    if logx:
        ax.set_xscale("log")
        log_axis(ax.xaxis, all_x)
    if logy:
        ax.set_yscale("log")
        log_axis(ax.yaxis, all_y)
    if chart.get("invert_y"):
        ax.invert_yaxis()
    ax.set_title(chart.get("title", ""), fontsize=11)
    ax.set_xlabel(chart.get("xlabel", ""))
    ax.set_ylabel(chart.get("ylabel", ""))
    ax.grid(True, which="major", alpha=0.3)
    if drawn == 0:
        ax.text(0.5, 0.5, "no finite data", transform=ax.transAxes, ha="center", va="center")
    elif drawn > 1 or chart.get("series", [{}])[0].get("label"):
        # Outside the axes, to the right; bbox_inches="tight" keeps it inside the image.
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    path = os.path.join(folder, chart["file"])
    tmp = path + ".tmp.png"
    fig.savefig(tmp, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)


def main():
    if len(sys.argv) != 2:
        sys.stderr.write("usage: littoral_plots.py CHARTS.json\n")
        return 2
    with open(sys.argv[1]) as f:
        charts = json.load(f)
    folder = os.path.dirname(os.path.abspath(sys.argv[1]))
    for chart in charts:
        draw(chart, folder)
    return 0


if __name__ == "__main__":
    sys.exit(main())
