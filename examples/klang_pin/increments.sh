#!/usr/bin/env bash
# Klang's pin with the force applied in 1, 5, 10, 25, 50 and 100 equal increments: friction is
# path dependent (the course shows the same). Prints the contact and stick half-arcs and the
# largest pressure error at the reference angles, and plots all runs.
# Usage: examples/klang_pin/increments.sh [BUILD_DIR] [OUT_DIR] [DECK]
#   DECK: klang_pin.yaml (default; the force spread over the pin) or klang_pin_point_force.yaml
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="${1:-$here/../../build}"
out="${2:-$(mktemp -d)}"
deck="${3:-klang_pin.yaml}"
[ -f "$here/$deck" ] || { echo "increments.sh: no deck $here/$deck" >&2; exit 2; }
mkdir -p "$out"
labels=()
for n in 1 5 10 25 50 100; do
  f=$(awk "BEGIN { print 1 / $n }")
  sed -e "s|increments: {initial: 0.1, max: 0.1}|increments: {initial: $f, max: $f}|" \
      -e "s|file: klang_pin.geo|file: $here/klang_pin.geo|" "$here/$deck" > "$out/deck_$n.yaml"
  "$build/signorini" run -q "$out/deck_$n.yaml" -o "$out/run_$n" > "$out/log_$n" 2>&1 || echo "$n increments: failed, see $out/log_$n"
  labels+=("$out/run_$n:$n increments")
done
/usr/bin/python3 "$here/plot.py" "${labels[0]}" "$out/klang_increments.png" "${labels[@]:1}"
