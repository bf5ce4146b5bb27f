# Shell functions shared by the peer-comparison harnesses (bench/run.sh: settled bed,
# bench/run_flowing.sh: flowing material). Sourced, not run; expects BENCH and ROOT set.

cpu_slug() { lscpu | sed -n 's/^Model name: *//p' | head -1 | tr 'A-Z' 'a-z' | sed 's/[^a-z0-9]\+/-/g; s/^-//; s/-$//' | cut -c1-32; }

# results_name BASE: BASE if BASE.csv is free, else the next free BASE-b, BASE-c, ... (an
# earlier invocation of the same day and machine keeps its files). With APPEND=1 the day's
# latest name instead, so that this invocation adds its runs to that file.
results_name() {
  local base=$1 name=$1 latest=$1 suffix
  for suffix in b c d e f g h i j k l m n o p q r s t u v w x y z; do
    [ -e "$name.csv" ] || break
    latest=$name; name="$base-$suffix"
  done
  [ "${APPEND:-0}" = 1 ] && name=$latest
  if [ -e "$name.csv" ] && [ "${APPEND:-0}" != 1 ]; then
    echo "bench: no free name for the results $base; set MACHINE" >&2; exit 2
  fi
  echo "$name"
}

# The peers from Debian 12 packages (LIGGGHTS 3.8.0, LAMMPS, Open MPI, GNU time), if missing.
install_peers() {
  if ! command -v lmp >/dev/null || ! command -v liggghts >/dev/null || ! command -v mpirun >/dev/null \
     || ! env time --version >/dev/null 2>&1; then
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y liggghts lammps openmpi-bin time
  fi
}

busy() { awk '/^cpu /{print $2+$3+$4+$7+$8+$9}' /proc/stat; }   # jiffies, all cores

# The machine may be shared: before each timed run wait (at most QUIET_WAIT s) until the other
# processes use < 0.15 cores over 2 s. Measured either way; the CPU used by others during each
# run is recorded (column other_load).
wait_quiet() {
  local t=0 b0 b1 hz; hz=$(getconf CLK_TCK)
  while [ "$t" -lt "$QUIET_WAIT" ]; do
    b0=$(busy); sleep 2; b1=$(busy); t=$((t+2))
    [ $(( (b1-b0)*100 / (2*hz) )) -lt 15 ] && return 0
  done
  return 0
}

# "key value" of GNU time -v output
time_field() { sed -n "s/^[[:space:]]*$2: //p" "$1" | head -1; }

# timed_run TAG LOG DIR COMMAND...: runs COMMAND in DIR under GNU time (to $LOGS/TAG.time),
# output to LOG; sets USER_S SYS_S RSS_KIB and OTHER_LOAD (cores used by other processes
# during the run).
timed_run() {
  local tag=$1 log=$2 dir=$3; shift 3
  local b0 t0 b1 t1 hz; hz=$(getconf CLK_TCK)
  b0=$(busy); t0=$(date +%s.%N)
  ( cd "$dir" && env time -v -o "$LOGS/$tag.time" "$@" ) > "$log" 2>&1 || echo "  $tag FAILED (see $log)"
  b1=$(busy); t1=$(date +%s.%N)
  USER_S=$(time_field "$LOGS/$tag.time" "User time (seconds)")
  SYS_S=$(time_field "$LOGS/$tag.time" "System time (seconds)")
  RSS_KIB=$(time_field "$LOGS/$tag.time" "Maximum resident set size (kbytes)")
  OTHER_LOAD=$(awk -v b=$((b1-b0)) -v hz="$hz" -v u="$USER_S" -v s="$SYS_S" -v t0="$t0" -v t1="$t1" \
          'BEGIN{o=(b/hz-u-s)/(t1-t0); if(o<0)o=0; printf "%.3f", o}')
}

# The machine line of a results summary. Hosts of one model name differ (a "AMD EPYC" guest
# may be Zen 3 or Zen 4): family, model, widest vector unit and caches say which one.
machine_line() {
  local vector=AVX2
  cpu_field() { lscpu | sed -n "s/^$1: *//p" | head -1; }
  grep -qw avx512f /proc/cpuinfo && vector=AVX-512
  grep -qw avx2 /proc/cpuinfo || vector=SSE
  # lscpu leaves the caches and the hypervisor out in some containers: glibc's view instead.
  cache() { local v; v=$(cpu_field "$1 cache"); [ -n "$v" ] && { echo "$v"; return; }
            getconf "LEVEL${1#L}_CACHE_SIZE" 2>/dev/null | awk '{if($1>0) printf "%.0f KiB (getconf)", $1/1024; else print "?"}'; }
  local hv; hv=$(cpu_field 'Hypervisor vendor'); [ -n "$hv" ] || hv=$(systemd-detect-virt 2>/dev/null || echo "?")
  echo "- CPU: $(cpu_field 'Model name'), family $(cpu_field 'CPU family') model $(cpu_field 'Model'), $vector, L2 $(cache L2), L3 $(cache L3), hypervisor $hv; $(nproc --all) logical CPUs; memory $(free -g | awk '/^Mem:/{print $2}') GiB"
}

