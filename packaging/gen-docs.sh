#!/usr/bin/env bash
# Generates the architecture-independent documentation of the package from the built executable's own
# help, so that it cannot drift from the code: a man page per subcommand (help2man on `m2mlat --help`
# and `m2mlat <sub> --help`; the subcommands are those `m2mlat help` lists) and the bash completion
# (subcommands, and each subcommand's options from its --help).
#
#   packaging/gen-docs.sh OUTDIR VERSION COMMAND...
#
# COMMAND runs m2mlat: the binary itself, or an emulator and the binary (the arm64 package is built
# this way, under qemu-aarch64, and its pages must equal the amd64 ones; tests/packaging checks it).
# Writes OUTDIR/man1/*.1.gz and OUTDIR/completions/m2mlat. Dates in the pages come from
# SOURCE_DATE_EPOCH (set by the caller), so two builds of the same version give identical files.
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 OUTDIR VERSION COMMAND..." >&2; exit 2; }
out=$1 version=$2
shift 2
command -v help2man >/dev/null || { echo "$0: help2man is missing (apt-get install help2man)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out/man1" "$out/completions"
rm -f "$out"/man1/m2mlat*.1.gz

# `m2mlat help`: "  <name>   <one line>" per subcommand.
"$@" help >"$tmp/help.txt"
mapfile -t subs < <(sed -n 's/^  \([a-z][a-z0-9-]*\)  .*/\1/p' "$tmp/help.txt")
[ ${#subs[@]} -gt 0 ] || { echo "$0: no subcommands in '$* help'" >&2; exit 1; }
describe() { sed -n "s/^  $1  *//p" "$tmp/help.txt"; }

# help2man runs a program by name and calls the page after it: one small wrapper per page.
runner=$(printf '%q ' "$@")
wrap() {  # wrap NAME [SUBCOMMAND]
  printf '#!/bin/sh\nexec %s %s "$@"\n' "$runner" "${2:-}" >"$tmp/bin/$1"
  chmod +x "$tmp/bin/$1"
}
mkdir -p "$tmp/bin"
man() {  # man NAME DESCRIPTION INCLUDE
  help2man --no-info --section=1 --version-string="$version" --name="$2" --include="$3" \
    --source="m2mlat $version" --manual="m2mlat manual" "$tmp/bin/$1" >"$tmp/$1.1"
  gzip -9n <"$tmp/$1.1" >"$out/man1/$1.1.gz"
}

{
  echo "[SEE ALSO]"
  for s in "${subs[@]}"; do [ "$s" = help ] || printf '.BR m2mlat-%s (1)\n' "$s"; done
} >"$tmp/main.h2m"
wrap m2mlat
man m2mlat "measure Motion-to-Motion latency between two boards" "$tmp/main.h2m"
printf '[SEE ALSO]\n.BR m2mlat (1)\n' >"$tmp/sub.h2m"
for s in "${subs[@]}"; do
  [ "$s" = help ] && continue  # `m2mlat help` only lists the subcommands: m2mlat(1) has them
  wrap "m2mlat-$s" "$s"
  man "m2mlat-$s" "$(describe "$s")" "$tmp/sub.h2m"
done

# The options in a --help text: "  -h,--help ...", "  --store TEXT ..."; and its own subcommands
# (CLI11's "Subcommands:" section; for `m2mlat --help`, the table's).
options_of() {
  awk '
    /^[A-Za-z]+:$/ { section = $0; next }
    section == "Subcommands:" && /^  [a-z]/ { print $1; next }
    /^  +-/ {
      n = split($1, names, ",")
      for (i = 1; i <= n; i++) if (names[i] ~ /^--?[A-Za-z0-9]/) print names[i]
    }' | sort -u | tr '\n' ' ' | sed 's/ $//'
}

{
  cat <<'HEAD'
# bash completion for m2mlat. Generated from `m2mlat help` and each subcommand's --help by
# packaging/gen-docs.sh: do not edit.
_m2mlat() {
  local cur=${COMP_WORDS[COMP_CWORD]} sub="" i words
  for ((i = 1; i < COMP_CWORD; i++)); do
    case ${COMP_WORDS[i]} in
      -*) ;;
      *) sub=${COMP_WORDS[i]}; break ;;
    esac
  done
  case $sub in
HEAD
  printf '    "") words="%s" ;;\n' "$("$@" --help | options_of)"
  for s in "${subs[@]}"; do
    printf '    %s) words="%s" ;;\n' "$s" "$("$@" "$s" --help | options_of)"
  done
  cat <<'TAIL'
    *) words="" ;;
  esac
  # After a subcommand, anything but an option is a value: leave it to file-name completion.
  if [[ -n $sub && $cur != -* ]]; then
    COMPREPLY=()
    return
  fi
  COMPREPLY=($(compgen -W "$words" -- "$cur"))
}
complete -o bashdefault -o default -F _m2mlat m2mlat
TAIL
} >"$out/completions/m2mlat"
