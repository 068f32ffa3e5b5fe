#!/usr/bin/env bash
# An unwritable output folder and a full disk (docs/architecture.md, "Disk errors"):
#   - unwritable folder (a file where a folder should be, a read-only file system, a folder the
#     user may not write): refused before the run starts, exit 1, a message naming the folder
#     and the system's reason, nothing written;
#   - a full disk, before the run and in the middle of it (a small tmpfs): the run stops at once
#     with "disk full while writing DIR/FILE: No space left on device", exit 1, and leaves no
#     temporary and no half-written file (every file present is complete).
# Root can write anywhere, so "may not write" runs the command as nobody (setpriv); the tmpfs
# cases need mount rights (root, or an unprivileged user namespace) and are skipped without them.
# Usage: test_disk_errors.sh GRANULE
set -uo pipefail
g="$(realpath "$1")"
tmp="$(mktemp -d)"
mounts=()
cleanup() {
    chmod -R u+w "$tmp" 2>/dev/null
    rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
ran=0 skipped=()

cat > "$tmp/s.ini" <<'INI'
[system]
dim = 1
N = 50
reduced_length = 0.1
[placement]
kind = uniform
[run]
warmup = 0
duration = 1
sample_every = 1e-3
[output]
snapshot_every = 1e-3
plots = false
INI
chmod 644 "$tmp/s.ini"

# expect_refusal NAME EXIT-CODE PATTERN COMMAND...: exit code, message, nothing written
expect() {
    local name="$1" code="$2" pattern="$3"
    shift 3
    "$@" >"$tmp/out.txt" 2>"$tmp/err.txt"
    local rc=$?
    [[ $rc == "$code" ]] || { cat "$tmp/err.txt" >&2; fail "$name: exit $rc, expected $code"; }
    grep -qE "$pattern" "$tmp/err.txt" || { cat "$tmp/err.txt" >&2; fail "$name: message does not match /$pattern/"; }
    echo "ok: $name: $(head -c 300 "$tmp/err.txt")"
    ran=$((ran + 1))
}

# 1. a regular file where the output folder (or a parent) should be
touch "$tmp/afile"
expect "file in place of the folder" 1 "output folder $tmp/afile exists but is not a folder" \
    "$g" run "$tmp/s.ini" --out "$tmp/afile"
expect "file in place of a parent" 1 "cannot create output folder $tmp/afile: Not a directory|$tmp/afile/out.*Not a directory" \
    "$g" run "$tmp/s.ini" --out "$tmp/afile/out"

# 2. a folder this user may not write (as nobody when root: root ignores permissions)
mkdir -p "$tmp/locked"
chmod 555 "$tmp/locked"
as_user=()
if [[ $(id -u) == 0 ]]; then
    if command -v setpriv >/dev/null && setpriv --reuid=65534 --regid=65534 --clear-groups "$g" --help >/dev/null 2>&1; then
        as_user=(setpriv --reuid=65534 --regid=65534 --clear-groups)
        chmod 755 "$tmp" # nobody must reach the scene and the folder
    else
        skipped+=("unwritable folder (root, and nobody cannot run $g)")
    fi
fi
if [[ $(id -u) != 0 || ${#as_user[@]} -gt 0 ]]; then
    expect "folder without write permission" 1 "output folder $tmp/locked( is not writable|/out).*Permission denied" \
        "${as_user[@]}" "$g" run "$tmp/s.ini" --out "$tmp/locked/out"
    expect "existing folder without write permission" 1 "output folder $tmp/locked is not writable: Permission denied" \
        "${as_user[@]}" "$g" run "$tmp/s.ini" --out "$tmp/locked"
    [[ -z "$(ls -A "$tmp/locked")" ]] || fail "files were written into the unwritable folder"
fi

# 3. tmpfs cases, in a private mount namespace (nothing leaks out of this test)
ns=()
if unshare -m true 2>/dev/null; then
    ns=(unshare -m)
elif unshare -rm true 2>/dev/null; then
    ns=(unshare -rm)
fi
in_tmpfs() { # in_tmpfs OPTIONS COMMAND...: run COMMAND with a tmpfs mounted on $tmp/mnt
    local opts="$1"
    shift
    mkdir -p "$tmp/mnt"
    "${ns[@]}" sh -c 'mount -t tmpfs -o "$1" granule-test "$0" || exit 99; shift; "$@"; rc=$?
                      rm -rf "$0.copy"; mkdir -p "$0.copy"; cp -a "$0/." "$0.copy/"; exit $rc' \
        "$tmp/mnt" "$opts" "$@"
}
if ((${#ns[@]})) && "${ns[@]}" sh -c "mount -t tmpfs -o size=64k granule-test '$tmp' 2>/dev/null"; then
    # 3a. read-only file system
    expect "read-only file system" 1 "output folder $tmp/mnt(/out)?.*Read-only file system" \
        in_tmpfs ro,size=64k "$g" run "$tmp/s.ini" --out "$tmp/mnt/out"
    # 3b. a disk that is full before the run starts
    expect "disk full before the run" 1 "disk full: output folder $tmp/mnt/out has no space left|disk full while writing $tmp/mnt/out" \
        in_tmpfs size=64k sh -c "dd if=/dev/zero of='$tmp/mnt/fill' bs=4k 2>/dev/null; \"\$0\" \"\$@\"" \
        "$g" run "$tmp/s.ini" --out "$tmp/mnt/out"
    # 3c. the disk fills up during the run: the streamed tables (checked every sample)...
    expect "disk full during the run (tables)" 1 "disk full while writing $tmp/mnt/out/(temperature|ledger).csv: No space left on device" \
        in_tmpfs size=64k "$g" run "$tmp/s.ini" --out "$tmp/mnt/out" --set output.snapshot_every=0
    ! find "$tmp/mnt.copy" -name '*.tmp*' | grep -q . || fail "disk full (tables): temporary files left behind"
    # ... and the snapshots
        expect "disk full during the run" 1 "disk full while writing $tmp/mnt/out/[^ ]+: No space left on device" \
        in_tmpfs size=256k "$g" run "$tmp/s.ini" --out "$tmp/mnt/out"
    # what the run left (copied out of the tmpfs before it went away): no temporaries, every
    # file complete: snapshots hold N + 2 lines, CSVs end with a newline, summary.json parses
    [[ -d "$tmp/mnt.copy" ]] || fail "disk full during the run: nothing copied out of the tmpfs"
    left="$(find "$tmp/mnt.copy" -type f | sed "s|$tmp/mnt.copy||")"
    echo "   left: $(echo "$left" | wc -l) files: $(echo "$left" | sed 's|.*/||' | sort | sed -n '1,4p;$p' | tr '\n' ' ')"
    ! grep -q '\.tmp' <<<"$left" || fail "temporary files left behind: $(grep '\.tmp' <<<"$left" | head -3)"
    while IFS= read -r f; do
        [[ -n "$f" ]] || continue
        p="$tmp/mnt.copy$f"
        case "$f" in
            *.xyz) [[ $(wc -l <"$p") == 52 ]] || fail "half-written snapshot $f ($(wc -l <"$p") lines)" ;;
            *.csv | *.ini) [[ -s "$p" && $(tail -c 1 "$p" | od -An -c | tr -d ' ') == '\n' ]] || fail "half-written $f" ;;
            *.json) python3 -c 'import json,sys; json.load(open(sys.argv[1]))' "$p" || fail "half-written $f" ;;
        esac
    done <<<"$left"
    if [[ -f "$tmp/mnt.copy/out/summary.json" ]]; then
        grep -q '"status": *"failed"' "$tmp/mnt.copy/out/summary.json" || fail "summary.json does not say failed"
    fi
    ran=$((ran + 1))
    # 3d. the disk fills up in the final writes of a run with no checkpoint (a 1D run with the
    # gaps observable: its files are written after the tables): status "failed", never
    # "completed" with files missing (issue 39), exit 1; once space is freed, --force starts it
    # again and completes
    cat >"$tmp/final.sh" <<'SH'
g="$1" tmp="$2" hit=0
mkdir -p "$tmp/fmnt"
for size in 160 200 240 280 320 360 400; do
    mount -t tmpfs -o size=${size}k granule-test "$tmp/fmnt" || exit 99
    out="$tmp/fmnt/out"
    "$g" run "$tmp/s.ini" --out "$out" --set analysis.observables=gaps --set run.duration=0.1 \
        --set output.snapshot_every=0 --quiet >/dev/null 2>"$tmp/ferr.txt"
    rc=$?
    status=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["status"])' "$out/summary.json" 2>/dev/null || echo none)
    echo "   ${size} KiB: exit $rc, status $status: $(head -c 120 "$tmp/ferr.txt")"
    case $rc/$status in
        0/completed) [[ -f "$out/gaps.csv" && -f "$out/gaps.meta.json" ]] || { echo "completed without gaps.csv"; exit 1; } ;;
        1/failed | 1/none)
            [[ ! -f "$out/checkpoint" ]] || { echo "exit 1 with a checkpoint"; exit 1; }
            grep -q 'disk full while writing' "$tmp/ferr.txt" || { echo "exit 1 without 'disk full'"; exit 1; }
            grep -q 'gaps' "$tmp/ferr.txt" && hit=1
            mount -o remount,size=8m "$tmp/fmnt"
            if [[ $status == failed ]]; then # --resume says how to start it again
                "$g" run --resume "$out" >/dev/null 2>"$tmp/ferr.txt"
                rc=$?
                [[ $rc == 2 ]] && grep -q -- "--out $out --force" "$tmp/ferr.txt" ||
                    { cat "$tmp/ferr.txt"; echo "--resume of a failed run: exit $rc, no --force named"; exit 1; }
            fi
            "$g" run "$tmp/s.ini" --out "$out" --set analysis.observables=gaps --set run.duration=0.1 \
                --set output.snapshot_every=0 --quiet --force >/dev/null 2>"$tmp/ferr.txt" ||
                { cat "$tmp/ferr.txt"; echo "--force after freeing space failed"; exit 1; }
            grep -qE '"status":[[:space:]]*"completed"' "$out/summary.json" && [[ -f "$out/gaps.csv" ]] ||
                { echo "--force after freeing space: not completed"; exit 1; } ;;
        *) cat "$tmp/ferr.txt"; echo "${size} KiB: exit $rc with status $status"; exit 1 ;;
    esac
    umount "$tmp/fmnt"
done
[[ $hit == 1 ]] || { echo "no size filled the disk while writing the gaps files"; exit 1; }
SH
    "${ns[@]}" bash "$tmp/final.sh" "$g" "$tmp" || fail "disk full in the final writes of a run without a checkpoint"
    echo "ok: disk full in the final writes without a checkpoint: status failed, exit 1, --force completes"
    ran=$((ran + 1))
else
    skipped+=("read-only and full-disk cases (cannot mount a tmpfs here: needs root or user namespaces)")
fi

for s in "${skipped[@]}"; do
    echo "skipped: $s"
done
echo "test_disk_errors: $ran checks passed"
