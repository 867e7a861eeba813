#!/usr/bin/env python3
"""Compares two recordings made by tools/golden.sh: OLD NEW [--rtol R] [--atol A].

Every run must have the same exit code and the same text apart from numbers (and the width of
the spaces around them); numbers agree when
|a − b| ≤ rtol·max(|a|, |b|) + atol, or when they differ by at most one unit in the last digit
printed (a report rounds to a few digits, so a change of rounding may flip that digit). Runs
that timed out in either recording are listed and skipped. Exit 0 when everything agrees."""
import argparse, os, re, sys

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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--atol", type=float, default=1e-9)
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
                why = compare_text(open(fo, errors="replace").read(),
                                   open(fn, errors="replace").read(), args.rtol, args.atol)
                if why:
                    bad.append(f"{d}/{case}{ext}: {why}")
    for s in skipped:
        print(f"skipped (timed out): {s}")
    for b in bad:
        print(f"DIFFERS {b}")
    print(f"{checked} runs compared (rtol {args.rtol:g}, atol {args.atol:g}), "
          f"{len(bad)} differ, {len(skipped)} skipped")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
