#!/usr/bin/env bash
# Architecture check (DESIGN.md "Modules depend downward only"). Prints every violation as
# FILE:LINE: TEXT and exits 1 on any:
#  - libinvfem includes no module header; solids/, shells/ and collisions/ never include one
#    another's headers (nor renders' or apps'); renders/ knows only the core;
#  - a core part includes only the parts below it (math; geometry and solve on math; integrate on
#    those three; world on integrate and below; io on math and geometry), and a collisions part likewise (colliders; self_collision
#    on colliders; certificate on neither);
#  - only the core's io part links or includes assimp;
#  - no dynamic_cast outside tests/ (a module that needs its own object back keeps it);
#  - the core's World (world.hpp, world*.cpp) names no object kind in its code (solid, cloth, shell,
#    garment, fracture, ObjectKind), comments aside.
#   module_includes.sh ROOT          check the tree at ROOT
#   module_includes.sh --self-test   check that a planted violation of each rule is caught
set -euo pipefail

sources() { find "$@" \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) -print 2>/dev/null; }

# report RULE < lines: prints each line as a violation of RULE; returns 1 when there was any.
report() {
  local rule="$1" bad=0 line
  while IFS= read -r line; do
    echo "violation: $rule: $line"
    bad=1
  done
  return $bad
}

# no_include ROOT DIR PREFIX...: files under ROOT/DIR must not include invfem/PREFIX.
no_include() {
  local root="$1" dir="$2" bad=0
  shift 2
  [ -d "$root/$dir" ] || return 0
  for prefix in "$@"; do
    { grep -rnE "#include *[<\"]invfem/$prefix/" "$root/$dir" --include='*.cpp' --include='*.hpp' --include='*.h' || true; } |
      sed "s#^$root/##" | report "$dir/ may not include invfem/$prefix/" || bad=1
  done
  return $bad
}

check() {
  local root="$1" bad=0
  # Modules.
  no_include "$root" libinvfem shells solids collisions renders || bad=1
  no_include "$root" shells solids collisions renders || bad=1
  no_include "$root" solids shells collisions renders || bad=1
  no_include "$root" collisions shells solids renders || bad=1
  no_include "$root" renders shells solids collisions || bad=1
  for dir in libinvfem shells solids collisions renders; do
    [ -d "$root/$dir" ] || continue
    { grep -rnE '#include *[<"](\.\./)+apps/' "$root/$dir" --include='*.cpp' --include='*.hpp' || true; } |
      sed "s#^$root/##" | report "$dir/ may not include apps/" || bad=1
  done
  # The core's parts, each on the parts below it only.
  no_include "$root" libinvfem/math core/geometry core/solve core/integrate core/world core/io || bad=1
  no_include "$root" libinvfem/geometry core/solve core/integrate core/world core/io || bad=1
  no_include "$root" libinvfem/solve core/geometry core/integrate core/world core/io || bad=1
  no_include "$root" libinvfem/integrate core/world core/io || bad=1
  no_include "$root" libinvfem/world core/io || bad=1
  no_include "$root" libinvfem/io core/solve core/integrate core/world || bad=1
  # The collisions' parts.
  no_include "$root" collisions/colliders collisions/self_collision collisions/certificate || bad=1
  no_include "$root" collisions/self_collision collisions/certificate || bad=1
  no_include "$root" collisions/certificate collisions/colliders collisions/self_collision || bad=1
  # assimp: the core's io part alone.
  { grep -rnE '#include *[<"]assimp/' "$root" --include='*.cpp' --include='*.hpp' --include='*.h' 2>/dev/null || true; } |
    { grep -v "^$root/libinvfem/io/\|^$root/build" || true; } | sed "s#^$root/##" |
    report "only libinvfem/io may include assimp" || bad=1
  { grep -rnE '^[^#]*(assimp::assimp|\bassimp\b *\))' "$root" --include='CMakeLists.txt' 2>/dev/null || true; } |
    { grep -v "^$root/build\|^$root/libinvfem/CMakeLists.txt:[0-9]*:invfem_core_part(io " || true; } | sed "s#^$root/##" |
    report "only the core's io part may link assimp" || bad=1
  # No dynamic_cast outside the tests.
  for dir in libinvfem shells solids collisions renders apps; do
    [ -d "$root/$dir" ] || continue
    { grep -rn 'dynamic_cast' "$root/$dir" --include='*.cpp' --include='*.hpp' || true; } | sed "s#^$root/##" |
      report "no dynamic_cast outside tests/" || bad=1
  done
  # The World names no object kind (code only: // comments are stripped first).
  for f in $(find "$root/libinvfem" \( -name world.hpp -o -name 'world*.cpp' \) 2>/dev/null); do
    sed 's#//.*##' "$f" | { grep -nEi '\b(solids?|cloths?|shells?|garments?|fractur[a-z]*|ObjectKind)\b' || true; } |
      sed "s#^#${f#$root/}:#" | report "the World names no object kind" || bad=1
  done
  return $bad
}

if [ "${1:-}" = "--self-test" ]; then
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  mkdir -p "$tmp/solids/src" "$tmp/shells/src" "$tmp/libinvfem/math/src" "$tmp/libinvfem/world/src" \
           "$tmp/collisions/certificate/src" "$tmp/apps/src"
  echo '#include "invfem/core/geometry/surface.hpp"' > "$tmp/shells/src/ok.cpp"
  echo 'void f(); // a solid' > "$tmp/libinvfem/world/src/world.cpp"
  check "$tmp" >/dev/null || { echo "self-test: a clean tree was flagged"; exit 1; }
  plant() {  # plant FILE TEXT: the rule must catch it, then the tree is clean again
    local file="$tmp/$1" before=""
    [ -f "$file" ] && before=$(cat "$file")
    echo "$2" >> "$file"
    if check "$tmp" >/dev/null; then echo "self-test: not caught: $1: $2"; exit 1; fi
    if [ -n "$before" ]; then echo "$before" > "$file"; else rm "$file"; fi
  }
  plant solids/src/planted.cpp '#include "invfem/shells/bending_force.hpp"'
  plant libinvfem/math/src/planted.cpp '#include "invfem/core/world/world.hpp"'
  plant collisions/certificate/src/planted.cpp '#include "invfem/collisions/self_collision/collision_mesh.hpp"'
  plant apps/src/planted.cpp '#include <assimp/Importer.hpp>'
  plant apps/src/planted.cpp 'auto* p = dynamic_cast<const A*>(b);'
  plant libinvfem/world/src/world.cpp 'if (o.kind == ObjectKind::Solid) {}'
  plant libinvfem/world/src/world.cpp 'int cloths = 0;'
  plant libinvfem/world/src/world_step_objects.cpp 'bool solid = true;'
  check "$tmp" >/dev/null || { echo "self-test: the tree is not clean after the plants"; exit 1; }
  echo "self-test: a planted violation of each rule is caught"
  exit 0
fi
root="${1:?usage: module_includes.sh ROOT | --self-test}"
if check "$root"; then echo "architecture: no violation"; else exit 1; fi
