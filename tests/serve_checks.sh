# Shared by the tests that run a partner against `quarry serve` (sourced; needs $quarry): a server
# started in the background, waited for until it listens, and every server killed on exit, also
# on failure. The caller's own EXIT trap, if it needs one, calls stop_servers_now.
servers=()
stop_servers_now() {
  for pid in "${servers[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
}
trap stop_servers_now EXIT

# serve LOG ENDPOINT: starts `quarry serve --endpoint ENDPOINT` (its output in LOG) and sets
# $endpoint to the one it listens at (a tcp port of 0 becomes the port it picked).
serve() {
  local log=$1
  # The log exists before the loop reads it: the background job's redirection may come later.
  : > "$log"
  "$quarry" serve --endpoint "$2" --threads 2 > "$log" 2>&1 &
  servers+=($!)
  for _ in $(seq 1 400); do
    endpoint=$(sed -n 's/^quarry serve: listening on \([^ ]*\).*/\1/p' "$log")
    [ -n "$endpoint" ] && return 0
    kill -0 "${servers[-1]}" 2>/dev/null ||
      { cat "$log"; echo "quarry serve exited before listening"; exit 1; }
    sleep 0.05
  done
  cat "$log"; echo "quarry serve did not listen within 20 s"; exit 1
}

# stop_servers LOG...: SIGTERM to every server started here; each must exit with code 0 (under
# ASan its leak check runs then). The LOGs are shown if one does not.
stop_servers() {
  local pid code
  for pid in "${servers[@]}"; do
    kill -TERM "$pid"
    code=0
    wait "$pid" || code=$?
    [ "$code" -eq 0 ] || { cat "$@"; echo "quarry serve exited with $code after SIGTERM"; exit 1; }
  done
  servers=()
}
