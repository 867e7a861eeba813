#!/usr/bin/env python3
"""Compares two recordings made by tools/golden.sh: OLD NEW [--rtol R] [--atol A].

Every run must have the same exit code and the same text apart from numbers (and the width of
the spaces around them); numbers agree when
|a − b| ≤ rtol·max(|a|, |b|) + atol, or when they differ by at most one unit in the last digit
printed (a report rounds to a few digits, so a change of rounding may flip that digit). Runs
that timed out in either recording are listed and skipped. Exit 0 when everything agrees.

With --scaled, rounding is judged against the size of the quantity rather than of each number
(a change in the order of a factorisation moves a zero reaction from 1e-13 to -8e-11 next to
reactions of 1e4): numbers agree when |a − b| ≤ rtol·scale + atol, where scale is the largest
magnitude of the same JSON key in the file (of the same column in a CSV, on the same line of a
text report). Eigenvalue lists are compared without their zeros (`spectrum`), in a fixed
order; mode-shape phases relative to the mode's largest component (an eigenvector is defined
up to a complex factor), and not where the magnitude is rounding (≤ rtol × the largest)."""
import argparse, csv, io, json, os, re, sys

NUM = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def last_digit_unit(tok):
    mant, _, exp = tok.lower().partition("e")
    decimals = len(mant.split(".")[1]) if "." in mant else 0
    return 10.0 ** (-decimals + (int(exp) if exp else 0))


def agree(a, b, rtol, atol):
    if a == b:
        return True
    x, y = float(a), float(b)
    if abs(x - y) <= rtol * max(abs(x), abs(y)) + atol:
        return True
    return abs(x - y) <= 1.0001 * max(last_digit_unit(a), last_digit_unit(b))


def texts(line):
    """The text between the numbers of `line`, runs of spaces collapsed (a number printed
    wider or narrower shifts a right-aligned column)."""
    return [re.sub(r"[ \t]+", " ", t) for t in NUM.split(line)]


def compare_text(old, new, rtol, atol):
    """First difference between two texts (None when they agree)."""
    ot, nt = texts(old), texts(new)
    on, nn = NUM.findall(old), NUM.findall(new)
    if ot != nt or len(on) != len(nn):
        for k, (a, b) in enumerate(zip(old.splitlines(), new.splitlines())):
            if texts(a) != texts(b) or len(NUM.findall(a)) != len(NUM.findall(b)):
                return f"line {k + 1}: text differs:\n    - {a[:200]}\n    + {b[:200]}"
        return "text differs (line count)"
    for a, b in zip(on, nn):
        if not agree(a, b, rtol, atol):
            return f"number {a} became {b}"
    return None


def key_scales(doc, scales, key=None):
    """Largest |number| under each JSON key."""
    if isinstance(doc, dict):
        for k, v in doc.items():
            key_scales(v, scales, k)
    elif isinstance(doc, list):
        for v in doc:
            key_scales(v, scales, key)
    elif isinstance(doc, (int, float)) and not isinstance(doc, bool):
        scales[key] = max(scales.get(key, 0.0), abs(float(doc)))


# λ² of a zero mode is a stiffness made of rounding (~1e-8 relative to the model's), so a
# zero eigenvalue comes out as large as ~1e-4 × the spectrum.
ZERO_EIGENVALUE = 1e-4
# Eigenvalues below this (radians per time unit) are zeros whatever the spectrum.
ZERO_EIGENVALUE_FLOOR = 1e-6


def canonical_phases(mode):
    """A mode shape is defined up to a complex factor: phases are made relative to the phase
    of the largest component of the mode."""
    comps = [c for part in mode.get("shape") or []
             for c in part.get("translation", []) + part.get("rotation", [])]
    if not comps:
        return mode
    ref = max(comps, key=lambda c: c["magnitude"])["phase_deg"]
    for c in comps:
        c["phase_deg"] = (c["phase_deg"] - ref + 180.0) % 360.0 - 180.0
    return mode


