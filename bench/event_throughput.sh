#!/usr/bin/env bash
# Event-driven throughput (one core, CPU time): 1D ring N = 1000, L' = 1, eps 0.1, and 2D
# phi = 0.353 and 0.53 with N = 10000, eps_n = eps_t = 0.1, both free-flight methods and the three
# calendars (binary heap of the due entries, of all entries, calendar queue; docs/event-driven.md). Targets: >= 3e5 collisions/s in 2D, 1e7 events/s in 1D.
# Usage: bench/event_throughput.sh [BUILD_DIR] [--quick]   (--quick: tiny sizes, for the tests)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
quick=${2:-}
b="$build/bench/bench_event"
s1=docs/scenes/rfm-1d-event.ini
s2=docs/scenes/rfm-2d-event.ini
if [[ $quick == --quick ]]; then
    "$b" $s1 --set system.N=100 --set system.reduced_length=0.1 --warmup 0.01 --time 0.01 --repeats 1 --label "1D quick"
    GRANULE_EVENT_CALENDAR=full "$b" $s1 --set system.N=100 --set system.reduced_length=0.1 --warmup 0.01 --time 0.01 --repeats 1 --label "1D quick full"
    GRANULE_EVENT_CALENDAR=sparse "$b" $s1 --set system.N=100 --set system.reduced_length=0.1 --warmup 0.01 --time 0.01 --repeats 1 --label "1D quick sparse"
    "$b" $s2 --set system.N=300 --set integrator.free_flight=kicks --warmup 0.005 --time 0.005 --repeats 1 --label "2D quick"
    exit 0
fi
echo "# granule event-driven throughput, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores"
for ff in exact kicks; do
    for cal in bucket sparse full; do
        GRANULE_EVENT_CALENDAR=$cal "$b" $s1 --set integrator.free_flight=$ff --warmup 1 --time 1 --repeats 3 --label "1D L'=1 eps 0.1 $ff $cal"
    done
done
for phi in 0.353 0.53; do
    for ff in exact kicks; do
        for cal in bucket sparse full; do
            GRANULE_EVENT_CALENDAR=$cal "$b" $s2 --set system.packing_fraction=$phi --set integrator.free_flight=$ff \
                --warmup 0.2 --time 0.1 --repeats 3 \
                --label "2D phi $phi eps 0.1/0.1 $ff $cal"
        done
    done
done
