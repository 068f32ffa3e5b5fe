#!/usr/bin/env python3
"""Which tests the sanitizer pass can leave out: those whose every line of granule's code (src/,
models/, include/) other tests of that pass already run. scripts/test.sh skips the tests listed in
tests/sanitizer-skip.txt in its AddressSanitizer + UBSan pass; this script is the evidence.

    scripts/sanitizer_coverage.py [COVERAGE_BUILD] [--out DIR]

Configures COVERAGE_BUILD (default /tmp/granule-coverage) with -Db_coverage=true at the sanitizer
pass's -O1, runs each of the sanitizer pass's tests on its own in quick mode (GRANULE_TEST_QUICK=1,
as scripts/test.sh does), collects the lines it ran with gcov's JSON output, then covers the union
greedily: first every test with a line no other test runs, then the one adding most lines per
second. Prints the tests left over (each with its time) and the sum of their times: the skip list's
candidates. One core, about half an hour on the 2-core VM. Line coverage is the criterion; a test
left out still runs in the release pass."""
import collections
import json
import os
import subprocess
import sys
import tempfile
import time

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + "/"
OURS = ("src/", "models/", "include/")


def lines_run(build):
    """(file:line) of granule's code that the .gcda files under build record as run."""
    by_dir = collections.defaultdict(list)
    for root, _, files in os.walk(build):
        by_dir[root] += [os.path.join(root, f) for f in files if f.endswith(".gcda")]
    covered = set()
    with tempfile.TemporaryDirectory() as tmp:
        for d, gcdas in by_dir.items():
            if not gcdas:
                continue
            out = subprocess.run(["gcov", "-t", "-j", "-o", d] + gcdas, cwd=tmp,
                                 capture_output=True, text=True, stdin=subprocess.DEVNULL).stdout
            dec, i = json.JSONDecoder(), 0
            while i < len(out):
                while i < len(out) and out[i].isspace():
                    i += 1
                if i >= len(out):
                    break
                doc, i = dec.raw_decode(out, i)
                for f in doc.get("files", []):
                    path = os.path.normpath(os.path.join(build, f["file"]))
                    rel = path[len(SRC):] if path.startswith(SRC) else ""
                    if rel.startswith(OURS):
                        covered |= {"%s:%d" % (rel, l["line_number"]) for l in f["lines"] if l["count"] > 0}
    return covered


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    build = args[0] if args else "/tmp/granule-coverage"
    out = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else build + "-lines"
    os.makedirs(out, exist_ok=True)
    if not os.path.exists(os.path.join(build, "build.ninja")):
        subprocess.run(["meson", "setup", build, "--buildtype=debug", "-Doptimization=1",
                        "-Db_coverage=true"], cwd=SRC, check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["ninja", "-C", build], check=True, stdout=subprocess.DEVNULL)
    # the sanitizer pass's tests: the tests its build defines (tests/meson.build leaves some to
    # the release pass); in this unsanitised build, those are read off an ASan configuration
    asan = build + "-asan-list"
    if not os.path.exists(os.path.join(asan, "build.ninja")):
        subprocess.run(["meson", "setup", asan, "-Db_sanitize=address,undefined", "-Db_lundef=false"],
                       cwd=SRC, check=True, stdout=subprocess.DEVNULL)
    names = [n for n in subprocess.run(["meson", "test", "-C", asan, "--list", "--no-rebuild"],
                                       capture_output=True, text=True).stdout.split() if n]
    env = dict(os.environ, GRANULE_TEST_QUICK="1", OMP_WAIT_POLICY="passive")
    cov, secs = {}, {}
    for k, name in enumerate(names):
        done = os.path.join(out, name + ".json")
        if os.path.exists(done):  # resumable: a test measured before is not run again
            d = json.load(open(done))
            cov[name], secs[name] = set(d["lines"]), d["seconds"]
            continue
        for root, _, files in os.walk(build):
            for f in files:
                if f.endswith(".gcda"):
                    os.unlink(os.path.join(root, f))
        t0 = time.time()
        rc = subprocess.run(["meson", "test", "-C", build, "--no-rebuild", name], env=env,
                            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL).returncode
        secs[name] = time.time() - t0
        cov[name] = lines_run(build)
        json.dump({"seconds": secs[name], "rc": rc, "lines": sorted(cov[name])}, open(done, "w"))
        print("%3d/%d %-40s %6.1f s %6d lines%s" % (k + 1, len(names), name, secs[name], len(cov[name]),
                                                    "" if rc == 0 else " (failed: rc %d)" % rc), flush=True)
    union = set().union(*cov.values())
    count = collections.Counter(l for s in cov.values() for l in s)
    kept = [n for n in names if any(count[l] == 1 for l in cov[n])]
    got = set().union(*(cov[n] for n in kept)) if kept else set()
    while got != union:
        best = max((n for n in names if n not in kept), key=lambda n: len(cov[n] - got) / max(secs[n], 0.5))
        kept.append(best)
        got |= cov[best]
    left = sorted((n for n in names if n not in kept), key=lambda n: -secs[n])
    print("%d lines of src/, models/, include/ run by %d tests in %.0f s; %d tests cover them in %.0f s"
          % (len(union), len(names), sum(secs.values()), len(kept), sum(secs[n] for n in kept)))
    print("every line of these is run by the others (%.0f s):" % sum(secs[n] for n in left))
    for n in left:
        print("  %-40s %6.1f s" % (n, secs[n]))


if __name__ == "__main__":
    main()
