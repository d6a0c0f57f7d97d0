#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs crossparam into a temporary prefix and builds a consumer project with find_package(crossparam).
set -eu
build=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
# Only the library is installed: the generated shapes, the CLI's rendering and its PNG writer are not.
stray=$(find "$work/prefix/include/crossparam" \( -name shapes.h -o -name render.h -o -name png.h \) -print)
if [ -n "$stray" ]; then
  echo "install: not library headers, installed: $stray"
  echo "install: 0 passed, 1 failed"
  exit 1
fi
cmake -S "$src/test/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/consumer" >/dev/null
"$work/consumer/consumer"
echo "install: 1 passed, 0 failed"
