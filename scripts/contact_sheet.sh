#!/usr/bin/env bash
# Renders every STEP file of a folder (default: the corpus) into one contact sheet for review:
# target/contact/sheet.png (tiles row by row in file-name order; sheet.txt names each tile) and
# one PNG per file in target/contact/images. Prints the time to image per file (import + mesh +
# render, on whatever adapter wgpu finds: Mesa's lavapipe without a GPU).
#
# Usage: scripts/contact_sheet.sh [FOLDER] [TILE_SIZE]
set -euo pipefail
cd "$(dirname "$0")/.."
folder=${1:-../shared/corpus/step}
size=${2:-256x192}
out=${CONTACT_OUT:-target/contact}
cargo build --release -q -p cadre
mkdir -p "$out"
"${CARGO_TARGET_DIR:-target}/release/cadre" render "$folder" -o "$out/images" --size "$size" \
    --sheet "$out/sheet.png"
