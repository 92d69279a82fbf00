#!/usr/bin/env bash
# The main job, embedded on one machine: sets up, then builds avatar populations and PCA
# avatar bases for each preset and measures how well held-out avatars reconstruct; runs the
# whole stack (coordinator, two workers, fit service) to build the clothing bases of a women's
# and a men's garment in two sizes and serve a customer's calls over gRPC; and drapes a shared
# garment in three sizes onto a held-out customer.
# It ends with the shopper's try-on page served, its URL printed and a headless screenshot in
# demo-out/tryon.png; with --serve the page stays up until Ctrl-C.
# Everything it writes lands in demo-out/.
set -euo pipefail
cd "$(dirname "$0")/.."
keep_serving=false
case "${1:-}" in
  "") ;;
  --serve) keep_serving=true ;;
  *) echo "usage: scripts/demo.sh [--serve]" >&2; exit 2 ;;
esac
scripts/setup.sh
fitbase=build/fitbase
out=demo-out
training=300
holdout=50
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
# Bodies from measurements: every held-out avatar measured and fed back (README "An avatar
# from measurements").
for preset in women men; do
  "$fitbase" basis eval-measurements --basis "$out/$preset/avatars.fbb" \
    --population "$out/$preset/holdout" | tee "$out/$preset/measurements.txt"
done

# What a later step consumes: one customer's weights, and the example avatars a garment is
# draped on (mean +- 1 sigma along the first component).
"$fitbase" basis project --basis "$out/all/avatars.fbb" --avatar "$out/all/holdout/avatar-00000.obj" \
  --json > "$out/all/customer-weights.json"
for sigma in -1 1; do
  "$fitbase" basis example --basis "$out/all/avatars.fbb" --component 0 --sigma "$sigma" \
    --out "$out/all/example-pc0-${sigma}sigma.obj" > /dev/null
done

# The production stack, embedded: coordinator, two drape workers and the fit service in one
# process (`serve --role all`) over a RocksDB store in $out/store. The avatar bases and two
# garments (a women's and a men's, sizes M and XL) go in through the catalogue RPCs, their
# clothing bases are built by the workers through the coordinator, and a shop's customer calls
# come last: project an avatar, fit a garment (Draco), fit an outfit (every size).
keys="$out/api-keys"
admin_key=$("$fitbase" keys add --file "$keys" --tenant demo --role admin 2>/dev/null)
shop_key=$("$fitbase" keys add --file "$keys" --tenant demo --role customer 2>/dev/null)
mkfifo "$out/serve.fifo"
"$fitbase" serve --role all --db "$out/store" --listen 127.0.0.1:0 --fit-listen 127.0.0.1:0 \
  --http-listen 127.0.0.1:0 --api-keys "$keys" --workers 2 > "$out/serve.fifo" \
  2> "$out/serve.log" &
serve_pid=$!
trap 'kill "$serve_pid" 2>/dev/null || true' EXIT
exec 3< "$out/serve.fifo"
read -r _ coordinator <&3
read -r _ fit <&3
read -r _ page <&3
echo "== stack: coordinator $coordinator, fit service $fit, page $page (logs: $out/serve.log)"

declare -A garment_of=([women]=female_casualsuit01 [men]=male_casualsuit02)
# The shop serves the kernel model, trained here on far fewer sampled drapes per size than the
# 800 recommended for a catalogue, on 30-component bases (README, "Recommended for a
# catalogue"), to keep the demo short.
demo_samples=24
# For size advice: a jersey T-shirt over leggings, and a woven shirt over trousers.
declare -A type_of=([women]=knit [men]=shirt)
declare -A garment_id build_id
export FITBASE_API_KEY=$admin_key
for preset in women men; do
  g=${garment_of[$preset]}
  "$fitbase" basis publish --coordinator "$coordinator" --population "$preset" \
    --basis "$out/$preset/avatars.fbb"
  basis_id=$("$fitbase" basis info "$out/$preset/avatars.fbb" | awk '/^id/{print $2}')
  garment_id[$preset]=$("$fitbase" garment upload --coordinator "$coordinator" \
    --mhclo "data/makehuman/clothes/$g/$g.mhclo" --basis-id "$basis_id" --sizes M,XL \
    --type "${type_of[$preset]}" |
    tee -a "$out/catalogue.txt" | awk '/^garment/{print $2}')
  build_id[$preset]=$("$fitbase" build submit --coordinator "$coordinator" \
    --garment "${garment_id[$preset]}" --sizes M,XL --methods linear,kernel \
    --samples "$demo_samples" | awk '{print $1; exit}')
