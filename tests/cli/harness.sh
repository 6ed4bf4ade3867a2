# SPDX-License-Identifier: GPL-3.0-or-later
# What every CLI test script shares (sourced after `set -u`): the argument check, a scratch
# folder removed on exit, the pass / fail tally and its ending.
#
#   source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
#   cli_test_begin NAME COUNT "USAGE ARGS" "$@"   # exit 2 with a usage line unless COUNT arguments
#   ... pass "check" || fail "check" "why" ... same_outputs "check" DIR_A DIR_B ...
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

# same_file A B F: file F of folders A and B holds the same bytes; energyplus-objects.idf names
# the CSV beside it by its absolute path, the folder's own, so there each folder's path counts as
# the same text.
same_file() {
  local a=$1 b=$2 f=$3
  if [[ "$(basename "$f")" == energyplus-objects.idf ]]; then
    cmp -s <(sed "s|$(cd "$a" && pwd)|OUTDIR|g" "$a/$f") <(sed "s|$(cd "$b" && pwd)|OUTDIR|g" "$b/$f")
  else
    cmp -s "$a/$f" "$b/$f"
  fi
}

# same_outputs NAME A B: folders A and B hold the same files, byte for byte (report.json without
# its start time, which no two runs share; energyplus-objects.idf as same_file compares it); one
# pass or fail named NAME.
same_outputs() {
  local name=$1 a=$2 b=$3
  local listing_a listing_b
  listing_a=$(cd "$a" && find . -type f | sort)
  listing_b=$(cd "$b" && find . -type f | sort)
  if [[ "$listing_a" != "$listing_b" ]]; then
    fail "$name" "different files: $(diff <(echo "$listing_a") <(echo "$listing_b") | tr '\n' ' ')"
    return
  fi
  local f
  while read -r f; do
    if [[ "$f" == ./report.json ]]; then
      if ! cmp -s <(grep -v '"started_utc"' "$a/$f") <(grep -v '"started_utc"' "$b/$f"); then
        fail "$name" "report.json differs: $(diff <(grep -v '"started_utc"' "$a/$f") <(grep -v '"started_utc"' "$b/$f") | head -5 | tr '\n' ' ')"
        return
      fi
    elif ! same_file "$a" "$b" "$f"; then
      fail "$name" "$f differs"
      return
    fi
  done <<<"$listing_a"
  pass "$name ($(echo "$listing_a" | wc -l) files identical)"
}

# cli_test_end: prints the tally; its status is the script's (non-zero when a check failed).
cli_test_end() {
  echo "$passed passed, $failed failed"
  [[ $failed -eq 0 ]]
}
