# Sourced by the benches that take MESH... arguments (proxy.sh, same_layouts.sh), from the checkout's
# top folder.
#   mesh_list HERE [MESH...]  sets the array `meshes`: the MESH arguments, made absolute against
#                             HERE (where the bench was called from), or with none the shared meshes
#                             of genus >= 2 (the caller adds its own extras when $# was 0)
mesh_list() {
  local here=$1 m
  shift
  meshes=()
  for m in "$@"; do case "$m" in /*) meshes+=("$m") ;; *) meshes+=("$here/$m") ;; esac; done
  if [ ${#meshes[@]} -eq 0 ]; then
    for m in 3holes.off botijo.off eight.off fertility.off input_wheel.off boot.obj skull.obj; do
      meshes+=("../shared/data/meshes/$m")
    done
  fi
}
