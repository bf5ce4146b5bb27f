#!/usr/bin/env bash
# The C partner printed in docs/coupling.md ("A partner in C, in this process") compiles as C11
# against quarry.h and libquarry.so alone and runs to the end: the page cannot drift from the ABI.
set -euo pipefail
source_dir=$1 include_dir=$2 library=$3 compiler=$4 work=$5 flags=${6:-}
rm -rf "$work"
mkdir -p "$work"
# The first ```c block after the section's heading.
awk '/^## A partner in C, in this process/ {section = 1}
     section && /^```c$/ {inside = 1; next}
     inside && /^```$/ {exit}
     inside {print}' "$source_dir/docs/coupling.md" > "$work/partner.c"
[ -s "$work/partner.c" ] || { echo "no C block found under 'A partner in C, in this process'"; exit 1; }
"$compiler" -std=c11 -Wall -Wextra -Werror $flags -I "$include_dir" "$work/partner.c" "$library" \
  -Wl,-rpath,"$(dirname "$library")" -o "$work/partner"
cd "$source_dir"  # the example names the deck relative to the repository root
"$work/partner"
echo "docs/coupling.md: the C partner compiled and ran"
