#!/usr/bin/env python3
"""trace_check.py — checks a trace written by `glint --trace` (used by tests/cli/trace.sh).

Usage: trace_check.py TRACE.json TILES PASSES THREADS [stopped]

The file must be JSON in the Chrome trace-event format: thread-name metadata for "main", "worker 1" ...
"worker THREADS-1" and "sample passes"; complete events with non-negative times; TILES x PASSES "tile" events
(each tile pass once, on a worker's row) unless the render was stopped, one per pass on the passes' row, and
one "scene load", "BVH build" (with its four steps inside it), "render" and "image write". Prints what is
wrong and exits 1, or exits 0.
"""
import json
import sys


def problems(path, tiles, passes, threads, stopped):
    with open(path, encoding="utf-8") as f:  # strict: the file must be UTF-8
        doc = json.load(f)
    if doc.get("displayTimeUnit") != "ms":
        yield "displayTimeUnit is not \"ms\""
    events = doc["traceEvents"]
    rows = {e["tid"]: e["args"]["name"] for e in events if e["ph"] == "M" and e["name"] == "thread_name"}
    wanted = ["main"] + ["worker %d" % i for i in range(1, threads)] + ["sample passes"]
    if sorted(rows.values()) != sorted(wanted):
        yield "thread names %s, expected %s" % (sorted(rows.values()), sorted(wanted))
    complete = [e for e in events if e["ph"] == "X"]
    for e in complete:
        missing = {"name", "cat", "ts", "dur", "pid", "tid", "args"} - set(e)
        if missing:
            yield "event %s lacks %s" % (e, sorted(missing))
        elif e["ts"] < 0 or e["dur"] < 0:
            yield "event %s has a negative time" % e
        elif e["tid"] not in rows:
            yield "event %s is on a row with no name" % e
    workers = {tid for tid, name in rows.items() if name == "main" or name.startswith("worker ")}
    tile_events = [e for e in complete if e["name"] == "tile"]
    keys = {(e["args"]["x"], e["args"]["y"], e["args"]["pass"]) for e in tile_events}
    if len(keys) != len(tile_events):
        yield "a tile pass is recorded twice"
    if not stopped and len(tile_events) != tiles * passes:
        yield "%d tile events, expected %d tiles x %d passes" % (len(tile_events), tiles, passes)
    if stopped and not any(e["args"].get("stopped") == 1 for e in tile_events):
        yield "no tile of the stopped render says it was stopped"
    if any(e["tid"] not in workers for e in tile_events):
        yield "a tile event is not on a worker's row"
    pass_events = [e for e in complete if e["name"] == "pass"]
    if not stopped and sorted(e["args"]["pass"] for e in pass_events) != list(range(passes)):
        yield "pass events %s, expected passes 0..%d" % ([e["args"]["pass"] for e in pass_events], passes - 1)
    if stopped and not any(e["args"]["complete"] == 0 for e in pass_events):
        yield "no pass of the stopped render is incomplete"
    if any(rows.get(e["tid"]) != "sample passes" for e in pass_events):
        yield "a pass event is not on the passes' row"
    for name in ("scene load", "JSON parse", "BVH build", "integrator setup", "render", "image write"):
        found = [e for e in complete if e["name"] == name]
        if len(found) != 1 or rows.get(found[0]["tid"]) != "main":
            yield "%d %r events on the main row, expected 1" % (len(found), name)
    # The build's steps, one each for the world's tree, inside the build and in their order.
    build = [e for e in complete if e["name"] == "BVH build"]
    order = ["BVH boxes", "BVH pre-split", "BVH binary tree", "BVH wide nodes", "BVH leaf packets"]
    steps = [e for e in complete if e["name"] in order]
    if [e["name"] for e in sorted(steps, key=lambda e: e["ts"])] != order:
        yield "BVH steps %s, expected boxes, pre-split, binary tree, wide nodes, leaf packets" % [e["name"] for e in steps]
    elif len(build) == 1 and any(e["tid"] != build[0]["tid"] or e["ts"] < build[0]["ts"] or
                                 e["ts"] + e["dur"] > build[0]["ts"] + build[0]["dur"] + 0.002 for e in steps):
        yield "a BVH step is not inside the BVH build on its row"


def main():
    path, tiles, passes, threads = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
    stopped = sys.argv[5:] == ["stopped"]
    try:
        found = list(problems(path, tiles, passes, threads, stopped))
    except (OSError, ValueError, KeyError, TypeError) as e:
        found = ["%s: %s" % (type(e).__name__, e)]
    for p in found:
        print("%s: %s" % (path, p), file=sys.stderr)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
