#!/usr/bin/env python3
"""Runs the test binaries that `cargo test --no-run --message-format=json`
built, two at a time, and exits non-zero if any of them failed.

`cargo test` runs its binaries one after another, and a binary whose last
test runs alone leaves the second core idle; the longest ones (a drape, the
stability suite, the GPU parity runs on llvmpipe) are mostly that. Running
two binaries at once keeps both cores busy. The slowest binaries start
first, so the run does not end on one long binary alone. Output streams
as it comes, each line prefixed with its binary's name.

Usage: run_tests.py BUILD_JSON [JOBS]
"""

import json
import os
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor, as_completed

# Started first, in this order: the binaries that take minutes.
SLOW_FIRST = [
    "relax_patterns",
    "drape_cli",
    "gpu_relax_parity",
    "stability_quick",
    "knit_gauge",
    "relax_converged",
    "export_meshio",
    "contact_tight_patterns",
]


def test_binaries(build_json):
    """(name, path) of every test executable in cargo's JSON messages."""
    out = []
    with open(build_json) as f:
        for line in f:
            try:
                msg = json.loads(line)
            except json.JSONDecodeError:
                continue
            if msg.get("reason") != "compiler-artifact" or not msg.get("executable"):
                continue
            if not msg["profile"]["test"]:
                continue
            target = msg["target"]
            out.append((f"{'/'.join(target['kind'])} {target['name']}", msg["executable"]))
    return out


def rank(item):
    name = item[0].split(" ", 1)[1]
    return SLOW_FIRST.index(name) if name in SLOW_FIRST else len(SLOW_FIRST)


PRINT = threading.Lock()


def say(text):
    with PRINT:
        print(text, flush=True)


def run(item):
    name, path = item
    start = time.monotonic()
    say(f"==== {name}: started")
    proc = subprocess.Popen([path], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    for line in proc.stdout:
        say(f"[{name}] {line.rstrip()}")
    code = proc.wait()
    return name, code, time.monotonic() - start


def main():
    build_json = sys.argv[1]
    jobs = int(sys.argv[2]) if len(sys.argv) > 2 else 2
    binaries = sorted(test_binaries(build_json), key=rank)
    if not binaries:
        print("no test binaries found in", build_json)
        return 1
    failed = []
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = [pool.submit(run, b) for b in binaries]
        for fut in as_completed(futures):
            name, code, wall = fut.result()
            status = "ok" if code == 0 else f"FAILED (exit {code})"
            say(f"==== {name}: {status}, {wall:.1f} s")
            if code != 0:
                failed.append(name)
    print(f"{len(binaries)} test binaries, {len(failed)} failed")
    for name in failed:
        print("  failed:", name)
    return 1 if failed else 0


if __name__ == "__main__":
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    sys.exit(main())
