#!/bin/sh
# Copies the shared STEP corpus (../shared/corpus/step next to the repository) into each
# fuzz target's corpus directory (step_parse, step_map, pipeline) as seeds.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
src="$here/../../shared/corpus/step"
if [ ! -d "$src" ]; then
    echo "skipping: ../shared/corpus not found ($src)" >&2
    exit 0
fi
for target in step_parse step_map pipeline; do
    dst="$here/corpus/$target"
    mkdir -p "$dst"
    cp "$src"/* "$dst"/
    echo "copied $(ls "$src" | wc -l) files into $dst"
done
