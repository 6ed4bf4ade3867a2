# SPDX-License-Identifier: GPL-3.0-or-later
# What every CLI test script shares (sourced after `set -u`): the argument check, a scratch
# folder removed on exit, the pass / fail tally and its ending.
#
#   source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
#   cli_test_begin NAME COUNT "USAGE ARGS" "$@"   # exit 2 with a usage line unless COUNT arguments
#   ... pass "check" || fail "check" "why" ...
#   cli_test_end                                  # the tally; fails when any check failed

# cli_test_begin NAME COUNT USAGE ARGS...: checks that ARGS has COUNT words and makes $WORK.
cli_test_begin() {
  local name=$1 count=$2 usage=$3
  shift 3
  if [[ $# -ne $count ]]; then
    echo "usage: $0 $usage" >&2
    exit 2
  fi
  WORK=$(mktemp -d "${TMPDIR:-/tmp}/shadow-$name.XXXXXX")
  trap 'rm -rf "$WORK"' EXIT
}

passed=0
failed=0
pass() { passed=$((passed + 1)); echo "ok   $1"; }
fail() { failed=$((failed + 1)); echo "FAIL $1: $2"; }

# cli_test_end: prints the tally; its status is the script's (non-zero when a check failed).
cli_test_end() {
  echo "$passed passed, $failed failed"
  [[ $failed -eq 0 ]]
}
