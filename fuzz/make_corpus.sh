#!/usr/bin/env bash
# Makes the fuzzers' seed inputs from real files: the MakeHuman data (data/makehuman: base.obj,
# targets, garments and their .mhclo bindings), and what the fitbase CLI writes from it (avatars, their measurements and parameters, common-format avatars raw and
# Draco, a small avatar basis, an imported garment, clothing bases and their cached drapes, an
# API key file), plus the seeds fitbase_fuzz_seeds writes (Draco payloads, drape task specs,
# build records). OBJ seeds are cropped to a few hundred vertices: the fuzzers' inputs stay
# small. Usage: fuzz/make_corpus.sh BUILD_DIR (a FITBASE_FUZZ build, for fitbase_fuzz_seeds;
# the files are written by build/fitbase, the Release CLI, or the fitbase binary $FITBASE
# names); writes BUILD_DIR/seeds/<fuzzer>/ and BUILD_DIR/seeds/catalogue/, never anything in
# the source tree.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: fuzz/make_corpus.sh BUILD_DIR}
data=data/makehuman
fitbase=${FITBASE:-build/fitbase}
seeds_tool="$build/fuzz/fitbase_fuzz_seeds"
out="$build/seeds"
partial="$out.partial"
rm -rf "$partial"
mkdir -p "$partial"
work="$partial/work"
mkdir -p "$work"
log="$work/log.txt"
run() { "$fitbase" --data "$data" "$@" >>"$log" 2>&1 || { cat "$log" >&2; exit 1; }; }
seed_dir() { mkdir -p "$partial/$1" && echo "$partial/$1"; }

# crop_obj IN OUT N: the first N vertices (and texture coordinates) and the faces that use only
# those, with the file's other lines.
crop_obj() {
  awk -v n="$3" '
    /^v / { if (++v <= n) print; next }
    /^vt / { if (++t <= n) print; next }
    /^f / {
      for (i = 2; i <= NF; i++) { split($i, c, "/"); if (c[1] + 0 > n || c[2] + 0 > n) next }
      print; next
    }
    { print }' "$1" > "$2"
}

echo "make_corpus: avatars, population, basis, garment, clothing bases ($fitbase)"
run population --preset women --count 6 --seed 5 --out "$work/pop"
run basis build --population "$work/pop" --components 2 --out "$work/b.fbb"
run garment import --mhclo "$data/clothes/female_sportsuit01/female_sportsuit01.mhclo" \
  --basis "$work/b.fbb" --sizes M,XL --out "$work/g.fbg"
run clothing build --basis "$work/b.fbb" --garment "$work/g.fbg" --size M --method linear \
  --homotopy-steps 2 --relax-steps 2 --cache "$work/drapes" --out "$work/M-linear.fbc"
run clothing build --basis "$work/b.fbb" --garment "$work/g.fbg" --size M --method quadratic \
  --homotopy-steps 2 --relax-steps 2 --cache "$work/drapes" --out "$work/M-quadratic.fbc"
run clothing build --basis "$work/b.fbb" --garment "$work/g.fbg" --size M --method kernel \
  --samples 4 --homotopy-steps 2 --relax-steps 2 --cache "$work/drapes" --out "$work/M-kernel.fbc"
avatar="$work/pop/avatar-00000.obj"
run avatar --params '{}' --out "$work/default.obj"

dir=$(seed_dir body_obj)
for n in 3 40 400; do
  crop_obj "$avatar" "$dir/avatar-$n.obj" "$n"
  crop_obj "$data/base.obj" "$dir/base-$n.obj" "$n"
done

dir=$(seed_dir garment_obj)
for garment in "$data"/clothes/*/*.obj; do
  crop_obj "$garment" "$dir/$(basename "$garment" .obj)-300.obj" 300
done
crop_obj "$data/clothes/female_sportsuit01/female_sportsuit01.obj" "$dir/sportsuit-30.obj" 30

dir=$(seed_dir target)
find "$data/targets" -name '*.target' -size -6k | sort | head -n 24 | while read -r target; do
  cp "$target" "$dir/$(basename "$target")"
done

dir=$(seed_dir mhclo)
for mhclo in "$data"/clothes/*/*.mhclo; do
  name=$(basename "$mhclo" .mhclo)
  # The header and the first vertex lines, and the whole file with delete_verts after them.
  awk '/^verts/ { print; verts = 1; next } verts && ++n > 60 { exit } { print }' "$mhclo" \
    > "$dir/$name-60.mhclo"
