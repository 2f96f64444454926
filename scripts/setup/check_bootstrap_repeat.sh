#!/usr/bin/env bash
# Shows that bootstrap's package-source step passes every time on a machine put
# back into the state of a fresh one before each run (issue: it failed 9-41 of
# 50 fresh machines when its check piped apt-cache into a grep that quit at
# the first match, under pipefail: apt-cache then died of SIGPIPE).
#
#   bash scripts/setup/check_bootstrap_repeat.sh [RUNS=50]
#
# Each run removes bootstrap's deb-src entry and apt's source indexes (what a
# fresh Debian 12 machine lacks), then runs `bootstrap.sh --check-source-index`,
# which adds the entry, runs apt-get update and checks that trilinos' source
# package is visible. It also runs the fixed check 200 times on the now-present
# index, where only SIGPIPE could fail it.
# Needs root (apt). Prints "N passed, N failed" and exits non-zero on a failure.
set -euo pipefail
runs=${1:-50}
root=$(cd "$(dirname "$0")/../.." && pwd)
deb_src=/etc/apt/sources.list.d/rast-bookworm-src.sources
pass=0 fail=0
for i in $(seq 1 "$runs"); do
  rm -f "$deb_src"
  find /var/lib/apt/lists -maxdepth 1 -name '*_source_Sources*' -delete
  if bash "$root/scripts/bootstrap.sh" --check-source-index >"/tmp/check_bootstrap.$i.log" 2>&1; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1))
    echo "run $i failed:"; cat "/tmp/check_bootstrap.$i.log"
  fi
  rm -f "/tmp/check_bootstrap.$i.log"
done

new_fail=0
for i in $(seq 1 200); do
  bash -c "set -o pipefail; apt-cache showsrc --only-source trilinos 2>/dev/null | grep '^Package: trilinos$' >/dev/null" || new_fail=$((new_fail + 1))
done
echo "index present, 200 checks: the fixed check failed $new_fail"
echo "fresh-state bootstrap source step: $pass passed, $fail failed"
[ "$fail" -eq 0 ] && [ "$new_fail" -eq 0 ]