def spectrum(doc):
    """Eigenvalue lists (`eigenvalues`, `modes`) without the zero eigenvalues (|λ| ≤
    ZERO_EIGENVALUE × the largest |λ|: a zero's rounding decides whether it is printed as 0 or
    as a ±ε pair; `zero_eigenvalues` counts them) and sorted by (imag, real), so that the order
    of a ± pair does not matter."""
    if isinstance(doc, dict):
        out = {}
        for k, v in doc.items():
            if k in ("eigenvalues", "modes") and isinstance(v, list) and all(
                    isinstance(e, dict) and "real" in e for e in v):
                big = max([abs(complex(e["real"], e.get("imag", 0.0))) for e in v] or [0.0])
                zero = max(ZERO_EIGENVALUE * big, ZERO_EIGENVALUE_FLOOR)
                keep = [canonical_phases(spectrum({a: b for a, b in e.items() if a != "number"}))
                        for e in v
                        if abs(complex(e["real"], e.get("imag", 0.0))) > zero]
                out[k] = sorted(keep, key=lambda e: (round(e.get("imag", 0.0), 6),
                                                     round(e["real"], 6)))
            else:
                out[k] = spectrum(v)
        return out
    if isinstance(doc, list):
        return [spectrum(v) for v in doc]
    return doc


def compare_json(old, new, rtol, atol):
    """First difference between two JSON documents judged with per-key scales (eigenvalue
    lists through `spectrum`)."""
    old, new = spectrum(old), spectrum(new)
    scales = {}
    key_scales(old, scales)
    key_scales(new, scales)

    def walk(a, b, path, key, parent_a=None, parent_b=None):
        if isinstance(a, dict) and isinstance(b, dict):
            if a.keys() != b.keys():
                return f"{path}: keys {sorted(a)} became {sorted(b)}"
            for k in a:
                w = walk(a[k], b[k], f"{path}.{k}", k, a, b)
                if w:
                    return w
            return None
        if isinstance(a, list) and isinstance(b, list):
            if len(a) != len(b):
                return f"{path}: {len(a)} items became {len(b)}"
            for i, (x, y) in enumerate(zip(a, b)):
                w = walk(x, y, f"{path}[{i}]", key)
                if w:
                    return w
            return None
        num = lambda v: isinstance(v, (int, float)) and not isinstance(v, bool)
        if num(a) and num(b):
            x, y = float(a), float(b)
            if key == "phase_deg":
                mags = [float(p.get("magnitude", 0.0)) for p in (parent_a, parent_b) if p]
                if max(mags, default=0.0) <= rtol * scales.get("magnitude", 0.0) + atol:
                    return None
                d = (x - y) % 360.0
                d = min(d, 360.0 - d)
                return None if d <= rtol * 360.0 + atol else f"{path}: {a} became {b}"
            if abs(x - y) <= rtol * scales.get(key, 0.0) + atol:
                return None
            return f"{path}: {a} became {b}"
        if a != b:
            return f"{path}: {a!r} became {b!r}"
        return None

    return walk(old, new, "$", None)


def column_name(field):
    """A CSV column's name without its unit suffix (`PART_2.x [mm]` -> `PART_2.x`)."""
    return re.sub(r" \[[^\]]*\]$", "", field.strip())


