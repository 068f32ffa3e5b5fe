#!/usr/bin/env bash
# What specialising a combination of laws buys (src/core/kernels.c, GR_HOT_KERNELS): each scene
# runs through its chosen instance and through the generic one (bench_throughput --generic),
# alternating ROUNDS times in one session from the same steady state; prints the median
# particle-steps/s of each and their ratio. Run it on otherwise idle cores.
# Usage: bench/kernel_instances.sh BUILD_DIR [ROUNDS] [SCENE[:SET,SET...] ...]
set -euo pipefail
build=$1
rounds=${2:-5}
shift $(($# >= 2 ? 2 : $#))
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(docs/scenes/rfm-1d.ini docs/scenes/rfm-2d.ini
    "docs/scenes/rfm-2d.ini:model.normal=hertz,model.tangential=tangential_spring,model.rotation=true")
bench=$build/bench/bench_throughput
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for spec in "${scenes[@]}"; do
    scene=${spec%%:*}
    sets=()
    if [[ $spec == *:* ]]; then
        IFS=, read -ra kv <<< "${spec#*:}"
        for x in "${kv[@]}"; do sets+=(--set "$x"); done
    fi
    "$bench" "$scene" "${sets[@]}" --warmup-steps 20000 --steps 1 --repeats 1 --save-state "$tmp/state" >/dev/null
    for r in $(seq "$rounds"); do
        for mode in chosen generic; do
            flag=(); [ $mode = generic ] && flag=(--generic)
            "$bench" "$scene" "${sets[@]}" --state "$tmp/state" --steps 4000 --repeats 3 --csv "${flag[@]}" |
                awk -F, -v m=$mode '{print m, $6, $4}' >> "$tmp/rates"
        done
    done
    for m in chosen generic; do
        grep "^$m " "$tmp/rates" | sort -g -k2 | awk '{a[NR] = $2; k = $3} END {print a[int((NR + 1) / 2)], k}' > "$tmp/$m"
    done
    read -r c k < "$tmp/chosen"
    read -r g _ < "$tmp/generic"
    echo "$spec"
    echo "  kernel $k"
    awk -v c="$c" -v g="$g" 'BEGIN {printf "  chosen %.3e  generic %.3e particle-steps/s  generic/chosen %.3f\n", c, g, g / c}'
    rm -f "$tmp/rates"
done
