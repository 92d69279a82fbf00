#!/usr/bin/env bash
# Runs fitbase on this machine, on 127.0.0.1: one coordinator and N drape workers, each its own
# process of build/fitbase (scripts/setup.sh builds it), with the store and logs in one folder.
# Every run writes a fresh API key file (an admin and a worker key of tenant "local") and
# prints the admin key's export line. Ctrl-C (or any process exiting) stops them all: workers
# first, so they finish or return their drapes, then the coordinator.

# kill_all and cleanup run from traps, which shellcheck cannot follow.
# shellcheck disable=SC2317
set -euo pipefail

usage() {
  cat <<'EOF'
usage: deploy/local/run.sh [--workers N] [--slots N] [--port P] [--dir DIR] [-- COORDINATOR_ARGS...]

  --workers N   drape worker processes (default 2; 0 runs the coordinator alone)
  --slots N     drapes each worker runs at once (default 1)
  --port P      coordinator port on 127.0.0.1 (default 7401; 0 picks a free one)
  --dir DIR     store, key file and logs (default deploy/local/run/, ignored by Git)
  -- ARGS       passed on to `fitbase serve --role coordinator`, e.g. -- --lease-seconds 120

Environment: FITBASE_BIN (default build/fitbase), FITBASE_DATA (MakeHuman data, else the
binary's default), FITBASE_START_TIMEOUT (seconds to wait for the coordinator, default 120).
EOF
}

if [ "${BASH_VERSINFO[0]}" -lt 5 ] || { [ "${BASH_VERSINFO[0]}" -eq 5 ] && [ "${BASH_VERSINFO[1]}" -lt 1 ]; }; then
  echo "run.sh: needs bash 5.1 or later (wait -n -p)" >&2
  exit 1
fi

root=$(cd "$(dirname "$0")/../.." && pwd)
workers=2
slots=1
port=7401
dir="$root/deploy/local/run"
coordinator_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --workers | --slots | --port | --dir)
      [ $# -ge 2 ] || { echo "run.sh: $1 needs a value" >&2; exit 2; }
      case "$1" in
        --workers) workers=$2 ;;
        --slots) slots=$2 ;;
        --port) port=$2 ;;
        --dir) dir=$2 ;;
      esac
      shift 2
      ;;
    --workers=*) workers=${1#*=}; shift ;;
    --slots=*) slots=${1#*=}; shift ;;
    --port=*) port=${1#*=}; shift ;;
    --dir=*) dir=${1#*=}; shift ;;
    --) shift; coordinator_args=("$@"); break ;;
    -h | --help) usage; exit 0 ;;
    *) echo "run.sh: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done