# build_bench TARGET...: Quarry's Release build (BUILD_DIR, default build/release) of these
# targets, unless SKIP_BUILD=1.
build_bench() {
  [ "${SKIP_BUILD:-0}" = 1 ] && return 0
  if [ "$BUILD_DIR" = build/release ]; then
    cmake --preset release -DQUARRY_BUILD_BENCH=ON > /dev/null
  else
    cmake --preset release -B "$BUILD_DIR" -DQUARRY_BUILD_BENCH=ON > /dev/null
  fi
  cmake --build "$BUILD_DIR" --target "$@"
}

# parse_run_log CODE LOG STEPS: the figures of one timed run, from Quarry's QUARRY_BENCH line
# or a peer's log (the timed run between BENCH_BEGIN and BENCH_END, then the metrics lines
# CONTACTS_PER_PARTICLE, POUR_KE, BED_METRICS, FZ_NO_FLOOR). Sets R_N R_LOOP R_PSS R_COORD
# R_NEIGH R_NB R_ZMAX R_ZMEAN R_FLOOR R_WEIGHT R_KE R_SHARE (empty when the log has none).
parse_run_log() {
  local code=$1 log=$2 steps=$3
  if [ "$code" = quarry ]; then
    local line; line=$(grep -m1 '^QUARRY_BENCH' "$log" || true)
    kv() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<<"$line"; }
    R_N=$(kv n); R_LOOP=$(kv loop_s); R_PSS=$(kv pss); R_COORD=$(kv coordination); R_NEIGH=$(kv neigh_pp)
    R_NB=$(kv rebuilds); R_ZMAX=$(kv zmax); R_ZMEAN=$(kv zmean); R_FLOOR=$(kv floor_force)
    R_WEIGHT=$(kv weight); R_KE=$(kv ke_pp); R_SHARE=$(kv neigh_share)
    return 0
  fi
  local timed lt metrics
  timed=$(sed -n '/BENCH_BEGIN/,/BENCH_END/p' "$log")
  lt=$(grep -m1 -o 'Loop time of [0-9.e+-]* on [0-9]* procs for [0-9]* steps with [0-9]* atoms' <<<"$timed" || true)
  R_LOOP=$(awk '{print $4}' <<<"$lt"); R_N=$(awk '{print $12}' <<<"$lt")
  R_PSS=$(awk -v n="$R_N" -v s="$steps" -v l="$R_LOOP" 'BEGIN{if(l>0) printf "%.6g", n*s/l}')
  R_NB=$(sed -n 's/.*Neighbor list builds = \([0-9]*\).*/\1/p' <<<"$timed" | head -1)
  R_NEIGH=$(sed -n 's/.*Ave neighs\/atom = \([0-9.]*\).*/\1/p' <<<"$timed" | head -1)
  # The neighbour stage's share of the loop: LIGGGHTS "Neigh time (%) = s (pct)", LAMMPS
  # "Neigh | min | avg | max | %varavg | %total".
  R_SHARE=$( { sed -n 's/^Neigh time (%) = [0-9.e+-]* (\([0-9.e+-]*\)).*/\1/p' <<<"$timed";
               sed -n 's/^Neigh *|.*| *\([0-9.]*\) *$/\1/p' <<<"$timed"; } | head -1 |
             awk '{if($1!="") printf "%.4f", $1/100}')
  R_COORD=$(sed -n 's/^CONTACTS_PER_PARTICLE \([0-9.e+-]*\).*/\1/p' "$log" | head -1)
  R_KE=$(sed -n 's/^POUR_KE \([0-9.e+-]*\).*/\1/p' "$log" | head -1)
  metrics=$(grep -m1 '^BED_METRICS' "$log" || true)
  R_ZMAX=$(awk '{print $2}' <<<"$metrics"); R_ZMEAN=$(awk '{print $3}' <<<"$metrics")
  R_WEIGHT=$(awk '{print $5}' <<<"$metrics")
  R_FLOOR=$(awk -v a="$(awk '{print $4}' <<<"$metrics")" -v b="$(sed -n 's/^FZ_NO_FLOOR //p' "$log" | head -1)" \
                'BEGIN{if(a!="" && b!="") printf "%.7g", a-b}')
}

# stage_tables "CASES" "SKINS": for each case and skin, the per-stage table of Quarry's last
# one-thread run ($LOGS/<case>_quarry_np1_skin<skin>_r$REPEATS.log) as a markdown section.
stage_tables() {
  local case skin last
  for case in $1; do
    for skin in $2; do
      last="$LOGS/${case}_quarry_np1_skin${skin}_r$REPEATS.log"
      [ -f "$last" ] || continue
      echo
      echo "### Quarry per-stage time, $case, skin $skin m, 1 thread ($(basename "$last"))"
      echo
      echo '```'
      sed -n '/^stage/,/^total/p' "$last"
      echo '```'
    done
  done
}
