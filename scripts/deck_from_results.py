#!/usr/bin/python3
"""Writes the processed deck of an ictus results file back out as a complete deck.

    deck_from_results.py results.h5 [-o deck.inp]        (default: standard output)

The root attribute `deck` of the results file holds every card and parameter line of the
processed deck; in place of the bulk data lines (nodes, elements, control points, the ids of
sets) it has marker lines "** data: <group>, <n> lines", and <group> holds those values as
exact integers and doubles (doc/results.md, "The processed deck"). This script puts the data
lines back: a line is row k of each dataset named in the group's attribute `columns`, values
joined by ", "; a group with the attribute `per_line` has one 1-D dataset whose values fill
lines of `per_line` values. Doubles are written with Python's repr(), the shortest text that
reads back to the same double, so running the deck written here reproduces the run bit for
bit (verification/results_layout checks this).

A results file of layout version 1 written before the record had data groups has no marker
lines; its `deck` attribute is then written out unchanged. A marker whose group is missing,
or whose group does not hold the number of lines it announces, ends the script with a
one-line message and exit status 1, before anything is written.
"""
import argparse
import re
import sys

import h5py
import numpy as np

MARKER = re.compile(r"\*\* data: (/deck/\S+), (\d+) lines?")


def text_attr(obj, name):
    """The string attribute `name` of an HDF5 object (fixed-length strings come as bytes)."""
    v = obj.attrs[name]
    if isinstance(v, np.ndarray):
        v = v.item()
    return v.decode() if isinstance(v, bytes) else str(v)


def values_text(a):
    """Deck text of the values of a 1-D array: integers as integers, doubles by repr()."""
    if np.issubdtype(a.dtype, np.integer):
        return [str(int(v)) for v in a]
    return [repr(float(v)) for v in a]


def data_lines(g):
    """The data lines of group g, as described by its attributes `columns` and `per_line`."""
    columns = text_attr(g, "columns").split()
    if "per_line" in g.attrs:
        vals = values_text(np.asarray(g[columns[0]]).ravel())
        n = int(g.attrs["per_line"])
        return [", ".join(vals[k:k + n]) for k in range(0, len(vals), n)]
    cols = []
    for name in columns:
        a = np.asarray(g[name])
        a = a.reshape(a.shape[0], -1)
        cols.extend(values_text(a[:, j]) for j in range(a.shape[1]))
    return [", ".join(row) for row in zip(*cols)]


def deck_text(f, where):
    """The full processed deck of the open results file f (where: its name, for messages)."""
    out = []
    for lineno, line in enumerate(text_attr(f, "deck").split("\n"), 1):
        m = MARKER.fullmatch(line)
        if not m:
            out.append(line)
            continue
        path, n = m.group(1), int(m.group(2))
        if path not in f:
            sys.exit(f"deck_from_results.py: {where}: deck line {lineno} names {path}, "
                     "which the file does not hold")
        lines = data_lines(f[path])
        if len(lines) != n:
            sys.exit(f"deck_from_results.py: {where}: {path} holds {len(lines)} lines, "
                     f"deck line {lineno} announces {n}")
        out.extend(lines)
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="an ictus results file (.h5)")
    ap.add_argument("-o", "--output", help="the deck to write (default: standard output)")
    a = ap.parse_args()
    try:
        f = h5py.File(a.results, "r")
    except OSError as e:
        sys.exit(f"deck_from_results.py: {a.results}: cannot open it as an HDF5 file ({e})")
    with f:
        if "deck" not in f.attrs:
            sys.exit(f"deck_from_results.py: {a.results}: no root attribute 'deck' "
                     "(not an ictus results file)")
        text = deck_text(f, a.results)
    if a.output:
        with open(a.output, "w") as fh:
            fh.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
