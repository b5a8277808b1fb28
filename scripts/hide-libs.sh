# Sourced (needs root, inside a private mount namespace): hide_suitesparse ROOT [KEEP] bind-mounts
# an empty file over every SuiteSparse and METIS shared object under ROOT (/ for the host), so
# that anything still needing them fails to load; KEEP lists (space-separated, inside ROOT) files
# to leave, those the program under test links itself. Prints how many it hid.
hide_suitesparse() {
  local root=${1%/} keep=" ${2:-} " empty lib f hidden=0
  empty=$(mktemp)
  for lib in cholmod amd camd colamd ccolamd suitesparseconfig metis; do
    for f in "$root"/usr/lib/x86_64-linux-gnu/lib$lib.so.*; do
      case $keep in *" ${f#"$root"} "*) continue ;; esac
      if [ -f "$f" ] && [ ! -L "$f" ]; then mount --bind "$empty" "$f"; hidden=$((hidden + 1)); fi
    done
  done
  echo "hide-libs: $hidden SuiteSparse/METIS files hidden under ${root:-/}"
}
