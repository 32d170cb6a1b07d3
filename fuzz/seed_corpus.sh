#!/bin/sh
# Copies the shared STEP corpus (../shared/corpus/step next to the repository) into each
# fuzz target's corpus directory (step_parse, step_map, pipeline) as seeds, and writes a
# dimension file of every kind as dimension_file's seed.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$here/corpus/dimension_file"
cat > "$here/corpus/dimension_file/all_kinds.json" <<'JSON'
{"dimensions": [
 {"kind": "distance", "value": 10.0, "text": "10.000 mm", "points": [[0,0,0],[10,0,0]]},
 {"kind": "length", "value": 3.14, "text": "3.140 mm", "points": [[1,0,0],[0.7,0.7,0],[0,1,0]]},
 {"kind": "radius", "value": 5.0, "text": "R5.000 mm", "points": [[0,0,0],[3,4,0],[0,0,1]]},
 {"kind": "angle", "value": 1.5707963, "text": "90.000°", "points": [[0,0,0],[1,0,0],[0,1,0]]},
 {"kind": "angle", "value": 0.5, "text": "28.648°", "points": [[0,0,0],[1,0,0]]}
]}
JSON
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
