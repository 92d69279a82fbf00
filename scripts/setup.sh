#!/usr/bin/env bash
# Prepares this checkout on a Debian (bookworm) machine: installs the Debian packages fitbase
# needs (skipping those already installed), makes the MakeHuman data available in data/, and
# builds Release into build/. Safe to run again: each step only does what is missing.
# --packages-only stops after the packages (deploy/Dockerfile's build stage uses it);
# --no-build after the data (scripts/fuzz.sh and test.sh --sanitize build elsewhere).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
packages_only=false
no_build=false
case "${1:-}" in
  "") ;;
  --packages-only) packages_only=true ;;
  --no-build) no_build=true ;;
  *) echo "usage: scripts/setup.sh [--packages-only | --no-build]" >&2; exit 2 ;;
esac

packages=(
  cmake ninja-build g++ pkg-config ca-certificates curl
  protobuf-compiler libprotobuf-dev protobuf-compiler-grpc libgrpc++-dev libabsl-dev libssl-dev
  libeigen3-dev librocksdb-dev libdraco-dev libopenmesh-dev libcli11-dev libpng-dev
  libgtest-dev libgmock-dev libbenchmark-dev libsuitesparse-dev libopenblas0-pthread
  libcpp-httplib-dev clang-16 libclang-rt-16-dev
)
# The page's browser tests drive Debian's chromium; an image build (--packages-only) runs none.
$packages_only || packages+=(chromium)
# The page's packages come from npm (web/package-lock.json); Debian's Node.js only where the
# machine has none of its own (a Node.js from elsewhere ships its own npm).
command -v npm > /dev/null || packages+=(nodejs npm)
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
# The drape's supernodal factorisation (CHOLMOD) spends most of its time in BLAS: with OpenBLAS
# it is 6.2x faster than Eigen's simplicial one on an 8.4k-vertex garment, with Debian's
# reference BLAS about as fast (fitbase_drape_bench --speed). OpenBLAS's threaded
# build, chosen even when another BLAS is installed; workers/sparse_cholesky runs it on one
# thread. The serial build is not safe for drapes side by side in one process.
for lib in libblas.so.3 liblapack.so.3; do
  want=/usr/lib/x86_64-linux-gnu/openblas-pthread/$lib
  if [ "$(readlink -f "/usr/lib/x86_64-linux-gnu/$lib")" != "$(readlink -f "$want")" ]; then
    $sudo update-alternatives --set "$lib-x86_64-linux-gnu" "$want"
  fi
done
if $packages_only; then exit 0; fi

# three.js for the page and playwright-core for its browser tests, exactly as locked; no
# browser download (the tests drive Debian's chromium).
if [ ! -f web/node_modules/.package-lock.json ] ||
   ! cmp -s web/package-lock.json web/node_modules/.fitbase-lock; then
  echo "setup: npm ci in web/"
  (cd web && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error)
  cp web/package-lock.json web/node_modules/.fitbase-lock
fi

# MakeHuman data (CC0), never committed: a link to ../shared/data/makehuman beside the checkout
# when there is one, else the pinned upstream files. scripts/makehuman_manifest.sha256 pins
# every file the project reads, so either way the bytes are the ones the tests expect.
manifest="$root/scripts/makehuman_manifest.sha256"
data="$root/data/makehuman"
mkdir -p "$root/data"
if [ ! -e "$data/base.obj" ]; then
  shared="$(cd "$root/.." && pwd)/shared/data/makehuman"
  if [ -f "$shared/base.obj" ]; then
    ln -sfn "$shared" "$data"
    echo "setup: linked $data -> $shared"
  else
    makehuman_commit=a8bc2d54ff0ac92e78ff71431b1023eda42bf482
    assets_commit=8cf9645b975a98eea056b140df11a1d278da0d10
    # FITBASE_DATA_MIRROR: the same layout elsewhere (a proxy, or file:// in a test).
    github=${FITBASE_DATA_MIRROR:-https://raw.githubusercontent.com/makehumancommunity}
    partial="$data.partial"
    rm -rf "$partial"
    total=$(wc -l < "$manifest")
    done_count=0
    start=$(date +%s)
    while read -r _ path; do
      case "$path" in
        base.obj) url="$github/makehuman/$makehuman_commit/makehuman/data/3dobjs/base.obj" ;;
        clothes/*) url="$github/makehuman-assets/$assets_commit/base/$path" ;;
        *) url="$github/makehuman/$makehuman_commit/makehuman/data/$path" ;;
      esac
      mkdir -p "$partial/$(dirname "$path")"
      curl -fsSL --retry 3 -o "$partial/$path" "$url"
      done_count=$((done_count + 1))
      elapsed=$(( $(date +%s) - start ))
      printf '\rsetup: downloading MakeHuman data %d/%d  elapsed %ds  ETA %ds' "$done_count" "$total" \
        "$elapsed" $(( elapsed * (total - done_count) / done_count )) >&2
    done < "$manifest"
    echo >&2
    mv "$partial" "$data"
  fi
fi
(cd "$data" && sha256sum --quiet --strict -c "$manifest") || {
  echo "setup: $data does not match scripts/makehuman_manifest.sha256" >&2
  exit 1
}
if $no_build; then exit 0; fi

cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release > "$root/build.log" 2>&1 ||
  { cat "$root/build.log"; exit 1; }
cmake --build "$root/build"
