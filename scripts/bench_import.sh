#!/usr/bin/env bash
# Imports every STEP file of a folder with cadre (parse + B-Rep + assembly) and with OCCT
# (read + transfer) in the same run, and prints per-file and total ratios.
#
# Usage: scripts/bench_import.sh [FOLDER] [REPEAT]
#   FOLDER defaults to ../shared/corpus/step, REPEAT (best of N per file) to 3.
# Needs: pip install cadquery-ocp-novtk
set -euo pipefail
cd "$(dirname "$0")/.."
folder=${1:-../shared/corpus/step}
repeat=${2:-3}
out=${BENCH_OUT:-target/bench-import}
mkdir -p "$out"
cargo build --release -q -p cadre
cadre=${CARGO_TARGET_DIR:-target}/release/cadre
echo "machine: $(nproc) cores, $(uname -m), $(date -u +%Y-%m-%d)" >&2
"$cadre" bench import "$folder" --repeat "$repeat" > "$out/cadre.jsonl"
python3 scripts/occt_import.py "$folder" --repeat "$repeat" > "$out/occt.jsonl"
python3 scripts/compare_import.py "$out/cadre.jsonl" "$out/occt.jsonl"
