#!/usr/bin/env bash
# Records the output of every linkage command on every bundled mechanism and every corpus dataset,
# so that a refactoring can show it changes no result:
#
#   tools/golden.sh BINARY OUTDIR          # record (BINARY: a built `linkage`)
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

for model in "${models[@]}"; do
  while IFS='|' read -r name args; do
    printf '%s\0%s\0%s\0%s\0%s\0%s\0' "$bin" "$out" "$limit" "$model" "$name" "$args"
  done <<<"$cases"
done | xargs -0 -n 6 -P "$jobs" bash -c 'run_one "$@"' _
echo "recorded $(find "$out" -name '*.rc' | wc -l) runs in $out"
