#!/usr/bin/env bash
# Architecture check (DESIGN.md "Modules depend downward only"): libinvfem includes no module
# header; solids/, shells/ and collisions/ never include one another's headers (nor renders' or
# apps'); renders/ knows only the core. Prints every violation as FILE:LINE: INCLUDE.
#   module_includes.sh ROOT          check the tree at ROOT; exit 1 on any violation
#   module_includes.sh --self-test   check that a planted violation is caught
set -euo pipefail

check() {
  local root="$1" bad=0
  # folder -> the invfem/<module>/ include prefixes it must not use
  declare -A forbidden=(
    [libinvfem]="shells solids collisions renders"
    [shells]="solids collisions renders"
    [solids]="shells collisions renders"
    [collisions]="shells solids renders"
    [renders]="shells solids collisions"
  )
  for dir in "${!forbidden[@]}"; do
    [ -d "$root/$dir" ] || continue
    for mod in ${forbidden[$dir]}; do
      while IFS= read -r hit; do
        echo "violation: $dir/ may not include invfem/$mod/: ${hit#$root/}"
        bad=1
      done < <(grep -rnE "#include *[<\"]invfem/$mod/" "$root/$dir" --include='*.cpp' --include='*.hpp' --include='*.h' || true)
    done
    # No include may reach into apps/ (it sits on top).
    while IFS= read -r hit; do
      echo "violation: $dir/ may not include apps/: ${hit#$root/}"
      bad=1
    done < <(grep -rnE '#include *[<"](\.\./)+apps/' "$root/$dir" --include='*.cpp' --include='*.hpp' || true)
  done
  return $bad
}

if [ "${1:-}" = "--self-test" ]; then
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  mkdir -p "$tmp/solids/src" "$tmp/shells/src"
  echo '#include "invfem/core/geometry/surface.hpp"' > "$tmp/shells/src/ok.cpp"
  check "$tmp" >/dev/null || { echo "self-test: a clean tree was flagged"; exit 1; }
  echo '#include "invfem/shells/bending_force.hpp"' > "$tmp/solids/src/planted.cpp"
  if check "$tmp" >/dev/null; then echo "self-test: the planted violation was not caught"; exit 1; fi
  echo "self-test: a planted violation is caught"
  exit 0
fi
root="${1:?usage: module_includes.sh ROOT | --self-test}"
if check "$root"; then echo "module includes: no violation"; else exit 1; fi
