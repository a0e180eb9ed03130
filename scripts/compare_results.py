#!/usr/bin/python3
"""Compares ictus results files bit for bit (doc/testing.md, "Bit-identical results").

    /usr/bin/python3 scripts/compare_results.py OLD.h5 NEW.h5 [--ignore-attr NAME ...]
    /usr/bin/python3 scripts/compare_results.py OLD_DIR NEW_DIR     # every *.h5 below, by path

What is compared, in both directions (an object or attribute on one side only is a
difference):
  * every group, dataset and link (soft and external links by their target);
  * every dataset's shape, HDF5 type (class, size, byte order, string padding) and its bytes:
    two floats are equal only with the same bit pattern, so NaN equals NaN of the same
    payload and -0.0 differs from 0.0;
  * every attribute of every object (the root, groups, datasets): type, shape and bytes;
  * the XDMF sidecar (same name, .xdmf), as text, when either side has one.
For numeric data that differs, it prints how many elements differ, the first one, and the
largest absolute and relative difference over the elements finite on both sides.

Not compared: the file's own bytes (HDF5 free-space layout, object header times), chunking
and compression: they are storage, not results.

Prints one verdict line per file pair ("IDENTICAL ..." or "DIFFERENT ...", then one indented
line per difference). Exit status 0 when every pair is identical, 1 otherwise (a missing or
unreadable file counts as a difference), 2 on a usage error.

Needs numpy and h5py: run it with /usr/bin/python3 (the python3 on PATH may lack them).
"""
import argparse
import os
import sys

import h5py
import numpy as np

# Attributes that legitimately differ between two runs of the same binary on the same deck,
# ignored wherever they appear (by name, with the reason). None: running every shipped deck and
# every verification case twice with the same binary, into different folders
# (bit_regression.py --old X --new X, 219 runs each), gave no differing attribute and no
# differing dataset. ictus writes no wall-clock time, date, host, build information or path
# into a completed run's results: the root attributes are program, version, format_version,
# title, analysis, ranks, deck, thickness, omega_max, dt and status (doc/results.md), and `deck`
# is the processed deck's record (its bulk data in /deck), without the deck's path. So the list is empty, and every
# attribute is compared.
#   `version` ("0.1.0", the CMake project version) is the same in any two builds of the same
#   version; a comparison across a version bump needs --ignore-attr version.
#   `status` of a run stopped by --wall-time names the step it stopped at (which depends on the
#   clock) and the deck and results paths: bit_regression.py compares such runs by exit status
#   only, not by ignoring status (which would hide a completed run turned into a failed one).
IGNORED_ATTRS = {
}

MAX_LISTED = 50  # differences printed per file pair (all are counted)


class Diff:
    """One difference: the HDF5 path, what differs, and detail."""

    def __init__(self, path, what, detail=""):
        self.path, self.what, self.detail = path, what, detail

    def __str__(self):
        return f"{self.path}: {self.what}" + (f" ({self.detail})" if self.detail else "")


def _raw(value):
    """The value as a contiguous byte string plus a description for comparison."""
    a = np.asarray(value)
    if a.dtype.kind == "O":  # variable-length strings or references: compare as Python objects
        return repr(a.tolist()).encode(), a
    return np.ascontiguousarray(a).tobytes(), a


def _show(x):
    """A number, with its bits in hex when it is a float (NaN payloads, signed zeros)."""
    if isinstance(x, np.floating):
        return f"{x!r} (0x{np.atleast_1d(x).view(np.uint8)[::-1].tobytes().hex()})"
    return repr(x)


def numeric_summary(a, b):
    """Counts differing elements (by bits) and the largest abs/rel difference where both
    are finite, for arrays of equal shape and numeric dtype."""
    if a.dtype.kind not in "iufcb" or b.dtype.kind not in "iufcb" or a.shape != b.shape:
        return ""
    scalar = a.ndim == 0
    a, b = np.atleast_1d(a), np.atleast_1d(b)
    ua = np.ascontiguousarray(a).view(np.uint8).reshape(a.shape + (-1,))
    ub = np.ascontiguousarray(b).view(np.uint8).reshape(b.shape + (-1,))
    if ua.shape != ub.shape:  # different item sizes: values only
        neq = np.asarray(a != b)
    else:
        neq = np.any(ua != ub, axis=-1)
    n = int(np.count_nonzero(neq))
    if scalar:
        parts = [f"{_show(a[0])} vs {_show(b[0])}"]
    else:
        first = tuple(int(i) for i in np.argwhere(neq)[0]) if n else ()
        parts = [f"{n} of {a.size} elements differ"]
        if n:
            parts.append(f"first at {list(first)}: {_show(a[first])} vs {_show(b[first])}")
    fa, fb = a.astype(np.complex128 if "c" in (a.dtype.kind + b.dtype.kind) else np.float64), \
        b.astype(np.complex128 if "c" in (a.dtype.kind + b.dtype.kind) else np.float64)
    both = np.isfinite(fa) & np.isfinite(fb) & np.asarray(neq)
    nonfinite = int(np.count_nonzero(np.asarray(neq) & ~(np.isfinite(fa) & np.isfinite(fb))))
    if np.any(both):
        d = np.abs(fa[both] - fb[both])
        scale = np.maximum(np.abs(fa[both]), np.abs(fb[both]))
        rel = np.where(scale > 0, d / np.where(scale > 0, scale, 1.0), 0.0)
        parts.append(f"max abs {d.max():.3e}, max rel {rel.max():.3e}")
    if nonfinite:
        parts.append(f"{nonfinite} differ in NaN/Inf")
    return ", ".join(parts)


