#!/usr/bin/env bash
# How lgh's renderer scales with cores (issue 50), in one prepared run for a lent many-core
# machine (the `device` tool: carry target/release/lgh) or any other:
#
#   tools/device/scaling.sh [--quick] [--bench]
#
# 1. the demo (`lgh demo`'s defaults: 128³, 640×360) at 1, 2, 4, 8 and 16 threads;
# 2. the Table-1 frame, the paper's Fig. 8 class (`lgh demo --resolution 267 --time 1.0
#    --width 1280 --height 720`), at 2 and 16 threads;
# 3. the Fig. 5 setting (the same with `--scatter-depth 4`) at 2 and 16 threads;
# 4. with --bench, `lgh bench table1` on the Table-1 frame at 2 and 16 threads (its JSON: the
#    cube maps' precompute per level, the render with and without them) — it always renders the
#    exact image too: about 8 minutes on 2 threads of a 16-core machine, so not by default.
#
# Thread counts above the machine's cores are skipped. For each run: wall seconds, CPU seconds,
# peak memory (GNU time, when /usr/bin/time exists) and the command's own phase lines (set up,
# cache, scattering, render); each image compared with the same setting's first image (`lgh
# compare`: the same bits at any thread count give 0). --quick runs small versions of each
# (64³ demo, 96³ frames at 320×180) to check the script: about a minute and a half on 2 cores
# (82 s of renders at 382e1f5). Everything goes to target/scaling/ (logs, images, summary.md);
# the summary is printed at the end.
set -euo pipefail
cd "$(dirname "$0")/../.."

quick=0
bench=0
for arg in "$@"; do
    case "$arg" in
        --quick) quick=1 ;;
        --bench) bench=1 ;;
        *) echo "scaling.sh: unknown argument $arg (--quick, --bench)" >&2; exit 2 ;;
    esac
done

LGH=${LGH_BIN:-target/release/lgh}
if [ ! -x "$LGH" ]; then
    echo "scaling.sh: no $LGH: build it (cargo build --release -p lgh-cli) or set LGH_BIN" >&2
    exit 2
fi
cores=$(nproc)
out=target/scaling
rm -rf "$out"
mkdir -p "$out"
summary="$out/summary.md"

if [ "$quick" = 1 ]; then
    demo=(--resolution 64)
    frame=(--resolution 96 --time 1.0 --width 320 --height 180)
else
    demo=()
    frame=(--resolution 267 --time 1.0 --width 1280 --height 720)
fi

{
    echo "# lgh scaling: $(date -u +%Y-%m-%dT%H:%MZ), $cores cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
    echo
    echo "| setting | threads | wall s | CPU s | peak MB | speed-up | image vs first |"
    echo "|---|---|---|---|---|---|---|"
} > "$summary"

# run NAME THREADS ARGS...: one timed run of `lgh --threads THREADS ARGS`; the first run of NAME
# is the baseline of its speed-up and its image.
run() {
    local name=$1 threads=$2
    shift 2
    if [ "$threads" -gt "$cores" ]; then
        echo "| $name | $threads | skipped: $cores cores | | | | |" >> "$summary"
        return
    fi
    local stem="$out/$name-t$threads"
    local image=()
    if [ "$1" = demo ]; then
        image=(--out "$stem.exr")
    fi
    echo "== $name, $threads threads: lgh $* ${image[*]}" >&2
    if [ -x /usr/bin/time ]; then
        /usr/bin/time -f "%e %U %S %M" -o "$stem.time" \
            "$LGH" --threads "$threads" "$@" "${image[@]}" > "$stem.log" 2>&1
    else
        local start end
        start=$(date +%s.%N)
        "$LGH" --threads "$threads" "$@" "${image[@]}" > "$stem.log" 2>&1
        end=$(date +%s.%N)
        awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f ? ? ?\n", b - a }' > "$stem.time"
    fi
    grep -E '^  (volume|hierarchy|cache|scatter|render|shadows)' "$stem.log" >&2 || true
    read -r wall user sys rss < "$stem.time"
    local cpu mb speedup="—" same="—"
    cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { if (u == "?") print "?"; else printf "%.1f", u + s }')
    mb=$(awk -v k="$rss" 'BEGIN { if (k == "?") print "?"; else printf "%.0f", k / 1024 }')
    local first="$out/$name.first"
    if [ -f "$first" ]; then
        read -r base_threads base_wall base_stem < "$first"
        speedup=$(awk -v a="$base_wall" -v b="$wall" -v t="$base_threads" \
            'BEGIN { printf "%.2f× over %d", a / b, t }')
        if [ -f "$stem.exr" ]; then
            same=$("$LGH" compare --diff "$stem-diff.png" "$stem.exr" "$base_stem.exr" 2>&1 \
                | sed -n 's/^relative RMSE \([^,]*\),.*/\1/p')
            same=${same:-compare failed}
        fi
    else
        echo "$threads $wall $stem" > "$first"
    fi
    echo "| $name | $threads | $wall | $cpu | $mb | $speedup | $same |" >> "$summary"
}

for t in 1 2 4 8 16; do
    run demo "$t" demo "${demo[@]}"
done
for t in 2 16; do
    run table1-frame "$t" demo "${frame[@]}"
done
for t in 2 16; do
    run fig5 "$t" demo "${frame[@]}" --scatter-depth 4
done
if [ "$bench" = 1 ]; then
    for t in 2 16; do
        run bench-table1 "$t" bench table1 "${frame[@]}" --compare raymarch
    done
fi

echo >&2
cat "$summary"
