#!/bin/sh
# Copies the shared STEP corpus (../shared/corpus/step next to the repository) into the
# step_parse fuzz target's corpus directory as seeds.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
src="$here/../../shared/corpus/step"
dst="$here/corpus/step_parse"
if [ ! -d "$src" ]; then
    echo "skipping: ../shared/corpus not found ($src)" >&2
    exit 0
fi
mkdir -p "$dst"
cp "$src"/* "$dst"/
echo "copied $(ls "$src" | wc -l) files into $dst"