def compare_csv(old, new, rtol, atol):
    """First difference between two CSV documents judged with per-column scales; columns by
    name (a unit suffix in the header is not part of it)."""
    ro, rn = list(csv.reader(io.StringIO(old))), list(csv.reader(io.StringIO(new)))
    names = lambda rows: [column_name(f) for f in rows[0]] if rows else []
    if len(ro) != len(rn) or names(ro) != names(rn):
        return "rows or header differ"
    rows = ro[1:] + rn[1:]
    width = max((len(r) for r in rows), default=0)
    scale = [0.0] * width
    for r in rows:
        for c, v in enumerate(r):
            try:
                scale[c] = max(scale[c], abs(float(v)))
            except ValueError:
                pass
    for k, (a, b) in enumerate(zip(ro[1:], rn[1:])):
        for c, (x, y) in enumerate(zip(a, b)):
            if x == y:
                continue
            try:
                if abs(float(x) - float(y)) <= rtol * scale[c] + atol:
                    continue
            except ValueError:
                pass
            return f"row {k + 2}, column {ro[0][c] if c < len(ro[0]) else c}: {x} became {y}"
    return None


def compare_lines_scaled(old, new, rtol, atol):
    """Text compared line by line, numbers judged against the largest on their line."""
    ol, nl = old.splitlines(), new.splitlines()
    if len(ol) != len(nl):
        return "text differs (line count)"
    for k, (a, b) in enumerate(zip(ol, nl)):
        on, nn = NUM.findall(a), NUM.findall(b)
        if texts(a) != texts(b) or len(on) != len(nn):
            return f"line {k + 1}: text differs:\n    - {a[:200]}\n    + {b[:200]}"
        scale = max([abs(float(x)) for x in on + nn] or [0.0])
        for x, y in zip(on, nn):
            if x != y and not (agree(x, y, rtol, atol)
                               or abs(float(x) - float(y)) <= rtol * scale + atol):
                return f"line {k + 1}: number {x} became {y}"
    return None


def compare_scaled(old, new, ext, rtol, atol):
    if ext == ".csv":
        return compare_csv(old, new, rtol, atol)
    try:
        jo, jn = json.loads(old), json.loads(new)
    except ValueError:
        return compare_lines_scaled(old, new, rtol, atol)
    return compare_json(jo, jn, rtol, atol)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--atol", type=float, default=1e-9)
    ap.add_argument("--scaled", action="store_true",
                    help="judge rounding against the size of each quantity (see above)")
    args = ap.parse_args()
    bad, skipped, checked = [], [], 0
    for d in sorted(os.listdir(args.old)):
        for f in sorted(os.listdir(os.path.join(args.old, d))):
            if not f.endswith(".rc"):
                continue
            case = f[:-3]
            po, pn = os.path.join(args.old, d), os.path.join(args.new, d)
            if not os.path.exists(os.path.join(pn, f)):
                bad.append(f"{d}/{case}: missing in {args.new}")
                continue
            rc_o = open(os.path.join(po, f)).read().strip()
            rc_n = open(os.path.join(pn, f)).read().strip()
            if "timeout" in (rc_o, rc_n):
                skipped.append(f"{d}/{case} (rc {rc_o} → {rc_n})")
                continue
            checked += 1
            if rc_o != rc_n:
                bad.append(f"{d}/{case}: exit code {rc_o} became {rc_n}")
                continue
            for ext in (".out", ".err", ".csv"):
                fo, fn = os.path.join(po, case + ext), os.path.join(pn, case + ext)
                if not os.path.exists(fo) and not os.path.exists(fn):
                    continue
                if os.path.exists(fo) != os.path.exists(fn):
                    bad.append(f"{d}/{case}{ext}: written in only one recording")
                    continue
                a = open(fo, errors="replace").read()
                b = open(fn, errors="replace").read()
                if args.scaled:
                    why = compare_scaled(a, b, ext, args.rtol, args.atol)
                else:
                    why = compare_text(a, b, args.rtol, args.atol)
                if why:
                    bad.append(f"{d}/{case}{ext}: {why}")
    for s in skipped:
        print(f"skipped (timed out): {s}")
    for b in bad:
        print(f"DIFFERS {b}")
    mode = ", scaled" if args.scaled else ""
    print(f"{checked} runs compared (rtol {args.rtol:g}, atol {args.atol:g}{mode}), "
          f"{len(bad)} differ, {len(skipped)} skipped")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
