#!/usr/bin/env bash
# The C coupling partner (coupling_partner.c) in process, then against `quarry serve` over ipc://
# (arrays in shared memory) and over tcp://127.0.0.1 (a free port the server picks), each with the
# forces copied in and through the load view (--load-view): each run must
# pass, and the remote ones must print the in-process run's state hash (issue 16 §5: the same bits
# across processes). Every server started here is killed on exit, also on failure.
set -euo pipefail
quarry=$1 partner=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
servers=()
cleanup() {
  for pid in "${servers[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
  rm -f "${ipc_path:-}"
}
trap cleanup EXIT

# serve LOG ENDPOINT: starts `quarry serve` and sets $endpoint to the one it listens at.
serve() {
  local log=$1
  # The log exists before the loop reads it: the background job's redirection may come later.
  : > "$log"
  "$quarry" serve --endpoint "$2" --threads 2 > "$log" 2>&1 &
  servers+=($!)
  for _ in $(seq 1 400); do
    endpoint=$(sed -n 's/^quarry serve: listening on \([^ ]*\).*/\1/p' "$log")
    [ -n "$endpoint" ] && return 0
    kill -0 "${servers[-1]}" 2>/dev/null || { cat "$log"; echo "quarry serve exited before listening"; exit 1; }
    sleep 0.05
  done
  cat "$log"; echo "quarry serve did not listen within 20 s"; exit 1
}

# run NAME [partner options]: runs the partner, echoes its output, prints its state hash.
run() {
  local name=$1; shift
  if ! "$partner" --checkpoint "$work/$name.qck" "$@" > "$work/$name.out" 2>&1; then
    cat "$work/$name.out"; echo "the partner failed ($name)"; exit 1
  fi
  sed -n 's/^state hash: //p' "$work/$name.out"
}

in_process=$(run in_process)
in_process_view=$(run in_process_view --load-view)
ipc_path=$(mktemp -u "${TMPDIR:-/tmp}/quarry-partner-XXXXXX.ipc")
serve "$work/serve_ipc.log" "ipc://$ipc_path"
ipc=$(run ipc --endpoint "$endpoint")
ipc_view=$(run ipc_view --endpoint "$endpoint" --load-view)
grep -q "arrays in shared memory" "$work/serve_ipc.log" || { cat "$work/serve_ipc.log"; echo "ipc without shared memory"; exit 1; }
serve "$work/serve_tcp.log" "tcp://127.0.0.1:0"
tcp=$(run tcp --endpoint "$endpoint")
tcp_view=$(run tcp_view --endpoint "$endpoint" --load-view)
echo "state hash: in process $in_process, ipc (shared memory) $ipc, tcp $tcp"
echo "with the load view: in process $in_process_view, ipc $ipc_view, tcp $tcp_view"
[ -n "$in_process" ] && [ "$ipc" = "$in_process" ] && [ "$tcp" = "$in_process" ] || { echo "the hashes differ"; exit 1; }
[ "$in_process_view" = "$in_process" ] && [ "$ipc_view" = "$in_process" ] && [ "$tcp_view" = "$in_process" ] ||
  { echo "the hashes with the load view differ from those with copies"; exit 1; }
# SIGTERM ends a server cleanly: exit code 0 (under ASan its leak check runs then), socket file gone.
for pid in "${servers[@]}"; do
  kill -TERM "$pid"
  code=0
  wait "$pid" || code=$?
  [ "$code" -eq 0 ] || { cat "$work"/serve_*.log; echo "quarry serve exited with $code after SIGTERM"; exit 1; }
done
[ ! -e "$ipc_path" ] || { echo "the ipc socket file is left behind"; exit 1; }
echo "ok: the remote runs reproduce the in-process state bit for bit"
