#!/usr/bin/env bash
# `cmake --install` into a scratch prefix, then the installed tools alone (check_installed.sh).
# Usage: install_test.sh SOURCE_DIR BINARY_DIR MAN_PAGES(ON|OFF)
set -euo pipefail
src=$1 build=$2 man_pages=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "install_test: FAIL: $*" >&2; exit 1; }

prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >"$work/install.log" 2>&1 ||
  { cat "$work/install.log"; fail "cmake --install failed"; }
bash "$(dirname "${BASH_SOURCE[0]}")/check_installed.sh" install_test "$prefix" "$src" "$build" \
  "$man_pages"
echo "install_test: ok"
