#!/usr/bin/env python3
"""Write the benchmark table of README.md and apps/bench/README.md from `invfem bench --json` files.

    python3 apps/bench/bench_table.py bench.json [more.json ...] [--readme PATH]... [--check]

Each file is what `invfem bench --json FILE` writes: a JSON list of objects with the fields
unit, ours, peer, measure, ratio, goal, runs, samples, note, status (and peer_source, quick).
With one file, `ours` is that run's figure (the median of its repetitions) and the range in
brackets is that of its repetitions (`samples`); with several files (several bench runs),
`ours` is the median of the runs' figures and the range is theirs. The ratio is computed from
that median and the peer's figure, in the direction the bench used (above 1: invfem is better).

The table replaces whatever lies between the lines `<!-- bench-table:begin -->` and
`<!-- bench-table:end -->` of each page (default: README.md and apps/bench/README.md of the
repository holding this script). --check writes nothing and exits 1 when a page's table would
change. Exit codes: 0 ok (or up to date), 1 --check found a stale table, 2 bad input.
Python 3 standard library only.
"""

import argparse
import json
import math
import os
import statistics
import sys

BEGIN = "<!-- bench-table:begin -->"
END = "<!-- bench-table:end -->"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT_PAGES = [os.path.join(ROOT, "README.md"), os.path.join(ROOT, "apps", "bench", "README.md")]


class InputError(Exception):
    pass


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def load_rows(path):
    """The rows of one `invfem bench --json` file, checked field by field."""
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except OSError as e:
        raise InputError(f"{path}: cannot read: {e.strerror}")
    except json.JSONDecodeError as e:
        raise InputError(f"{path}: not JSON: {e}")
    if not isinstance(data, list):
        raise InputError(f"{path}: expected a JSON list of rows (invfem bench --json), found {type(data).__name__}")
    rows = []
    for i, row in enumerate(data):
        where = f"{path}: row {i}"
        if not isinstance(row, dict):
            raise InputError(f"{where}: expected an object, found {type(row).__name__}")
        for key in ("unit", "measure", "status"):
            if not isinstance(row.get(key), str) or not row[key]:
                raise InputError(f"{where}: field \"{key}\" must be a non-empty string")
        where = f"{path}: row {i} ({row['unit']})"
        for key in ("ours", "peer", "ratio"):
            if row.get(key) is not None and not is_number(row[key]):
                raise InputError(f"{where}: field \"{key}\" must be a finite number or null, found {row[key]!r}")
        if row["status"] == "ok" and row.get("ours") is None:
            raise InputError(f"{where}: status ok without a figure in \"ours\"")
        if "goal" in row and not isinstance(row["goal"], str):
            raise InputError(f"{where}: field \"goal\" must be a string")
        runs = row.get("runs")
        if runs is not None and (not isinstance(runs, int) or isinstance(runs, bool) or runs < 0):
            raise InputError(f"{where}: field \"runs\" must be a count, found {runs!r}")
        samples = row.get("samples", [])
        if not isinstance(samples, list) or not all(is_number(s) for s in samples):
            raise InputError(f"{where}: field \"samples\" must be a list of finite numbers")
        if any(r["unit"] == row["unit"] for r in rows):
            raise InputError(f"{where}: unit \"{row['unit']}\" appears twice in one file")
        rows.append(row)
    if not rows:
        raise InputError(f"{path}: no rows")
    return rows


def fmt(v):
    """Three significant digits, trailing zeros kept: 18.0, 0.600, 340, 4.90."""
    text = f"{v:#.3g}"
    if "e" not in text:
        text = text.rstrip(".")
    return text


def scale_of(v):
    a = abs(v)
    if a >= 1e6:
        return 1e6, " M"
    if a >= 1e4:
        return 1e3, " k"
    return 1.0, ""


def cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def unit_row(unit, rows, several_files):
    """One table row from a unit's rows (one per file that has it)."""
    first = rows[0]
    measure = first["measure"]
    ok = [r for r in rows if r["status"] == "ok"]
    peer = next((r["peer"] for r in rows if r.get("peer") is not None), None)
    goal = next((r.get("goal") for r in rows if r.get("goal")), "") or ""
    if not ok:
        status = first["status"]
        return [f"`{unit}`", status, "-" if peer is None else fmt(peer), "-", cell(goal), "-"]
    figures = [r["ours"] for r in ok]
    ours = statistics.median(figures)
    summed = any(r.get("figure") == "sum" for r in ok)
    if several_files:
        spread = figures if len(figures) > 1 else []
    else:
        spread = [] if summed else ok[0].get("samples", [])
    factor, prefix = scale_of(ours)
    text = f"{fmt(ours / factor)}{prefix} {measure}"
    if len(spread) > 1:
        text += f" ({fmt(min(spread) / factor)}-{fmt(max(spread) / factor)})"
    if summed:
        text += " in all"
    if len(ok) < len(rows):
        text += f", {len(rows) - len(ok)} of {len(rows)} runs {'/'.join(sorted({r['status'] for r in rows if r['status'] != 'ok'}))}"
    peer_text = "-" if peer is None else f"{fmt(peer / factor)}{prefix}"
    ratio_text = "-"
    if peer is not None and peer > 0 and ours > 0:
        # The bench's direction: ours / peer for rates, peer / ours for times; read from a row's ratio.
        higher_is_better = None
        for r in ok:
            if r.get("ratio") is not None:
                rate, time = r["ours"] / peer, peer / r["ours"]
                higher_is_better = abs(r["ratio"] - rate) <= abs(r["ratio"] - time)
                break
        if higher_is_better is not None:
            ratio_text = fmt(ours / peer if higher_is_better else peer / ours)
    runs = sorted({r.get("runs") for r in ok if r.get("runs") is not None})
    runs_text = "-" if not runs else (str(runs[0]) if len(runs) == 1 else f"{runs[0]}-{runs[-1]}")
    if several_files and runs:
        runs_text = f"{len(ok)} x {runs_text}"
    if any(r.get("quick") for r in ok):
        # A reduced window (--quick) is no verdict on a goal that is set for the whole unit.
        text += " (quick window)"
        goal = f"{goal}: not judged on the quick window" if goal else goal
    return [f"`{unit}`", cell(text), peer_text, ratio_text, cell(goal), runs_text]


def shown_path(path):
    """A path as the legend shows it: relative to the repository when inside it."""
    full = os.path.abspath(path)
    rel = os.path.relpath(full, ROOT)
    return full if rel.startswith("..") else rel


def table(files, paths):
    """The Markdown block that goes between the markers."""
    order, by_unit = [], {}
    quick = set()
    for rows in files:
        for r in rows:
            if r["unit"] not in by_unit:
                order.append(r["unit"])
                by_unit[r["unit"]] = []
            by_unit[r["unit"]].append(r)
            if "quick" in r:
                quick.add(bool(r["quick"]))
    several = len(files) > 1
    kind = {frozenset([True]): "invfem bench --quick", frozenset([False]): "invfem bench"}.get(
        frozenset(quick), "invfem bench")
    sources = ", ".join(f"`{shown_path(p)}`" for p in paths)
    legend = (
        f"Written by `apps/bench/bench_table.py` from {sources} (`{kind} --json` rows). ours: the median "
        + ("of the files' figures, their range in brackets" if several
           else "of the repetitions, their range in brackets where the file keeps them")
        + "; ratio above 1: invfem is better; runs: repetitions"
        + (" (files x repetitions)." if several else ".")
    )
    lines = [legend, "", "| unit | ours | peer | ratio | goal | runs |", "|---|---|---|---|---|---|"]
    for unit in order:
        lines.append("| " + " | ".join(unit_row(unit, by_unit[unit], several)) + " |")
    return "\n".join(lines)


def replaced(text, block, path):
    begin, end = text.count(BEGIN), text.count(END)
    if begin != 1 or end != 1:
        raise InputError(f"{path}: expected one line {BEGIN} and one line {END}, found {begin} and {end}")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return head + BEGIN + "\n" + block + "\n" + END + tail


def main(argv):
    parser = argparse.ArgumentParser(
        description="Rewrite the benchmark table between the bench-table markers from invfem bench --json files.")
    parser.add_argument("json", nargs="+", help="files written by `invfem bench --json FILE` (several: several runs)")
    parser.add_argument("--readme", action="append", metavar="PATH",
                        help="a page holding the markers (repeatable; default: README.md and apps/bench/README.md)")
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 when a table would change")
    args = parser.parse_args(argv)
    try:
        block = table([load_rows(p) for p in args.json], args.json)
        stale = []
        for page in args.readme or DEFAULT_PAGES:
            try:
                with open(page, encoding="utf-8") as f:
                    old = f.read()
            except OSError as e:
                raise InputError(f"{page}: cannot read: {e.strerror}")
            new = replaced(old, block, page)
            if new == old:
                continue
            stale.append(page)
            if not args.check:
                tmp = page + ".tmp"
                with open(tmp, "w", encoding="utf-8") as f:
                    f.write(new)
                os.replace(tmp, page)
    except InputError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    for page in stale:
        print(f"{'stale' if args.check else 'updated'}: {os.path.relpath(page)}")
    return 1 if args.check and stale else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
