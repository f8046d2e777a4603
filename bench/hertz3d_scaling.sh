#!/usr/bin/env bash
# Hertz 3D quarter model (examples/hertz_sphere_3d) at increasing size: DOFs, Newton
# iterations, wall time split into assembly / contact / linear solve, peak memory, and the
# errors against Hertz. Usage: [LINEAR=gamg] [MPIRUN="mpirun -np 2"] [FRICTION="{law: coulomb,
# mu: 0.3}"] [ENFORCEMENT=penalty] bench/hertz3d_scaling.sh [BUILD_DIR] [hc ...]. LINEAR: the deck's solver.linear
# (default: the deck's own, auto); MPIRUN: the launcher the solver runs under (default: none, one
# process); FRICTION: the pair's friction (default: frictionless; the contact system is then
# unsymmetric: with Lagrange multipliers condensed node by node, with ENFORCEMENT=penalty as it is,
# for GMRES over GAMG, which auto takes in 3D at any size; docs/performance.md, sessions 57-59);
# ENFORCEMENT: the pair's enforcement method (default: the deck's, lagrange).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
shift || true
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(0.02 0.015 0.012 0.01 0.008)
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
printf "%-7s %8s %6s %9s %9s %9s %9s %9s %8s %8s  %s\n" hc dofs iters total_s assemb_s contact_s solve_s mem_MiB p0_err a_err solver
for hc in "${sizes[@]}"; do
  sed -e "s|hc: [0-9.]*|hc: $hc|" -e "s|file: hertz_sphere_3d.geo|file: $here/examples/hertz_sphere_3d/hertz_sphere_3d.geo|" \
    "$here/examples/hertz_sphere_3d/hertz_sphere_3d.yaml" > "$work/deck.yaml"
  if [ -n "${LINEAR:-}" ]; then echo "solver: {linear: $LINEAR}" >> "$work/deck.yaml"; fi
  if [ -n "${FRICTION:-}" ]; then
    sed -i "s|^    slave: SphereSurface\$|    slave: SphereSurface\n    friction: $FRICTION|" "$work/deck.yaml"
    grep -q "friction: " "$work/deck.yaml" || { echo "FRICTION: no slave line to add it under" >&2; exit 1; }
  fi
  if [ -n "${ENFORCEMENT:-}" ]; then
    sed -i "s|^    slave: SphereSurface\$|    slave: SphereSurface\n    enforcement: {method: $ENFORCEMENT}|" "$work/deck.yaml"
    grep -q "enforcement: " "$work/deck.yaml" || { echo "ENFORCEMENT: no slave line to add it under" >&2; exit 1; }
  fi
  ${MPIRUN:-} "$build/signorini" run -q "$work/deck.yaml" -o "$work/out" > "$work/log" 2>&1 || true
  s="$work/out/summary.json"
  get() { grep -o "\"$1\": [^,}]*" "$s" | head -1 | sed 's/.*: //'; }
  errs=$(grep -o '"error": [^,]*' "$s" | sed 's/.*: //' | head -2 | tr '\n' ' ')
  solver=$(grep -o '"linear_solver": "[^"]*"' "$s" | tail -1 | sed 's/.*: //; s/"//g' || true)
  printf "%-7s %8s %6s %9.2f %9.2f %9.2f %9.2f %9.0f %8.4f %8.4f  %s\n" "$hc" "$(get dofs)" "$(get total_iterations)" \
    "$(get total_s)" "$(get assembly_s)" "$(get contact_s)" "$(get linear_solve_s)" "$(get peak_memory_mib)" $errs "$solver"
done
