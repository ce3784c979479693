#!/usr/bin/env bash
# layers.sh — the module graph has no circle and no arrow back up the flow of a render: every quoted #include
# in src/ ("module/file.h", "glint.h", or a bare name of the file's own folder) names the file's own module or
# one on a lower layer. The layers are read from the
# table under "## Module layers" in docs/architecture.md, so the documentation and this check cannot drift.
# Usage: layers.sh SOURCE_DIR
set -euo pipefail
root=${1:?usage: layers.sh SOURCE_DIR}
doc="$root/docs/architecture.md"

declare -A layer
# Table rows of the section: | N | `mod`, `mod` | ... |
while IFS='|' read -r _ n mods _; do
  n=${n//[[:space:]]/}
  [[ $n =~ ^[0-9]+$ ]] || continue
  for m in $(grep -o '`[a-z_]*`' <<<"$mods" | tr -d '`'); do layer[$m]=$n; done
done < <(sed -n '/^## Module layers/,/^## /p' "$doc")
[ "${#layer[@]}" -gt 0 ] || { echo "FAIL: no layer table under '## Module layers' in $doc"; exit 1; }

fail=0 checked=0
for dir in "$root"/src/*/; do
  mod=$(basename "$dir")
  if [ -z "${layer[$mod]:-}" ]; then echo "FAIL: src/$mod/ has no layer in docs/architecture.md"; fail=1; continue; fi
  # Every quoted include: "module/file.h" names its module; "glint.h" is the public API's (module api); any
  # other bare name must be a file of the including file's own folder.
  while IFS=: read -r file line text; do
    name=$(sed -E 's/^#include "([^"]*)".*/\1/' <<<"$text")
    checked=$((checked + 1))
    if [[ $name == */* ]]; then
      dep=${name%%/*}
    elif [[ $name == glint.h ]]; then
      dep=api
    elif [[ -f $(dirname "$file")/$name ]]; then
      continue
    else
      echo "FAIL: ${file#$root/}:$line includes \"$name\", which is not a file of src/$mod/"; fail=1; continue
    fi
    [ "$dep" = "$mod" ] && continue
    if [ -z "${layer[$dep]:-}" ]; then
      echo "FAIL: ${file#$root/}:$line includes $dep/, a module with no layer"; fail=1
    elif [ "${layer[$dep]}" -ge "${layer[$mod]}" ]; then
      echo "FAIL: ${file#$root/}:$line: $mod (layer ${layer[$mod]}) includes $dep (layer ${layer[$dep]})"; fail=1
    fi
  done < <(grep -Hn '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$dir"* | sed -E 's/:[[:space:]]*#[[:space:]]*include[[:space:]]*/:#include /' || true)
done
# The command-line program is a client of the public API only.
if grep -Hn '^#include "[a-z_]*/' "$root"/src/cli/* >/dev/null 2>&1; then
  grep -Hn '^#include "[a-z_]*/' "$root"/src/cli/*; echo "FAIL: src/cli uses more than include/glint.h"; fail=1
fi
[ "$fail" = 0 ] || exit 1
echo "layers: all $checked quoted includes in src/ point down the layers of ${#layer[@]} modules"
