#!/usr/bin/python3
"""One result of a committed campaign over other settings of one of its keys (docs/results/investigations).

A campaign's result fixes its window (x_min of an spm fit, the free-path bound pl_max, ...). This
reruns the analysis of RESULT over the values given for KEY, with granule's own code and no new
runs: it writes a campaign file made of the campaign's own header (scene, sweep, [set]: so the scene
hashes match) and one copy of RESULT per value, restores the points archived with the result set
(RESULTS/points) and collects them (`granule reproduce FILE --collect`). The row whose setting is
the campaign's own is the campaign's number. Prints CSV: the setting, then the columns of
results.csv that describe the number.

usage: result_windows.py RESULTS RESULT KEY=V1,V2,...      (CSV on standard output)
       a value "default" leaves KEY out (the campaign's own where it does not set KEY);
       RESULTS: a committed result set (docs/results/NAME); granule is $GRANULE, else build/granule
       beside this script, else granule on PATH
"""
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
COLUMNS = ["group", "quantity", "unit", "value", "error", "error_fit_or_run", "error_seeds", "seeds", "fit_points", "chi2_red", "x_lo", "x_hi", "x_unit", "commit"]
DROPPED = ("thesis", "thesis_source", "note", "verdict", "restates")  # no comparison: only the numbers


def granule():
    for exe in (os.environ.get("GRANULE"), os.path.join(HERE, "..", "build", "granule"), shutil.which("granule")):
        if exe and os.access(exe, os.X_OK):
            return exe
    sys.exit("result_windows.py: granule not found (set GRANULE, or build it: scripts/setup.sh)")


def sections(text):
    """(the lines before the first [result ...] section, {id: the lines of each result's section})"""
    head, results, cur = [], {}, None
    for line in text.splitlines():
        m = re.match(r"\s*\[result\s+([^\]\s]+)\s*\]", line)
        if m:
            cur = results.setdefault(m.group(1), [])
        elif re.match(r"\s*\[", line):
            cur = None  # another section: a result's lines end here
            if not results:
                head.append(line)
        elif cur is not None:
            cur.append(line)
        elif not results:
            head.append(line)
    return "\n".join(head), results


def variant(lines, rid, key, value):
    """RESULT's section as result RID with KEY = VALUE ("default": KEY left out), without its comparison"""
    out = ["[result %s]" % rid]
    for line in lines:
        name = line.split("=", 1)[0].strip()
        if name in DROPPED or name == key:
            continue
        out.append(line)
    if value != "default":
        out.append("%s = %s" % (key, value))
    return "\n".join(out)


def main(argv):
    if len(argv) != 3 or "=" not in argv[2]:
        sys.exit(__doc__)
    results, rid, setting = argv
    key, values = setting.split("=", 1)
    values = [v.strip() for v in values.split(",") if v.strip()]
    meta = json.load(open(os.path.join(results, "results.json")))
    name, fidelity = meta["campaign"], meta["fidelity"]
    ini = os.path.join(HERE, "..", "docs", "campaigns", name + ".ini")
    head, found = sections(open(ini).read())
    if rid not in found:
        sys.exit("result_windows.py: %s has no [result %s] (results: %s)" % (ini, rid, ", ".join(found)))
    own = [l.split("=", 1)[1].split(";")[0].strip() for l in found[rid] if l.split("=", 1)[0].strip() == key]
    with tempfile.TemporaryDirectory() as tmp:
        ids = ["%s-%d" % (rid, i) for i in range(len(values))]
        text = head + "\n\n" + "\n\n".join(variant(found[rid], ids[i], key, v) for i, v in enumerate(values)) + "\n"
        path = os.path.join(tmp, name + ".ini")
        open(path, "w").write(text)
        res = os.path.join(tmp, "results")
        os.makedirs(res)
        shutil.copytree(os.path.join(results, "points"), os.path.join(res, "points"))
        run = subprocess.run([granule(), "reproduce", path, "--fidelity", fidelity, "--out", os.path.join(tmp, "out"), "--results", res, "--collect"],
                             capture_output=True, text=True)
        # exit 1 with "only K of M points are finished" is a campaign whose archive lacks some points: its numbers use the rest
        if run.returncode and not (run.returncode == 1 and "points are finished" in run.stderr):
            sys.exit("result_windows.py: granule reproduce --collect failed (exit %d):\n%s" % (run.returncode, run.stderr.strip()))
        rows = list(csv.DictReader(open(os.path.join(res, "results.csv"))))
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["campaign", "result", "key", "setting", "campaigns_own"] + COLUMNS)
    for i, v in enumerate(values):
        for r in rows:
            if r["result"] == ids[i]:
                is_own = "yes" if (own[0] if own else "default") == v else ""
                w.writerow([name, rid, key, v, is_own] + [r[c] for c in COLUMNS])


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except (OSError, KeyError, ValueError) as e:  # a folder that is not a result set with archived points
        sys.exit("result_windows.py: %s (give a committed result set: docs/results/NAME with results.json and points/)" % e)
