#!/usr/bin/env bash
# CTest fixture: a small avatar basis (2 components: 5 example drapes per size), a garment
# imported on it, and the linear clothing basis of size M built locally with the short drape
# schedule, for the distributed-build tests to compare against. Usage: small_catalogue.sh
# FITBASE DATA_DIR OUT_DIR.
set -euo pipefail
fitbase=$1 data=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
run() { "$fitbase" --data "$data" "$@" >>"$out/log.txt" 2>&1; }
run population --preset women --count 8 --seed 5 --out "$out/pop"
run basis build --population "$out/pop" --components 2 --out "$out/b.fbb"
run garment import --mhclo "$data/clothes/female_sportsuit01/female_sportsuit01.mhclo" \
  --basis "$out/b.fbb" --sizes M,XL --out "$out/g.fbg"
run clothing build --basis "$out/b.fbb" --garment "$out/g.fbg" --size M --method linear \
  --homotopy-steps 2 --relax-steps 2 --out "$out/M-linear.fbc"
touch "$out/ready"
