#!/usr/bin/env bash
# The rooms' arrows (docs/architecture.md), checked on every #include of our own code: a room
# includes only itself and the rooms below it. The link lines enforce the same for calls; this
# also catches header-only uses, which link anyway.
set -euo pipefail
cd "${1:-$(dirname "$0")/..}"
declare -A allowed=(
  [core]="core"
  [body]="body core"
  [clothing]="clothing body core"
  [proto]="proto clothing body core"
  [storage]="storage core"
  [workers]="workers proto clothing body core"
  [pipeline]="pipeline workers proto clothing body core"
  [services/rpc]="services/rpc storage core"
  [services/build]="services/build services/rpc pipeline workers storage proto clothing body core"
  [services/fit]="services/fit services/rpc pipeline storage proto clothing body core"
  [services/http]="services/http services/rpc pipeline proto clothing body core"
  [cli]="cli services/build services/fit services/http services/rpc pipeline workers storage proto clothing body core"
  [fuzz]="fuzz services/build services/fit services/http services/rpc pipeline workers storage proto clothing body core"
)
# Generated protobuf headers live under proto/'s build folder as fitbase/v1/*.
room_of_include() {
  case "$1" in
    fitbase/v1/*) echo proto ;;
    services/*) echo "${1%/*}" ;;
    */*) echo "${1%%/*}" ;;
    *) echo "" ;;
  esac
}
failures=0
checked=0
for room in "${!allowed[@]}"; do
  for file in "$room"/*.h "$room"/*.cc; do
    [ -e "$file" ] || continue
    checked=$((checked + 1))
    while IFS= read -r line; do
      path=${line#*\"}; path=${path%\"*}
      target=$(room_of_include "$path")
      [ -n "$target" ] && [ -n "${allowed[$target]+x}" ] || continue
      if [[ " ${allowed[$room]} " != *" $target "* ]]; then
        echo "$file includes $path: $room may include only ${allowed[$room]}" >&2
        failures=$((failures + 1))
      fi
    done < <(grep -E '^#include "' "$file" || true)
  done
done
if [ "$failures" -gt 0 ]; then
  echo "$failures includes against the arrows" >&2
  exit 1
fi
echo "layering: $checked files, every include points down"