def _type_text(t):
    try:
        return str(t.dtype)
    except Exception:  # noqa: BLE001 - a type h5py cannot map
        return f"HDF5 class {t.get_class()}"


def _compare_attrs(path, oa, ob, ignore, diffs, counts):
    na, nb = set(oa.attrs.keys()), set(ob.attrs.keys())
    for name in sorted(na | nb):
        if name in ignore:
            counts["ignored"] += 1
            continue
        counts["attributes"] += 1
        where = f"{path} @{name}"
        if name not in nb:
            diffs.append(Diff(where, "attribute only in the first file"))
            continue
        if name not in na:
            diffs.append(Diff(where, "attribute only in the second file"))
            continue
        ta, tb = oa.attrs.get_id(name).get_type(), ob.attrs.get_id(name).get_type()
        if ta != tb:
            diffs.append(Diff(where, "attribute type differs", f"{_type_text(ta)} vs "
                              f"{_type_text(tb)}"))
            continue
        va, vb = oa.attrs[name], ob.attrs[name]
        (ra, aa), (rb, ab) = _raw(va), _raw(vb)
        if aa.shape != ab.shape:
            diffs.append(Diff(where, "attribute shape differs", f"{aa.shape} vs {ab.shape}"))
        elif ra != rb:
            detail = numeric_summary(aa, ab)
            if not detail:
                sa, sb = repr(va), repr(vb)
                detail = f"{sa[:80]}{'...' if len(sa) > 80 else ''} vs " \
                         f"{sb[:80]}{'...' if len(sb) > 80 else ''}"
            diffs.append(Diff(where, "attribute value differs", detail))


def _compare_dataset(path, da, db, diffs, counts):
    counts["datasets"] += 1
    if da.shape != db.shape:
        diffs.append(Diff(path, "shape differs", f"{da.shape} vs {db.shape}"))
        return
    ta, tb = da.id.get_type(), db.id.get_type()
    if ta != tb:
        diffs.append(Diff(path, "type differs", f"{_type_text(ta)} vs {_type_text(tb)}"))
        return
    if da.shape is None:  # null dataspace: nothing to read
        return
    (ra, aa), (rb, ab) = _raw(da[()]), _raw(db[()])
    counts["bytes"] += len(ra)
    if ra != rb:
        diffs.append(Diff(path, "data differs", numeric_summary(aa, ab) or "non-numeric"))


def _walk(group, prefix=""):
    """{path: (kind, obj_or_target)} of every object below group, links not followed."""
    out = {}
    for name in group.keys():
        path = f"{prefix}/{name}"
        link = group.get(name, getlink=True)
        if isinstance(link, h5py.SoftLink):
            out[path] = ("soft link", link.path)
        elif isinstance(link, h5py.ExternalLink):
            out[path] = ("external link", f"{link.filename}:{link.path}")
        else:
            obj = group.get(name)
            if isinstance(obj, h5py.Group):
                out[path] = ("group", obj)
                out.update(_walk(obj, path))
            elif isinstance(obj, h5py.Dataset):
                out[path] = ("dataset", obj)
            else:
                out[path] = ("named type", obj)
    return out


