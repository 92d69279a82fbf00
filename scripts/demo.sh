#!/usr/bin/env bash
# The main job, embedded on one machine: sets up, then builds avatar populations and PCA
# avatar bases for each preset, and measures how well held-out avatars reconstruct.
# Everything it writes lands in demo-out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
fitbase=build/fitbase
out=demo-out
training=300
holdout=30
rm -rf "$out"
mkdir -p "$out"

for preset in women men all; do
  echo "== $preset: $training training avatars (seed 1), $holdout held-out avatars (seed 2)"
  "$fitbase" population --preset "$preset" --count "$training" --seed 1 --out "$out/$preset/population"
  "$fitbase" population --preset "$preset" --count "$holdout" --seed 2 --out "$out/$preset/holdout"
  "$fitbase" basis build --population "$out/$preset/population" --out "$out/$preset/avatars.fbb" |
    tee "$out/$preset/build.txt"
  "$fitbase" basis eval --basis "$out/$preset/avatars.fbb" --population "$out/$preset/holdout" |
    tee "$out/$preset/holdout.txt"
done

# What a later step consumes: one customer's weights, and the example avatars a garment is
# draped on (mean +- 1 sigma along the first component).
"$fitbase" basis project --basis "$out/all/avatars.fbb" --avatar "$out/all/holdout/avatar-00000.obj" \
  --json > "$out/all/customer-weights.json"
for sigma in -1 1; do
  "$fitbase" basis example --basis "$out/all/avatars.fbb" --component 0 --sigma "$sigma" \
    --out "$out/all/example-pc0-${sigma}sigma.obj" > /dev/null
done

echo
echo "== Summary (per-vertex reconstruction error of held-out avatars, default selection: training mean <= 1 mm)"
printf '%-7s %11s %10s %14s %14s %15s\n' preset components variance% train_mean_mm heldout_mean_mm heldout_worst_mm
for preset in women men all; do
  # The CLI prints these figures in fixed words; pick them out for the table.
  read -r components variance train < <(sed -E -n \
    's/.*: ([0-9]+) components from [0-9]+ avatars, ([0-9.]+)% of the variance, training error mean ([0-9.]+) mm.*/\1 \2 \3/p' \
    "$out/$preset/build.txt")
  read -r heldout worst < <(sed -E -n \
    's/.*per-vertex error mean ([0-9.]+) mm \(worst avatar ([0-9.]+) mm\).*/\1 \2/p' "$out/$preset/holdout.txt")
  printf '%-7s %11s %10s %14s %14s %15s\n' "$preset" "$components" "$variance" "$train" "$heldout" "$worst"
done
echo
echo "Outputs in $out/: populations (OBJ + params.jsonl), bases (*.fbb), all/customer-weights.json, all/example-pc0-*.obj"
