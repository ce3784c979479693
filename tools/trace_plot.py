#!/usr/bin/env python3
"""Draws a trace written by `glint --trace` as an SVG timeline: a Gantt chart of where the threads' time went.

One row per thread of the trace (main, worker 1, ..., sample passes), in the trace's own order; on a thread's
row, each tile pass is a box coloured by its pass, each wait a grey box, and the other steps (scene loading,
BVH build, checkpoint and image writes) a thin bar above the tiles with its name when there is room. Hovering
over a box in a browser shows the event's name, times and arguments. It reads what Perfetto reads, so it is
a stand-in for a screenshot of https://ui.perfetto.dev where no browser is at hand (docs/benchmarks.md).
Python's standard library only.

Usage: trace_plot.py TRACE.json OUT.svg [--width PIXELS] [--title TEXT]
"""
import argparse
import html
import json
import sys

# Pass colours: a sequential palette from light to dark, so that later (longer) passes read as deeper.
PASS_COLOURS = ["#c6dbef", "#9ecae1", "#6baed6", "#4292c6", "#2171b5", "#08519c", "#08306b",
                "#41ab5d", "#238b45", "#006d2c", "#00441b"]
STAGE_COLOURS = {"load": "#e6550d", "render": "#756bb1", "io": "#31a354"}
WAIT_COLOUR = "#bdbdbd"

LABEL_WIDTH = 110   # the thread names' column
ROW_HEIGHT = 34     # a thread's row: a stage bar, then the tiles
STAGE_HEIGHT = 9
TOP = 46            # the title and the time axis above the rows
LEGEND_HEIGHT = 44


def rows_of(events):
    """The thread rows: tid -> name, in the trace's sort order."""
    names = {e["tid"]: e["args"]["name"] for e in events if e.get("ph") == "M" and e["name"] == "thread_name"}
    order = {e["tid"]: e["args"]["sort_index"] for e in events
             if e.get("ph") == "M" and e["name"] == "thread_sort_index"}
    return sorted(names.items(), key=lambda item: (order.get(item[0], item[0]), item[0]))


def tick_step(span_us, pixels):
    """A round time step (1, 2 or 5 times a power of ten, in microseconds) that gives ticks ~100 px apart."""
    target = span_us * 100.0 / max(pixels, 1)
    step = 1.0
    while True:
        for m in (1, 2, 5):
            if step * m >= target:
                return step * m
        step *= 10


def tooltip(e):
    args = ", ".join("%s=%s" % (k, v) for k, v in e.get("args", {}).items())
    text = "%s (%s): %.3f ms at %.3f ms" % (e["name"], e.get("cat", ""), e["dur"] / 1000, e["ts"] / 1000)
    return html.escape(text + (": " + args if args else ""))


