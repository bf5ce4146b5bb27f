# Shared by the CLI restart tests (sourced; needs $quarry and $python): a damaged checkpoint made
# by tests/checkpoint_damage.py, and a restart of it that must exit 2 with a given message.
checks_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
damage() {  # IN OUT SECTION OFFSET FORMAT VALUE (checkpoint_damage.py)
  "$python" "$checks_dir/checkpoint_damage.py" "$@"
}
expect_refused() {  # FILE PATTERN
  set +e
  message=$("$quarry" restart "$1" --quiet --output-dir refused 2>&1)
  code=$?
  set -e
  echo "$message"
  test "$code" -eq 2 || { echo "expected exit code 2, got $code"; exit 1; }
  grep -q "$2" <<< "$message" || { echo "expected: $2"; exit 1; }
}