done
sportsuit="$data/clothes/female_sportsuit01/female_sportsuit01.mhclo"
{
  awk '/^verts/ { verts = 1 } !verts || ++n <= 12 { print }' "$sportsuit"
  sed -n '/^delete_verts/,$p' "$sportsuit" | head -n 8
} > "$dir/with-delete-verts.mhclo"

dir=$(seed_dir avatar_params_json)
split -l 1 -d "$work/pop/params.jsonl" "$dir/params-"
printf '%s\n' '{}' > "$dir/empty.json"
printf '%s\n' '{"gender": 0.1, "age_years": 40,' \
  '"modifiers": {"measure/measure-waist-circ-decr|incr": 0.3}}' > "$dir/readme.json"

dir=$(seed_dir measurements_json)
for i in 00000 00001 00002; do
  run avatar measure "$work/pop/avatar-$i.obj" --json
  tail -n 1 "$log" > "$dir/avatar-$i.json"
done
printf '%s\n' '{"stature_cm": 165, "weight_kg": 62, "bust_girth_cm": 92,' \
  '"waist_girth_cm": 74, "hip_girth_cm": 100}' > "$dir/five.json"

dir=$(seed_dir avatar)
run avatar export --obj "$avatar" --out "$dir/raw.fba"
head -n 1 "$work/pop/params.jsonl" > "$work/params.json"
run avatar export --obj "$avatar" --params "$work/params.json" --draco --out "$dir/draco-params.fba"
run avatar export --obj "$work/default.obj" --draco --out "$dir/default-draco.fba"

"$seeds_tool" draco "$(seed_dir draco_positions)" "$avatar" \
  "$data/clothes/female_sportsuit01/female_sportsuit01.obj"

dir=$(seed_dir avatar_basis)
cp "$work/b.fbb" "$dir/b.fbb"

dir=$(seed_dir garment)
cp "$work/g.fbg" "$dir/g.fbg"

dir=$(seed_dir clothing_basis)
cp "$work/M-linear.fbc" "$work/M-quadratic.fbc" "$work/M-kernel.fbc" "$dir/"

dir=$(seed_dir drape_result)
cp "$work"/drapes/*.fbd "$dir/"

"$seeds_tool" specs "$(seed_dir drape_task_spec)" "$work/b.fbb" "$work/g.fbg"
"$seeds_tool" builds "$(seed_dir build_record)" "$work/g.fbg"
mkdir -p "$partial/catalogue"
cp "$work/b.fbb" "$work/g.fbg" "$partial/catalogue/"

dir=$(seed_dir api_keys)
for role in customer ingestion admin worker; do
  run keys add --file "$dir/keys" --tenant "shop-$role" --role "$role"
done
{ echo "# fitbase API keys"; echo; cat "$dir/keys"; } > "$dir/commented"

# The HTTP API's bodies: the first byte picks the endpoint (fuzz/http_body_fuzzer.cc): 0 the
# try-on JSON, 1 typed measurements, 2 an OBJ upload, 3 an .fba upload.
dir=$(seed_dir http_body)
printf '\000{"garment_id": "g", "method": "linear", "weights": {"basis_id": "b", "weights": [0.01, -0.02]}}' \
  > "$dir/tryon"
printf '\001{"population": "women", "measurements": {"stature_cm": 168, "weight_kg": 65}}' \
  > "$dir/measurements"
for f in "$partial"/body_obj/*; do { printf '\002'; cat "$f"; } > "$dir/obj-$(basename "$f")"; done
for f in "$partial"/avatar/*; do { printf '\003'; cat "$f"; } > "$dir/fba-$(basename "$f")"; done

rm -rf "$work"
rm -rf "$out"
mv "$partial" "$out"
for d in "$out"/*/; do
  printf 'make_corpus: %-20s %3d seeds, %7d bytes\n' "$(basename "$d")" "$(ls "$d" | wc -l)" \
    "$(cat "$d"/* | wc -c)"
done
