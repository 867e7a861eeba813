#!/usr/bin/env bash
# Records the output of every linkage command on every bundled mechanism and every corpus dataset,
# so that a refactoring can show it changes no result:
#
#   tools/golden.sh BINARY OUTDIR          # record (BINARY: a built `linkage`)
#   GOLDEN_ONLY=acf tools/golden.sh …      # only the command files (`linkage run`)
#   tools/golden_compare.py OLD NEW        # compare two recordings up to rounding
#
# Each run leaves OUTDIR/<dataset>/<case>.{out,err,rc} (and .csv for runs that write one).
# Runs are bounded by GOLDEN_TIMEOUT seconds (default 20); a run that times out records rc=timeout.
set -uo pipefail
bin=$(realpath "$1")
out=$(realpath -m "$2")
here=$(cd "$(dirname "$0")/.." && pwd)
corpus="$here/../shared/corpus"
limit=${GOLDEN_TIMEOUT:-20}
jobs=${GOLDEN_JOBS:-2}
mkdir -p "$out"

# case name | arguments (MODEL replaced by the dataset, CSV by the case's CSV path)
cases='verify|verify MODEL --format json
verify_text|verify MODEL
explain|verify MODEL --explain --format json
ic|ic MODEL --format json
ic_text|ic MODEL
static|static MODEL --format json
static_text|static MODEL
quasi|static MODEL --end 1 --steps 4 --format csv
settle|static MODEL --settle --format json
linear|linear MODEL --format json
linear_static|linear MODEL --static-first --format json
linear_modes|linear MODEL --modes 4 --format json
simulate|simulate MODEL --end 0.05 --steps 5 --format json --out CSV
simulate_text|simulate MODEL --end 0.05 --steps 5
simulate_eq|simulate MODEL --end 0.05 --steps 5 --start-at-equilibrium --format json'

models=("$here"/mechanisms/*.adm "$here"/examples/*.adm)
if [ -d "$corpus" ]; then models+=("$corpus"/*.adm); fi

run_one() {
  local bin=$1 out=$2 limit=$3 model=$4 name=$5 args=$6
  local dir="$out/$(basename "$(dirname "$model")")__$(basename "$model" .adm)"
  mkdir -p "$dir"
  args=${args//MODEL/$model}
  args=${args//CSV/$dir/$name.csv}
  # shellcheck disable=SC2086
  (cd "$dir" && timeout "$limit" "$bin" $args >"$name.out" 2>"$name.err"; rc=$?
   if [ $rc -eq 124 ]; then echo timeout; else echo $rc; fi >"$name.rc")
  # paths differ between checkouts: keep only the file names
  sed -i "s#$(dirname "$model")/##g; s#$dir/##g" "$dir/$name.out" "$dir/$name.err"
}
export -f run_one

[ "${GOLDEN_ONLY:-}" = acf ] && models=()
for model in "${models[@]}"; do
  while IFS='|' read -r name args; do
    printf '%s\0%s\0%s\0%s\0%s\0%s\0' "$bin" "$out" "$limit" "$model" "$name" "$args"
  done <<<"$cases"
done | xargs -0 -n 6 -P "$jobs" bash -c 'run_one "$@"' _
# Command files: `linkage run` of every bundled and corpus .acf; the message file (CPU times and
# the date of the request file removed) as the case's text, its CSV as the case's CSV.
run_acf() {
  local bin=$1 out=$2 limit=$3 acf=$4
  local dir="$out/acf__$(basename "$acf" .acf)"
  mkdir -p "$dir/files"
  (cd "$dir/files" && timeout "$limit" "$bin" run "$acf" --out-dir "$dir/files" >"$dir/run.err" 2>&1; rc=$?
   if [ $rc -eq 124 ]; then echo timeout; else echo $rc; fi >"$dir/run.rc")
  local msg; msg=$(ls "$dir"/files/*.msg 2>/dev/null | head -1)
  if [ -n "$msg" ]; then
    sed -E 's/, [0-9.]+ s CPU//; s#'"$(dirname "$acf")"'/##g; s#'"$dir"'/files/##g; /^ linkage [0-9]/d' "$msg" >"$dir/run.out"
  fi
  local csv; csv=$(ls "$dir"/files/*.csv 2>/dev/null | head -1)
  if [ -n "$csv" ]; then cp "$csv" "$dir/run.csv"; fi
  sed -i "s#$(dirname "$acf")/##g; s#$dir/files/##g" "$dir/run.err"
  rm -rf "$dir/files"
}
export -f run_acf
acfs=("$here"/examples/*.acf)
if [ -d "$corpus" ]; then acfs+=("$corpus"/*.acf); fi
for acf in "${acfs[@]}"; do
  printf '%s\0%s\0%s\0%s\0' "$bin" "$out" "$limit" "$acf"
done | xargs -0 -n 4 -P "$jobs" bash -c 'run_acf "$@"' _

echo "recorded $(find "$out" -name '*.rc' | wc -l) runs in $out"