done
for preset in women men; do
  "$fitbase" build watch --coordinator "$coordinator" "${build_id[$preset]}" | tee -a "$out/builds.txt"
done

export FITBASE_API_KEY=$shop_key
mkdir -p "$out/customer"
for preset in women men; do
  g=${garment_of[$preset]}
  c="$out/customer/$preset"
  cp "$out/$preset/holdout/avatar-00000.obj" "$c-avatar.obj"
  {
    echo "== $preset customer (held-out avatar 0): $g"
    "$fitbase" customer project --server "$fit" --avatar "$c-avatar.obj" --population "$preset" \
      --draco --out "$c-weights.json"
    for size in M XL; do
      "$fitbase" customer fit --server "$fit" --weights "$c-weights.json" \
        --garment "${garment_id[$preset]}" --size "$size" --out "$c-$g-$size.obj"
    done
    "$fitbase" customer outfit --server "$fit" --weights "$c-weights.json" \
      --garments "${garment_id[$preset]}" --out "$c-outfit"
    # The second customer has no scan: a tailor's five measurements of held-out avatar 1,
    # typed into the shop (cm, kg), make the body its garments are fitted to.
    m="$out/customer/$preset-2"
    echo "== $preset customer 2 (typed measurements of held-out avatar 1): $g"
    "$fitbase" avatar measure --json "$out/$preset/holdout/avatar-00001.obj" |
      grep -oE '"(stature_cm|weight_kg|bust_girth_cm|waist_girth_cm|hip_girth_cm)": [0-9.]+' |
      paste -sd, - | sed 's/^/{/; s/$/}/' > "$m-measurements.json"
    cat "$m-measurements.json"
    "$fitbase" customer from-measurements --server "$fit" --population "$preset" \
      --measurements "$m-measurements.json" --out "$m-avatar.obj" --weights "$m-weights.json"
    for size in M XL; do
      "$fitbase" customer fit --server "$fit" --weights "$m-weights.json" \
        --garment "${garment_id[$preset]}" --size "$size" --out "$m-$g-$size.obj"
    done
  } | tee -a "$out/customer/summary.txt"
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
echo "== Bodies from measurements: $holdout held-out avatars measured and fed back (see $out/*/measurements.txt)"
for preset in women men; do
  echo "$preset:"
  grep -E '^\|' "$out/$preset/measurements.txt"
done
echo
echo "== Drapes of $garment on $customer (see $out/drapes.txt)"
grep -E "^(drape|geometric)" "$out/drapes.txt" | sed -E 's/ \([^)]*\.obj\)//'
echo
echo "== Builds through the coordinator (see $out/builds.txt) and the customer's calls over gRPC"
grep -E "BUILD_|published" "$out/builds.txt"
cat "$out/customer/summary.txt"
echo
echo "Outputs in $out/: populations (OBJ + params.jsonl), bases (*.fbb), all/customer-weights.json,"
echo "all/example-pc0-*.obj, $garment.fbg, customer.obj and its drapes $garment-{S,M,XL,geometric}.obj (+ .json reports);"
echo "store/ (avatar bases, garments, drapes, clothing bases, builds), api-keys, serve.log;"
echo "customer/: per population the avatar, its weights, the fitted garments (M, XL), the outfit, summary.txt;"
echo "  the second customer's typed measurements, the body made from them, its weights and fitted garments (*-2-*);"
echo "women/measurements.txt, men/measurements.txt: bodies from measurements of the held-out avatars"

# The shopper's page: the browser tests drive Debian's chromium through a sample body, a size
# switch and bad uploads, and leave a screenshot of the fit.
echo
echo "== The try-on page (browser checks and screenshot: $out/tryon.png)"
node web/tests/tryon.test.mjs --server "http://$page" --key "$shop_key" \
  --screenshot "$out/tryon.png" > "$out/tryon-tests.txt" 2>&1 ||
  { tail -20 "$out/tryon-tests.txt"; exit 1; }
grep -E "^# (pass|fail)" "$out/tryon-tests.txt"
echo "Try it on: http://$page/#key=$shop_key"
if $keep_serving; then
  echo "Serving until Ctrl-C."
  trap 'kill "$serve_pid" 2>/dev/null || true' INT
  wait "$serve_pid" || true
else
  kill "$serve_pid"
  wait "$serve_pid" || true
fi
trap - EXIT
