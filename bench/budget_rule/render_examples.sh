#!/usr/bin/env bash
# The page's five examples generated with two builds side by side: points | OLD | NEW
# (issue 15 item 5: the budget rule before and after the planar share).
#
#   bash bench/budget_rule/render_examples.sh OLD_MESHFLOW NEW_MESHFLOW OUT.png
#
# Each build generates from web/examples/*.ply with its defaults and the weights it finds;
# NEW converts the meshes to OBJ for scripts/render_meshes.py (numpy, matplotlib).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
OLD="${1:?usage: render_examples.sh OLD_MESHFLOW NEW_MESHFLOW OUT.png}"
NEW="${2:?usage: render_examples.sh OLD_MESHFLOW NEW_MESHFLOW OUT.png}"
OUT="${3:?usage: render_examples.sh OLD_MESHFLOW NEW_MESHFLOW OUT.png}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
panels=()
titles=()
for ply in "$ROOT"/web/examples/*.ply; do
    name="$(basename "$ply" .ply)"
    "$NEW" convert "$ply" "$TMP/$name.points.obj" >/dev/null
    "$OLD" generate "$ply" -o "$TMP/$name.old.glb" >/dev/null
    "$NEW" generate "$ply" -o "$TMP/$name.new.glb" >/dev/null
    for arm in old new; do
        "$NEW" convert "$TMP/$name.$arm.glb" "$TMP/$name.$arm.obj" >/dev/null
    done
    panels+=("$TMP/$name.points.obj" "$TMP/$name.old.obj" "$TMP/$name.new.obj")
    titles+=("$name points" "previous rule" "planar-share rule")
done
python3 "$ROOT/scripts/render_meshes.py" "$OUT" "${panels[@]}" --cols 3 --titles "${titles[@]}"
