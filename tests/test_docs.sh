#!/usr/bin/env bash
# The generated documentation matches what the binary says: docs/scene-keys.md is exactly the
# output of `granule keys`, docs/cli.md of `granule help --markdown` (the option tables), and
# docs/models.md contains `granule models --markdown`.
set -euo pipefail
granule=$1
src=$2
pass=0
fail=0
check() { if "$@"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAILED: $*" >&2; fi; }
keys=$(mktemp)
models=$(mktemp)
cli=$(mktemp)
trap 'rm -f "$keys" "$models" "$cli"' EXIT
"$granule" keys >"$keys"
"$granule" models --markdown >"$models"
check cmp -s "$keys" "$src/docs/scene-keys.md"
"$granule" help --markdown >"$cli"
check cmp -s "$cli" "$src/docs/cli.md"
check python3 -c "import sys; a=open(sys.argv[1]).read(); b=open(sys.argv[2]).read(); sys.exit(0 if a.strip() in b else 1)" "$models" "$src/docs/models.md"
for f in "$src"/docs/scenes/*.ini; do
    check grep -q "^\[system\]" "$f"
done
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
