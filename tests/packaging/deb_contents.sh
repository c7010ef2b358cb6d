#!/usr/bin/env bash
# The two packages as built: metadata (dpkg-deb -I), files (dpkg-deb -c), each binary's architecture,
# Depends from dpkg-shlibdeps that name the real library packages (never the cross toolchain's
# *-arm64-cross ones) and are the same for both, the arm64 Depends satisfiable from the archive
# (apt-get -s on this multiarch host), man pages and completion identical in both (generated on amd64
# natively and on arm64 under the emulator), and the completion script working in bash.
#
#   tests/packaging/deb_contents.sh AMD64.deb ARM64.deb
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 AMD64.deb ARM64.deb" >&2; exit 2; }
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
declare -A DEB=([amd64]=$(realpath "$1") [arm64]=$(realpath "$2"))
declare -A ELF=([amd64]="x86-64" [arm64]="ARM aarch64")

FILES="./usr/bin/m2mlat ./usr/lib/systemd/system/m2mlat-agent@.service ./usr/lib/udev/rules.d/60-m2mlat-gpio.rules
./usr/libexec/m2mlat/irq-affinity ./etc/m2mlat/agent.toml.example ./usr/share/man/man1/m2mlat.1.gz
./usr/share/man/man1/m2mlat-record.1.gz ./usr/share/bash-completion/completions/m2mlat
./usr/share/doc/m2mlat/packaging.md"
for arch in amd64 arm64; do
  deb=${DEB[$arch]}
  field() { dpkg-deb -f "$deb" "$1"; }
  [ "$(field Package)" = m2mlat ] || fail "$deb: Package $(field Package)"
  [ "$(field Architecture)" = "$arch" ] || fail "$deb: Architecture $(field Architecture), expected $arch"
  depends=$(field Depends)
  # The package names alone, one a line, compared as fixed strings ("libstdc++6" is no regex).
  tr ',' '\n' <<<"$depends" | sed 's/^ *//; s/ .*//' | sort >"$WORK/$arch.depends"
  for lib in libc6 libstdc++6 libgcc-s1 libsqlite3-0 libfmt9 libcpp-httplib0.11 libpcap0.8 libzstd1 liblz4-1 libpq5 adduser; do
    grep -qxF "$lib" "$WORK/$arch.depends" || fail "$deb: Depends lacks $lib: $depends"
  done
  case $depends in *-cross*) fail "$deb: Depends names the cross toolchain: $depends" ;; esac
  # Outputs are captured before grep -q looks at them: grep stops at its first match, and under
  # pipefail the writer's SIGPIPE would fail the check.
  info=$(dpkg-deb -I "$deb")
  grep -Eq '[[:space:]]postinst([[:space:]]|$)' <<<"$info" || fail "$deb: no postinst: $info"
  conffiles=$(dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./conffiles)
  grep -qx /etc/m2mlat/agent.toml.example <<<"$conffiles" || fail "$deb: agent.toml.example is not a conffile"
  dpkg-deb -c "$deb" | awk '{print $6}' >"$WORK/$arch.files"
  for f in $FILES; do grep -qx "$f" "$WORK/$arch.files" || fail "$deb: $f missing"; done
  mkdir "$WORK/$arch"
  dpkg-deb -x "$deb" "$WORK/$arch"
  file "$WORK/$arch/usr/bin/m2mlat" | grep -q "${ELF[$arch]}" || fail "$deb: m2mlat is not ${ELF[$arch]}"
  file "$WORK/$arch/usr/bin/m2mlat" | grep -q ', stripped' || fail "$deb: m2mlat is not stripped"
  [ "$(stat -c %a "$WORK/$arch/usr/libexec/m2mlat/irq-affinity")" = 755 ] || fail "$deb: helper not executable"
  echo "$arch: $(du -k "$deb" | cut -f1) KiB, $(wc -l <"$WORK/$arch.files") entries; Depends: $depends"
done
diff -u "$WORK/amd64.depends" "$WORK/arm64.depends" || fail "the two packages depend on different packages"
diff -r "$WORK/amd64/usr/share" "$WORK/arm64/usr/share" || fail "man pages or completion differ between amd64 and arm64"
diff -r "$WORK/amd64/etc" "$WORK/arm64/etc" || fail "the configuration differs between amd64 and arm64"

# The arm64 package's Depends are satisfiable from the archive (resolved as for an arm64 board).
if dpkg --print-foreign-architectures | grep -qx arm64; then
  apt-get install -s -qq "${DEB[arm64]}" >"$WORK/sim.txt" 2>&1 || { cat "$WORK/sim.txt" >&2; fail "apt cannot satisfy the arm64 Depends"; }
  grep -q '^Inst m2mlat:arm64' "$WORK/sim.txt" || { cat "$WORK/sim.txt" >&2; fail "apt -s did not plan m2mlat:arm64"; }
fi

# Every man page names its subcommand; every subcommand of `m2mlat help` has one.
for page in "$WORK"/amd64/usr/share/man/man1/*.1.gz; do
  name=$(basename "$page" .1.gz)
  text=$(zcat "$page")
  grep -q "^$name \\\\- " <<<"$text" || fail "$name.1 has no NAME line"
done

# The completion: subcommands after `m2mlat`, a subcommand's options after it, files for values.
completion=$WORK/amd64/usr/share/bash-completion/completions/m2mlat
complete_words() {  # complete_words WORD... : the candidates for the last word
  bash -c 'source "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _m2mlat; printf "%s\n" "${COMPREPLY[@]}"' \
    _ "$completion" "$@"
}
[ "$(complete_words m2mlat rec)" = record ] || fail "completion of 'm2mlat rec': $(complete_words m2mlat rec)"
grep -qx report <<<"$(complete_words m2mlat '')" || fail "'m2mlat <TAB>' lacks report"
grep -qx -- --store <<<"$(complete_words m2mlat record --st)" || fail "'m2mlat record --st' lacks --store"
grep -qx -- --duration <<<"$(complete_words m2mlat record --store x.db --dur)" || fail "'record ... --dur' lacks --duration"
[ -z "$(complete_words m2mlat export --dur)" ] || fail "'export --dur' offers record's options"
[ -z "$(complete_words m2mlat export st)" ] || fail "a value after a subcommand should be left to file names"
echo "deb_contents: ok"
