#!/usr/bin/env bash
# 3D Hertz on CalculiX's tet10 meshes (the side-by-side harness of
# ../shared/peers/calculix-hertz: quarter sphere R = 8 mm on a block, steel, the sphere's top
# pressed down by 0.031 mm) with 3D mortar and Lagrange multipliers: DOFs, Newton iterations,
# wall time split into assembly / contact / linear solve, peak memory, the load P on the whole
# sphere and the peak nodal pressure against Hertz's p0 for that load (Johnson 1985, ch. 4).
# Usage: bench/hertz3d_tet10_mortar.sh [BUILD_DIR] [MESH ...]
#   MESH: a C3D10 .inp or .msh of the harness (default: the coarse one in tests/data/calculix;
#   the fine one is there too, hertz3d_fine_c3d10.inp; the medium one comes from the harness's
#   scripts/mesh3d.py, which needs python3-gmsh).
# DISCRETIZATION=segment_to_segment (or another) runs that instead of mortar; LINEAR=gamg (or
# another solver.linear type) solves the condensed system with it (default: auto, which takes
# CHOLMOD, or GAMG where the Cholesky factor would hold more than 5e7 entries, as on the fine
# mesh); FACTOR_LIMIT=0 keeps auto on CHOLMOD (solver.linear.direct_factor_limit).
# FRICTION="{law: coulomb, mu: 0.3}" gives the pair friction (default: frictionless); with
# Lagrange multipliers on mortar, friction's blocks on shared DOFs, condensed for GMRES over
# GAMG (docs/performance.md, sessions 61 and 62). MPIRUN="mpirun -np 2" runs the solver under
# that launcher (default: one process).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
shift || true
meshes=("$@")
[ ${#meshes[@]} -gt 0 ] || meshes=("$here/tests/data/calculix/meshes/hertz3d_coarse_c3d10.inp")
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
printf "%-28s %7s %6s %8s %8s %8s %8s %8s %9s %8s\n" mesh dofs iters total_s assemb_s contact_s solve_s mem_MiB P_N p0_err_%
for mesh in "${meshes[@]}"; do
  mesh="$(cd "$(dirname "$mesh")" && pwd)/$(basename "$mesh")"
  cat > "$work/deck.yaml" <<DECK
title: Hertz 3D tet10, ${DISCRETIZATION:-mortar}
analysis: {dimension: 3d}
mesh: {file: $mesh}
materials:
  steel: {model: linear_elastic, E: 200000, nu: 0.3}
bodies:
  - {name: sphere, region: SPH, material: steel}
  - {name: block, region: BLOCK, material: steel}
contact:
  - {name: hertz, slave: SLAVE, master: MASTER, discretization: ${DISCRETIZATION:-mortar}${FRICTION:+, friction: $FRICTION}}
steps:
  - name: press
    boundary:
      - {set: NSYMX, ux: 0}
      - {set: NSYMY, uy: 0}
      - {set: NBOT, uz: 0}
      - {set: NTOP, uz: -0.031}
output: {vtu: none}
solver: {linear: {type: ${LINEAR:-auto}, direct_factor_limit: ${FACTOR_LIMIT:-5e7}}}
DECK
  ${MPIRUN:-} "$build/signorini" run -q "$work/deck.yaml" -o "$work/out" > "$work/log" 2>&1 || true
  s="$work/out/summary.json"
  get() { grep -o "\"$1\": [^,}]*" "$s" | head -1 | sed 's/.*: //'; }
  # P = 4 |F_z| on NTOP (quarter model); Hertz: a = (3 P R / 4 E*)^(1/3), p0 = 3 P / (2 pi a^2).
  P=$(awk -F, '$5 == "NTOP" { f = $8 } END { printf "%.6g", 4 * (f < 0 ? -f : f) }' "$work/out/reactions.csv")
  peak=$(awk -F, 'NR > 1 && $6 > m { m = $6 } END { print m + 0 }' "$work"/out/contact_hertz_*.csv)
  err=$(awk -v P="$P" -v p="$peak" 'BEGIN { E = 200000 / (2 * (1 - 0.09)); a = (3 * P * 8 / (4 * E)) ^ (1 / 3);
        printf "%+.3f", 100 * (p / (3 * P / (2 * 3.14159265358979 * a * a)) - 1) }')
  printf "%-28s %7s %6s %8.1f %8.1f %8.1f %8.1f %8.0f %9s %8s\n" "$(basename "$mesh")" "$(get dofs)" \
    "$(get total_iterations)" "$(get total_s)" "$(get assembly_s)" "$(get contact_s)" "$(get linear_solve_s)" \
    "$(get peak_memory_mib)" "$P" "$err"
done
