#!/usr/bin/env bash
# `pip install .` (pyproject.toml, meson-python) on a machine without a package index, as
# docs/python.md says: a venv of Debian's /usr/bin/python3 that sees Debian's numpy and
# python3-mesonpy builds and installs the module; the installed module has __version__ equal to
# the C library's and the command's, and passes tests/test_python_readers.py without PYTHONPATH
# (tests/test_python.py runs the same library through the build's module). An interpreter without
# numpy is told numpy is missing, both when the module is imported and when meson configures the
# build for it.
# Exit 77 (skipped) only when python3-venv or python3-mesonpy is not installed.
# usage: tests/test_pip_install.sh path/to/granule SOURCE_DIR
set -euo pipefail
G=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$2" && pwd)
PY=/usr/bin/python3
TMP=$(mktemp -d "${TMPDIR:-/tmp}/granule-test-pip-XXXXXX")
trap 'rm -rf "$TMP"' EXIT
for m in venv mesonpy ensurepip; do
    if ! "$PY" -c "import $m" 2>/dev/null; then
        echo "skipped: $PY cannot import $m (apt-get install python3-venv python3-mesonpy)"
        exit 77
    fi
done
# the module pip builds is a release build of its own: the sanitizer pass (GRANULE_TEST_QUICK=1,
# scripts/test.sh) would only repeat the release pass's minute
if [[ ${GRANULE_TEST_QUICK:-0} == 1 ]]; then
    echo "skipped: GRANULE_TEST_QUICK=1 (the release pass runs it)"
    exit 77
fi
fail() { echo "FAIL $*"; exit 1; }

# 1. the documented install: no index, no build isolation, no cached wheel
"$PY" -m venv --system-site-packages "$TMP/V"
if ! "$TMP/V/bin/pip" install --no-build-isolation --no-index --no-cache-dir --disable-pip-version-check \
        "$SRC" >"$TMP/pip.log" 2>&1; then
    tail -30 "$TMP/pip.log"
    fail "pip install --no-build-isolation . into a venv of $PY"
fi
echo "ok pip install --no-build-isolation --no-index . into a venv of $PY"

# 2. the installed module, from a folder that has no granule package in it
cd "$TMP"
want=$("$G" --version | awk '{print $2}')
OMP_NUM_THREADS=1 "$TMP/V/bin/python" - "$want" "$TMP/V" <<'EOF'
import importlib.metadata, os, sys
import granule
want, venv = sys.argv[1], sys.argv[2]
assert os.path.realpath(granule.__file__).startswith(os.path.realpath(venv)), granule.__file__
assert granule.__version__ == granule.version == want, (granule.__version__, granule.version, want)
assert importlib.metadata.version("granule") == want, importlib.metadata.version("granule")
print("ok the installed granule %s (from %s) has __version__ = the command's and the package's" % (want, os.path.dirname(granule.__file__)))
EOF
# the installed module against the readers' test (every folder kind and trajectory format); the
# simulation API's own test (python) runs the same C library through the build's module
for t in test_python_readers; do
    set +e
    OMP_NUM_THREADS=1 "$TMP/V/bin/python" "$SRC/tests/$t.py" "$G" "$SRC" >"$TMP/$t.log" 2>&1
    rc=$?
    set -e
    [[ $rc -eq 0 || ($rc -eq 77 && $t == test_python_readers) ]] \
        || { grep FAIL "$TMP/$t.log" || tail "$TMP/$t.log"; fail "tests/$t.py with the installed module"; }
    echo "ok tests/$t.py with the installed module (no PYTHONPATH): $(tail -1 "$TMP/$t.log")"
done

# 3. an interpreter without numpy: a venv that does not see Debian's packages
"$PY" -m venv "$TMP/W"
site=$("$TMP/V/bin/python" -c "import granule, os; print(os.path.dirname(os.path.dirname(granule.__file__)))")
if "$TMP/W/bin/python" -c "import numpy" 2>/dev/null; then
    fail "the venv without system site packages imports numpy: the check below would prove nothing"
fi
set +e
msg=$(PYTHONPATH=$site "$TMP/W/bin/python" -c "import granule" 2>&1)
rc=$?
set -e
[[ $rc -ne 0 ]] || fail "import granule without numpy succeeded"
last=$(tail -1 <<<"$msg")
[[ $last == "ImportError: granule needs numpy, which $TMP/W/bin/python"*"cannot import"* ]] \
    || fail "import granule without numpy: want 'granule needs numpy, which INTERPRETER cannot import', got: $last"
echo "ok import granule without numpy says so: ${last:0:110}..."
# meson configuring the module for that interpreter (what pip's build would do) names numpy
printf "[binaries]\npython = '%s'\n" "$TMP/W/bin/python" >"$TMP/native.ini"
set +e
out=$(meson setup "$TMP/b" "$SRC" --native-file "$TMP/native.ini" -Dmodule_only=true -Dtests=disabled -Dmpi=disabled 2>&1)
rc=$?
set -e
[[ $rc -ne 0 ]] || fail "meson setup -Dmodule_only=true for an interpreter without numpy succeeded"
grep -q "python: $TMP/W/bin/python.* cannot import numpy" <<<"$out" \
    || { tail -5 <<<"$out"; fail "meson setup for an interpreter without numpy: no 'cannot import numpy' message"; }
echo "ok meson setup for an interpreter without numpy: $(grep -o 'python: .*cannot import numpy' <<<"$out" | head -1)"
