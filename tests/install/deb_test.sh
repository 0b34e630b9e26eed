#!/usr/bin/env bash
# The Debian package: `cpack -G DEB` from the Release build into a scratch folder, then its control
# fields (name, version, amd64; a dependency on the package of every library a tool links, and on
# Mesa's drivers), its contents (the tools in /usr/bin, the man pages, the documentation, nothing
# outside /usr), and the package extracted with `dpkg-deb -x` into a scratch root with its tools run
# from there (check_installed.sh): the libraries are Debian's, so nothing else is needed.
# Usage: deb_test.sh SOURCE_DIR BINARY_DIR VERSION MAN_PAGES(ON|OFF)
set -euo pipefail
src=$1 build=$2 version=$3 man_pages=$4
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "deb_test: FAIL: $*" >&2; exit 1; }
tools=(sss-irrmap sss-bake sss-render sss-relight)

cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work/package" >"$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log"; fail "cpack -G DEB failed"; }
deb=$work/package/sss-tools_${version}_amd64.deb
[[ -f $deb ]] || fail "cpack wrote no $(basename "$deb"): $(ls "$work/package" | tr "\n" " ")"

field() { dpkg-deb --field "$deb" "$1"; }
[[ $(field Package) == sss-tools ]] || fail "Package: $(field Package)"
[[ $(field Version) == "$version" ]] || fail "Version: $(field Version), expected $version"
[[ $(field Architecture) == amd64 ]] || fail "Architecture: $(field Architecture)"
depends=$(field Depends)
# The package names in Depends, one a line ("libc6 (>= 2.35), libegl1" -> libc6, libegl1).
depends_on=$(tr ',|' '\n\n' <<<"$depends" | sed 's/^ *//; s/[ (].*//')
grep -qxF libgl1-mesa-dri <<<"$depends_on" || fail "Depends lacks libgl1-mesa-dri: $depends"

contents=$(dpkg-deb --contents "$deb" | awk '{ print $NF }')
outside=$(grep -v '^\./usr/' <<<"$contents" | grep -vx '\./' || true)
[[ -z $outside ]] || fail "files outside /usr: $outside"
expected=(./usr/share/doc/sss-tools/README.md ./usr/share/doc/sss-tools/LICENSE
  ./usr/share/doc/sss-tools/viewer/index.html)
for tool in "${tools[@]}"; do
  expected+=("./usr/bin/$tool")
  [[ $man_pages == OFF ]] || expected+=("./usr/share/man/man1/$tool.1")
done
for path in "${expected[@]}"; do grep -qxF "$path" <<<"$contents" || fail "no $path in the .deb"; done

root=$work/root
dpkg-deb -x "$deb" "$root" || fail "dpkg-deb -x failed"
# Every library a tool names (NEEDED) belongs to a package that Depends names (amd64: the
# x86_64-linux-gnu folders, not lib32/).
sonames=$(for tool in "${tools[@]}"; do readelf -d "$root/usr/bin/$tool"; done |
  sed -n 's/.*(NEEDED).*\[\(.*\)\]$/\1/p' | sort -u)
[[ -n $sonames ]] || fail "the tools name no library (readelf -d)"
for soname in $sonames; do
  owner=$(dpkg -S "*/x86_64-linux-gnu/$soname" 2>/dev/null | head -n 1 | sed 's/[:,].*//') ||
    fail "no installed package holds $soname"
  [[ -n $owner ]] || fail "no installed package holds $soname"
  grep -qxF "$owner" <<<"$depends_on" || fail "Depends lacks $owner (for $soname): $depends"
done

bash "$(dirname "${BASH_SOURCE[0]}")/check_installed.sh" deb_test "$root/usr" "$src" "$build" \
  "$man_pages"
echo "deb_test: ok ($(basename "$deb"), $(stat -c %s "$deb") bytes; Depends: $depends)"
