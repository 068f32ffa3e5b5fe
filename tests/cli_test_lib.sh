# Sourced by shell tests called as `test_X.sh GRANULE SOURCE_DIR`: G and SRC as absolute paths, a
# temporary folder $tmp removed at exit, and check CMD... counting passes and failures (finish
# prints the tally and sets the exit status).
set -uo pipefail
G=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$2" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
check() { if "$@"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAILED: $*" >&2; fi; }
finish() { echo "$pass passed, $fail failed"; [[ $fail -eq 0 ]]; }
