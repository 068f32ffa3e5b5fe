# Shared helpers of the bench scripts (sourced, not run). Expects $build (the build folder).
#
# bench_outputs QUICK NAME: sets $out (CSV and Markdown tables) and $img (plots). A full run
#   writes out/bench/ and docs/img/, the files docs/performance.md shows; --quick writes a
#   temporary folder that is removed on exit, so the test suite never touches the source tree.
# probe_kind SCENE KIND [--set k=v ...]: prints nothing and returns 0 when the integrator kind
#   runs in this build; otherwise prints "skipped: not built (...)" and returns 1.
# find_lmp: prints the path of the first lmp / lmp_serial / lmp_mpi on PATH built with the GRANULAR
#   package, or returns 1.
# bench_header: one comment line with the date, machine, compiler flags and commit.
# lmp_or_skip NAME INSTALL: sets $lmp to an lmp built with GRANULAR; INSTALL = 1 installs Debian's
#   lammps with apt-get first when none is found (as root). Without one it prints "NAME: skipped: ..."
#   and exits 0 (the bench scripts skip, they do not fail, on a machine without LAMMPS).
# build_and_quick USAGE ARGS...: the usual [BUILD_DIR] [--quick] arguments into $build (default
#   build) and $quick (true or false); any other option prints "usage: USAGE" and exits 2.
# require_built NAME PATH: exits 1 with "NAME: PATH not found: build the project (ninja -C $build)
#   first" unless PATH is an executable.

require_built() {
    [[ -x $2 ]] || { echo "$1: $2 not found: build the project (ninja -C $build) first" >&2; exit 1; }
}

build_and_quick() {
    local usage=$1 a
    shift
    build=build
    quick=false
    for a in "$@"; do
        case $a in
            --quick) quick=true ;;
            -*) echo "usage: $usage" >&2; exit 2 ;;
            *) build=$a ;;
        esac
    done
}

bench_outputs() {
    local quick=$1 name=$2
    if [[ $quick == true ]]; then
        out=$(mktemp -d "/tmp/granule-bench-$name.XXXXXX")
        img=$out
        # shellcheck disable=SC2064
        trap "rm -rf '$out'" EXIT
    else
        out=${GRANULE_BENCH_OUT:-out/bench}
        img=${GRANULE_BENCH_IMG:-docs/img}
        mkdir -p "$out" "$img"
    fi
}

probe_kind() {
    local scene=$1 kind=$2
    shift 2
    local msg
    if msg=$(timeout -k 5 20 "$build/bench/bench_throughput" "$scene" --set system.N=20 --set integrator.kind="$kind" "$@" \
        --warmup-steps 0 --steps 1 --repeats 1 2>&1 >/dev/null); then
        return 0
    fi
    if [[ -z $msg ]]; then
        echo "skipped: $kind did not finish a 20-particle, one-step probe within 20 s"
    elif grep -qi "not available\|not a normal model\|unknown\|choose one of" <<<"$msg"; then
        echo "skipped: not built ($kind: ${msg#bench_throughput: })"
    else
        echo "skipped: $kind failed on a 20-particle probe: ${msg#bench_throughput: }"
    fi
    return 1
}

bench_header() {
    local cpu
    cpu=$(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//')
    echo "# $(date -u +%Y-%m-%dT%H:%MZ), ${cpu:-unknown CPU}, $(nproc --all) cores, commit $(git rev-parse --short=12 HEAD 2>/dev/null || echo unknown)"
}

find_lmp() {
    local b
    for b in lmp lmp_serial lmp_mpi; do
        # (the help text is read whole first: grep -q closing the pipe early would fail under pipefail)
        if command -v "$b" >/dev/null 2>&1 && grep -qw GRANULAR <<<"$("$b" -h 2>/dev/null)"; then
            command -v "$b"
            return 0
        fi
    done
    return 1
}

lmp_or_skip() {
    local name=$1 install=$2
    lmp=$(find_lmp || true)
    if [[ -z $lmp && $install == 1 ]]; then
        if [[ $(id -u) == 0 ]] && command -v apt-get >/dev/null; then
            echo "$name: installing the Debian package lammps" >&2
            DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends lammps >/dev/null ||
                { DEBIAN_FRONTEND=noninteractive apt-get update -q >/dev/null &&
                  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends lammps >/dev/null; } || true
            lmp=$(find_lmp || true)
        fi
    fi
    if [[ -z $lmp ]]; then
        echo "$name: skipped: no lmp built with the GRANULAR package found (Debian package lammps; --install installs it as root)"
        exit 0
    fi
}
