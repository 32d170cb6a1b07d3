#!/usr/bin/env bash
# Meshes every STEP file of a folder with cadre (import + mesh) and with OCCT (read + transfer +
# parallel BRepMesh) in the same run at the benchmark settings (linear deflection 0.001 x bbox
# diagonal, angular deflection 0.5 rad), and prints the per-file table, the speed and triangle
# ratios and the mesh quality against the corpus reference.
#
# Usage: scripts/bench_mesh.sh [FOLDER] [EXTRA compare_mesh.py OPTIONS...]
#   FOLDER defaults to ../shared/corpus/step. Results go to ${BENCH_OUT:-target/bench-mesh}:
#   results.json (every record and the summary) and report.txt (table and summary).
# Needs: pip install cadquery-ocp-novtk
set -euo pipefail
cd "$(dirname "$0")/.."
folder=${1:-../shared/corpus/step}
shift || true
out=${BENCH_OUT:-target/bench-mesh}
mkdir -p "$out"
cargo build --release -q -p cadre
cadre=${CARGO_TARGET_DIR:-target}/release/cadre
echo "machine: $(nproc) cores, $(uname -m), $(date -u +%Y-%m-%d)" | tee "$out/report.txt" >&2
python3 scripts/compare_mesh.py "$folder" --cadre "$cadre" --deflection-rel 0.001 --angle 0.5 \
    --jobs 1 --json-out "$out/results.json" "$@" | tee -a "$out/report.txt"
