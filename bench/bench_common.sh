# Sourced by the bench scripts (bench_cycles.sh, bench_methods.sh): the repository root, the
# default build folder, the options every script takes and the check of the programs it runs.
# shellcheck shell=bash
# shellcheck disable=SC2034  # BUILD, OUT and SHIFT are read by the scripts that source this

# ROOT: the repository; BUILD: the build folder whose bin/ holds the programs (--build DIR)
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="$ROOT/build"

# usage: the calling script's header comment (from its line 2 to the line before `set -...`)
usage() {
  sed -n '2,/^set -/p' "$0" | sed '$d'
}

# common_option ARGS...: the option at the front of ARGS that every bench script takes:
# --build DIR (sets BUILD), --out DIR (sets OUT), -h/--help (prints usage, exits 0); any other
# exits 2 as unknown. Sets SHIFT to the number of words it used.
common_option() {
  case "$1" in
    --build) BUILD="$(cd "$2" && pwd)"; SHIFT=2 ;;
    --out) OUT="$2"; SHIFT=2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
}

# need_programs EXE...: exits 2 naming the first EXE that is not an executable file (and the
# targets that build them all: the EXEs' names)
need_programs() {
  local exe targets=""
  for exe in "$@"; do targets+="${targets:+ and }$(basename "$exe")"; done
  for exe in "$@"; do
    [[ -x "$exe" ]] || { echo "missing $exe (build the $targets targets)" >&2; exit 2; }
  done
}
