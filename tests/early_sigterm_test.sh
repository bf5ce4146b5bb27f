#!/usr/bin/env bash
# SIGTERM at the earliest moment a handler can exist (issue 19: the first ~20 ms exited 143 with
# no checkpoint). The handlers are installed at the first statement of main, before anything is
# read or written: whenever the output folder exists the process already catches SIGTERM (its
# /proc status SigCgt has bit 15), and a SIGTERM sent the moment it does so stops the run with a
# checkpoint and exit 130. The time before main (the dynamic loader mapping the libraries) is
# not the program's: a signal then ends a process that has written nothing.
set -euo pipefail
quarry=$1 deck=$2 out=$3
rm -rf "$out" && mkdir -p "$(dirname "$out")"
catches_term() {  # SigCgt is a hex mask; SIGTERM (15) is bit 14
  local mask
  mask=$(sed -n 's/^SigCgt:[[:space:]]*//p' "/proc/$1/status" 2>/dev/null) || return 1
  [ -n "$mask" ] && (( (16#$mask >> 14) & 1 ))
}
"$quarry" run "$deck" --output-dir "$out" --quiet > "$out.log" 2>&1 &
pid=$!
for _ in $(seq 1 20000); do
  if [ -e "$out" ] && ! catches_term "$pid"; then
    kill -9 "$pid" 2>/dev/null || true
    echo "the output folder exists before the SIGTERM handler is installed"; exit 1
  fi
  catches_term "$pid" && break
done
kill -TERM "$pid"
set +e; wait "$pid"; code=$?; set -e
cat "$out.log"
[ "$code" -eq 130 ] || { echo "expected exit code 130, got $code"; exit 1; }
[ -f "$out/checkpoint.qck" ] || { echo "no checkpoint"; exit 1; }
echo "SIGTERM as soon as the handler exists: exit 130 with a checkpoint: ok"