def draw(doc, width, title):
    events = doc["traceEvents"]
    complete = [e for e in events if e.get("ph") == "X"]
    if not complete:
        raise ValueError("the trace holds no complete events")
    rows = rows_of(events)
    row_of = {tid: i for i, (tid, _) in enumerate(rows)}
    t0 = min(e["ts"] for e in complete)
    t1 = max(e["ts"] + e["dur"] for e in complete)
    span = max(t1 - t0, 1.0)
    plot = width - LABEL_WIDTH - 20
    height = TOP + len(rows) * ROW_HEIGHT + LEGEND_HEIGHT

    def x(ts):
        return LABEL_WIDTH + (ts - t0) * plot / span

    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
           'font-family="DejaVu Sans, Helvetica, Arial, sans-serif" font-size="11">' % (width, height, width, height),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="16" font-size="13" font-weight="bold">%s</text>' % (LABEL_WIDTH, html.escape(title))]
    # The time axis, in milliseconds.
    step = tick_step(span, plot)
    bottom = TOP + len(rows) * ROW_HEIGHT
    k = 0
    while k * step <= span:
        tx = x(t0 + k * step)
        out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#e0e0e0"/>' % (tx, TOP - 4, tx, bottom))
        out.append('<text x="%.1f" y="%d" text-anchor="middle" fill="#555">%g ms</text>'
                   % (tx, TOP - 8, k * step / 1000))
        k += 1
    for i, (tid, name) in enumerate(rows):
        y = TOP + i * ROW_HEIGHT
        if i % 2:
            out.append('<rect x="0" y="%d" width="%d" height="%d" fill="#f7f7f7"/>' % (y, width, ROW_HEIGHT))
        out.append('<text x="8" y="%d">%s</text>' % (y + ROW_HEIGHT - 10, html.escape(name)))
    labels = []  # drawn after every box, so that no box hides a label
    # Longest first, so that what is nested inside an event (the stages of a render) is drawn over it.
    for e in sorted(complete, key=lambda e: -e["dur"]):
        if e["tid"] not in row_of:
            continue
        y = TOP + row_of[e["tid"]] * ROW_HEIGHT
        left, w = x(e["ts"]), max(e["dur"] * plot / span, 0.6)
        tip = "<title>%s</title>" % tooltip(e)
        if e["name"] in ("tile", "pass"):
            colour = PASS_COLOURS[e["args"]["pass"] % len(PASS_COLOURS)]
            stroke = ' stroke="#ffffff" stroke-width="0.5"' if w > 3 else ""
            out.append('<rect x="%.2f" y="%d" width="%.2f" height="%d" fill="%s"%s>%s</rect>'
                       % (left, y + STAGE_HEIGHT + 3, w, ROW_HEIGHT - STAGE_HEIGHT - 6, colour, stroke, tip))
            label = "pass %d: %d spp" % (e["args"]["pass"], e["args"]["samples"]) if e["name"] == "pass" else ""
            if label and w > 6.5 * len(label) + 6:
                labels.append('<text x="%.1f" y="%d" fill="%s">%s</text>'
                              % (left + 3, y + ROW_HEIGHT - 10, "#fff" if e["args"]["pass"] >= 3 else "#000", label))
        elif e["name"] == "wait":
            out.append('<rect x="%.2f" y="%d" width="%.2f" height="%d" fill="%s">%s</rect>'
                       % (left, y + STAGE_HEIGHT + 3, w, ROW_HEIGHT - STAGE_HEIGHT - 6, WAIT_COLOUR, tip))
        elif e["name"] == "render":
            # The whole render: a thin line under the stage bar, so the tiles stay visible.
            out.append('<rect x="%.2f" y="%d" width="%.2f" height="2" fill="%s">%s</rect>'
                       % (left, y + STAGE_HEIGHT + 1, w, STAGE_COLOURS["render"], tip))
        else:
            colour = STAGE_COLOURS.get(e.get("cat"), "#636363")
            out.append('<rect x="%.2f" y="%d" width="%.2f" height="%d" fill="%s">%s</rect>'
                       % (left, y + 1, w, STAGE_HEIGHT, colour, tip))
            if w > 5.5 * len(e["name"]) + 4:
                labels.append('<text x="%.1f" y="%d" font-size="9" fill="#fff">%s</text>'
                              % (left + 2, y + STAGE_HEIGHT - 1, html.escape(e["name"])))
    out.extend(labels)
    # The legend: the passes actually present, then the stages.
    passes = sorted({e["args"]["pass"] for e in complete if e["name"] in ("tile", "pass")})
    ly = bottom + 16
    lx = LABEL_WIDTH
    out.append('<text x="8" y="%d" fill="#555">tile passes</text>' % (ly + 9))
    for p in passes:
        out.append('<rect x="%d" y="%d" width="12" height="12" fill="%s"/>' % (lx, ly, PASS_COLOURS[p % len(PASS_COLOURS)]))
        out.append('<text x="%d" y="%d">%d</text>' % (lx + 15, ly + 10, p))
        lx += 36
    lx += 20
    for label, colour in (("wait", WAIT_COLOUR), ("load", STAGE_COLOURS["load"]),
                          ("render (BVH build, setup)", STAGE_COLOURS["render"]), ("file writes", STAGE_COLOURS["io"])):
        out.append('<rect x="%d" y="%d" width="12" height="12" fill="%s"/>' % (lx, ly, colour))
        out.append('<text x="%d" y="%d">%s</text>' % (lx + 15, ly + 10, html.escape(label)))
        lx += 22 + 7 * len(label)
    out.append("</svg>")
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trace")
    ap.add_argument("svg")
    ap.add_argument("--width", type=int, default=1200)
    ap.add_argument("--title", default=None)
    a = ap.parse_args()
    try:
        with open(a.trace, encoding="utf-8") as f:
            doc = json.load(f)
        svg = draw(doc, a.width, a.title if a.title is not None else a.trace)
    except (OSError, ValueError, KeyError) as e:
        print("trace_plot.py: %s: %s" % (a.trace, e), file=sys.stderr)
        return 1
    with open(a.svg, "w", encoding="utf-8") as f:
        f.write(svg)
    return 0


if __name__ == "__main__":
    sys.exit(main())
