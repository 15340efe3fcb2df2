# Sourced by the repair surveys: the real meshes a machine has, in a fixed order.
#   real_meshes WORK [FIND_TEST...]
# appends to the array `meshes` every mesh of ../shared/meshes (when present) and of
# libcgal-demo's data.tar.gz (unpacked under WORK), the latter filtered by the find tests given
# (e.g. -size -2M).
real_meshes() {
  local work=$1 f
  shift
  [[ -d ../shared/meshes ]] && for f in ../shared/meshes/*.{off,stl,STL,ply,obj}; do
    [[ -f $f ]] && meshes+=("$f")
  done
  local tarball=/usr/share/doc/libcgal-demo/data.tar.gz
  if [[ -f $tarball ]]; then
    tar -xzf "$tarball" -C "$work" data/meshes 2>/dev/null || true
    while IFS= read -r f; do meshes+=("$f"); done < <(find "$work/data/meshes" -type f \
      \( -name '*.off' -o -name '*.ply' -o -name '*.obj' -o -name '*.stl' \) "$@" | sort)
  fi
  return 0
}
