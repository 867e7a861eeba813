#!/usr/bin/env python3
"""The stated minimum Rust version is the true one for the lockfiles.

For the workspace (Cargo.toml, Cargo.lock) and the Python package (python/Cargo.toml,
python/Cargo.lock), reads `cargo metadata --locked` (which fails when a lockfile is out of
date with its manifest) and checks that the workspace's `rust-version` is at least every
locked package's `rust-version` and equals the largest of them: the README's "1.x or newer"
is then what `cargo build --locked` needs. No toolchain of that version is needed (rustup
cannot download one offline): the packages state their own minimums.

    tools/msrv_check.py            # exit 1 with the offending packages, 0 when true
"""
import json
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent


def version(text):
    return tuple(int(p) for p in text.split("."))


def metadata(manifest):
    out = subprocess.run(
        ["cargo", "metadata", "--locked", "--format-version", "1", "--manifest-path", str(manifest)],
        capture_output=True, text=True, cwd=ROOT)
    if out.returncode != 0:
        sys.exit(f"msrv_check: {manifest}: the lockfile is not in sync with the manifest:\n{out.stderr}")
    return json.loads(out.stdout)


def main():
    stated = None
    for line in (ROOT / "Cargo.toml").read_text().splitlines():
        if line.startswith("rust-version"):
            stated = line.split("=", 1)[1].strip().strip('"')
    if stated is None:
        sys.exit("msrv_check: Cargo.toml states no rust-version")
    needed = {}
    for manifest in [ROOT / "Cargo.toml", ROOT / "python" / "Cargo.toml"]:
        for p in metadata(manifest)["packages"]:
            if p.get("rust_version") and p.get("source"):
                needed[(p["name"], p["version"])] = p["rust_version"]
    top = max(needed.values(), key=version)
    above = sorted(f"{n} {v} (rust {r})" for (n, v), r in needed.items() if version(r) > version(stated))
    if above:
        sys.exit(f"msrv_check: rust-version {stated} is below what these locked packages need: "
                 + ", ".join(above))
    if version(top) < version(stated):
        print(f"msrv_check: note: rust-version {stated}; the locked packages need only {top}")
    print(f"msrv_check: rust-version {stated}: every locked package needs at most {top}")


if __name__ == "__main__":
    main()