def compare_files(file_a, file_b, ignore=()):
    """Returns (list of Diff, counts) for two results files (sidecars included)."""
    ignore = set(IGNORED_ATTRS) | set(ignore)
    diffs = []
    counts = {"groups": 1, "datasets": 0, "attributes": 0, "ignored": 0, "bytes": 0}
    handles, errors = [], []
    for f in (file_a, file_b):
        try:
            handles.append(h5py.File(f, "r"))
        except (OSError, ValueError) as e:
            errors.append(Diff(f, "cannot be opened as HDF5", str(e).splitlines()[0][:120]))
    if len(errors) == 2 and all(os.path.isfile(f) for f in (file_a, file_b)):
        # neither is HDF5 (e.g. a junk file a test wrote on purpose): the same bytes or not
        counts["not_hdf5"] = True
        if open(file_a, "rb").read() != open(file_b, "rb").read():
            diffs.append(Diff(file_b, "neither file is HDF5, and their bytes differ"))
    else:
        diffs += errors
    if len(handles) == 2:
        fa, fb = handles
        _compare_attrs("/", fa, fb, ignore, diffs, counts)
        wa, wb = _walk(fa), _walk(fb)
        for path in sorted(set(wa) | set(wb)):
            if path not in wb:
                diffs.append(Diff(path, f"{wa[path][0]} only in the first file"))
                continue
            if path not in wa:
                diffs.append(Diff(path, f"{wb[path][0]} only in the second file"))
                continue
            (ka, oa), (kb, ob) = wa[path], wb[path]
            if ka != kb:
                diffs.append(Diff(path, "kind differs", f"{ka} vs {kb}"))
            elif ka in ("soft link", "external link"):
                if oa != ob:
                    diffs.append(Diff(path, f"{ka} target differs", f"{oa} vs {ob}"))
            elif ka == "named type":
                if oa.id != ob.id:
                    diffs.append(Diff(path, "named type differs"))
            else:
                try:
                    if ka == "group":
                        counts["groups"] += 1
                    else:
                        _compare_dataset(path, oa, ob, diffs, counts)
                    _compare_attrs(path, oa, ob, ignore, diffs, counts)
                except Exception as e:  # noqa: BLE001 - never pass what could not be read
                    diffs.append(Diff(path, "could not be compared", repr(e)[:160]))
    for h in handles:
        h.close()
    xa, xb = (sidecar(f) for f in (file_a, file_b))
    if os.path.exists(xa) or os.path.exists(xb):
        ta = open(xa, "rb").read() if os.path.exists(xa) else None
        tb = open(xb, "rb").read() if os.path.exists(xb) else None
        if ta is None or tb is None:
            diffs.append(Diff(os.path.basename(xa if ta is not None else xb),
                              "XDMF sidecar only in the " + ("first" if tb is None else
                                                             "second") + " file's folder"))
        else:
            # the sidecar names its results file ("a.h5:/model/..."): the same text up to that
            ta = ta.replace(os.path.basename(file_a).encode() + b":/", b"<results>:/")
            tb = tb.replace(os.path.basename(file_b).encode() + b":/", b"<results>:/")
            if ta != tb:
                la = ta.decode(errors="replace").splitlines()
                lb = tb.decode(errors="replace").splitlines()
                line = next((i for i, (p, q) in enumerate(zip(la, lb)) if p != q),
                            min(len(la), len(lb)))
                diffs.append(Diff(os.path.basename(xa), "XDMF sidecar differs",
                                  f"first at line {line + 1}"))
    return diffs, counts


def sidecar(path):
    return path[:-3] + ".xdmf" if path.endswith(".h5") else path + ".xdmf"


def verdict(label, diffs, counts, out=sys.stdout, max_listed=MAX_LISTED):
    """Prints the one-line verdict and the differences; returns True when identical."""
    if counts.get("not_hdf5"):
        what = "neither file is HDF5: compared as bytes"
    else:
        what = (f"{counts['groups']} groups, {counts['datasets']} datasets "
                f"({counts['bytes']} bytes), {counts['attributes']} attributes"
                + (f", {counts['ignored']} ignored" if counts["ignored"] else ""))
    if not diffs:
        print(f"IDENTICAL {label}: {what}", file=out)
        return True
    print(f"DIFFERENT {label}: {len(diffs)} difference(s) in {what}", file=out)
    for d in diffs[:max_listed]:
        print(f"    {d}", file=out)
    if len(diffs) > max_listed:
        print(f"    ... and {len(diffs) - max_listed} more", file=out)
    return False


def results_files(folder):
    """Relative paths of the results files below folder (checkpoints *.chk.h5 included)."""
    found = []
    for root, _, files in os.walk(folder):
        for f in files:
            if f.endswith(".h5"):
                found.append(os.path.relpath(os.path.join(root, f), folder))
    return sorted(found)


def compare_trees(dir_a, dir_b, ignore=(), out=sys.stdout):
    """Compares every results file below two folders, matched by relative path."""
    ok = True
    names = sorted(set(results_files(dir_a)) | set(results_files(dir_b)))
    if not names:
        print(f"DIFFERENT {dir_a} vs {dir_b}: no results file in either folder", file=out)
        return False
    for rel in names:
        a, b = os.path.join(dir_a, rel), os.path.join(dir_b, rel)
        if not os.path.exists(a) or not os.path.exists(b):
            print(f"DIFFERENT {rel}: only in {dir_a if os.path.exists(a) else dir_b}", file=out)
            ok = False
            continue
        ok &= verdict(rel, *compare_files(a, b, ignore), out=out)
    return ok


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="Ignored by default: " + "; ".join(
                                     f"{k} ({v})" for k, v in IGNORED_ATTRS.items()))
    ap.add_argument("first", help="results file (or folder of results files)")
    ap.add_argument("second", help="results file (or folder) to compare with")
    ap.add_argument("--ignore-attr", action="append", default=[], metavar="NAME",
                    help="also ignore attributes of this name (repeatable)")
    ap.add_argument("--max-listed", type=int, default=MAX_LISTED,
                    help=f"differences printed per file pair (default {MAX_LISTED})")
    a = ap.parse_args(argv)
    if os.path.isdir(a.first) and os.path.isdir(a.second):
        return 0 if compare_trees(a.first, a.second, a.ignore_attr) else 1
    if os.path.isdir(a.first) or os.path.isdir(a.second):
        ap.error("give two files or two folders")
    diffs, counts = compare_files(a.first, a.second, a.ignore_attr)
    ok = verdict(f"{a.first} vs {a.second}", diffs, counts, max_listed=a.max_listed)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
