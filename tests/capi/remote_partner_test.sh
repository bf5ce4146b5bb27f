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
source "$(dirname "$0")/../serve_checks.sh"
trap 'stop_servers_now; rm -f "${ipc_path:-}"' EXIT

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
# SIGTERM ends a server cleanly: exit code 0, socket file gone.
stop_servers "$work"/serve_*.log
[ ! -e "$ipc_path" ] || { echo "the ipc socket file is left behind"; exit 1; }
echo "ok: the remote runs reproduce the in-process state bit for bit"
