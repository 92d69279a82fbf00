#!/usr/bin/env bash
# The main job, embedded on one machine: sets up, then builds avatar populations and PCA
# avatar bases for each preset, measures how well held-out avatars reconstruct, builds the
# clothing bases of a women's and a men's garment in two sizes, fits them to held-out
# customers with the accuracy table against the physics drape, and drapes a shared garment in
# three sizes onto a held-out customer.
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

# The clothing bases and the online fit: a women's and a men's garment, each imported on its
# population's basis, in two sizes; each fitted to three held-out customers of that population,
# and the accuracy table of every method against the physics drape on five held-out customers.
# Example drapes are cached by content key in $out/drapes, so the table reuses them.
declare -A garment_of=([women]=female_casualsuit01 [men]=male_casualsuit02)
for preset in women men; do
  g=${garment_of[$preset]}
  basis="$out/$preset/avatars.fbb"
  "$fitbase" garment import --mhclo "data/makehuman/clothes/$g/$g.mhclo" --basis "$basis" \
    --sizes M,XL --out "$out/$preset/$g.fbg"
  for size in M XL; do
    "$fitbase" clothing build --basis "$basis" --garment "$out/$preset/$g.fbg" --size "$size" \
      --method linear --cache "$out/drapes" --out "$out/$preset/$g-$size.fbc"
    for customer in 0 1 2; do
      "$fitbase" fit --clothing "$out/$preset/$g-$size.fbc" --basis "$basis" \
        --avatar "$out/$preset/holdout/avatar-0000$customer.obj" \
        --out "$out/$preset/fit-$g-$size-customer$customer.obj" | tee -a "$out/fits.txt"
    done
  done
  "$fitbase" eval --basis "$basis" --garment "$out/$preset/$g.fbg" --size M --holdout 5 --seed 2 \
    --cache "$out/drapes" --out "$out/$preset/accuracy" > /dev/null
done

# The offline fitter: one shared garment, imported onto the `all` basis's mean avatar and
# draped in three sizes onto a held-out customer, next to the geometric baseline.
garment=female_casualsuit01
"$fitbase" garment import --mhclo "data/makehuman/clothes/$garment/$garment.mhclo" \
  --basis "$out/all/avatars.fbb" --sizes S,M,XL --out "$out/$garment.fbg"
customer="$out/all/holdout/avatar-00001.obj"
cp "$customer" "$out/customer.obj"
for size in S M XL; do
  "$fitbase" drape --garment "$out/$garment.fbg" --size "$size" --avatar "$customer" \
    --out "$out/$garment-$size.obj" --report "$out/$garment-$size.json" | tee -a "$out/drapes.txt"
done
"$fitbase" drape --method geometric --garment "$out/$garment.fbg" --size M --avatar "$customer" \
  --out "$out/$garment-geometric.obj" --report "$out/$garment-geometric.json" | tee -a "$out/drapes.txt"

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
echo "== Drapes of $garment on $customer (see $out/drapes.txt)"
grep -E "^(drape|geometric)" "$out/drapes.txt" | sed -E 's/ \([^)]*\.obj\)//'
for preset in women men; do
  echo
  echo "== Fast fit vs physics drape, ${garment_of[$preset]} size M, 5 held-out $preset (see $out/$preset/accuracy/report.md)"
  sed -n '/^## All/,$p' "$out/$preset/accuracy/report.md" | tail -n +3
done
echo
echo "Outputs in $out/: populations (OBJ + params.jsonl), bases (*.fbb), all/customer-weights.json,"
echo "all/example-pc0-*.obj, $garment.fbg, customer.obj and its drapes $garment-{S,M,XL,geometric}.obj (+ .json reports);"
echo "per population: the garment (.fbg), its clothing bases (.fbc, sizes M and XL), fitted garments"
echo "fit-*-customer*.obj for held-out avatars 0-2 (beside them in */holdout/), accuracy/report.{md,json}"
