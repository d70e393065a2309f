#!/usr/bin/env bash
# Coverage-guided fuzzing of lgh's input parsers with AFL++ (cargo-afl, stable Rust).
#
#   fuzz/run.sh [-n EXECUTIONS] [TARGET...]      (default: 1000000 executions, every target)
#
# For each target (vdb uni ply obj exr): builds the seeds (fuzz/afl's `seeds` and
# make_vdb_seeds.py, from ../shared/data when it is there), adds the saved corpus
# (fuzz/corpus/TARGET), runs `cargo afl fuzz -E EXECUTIONS`, prints one line of figures
# (executions, edges found, crashes, hangs), copies any crash or hang into fuzz/corpus/TARGET
# as `crash-*` / `hang-*` for the replay test, and replaces the saved corpus by the smallest
# files of the minimised queue (`afl-cmin`), up to 60 kB a target. The work folder is
# fuzz/work (not committed).
set -euo pipefail
cd "$(dirname "$0")"
EXECS=1000000
if [[ "${1:-}" == "-n" ]]; then EXECS="$2"; shift 2; fi
TARGETS=("$@")
[[ ${#TARGETS[@]} -eq 0 ]] && TARGETS=(uni ply obj exr vdb)
SHARED="$(cd .. && pwd)/../shared/data"
WORK="$PWD/work"
BIN="$PWD/afl/target/release/lgh-fuzz-afl"

command -v cargo-afl > /dev/null || cargo install cargo-afl
# AFL++ itself, built once per machine by cargo-afl.
cargo afl config --build > /dev/null 2>&1 || true
(cd afl && cargo afl build --release --quiet)
AFL_BIN="$(dirname "$(ls -d "$HOME"/.local/share/afl.rs/rustc-*/afl.rs-*/afl/bin/afl-fuzz | tail -n 1)")"
rm -rf "$WORK/seeds" && mkdir -p "$WORK/seeds/vdb"
afl/target/release/seeds "$WORK/seeds" "$SHARED"
FRAME="$SHARED/volumes/blender_fire_pesichra/data/fluid_data_0056.vdb"
if [[ -f "$FRAME" ]] && /usr/bin/python3 -c "import pyopenvdb" 2> /dev/null; then
  /usr/bin/python3 make_vdb_seeds.py "$FRAME" "$WORK/seeds/vdb"
else
  echo "fuzz: no VDB seeds made (needs $FRAME and Debian's python3-openvdb); the saved corpus only"
fi

export AFL_SKIP_CPUFREQ=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_NO_UI=1
for t in "${TARGETS[@]}"; do
  in="$WORK/in/$t" out="$WORK/out/$t"
  rm -rf "$in" "$out" && mkdir -p "$in" "$WORK/out"
  cp "$WORK/seeds/$t/"* "$in/" 2> /dev/null || true
  cp corpus/"$t"/* "$in/" 2> /dev/null || true
  # -m: a giant allocation fails (and aborts: a crash) instead of exhausting the machine;
  # -t: an input taking over a second is a hang.
  if ! cargo afl fuzz -i "$in" -o "$out" -E "$EXECS" -m 4096 -t 1000 -- "$BIN" "$t" > "$WORK/$t.log" 2>&1; then
    tail -n 20 "$WORK/$t.log"
    exit 1
  fi
  stats="$out/default/fuzzer_stats"
  get() { awk -F' *: *' -v k="$1" '$1 == k { print $2 }' "$stats"; }
  echo "$t: $(get execs_done) executions in $(get run_time) s ($(get execs_per_sec)/s), edges $(get edges_found)/$(get total_edges), $(get corpus_count) inputs kept, crashes $(get saved_crashes), hangs $(get saved_hangs)"
  for kind in crashes hangs; do
    for f in "$out/default/$kind"/id*; do
      [[ -f "$f" ]] || continue
      cp "$f" "corpus/$t/${kind%es}-$(sha1sum "$f" | cut -c1-12)"
    done
  done
  rm -rf "$WORK/cmin/$t"
  # The shell afl-cmin: cargo-afl's Python one finds no tuples with a persistent-mode target.
  AFL_PATH="$AFL_BIN" "$AFL_BIN/afl-cmin.bash" -i "$out/default/queue" -o "$WORK/cmin/$t" \
    -m 4096 -t 1000 -- "$BIN" "$t" > "$WORK/$t.cmin.log" 2>&1
  find "corpus/$t" -maxdepth 1 -type f ! -name 'crash-*' ! -name 'hang-*' -delete 2> /dev/null || true
  mkdir -p "corpus/$t"
  # The smallest files of the minimised queue, up to 60 kB a target: what the repository keeps
  # (the whole queue stays in fuzz/work).
  total=0
  while read -r size f; do
    (( total + size > 60000 )) && break
    total=$(( total + size ))
    cp "$f" "corpus/$t/$(sha1sum "$f" | cut -c1-16)"
  done < <(find "$WORK/cmin/$t" -type f -printf '%s %p\n' | sort -n)
done
