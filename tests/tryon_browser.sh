#!/usr/bin/env bash
# The try-on page in Debian's chromium against the whole stack: `serve --role all` with the
# HTTP API on 127.0.0.1 (port 0), the small catalogue's basis published, a garment uploaded and
# built in two sizes by the in-process workers (the short drape schedule; a T-shirt and
# leggings, whose chest the tests read), then
# web/tests/tryon.test.mjs drives the page and the API. Usage: tryon_browser.sh FITBASE
# DATA_DIR SMALL_CATALOGUE_DIR WEB_DIR [SCREENSHOT]
set -euo pipefail
fitbase=$1 data=$2 small=$3 web=$4 screenshot=${5:-}
work=$(mktemp -d)
serve_pid=""
cleanup() {
  [ -n "$serve_pid" ] && kill "$serve_pid" 2>/dev/null && wait "$serve_pid" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
keys=$work/keys
admin=$("$fitbase" keys add --file "$keys" --tenant shop --role admin 2>/dev/null)
customer=$("$fitbase" keys add --file "$keys" --tenant shop --role customer 2>/dev/null)
mkfifo "$work/out"
"$fitbase" --data "$data" serve --role all --db "$work/store" --listen 127.0.0.1:0 \
  --fit-listen 127.0.0.1:0 --http-listen 127.0.0.1:0 --web-root "$web" --api-keys "$keys" \
  --workers 2 > "$work/out" 2> "$work/serve.log" &
serve_pid=$!
exec 3< "$work/out"
read -r _ coordinator <&3
read -r _ _ <&3
read -r _ http <&3
export FITBASE_API_KEY=$admin
"$fitbase" basis publish --coordinator "$coordinator" --population women --basis "$small/b.fbb" \
  > /dev/null
basis_id=$("$fitbase" basis info "$small/b.fbb" | awk '/^id/{print $2}')
garment=$("$fitbase" --data "$data" garment upload --coordinator "$coordinator" \
  --mhclo "$data/clothes/female_casualsuit01/female_casualsuit01.mhclo" --basis-id "$basis_id" \
  --sizes M,XL | awk '/^garment/{print $2}')
build=$("$fitbase" build submit --coordinator "$coordinator" --garment "$garment" --sizes M,XL \
  --methods linear --homotopy-steps 2 --relax-steps 2 | awk '{print $1; exit}')
"$fitbase" build watch --coordinator "$coordinator" "$build" > /dev/null
args=(--server "http://$http" --key "$customer" --scan "$small/pop/avatar-00003.obj")
[ -n "$screenshot" ] && args+=(--screenshot "$screenshot")
node "$web/tests/tryon.test.mjs" "${args[@]}"
