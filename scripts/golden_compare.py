#!/usr/bin/env python3
"""Compares two directories written by scripts/golden.sh (before and after a refactor).

Numbers must agree to a relative tolerance (default 1e-12, of the larger magnitude, with the
column's or dataset's largest magnitude as the floor): every CSV cell, every number in
summary.json (keys naming wall-clock times are skipped), every HDF5 dataset. VTK XML files
must be byte-identical; PNG differences are listed but do not fail (drawing code may move).

    python3 scripts/golden_compare.py BEFORE AFTER [--tol 1e-12]
"""
import argparse
import csv
import json
import math
import os
import sys

TIMING_KEYS = ("wall", "elapsed", "ns_per_step")


def close(a, b, scale, tol):
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return abs(a - b) <= tol * max(abs(a), abs(b), scale, 1e-300)


def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return None


def compare_csv(pa, pb, tol, errs):
    ra = list(csv.reader(open(pa)))
    rb = list(csv.reader(open(pb)))
    if len(ra) != len(rb):
        errs.append(f"{pb}: {len(rb)} rows, before {len(ra)}")
        return
    if ra and ra[0] != rb[0]:
        errs.append(f"{pb}: header {rb[0]} != {ra[0]}")
        return
    header = ra[0] if ra else []
    ncol = max((len(r) for r in ra), default=0)
    scale = [0.0] * ncol
    for r in ra[1:]:
        for j, c in enumerate(r):
            v = num(c)
            if v is not None and math.isfinite(v):
                scale[j] = max(scale[j], abs(v))
    for i, (x, y) in enumerate(zip(ra, rb)):
        if len(x) != len(y):
            errs.append(f"{pb}:{i + 1}: {len(y)} cells, before {len(x)}")
            continue
        for j, (c, d) in enumerate(zip(x, y)):
            name = header[j] if j < len(header) else str(j)
            if any(k in name for k in TIMING_KEYS):
                continue
            u, v = num(c), num(d)
            if u is None or v is None:
                if c != d:
                    errs.append(f"{pb}:{i + 1}:{name}: {d!r} != {c!r}")
            elif not close(u, v, scale[j], tol):
                errs.append(f"{pb}:{i + 1}:{name}: {v!r} != {u!r}")


def compare_json(a, b, path, tol, errs):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if any(t in k for t in TIMING_KEYS):
                continue
            if k not in a or k not in b:
                errs.append(f"{path}.{k}: only in {'after' if k in b else 'before'}")
                continue
            compare_json(a[k], b[k], f"{path}.{k}", tol, errs)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            errs.append(f"{path}: length {len(b)} != {len(a)}")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            compare_json(x, y, f"{path}[{i}]", tol, errs)
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if not close(float(a), float(b), 0.0, tol):
            errs.append(f"{path}: {b!r} != {a!r}")
    elif a != b:
        errs.append(f"{path}: {b!r} != {a!r}")


def compare_h5(pa, pb, tol, errs):
    import h5py
    import numpy as np

    with h5py.File(pa, "r") as fa, h5py.File(pb, "r") as fb:
        na, nb = [], []
        fa.visit(na.append)
        fb.visit(nb.append)
        if sorted(na) != sorted(nb):
            errs.append(f"{pb}: objects differ: {sorted(set(na) ^ set(nb))}")
        for name in sorted(set(na) & set(nb)):
            oa, ob = fa[name], fb[name]
            for k in sorted(set(oa.attrs) | set(ob.attrs)):
                if k not in oa.attrs or k not in ob.attrs:
                    errs.append(f"{pb}:{name}@{k}: attribute only on one side")
                elif "file" in k and os.path.basename(str(oa.attrs[k])) == os.path.basename(str(ob.attrs[k])):
                    continue  # a path: the checkout may sit elsewhere
                elif k != "scene" and str(oa.attrs[k]) != str(ob.attrs[k]):
                    errs.append(f"{pb}:{name}@{k}: {ob.attrs[k]!r} != {oa.attrs[k]!r}")
            if not isinstance(oa, h5py.Dataset):
                continue
            x, y = oa[()], ob[()]
            if getattr(x, "shape", None) != getattr(y, "shape", None):
                errs.append(f"{pb}:{name}: shape {getattr(y, 'shape', None)} != {getattr(x, 'shape', None)}")
                continue
            if x.dtype.kind in "fiu":
                x = np.asarray(x, dtype=float)
                y = np.asarray(y, dtype=float)
                scale = float(np.nanmax(np.abs(x))) if x.size and not np.isnan(x).all() else 0.0
                d = np.abs(x - y)
                bound = tol * np.maximum(np.maximum(np.abs(x), np.abs(y)), max(scale, 1e-300))
                bad = ~((d <= bound) | (np.isnan(x) & np.isnan(y)))
                if bad.any():
                    errs.append(f"{pb}:{name}: {int(bad.sum())} values differ, largest |Δ| {np.nanmax(d):.3e} (scale {scale:.3e})")
            elif not np.array_equal(x, y):
                errs.append(f"{pb}:{name}: contents differ")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--tol", type=float, default=1e-12)
    a = ap.parse_args()
    errs, notes, counts = [], [], {}
    for root, _, files in os.walk(a.before, followlinks=True):
        for f in sorted(files):
            pa = os.path.join(root, f)
            rel = os.path.relpath(pa, a.before)
            pb = os.path.join(a.after, rel)
            ext = os.path.splitext(f)[1]
            if ext == ".log" or f.startswith(".rubsim-"):
                # Logs, and the output directory's own files (lock, manifest): not results.
                continue
            if not os.path.exists(pb):
                errs.append(f"{rel}: missing after")
                continue
            counts[ext] = counts.get(ext, 0) + 1
            if ext == ".csv":
                compare_csv(pa, pb, a.tol, errs)
            elif ext == ".json":
                compare_json(json.load(open(pa)), json.load(open(pb)), rel, a.tol, errs)
            elif ext in (".vtkhdf", ".h5", ".hdf5"):
                compare_h5(pa, pb, a.tol, errs)
            elif ext == ".png":
                if open(pa, "rb").read() != open(pb, "rb").read():
                    notes.append(f"{rel}: picture differs")
            elif open(pa, "rb").read() != open(pb, "rb").read():
                errs.append(f"{rel}: bytes differ")
    for root, _, files in os.walk(a.after, followlinks=True):
        for f in files:
            rel = os.path.relpath(os.path.join(root, f), a.after)
            if rel.endswith(".log") or f.startswith(".rubsim-"):
                continue
            if not os.path.exists(os.path.join(a.before, rel)):
                errs.append(f"{rel}: new file after")
    for n in notes:
        print("note:", n)
    for e in errs[:200]:
        print("DIFF:", e)
    print(f"compared {sum(counts.values())} files ({', '.join(f'{v} {k}' for k, v in sorted(counts.items()))}): "
          f"{len(errs)} differences, {len(notes)} pictures differ")
    sys.exit(1 if errs else 0)


if __name__ == "__main__":
    main()