[[ $workers =~ ^[0-9]+$ ]] || { echo "run.sh: --workers must be a count, got '$workers'" >&2; exit 2; }
[[ $slots =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: --slots must be at least 1, got '$slots'" >&2; exit 2; }
if ! [[ $port =~ ^[0-9]+$ ]] || [ "$port" -gt 65535 ]; then
  echo "run.sh: --port must be 0..65535, got '$port'" >&2
  exit 2
fi
[ -n "$dir" ] || { echo "run.sh: --dir is empty" >&2; exit 2; }

bin=${FITBASE_BIN:-$root/build/fitbase}
[ -x "$bin" ] || { echo "run.sh: no executable $bin; run scripts/setup.sh first" >&2; exit 1; }
start_timeout=${FITBASE_START_TIMEOUT:-120}
[[ $start_timeout =~ ^[1-9][0-9]*$ ]] ||
  { echo "run.sh: FITBASE_START_TIMEOUT must be whole seconds, got '$start_timeout'" >&2; exit 2; }

# Keys, key file and store are for this user only.
umask 077
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)

# A key like fitbase's own (services/rpc/api_keys.h): "fb_" and 64 hex digits from 32 random bytes.
new_key() { printf 'fb_%s' "$(head -c 32 /dev/urandom | od -An -tx1 | tr -d ' \n')"; }
# The key file lists the SHA-256 of the key's bytes, no newline.
key_hash() { printf '%s' "$1" | sha256sum | cut -d' ' -f1; }

admin_key=$(new_key)
worker_key=$(new_key)
{
  echo "# written by deploy/local/run.sh; fresh keys every run. <sha256 of key> <tenant> <role>"
  echo "$(key_hash "$admin_key") local admin"
  echo "$(key_hash "$worker_key") local worker"
} > "$dir/api-keys.tmp"
mv "$dir/api-keys.tmp" "$dir/api-keys"
printf 'export FITBASE_API_KEY=%s\n' "$admin_key" > "$dir/admin.env"

coordinator_pid=""
worker_pids=()
fifo=""

kill_all() {
  local p
  for p in "${worker_pids[@]}"; do kill "-$1" "$p" 2>/dev/null || true; done
  [ -z "$coordinator_pid" ] || kill "-$1" "$coordinator_pid" 2>/dev/null || true
}

# Stops what is still running, workers first (SIGTERM: they finish or return their leases),
# then the coordinator (SIGTERM: it drains). A second Ctrl-C kills them at once.
cleanup() {
  local rc=$? p
  set +e
  trap - EXIT
  killed=""
  trap 'echo "run.sh: killing them" >&2; killed=1; kill_all KILL' INT TERM
  [ -z "$fifo" ] || rm -f "$fifo"
  local live=()
  for p in "${worker_pids[@]}"; do kill -0 "$p" 2>/dev/null && live+=("$p"); done
  if [ ${#live[@]} -gt 0 ]; then
    echo "run.sh: stopping ${#live[@]} worker(s); they finish or return their drapes (Ctrl-C again to kill)" >&2
    kill -TERM "${live[@]}" 2>/dev/null
    for p in "${live[@]}"; do wait "$p" 2>/dev/null; done
  fi
  if [ -n "$coordinator_pid" ]; then
    if [ -z "$killed" ] && kill -0 "$coordinator_pid" 2>/dev/null; then
      echo "run.sh: stopping the coordinator" >&2
      kill -TERM "$coordinator_pid" 2>/dev/null
    fi
    wait "$coordinator_pid" 2>/dev/null
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# Children run in sessions of their own (setsid), so a Ctrl-C reaches only this script, which
# then stops them in order. The coordinator's stdout is a FIFO this script reads its
# `listening <host:port>` line from.
fifo=$(mktemp -u "$dir/.coordinator-stdout.XXXXXX")
mkfifo "$fifo"
setsid "$bin" serve --role coordinator --db "$dir/store" --listen "127.0.0.1:$port" \
  --api-keys "$dir/api-keys" "${coordinator_args[@]}" > "$fifo" 2> "$dir/coordinator.log" &
coordinator_pid=$!
exec 3< "$fifo"
rm -f "$fifo"
fifo=""

: > "$dir/coordinator.out"
address=""
deadline=$((SECONDS + start_timeout))
while [ -z "$address" ]; do
  left=$((deadline - SECONDS))
  if [ "$left" -le 0 ]; then
    echo "run.sh: the coordinator printed no 'listening' line in ${start_timeout}s; see $dir/coordinator.log" >&2
    exit 1
  fi
  rc=0
  IFS= read -r -t "$left" line <&3 || rc=$?
  if [ "$rc" -gt 128 ]; then
    continue  # timed out: the check above reports it
  elif [ "$rc" -ne 0 ]; then
    wait "$coordinator_pid" 2>/dev/null && status=0 || status=$?
    coordinator_pid=""
    echo "run.sh: the coordinator exited (status $status) before listening; its log $dir/coordinator.log ends:" >&2
    tail -n 20 "$dir/coordinator.log" >&2
    exit 1
  fi
  printf '%s\n' "$line" >> "$dir/coordinator.out"
  case "$line" in
    "listening "*) address=${line#listening } ;;
  esac
done
# Keep draining its stdout so it never blocks on a full pipe.
cat <&3 >> "$dir/coordinator.out" &
exec 3<&-

for i in $(seq 1 "$workers"); do
  FITBASE_API_KEY=$worker_key setsid "$bin" serve --role worker --coordinator "$address" \
    --slots "$slots" > "$dir/worker-$i.log" 2>&1 &
  worker_pids+=($!)
done

rel=${dir#"$root"/}
cat <<EOF
fitbase coordinator listening on $address (pid $coordinator_pid, log $rel/coordinator.log)
$workers worker(s) with $slots slot(s) each (logs $rel/worker-N.log); store $rel/store
admin key (also in $rel/admin.env):
export FITBASE_API_KEY=$admin_key
Ctrl-C stops everything.
EOF

# Until Ctrl-C, or until any of them exits: then stop the others.
exited=""
rc=0
wait -n -p exited "$coordinator_pid" "${worker_pids[@]}" || rc=$?
if [ "$exited" = "$coordinator_pid" ]; then
  coordinator_pid=""
  echo "run.sh: the coordinator exited (status $rc); see $rel/coordinator.log" >&2
else
  for i in "${!worker_pids[@]}"; do
    if [ "${worker_pids[$i]}" = "$exited" ]; then
      unset 'worker_pids[i]'
      echo "run.sh: worker $((i + 1)) exited (status $rc); see $rel/worker-$((i + 1)).log" >&2
    fi
  done
fi
exit 1
